#!/usr/bin/env bash
# Installs what is needed, builds, and runs plugslam on its built-in default pipeline.
# Outputs land in out/demo (trajectory, map, run.json).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
"$root/build/bin/plugslam" run -o "${1:-$root/out/demo}"
