#!/usr/bin/env bash
# Configures and builds plugslam (Release, Ninja) into build/ (or $PLUGSLAM_BUILD_DIR).
# Extra arguments go to cmake's configure step, e.g. -DPLUGSLAM_SANITIZE=ON.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${PLUGSLAM_BUILD_DIR:-$root/build}"
jobs="${PLUGSLAM_JOBS:-2}"
export CCACHE_BASEDIR="$root"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE="${CMAKE_BUILD_TYPE:-Release}" \
  -DCMAKE_INSTALL_PREFIX="${PLUGSLAM_PREFIX:-$build/install}" "$@" > "$build.configure.log" 2>&1 \
  || { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j "$jobs"
