// Makes ROS 2 test bags with implementations independent of plugslam's: a ROS 1 bag read by
// @foxglove/rosbag, its messages re-serialized to CDR by @foxglove/rosmsg2-serialization (from the
// ROS 2 .msg definitions parsed by @foxglove/rosmsg), written as MCAP by @mcap/core (chunks
// uncompressed, lz4 by lz4js, zstd by @foxglove/wasm-zstd; indexed or not) and as rosbag2 SQLite
// by sql.js. Plus a small camera bag (Image, CompressedImage, CameraInfo, TFMessage) of known
// values for the CDR decoders. And a camera run in the KITTI odometry layout (a simulated one:
// io.ImageSequenceWriter) as the stereo bags a ROS 2 camera driver would record: the pair as
// CompressedImage (the PNG files' bytes) in MCAP and as raw mono8 Image (decoded here with
// node's zlib) in .db3, CameraInfo from calib.txt, the stamps of times.txt.
//   node ros2_bags.js IN.bag OUT_DIR            writes the bags listed in OUT_DIR/bags.json
//   node ros2_bags.js --kitti SEQ_DIR OUT_DIR   writes the stereo bags listed in OUT_DIR/stereo.json
//   node ros2_bags.js --tum SEQ_DIR OUT_DIR FX FY CX CY   the RGB-D bags (OUT_DIR/rgbd.json) of a
//                                             TUM-layout run (colour + 16-bit depth, 5000 per metre)
// Exit 77 (CTest's skip) when the npm packages are missing. The bags are build artifacts.
"use strict";
const fs = require("fs");
const path = require("path");
const zlib = require("zlib");

const SKIP = 77;
let deps;
try {
  deps = {
    Bag: require("@foxglove/rosbag").Bag,
    FileReader: require("@foxglove/rosbag/node").FileReader,
    Bzip2: require("@foxglove/wasm-bz2"),
    rosmsg: require("@foxglove/rosmsg"),
    MessageWriter: require("@foxglove/rosmsg2-serialization").MessageWriter,
    mcap: require("@mcap/core"),
    lz4: require("lz4js"),
    zstd: require("@foxglove/wasm-zstd"),
    initSqlJs: require("sql.js"),
  };
} catch (e) {
  console.log(`SKIPPED: npm packages missing (${e.message.split("\n")[0]}): run scripts/install-web-deps.sh`);
  process.exit(SKIP);
}

const SEP = "\n================================================================================\nMSG: ";
const TIME = "builtin_interfaces/Time\nint32 sec\nuint32 nanosec";
const HEADER = "std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id";
const VECTOR3 = "geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z";
const QUATERNION = "geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1";
// ROS 2 (Humble) definitions in the concatenated form rosbag2 stores as `ros2msg` schemas.
const DEFINITIONS = {
  "sensor_msgs/msg/LaserScan": [
    "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n" +
      "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n" +
      "float32[] ranges\nfloat32[] intensities",
    HEADER, TIME,
  ],
  "nav_msgs/msg/Odometry": [
    "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n" +
      "geometry_msgs/TwistWithCovariance twist",
    HEADER, TIME,
    "geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\nfloat64[36] covariance",
    "geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation",
    "geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z",
    QUATERNION,
    "geometry_msgs/TwistWithCovariance\ngeometry_msgs/Twist twist\nfloat64[36] covariance",
    "geometry_msgs/Twist\ngeometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular",
    VECTOR3,
  ],
  "tf2_msgs/msg/TFMessage": [
    "geometry_msgs/TransformStamped[] transforms",
    "geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n" +
      "geometry_msgs/Transform transform",
    HEADER, TIME,
    "geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation",
    VECTOR3, QUATERNION,
  ],
  "sensor_msgs/msg/Image": [
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n" +
      "uint32 step\nuint8[] data",
    HEADER, TIME,
  ],
  "sensor_msgs/msg/CompressedImage": ["std_msgs/Header header\nstring format\nuint8[] data", HEADER, TIME],
  "sensor_msgs/msg/CameraInfo": [
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\n" +
      "float64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\n" +
      "sensor_msgs/RegionOfInterest roi",
    HEADER, TIME,
    "sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify",
  ],
};

