// ROS 2 input end to end (issue 21): makes the ROS 2 bags of ros2_bags.js from the DIS ROS 1 bag
// into a temporary folder, runs the C++ checks on them (plugins/io/tests/ros2_bags_test.cpp:
// frames bit for bit, /tf_static mounts, every bad input), then runs the laser pipeline on the
// ROS 1 bag and on every ROS 2 bag and requires the same trajectory, byte for byte.
//   node ros2_bags_test.js PLUGSLAM IO_ROS2_BAGS_TEST
"use strict";
const fs = require("fs");
const path = require("path");
const { spawnSync } = require("child_process");
const { check, skip, tempDir } = require("./lib");

const [plugslam, gtest] = process.argv.slice(2);
const data = process.env.PLUGSLAM_DATA || path.join(__dirname, "../../../shared/data");
const ros1 = path.join(data, "laser2d/dis-underground-rosbag/dis-underground.bag");
if (!fs.existsSync(ros1)) skip(`no DIS bag at ${ros1} (set PLUGSLAM_DATA)`);
const root = path.join(__dirname, "../..");
const dir = tempDir("ros2-bags");
try {
  const made = spawnSync(process.execPath, [path.join(__dirname, "ros2_bags.js"), ros1, dir], { encoding: "utf8" });
  if (made.status === 77) skip(made.stdout.trim());
  check(made.status === 0, `ros2_bags.js made the bags (${made.stdout.trim()}${made.stderr.trim()})`);
  const bags = JSON.parse(fs.readFileSync(path.join(dir, "bags.json"), "utf8"));

  const cpp = spawnSync(gtest, [], { encoding: "utf8", env: { ...process.env, PLUGSLAM_ROS2_BAGS: dir } });
  process.stdout.write(cpp.stdout.split("\n").filter((l) => /^\[( +OK|  FAILED|  SKIPPED|  PASSED) /.test(l) || /Failure|error/.test(l)).join("\n") + "\n");
  check(cpp.status === 0 && !/SKIPPED/.test(cpp.stdout), `the C++ checks on the bags pass (exit ${cpp.status})`);

  // The same pipeline (configs/laser2d_ros2.yaml is laser2d_rosbag.yaml's twin) on each bag.
  const run = (config, bagPath, name) => {
    const out = path.join(dir, `run_${name}`);
    const r = spawnSync(plugslam, ["run", path.join(root, "configs", config), "-o", out, "--set", `source.path=${bagPath}`],
                        { encoding: "utf8", env: process.env });
    check(r.status === 0, `${name}: the run ended normally (exit ${r.status}) ${r.status ? r.stderr.slice(-2000) : ""}`);
    return fs.readFileSync(path.join(out, "trajectory.tum"), "utf8");
  };
  const reference = run("laser2d_rosbag.yaml", ros1, "ros1");
  check(reference.split("\n").length > 4000, `ROS 1 trajectory of ${reference.split("\n").length - 1} poses`);
  for (const name of ["mcap_none", "mcap_zstd", "mcap_unindexed_lz4", "folder_mcap_lz4", "folder_db3"]) {
    const t = run("laser2d_ros2.yaml", bags[name], name);
    check(t === reference, `${name}: the trajectory is the ROS 1 run's, byte for byte`);
  }
} finally {
  fs.rmSync(dir, { recursive: true, force: true });
}
