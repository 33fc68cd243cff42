// Every channel's messages validate against @foxglove/schemas: a live run of the mixed world
// (laser, odometry, an RGB-D camera) with a client subscribed to every channel.
"use strict";
const path = require("path");
const { check, fail, tempDir, startHost, exited, until, connect, hostPath } = require("./lib");
const { validators } = require("./schemas");

async function main() {
  const validatorFor = validators();
  const plugslam = hostPath();
  const out = tempDir("schemas");
  const config = path.join(__dirname, "..", "..", "configs", "sim_mixed.yaml");
  // The mixed world's camera and a grid writer: every kind of drawable goes out.
  const host = await startHost(plugslam, [
    "run", config, "--serve", "127.0.0.1:0", "--paused", "-o", out,
    "--set", "max_frames=40",
    "--set", "outputs=[{type: laser2d.OccupancyMapWriter}]",
    "--set", "pipeline.graph={type: sdk.GraphSlam2D, deterministic: true}",
  ]);
  const s = connect(host.url);
  await until(() => s.serverInfo && s.services.size > 0, "serverInfo");
  s.subscribeAll();
  const r = await s.call("resume");
  check(r.ok, "resume");
  check((await exited(host.child)) === 0, "the run ended normally");
  await until(() => s.closed, "the server to close");
  const kinds = new Set();
  let count = 0;
  for (const channel of s.channels.values()) {
    const messages = s.messages.get(channel.topic) || [];
    const validate = validatorFor(channel.schemaName, channel.schema);
    for (const m of messages) {
      const error = validate(m);
      if (error) fail(`${channel.topic} (${channel.schemaName}): ${error}: ${JSON.stringify(m).slice(0, 300)}`);
      ++count;
    }
    if (messages.length) kinds.add(channel.schemaName);
    console.log(`  ${channel.topic} ${channel.schemaName}: ${messages.length} valid`);
  }
  for (const k of ["foxglove.FrameTransforms", "foxglove.PoseInFrame", "foxglove.PosesInFrame",
                   "foxglove.PointCloud", "foxglove.Grid", "foxglove.SceneUpdate",
                   "foxglove.CompressedImage", "foxglove.CameraCalibration", "plugslam.Status", "foxglove.Log"])
    check(kinds.has(k), `messages of ${k} received and valid`);
  check(count > 50, `${count} messages validated`);
  check(s.errors.length === 0, `no client errors ${s.errors.slice(0, 3).join("; ")}`);
}

main().catch((e) => fail(e.stack || e));
