#!/usr/bin/env bash
# The visual SLAM bench (issue 16): stereo SLAM on the rendered street (the default drive and the
# full KITTI-00 path) with its loops checked against the ground truth, RGB-D SLAM (the rendered
# living room, the fr1_xyz path in it, real 7-Scenes) against tracking alone, and the mixed world's
# cues alone and together in one Multi-Aligner. Writes the `visual_slam` section of
# docs/benchmarks.md.
#   scripts/bench/visual_slam.sh                 every case
#   scripts/bench/visual_slam.sh street mixed    only these groups (street, kitti00, rgbd, mixed)
# Run scripts/build.sh first, and nothing else CPU-heavy at the same time (speed is measured).
set -euo pipefail
. "$(dirname "$0")/common.sh" visual_slam
metrics="$root/scripts/bench/visual_metrics.py"
mkdir -p "$out"
k00="$data/stereo/kitti00-trajectories-evo"
selected=" ${*:-street kitti00 rgbd mixed} "

# run NAME CONFIG [--set ...]: one run into $out/NAME; its run.json, or nothing when it failed.
run() {
  local name="$1" config="$2"
  shift 2
  echo "visual_slam: $name ..." >&2
  # The peak resident memory of the run (its own, as the kernel counts it) goes to NAME.rss.
  if ! python3 -c 'import resource, subprocess, sys
code = subprocess.call(sys.argv[2:], stdout=open(sys.argv[1] + ".log", "w"), stderr=subprocess.STDOUT)
open(sys.argv[1] + ".rss", "w").write(str(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss // 1024))
sys.exit(code)' "$out/$name" "$bin" run "$root/$config" -o "$out/$name" -q "$@"; then
    echo "visual_slam: $name failed, see $out/$name.log" >&2
    return 1
  fi
}

# One row of the SLAM table: run.json figures and the loops against the ground truth.
slam_row() {
  local name="$1" dir="$out/$1"
  python3 - "$dir/run.json" "$(python3 "$metrics" loops "$dir")" "$name" "$(cat "$dir.rss")" <<'PY'
import json, sys
r, l, name, rss = json.load(open(sys.argv[1])), json.loads(sys.argv[2]), sys.argv[3], sys.argv[4]
g, ref = r["graph"], r.get("reference", {})
opposite = sum(1 for x in l["return_list"] if x["heading_deg"] > 90)
print(f"| {name} | {r['frames']} | {r['pipeline_hz']:.1f} | {ref.get('ate_rmse_m', float('nan')):.3f} | "
      f"{g['loops_accepted']} / {g['loops_rejected']} | {l['wrong']} | {l['worst_m']:.3f} m, "
      f"{l['worst_deg']:.2f} deg | {l['returns_closed']} of {l['returns']} ({opposite} driven the "
      f"other way) | {rss} |")
PY
}

slam_rows=""
if [[ "$selected" == *" street "* ]] && run street configs/sim3d_stereo_slam.yaml; then
  slam_rows+="$(slam_row street)"$'\n'
fi
if [[ "$selected" == *" kitti00 "* ]]; then
  if [ ! -e "$k00/KITTI_00_gt.txt" ]; then
    echo "visual_slam: kitti00 skipped ($k00 is absent)" >&2
  elif run kitti00 configs/sim3d_stereo_slam.yaml --set "source.trajectory=$k00/KITTI_00_gt.txt" \
      --set "source.kitti_times=$k00/KITTI_00_gt_times.txt"; then
    slam_rows+="$(slam_row kitti00)"$'\n'
  fi
fi

# RGB-D SLAM against the same data tracked alone. Indoors a return is a map within 1 m of one
# more than 3 m of path back (the depth camera's range is about 4 m).
fr1="$data/rgbd/tum-fr1_xyz-trajectories-evo/freiburg1_xyz-groundtruth.txt"
rgbd_rows=""
if [[ "$selected" == *" rgbd "* ]]; then
  for c in "livingroom|configs/sim3d_rgbd.yaml|configs/sim3d_rgbd_slam.yaml|" \
           "fr1_xyz path|configs/sim3d_rgbd.yaml|configs/sim3d_rgbd_slam.yaml|$fr1" \
           "7-Scenes (real)|configs/rgbd_7scenes.yaml|configs/rgbd_7scenes_slam.yaml|"; do
    IFS='|' read -r label tracking slam trajectory <<< "$c"
    name="rgbd-$(echo "$label" | tr -cd 'a-zA-Z0-9')"
    args=()
    if [ -n "$trajectory" ]; then
      if [ ! -e "$trajectory" ]; then echo "visual_slam: $label skipped ($trajectory is absent)" >&2; continue; fi
      args=(--set "source.trajectory=$trajectory" --set source.rate=30)
    fi
    run "$name-tracking" "$tracking" "${args[@]}" || continue
    run "$name" "$slam" "${args[@]}" || continue
    rgbd_rows+="$(python3 - "$out/$name-tracking/run.json" "$out/$name/run.json" \
        "$(python3 "$metrics" loops "$out/$name" 1.0 3.0)" "$label" "$(cat "$out/$name.rss")" <<'PY'
import json, sys
t, r, l, label, rss = (json.load(open(sys.argv[1])), json.load(open(sys.argv[2])),
                       json.loads(sys.argv[3]), sys.argv[4], sys.argv[5])
g = r["graph"]
ate = lambda j: j.get("reference", {}).get("ate_rmse_m", float("nan"))
print(f"| {label} | {r['frames']} | {r['pipeline_hz']:.1f} | {ate(t):.4f} | {ate(r):.4f} | "
      f"{r['local_maps']} | {g['loops_accepted']} / {g['loops_rejected']} | {l['wrong']} | "
      f"{l['returns_closed']} of {l['returns']} | {r['tracking_failures']} | {rss} |")
PY
)"$'\n'
  done
fi

# The mixed world: each cue's aligner slices alone and together; the tracker keeps every cue's
# map in all of them, so only what constrains the pose differs.
laser="{type: laser2d.PointToLineSlice, measurement: front, scene: front}"
camera="{type: sdk.ReprojectionSlice2D, measurement: features, scene: landmarks, landmark_uncertainty: true}"
odom="{type: odometry.PriorSlice}"
dense="{type: rgbd.DepthSlice2D}"
# The dense depth rows add its keyframe to the tracker (the shipped config has no dense cue).
with_keyframe="pipeline.tracker.slices=[{type: laser2d.PointMapSlice, measurement: front, scene: front}, {type: sdk.LandmarkMapSlice2D, measurement: features, scene: landmarks}, {type: rgbd.DepthKeyframeSlice2D}]"
mixed_rows=""
if [[ "$selected" == *" mixed "* ]]; then
  for c in "laser|$laser" "laser + odometry|$laser, $odom" "RGB-D|$camera" \
           "RGB-D + odometry|$camera, $odom" "laser + RGB-D|$laser, $camera" \
           "laser + RGB-D + odometry (sim_mixed_rgbd.yaml)|$laser, $camera, $odom" \
           "RGB-D + dense depth|$camera, $dense|$with_keyframe" \
           "laser + RGB-D + dense depth|$laser, $camera, $dense|$with_keyframe"; do
    IFS='|' read -r label slices tracker <<< "$c"
    name="mixed-$(echo "$label" | tr -cd 'a-zA-Z+' | tr '+' '_')"
    extra=()
    [ -n "$tracker" ] && extra=(--set "$tracker")
    run "$name" configs/sim_mixed_rgbd.yaml --set "pipeline.tracker.aligner.slices=[$slices]" \
        "${extra[@]}" || continue
    mixed_rows+="$(python3 - "$out/$name" "$label" "$(cat "$out/$name.rss")" <<'PY'
import json, math, sys
d, label, rss = sys.argv[1], sys.argv[2], sys.argv[3]
r = json.load(open(d + "/run.json"))
ref = r.get("reference", {})
# Frame to frame: the error of each step's (x, y, heading) in the robot frame against the truth.
# Its RMS is the random part; its mean heading error, summed over the run, the drift that a bias
# leaves in the ATE.
load = lambda p: [list(map(float, l.split())) for l in open(p) if not l.startswith("#")]
yaw = lambda q: math.atan2(2 * (q[3] * q[2] + q[0] * q[1]), 1 - 2 * (q[1] ** 2 + q[2] ** 2))
def step(a, b):
    t = yaw(a[4:8]); dx, dy = b[1] - a[1], b[2] - a[2]
    return (math.cos(t) * dx + math.sin(t) * dy, -math.sin(t) * dx + math.cos(t) * dy,
            (yaw(b[4:8]) - t + math.pi) % (2 * math.pi) - math.pi)
R, T = load(d + "/reference.tum"), load(d + "/trajectory.tum")
e = [[u - v for u, v in zip(step(T[i], T[i + 1]), step(R[i], R[i + 1]))] for i in range(len(T) - 1)]
rms_t = math.sqrt(sum(x * x + y * y for x, y, _ in e) / len(e))
rms_r = math.sqrt(sum(h * h for _, _, h in e) / len(e))
drift = math.degrees(sum(h for _, _, h in e))
print(f"| {label} | {r['frames']} | {r['pipeline_hz']:.1f} | {ref.get('ate_rmse_m', float('nan')):.4f} | "
      f"{ref.get('ate_max_m', float('nan')):.4f} | {1000 * rms_t:.2f} mm, {1000 * rms_r:.2f} mrad | "
      f"{drift:+.2f} | {r['tracking_failures']} | {rss} |")
PY
)"$'\n'
  done
