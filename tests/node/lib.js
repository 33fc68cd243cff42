// Shared by the Node tests of the viewer stream: start the host, connect a Foxglove client, wait.
"use strict";
const { spawn } = require("child_process");
const fs = require("fs");
const os = require("os");
const path = require("path");

// CTest's "skipped" code (SKIP_RETURN_CODE in CMakeLists.txt).
const SKIP = 77;

function skip(why) {
  console.log(`SKIPPED: ${why}`);
  process.exit(SKIP);
}

// The client packages, or a skip saying how to get them.
function requireClient() {
  try {
    return {
      FoxgloveClient: require("@foxglove/ws-protocol").FoxgloveClient,
      WebSocket: require("ws"),
    };
  } catch (e) {
    skip(`npm packages missing (${e.message.split("\n")[0]}): run scripts/install-web-deps.sh`);
  }
}

function fail(message) {
  console.error(`FAIL: ${message}`);
  process.exit(1);
}

function check(condition, message) {
  if (!condition) fail(message);
  console.log(`ok - ${message}`);
}

// A fresh temporary folder of this test.
function tempDir(name) {
  return fs.mkdtempSync(path.join(os.tmpdir(), `plugslam-${name}-`));
}

// Starts `plugslam ARGS` and resolves { child, url } once it prints where it serves.
function startHost(plugslam, args, { timeoutMs = 60000 } = {}) {
  return new Promise((resolve, reject) => {
    const child = spawn(plugslam, args, { stdio: ["ignore", "pipe", "pipe"] });
    let out = "";
    let err = "";
    const timer = setTimeout(() => reject(new Error(`no "serving" line in ${timeoutMs} ms:\n${out}\n${err}`)), timeoutMs);
    child.stdout.on("data", (d) => {
      out += d;
      const m = /serving (ws:\/\/[^\s]+)/.exec(out);
      if (m && !child.url) {
        child.url = m[1];
        clearTimeout(timer);
        resolve({ child, url: m[1], output: () => out, errors: () => err });
      }
    });
    child.stderr.on("data", (d) => (err += d));
    child.on("exit", (code) => {
      child.exitCode_ = code;
      if (!child.url) {
        clearTimeout(timer);
        reject(new Error(`plugslam exited with ${code} before serving:\n${out}\n${err}`));
      }
    });
  });
}

// Resolves with the exit code of a child (at most timeoutMs).
function exited(child, timeoutMs = 120000) {
  return new Promise((resolve, reject) => {
    if (child.exitCode !== null) return resolve(child.exitCode);
    const timer = setTimeout(() => reject(new Error("the host did not exit")), timeoutMs);
    child.on("exit", (code) => {
      clearTimeout(timer);
      resolve(code);
    });
  });
}

// Resolves when predicate() is true (polled), rejects after timeoutMs.
function until(predicate, what, timeoutMs = 30000) {
  return new Promise((resolve, reject) => {
    const start = Date.now();
    const tick = () => {
      if (predicate()) return resolve();
      if (Date.now() - start > timeoutMs) return reject(new Error(`timed out waiting for ${what}`));
      setTimeout(tick, 20);
    };
    tick();
  });
}

