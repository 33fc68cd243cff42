#!/usr/bin/env bash
# Side-by-side timing of `plugslam optimize --solver gn` against an existing g2o binary
# (`g2o -solver gn_var_cholmod -i -1`: Gauss-Newton, CHOLMOD, stop on gain < 1e-6) on the se-sync
# graphs: same start file, same stopping rule (relative chi2 decrease < 1e-6), runs interleaved,
# medians of REPS. Prints ratios (g2o time / plugslam time) and the chi2 each reached; the
# `g2o` section of docs/benchmarks.md is written by hand from this output.
# This script only runs g2o; it does not fetch or build it.
#
#   scripts/bench/g2o_compare.sh G2O_BINARY [REPS]        (REPS default 7)
#
# Environment: PLUGSLAM_DATA (default ../shared/data next to the repository), PLUGSLAM_BUILD_DIR
# (default build/), BENCH_WORK (scratch folder, default out/bench/g2o). On a shared machine wrap
# it in flock so that no build runs alongside.
set -euo pipefail
. "$(dirname "$0")/build_paths.sh"
work="${BENCH_WORK:-$root/out/bench/g2o}"
g2o="${1:-}"
reps="${2:-7}"
if [ -z "$g2o" ] || [ ! -x "$g2o" ]; then
  echo "usage: g2o_compare.sh G2O_BINARY [REPS]  (an existing g2o executable)" >&2
  exit 2
fi
[ -x "$plugslam" ] || { echo "g2o_compare.sh: $plugslam not found; run scripts/build.sh" >&2; exit 1; }
[ -d "$data/posegraph/se-sync" ] || { echo "g2o_compare.sh: no se-sync graphs in '$data'" >&2; exit 1; }
mkdir -p "$work"

jnum() { grep -o "\"$1\": [^,}]*" "$2" | head -n 1 | cut -d' ' -f2; }
median() { sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
wall() {  # wall seconds of a command into file $1
  local out=$1; shift
  local t0=$EPOCHREALTIME; "$@"; local t1=$EPOCHREALTIME
  awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.5f\n", b-a}' > "$out"
}
g2o_last() {  # field of g2o's last iteration line: cumTime or chi2
  grep '^iteration=' "$2" | tail -1 | sed "s/.*$1= *\([^ \t]*\).*/\1/"
}

printf "%-10s %12s %12s %12s %10s %10s %10s\n" graph chi2_plugslam chi2_g2o chi2_chordal \
  opt_ratio proc_ratio chordal_ratio
for g in intel MIT manhattan kitti_00 sphere2500; do
  in="$data/posegraph/se-sync/$g.g2o"
  if ! grep -q '^VERTEX' "$in"; then
    # g2o cannot load edge-only files: both start from the same spanning-tree (odometry) poses.
    "$plugslam" optimize "$in" -o "$work/${g}_start.g2o" --init odometry --iterations 0 -q \
      --summary "$work/${g}_start.json" > /dev/null
    in="$work/${g}_start.g2o"
  fi
  : > "$work/$g.ours"; : > "$work/$g.g2o"; : > "$work/$g.chord"
  for _ in $(seq "$reps"); do
    wall "$work/t1" "$plugslam" optimize "$in" -o "$work/o1.g2o" --solver gn --init file -q \
      --summary "$work/s1.json" > /dev/null
    wall "$work/t2" "$g2o" -v -solver gn_var_cholmod -i -1 -o "$work/o2.g2o" "$in" \
      > /dev/null 2> "$work/g2o.log"
    wall "$work/t3" "$plugslam" optimize "$in" -o "$work/o3.g2o" --solver gn --init chordal -q \
      --summary "$work/s3.json" > /dev/null
    echo "$(jnum time_optimize "$work/s1.json") $(cat "$work/t1") $(jnum final_chi2 "$work/s1.json")" \
      >> "$work/$g.ours"
    echo "$(g2o_last cumTime "$work/g2o.log") $(cat "$work/t2") $(g2o_last chi2 "$work/g2o.log")" \
      >> "$work/$g.g2o"
    echo "$(awk -v a="$(jnum time_init "$work/s3.json")" -v b="$(jnum time_optimize "$work/s3.json")" \
      'BEGIN{print a+b}') $(cat "$work/t3") $(jnum final_chi2 "$work/s3.json")" >> "$work/$g.chord"
  done
  oo=$(cut -d' ' -f1 "$work/$g.ours" | median); wo=$(cut -d' ' -f2 "$work/$g.ours" | median)
  og=$(cut -d' ' -f1 "$work/$g.g2o" | median); wg=$(cut -d' ' -f2 "$work/$g.g2o" | median)
  oc=$(cut -d' ' -f1 "$work/$g.chord" | median)
  co=$(tail -1 "$work/$g.ours" | cut -d' ' -f3); cg=$(tail -1 "$work/$g.g2o" | cut -d' ' -f3)
  cc=$(tail -1 "$work/$g.chord" | cut -d' ' -f3)
  printf "%-10s %12.6g %12.6g %12.6g %10.2f %10.2f %10.2f\n" "$g" "$co" "$cg" "$cc" \
    "$(awk -v a="$og" -v b="$oo" 'BEGIN{print a/b}')" "$(awk -v a="$wg" -v b="$wo" 'BEGIN{print a/b}')" \
    "$(awk -v a="$og" -v b="$oc" 'BEGIN{print a/b}')"
done
