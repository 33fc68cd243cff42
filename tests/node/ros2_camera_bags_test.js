// Camera input from ROS 2 bags end to end (issue 21): a simulated stereo run (sim.Simulator3D,
// configs/sim3d_stereo.yaml) is written in the KITTI odometry layout by io.ImageSequenceWriter,
// converted by ros2_bags.js --kitti into ROS 2 bags (CompressedImage PNG in MCAP, raw mono8 Image
// in a .db3 rosbag2 folder), and configs/stereo_ros2.yaml on each bag must give the trajectory of
// configs/stereo_kitti.yaml on the sequence folder, byte for byte (deterministic mode). The same
// for a simulated RGB-D run (configs/sim3d_rgbd.yaml) in the TUM layout, ros2_bags.js --tum
// (rgb8 Image or PNG CompressedImage + 32FC1 depth), configs/rgbd_ros2.yaml against
// configs/rgbd_tum.yaml with the simulator's pinhole.
//   node ros2_camera_bags_test.js PLUGSLAM
"use strict";
const fs = require("fs");
const path = require("path");
const { spawnSync } = require("child_process");
const { check, skip, tempDir } = require("./lib");

const [plugslam] = process.argv.slice(2);
const root = path.join(__dirname, "../..");
// Enough frames for several local maps of the street (8 m/s, 10 Hz, a split every 10 m).
const FRAMES = 40;
const dir = tempDir("ros2-camera-bags");
// The length of a TUM trajectory's path [m].
const pathLength = (tum) => {
  const xyz = tum.trim().split("\n").filter((l) => !l.startsWith("#")).map((l) => l.split(/\s+/).slice(1, 4).map(Number));
  let length = 0;
  for (let k = 1; k < xyz.length; ++k) length += Math.hypot(...xyz[k].map((v, i) => v - xyz[k - 1][i]));
  return length;
};
try {
  const run = (args, what) => {
    const r = spawnSync(plugslam, ["run", ...args], { encoding: "utf8", env: process.env });
    check(r.status === 0, `${what}: the run ended normally (exit ${r.status}) ${r.status ? r.stderr.slice(-2000) : ""}`);
    return r;
  };
  // The simulated run, its raw images kept as a KITTI sequence.
  const config = path.join(dir, "sim3d_stereo_export.yaml");
  fs.writeFileSync(config, `base: ${path.join(root, "configs/sim3d_stereo.yaml")}\n` +
                   "outputs[3]: {type: io.ImageSequenceWriter, layout: kitti, folder: sequence}\n");
  run([config, "-o", path.join(dir, "sim"), "--set", `max_frames=${FRAMES}`], "simulated stereo run");
  const seq = path.join(dir, "sim", "sequence");
  check(fs.existsSync(path.join(seq, "calib.txt")), "the run wrote the KITTI sequence");

  const made = spawnSync(process.execPath, [path.join(__dirname, "ros2_bags.js"), "--kitti", seq, path.join(dir, "bags")],
                         { encoding: "utf8" });
  if (made.status === 77) skip(made.stdout.trim());
  check(made.status === 0, `ros2_bags.js --kitti made the bags (${made.stdout.trim()}${made.stderr.trim()})`);
  const bags = JSON.parse(fs.readFileSync(path.join(dir, "bags", "stereo.json"), "utf8"));

  const trajectory = (config, source, name) => {
    const out = path.join(dir, `run_${name}`);
    run([path.join(root, "configs", config), "-o", out, "--set", `source.path=${source}`], name);
    return fs.readFileSync(path.join(out, "trajectory.tum"), "utf8");
  };
  const reference = trajectory("stereo_kitti.yaml", seq, "kitti");
  const poses = reference.trim().split("\n").filter((l) => !l.startsWith("#")).length;
  check(poses === FRAMES, `the KITTI-layout run has ${poses} poses (${FRAMES} frames)`);
  // A tracked drive, not a run stuck at its start: the street is driven at 8 m/s for 3.9 s.
  const length = pathLength(reference);
  check(length > 25 && length < 40, `the KITTI-layout run drove ${length.toFixed(2)} m (the simulator drives 8 m/s for 3.9 s)`);
  for (const name of ["stereo_mcap", "stereo_db3"]) {
    const t = trajectory("stereo_ros2.yaml", bags[name], name);
    check(t === reference, `${name}: the trajectory is the KITTI-layout run's, byte for byte`);
  }

  // RGB-D: a simulated living-room run in the TUM layout (depth 5000 per metre), as an RGB-D
  // driver's bags (colour rgb8 Image + 32FC1 depth in MCAP; colour PNG CompressedImage in .db3).
  const RGBD_FRAMES = 30;  // one second at 30 Hz
  const rgbdConfig = path.join(dir, "sim3d_rgbd_export.yaml");
  fs.writeFileSync(rgbdConfig, `base: ${path.join(root, "configs/sim3d_rgbd.yaml")}\n` +
                   "outputs[2]: {type: io.ImageSequenceWriter, layout: tum, folder: sequence}\n");
  run([rgbdConfig, "-o", path.join(dir, "sim_rgbd"), "--set", `max_frames=${RGBD_FRAMES}`], "simulated RGB-D run");
  const tum = path.join(dir, "sim_rgbd", "sequence");
  // The simulator's VGA camera (plugins/sim/src/sim3d/renderer.cpp), undistorted.
  const K = ["525", "525", "319.5", "239.5"];
  const madeRgbd = spawnSync(process.execPath, [path.join(__dirname, "ros2_bags.js"), "--tum", tum, path.join(dir, "rgbd_bags"), ...K],
                             { encoding: "utf8" });
  check(madeRgbd.status === 0, `ros2_bags.js --tum made the bags (${madeRgbd.stdout.trim()}${madeRgbd.stderr.trim()})`);
  const rgbdBags = JSON.parse(fs.readFileSync(path.join(dir, "rgbd_bags", "rgbd.json"), "utf8"));
  const folderRun = (() => {
    const out = path.join(dir, "run_tum");
    run([path.join(root, "configs", "rgbd_tum.yaml"), "-o", out, "--set", `source.path=${tum}`,
         "--set", `source.fx=${K[0]}`, "--set", `source.fy=${K[1]}`, "--set", `source.cx=${K[2]}`,
         "--set", `source.cy=${K[3]}`, "--set", "source.distortion_model=none", "--set", "source.distortion=[]"], "tum");
    return fs.readFileSync(path.join(out, "trajectory.tum"), "utf8");
  })();
  const rgbdPoses = folderRun.trim().split("\n").filter((l) => !l.startsWith("#")).length;
  check(rgbdPoses === RGBD_FRAMES, `the TUM-layout run has ${rgbdPoses} poses (${RGBD_FRAMES} frames)`);
  const walked = pathLength(folderRun);
  check(walked > 0.05, `the TUM-layout run moved ${walked.toFixed(3)} m (a hand-held loop)`);
  for (const name of ["rgbd_mcap", "rgbd_db3"]) {
    const t = trajectory("rgbd_ros2.yaml", rgbdBags[name], name);
    check(t === folderRun, `${name}: the trajectory is the TUM-layout run's, byte for byte`);
  }
} finally {
  fs.rmSync(dir, { recursive: true, force: true });
}
