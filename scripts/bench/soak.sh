#!/usr/bin/env bash
# Soak: replays the longest real logs endlessly (`source.repeat: 0`) for SECONDS each and samples
# the process's memory (VmRSS, VmHWM from /proc/PID/status, every 0.2 s) and its progress (the
# source logs the start of each replay). Two modes per log:
#   localize  the log is mapped once (`plugslam shell`: run, save), then `plugslam run --session
#             --localize` replays it against the frozen maps: nothing is added to the maps;
#   mapping   `plugslam run` maps every replay: each pass adds local maps and graph nodes.
# The run is stopped with SIGINT (it finishes, writes its outputs and exits 130); a run still
# finishing PLUGSLAM_SOAK_FINISH_S seconds later (default 300: the final optimization of a graph
# mapped many times over can take longer) is killed and reported as such. Writes the table into
# docs/benchmarks.md (section soak); raw samples and logs in out/bench/soak/.
#   scripts/bench/soak.sh [SECONDS] [MODE...]     (default 120 s, both modes)
#   PLUGSLAM_SOAK_REPORT_ONLY=1 scripts/bench/soak.sh SECONDS   table from the runs already made
# Run scripts/build.sh first. On a shared machine wrap it in flock (it keeps the CPU busy).
set -euo pipefail
. "$(dirname "$0")/common.sh" soak
seconds="${1:-120}"
finish_s="${PLUGSLAM_SOAK_FINISH_S:-300}"
shift || true
modes=("$@")
[ ${#modes[@]} -eq 0 ] && modes=(localize mapping)
need_data laser2d
mkdir -p "$out"
export TZ=UTC  # the log's clock and the sampler's must agree

# The longest logs the shipped configs map well: Freiburg 079 (4791 scans), the DIS bag (4427
# scans), intel (910). Freiburg campus (2008) is left out: the indoor configs lose track on it
# (148 tracking failures in one pass, 1490 local maps), so localizing in its maps fails.
logs=(freiburg-079-gfs-corrected/freiburg-079-corrected.log.gz
      dis-underground-rosbag/dis-underground.bag
      intel-gfs-corrected/intel-corrected.log.gz)

# Runs "$@" (a plugslam command line) in the background for $seconds, sampling its memory into
# files in the folder $1; then SIGINT, and waits for it to finish.
sample_run() {
  local run="$1"
  shift
  "$@" > "$run/stdout.log" 2> "$run/stderr.log" &
  local pid=$! start now signalled=0
  start=$(date +%s.%N)
  : > "$run/samples.txt"
  while kill -0 "$pid" 2> /dev/null; do
    now=$(date +%s.%N)
    awk -v t="$now" '/^VmRSS/ {r = $2} /^VmHWM/ {h = $2} END {if (r) print t, r, h}' \
      "/proc/$pid/status" >> "$run/samples.txt" 2> /dev/null || true
    if [ $signalled -eq 0 ] && awk -v a="$start" -v b="$now" -v s="$seconds" 'BEGIN {exit !(b - a >= s)}'; then
      kill -INT "$pid" 2> /dev/null || true
      echo "$now" > "$run/sigint.txt"
      signalled=1
    elif [ $signalled -eq 1 ] && awk -v a="$start" -v b="$now" -v s="$((seconds + finish_s))" 'BEGIN {exit !(b - a >= s)}'; then
      kill -KILL "$pid" 2> /dev/null || true
      echo "$now" > "$run/killed.txt"
      signalled=2
    fi
    sleep 0.2
  done
  local rc=0
  wait "$pid" || rc=$?
  echo "$rc" > "$run/exit.txt"
  [ "$rc" -eq 130 ] || { echo "soak: $run exited $rc (expected 130 after SIGINT)" >&2; tail -5 "$run/stderr.log" >&2; }
  return 0
}

rows=()
for rel in "${logs[@]}"; do
  log="$data/laser2d/$rel"
  [ -f "$log" ] || { echo "soak: skipping missing $log" >&2; continue; }
  name=$(basename "$(dirname "$rel")")
  if [[ "$log" == *.bag ]]; then cfg="$root/configs/laser2d_rosbag.yaml"; else cfg="$root/configs/laser2d_carmen.yaml"; fi
  base="$out/$name"
  if [ -n "${PLUGSLAM_SOAK_REPORT_ONLY:-}" ]; then
    frames=$(python3 -c "import json;print(json.load(open('$base/once/run.json'))['frames'])")
    for mode in "${modes[@]}"; do rows+=("$name $mode $frames $base/$mode"); done
    continue
  fi
  rm -rf "$base"
  mkdir -p "$base"
  # The shipped config on this log (a config must open its source to load).
  sed "s#^  path: .*#  path: $log#" "$cfg" > "$base/config.yaml"
  cfg="$base/config.yaml"
  # One pass, mapped, saved as a session (the maps of the localization soak; frames per pass).
  printf 'run\nwait\nsave %s\nquit\n' "$base/session" > "$base/map.shell"
  "$bin" shell "$cfg" --script "$base/map.shell" -o "$base/once" > "$base/map.log" 2>&1 ||
    { cat "$base/map.log" >&2; exit 1; }
  frames=$(python3 -c "import json;print(json.load(open('$base/once/run.json'))['frames'])")
  for mode in "${modes[@]}"; do
    run="$base/$mode"
    mkdir -p "$run"
    args=(run "$cfg" -o "$run/out" --set source.repeat=0 --checkpoint-every 0)
    [ "$mode" = localize ] && args+=(--session "$base/session" --localize)
    # Endless mapping piles every replay onto the same places: the final loop pass would try
    # ~24 candidates for each of tens of thousands of maps after the SIGINT, and each replay
    # starts with the odometry's jump from the log's end back to its start (carrying the whole
    # log's odometry drift), which the odometry audit would try to explain with up to 20 more
    # optimizations of that graph (memory is measured, not the end of the run).
    [ "$mode" = mapping ] && args+=(--set 'pipeline.graph.final_detectors=[]'
                                    --set 'pipeline.graph.loop_filters=[sdk.ConsistencyFilter, sdk.ResidualVeto]')
    echo "== $name $mode: ${seconds}s" >&2
    sample_run "$run" "$bin" "${args[@]}"
    rows+=("$name $mode $frames $run")
  done
done

python3 - "$seconds" "${rows[@]}" <<'EOF' | python3 "$(dirname "$0")/update_section.py" soak "$root/docs/benchmarks.md"
import datetime, json, re, statistics, subprocess, sys

seconds = sys.argv[1]
rows = [r.split(" ", 3) for r in sys.argv[2:]]
root = subprocess.run(["git", "rev-parse", "--show-toplevel"], capture_output=True, text=True).stdout.strip()
machine = subprocess.run([f"{root}/scripts/bench/machine_info.sh"], capture_output=True, text=True).stdout.strip()

def clock(line, day0):
    m = re.match(r"\[(\d+):(\d+):(\d+\.\d+)\]", line)
    if not m:
        return None
    t = day0 + int(m[1]) * 3600 + int(m[2]) * 60 + float(m[3])
    return t

summary, detail, notes = [], [], []
for name, mode, frames, run in rows:
    frames = int(frames)
    samples = [tuple(map(float, l.split())) for l in open(f"{run}/samples.txt") if l.strip()]
    if not samples:
        continue
    first = datetime.datetime.fromtimestamp(samples[0][0], datetime.timezone.utc)
    day0 = datetime.datetime(first.year, first.month, first.day, tzinfo=datetime.timezone.utc).timestamp()
    try:
        stop = float(open(f"{run}/sigint.txt").read())
    except FileNotFoundError:  # ended by itself
        stop = samples[-1][0]
    starts = []
    for line in open(f"{run}/stderr.log"):
        if re.search(r"\] \[info\] running ", line):
            starts = [clock(line, day0)]
        elif re.search(r"\] \[info\] .*: replay \d+", line):
            starts.append(clock(line, day0))
    try:
        report = json.load(open(f"{run}/out/run.json"))
        unfinished = None
    except FileNotFoundError:  # killed while finishing: what its log and samples say
        done = [int(m[1]) for m in re.finditer(r"\] \[info\] frame (\d+) ", open(f"{run}/stderr.log").read())]
        once = json.load(open(f"{run}/../once/run.json"))  # the same log mapped once
        report = {"frames": done[-1] if done else 0, "local_maps": "n/a", "graph": {"nodes": "n/a"},
                  "reference": once["reference"]}
        unfinished = samples[-1][0] - stop
        notes.append(f"{name} {mode}: still finishing {unfinished:.0f} s after SIGINT (the back-end's "
                     "final optimization), killed; frames = the last progress line, graph size unknown.")
    def rss_at(t):  # the first sample at or after t (the last one if none), in MiB
        after = [s for s in samples if s[0] >= t]
        return (after[0] if after else samples[-1])[1] / 1024
    complete = len(starts) - 1  # replays with a start and an end
    hz = [frames / (b - a) for a, b in zip(starts, starts[1:])]
    end_rss = [s for s in samples if s[0] <= stop][-1][1] / 1024
    peak = samples[-1][2] / 1024
    if complete >= 1:
        after_first = rss_at(starts[1])
        growth = f"{100 * (end_rss - after_first) / after_first:+.1f} %"
        after_first = f"{after_first:.1f}"
    else:
        growth, after_first = "n/a", "n/a"
    # The trajectory record: the pipeline keeps every tracked frame (144 bytes: stamp, local map,
    # pose in it) and, when the log has one, its reference pose (144 bytes) for the outputs.
    record = 144 * (2 if report["reference"]["ate_rmse_m"] is not None else 1)
    per_frame, beyond = "", "n/a"
    if complete >= 1:
        extra = max(report["frames"] - frames, 1)
        per_frame = f"{1024 * 1024 * (end_rss - rss_at(starts[1])) / extra:.0f}"
        rest = end_rss - rss_at(starts[1]) - extra * record / (1024 * 1024)
        beyond = f"{100 * rest / rss_at(starts[1]):+.1f} %"
    summary.append(f"| {name} | {mode} | {report['frames']} | {complete} | {after_first} | {end_rss:.1f} | "
                   f"{growth} | {per_frame or 'n/a'} | {record} | {beyond} | {peak:.1f} | "
                   f"{(f'{hz[0]:.0f} / {statistics.median(hz):.0f} / {hz[-1]:.0f}') if hz else 'n/a'} | "
                   f"{report['local_maps']} | {report['graph']['nodes']} |")
    # Replay by replay: the first three, then evenly spaced, and the last.
    picks = sorted(set(list(range(min(3, complete))) + list(range(0, complete, max(1, complete // 6))) + ([complete - 1] if complete else [])))
    detail.append(f"| {name} | {mode} | " + "; ".join(
        f"{i + 1}: {hz[i]:.0f} Hz, {rss_at(starts[i + 1]):.1f} MiB" for i in picks) + " |")

print("## Soak: endless replays of the longest logs")
print()
print(machine)
print(f"Command: `scripts/bench/soak.sh {seconds}` (configs/laser2d_carmen.yaml, configs/laser2d_rosbag.yaml"
      " with `source.repeat: 0`), each run stopped by SIGINT after the time given.")
print("localize: the log mapped once, then replayed endlessly with `--session ... --localize` (frozen")
print("maps; the steady state of a robot working in a known place). mapping: every replay is mapped")
print("anew (new local maps each pass; the pose graph grows with them, by design).")
print("Memory: VmRSS sampled every 0.2 s; growth = RSS at the end vs RSS when the first replay ended")
print("(target ≤ 5 % for a bounded run); bytes/frame = that growth over the frames after the first")
print("replay; record = the bytes per frame the pipeline keeps for the trajectory outputs (tracked")
print("pose, plus the reference pose when the log has one); beyond = the growth left once that record")
print("is taken out; peak = VmHWM, including the outputs written at the end. Hz: frames of one pass / its")
print("wall time (source, pipeline and sinks), for the first, median and last complete replays.")
print()
print("| log | mode | frames | replays | RSS after 1st [MiB] | RSS at end [MiB] | growth | bytes / frame | record [B/frame] | beyond the record | peak [MiB] | Hz first / median / last | local maps | graph nodes |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
print("\n".join(summary))
print()
for n in notes:
    print(f"Note: {n}")
    print()
print("Per replay (replay: Hz, RSS at its end):")
print()
print("| log | mode | replays |")
print("|---|---|---|")
print("\n".join(detail))
EOF
echo "wrote docs/benchmarks.md (soak)"
