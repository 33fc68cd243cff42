// A 2D session of N local maps, as plugslam's channels carry it (foxglove.FrameTransforms,
// PointCloud, PosesInFrame, SceneUpdate): a robot driving a lawn-mower path through a building,
// one local map per metre (its origin on /tf/maps, as the host sends it), each holding the wall
// points its laser saw. For the page's frame-rate bench: the rendering cost depends on how much is
// drawn, not on where it came from.

function b64(bytes) {
  return Buffer.from(bytes.buffer, bytes.byteOffset, bytes.byteLength).toString("base64");
}

const q = (yaw) => ({ x: 0, y: 0, z: Math.sin(yaw / 2), w: Math.cos(yaw / 2) });

/** Messages [topic, message] of a session with `maps` local maps of `points` points each. */
export function syntheticSession({ maps = 1000, points = 600, loopsPerMap = 2 } = {}) {
  const out = [];
  const origins = [];
  const lane = 40; // metres per lane
  for (let i = 0; i < maps; ++i) {
    const row = Math.floor(i / lane), col = i % lane;
    const x = row % 2 === 0 ? col : lane - 1 - col, y = row * 4;
    const yaw = row % 2 === 0 ? 0 : Math.PI;
    origins.push([x, y]);
    const frame = `map/${i}`;
    out.push(["/tf/maps", { transforms: [{ timestamp: { sec: i, nsec: 0 }, parent_frame_id: "world", child_frame_id: frame, translation: { x, y, z: 0 }, rotation: q(yaw) }] }]);
    // Walls 1.5 m either side of the lane, seen over the metre of this map, plus clutter.
    const cloud = new Float32Array(points * 3);
    for (let k = 0; k < points; ++k) {
      const side = k % 2 === 0 ? 1.5 : -1.5;
      cloud[3 * k] = (k / points) * 3 - 1 + 0.01 * Math.sin(k * 12.9898);
      cloud[3 * k + 1] = side + 0.02 * Math.sin(k * 78.233);
    }
    out.push(["/map/front", {
      timestamp: { sec: i, nsec: 0 }, frame_id: frame,
      pose: { position: { x: 0, y: 0, z: 0 }, orientation: { x: 0, y: 0, z: 0, w: 1 } },
      point_stride: 12,
      fields: [{ name: "x", offset: 0, type: 7 }, { name: "y", offset: 4, type: 7 }, { name: "z", offset: 8, type: 7 }],
      data: b64(cloud),
    }]);
    const poses = [];
    for (let k = 0; k < 10; ++k) poses.push({ position: { x: k * 0.1, y: 0, z: 0 }, orientation: q(0) });
    out.push(["/trajectory", { timestamp: { sec: i, nsec: 0 }, frame_id: frame, poses }]);
  }
  const P = ([x, y]) => ({ x, y, z: 0 });
  const odometry = [], loops = [];
  for (let i = 1; i < maps; ++i) odometry.push(P(origins[i - 1]), P(origins[i]));
  for (let i = lane; i < maps; ++i)
    for (let l = 0; l < loopsPerMap; ++l) loops.push(P(origins[i]), P(origins[Math.max(0, i - lane - l)]));
  const line = (points, color) => ({ type: 2, pose: { position: P([0, 0]), orientation: q(0) }, thickness: 1, scale_invariant: true, points, color, colors: [], indices: [] });
  out.push(["/graph", {
    deletions: [],
    entities: [
      { id: "odometry", frame_id: "world", timestamp: { sec: maps, nsec: 0 }, lines: [line(odometry, { r: 0.5, g: 0.5, b: 0.5, a: 1 })] },
      { id: "loops", frame_id: "world", timestamp: { sec: maps, nsec: 0 }, lines: [line(loops, { r: 0.8, g: 0.1, b: 0.1, a: 1 })] },
      { id: "nodes", frame_id: "world", timestamp: { sec: maps, nsec: 0 }, spheres: origins.map((o) => ({ pose: { position: P(o), orientation: q(0) }, size: { x: 0.1, y: 0.1, z: 0.1 }, color: { r: 0, g: 0, b: 1, a: 1 } })) },
    ],
  }]);
  const last = origins[origins.length - 1];
  out.push(["/pose", { timestamp: { sec: maps, nsec: 0 }, frame_id: "world", pose: { position: P(last), orientation: q(0) } }]);
  const scan = new Float32Array(360 * 3);
  for (let k = 0; k < 360; ++k) {
    const a = (k / 360) * 2 * Math.PI;
    scan[3 * k] = 1.5 * Math.cos(a) / Math.max(0.2, Math.abs(Math.sin(a)));
    scan[3 * k + 1] = 1.5 * Math.sign(Math.sin(a));
  }
  out.push(["/scan/front", { timestamp: { sec: maps, nsec: 0 }, frame_id: "base_link", pose: { position: P([0, 0]), orientation: q(0) }, point_stride: 12, fields: [{ name: "x", offset: 0, type: 7 }, { name: "y", offset: 4, type: 7 }, { name: "z", offset: 8, type: 7 }], data: b64(scan) }]);
  out.push(["/status", { frame: maps * 10, hz: 30, loops: loops.length / 2, local_maps: maps, tracking_failures: 0, state: "running", dropped: 0, dropped_total: 0 }]);
  return out;
}
