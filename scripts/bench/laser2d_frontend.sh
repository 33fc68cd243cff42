#!/usr/bin/env bash
# The 2D laser front-end alone (issue 4's targets): the shipped configs with the graph back-end
# and the map writer dropped by --set, on every log in $PLUGSLAM_DATA/laser2d. Per log: beams
# per scan, scans/s inside the pipeline (single thread, best of 3 runs), the relative error over
# 1 m of travel against the log's GMapping poses (`plugslam eval rpe --unit m --delta 1`),
# local crispness (scans at most 10 apart) of ours and of the reference, and how noisy the
# reference itself is over 1 m (three-cornered hat with a laser-only and an odometry-only run,
# scripts/bench/reference_floor.py). Writes section laser2d_frontend of docs/benchmarks.md.
# A separate script (called by laser2d.sh) so the front-end figures can be refreshed alone in
# seconds, without the minutes of full SLAM.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
here="$(dirname "$0")"
bin="$root/build/bin/plugslam"
[ -x "$bin" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
data="${PLUGSLAM_DATA:-$root/../shared/data}"
[ -d "$data/laser2d" ] || { echo "no data at $data/laser2d (set PLUGSLAM_DATA)" >&2; exit 1; }
out="${PLUGSLAM_BENCH_OUT:-$root/out/bench/laser2d_frontend}"
mkdir -p "$out"

# Front-end only: no graph back-end, the trajectory writer as the only output.
frontend=(--set pipeline.graph=null --set "outputs=[{type: io.TrajectoryWriter, format: tum}]")
laser_only=(--set "pipeline.tracker.aligner.slices=[{type: laser2d.PointToLineSlice, measurement: front, scene: front}]")
# Only the odometry prior: the estimate is dead reckoning (one factor is a valid solution).
odometry_only=(--set "pipeline.tracker.aligner.slices=[{type: odometry.PriorSlice}]"
               --set pipeline.tracker.aligner.min_inliers=1)
json() { python3 -c "import json,sys;d=json.load(open(sys.argv[1]));print(eval(sys.argv[2]))" "$@"; }

rows=""
growth=""
for dir in "$data"/laser2d/*/; do
  name=$(basename "$dir")
  log=$(ls "$dir"/*.log.gz "$dir"/*.bag 2>/dev/null | head -n1 || true)
  [ -n "$log" ] || continue
  run="$out/$name"
  if [[ "$log" == *.bag ]]; then cfg="$root/configs/laser2d_rosbag.yaml"; else cfg="$root/configs/laser2d_carmen.yaml"; fi
  extra=(--set "source.path=$log")
  # Edmonton marks "no return" with ~51 m readings instead of the usual 80+ m.
  [[ "$name" == edmonton* ]] && extra+=(--set source.max_range=50)
  best=0
  for i in 1 2 3; do
    "$bin" run "$cfg" -o "$run" "${extra[@]}" "${frontend[@]}" -q > /dev/null
    hz=$(json "$run/run.json" "round(d['pipeline_hz'])")
    [ "$hz" -gt "$best" ] && best=$hz
  done
  frames=$(json "$run/run.json" "d['frames']")
  failures=$(json "$run/run.json" "d['tracking_failures']")
  beams=$(python3 "$here/scan_beams.py" "$log" || echo n/a)
  rpe="n/a | n/a"; crisp="n/a"; floor="n/a"
  if [ -s "$run/reference.tum" ]; then
    "$bin" eval rpe "$run/reference.tum" "$run/trajectory.tum" --unit m --delta 1 --format json -o "$run/rpe.json"
    rpe=$(json "$run/rpe.json" "f\"{d['translation_percent']['mean']:.2f} ({d['translation_percent']['rmse']:.2f}, {d['translation_percent']['std']:.2f}) | {d['rotation_deg']['mean']:.2f} ({d['rotation_deg']['rmse']:.2f}, {d['rotation_deg']['std']:.2f}) | {d['length_m']['mean']:.2f}\"")
    for t in trajectory reference; do
      "$bin" eval crispness "$log" "$run/$t.tum" --min-gap 1 --max-gap 10 --max-range 20 \
        --format json -o "$run/local_crisp_$t.json" > /dev/null 2>&1
    done
    crisp="$(json "$run/local_crisp_trajectory.json" "f\"{1000*d['mean_m']:.1f}\"") / $(json "$run/local_crisp_reference.json" "f\"{1000*d['mean_m']:.1f}\"")"
    "$bin" run "$cfg" -o "$run/laser_only" "${extra[@]}" "${frontend[@]}" "${laser_only[@]}" -q > /dev/null
    "$bin" run "$cfg" -o "$run/odometry_only" "${extra[@]}" "${frontend[@]}" "${odometry_only[@]}" -q > /dev/null
    python3 "$here/reference_floor.py" "$run/reference.tum" "$run/laser_only/trajectory.tum" \
      "$run/odometry_only/trajectory.tum" > "$run/reference_floor.json"
    floor=$(json "$run/reference_floor.json" "f\"{d['reference']['floor_translation_pct_mean']:.2f} / {d['reference']['floor_rotation_deg_mean']:.2f}\"")
    # How the error grows with the segment length: a part that does not grow is per-pose noise
    # (of the reference, as ours is locally crisper), the growing part is drift.
    cells=""
    for delta in 0.5 1 2 4 8; do
      "$bin" eval rpe "$run/reference.tum" "$run/trajectory.tum" --unit m --delta "$delta" --format json -o "$run/rpe_$delta.json"
      cells+=" $(json "$run/rpe_$delta.json" "f\"{100*d['translation_m']['mean']:.1f} cm, {d['translation_percent']['mean']:.2f} %\"") |"
    done
    growth+="| $name |$cells"$'\n'
  else
    rpe="n/a | n/a | n/a"
  fi
  rows+="| $name | $beams | $frames | $best | $failures | $rpe | $crisp | $floor |"$'\n'
done
{
  echo "## 2D laser front-end alone (no loop closure)"
  echo
  echo "$("$here/machine_info.sh")"
  echo "Command: \`scripts/bench/laser2d_frontend.sh\` (also run by \`scripts/bench/laser2d.sh\`): the shipped"
  echo "configs with \`--set pipeline.graph=null --set 'outputs=[{type: io.TrajectoryWriter, format: tum}]'\`."
  echo "Scans/s: frames / time inside the pipeline (run.json \`pipeline_hz\`), single thread, best of 3 runs."
  echo "Relative error over 1 m: \`plugslam eval rpe reference.tum trajectory.tum --unit m --delta 1\`, every"
  echo "scan i paired with the first scan j whose path length along the reference L_ij is ≥ 1 m; error"
  echo "E = (Q_i⁻¹Q_j)⁻¹(P_i⁻¹P_j) (Q reference, P ours); translation 100·|t(E)|/L_ij in %, rotation |angle(E)|"
  echo "in degrees; mean (rmse, std); L is the mean L_ij. Local crispness: \`plugslam eval crispness LOG TRAJ"
  echo "--min-gap 1 --max-gap 10 --max-range 20\` (mean distance from each point to the nearest point of scans"
  echo "1..10 apart, lower is more consistent), ours / the reference's. Reference floor: the mean error a"
  echo "perfect front-end would show against the reference, from the reference's own noise over the same"
  echo "segments (three-cornered hat, \`scripts/bench/reference_floor.py\`; see below)."
  echo
  echo "| log | beams | scans | scans/s | tracking failures | translation % over 1 m, mean (rmse, std) | rotation ° over 1 m, mean (rmse, std) | L [m] | local crispness ours / reference [mm] | reference floor translation % / rotation ° |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  printf "%s" "$rows"
  echo
  echo "Translation error against the reference by segment length (mean, in cm and in % of L_ij):"
  echo
  echo "| log | ≥ 0.5 m | ≥ 1 m | ≥ 2 m | ≥ 4 m | ≥ 8 m |"
  echo "|---|---|---|---|---|---|"
  printf "%s" "$growth"
  echo
  echo "The reference is GMapping's estimate, not ground truth, and it is noisy pose by pose. Reference"
  echo "floor: three estimates of every 1 m segment's motion, the reference (A), the laser-only front-end"
  echo "(B, the odometry prior dropped) and dead reckoning (C, only the odometry prior), give var(A−B),"
  echo "var(A−C), var(B−C) per component (robust, 1.4826·MAD); if the three errors are independent,"
  echo "σ_A² = (var(A−B) + var(A−C) − var(B−C)) / 2 (three-cornered hat). The floor is the mean error a"
  echo "perfect estimate would show against a reference with that noise. Errors shared by the two laser"
  echo "estimates (same scans) make σ_A smaller than it is, so the floor is conservative. The error in cm"
  echo "by segment length separates the two parts as well: per-pose noise does not grow with the length,"
  echo "drift does."
} | python3 "$here/update_section.py" laser2d_frontend "$root/docs/benchmarks.md"
echo "wrote docs/benchmarks.md (laser2d_frontend)"