function schemaText(type) {
  const [root, ...deps] = DEFINITIONS[type];
  return root + deps.map((d) => SEP + d).join("");
}

const writers = new Map();
function serialize(type, message) {
  if (!writers.has(type)) {
    writers.set(type, new deps.MessageWriter(deps.rosmsg.parse(schemaText(type), { ros2: true })));
  }
  return writers.get(type).writeMessage(message);
}

// ROS 1 -> ROS 2 message objects.
const frame = (f) => (f.startsWith("/") ? f.slice(1) : f);
const header = (h) => ({ stamp: { sec: h.stamp.sec, nanosec: h.stamp.nsec }, frame_id: frame(h.frame_id) });
const CONVERT = {
  "sensor_msgs/LaserScan": ["sensor_msgs/msg/LaserScan", (m) => ({ ...m, header: header(m.header) })],
  "nav_msgs/Odometry": [
    "nav_msgs/msg/Odometry",
    (m) => ({ ...m, header: header(m.header), child_frame_id: frame(m.child_frame_id) }),
  ],
  "tf2_msgs/TFMessage": [
    "tf2_msgs/msg/TFMessage",
    (m) => ({
      transforms: m.transforms.map((t) => ({ ...t, header: header(t.header), child_frame_id: frame(t.child_frame_id) })),
    }),
  ],
};

// Reads the ROS 1 bag: [{topic, type (ROS 2), logTime (ns, BigInt), data (CDR)}], plus the
// /tf_static a ROS 2 robot would publish: every /tf edge whose transform never changes.
async function readRos1(file) {
  const bz2 = await deps.Bzip2.init();
  const reader = new deps.FileReader(file);
  const bag = new deps.Bag(reader, {
    parse: true,
    decompress: { bz2: (buffer, size) => bz2.decompress(buffer, size, { small: false }) },
  });
  await bag.open();
  const out = [];
  const edges = new Map();  // "parent child" -> {transform, changed}
  let firstNs = null;
  for await (const e of bag.messageIterator()) {
    const conv = CONVERT[bag.connections.get(e.connectionId).type];
    if (!conv) continue;
    const ns = BigInt(e.timestamp.sec) * 1000000000n + BigInt(e.timestamp.nsec);
    if (firstNs === null) firstNs = ns;
    const msg = conv[1](e.message);
    out.push({ topic: e.topic, type: conv[0], logTime: ns, data: serialize(conv[0], msg) });
    if (conv[0] === "tf2_msgs/msg/TFMessage") {
      for (const t of msg.transforms) {
        const key = `${t.header.frame_id} ${t.child_frame_id}`;
        const v = JSON.stringify(t.transform);
        const seen = edges.get(key);
        if (!seen) edges.set(key, { t, v, changed: false, n: 1 });
        else {
          seen.n += 1;
          if (seen.v !== v) seen.changed = true;
        }
      }
    }
  }
  await reader.close();
  const statics = [...edges.values()].filter((e) => !e.changed && e.n > 1).map((e) => e.t);
  if (statics.length > 0) {
    const m = { transforms: statics };
    out.unshift({ topic: "/tf_static", type: "tf2_msgs/msg/TFMessage", logTime: firstNs,
                  data: serialize("tf2_msgs/msg/TFMessage", m) });
  }
  return out;
}

