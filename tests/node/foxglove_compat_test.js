// What Foxglove and Lichtblick need beyond schema validity, checked on a live run of the mixed
// world (laser, odometry, RGB-D camera, occupancy grid) with the current subprotocol
// (foxglove.sdk.v1, the one Foxglove 2 offers):
// - the subprotocol is echoed and serverInfo carries what the client reads (name, capabilities,
//   sessionId: a new one tells the client to drop its cached state);
// - each advertised JSON schema is a structural subset of @foxglove/schemas' own: every field we
//   declare has the official name and type, so the app's message paths and plots read them;
// - the frames form one tree rooted at `world` (the 3D panel renders nothing it cannot place):
//   each child has one parent, no cycle, every message's frame_id is reachable, rotations are unit;
// - the byte layouts the 3D and Image panels decode: point clouds (stride x count = data, fields
//   inside the stride), grids (row stride x rows = data), JPEG data, calibration matrix sizes and
//   a distortion model with its documented coefficient count.
"use strict";
const { check, fail, hostPath, skip, watchMixedWorld } = require("./lib");

function officialSchemas() {
  try {
    return require("@foxglove/schemas/jsonschema");
  } catch (e) {
    skip(`npm packages missing (${e.message.split("\n")[0]}): run scripts/install-web-deps.sh`);
  }
}

// Where `ours` declares something `official` does not, or with another type: a list of paths.
function subsetErrors(ours, official, at, errors) {
  if (!official) return errors.push(`${at}: not in the official schema`);
  if (ours.type && official.type && ours.type !== official.type &&
      !(ours.type === "integer" && official.type === "number"))
    errors.push(`${at}: ${ours.type}, official ${official.type}`);
  if (ours.type && !official.type && official.oneOf) {
    // An enum (NumericType, LogLevel, LineType...): integer constants.
    if (ours.type !== "integer" || !official.oneOf.every((o) => Number.isInteger(o.const)))
      errors.push(`${at}: ${ours.type}, official an enum`);
  }
  if (ours.contentEncoding && ours.contentEncoding !== official.contentEncoding)
    errors.push(`${at}: contentEncoding ${ours.contentEncoding}, official ${official.contentEncoding}`);
  for (const [name, sub] of Object.entries(ours.properties || {}))
    subsetErrors(sub, (official.properties || {})[name], `${at}.${name}`, errors);
  if (ours.items) subsetErrors(ours.items, official.items, `${at}[]`, errors);
  return errors;
}

// The frame_ids a message is drawn in.
function framesOf(schemaName, m) {
  switch (schemaName) {
    case "foxglove.SceneUpdate":
      return m.entities.map((e) => e.frame_id);
    case "foxglove.FrameTransforms":
      return [];
    default:
      return "frame_id" in m ? [m.frame_id] : [];
  }
}

function unitQuaternion(q, what) {
  const n = Math.hypot(q.x, q.y, q.z, q.w);
  // The host rounds to 6 decimals: a norm within 1e-5 of 1 (measured: under 3e-6).
  if (!(Math.abs(n - 1) < 1e-5)) fail(`${what}: a rotation of norm ${n}`);
}

// foxglove.NumericType sizes in bytes (UINT8 .. FLOAT64).
const typeSize = { 1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 4, 8: 8 };
// The coefficient counts the schema documents per distortion model.
const distortionCounts = { plumb_bob: [5], rational_polynomial: [8], kannala_brandt: [4], fisheye62: [6, 7] };

