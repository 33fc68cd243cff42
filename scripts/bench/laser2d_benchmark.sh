#!/usr/bin/env bash
# The Freiburg SLAM benchmark (Kuemmerle et al., "On measuring the accuracy of SLAM algorithms",
# 2009): the sweep scripts/bench/laser2d_benchmark.sweep.yaml, the one shipped config
# (configs/laser2d_carmen.yaml, only source.path set) on the benchmark logs in
# $PLUGSLAM_DATA/laser2d/*-kuemmerle-benchmark (the original .clf.bz2 and its manual relations),
# with its odometry and laser only, scored by `plugslam eval relations` exactly as the benchmark
# defines it. One case at a time (its Hz column must not share the cores); then `plugslam sweep
# report --section laser2d_benchmark` writes the table into docs/benchmarks.md with the machine,
# date and commit, the front-end's time split and the published figures (in the sweep's notes).
# The folder is emptied first: a sweep never reruns a finished case. Run scripts/build.sh first.
set -euo pipefail
. "$(dirname "$0")/common.sh" laser2d_benchmark
need_data laser2d/intel-kuemmerle-benchmark
need_data laser2d/fr079-kuemmerle-benchmark
run_sweep laser2d_benchmark