async function writeMcap(file, messages, { compression = "", indexed = true, chunkSize = 256 * 1024 } = {}) {
  const fd = fs.openSync(file, "w");
  let position = 0n;
  const writable = {
    position: () => position,
    write: async (buffer) => {
      fs.writeSync(fd, buffer);
      position += BigInt(buffer.byteLength);
    },
  };
  const compressChunk =
    compression === "lz4" ? (d) => ({ compression: "lz4", compressedData: Uint8Array.from(deps.lz4.compress(d)) })
      : compression === "zstd" ? (d) => ({ compression: "zstd", compressedData: deps.zstd.compress(d, 3) })
      : undefined;
  const flags = indexed ? {} : {
    useStatistics: false, useSummaryOffsets: false, repeatSchemas: false, repeatChannels: false,
    useAttachmentIndex: false, useMetadataIndex: false, useMessageIndex: false, useChunkIndex: false,
  };
  const writer = new deps.mcap.McapWriter({ writable, chunkSize, compressChunk, ...flags });
  await writer.start({ profile: "ros2", library: "plugslam tests/node/ros2_bags.js" });
  const channels = new Map();
  for (const m of messages) {
    if (!channels.has(m.topic)) {
      const schemaId = await writer.registerSchema({
        name: m.type, encoding: "ros2msg", data: new TextEncoder().encode(schemaText(m.type)),
      });
      channels.set(m.topic, await writer.registerChannel({
        topic: m.topic, schemaId, messageEncoding: "cdr", metadata: new Map(),
      }));
    }
    await writer.addMessage({
      channelId: channels.get(m.topic), sequence: 0, logTime: m.logTime, publishTime: m.logTime, data: m.data,
    });
  }
  await writer.end();
  fs.closeSync(fd);
}

async function writeDb3(file, messages) {
  const SQL = await deps.initSqlJs();
  const db = new SQL.Database();
  // rosbag2's SQLite layout (schema version 3: what Humble's sqlite3 storage plugin reads).
  db.run("CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);" +
         "INSERT INTO schema VALUES (3, 'humble');" +
         "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, " +
         "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);" +
         "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, " +
         "timestamp INTEGER NOT NULL, data BLOB NOT NULL);" +
         "CREATE INDEX timestamp_idx ON messages (timestamp ASC);");
  const ids = new Map();
  db.run("BEGIN");
  for (const m of messages) {
    if (!ids.has(m.topic)) {
      ids.set(m.topic, ids.size + 1);
      db.run("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", [ids.get(m.topic), m.topic, m.type]);
    }
    // The stamp as an SQL literal: nanoseconds since 1970 exceed a double's 53 bits.
    db.run(`INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ${m.logTime.toString()}, ?)`,
           [ids.get(m.topic), m.data]);
  }
  db.run("COMMIT");
  fs.writeFileSync(file, Buffer.from(db.export()));
  db.close();
}

function writeMetadata(folder, storage, files, messages) {
  const counts = new Map();
  for (const m of messages) {
    const c = counts.get(m.topic) || { type: m.type, n: 0 };
    c.n += 1;
    counts.set(m.topic, c);
  }
  const first = messages.reduce((a, m) => (m.logTime < a ? m.logTime : a), messages[0].logTime);
  const last = messages.reduce((a, m) => (m.logTime > a ? m.logTime : a), messages[0].logTime);
  let y = "rosbag2_bagfile_information:\n  version: 5\n";
  y += `  storage_identifier: ${storage}\n`;
  y += `  duration:\n    nanoseconds: ${last - first}\n`;
  y += `  starting_time:\n    nanoseconds_since_epoch: ${first}\n`;
  y += `  message_count: ${messages.length}\n  topics_with_message_count:\n`;
  for (const [topic, c] of counts) {
    y += `    - topic_metadata:\n        name: ${topic}\n        type: ${c.type}\n` +
         `        serialization_format: cdr\n        offered_qos_profiles: ""\n` +
         `      message_count: ${c.n}\n`;
  }
  y += "  compression_format: \"\"\n  compression_mode: \"\"\n  relative_file_paths:\n";
  for (const f of files) y += `    - ${f}\n`;
  fs.writeFileSync(path.join(folder, "metadata.yaml"), y);
}