// A Foxglove client that records what the server sends.
function connect(url, protocol = "foxglove.websocket.v1") {
  const { FoxgloveClient, WebSocket } = requireClient();
  const ws = new WebSocket(url, [protocol]);
  const client = new FoxgloveClient({ ws });
  const state = {
    client,
    ws, // the socket under the client (to stop reading it, in stalled-client tests)
    serverInfo: null,
    channels: new Map(), // id -> channel
    services: new Map(), // name -> service
    messages: new Map(), // topic -> [decoded JSON]
    bySubscription: new Map(), // subscription id -> channel
    statuses: [],
    parameterValues: [],
    responses: new Map(), // call id -> {ok, data|message}
    errors: [],
    closed: false,
    autoSubscribe: false, // subscribe to channels advertised later too (set by subscribeAll)
  };
  const decoder = new TextDecoder();
  client.on("serverInfo", (m) => (state.serverInfo = m));
  client.on("advertise", (channels) => {
    channels.forEach((c) => state.channels.set(c.id, c));
    if (state.autoSubscribe) state.subscribeAll();
  });
  client.on("advertiseServices", (s) => s.forEach((x) => state.services.set(x.name, x)));
  client.on("status", (s) => state.statuses.push(s));
  client.on("parameterValues", (p) => state.parameterValues.push(p));
  client.on("message", (m) => {
    const channel = state.bySubscription.get(m.subscriptionId);
    if (!channel) return state.errors.push(`a message for unknown subscription ${m.subscriptionId}`);
    const text = decoder.decode(m.data);
    let decoded;
    try {
      decoded = JSON.parse(text);
    } catch (e) {
      return state.errors.push(`${channel.topic}: not JSON: ${text.slice(0, 80)}`);
    }
    if (!state.messages.has(channel.topic)) state.messages.set(channel.topic, []);
    state.messages.get(channel.topic).push(decoded);
  });
  client.on("serviceCallResponse", (r) =>
    state.responses.set(r.callId, { ok: true, data: JSON.parse(decoder.decode(r.data)) }),
  );
  client.on("serviceCallFailure", (f) => state.responses.set(f.callId, { ok: false, message: f.message }));
  client.on("error", (e) => state.errors.push(String(e && e.message ? e.message : e)));
  client.on("close", () => (state.closed = true));
  state.subscribeAll = () => {
    state.autoSubscribe = true;
    for (const c of state.channels.values()) {
      if ([...state.bySubscription.values()].includes(c)) continue;
      const id = client.subscribe(c.id);
      state.bySubscription.set(id, c);
    }
  };
  let nextCall = 1;
  state.call = async (name, request = {}) => {
    const service = state.services.get(name);
    if (!service) throw new Error(`no service ${name}`);
    const callId = nextCall++;
    client.sendServiceCallRequest({
      serviceId: service.id,
      callId,
      encoding: "json",
      data: new TextEncoder().encode(JSON.stringify(request)),
    });
    await until(() => state.responses.has(callId), `the reply to ${name}`);
    return state.responses.get(callId);
  };
  return state;
}

// The plugslam executable: argv[2], or the build tree's.
function hostPath() {
  const p = process.argv[2] || path.join(__dirname, "..", "..", "build", "bin", "plugslam");
  if (!fs.existsSync(p)) skip(`no plugslam executable at ${p}`);
  return p;
}

// A whole run of the mixed world (laser, odometry, an RGB-D camera) with a graph back-end and a
// grid writer, so every kind of drawable goes out, watched by one client subscribed to every channel from the first
// frame (the run starts paused, the client resumes it). Resolves with the client's record once
// the server has closed.
async function watchMixedWorld(plugslam, { name, frames, protocol = "foxglove.websocket.v1" }) {
  const config = path.join(__dirname, "..", "..", "configs", "sim_mixed.yaml");
  const host = await startHost(plugslam, [
    "run", config, "--serve", "127.0.0.1:0", "--paused", "-o", tempDir(name),
    "--set", `max_frames=${frames}`,
    "--set", "outputs=[{type: laser2d.OccupancyMapWriter}]",
    "--set", "pipeline.graph={type: sdk.GraphSlam2D, deterministic: true}",
  ]);
  const s = connect(host.url, protocol);
  await until(() => s.serverInfo && s.services.size > 0, "serverInfo");
  s.subscribeAll();
  const r = await s.call("resume");
  check(r.ok, "resume");
  check((await exited(host.child)) === 0, "the run ended normally");
  await until(() => s.closed, "the server to close");
  return s;
}

module.exports = { SKIP, skip, fail, check, tempDir, startHost, exited, until, connect, hostPath, requireClient,
                   watchMixedWorld };