fi

# Each group writes its own section of docs/benchmarks.md (with the machine, date and commit it
# ran on), so one group can be measured again without the others.
update() { python3 "$(dirname "$0")/update_section.py" "$1" "$root/docs/benchmarks.md"; echo "wrote docs/benchmarks.md ($1)"; }
machine="$("$(dirname "$0")/machine_info.sh")"
if [ -n "$slam_rows" ]; then
  {
    echo "## Visual SLAM (issue 16)"
    echo
    echo "$machine"
    echo "Command: \`scripts/bench/visual_slam.sh street kitti00\`. Hz: the pipeline's own rate (run.json"
    echo "pipeline_hz), the front-end single-threaded, the back-end on its thread; rendering is not counted."
    echo
    echo "Stereo SLAM on the rendered street (configs/sim3d_stereo_slam.yaml): \`street\` is the default"
    echo "drive, \`kitti00\` the full KITTI-00 path (\`--set source.trajectory=KITTI_00_gt.txt\`). Loops:"
    echo "accepted / rejected by the validators and filters. Wrong: loop edges of the final graph off the"
    echo "ground truth by > 0.5 m or 2 deg (\`visual_metrics.py loops\`: each map matched to the frame"
    echo "it opened). Returns: places the ground truth comes back to (a map within 10 m of one more"
    echo "than 50 m of path back), and how many of them got a loop."
    echo
    echo "| run | frames | Hz | ATE [m] | loops | wrong | worst loop | returns closed | peak RSS [MB] |"
    echo "|---|---|---|---|---|---|---|---|---|"
    printf "%s" "$slam_rows"
  } | update visual_slam
