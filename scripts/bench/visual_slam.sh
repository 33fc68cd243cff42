#!/usr/bin/env bash
# The visual SLAM benches (issues 16, 42), three sweeps, each writing its own section of
# docs/benchmarks.md with `plugslam sweep report --section`:
#   street   scripts/bench/visual_slam.sweep.yaml        stereo SLAM (alone and with odometry) on the
#            rendered street, at highway speed and on the
#            KITTI-00 path, loops checked against the ground truth (section visual_slam)
#   rgbd     scripts/bench/visual_slam_rgbd.sweep.yaml   RGB-D data tracked alone and with SLAM
#            (section visual_slam_rgbd)
#   mixed    scripts/bench/visual_slam_mixed.sweep.yaml  the mixed world's aligner slices alone and
#            together (section visual_slam_mixed)
#   scripts/bench/visual_slam.sh              all three
#   scripts/bench/visual_slam.sh rgbd mixed   only these
# One case at a time (speed is measured); each sweep's folder is emptied first (a sweep never
# reruns a finished case). Run scripts/build.sh first, and nothing else CPU-heavy at the same time.
set -euo pipefail
. "$(dirname "$0")/common.sh" visual_slam
need_data stereo
need_data rgbd
for group in ${*:-street rgbd mixed}; do
  case "$group" in
    street) name=visual_slam ;;
    rgbd) name=visual_slam_rgbd ;;
    mixed) name=visual_slam_mixed ;;
    *) echo "visual_slam: unknown group '$group' (street, rgbd, mixed)" >&2; exit 2 ;;
  esac
  run_sweep "$name" "$root/out/bench/$name"
done
