// MCAP recordings: @mcap/core's indexed reader opens a `--record` file (chunks, message indexes,
// summary) and reads back every message the host says it recorded, each valid against its schema;
// its stream reader reads the same messages with every CRC checked.
"use strict";
const fs = require("fs");
const path = require("path");
const { check, fail, skip, tempDir, hostPath } = require("./lib");
const { validators } = require("./schemas");
const { spawnSync } = require("child_process");

async function main() {
  let mcap;
  try {
    mcap = require("@mcap/core");
  } catch (e) {
    skip(`npm packages missing (${e.message.split("\n")[0]}): run scripts/install-web-deps.sh`);
  }
  const validatorFor = validators();
  const plugslam = hostPath();
  const out = tempDir("mcap");
  const file = path.join(out, "run.mcap");
  const run = spawnSync(plugslam, ["run", "--record", file, "-o", out, "--set", "max_frames=600"], {
    encoding: "utf8",
  });
  check(run.status === 0, `the recorded run ended normally (exit ${run.status})`);
  const said = /recorded (\d+) messages/.exec(run.stderr);
  check(said, "the host says how many messages it recorded");
  const recorded = Number(said[1]);

  const fd = fs.openSync(file, "r");
  const readable = {
    size: async () => BigInt(fs.fstatSync(fd).size),
    read: async (offset, size) => {
      const buffer = Buffer.alloc(Number(size));
      fs.readSync(fd, buffer, 0, Number(size), Number(offset));
      return new Uint8Array(buffer.buffer, buffer.byteOffset, buffer.byteLength);
    },
  };
  const reader = await mcap.McapIndexedReader.Initialize({ readable });
  check(reader.chunkIndexes.length > 0, `indexed: ${reader.chunkIndexes.length} chunk indexes in the summary`);
  check(reader.statistics && Number(reader.statistics.messageCount) === recorded,
        `statistics count ${reader.statistics && reader.statistics.messageCount} messages`);
  check(reader.channelsById.size >= 8, `${reader.channelsById.size} channels in the summary`);
  // What Foxglove and Lichtblick read to decode: no ROS profile, JSON messages with JSON schemas.
  check(reader.header.profile === "" && /^plugslam /.test(reader.header.library),
        `header: profile "${reader.header.profile}", library "${reader.header.library}"`);
  check([...reader.channelsById.values()].every((c) => c.messageEncoding === "json" &&
          reader.schemasById.get(c.schemaId) && reader.schemasById.get(c.schemaId).encoding === "jsonschema"),
        "every channel: json messages, a jsonschema schema");

  const decoder = new TextDecoder();
  const perChannel = new Map();
  let count = 0;
  let previous = -1n;
  for await (const m of reader.readMessages({ validateCrcs: true })) {
    const channel = reader.channelsById.get(m.channelId);
    const schema = reader.schemasById.get(channel.schemaId);
    const decoded = JSON.parse(decoder.decode(m.data));
    const error = validatorFor(schema.name, decoder.decode(schema.data))(decoded);
    if (error) fail(`${channel.topic}: ${error}`);
    if (m.logTime < previous) fail("messages out of log-time order");
    previous = m.logTime;
    perChannel.set(channel.topic, (perChannel.get(channel.topic) || 0) + 1);
    ++count;
  }
  check(count === recorded, `the indexed reader read back all ${count} messages, each valid`);
  for (const [id, n] of reader.statistics.channelMessageCounts)
    if (Number(n) !== perChannel.get(reader.channelsById.get(id).topic))
      fail(`channel ${id}: statistics say ${n}`);
  check(true, "per-channel counts match the statistics");
  for (const topic of ["/status", "/pose", "/tf", "/tf/maps", "/trajectory", "/scan/front", "/map/front", "/grid", "/graph"])
    check(perChannel.get(topic) > 0, `${topic}: ${perChannel.get(topic)} messages`);

  // Seeking: a window in the middle reads only its messages, through the index.
  const start = reader.statistics.messageStartTime, end = reader.statistics.messageEndTime;
  const mid = start + (end - start) / 2n;
  let windowed = 0;
  for await (const m of reader.readMessages({ startTime: mid, endTime: end })) {
    if (m.logTime < mid) fail("a message before the window");
    ++windowed;
  }
  check(windowed > 0 && windowed < count, `a time window reads ${windowed} of ${count} messages`);

  // The stream reader checks the chunk CRCs and the data section's CRC as it goes.
  const stream = new mcap.McapStreamReader({ validateCrcs: true });
  stream.append(new Uint8Array(fs.readFileSync(file)));
  let streamed = 0, footer = false;
  for (let r; (r = stream.nextRecord()); ) {
    if (r.type === "Message") ++streamed;
    if (r.type === "Footer") footer = true;
  }
  check(stream.done() && footer && streamed === count, `the stream reader reads ${streamed} messages, CRCs valid`);
  fs.closeSync(fd);
}

main().catch((e) => fail(e.stack || e));