// Messages of known values for the CDR decoders' test.
function cameraMessages() {
  const stamp = { sec: 1700000000, nanosec: 123456789 };
  const h = { stamp, frame_id: "camera_optical" };
  const pixels = new Uint8Array(4 * 3 * 3).map((_, i) => i);
  const info = {
    header: h, height: 3, width: 4, distortion_model: "plumb_bob", d: [0.1, -0.2, 0.001, 0.002, 0.05],
    k: [500, 0, 320.5, 0, 501, 240.25, 0, 0, 1], r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
    p: [500, 0, 320.5, -25, 0, 501, 240.25, 0, 0, 0, 1, 0], binning_x: 1, binning_y: 2,
    roi: { x_offset: 5, y_offset: 6, height: 7, width: 8, do_rectify: true },
  };
  const tf = { transforms: [
    { header: { stamp, frame_id: "base_link" }, child_frame_id: "laser",
      transform: { translation: { x: 0.25, y: -0.1, z: 0.3 }, rotation: { x: 0, y: 0, z: Math.sin(0.25), w: Math.cos(0.25) } } },
    { header: { stamp, frame_id: "base_link" }, child_frame_id: "camera_optical",
      transform: { translation: { x: 0.1, y: 0, z: 0.5 }, rotation: { x: -0.5, y: 0.5, z: -0.5, w: 0.5 } } },
  ] };
  const ns = BigInt(stamp.sec) * 1000000000n + BigInt(stamp.nanosec);
  const list = [
    ["/camera/image_raw", "sensor_msgs/msg/Image",
     { header: h, height: 3, width: 4, encoding: "rgb8", is_bigendian: 0, step: 12, data: pixels }],
    ["/camera/image_raw/compressed", "sensor_msgs/msg/CompressedImage",
     { header: h, format: "jpeg", data: new Uint8Array([0xff, 0xd8, 0xff, 0xd9, 7]) }],
    ["/camera/camera_info", "sensor_msgs/msg/CameraInfo", info],
    ["/tf_static", "tf2_msgs/msg/TFMessage", tf],
  ];
  return list.map(([topic, type, m], i) => ({ topic, type, logTime: ns + BigInt(i), data: serialize(type, m) }));
}

// A PNG as written by plugslam's encoder (8-bit grey or RGB, not interlaced):
// {width, height, channels, pixels (rows without filter bytes)}. Throws on anything else.
function decodePng(bytes, name) {
  const sig = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a];
  if (!sig.every((b, i) => bytes[i] === b)) throw new Error(`${name}: not a PNG`);
  let at = 8, width = 0, height = 0, channels = 0, bits = 8;
  const idat = [];
  while (at < bytes.length) {
    const len = bytes.readUInt32BE(at);
    const type = bytes.toString("latin1", at + 4, at + 8);
    const body = bytes.subarray(at + 8, at + 8 + len);
    if (type === "IHDR") {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      const [depth, colour, , , interlace] = body.subarray(8, 13);
      channels = { 0: 1, 2: 3 }[colour];
      bits = depth;
      if ((depth !== 8 && !(depth === 16 && colour === 0)) || !channels || interlace !== 0)
        throw new Error(`${name}: not 8-bit grey/RGB or 16-bit grey, non-interlaced`);
    } else if (type === "IDAT") idat.push(body);
    else if (type === "IEND") break;
    at += 12 + len;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const bpp = channels * bits / 8;  // bytes per pixel: the filters' left neighbour
  const stride = width * bpp;
  const out = Buffer.alloc(stride * height);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; ++x) {
      const a = x >= bpp ? out[y * stride + x - bpp] : 0;
      const b = y > 0 ? out[(y - 1) * stride + x] : 0;
      const c = x >= bpp && y > 0 ? out[(y - 1) * stride + x - bpp] : 0;
      let v = line[x];
      if (filter === 1) v += a;
      else if (filter === 2) v += b;
      else if (filter === 3) v += (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        v += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      } else if (filter !== 0) throw new Error(`${name}: PNG filter ${filter}`);
      out[y * stride + x] = v & 0xff;
    }
  }
  return { width, height, channels, bits, pixels: out };  // 16 bits: big-endian samples
}

