#!/usr/bin/env bash
# End to end against the pipeline alone (issue 42): camera runs with the source read and decoded
# on the pipeline's thread (read_ahead=0) and ahead of it on a thread of its own (read_ahead=4,
# the default). Also measures how much two busy threads get of this machine's cores (two
# processes counting at once against one alone), which bounds what reading ahead can gain.
# Writes the `read-ahead` section of docs/benchmarks.md.
#   scripts/bench/read_ahead.sh [REPEATS]   (default 3; the median run is kept)
# Run scripts/build.sh first, and nothing else CPU-heavy at the same time (speed is measured).
set -euo pipefail
. "$(dirname "$0")/common.sh" read_ahead
repeats="${1:-3}"
mkdir -p "$out"
CASES=(
  "kitti-raw-0001|configs/stereo_kitti_raw.yaml|$data/stereo/kitti-raw-0001-stereo-soft"
  "7scenes-300|configs/rgbd_7scenes.yaml|$data/rgbd/7scenes-300frames-tsdf-fusion"
  "tum-fr1xyz|configs/rgbd_tum.yaml|$data/rgbd/rgbd_dataset_freiburg1_xyz"
)
parallel=$(cores_delivered)
rows=""
for c in "${CASES[@]}"; do
  IFS='|' read -r name config need <<< "$c"
  if [ "$need" != "-" ] && [ ! -e "$need" ]; then
    echo "read_ahead: $name skipped ($need is absent)" >&2
    continue
  fi
  row="| $name |"
  for ra in 0 4; do
    runs=()
    for _ in $(seq "$repeats"); do
      "$bin" run "$root/$config" -o "$out/$name-$ra" -q --set read_ahead=$ra > "$out/$name-$ra.log" 2>&1 \
        || { echo "read_ahead: $name failed, see $out/$name-$ra.log" >&2; continue 2; }
      runs+=("$(python3 -c "import json; r = json.load(open('$out/$name-$ra/run.json')); print(r['hz'], r['pipeline_hz'])")")
    done
    median=$(printf '%s\n' "${runs[@]}" | sort -n | sed -n "$(( (${#runs[@]} + 1) / 2 ))p")
    read -r hz phz <<< "$median"
    row+=" $(printf '%.1f' "$hz") / $(printf '%.1f' "$phz") ($(python3 -c "print(f'{$hz / $phz:.2f}')")) |"
  done
  rows+="$row"$'\n'
done
{
  section_start "Reading ahead of the pipeline (issue 42)"
  echo "Command: \`scripts/bench/read_ahead.sh\` (median of $repeats runs). End-to-end Hz (what a user"
  echo "waits for: reading and decoding included) / the pipeline's own Hz (run.json hz / pipeline_hz),"
  echo "and their ratio, with the source read on the pipeline's thread and ahead of it on its own."
  echo "Two busy processes at once get $parallel cores of this machine's $(nproc) (1.00: the second core"
  echo "adds nothing): reading ahead can only overlap decoding and tracking as far as that allows."
  echo
  echo "| dataset | read_ahead 0: end to end / pipeline | read_ahead 4 |"
  echo "|---|---|---|"
  printf '%s' "$rows"
} | python3 "$root/scripts/bench/update_section.py" read-ahead "$root/docs/benchmarks.md"
echo "wrote docs/benchmarks.md (read-ahead)" >&2
