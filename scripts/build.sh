#!/usr/bin/env bash
# Configures and builds plugslam (Release, Ninja) into build/ (or $PLUGSLAM_BUILD_DIR).
# Extra arguments go to cmake's configure step, e.g. -DPLUGSLAM_SANITIZE=ON.
#   PLUGSLAM_JOBS     parallel compile jobs; default: the machine's cores, at most one per 2 GiB
#                     of available memory (a heavy translation unit takes about that much)
#   PLUGSLAM_TARGETS  build only these targets (space separated; default: everything)
#   PLUGSLAM_WERROR   ON: warnings are errors, as in CI (scripts/test.sh reads it the same way)
#   scripts/build.sh --print-jobs   prints the default job count and exits
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${PLUGSLAM_BUILD_DIR:-$root/build}"

default_jobs() {
  local cores mem_kib by_memory
  cores="$(nproc 2>/dev/null || echo 1)"
  mem_kib="$(awk '/^MemAvailable:/ {print $2}' /proc/meminfo 2>/dev/null || true)"
  by_memory=$(( ${mem_kib:-2097152} / 2097152 ))
  local jobs=$(( cores < by_memory ? cores : by_memory ))
  echo $(( jobs > 0 ? jobs : 1 ))
}
if [ "${1:-}" = "--print-jobs" ]; then
  default_jobs
  exit 0
fi
jobs="${PLUGSLAM_JOBS:-$(default_jobs)}"
export CCACHE_BASEDIR="$root"
werror=()
[ -n "${PLUGSLAM_WERROR:-}" ] && werror=(-DPLUGSLAM_WERROR="$PLUGSLAM_WERROR")
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE="${CMAKE_BUILD_TYPE:-Release}" \
  -DCMAKE_INSTALL_PREFIX="${PLUGSLAM_PREFIX:-$build/install}" "${werror[@]}" "$@" > "$build.configure.log" 2>&1 \
  || { cat "$build.configure.log"; exit 1; }
targets=()
for t in ${PLUGSLAM_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build "$build" -j "$jobs" "${targets[@]}"
