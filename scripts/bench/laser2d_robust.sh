#!/usr/bin/env bash
# Issues 20 and 41: the one shipped config (configs/laser2d_carmen.yaml, nothing set per log) on
# every shared CARMEN log and on degraded variants of each: the sweep
# scripts/bench/laser2d_robust.sweep.yaml. The variants are written from the originals first
# (scripts/bench/laser2d_variants_all.sh; none is stored), the sweep runs one case at a time (its
# Hz column must not share the cores), then `plugslam sweep report --section laser2d_robust` writes
# its table, with the issue's targets judged per case, into docs/benchmarks.md. On a cluster: the
# same sweep with --engine slurm (docs/sweeps.md). The folder is emptied first: a sweep never
# reruns a finished case, and a bench measures the code as it is now. Another build or config for
# a "before" table: PLUGSLAM_BIN, then `sweep report DIR --compare BEFORE`. Run scripts/build.sh
# first.
set -euo pipefail
. "$(dirname "$0")/common.sh" laser2d_robust
need_data laser2d
cd "$root"
scripts/bench/laser2d_variants_all.sh
run_sweep laser2d_robust