fi
if [ -n "$rgbd_rows" ]; then
  {
    echo "### RGB-D SLAM"
    echo
    echo "$machine"
    echo "Command: \`scripts/bench/visual_slam.sh rgbd\`. configs/sim3d_rgbd_slam.yaml and"
    echo "configs/rgbd_7scenes_slam.yaml against the same data tracked alone (configs/sim3d_rgbd.yaml,"
    echo "configs/rgbd_7scenes.yaml). ATE: SE3-aligned RMSE (7-Scenes: against KinectFusion's poses,"
    echo "themselves good to 1-2 cm). Returns: a map within 1 m of one more than 3 m of path back, and"
    echo "how many got a loop. Hz: the SLAM run's pipeline rate, rendering not counted."
    echo
    echo "| data | frames | Hz | ATE tracking [m] | ATE SLAM [m] | local maps | loops | wrong | returns closed | failures | peak RSS [MB] |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|"
    printf "%s" "$rgbd_rows"
  } | update visual_slam_rgbd
fi
if [ -n "$mixed_rows" ]; then
  {
    echo "### Mixed cues: laser + RGB-D in one aligner"
    echo
    echo "$machine"
    echo "Command: \`scripts/bench/visual_slam.sh mixed\`. The mixed world (configs/sim_mixed_rgbd.yaml,"
    echo "a planar laser, wheel odometry and an RGB-D camera on one robot): the aligner's slices alone and"
    echo "together, tracking alone, ATE against the robot base. Per frame: the RMS error of each"
    echo "frame-to-frame step (x, y; heading) against the truth; heading drift: those steps' heading"
    echo "errors summed over the run (a bias, where the RMS is the random part). Dense depth: the RGB-D"
    echo "plugin's rgbd.DepthSlice2D joined to the aligner and its keyframe slice to the tracker."
    echo
    echo "| aligner slices | frames | Hz | ATE rmse [m] | ATE max [m] | per frame | heading drift [deg] | failures | peak RSS [MB] |"
    echo "|---|---|---|---|---|---|---|---|---|"
    printf "%s" "$mixed_rows"
  } | update visual_slam_mixed
fi
