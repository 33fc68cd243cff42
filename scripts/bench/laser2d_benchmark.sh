#!/usr/bin/env bash
# The Freiburg SLAM benchmark (Kuemmerle et al., "On measuring the accuracy of SLAM algorithms",
# 2009): the one shipped config (configs/laser2d_carmen.yaml, only source.path set) on every
# benchmark log in $PLUGSLAM_DATA/laser2d/*-kuemmerle-benchmark (the original .clf.bz2 and its
# manual relations), with its odometry and laser only (no motion model: the odometry unread),
# scored by `plugslam eval relations` exactly as the benchmark defines it. Writes the table into
# docs/benchmarks.md (section laser2d_benchmark) beside the published figures of Cartographer
# (Hess et al., ICRA 2016, Table II), graph mapping and GMapping (Kuemmerle et al. 2009), with
# the machine, date and commit, and the front-end's time split (run.json tracking_time_s).
# PLUGSLAM_BENCH_NO_DOC=1 prints the table instead. Run scripts/build.sh first.
set -euo pipefail
. "$(dirname "$0")/common.sh" laser2d_benchmark
cfg="$root/configs/laser2d_carmen.yaml"
mkdir -p "$out"
shopt -s nullglob
dirs=("$data"/laser2d/*-kuemmerle-benchmark/)
[ ${#dirs[@]} -gt 0 ] || { echo "no *-kuemmerle-benchmark logs in $data/laser2d (set PLUGSLAM_DATA)" >&2; exit 1; }

for dir in "${dirs[@]}"; do
  name=$(basename "$dir")
  log=$(ls "$dir"/*.clf* | head -n1)
  rel=$(ls "$dir"/*.relations | head -n1)
  for mode in odometry laser_only; do
    run="$out/$name/$mode"
    rm -rf "$run"
    mkdir -p "$run"
    extra=()
    [ "$mode" = laser_only ] && extra=(--set pipeline.tracker.motion=null)
    echo "$name $mode ..." >&2
    /usr/bin/time -f "%e %M" -o "$run/time.txt" \
      "$bin" run "$cfg" -o "$run" --set "source.path=$log" "${extra[@]}" -q \
      > "$run/stdout.txt" 2> "$run/stderr.txt"
    "$bin" eval relations "$run/trajectory.tum" --relations "$rel" --format json \
      -o "$run/relations.json"
  done
done

table=$(python3 - "$out" <<'EOF'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
# Published mean translational errors [m], as the data folder's SOURCE.md cites them.
published = {
    "intel": {"Cartographer": 0.0229, "graph mapping": 0.031, "GMapping": 0.070},
    "fr079": {"Cartographer": 0.0452, "graph mapping": 0.056, "GMapping": 0.061},
}
rows = []
for bench in sorted(out.iterdir()):
    if not bench.is_dir():
        continue
    short = bench.name.replace("-kuemmerle-benchmark", "")
    cells = {}
    for mode in ("odometry", "laser_only"):
        run = bench / mode
        rel = json.loads((run / "relations.json").read_text())
        rj = json.loads((run / "run.json").read_text())
        wall, mem = (run / "time.txt").read_text().split()[-2:]
        cells[mode] = (rel, rj, float(wall), int(mem))
    for mode, (rel, rj, wall, mem) in cells.items():
        t = rj.get("tracking_time_s", {})
        rows.append(
            f"| {short} | {mode.replace('_', ' ')} | {rel['used']} / {rel['relations']} | "
            f"{rel['translation_m']['mean']:.4f} ± {rel['translation_m']['std']:.4f} | "
            f"{rel['rotation_deg']['mean']:.3f} ± {rel['rotation_deg']['std']:.3f} | "
            f"{rj['tracking_failures']} | {rj.get('tracking_ambiguous', 0)} | "
            f"{rj['frames'] / rj['pipeline_time_s']:.0f} | "
            f"{t.get('search', 0):.2f} / {t.get('refine', 0):.2f} / {t.get('merge', 0):.2f} | "
            f"{wall:.1f} | {mem // 1024} MiB |")
    pub = published.get(short, {})
    if pub:
        rows.append(f"| {short} | published | | " + "; ".join(
            f"{k} {v:.4f}" for k, v in pub.items()) + " | | | | | | | |")
print("\n".join(rows))
EOF
)

machine=$("$here/machine_info.sh")
doc=$(cat <<EOF
## 2D laser SLAM: the Freiburg benchmark (issue 41)

$machine
Command: \`scripts/bench/laser2d_benchmark.sh\` (configs/laser2d_carmen.yaml, only \`source.path\`
set; laser only: \`--set pipeline.tracker.motion=null\`, the odometry unread). Metric: \`plugslam
eval relations --relations\` on the benchmark's manual relations, E = relation^-1 * (estimate(t1)^-1
* estimate(t2)), mean ± std of |t(E)| and |angle(E)| (Kuemmerle et al. 2009). Hz: frames / time in
the pipeline. Front-end split: seconds in the aligner's correlative search, its solve, and merging
into local maps. Published mean translational errors: Hess et al. 2016 (Cartographer, Table II),
Kuemmerle et al. 2009 (graph mapping, GMapping).

| log | odometry | relations used | translation [m] | rotation [deg] | failures | ambiguous | Hz | search / refine / merge [s] | wall [s] | peak memory |
|---|---|---|---|---|---|---|---|---|---|---|
$table
EOF
)
if [ -n "${PLUGSLAM_BENCH_NO_DOC:-}" ]; then
  echo "$doc"
else
  echo "$doc" | python3 "$here/update_section.py" laser2d_benchmark "$root/docs/benchmarks.md"
  echo "table written into docs/benchmarks.md (section laser2d_benchmark)" >&2
fi
