#!/usr/bin/env bash
# The visual bench (issue 15): stereo (and RGB-D) tracking on the simulator and on the real camera
# data in $PLUGSLAM_DATA. Per dataset: frames, the pipeline's own Hz (run.json pipeline_hz, the
# front-end single-threaded), ATE and RPE against the reference, the dataset's own target metric,
# tracking failures, keypoints and landmarks per frame, and the time per stage (extraction,
# matching, alignment, merge). Writes the `visual` section of docs/benchmarks.md.
#   scripts/bench/visual.sh            every case whose data is present
#   scripts/bench/visual.sh sim-block  only the named cases (see CASES below)
# Run scripts/build.sh first, and nothing else CPU-heavy at the same time (speed is measured).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
bin="$root/build/bin/plugslam"
[ -x "$bin" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
data="${PLUGSLAM_DATA:-$root/../shared/data}"
out="${PLUGSLAM_BENCH_OUT:-$root/out/bench/visual}"
metrics="$root/scripts/bench/visual_metrics.py"
mkdir -p "$out"

# One case: NAME|CONFIG|DATA (folder that must exist, or -)|METRIC (kitti, f2f, static, none)|
# TARGET (text for the table)|extra --set arguments. Cameras other than stereo add their rows here.
k00="$data/stereo/kitti00-trajectories-evo"
CASES=(
  "sim-block|configs/sim3d_stereo.yaml|-|kitti|-|"
  "sim-kitti00|configs/sim3d_stereo.yaml|$k00|kitti|drift <= 1.5 %|--set source.trajectory=$k00/KITTI_00_gt.txt --set source.kitti_times=$k00/KITTI_00_gt_times.txt"
  "kitti00-first5|configs/stereo_kitti.yaml|$data/stereo/kitti00-first5-srrg2|f2f|<= 2 %, <= 0.1 deg per frame|--set source.path=$data/stereo/kitti00-first5-srrg2"
  "euroc-v101-static|configs/stereo_euroc.yaml|$data/stereo/euroc-v101-static-kimera|static|within 1 cm, 0.5 deg; no failure|--set source.path=$data/stereo/euroc-v101-static-kimera"
  "kitti-raw-0001|configs/stereo_kitti_raw.yaml|$data/stereo/kitti-raw-0001-stereo-soft|none|no failure, >= 60 Hz|--set source.path=$data/stereo/kitti-raw-0001-stereo-soft"
)

selected=("$@")
rows=""
stages=""
for c in "${CASES[@]}"; do
  IFS='|' read -r name config need metric target extra <<< "$c"
  if [ ${#selected[@]} -gt 0 ] && [[ ! " ${selected[*]} " == *" $name "* ]]; then continue; fi
  if [ "$need" != "-" ] && [ ! -e "$need" ]; then
    echo "visual: $name skipped ($need is absent)" >&2
    continue
  fi
  if [ ! -e "$root/$config" ]; then
    echo "visual: $name skipped ($config does not exist yet)" >&2
    continue
  fi
  dir="$out/$name"
  echo "visual: $name ..." >&2
  # shellcheck disable=SC2086
  if ! "$bin" run "$root/$config" -o "$dir" -q $extra > "$dir.log" 2>&1; then
    echo "visual: $name failed, see $dir.log" >&2
    rows+="| $name | failed (see the log) | | | | | | $target |"$'\n'
    continue
  fi
  m="{}"
  if [ "$metric" != "none" ] && [ -e "$dir/reference.tum" ]; then
    m="$(python3 "$metrics" "$metric" "$dir/reference.tum" "$dir/trajectory.tum")"
  fi
  read -r row stage < <(python3 - "$dir/run.json" "$metric" "$m" "$name" "$target" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
metric, m, name, target = sys.argv[2], json.loads(sys.argv[3]), sys.argv[4], sys.argv[5]
ref = r.get("reference", {})
def f(v, fmt):
    return "-" if v is None else format(v, fmt)
stats = r.get("statistics", {})
def stat(key):
    for module, figures in stats.items():
        if key in figures:
            return figures[key], module
    return None, None
if metric == "kitti":
    got = f"{f(m.get('translation_percent'), '.2f')} % / {f(m.get('rotation_deg_per_100m'), '.3f')} deg/100 m ({m.get('segments', 0)} segments, {m.get('length_m', 0):.0f} m)"
elif metric == "f2f":
    got = f"mean {m['translation_percent_mean']:.2f} % (max {m['translation_percent_max']:.2f}), {m['rotation_deg_mean']:.3f} deg (max {m['rotation_deg_max']:.3f})"
elif metric == "static":
    got = f"{100 * m['estimate_max_m']:.2f} cm, {m['estimate_max_deg']:.3f} deg (reference moves {100 * m['reference_max_m']:.2f} cm, {m['reference_max_deg']:.3f} deg)"
else:
    got = "-"
kp, _ = stat("keypoints_per_frame")
depth, _ = stat("with_depth_per_frame")
matches, _ = stat("matched_per_frame")
lms, _ = stat("landmarks_per_frame")
n = max(1, r["frames"])
def ms(key):
    v, _ = stat(key)
    return "-" if v is None else f"{1e3 * v / n:.2f}"
row = (f"| {name} | {r['frames']} | {r['pipeline_hz']:.1f} | {f(ref.get('ate_rmse_m'), '.3f')} | "
       f"{f(ref.get('rpe_1m_rmse_m'), '.4f')} | {got} | {r['tracking_failures']} | {target} |")
stage = (f"| {name} | {f(kp, '.0f')} / {f(depth, '.0f')} | {f(matches, '.0f')} / {f(lms, '.0f')} | "
         f"{ms('extraction_s')} | {ms('matching_s')} | {ms('alignment_s')} | {ms('merge_s')} | "
         f"{1e3 * r['pipeline_time_s'] / n:.2f} |")
print(row.replace(" ", "\x1f"), stage.replace(" ", "\x1f"))
PY
)
  rows+="${row//$'\x1f'/ }"$'\n'
  stages+="${stage//$'\x1f'/ }"$'\n'
done
{
  echo "## Visual tracking (issue 15)"
  echo
  echo "$("$(dirname "$0")/machine_info.sh")"
  echo "Command: \`scripts/bench/visual.sh\`. Tracking alone (no loop closing). Hz is the pipeline's own"
  echo "rate (run.json pipeline_hz: frames / time inside the pipeline, without image decoding or"
  echo "rendering), single-threaded (the stereo plugin calls cv::setNumThreads(0): OpenCV runs sequentially in the caller). ATE: SE3-aligned RMSE;"
  echo "RPE: translation RMSE over 1 m of travel. Drift: the KITTI devkit's segment metric over"
  echo "100..800 m segments (scripts/bench/visual_metrics.py)."
  echo
  echo "| dataset | frames | Hz | ATE [m] | RPE 1 m [m] | target metric | failures | target |"
  echo "|---|---|---|---|---|---|---|---|"
  printf "%s" "$rows"
  echo
  echo "Per frame: keypoints / with depth, matched landmarks / landmarks in the local map, and the"
  echo "time per stage [ms] (run.json statistics; the pipeline column includes everything else)."
  echo
  echo "| dataset | keypoints | matches / landmarks | extraction | matching | alignment | merge | pipeline |"
  echo "|---|---|---|---|---|---|---|---|"
  printf "%s" "$stages"
} | python3 "$(dirname "$0")/update_section.py" visual "$root/docs/benchmarks.md"
echo "wrote docs/benchmarks.md (visual)"
