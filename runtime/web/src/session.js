// What the page knows of the run: frames, local maps, trajectory, graph, current scan, grid,
// status and images, kept from the messages of the plugslam channels (Foxglove schemas, JSON).
// Rendering reads it; nothing here touches the DOM or three.js, so the fps bench and the tests
// can feed it messages directly.

/** Decodes a base64 string into bytes. */
export function fromBase64(text) {
  const bin = atob(text || "");
  const out = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) out[i] = bin.charCodeAt(i);
  return out;
}

/** A rigid transform as translation [x, y, z] and unit quaternion [x, y, z, w]. */
export function makeTransform(t = { x: 0, y: 0, z: 0 }, q = { x: 0, y: 0, z: 0, w: 1 }) {
  return { t: [t.x || 0, t.y || 0, t.z || 0], q: [q.x || 0, q.y || 0, q.z || 0, q.w ?? 1] };
}

function rotate(q, v) {
  const [x, y, z, w] = q;
  // v + 2 w (q x v) + 2 q x (q x v)
  const cx = y * v[2] - z * v[1], cy = z * v[0] - x * v[2], cz = x * v[1] - y * v[0];
  const dx = y * cz - z * cy, dy = z * cx - x * cz, dz = x * cy - y * cx;
  return [v[0] + 2 * (w * cx + dx), v[1] + 2 * (w * cy + dy), v[2] + 2 * (w * cz + dz)];
}

/** a * b (apply b, then a). */
export function compose(a, b) {
  const t = rotate(a.q, b.t);
  const [ax, ay, az, aw] = a.q, [bx, by, bz, bw] = b.q;
  return {
    t: [t[0] + a.t[0], t[1] + a.t[1], t[2] + a.t[2]],
    q: [
      aw * bx + ax * bw + ay * bz - az * by,
      aw * by - ax * bz + ay * bw + az * bx,
      aw * bz + ax * by - ay * bx + az * bw,
      aw * bw - ax * bx - ay * by - az * bz,
    ],
  };
}

/** Applies a transform to a point [x, y, z]. */
export function apply(T, p) {
  const r = rotate(T.q, p);
  return [r[0] + T.t[0], r[1] + T.t[1], r[2] + T.t[2]];
}

