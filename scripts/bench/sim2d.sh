#!/usr/bin/env bash
# Reproduces the seed's Table I on the simulator: the sweep scripts/bench/sim2d.sweep.yaml (the
# single- and the double-laser pipeline on sessions stage-0..stage-3), run here one case at a
# time (its Hz column must not share the cores), then `plugslam sweep report --section sim2d`
# writes its table into docs/benchmarks.md. On a cluster: the same sweep with --engine slurm
# (docs/sweeps.md). The folder is emptied first: a sweep never reruns a finished case, and a
# bench measures the code as it is now. Run scripts/build.sh first.
set -euo pipefail
. "$(dirname "$0")/common.sh" sim2d
run_sweep sim2d
