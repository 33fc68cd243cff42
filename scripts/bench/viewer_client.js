// A viewer for scripts/bench/viewer.sh: connects to a `plugslam run --serve --paused`, subscribes
// to every channel, resumes the run and counts what arrives until the server goes. With --stall it
// stops reading right after subscribing (a stalled client). Prints one JSON line.
//   node viewer_client.js URL [--stall]
"use strict";
const path = require("path");
const { connect, until } = require(path.join(__dirname, "..", "..", "tests", "node", "lib"));

async function main() {
  const url = process.argv[2];
  const stall = process.argv.includes("--stall");
  const s = connect(url);
  const bytes = new Map();
  let total = 0, first = null, last = null;
  s.client.on("message", (m) => {
    const c = s.bySubscription.get(m.subscriptionId);
    const n = m.data.byteLength + 13;  // payload and the Message Data header
    total += n;
    if (c) bytes.set(c.topic, (bytes.get(c.topic) || 0) + n);
  });
  await until(() => s.serverInfo && s.services.size > 0, "serverInfo", 60000);
  s.subscribeAll();
  const start = Date.now();
  const r = await s.call("resume");
  if (!r.ok) throw new Error(`resume: ${r.message}`);
  if (stall) {
    // Stops reading: the TCP window closes and the server's queue for this client fills. The
    // bench ends this process once the run is over.
    s.ws._socket.pause();
    await new Promise(() => {});
  }
  await until(() => s.closed, "the run to end", 24 * 3600 * 1000);
  const seconds = (Date.now() - start) / 1000;
  const statuses = s.messages.get("/status") || [];
  for (const st of statuses) {
    const t = st.timestamp.sec + st.timestamp.nsec * 1e-9;
    if (t > 0) {
      if (first === null) first = t;
      last = t;
    }
  }
  const lastStatus = statuses[statuses.length - 1] || {};
  console.log(JSON.stringify({
    seconds, bytes: total, data_seconds: first !== null ? last - first : null,
    frames: lastStatus.frame, dropped: lastStatus.dropped, dropped_total: lastStatus.dropped_total,
    topics: Object.fromEntries([...bytes.entries()].sort((a, b) => b[1] - a[1])),
  }));
}

main().catch((e) => {
  console.error(e.stack || e);
  process.exit(1);
});
