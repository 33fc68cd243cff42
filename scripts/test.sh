#!/usr/bin/env bash
# Installs what is needed, builds, and runs the whole test suite with ctest.
#   scripts/test.sh               Release build in build/
#   scripts/test.sh --sanitize    ASan+UBSan build in build-sanitize/
#   scripts/test.sh -L unit       extra arguments go to ctest (here: only unit tests)
# PLUGSLAM_WERROR=ON (CI sets it, as does CI=true) builds with warnings as errors.
# Tests that need real data read it from $PLUGSLAM_DATA (default ../shared/data) and skip,
# saying why, when it is absent; the end of the output counts the skipped tests and their reasons.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cmake_args=()
ctest_args=()
werror="${PLUGSLAM_WERROR:-$([ "${CI:-}" = true ] && echo ON || echo OFF)}"
cmake_args+=(-DPLUGSLAM_WERROR="$werror")
export PLUGSLAM_BUILD_DIR="$root/build"
for a in "$@"; do
  case "$a" in
    --sanitize)
      export PLUGSLAM_BUILD_DIR="$root/build-sanitize"
      cmake_args+=(-DPLUGSLAM_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo)
      export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
      export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" ;;
    *) ctest_args+=("$a") ;;
  esac
done
"$root/scripts/install-deps.sh"
# Node, the page's and the viewer tests' npm packages (runtime/web, tests/node), and Debian's
# chromium for the page's browser tests.
"$root/scripts/install-web-deps.sh" --browser
"$root/scripts/build.sh" "${cmake_args[@]}"
: "${PLUGSLAM_DATA:=$root/../shared/data}"
export PLUGSLAM_DATA
cd "$PLUGSLAM_BUILD_DIR"
junit="$PLUGSLAM_BUILD_DIR/Testing/results.xml"
rm -f "$junit"
rc=0
ctest --output-on-failure -j 2 --timeout 900 --output-junit "$junit" "${ctest_args[@]}" || rc=$?
# ctest counts skipped tests as passed and shows no reason: say how many, and why.
if [ -f "$junit" ]; then python3 "$root/scripts/skipped_tests.py" "$junit" || true; fi
exit "$rc"
