// The page's link to a plugslam host: the Foxglove WebSocket protocol through
// @foxglove/ws-protocol's client (the one Lichtblick uses). Subscribes to every channel, decodes
// JSON messages into the Session, and calls services with JSON requests.
import { FoxgloveClient } from "@foxglove/ws-protocol";

const decoder = new TextDecoder();
const encoder = new TextEncoder();

/** One connection; `onChange(state)` hears "connecting", "open", "closed". */
export class Connection {
  constructor(url, session, { onChange = () => {}, onServices = () => {} } = {}) {
    this.url = url;
    this.session = session;
    this.onChange = onChange;
    this.onServices = onServices;
    this.channels = new Map(); // subscription id -> channel
    this.services = new Map(); // name -> service
    this.pending = new Map(); // call id -> {resolve, reject}
    this.nextCall = 1;
    this.connect();
  }

  connect() {
    this.onChange("connecting");
    const ws = new WebSocket(this.url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    const client = new FoxgloveClient({ ws });
    this.client = client;
    client.on("open", () => this.onChange("open"));
    client.on("close", () => {
      this.onChange("closed");
      for (const p of this.pending.values()) p.reject(new Error("connection closed"));
      this.pending.clear();
      this.channels.clear();
      this.services.clear();
      // A host restarted or a network hiccup: try again, gently.
      setTimeout(() => this.connect(), 2000);
    });
    client.on("error", () => {});
    client.on("serverInfo", (info) => (this.serverInfo = info));
    client.on("advertise", (channels) => {
      for (const ch of channels) {
        if (ch.encoding !== "json") continue;
        const id = client.subscribe(ch.id);
        this.channels.set(id, ch);
      }
    });
    client.on("message", ({ subscriptionId, data }) => {
      const ch = this.channels.get(subscriptionId);
      if (!ch) return;
      try {
        const msg = JSON.parse(decoder.decode(data));
        this.session.ingest(ch.topic, msg, ch.schemaName);
      } catch (e) {
        console.warn(`bad message on ${ch.topic}: ${e}`);
      }
    });
    client.on("advertiseServices", (services) => {
      for (const s of services) this.services.set(s.name, s);
      this.onServices([...this.services.keys()]);
    });
    client.on("unadvertiseServices", (ids) => {
      for (const [name, s] of this.services) if (ids.includes(s.id)) this.services.delete(name);
      this.onServices([...this.services.keys()]);
    });
    client.on("serviceCallResponse", ({ callId, data }) => {
      const p = this.pending.get(callId);
      if (!p) return;
      this.pending.delete(callId);
      const text = decoder.decode(data);
      let reply;
      try {
        reply = text ? JSON.parse(text) : {};
      } catch {
        reply = { message: text };
      }
      // The host answers {"message": TEXT}; a service whose answer is itself JSON (the editor's)
      // has it in that text.
      if (reply && typeof reply.message === "string" && Object.keys(reply).length === 1 && reply.message.startsWith("{")) {
        try {
          reply = JSON.parse(reply.message);
        } catch {
          // plain text after all
        }
      }
      p.resolve(reply);
    });
    client.on("serviceCallFailure", ({ callId, message }) => {
      const p = this.pending.get(callId);
      if (!p) return;
      this.pending.delete(callId);
      p.reject(new Error(message));
    });
    client.on("status", (s) => this.session.ingest("/log", { level: s.level, message: s.message }));
  }

  /** True when the host offers this service. */
  has(name) {
    return this.services.has(name);
  }

  /** Calls a service with a JSON request; resolves with the JSON response. */
  call(name, request = {}) {
    const service = this.services.get(name);
    if (!service) return Promise.reject(new Error(`the host offers no service '${name}'`));
    const callId = this.nextCall++;
    return new Promise((resolve, reject) => {
      this.pending.set(callId, { resolve, reject });
      this.client.sendServiceCallRequest({
        serviceId: service.id,
        callId,
        encoding: "json",
        data: new DataView(encoder.encode(JSON.stringify(request)).buffer),
      });
    });
  }
}