async function main() {
  const official = officialSchemas();
  const s = await watchMixedWorld(hostPath(), { name: "compat", frames: 60, protocol: "foxglove.sdk.v1" });
  check(s.ws.protocol === "foxglove.sdk.v1", `the subprotocol foxglove.sdk.v1 is echoed (${s.ws.protocol})`);
  const info = s.serverInfo;
  check(typeof info.name === "string" && info.name.length > 0, `serverInfo names the server (${info.name})`);
  check(typeof info.sessionId === "string" && info.sessionId.length > 0, "serverInfo has a sessionId");
  check(Array.isArray(info.capabilities) && info.capabilities.includes("services"),
        `capabilities ${JSON.stringify(info.capabilities)}`);

  // Advertised channels and their schemas.
  for (const c of s.channels.values()) {
    if (c.encoding !== "json" || c.schemaEncoding !== "jsonschema")
      fail(`${c.topic}: encoding ${c.encoding}, schemaEncoding ${c.schemaEncoding}`);
    const schema = JSON.parse(c.schema);
    if (!c.schemaName.startsWith("foxglove.")) continue;
    const reference = official[c.schemaName.slice("foxglove.".length)];
    if (!reference) fail(`${c.topic}: @foxglove/schemas has no ${c.schemaName}`);
    const errors = subsetErrors(schema, reference, c.schemaName, []);
    if (errors.length) fail(`${c.topic}: advertised schema differs from the official one: ${errors.join("; ")}`);
  }
  check(true, `${s.channels.size} channels: json + jsonschema, foxglove.* schemas a subset of the official ones`);

  // The frame tree.
  const parentOf = new Map();
  const schemaOfTopic = new Map([...s.channels.values()].map((c) => [c.topic, c.schemaName]));
  for (const [topic, messages] of s.messages) {
    if (schemaOfTopic.get(topic) !== "foxglove.FrameTransforms") continue;
    for (const m of messages)
      for (const t of m.transforms) {
        unitQuaternion(t.rotation, `${topic} ${t.parent_frame_id}->${t.child_frame_id}`);
        const known = parentOf.get(t.child_frame_id);
        if (known !== undefined && known !== t.parent_frame_id)
          fail(`${t.child_frame_id} has two parents: ${known} and ${t.parent_frame_id}`);
        parentOf.set(t.child_frame_id, t.parent_frame_id);
      }
  }
  const rooted = (frame) => {
    const seen = new Set();
    for (let f = frame; f !== "world"; f = parentOf.get(f)) {
      if (f === undefined || seen.has(f)) return false;
      seen.add(f);
    }
    return true;
  };
  check(parentOf.size >= 3 && [...parentOf.keys()].every(rooted),
        `${parentOf.size} frames, one tree rooted at world (${[...parentOf.keys()].slice(0, 4).join(", ")}...)`);
  const used = new Set();
  for (const [topic, messages] of s.messages)
    for (const m of messages)
      for (const f of framesOf(schemaOfTopic.get(topic), m)) {
        if (!rooted(f)) fail(`${topic}: frame_id "${f}" is not connected to world`);
        used.add(f);
      }
  check(used.size > 0, `every message's frame_id is placed in the tree (${used.size} frames used)`);

  // Byte layouts.
  const bytes = (b64) => Buffer.from(b64, "base64");
  let clouds = 0, grids = 0, images = 0, calibrations = 0;
  for (const [topic, messages] of s.messages) {
    const schemaName = schemaOfTopic.get(topic);
    for (const m of messages) {
      if ("pose" in m && m.pose) unitQuaternion(m.pose.orientation, topic);
      if (schemaName === "foxglove.PointCloud") {
        const data = bytes(m.data);
        if (m.point_stride <= 0 || data.length % m.point_stride !== 0)
          fail(`${topic}: ${data.length} bytes, stride ${m.point_stride}`);
        for (const f of m.fields)
          if (!typeSize[f.type] || f.offset + typeSize[f.type] > m.point_stride)
            fail(`${topic}: field ${f.name} (type ${f.type} at ${f.offset}) outside the stride ${m.point_stride}`);
        if (!["x", "y"].every((n) => m.fields.some((f) => f.name === n))) fail(`${topic}: no x and y fields`);
        ++clouds;
      } else if (schemaName === "foxglove.Grid") {
        const data = bytes(m.data);
        const rows = data.length / m.row_stride;
        if (!Number.isInteger(rows) || rows < 1 || m.row_stride < m.column_count * m.cell_stride ||
            !(m.cell_size.x > 0 && m.cell_size.y > 0))
          fail(`${topic}: ${data.length} bytes, ${m.column_count} columns, row stride ${m.row_stride}`);
        for (const f of m.fields)
          if (!typeSize[f.type] || f.offset + typeSize[f.type] > m.cell_stride) fail(`${topic}: field ${f.name} outside the cell`);
        ++grids;
      } else if (schemaName === "foxglove.CompressedImage") {
        const data = bytes(m.data);
        if (m.format !== "jpeg" || data[0] !== 0xff || data[1] !== 0xd8 || data[data.length - 2] !== 0xff ||
            data[data.length - 1] !== 0xd9)
          fail(`${topic}: format ${m.format}, not a complete JPEG`);
        ++images;
      } else if (schemaName === "foxglove.CameraCalibration") {
        if (m.K.length !== 9 || m.R.length !== 9 || m.P.length !== 12 || !(m.width > 0 && m.height > 0))
          fail(`${topic}: K ${m.K.length}, R ${m.R.length}, P ${m.P.length}, ${m.width}x${m.height}`);
        const counts = distortionCounts[m.distortion_model];
        if (!counts || !counts.includes(m.D.length))
          fail(`${topic}: distortion model "${m.distortion_model}" with ${m.D.length} coefficients`);
        ++calibrations;
      }
    }
  }
  check(clouds > 0 && grids > 0 && images > 0 && calibrations > 0,
        `layouts as the panels decode them: ${clouds} clouds, ${grids} grids, ${images} JPEG images, ${calibrations} calibrations`);
  check(s.errors.length === 0, `no client errors ${s.errors.slice(0, 3).join("; ")}`);
}

main().catch((e) => fail(e.stack || e));