/** Heading (yaw) of a transform, radians. */
export function yawOf(T) {
  const [x, y, z, w] = T.q;
  return Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

const kFieldSize = { 1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 4, 8: 8 };

/** The x, y, z of every point of a foxglove.PointCloud, in its own frame, as a Float32Array. */
export function decodePointCloud(msg) {
  const bytes = msg._bytes || fromBase64(msg.data);
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const stride = msg.point_stride || 0;
  const field = (name) => (msg.fields || []).find((f) => f.name === name);
  const fx = field("x"), fy = field("y"), fz = field("z");
  const n = stride > 0 && fx && fy ? Math.floor(bytes.byteLength / stride) : 0;
  const read = (f, at) => {
    if (!f) return 0;
    switch (f.type) {
      case 7: return view.getFloat32(at + f.offset, true);
      case 8: return view.getFloat64(at + f.offset, true);
      case 5: return view.getInt32(at + f.offset, true);
      case 6: return view.getUint32(at + f.offset, true);
      default: return 0;
    }
  };
  const pose = msg.pose ? makeTransform(msg.pose.position, msg.pose.orientation) : null;
  const out = new Float32Array(n * 3);
  for (let i = 0; i < n; ++i) {
    const at = i * stride;
    let p = [read(fx, at), read(fy, at), read(fz, at)];
    if (pose) p = apply(pose, p);
    out[3 * i] = p[0];
    out[3 * i + 1] = p[1];
    out[3 * i + 2] = p[2];
  }
  return out;
}

/** Occupied cells (value >= 65 of 0..100, 255 unknown) of a foxglove.Grid as points. */
export function decodeGridOccupied(msg) {
  const bytes = msg._bytes || fromBase64(msg.data);
  const cols = msg.column_count || 0, cellStride = msg.cell_stride || 1;
  const rowStride = msg.row_stride || cols * cellStride;
  const rows = rowStride > 0 ? Math.floor(bytes.byteLength / rowStride) : 0;
  const f = (msg.fields || []).find((x) => x.name === "occupancy") || { offset: 0 };
  const sx = (msg.cell_size && msg.cell_size.x) || 0.05, sy = (msg.cell_size && msg.cell_size.y) || sx;
  const pose = makeTransform(msg.pose && msg.pose.position, msg.pose && msg.pose.orientation);
  const pts = [];
  for (let r = 0; r < rows; ++r)
    for (let c = 0; c < cols; ++c) {
      const v = bytes[r * rowStride + c * cellStride + f.offset];
      if (v >= 65 && v <= 100) pts.push(...apply(pose, [(c + 0.5) * sx, (r + 0.5) * sy, 0]));
    }
  return new Float32Array(pts);
}

/** The state of one viewed run. */
export class Session {
  constructor() {
    this.frames = new Map(); // child frame -> {parent, T}
    this.maps = new Map(); // "map/<id>" -> {cloud: Float32Array[], grid, trajectory: [[x,y,z]]}
    this.robot = null; // transform of base_link in world
    this.robotTrack = []; // world positions of /pose, for a live trail
    this.scan = null; // {frame, points}
    this.graph = { nodes: [], odometry: [], loops: [] }; // world points (pairs for lines)
    this.status = {};
    this.images = new Map(); // topic -> {format, bytes}
    this.log = [];
    this.version = 0; // bumped when anything drawn from the maps changes
    this.scanVersion = 0;
    this.messages = 0;
  }

  /** World transform of a frame (identity for "world" or unknown frames). */
  worldOf(frame, depth = 0) {
    if (!frame || frame === "world" || depth > 32) return makeTransform();
    const f = this.frames.get(frame);
    if (!f) return makeTransform();
    return compose(this.worldOf(f.parent, depth + 1), f.T);
  }

  map(frame) {
    let m = this.maps.get(frame);
    if (!m) {
      m = { clouds: new Map(), grid: null, trajectory: [], rev: 0 };
      this.maps.set(frame, m);
    }
    return m;
  }

  /**
   * Takes one decoded message of a channel. Transforms are known by their schema, as Foxglove and
   * Lichtblick know them, whatever the topic: the host sends the robot on /tf and the local maps'
   * origins on /tf/maps. Without a schema (messages fed by hand), /tf and /tf/... carry them.
   */
  ingest(topic, msg, schema = "") {
    ++this.messages;
    const transforms = schema
      ? schema === "foxglove.FrameTransforms" || schema === "foxglove.FrameTransform"
      : topic === "/tf" || topic.startsWith("/tf/");
    if (transforms) {
      for (const t of schema === "foxglove.FrameTransform" ? [msg] : msg.transforms || []) {
        this.frames.set(t.child_frame_id, {
          parent: t.parent_frame_id,
          T: makeTransform(t.translation, t.rotation),
        });
        if (t.child_frame_id.startsWith("map/")) this.version++;
      }
    } else if (topic === "/pose") {
      const T = compose(this.worldOf(msg.frame_id), makeTransform(msg.pose.position, msg.pose.orientation));
      this.robot = T;
      const last = this.robotTrack[this.robotTrack.length - 1];
      if (!last || Math.hypot(last[0] - T.t[0], last[1] - T.t[1], last[2] - T.t[2]) > 0.02)
        this.robotTrack.push(T.t);
    } else if (topic === "/trajectory") {
      const m = this.map(msg.frame_id);
      m.trajectory = (msg.poses || []).map((p) => [p.position.x, p.position.y, p.position.z || 0]);
      m.rev++;
      this.version++;
    } else if (topic.startsWith("/map/")) {
      const m = this.map(msg.frame_id);
      m.clouds.set(topic, decodePointCloud(msg));
      m.rev++;
      this.version++;
    } else if (topic === "/grid") {
      const m = this.map(msg.frame_id);
      m.grid = decodeGridOccupied(msg);
      m.rev++;
      this.version++;
    } else if (topic.startsWith("/scan/")) {
      this.scan = { frame: msg.frame_id, points: decodePointCloud(msg), topic };
      this.scanVersion++;
    } else if (topic === "/graph") {
      for (const e of msg.entities || []) {
        const W = this.worldOf(e.frame_id);
        const pts = [];
        for (const l of e.lines || []) {
          const lp = (l.points || []).map((p) => apply(W, [p.x, p.y, p.z || 0]));
          // LINE_LIST (2) pairs as given; LINE_STRIP (0) and LINE_LOOP (1) as consecutive pairs.
          if (l.type === 2) pts.push(...lp);
          else for (let i = 0; i + 1 < lp.length; ++i) pts.push(lp[i], lp[i + 1]);
        }
        for (const s of [...(e.spheres || []), ...(e.cubes || [])])
          pts.push(apply(W, [s.pose.position.x, s.pose.position.y, s.pose.position.z || 0]));
        if (e.id === "nodes" || e.id === "odometry" || e.id === "loops") this.graph[e.id] = pts;
      }
      this.version++;
    } else if (topic === "/status") {
      this.status = msg;
    } else if (topic === "/log") {
      this.log.push(msg);
      if (this.log.length > 200) this.log.shift();
    } else if (topic.startsWith("/camera/") && topic.endsWith("/image")) {
      this.images.set(topic, { format: msg.format, data: msg.data });
    }
  }

  /** Number of local maps seen. */
  localMaps() {
    return this.maps.size;
  }
}