// A KITTI odometry sequence folder (image_0/, image_1/, calib.txt, times.txt) as the messages of
// a ROS 2 stereo camera: `compressed` = CompressedImage (the files' PNG bytes), else mono8 Image.
function kittiMessages(dir, { compressed }) {
  const calib = {};
  for (const line of fs.readFileSync(path.join(dir, "calib.txt"), "utf8").split("\n")) {
    const m = line.match(/^(P[0-3]):\s*(.*)$/);
    if (m) calib[m[1]] = m[2].trim().split(/\s+/).map(Number);
  }
  const times = fs.readFileSync(path.join(dir, "times.txt"), "utf8").trim().split(/\s+/).map(Number);
  const files = fs.readdirSync(path.join(dir, "image_0")).filter((f) => /^\d+\.png$/.test(f)).sort();
  if (files.length !== times.length) throw new Error(`${dir}: ${files.length} images, ${times.length} times`);
  // The stamp as ROS writes it: whole seconds and nanoseconds.
  const stampOf = (t) => {
    const sec = Math.floor(t);
    return { sec, nanosec: Math.round((t - sec) * 1e9) };
  };
  const nsOf = (s) => BigInt(s.sec) * 1000000000n + BigInt(s.nanosec);
  const first = decodePng(fs.readFileSync(path.join(dir, "image_0", files[0])), files[0]);
  const info = (frame, P) => ({
    header: { stamp: stampOf(times[0]), frame_id: frame }, height: first.height, width: first.width,
    distortion_model: "plumb_bob", d: [0, 0, 0, 0, 0],
    k: [P[0], P[1], P[2], P[4], P[5], P[6], P[8], P[9], P[10]], r: [1, 0, 0, 0, 1, 0, 0, 0, 1], p: P,
    binning_x: 0, binning_y: 0, roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false },
  });
  const t0 = nsOf(stampOf(times[0]));
  const out = [];
  const add = (topic, type, logTime, m) => out.push({ topic, type, logTime, data: serialize(type, m) });
  // The left camera is the robot frame here, as io.KittiSource takes camera 0's poses.
  add("/tf_static", "tf2_msgs/msg/TFMessage", t0, { transforms: [{
    header: { stamp: stampOf(times[0]), frame_id: "base_link" }, child_frame_id: "left_camera_optical",
    transform: { translation: { x: 0, y: 0, z: 0 }, rotation: { x: 0, y: 0, z: 0, w: 1 } } }] });
  add("/stereo/left/camera_info", "sensor_msgs/msg/CameraInfo", t0, info("left_camera_optical", calib.P0));
  add("/stereo/right/camera_info", "sensor_msgs/msg/CameraInfo", t0, info("right_camera_optical", calib.P1));
  files.forEach((f, k) => {
    const stamp = stampOf(times[k]);
    for (const [side, folder] of [["left", "image_0"], ["right", "image_1"]]) {
      const bytes = fs.readFileSync(path.join(dir, folder, f));
      const header = { stamp, frame_id: `${side}_camera_optical` };
      if (compressed) {
        add(`/stereo/${side}/image_rect`, "sensor_msgs/msg/CompressedImage", nsOf(stamp),
            { header, format: "mono8; png compressed", data: bytes });
      } else {
        const im = decodePng(bytes, f);
        if (im.channels !== 1) throw new Error(`${f}: not grey`);
        add(`/stereo/${side}/image_rect`, "sensor_msgs/msg/Image", nsOf(stamp),
            { header, height: im.height, width: im.width, encoding: "mono8", is_bigendian: 0, step: im.width, data: im.pixels });
      }
    }
  });
  return out;
}

