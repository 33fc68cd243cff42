#!/usr/bin/env bash
# The visual bench (issues 15, 42): stereo and RGB-D tracking on the simulator and on the camera
# data in $PLUGSLAM_DATA, the sweep scripts/bench/visual.sweep.yaml (each dataset with its camera's
# shipped config; its own evaluators give the step, drift, standing-still, per-frame and depth
# figures and the time per stage, from scripts/bench/visual_metrics.py). One case at a time (speed
# is measured); then `plugslam sweep report --section visual` writes the table into
# docs/benchmarks.md. The folder is emptied first: a sweep never reruns a finished case. Run
# scripts/build.sh first (build/bin/rgbd_depth_check is one of the evaluators), and nothing else
# CPU-heavy at the same time.
set -euo pipefail
. "$(dirname "$0")/common.sh" visual
need_data stereo
need_data rgbd
run_sweep visual
