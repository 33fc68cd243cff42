// Every channel's messages validate against @foxglove/schemas: a live run of the mixed world
// (laser, odometry, an RGB-D camera) with a client subscribed to every channel.
"use strict";
const { check, fail, hostPath, watchMixedWorld } = require("./lib");
const { validators } = require("./schemas");

async function main() {
  const validatorFor = validators();
  const s = await watchMixedWorld(hostPath(), { name: "schemas", frames: 40 });
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