// A TUM RGB-D sequence folder (rgb.txt, depth.txt, 16-bit depth PNGs of `depthScale` per metre)
// as an RGB-D camera's messages, depth aligned to colour: colour as rgb8 Image, or (`compressed`)
// CompressedImage (the PNG bytes); depth as 32FC1 metres, the float io.TumRgbdSource computes
// (the 16-bit value times float(1/scale), rounded to float), 0 and 65535 none.
function tumMessages(dir, { compressed, fx, fy, cx, cy, depthScale = 5000 }) {
  const list = (f) => fs.readFileSync(path.join(dir, f), "utf8").split("\n")
    .filter((l) => l.trim() && !l.startsWith("#")).map((l) => l.trim().split(/\s+/));
  const rgb = list("rgb.txt"), depth = list("depth.txt");
  if (rgb.length !== depth.length || rgb.some((r, k) => r[0] !== depth[k][0]))
    throw new Error(`${dir}: rgb.txt and depth.txt do not list the same stamps`);
  const stampOf = (text) => {
    const t = Number(text), sec = Math.floor(t);
    return { sec, nanosec: Math.round((t - sec) * 1e9) };
  };
  const nsOf = (s) => BigInt(s.sec) * 1000000000n + BigInt(s.nanosec);
  const first = decodePng(fs.readFileSync(path.join(dir, rgb[0][1])), rgb[0][1]);
  const frame = "camera_color_optical_frame";
  const t0 = stampOf(rgb[0][0]);
  const out = [];
  const add = (topic, type, logTime, m) => out.push({ topic, type, logTime, data: serialize(type, m) });
  add("/camera/color/camera_info", "sensor_msgs/msg/CameraInfo", nsOf(t0), {
    header: { stamp: t0, frame_id: frame }, height: first.height, width: first.width,
    distortion_model: "plumb_bob", d: [0, 0, 0, 0, 0], k: [fx, 0, cx, 0, fy, cy, 0, 0, 1],
    r: [1, 0, 0, 0, 1, 0, 0, 0, 1], p: [fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0], binning_x: 0, binning_y: 0,
    roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false },
  });
  const scale = Math.fround(1 / depthScale);
  rgb.forEach(([t, file], k) => {
    const stamp = stampOf(t);
    const header = { stamp, frame_id: frame };
    const bytes = fs.readFileSync(path.join(dir, file));
    if (compressed) {
      add("/camera/color/image_raw", "sensor_msgs/msg/CompressedImage", nsOf(stamp), { header, format: "rgb8; png compressed", data: bytes });
    } else {
      const im = decodePng(bytes, file);
      if (im.channels !== 3) throw new Error(`${file}: not RGB`);
      add("/camera/color/image_raw", "sensor_msgs/msg/Image", nsOf(stamp),
          { header, height: im.height, width: im.width, encoding: "rgb8", is_bigendian: 0, step: 3 * im.width, data: im.pixels });
    }
    const d = decodePng(fs.readFileSync(path.join(dir, depth[k][1])), depth[k][1]);
    if (d.bits !== 16) throw new Error(`${depth[k][1]}: not a 16-bit depth image`);
    const metres = new Float32Array(d.width * d.height);
    for (let i = 0; i < metres.length; ++i) {
      const v = d.pixels.readUInt16BE(2 * i);
      metres[i] = v === 0 || v === 65535 ? 0 : Math.fround(v * scale);
    }
    add("/camera/aligned_depth_to_color/image_raw", "sensor_msgs/msg/Image", nsOf(stamp),
        { header, height: d.height, width: d.width, encoding: "32FC1", is_bigendian: 0, step: 4 * d.width,
          data: new Uint8Array(metres.buffer) });
  });
  return out;
}

// node ros2_bags.js --tum SEQ OUT FX FY CX CY: the RGB-D bags of a TUM-layout sequence.
async function tumMain(seq, outDir, k) {
  fs.mkdirSync(outDir, { recursive: true });
  const [fx, fy, cx, cy] = k.map(Number);
  if (![fx, fy, cx, cy].every(Number.isFinite)) throw new Error("--tum needs FX FY CX CY");
  const out = (f) => path.join(outDir, f);
  const bags = {};
  const raw = tumMessages(seq, { compressed: false, fx, fy, cx, cy });
  await writeMcap(out("rgbd.mcap"), raw, {});
  bags.rgbd_mcap = out("rgbd.mcap");
  const compressed = tumMessages(seq, { compressed: true, fx, fy, cx, cy });
  fs.mkdirSync(out("rgbd_db3"), { recursive: true });
  await writeDb3(path.join(out("rgbd_db3"), "rgbd_db3_0.db3"), compressed);
  writeMetadata(out("rgbd_db3"), "sqlite3", ["rgbd_db3_0.db3"], compressed);
  bags.rgbd_db3 = out("rgbd_db3");
  fs.writeFileSync(out("rgbd.json"), JSON.stringify(bags, null, 1));
  console.log(`wrote ${Object.keys(bags).length} RGB-D bags of ${raw.length} messages into ${outDir}`);
}

