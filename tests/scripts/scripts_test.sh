#!/usr/bin/env bash
# scripts_test.sh SOURCE_DIR BUILD_DIR: checks scripts/build.sh, demo.sh, install-deps.sh and
# skipped_tests.py as a user meets them (issue 17, items 21, 24, 25, 26). Writes only under a
# fresh temporary folder, removed at the end.
set -euo pipefail
src="$1"
build="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# 17.26: PLUGSLAM_JOBS defaults to the cores, at most one job per 2 GiB of available memory.
jobs="$("$src/scripts/build.sh" --print-jobs)"
[[ "$jobs" =~ ^[0-9]+$ ]] || fail "build.sh --print-jobs printed '$jobs'"
by_memory=$(( $(awk '/^MemAvailable:/ {print $2}' /proc/meminfo) / 2097152 ))
(( by_memory < 1 )) && by_memory=1
expected=$(( $(nproc) < by_memory ? $(nproc) : by_memory ))
[ "$jobs" -eq "$expected" ] || fail "default jobs $jobs, expected $expected (cores $(nproc), memory $by_memory)"
echo "ok: default PLUGSLAM_JOBS=$jobs"

# 17.25: demo.sh builds the host and the default config's plugins, nothing of the test suite.
targets="$("$src/scripts/demo.sh" --print-targets)"
[ "$(wc -w <<< "$targets")" -ge 2 ] || fail "demo targets: '$targets'"
known="$(ninja -C "$build" -t targets all)"
for t in $targets; do
  grep -q "^$t: " <<< "$known" || fail "demo target '$t' is not a target of the build"
done
[[ " $targets " == *" plugslam "* ]] || fail "the demo does not build the host: '$targets'"
[[ "$targets" != *test* ]] || fail "the demo builds tests: '$targets'"
echo "ok: demo builds $targets"

# 17.21: a user without root and without sudo gets the apt-get line to run as root, not
# "sudo: command not found". Stubs: id says uid 1000, dpkg-query finds no package, and PATH has
# no sudo.
stub="$tmp/bin"
mkdir -p "$stub"
printf '#!/bin/sh\necho 1000\n' > "$stub/id"
printf '#!/bin/sh\nexit 1\n' > "$stub/dpkg-query"
chmod +x "$stub/id" "$stub/dpkg-query"
for tool in bash grep dirname; do ln -s "$(command -v "$tool")" "$stub/$tool"; done
bash_bin="$(command -v bash)"
if out="$(PATH="$stub" "$bash_bin" "$src/scripts/install-deps.sh" 2>&1)"; then
  fail "install-deps.sh succeeded without root or sudo: $out"
fi
grep -q "command not found" <<< "$out" && fail "install-deps.sh: $out"
grep -q "there is no sudo" <<< "$out" || fail "install-deps.sh does not say why: $out"
grep -q "^  apt-get update && apt-get install -y --no-install-recommends build-essential " \
  <<< "$out" || fail "install-deps.sh does not print the apt-get line: $out"
echo "ok: install-deps.sh without sudo prints the command to run as root"

# 17.24: a skipped test is counted, with its reason, from a real ctest run (this test skips
# when the data folder has no intel log).
skipping='^PluginFault.BadInputMidRunStillSavesWhatWasBuilt$'
PLUGSLAM_DATA="$tmp/no-data" ctest --test-dir "$build" -R "$skipping" \
  --output-junit "$tmp/results.xml" > "$tmp/ctest.log" 2>&1 || fail "ctest: $(cat "$tmp/ctest.log")"
grep -q "1 tests passed\|tests passed, 0 tests failed out of 1" "$tmp/ctest.log" \
  || fail "the skipping test did not run: $(cat "$tmp/ctest.log")"
summary="$(python3 "$src/scripts/skipped_tests.py" "$tmp/results.xml")"
grep -q "^1 test skipped" <<< "$summary" || fail "no count of skipped tests: '$summary'"
grep -q "no intel log at $tmp/no-data" <<< "$summary" || fail "no reason: '$summary'"
echo "ok: skipped tests are counted with their reasons"
