# Sourced by the bench scripts after `set -euo pipefail`, with the bench's name:
#   . "$(dirname "$0")/common.sh" NAME
# so that every bench finds the checkout (root), the host (bin, PLUGSLAM_BIN), the data (data,
# PLUGSLAM_DATA) and its output folder (out, PLUGSLAM_BENCH_OUT, default out/bench/NAME) the same
# way, and stops before it runs anything when the host is not built.
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
here="$(dirname "$0")"
bin="${PLUGSLAM_BIN:-$root/build/bin/plugslam}"
[ -x "$bin" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
data="${PLUGSLAM_DATA:-$root/../shared/data}"
out="${PLUGSLAM_BENCH_OUT:-$root/out/bench/$1}"

# The start of the bench's section of docs/benchmarks.md: its title, then the machine it ran on
# (every section says where its figures were measured).
section_start() {
  echo "## $1"
  echo
  echo "$("$here/machine_info.sh")"
}

# Stops unless the data folder holds SUBDIR (a bench that cannot run says so at once).
need_data() { [ -d "$data/$1" ] || { echo "no data at $data/$1 (set PLUGSLAM_DATA)" >&2; exit 1; }; }

# How many of this machine's cores two busy processes get at once (2.00: two real cores; 1.00:
# the second adds nothing): what any parallel speed-up measured here is bounded by. A virtual
# machine's share of its host varies from second to second: the median of three rounds.
cores_delivered() {
  spin() { python3 -c 'import time
t = time.time(); x = 0
for i in range(20_000_000): x += i
print(time.time() - t)'; }
  local one two rounds=()
  for _ in 1 2 3; do
    one=$(spin)
    two=$( (spin & spin; wait) | sort -n | tail -1)
    rounds+=("$(python3 -c "print(2 * $one / $two)")")
  done
  printf '%s\n' "${rounds[@]}" | sort -n | sed -n 2p | xargs printf '%.2f\n'
}

# run_sweep NAME [DIR]: the bench's sweep, scripts/bench/NAME.sweep.yaml, run afresh into DIR
# (default $out; a sweep never reruns a finished case, and a bench measures the code as it is
# now) one case at a time (speed is measured), then its section NAME of docs/benchmarks.md
# written by `sweep report --section`. From the checkout's root, so the section's commands read
# as a user would type them there.
run_sweep() {
  local name="$1" dir="${2:-$out}"
  export PLUGSLAM_DATA="$data"
  cd "$root"
  rm -rf "$dir"
  dir="${dir#"$root"/}"
  "$bin" sweep run "scripts/bench/$name.sweep.yaml" -o "$dir" --engine local -j 1
  "$bin" sweep report "$dir" --no-plots --section "$name" --doc docs/benchmarks.md
}