async function kittiMain(seq, outDir) {
  await deps.zstd.isLoaded;
  fs.mkdirSync(outDir, { recursive: true });
  const out = (f) => path.join(outDir, f);
  const bags = {};
  const compressed = kittiMessages(seq, { compressed: true });
  await writeMcap(out("stereo_png_zstd.mcap"), compressed, { compression: "zstd" });
  bags.stereo_mcap = out("stereo_png_zstd.mcap");
  const raw = kittiMessages(seq, { compressed: false });
  fs.mkdirSync(out("stereo_db3"), { recursive: true });
  await writeDb3(path.join(out("stereo_db3"), "stereo_db3_0.db3"), raw);
  writeMetadata(out("stereo_db3"), "sqlite3", ["stereo_db3_0.db3"], raw);
  bags.stereo_db3 = out("stereo_db3");
  fs.writeFileSync(out("stereo.json"), JSON.stringify(bags, null, 1));
  console.log(`wrote ${Object.keys(bags).length} stereo bags of ${raw.length} messages into ${outDir}`);
}

async function main() {
  if (process.argv[2] === "--kitti") return kittiMain(process.argv[3], process.argv[4]);
  if (process.argv[2] === "--tum") return tumMain(process.argv[3], process.argv[4], process.argv.slice(5, 9));
  const [input, outDir] = process.argv.slice(2);
  if (!input || !outDir) {
    console.error("usage: node ros2_bags.js IN.bag OUT_DIR");
    process.exit(2);
  }
  await deps.zstd.isLoaded;
  fs.mkdirSync(outDir, { recursive: true });
  const messages = await readRos1(input);
  const out = (f) => path.join(outDir, f);
  const bags = {};
  await writeMcap(out("dis_none.mcap"), messages, {});
  bags.mcap_none = out("dis_none.mcap");
  await writeMcap(out("dis_zstd.mcap"), messages, { compression: "zstd" });
  bags.mcap_zstd = out("dis_zstd.mcap");
  await writeMcap(out("dis_unindexed_lz4.mcap"), messages, { compression: "lz4", indexed: false });
  bags.mcap_unindexed_lz4 = out("dis_unindexed_lz4.mcap");
  fs.mkdirSync(out("dis_lz4"), { recursive: true });
  await writeMcap(path.join(out("dis_lz4"), "dis_lz4_0.mcap"), messages, { compression: "lz4" });
  writeMetadata(out("dis_lz4"), "mcap", ["dis_lz4_0.mcap"], messages);
  bags.folder_mcap_lz4 = out("dis_lz4");
  fs.mkdirSync(out("dis_db3"), { recursive: true });
  await writeDb3(path.join(out("dis_db3"), "dis_db3_0.db3"), messages);
  writeMetadata(out("dis_db3"), "sqlite3", ["dis_db3_0.db3"], messages);
  bags.folder_db3 = out("dis_db3");
  bags.db3 = path.join(out("dis_db3"), "dis_db3_0.db3");
  await writeMcap(out("camera.mcap"), cameraMessages(), { compression: "zstd" });
  bags.camera = out("camera.mcap");
  fs.writeFileSync(out("bags.json"), JSON.stringify(bags, null, 1));
  console.log(`wrote ${Object.keys(bags).length} bags of ${messages.length} messages into ${outDir}`);
}

main().catch((e) => {
  console.error(`FAIL: ${e.stack || e}`);
  process.exit(1);
});
