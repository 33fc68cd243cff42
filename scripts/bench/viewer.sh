#!/usr/bin/env bash
# The viewer stream's targets (issue 19), written into docs/benchmarks.md (section viewer):
#   cost      the viewer's time on the run's thread per frame, against the pipeline's frame time,
#             on the default demo: without a viewer, with --serve and no client, with one client;
#   bandwidth what one client subscribed to every channel receives at default settings, per second
#             of wall time and per second of data, on the intel log and the simulated stereo street;
#   stalled   a client that stops reading: the run's rate, and its messages dropped and counted.
# Needs Node and tests/node's packages (scripts/install-web-deps.sh). Run scripts/build.sh first.
#   scripts/bench/viewer.sh [REPEATS]     (default 3; the median is reported)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
bin="$root/build/bin/plugslam"
[ -x "$bin" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
command -v node > /dev/null || { echo "viewer.sh needs Node (scripts/install-web-deps.sh)" >&2; exit 1; }
[ -d "$root/tests/node/node_modules/@foxglove/ws-protocol" ] ||
  { echo "viewer.sh needs tests/node's packages (scripts/install-web-deps.sh)" >&2; exit 1; }
: "${PLUGSLAM_DATA:=$root/../shared/data}"
export PLUGSLAM_DATA
repeats="${1:-3}"
out="${PLUGSLAM_BENCH_OUT:-$root/out/bench/viewer}"
rm -rf "$out"
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

for i in $(seq "$repeats"); do
  host "$out/demo-none-$i" none
  "$bin" run --serve 127.0.0.1:0 -o "$out/demo-serve-$i" > "$out/demo-serve-$i.stdout" 2> "$out/demo-serve-$i.stderr"
  host "$out/demo-client-$i" client
  host "$out/demo-stall-$i" stall
done
host "$out/intel" client "$root/configs/laser2d_carmen.yaml"
host "$out/street" client "$root/configs/sim3d_stereo.yaml" --set max_frames=300

python3 - "$out" "$repeats" > "$out/section.md" <<'PY'
import json, re, statistics, sys, pathlib
out, repeats = pathlib.Path(sys.argv[1]), int(sys.argv[2])

def run(d):
    r = json.load(open(d / "run.json"))
    mods = {m: v["total_s"] for m, v in r["modules"].items()}
    return r, mods

def median(values):
    return statistics.median(values)

rows = []
def case(label, dirs):
    frames, pipe, viewer, hz, thread = [], [], [], [], []
    for d in dirs:
        r, mods = run(d)
        frames.append(r["frames"])
        pipe.append(1e3 * r["pipeline_time_s"] / r["frames"])
        viewer.append(1e3 * mods.get("viewer", 0.0) / r["frames"])
        hz.append(r["hz"])
    return frames, pipe, viewer, hz

base = case("none", [out / f"demo-none-{i}" for i in range(1, repeats + 1)])
serve = case("serve", [out / f"demo-serve-{i}" for i in range(1, repeats + 1)])
client = case("client", [out / f"demo-client-{i}" for i in range(1, repeats + 1)])
stall = case("stall", [out / f"demo-stall-{i}" for i in range(1, repeats + 1)])
frame_ms = median(base[1])
def line(name, c):
    v = median(c[2])
    return (f"| {name} | {median(c[1]):.3f} | {v:.4f} | {100 * v / frame_ms:.2f} % | {median(c[3]):.0f} |")

drops = []
for i in range(1, repeats + 1):
    m = re.search(r"(\d+) stream messages dropped", (out / f"demo-stall-{i}" / "stderr").read_text())
    drops.append(int(m.group(1)) if m else -1)

def bandwidth(d):
    c = json.load(open(d / "client.json"))
    r, _ = run(d)
    top = ", ".join(f"{t} {b / 1e6:.2f}" for t, b in list(c["topics"].items())[:4])
    data = c["data_seconds"] or 0
    return (f"{r['frames']} | {c['seconds']:.1f} | {c['bytes'] / 1e6:.2f} | "
            f"{c['bytes'] / 1e6 / c['seconds']:.3f} | "
            f"{(c['bytes'] / 1e6 / data) if data > 0 else float('nan'):.3f} | {top}")

print("Cost on the default demo (`plugslam run`, simulated office, 1689 frames), median of "
      f"{repeats} runs. The viewer's time is the `viewer` module of run.json: the stream's work on "
      "the run's thread after each frame (the hub's encoding and the server run on their own "
      "threads). The share is that time over the pipeline's own frame time without a viewer.")
print()
print("| case | pipeline ms / frame | viewer ms / frame | viewer / frame time | wall Hz |")
print("|---|---|---|---|---|")
print(f"| no viewer | {median(base[1]):.3f} | 0 | 0 % | {median(base[3]):.0f} |")
print(line("`--serve`, no client", serve))
print(line("`--serve`, one client on every channel", client))
print(line("`--serve`, one client that stops reading", stall))
print()
print(f"Stalled client: the run's wall rate is {median(stall[3]):.0f} Hz against {median(client[3]):.0f} Hz "
      f"with a client that reads; its stream messages dropped (and counted on /status): "
      f"{', '.join(map(str, drops))} in the {repeats} runs.")
print()
print("Bandwidth of one client subscribed to every channel, default settings (`--view-rate 10`). "
      "The run replays as fast as it can, so per wall second is the worst case; per second of data "
      "is what a robot streaming live sends.")
print()
print("| run | frames | wall s | MB | MB / wall s | MB / data s | largest topics [MB] |")
print("|---|---|---|---|---|---|---|")
print(f"| intel (laser2d_carmen.yaml) | {bandwidth(out / 'intel')} |")
print(f"| stereo street (sim3d_stereo.yaml, 300 frames; no tracker yet: images and status only) | {bandwidth(out / 'street')} |")
PY
{
  echo "## Viewer stream: cost, bandwidth, stalled client (\`scripts/bench/viewer.sh\`)"
  echo
  echo "$("$(dirname "$0")/machine_info.sh")"
  echo
  cat "$out/section.md"
} | python3 "$(dirname "$0")/update_section.py" viewer "$root/docs/benchmarks.md"
echo "wrote docs/benchmarks.md (viewer)"
