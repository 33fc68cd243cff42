#!/usr/bin/env bash
# The viewer stream's targets (issue 19), written into docs/benchmarks.md (section viewer), on the
# built-in default demo (plain `plugslam run`: the simulated office, two lasers + odometry, with
# loop closing), the intel log (configs/laser2d_carmen.yaml: one laser + odometry, real data) and the simulated
# stereo street (configs/sim3d_stereo.yaml: two 1241x376 images per frame, landmark tracking):
#   cost      the viewer's time on the run's thread per frame against the pipeline's frame time,
#             and the pipeline's own frame time: without a viewer, with --serve and no client,
#             with one client subscribed to every channel;
#   bandwidth what that client receives at default settings, per second of wall time (the run
#             replays as fast as it can) and, for the street, live (--rate 1, the data's pace);
#   stalled   a client that stops reading: the run's rate, its messages dropped and counted.
# Needs Node and tests/node's packages (scripts/install-web-deps.sh). Run scripts/build.sh first.
#   scripts/bench/viewer.sh [REPEATS]     (default 3; the median is reported)
#   PLUGSLAM_VIEWER_CASES="demo intel street live stall" (default all): run only some, in pieces
#   (each piece keeps its outputs; the table is written from whatever is there)
set -euo pipefail
. "$(dirname "$0")/common.sh" viewer
command -v node > /dev/null || { echo "viewer.sh needs Node (scripts/install-web-deps.sh)" >&2; exit 1; }
[ -d "$root/tests/node/node_modules/@foxglove/ws-protocol" ] ||
  { echo "viewer.sh needs tests/node's packages (scripts/install-web-deps.sh)" >&2; exit 1; }
: "${PLUGSLAM_DATA:=$root/../shared/data}"
export PLUGSLAM_DATA
repeats="${1:-3}"
mkdir -p "$out"
client="$root/scripts/bench/viewer_client.js"

# host DIR [client|stall|none] ARGS...: one run; a client (when asked) resumes it and counts.
host() {
  local dir="$1" who="$2"
  shift 2
  mkdir -p "$dir"
  if [ "$who" = none ]; then
    "$bin" run -o "$dir" "$@" > "$dir/stdout" 2> "$dir/stderr"
    return
  fi
  "$bin" run --serve 127.0.0.1:0 --paused -o "$dir" "$@" > "$dir/stdout" 2> "$dir/stderr" &
  local pid=$!
  local url=""
  for _ in $(seq 600); do
    url=$(grep -o 'ws://[^ ]*' "$dir/stdout" 2> /dev/null | head -1 || true)
    [ -n "$url" ] && break
    sleep 0.1
  done
  [ -n "$url" ] || { cat "$dir/stderr" >&2; exit 1; }
  if [ "$who" = stall ]; then
    node "$client" "$url" --stall > "$dir/client.json" 2> "$dir/client.stderr" &
    local cpid=$!
    wait "$pid"
    kill "$cpid" 2> /dev/null || true
    wait "$cpid" 2> /dev/null || true
  else
    node "$client" "$url" > "$dir/client.json" 2> "$dir/client.stderr"
    wait "$pid"
  fi
}

demo=()  # no config: the host's built-in default
intel=("$root/configs/laser2d_carmen.yaml")
# 300 frames: 30 s of data, two images each; the street's loop needs no more to be typical.
street=("$root/configs/sim3d_stereo.yaml" --set max_frames=300)
cases="${PLUGSLAM_VIEWER_CASES:-demo intel street live stall}"
for name in demo intel street; do
  [[ " $cases " == *" $name "* ]] || continue
  declare -n args="$name"
  rm -rf "$out/$name"-{none,serve,client}-*
  for i in $(seq "$repeats"); do
    host "$out/$name-none-$i" none "${args[@]}"
    mkdir -p "$out/$name-serve-$i"
    "$bin" run --serve 127.0.0.1:0 -o "$out/$name-serve-$i" "${args[@]}" \
      > "$out/$name-serve-$i/stdout" 2> "$out/$name-serve-$i/stderr"
    host "$out/$name-client-$i" client "${args[@]}"
  done
  unset -n args
done
if [[ " $cases " == *" live "* ]]; then
  rm -rf "$out/street-live"
  host "$out/street-live" client "${street[@]}" --rate 1
fi
if [[ " $cases " == *" stall "* ]]; then
  # Each stalled run right after a run without a viewer: the machine's speed drifts over minutes,
  # so only neighbouring runs compare.
  rm -rf "$out"/street-stall*
  for i in $(seq "$repeats"); do
    host "$out/street-stallbase-$i" none "${street[@]}"
    host "$out/street-stall-$i" stall "${street[@]}"
  done
fi

python3 - "$out" "$repeats" > "$out/section.md" <<'PY'
import json, re, statistics, sys, pathlib
out, repeats = pathlib.Path(sys.argv[1]), int(sys.argv[2])

def run(d):
    r = json.load(open(d / "run.json"))
    return r, {m: v["total_s"] for m, v in r["modules"].items()}

def case(dirs):
    pipe, viewer, hz = [], [], []
    for d in dirs:
        r, mods = run(d)
        pipe.append(1e3 * r["pipeline_time_s"] / r["frames"])
        viewer.append(1e3 * mods.get("viewer", 0.0) / r["frames"])
        hz.append(r["hz"])
    return statistics.median(pipe), statistics.median(viewer), statistics.median(hz), r["frames"]

def bandwidth(d):
    c = json.load(open(d / "client.json"))
    r, _ = run(d)
    top = ", ".join(f"{t} {b / 1e6:.2f}" for t, b in list(c["topics"].items())[:4])
    data = c["data_seconds"] or 0
    return (f"{r['frames']} | {r['wall_time_s']:.1f} | {c['seconds']:.1f} | {c['bytes'] / 1e6:.2f} | "
            f"{c['bytes'] / 1e6 / c['seconds']:.3f} | "
            f"{(c['bytes'] / 1e6 / data) if data > 0 else float('nan'):.3f} | {top}")

runs = {"demo": "default demo (`plugslam run`, sim2d_double_laser.yaml)",
        "intel": "intel log (laser2d_carmen.yaml)",
        "street": "stereo street (sim3d_stereo.yaml, 300 frames)"}
print(f"Cost: median of {repeats} runs each. *viewer* is the `viewer` module of run.json: the "
      "stream's work on the run's thread after each frame (the hub's encoding, JPEG included, and "
      "the server run on their own threads); its share is over the pipeline's frame time without "
      "a viewer. *pipeline* is the pipeline's own time per frame, so the other threads' share of "
      "the 2 cores shows there.")
print()
print("| run | case | pipeline ms / frame | viewer ms / frame | viewer / frame time | pipeline vs no viewer | wall Hz |")
print("|---|---|---|---|---|---|---|")
for key, label in runs.items():
    dirs = lambda c: [out / f"{key}-{c}-{i}" for i in range(1, repeats + 1)]
    if not all((d / "run.json").exists() for d in dirs("none") + dirs("serve") + dirs("client")):
        continue
    base = case(dirs("none"))
    print(f"| {label} | no viewer | {base[0]:.3f} | 0 | 0 % | 0 % | {base[2]:.0f} |")
    for c, name in (("serve", "`--serve`, no client"), ("client", "`--serve`, one client on every channel")):
        v = case(dirs(c))
        print(f"| | {name} | {v[0]:.3f} | {v[1]:.4f} | {100 * v[1] / base[0]:.2f} % | "
              f"{100 * (v[0] - base[0]) / base[0]:+.1f} % | {v[2]:.0f} |")
print()
print("Bandwidth of one client subscribed to every channel, default settings (`--view-rate 10`, "
      "images at most 5 Hz, `--view-budget 1` MB/s). Replayed as fast as the run goes, per wall "
      "second is the worst case; live (`--rate 1`) is what a robot streaming as it records sends. "
      "*run s* is the run's own wall time; *wall s* is the client's, from resume until the server "
      "closes, which includes the end of the run held back by the budget and sent before closing.")
print()
print("| run | frames | run s | wall s | MB | MB / wall s | MB / data s | largest topics [MB] |")
print("|---|---|---|---|---|---|---|---|")
for key, label in runs.items():
    d = out / f"{key}-client-1"
    if (d / "client.json").exists():
        print(f"| {label} | {bandwidth(d)} |")
if (out / "street-live" / "client.json").exists():
    print(f"| stereo street live (`--rate 1`) | {bandwidth(out / 'street-live')} |")
stalls = sorted(out.glob("street-stall-*"))
if stalls and all((d / "run.json").exists() for d in stalls):
    hz = statistics.median(run(d)[0]["hz"] for d in stalls)
    bases = [out / d.name.replace("stall-", "stallbase-") for d in stalls]
    base = statistics.median(run(d)[0]["hz"] for d in bases)
    dropped = []
    for d in stalls:
        m = re.search(r"(\d+) stream messages dropped", (d / "stderr").read_text())
        dropped.append(m.group(1) if m else "none reported")
    print()
    print(f"Stalled client (stops reading after subscribing, on the stereo street; each of {len(stalls)} "
          f"runs right after one without a viewer, medians): the run went at {hz:.1f} Hz against "
          f"{base:.1f} Hz without a viewer; stream messages dropped and counted on /status: "
          f"{', '.join(dropped)}.")
PY
{
  section_start "Viewer stream: cost, bandwidth, stalled client (\`scripts/bench/viewer.sh\`)"
  echo
  cat "$out/section.md"
} | python3 "$(dirname "$0")/update_section.py" viewer "$root/docs/benchmarks.md"
echo "wrote docs/benchmarks.md (viewer)"
