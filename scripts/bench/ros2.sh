#!/usr/bin/env bash
# Reading speed of ROS bags (issue 21, target >= 50 MB/s of bag), written into docs/benchmarks.md
# (section ros2). The DIS ROS 1 bag is converted into ROS 2 bags by tests/node/ros2_bags.js (MCAP
# uncompressed, lz4, zstd, without summary; rosbag2 SQLite), then build/bin/io_bag_read_bench
# reads each to its end through the source a run uses (storage, decompression, CRCs, decoding,
# synchronisation into frames; no SLAM). Needs Node and tests/node's packages
# (scripts/install-web-deps.sh); run scripts/build.sh first.
#   scripts/bench/ros2.sh [REPEATS]     (default 5; the median pass is reported)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
bench="$root/build/bin/io_bag_read_bench"
[ -x "$bench" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
command -v node > /dev/null || { echo "ros2.sh needs Node (scripts/install-web-deps.sh)" >&2; exit 1; }
: "${PLUGSLAM_DATA:=$root/../shared/data}"
repeats="${1:-5}"
ros1="$PLUGSLAM_DATA/laser2d/dis-underground-rosbag/dis-underground.bag"
[ -f "$ros1" ] || { echo "no DIS bag at $ros1 (set PLUGSLAM_DATA)" >&2; exit 1; }
doc="${PLUGSLAM_BENCH_DOC:-$root/docs/benchmarks.md}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
node "$root/tests/node/ros2_bags.js" "$ros1" "$work/bags" > /dev/null
b="$work/bags"
"$bench" "$repeats" "$ros1" "$b/dis_none.mcap" "$b/dis_lz4" "$b/dis_zstd.mcap" \
  "$b/dis_unindexed_lz4.mcap" "$b/dis_db3" > "$work/table.tsv"

section="$work/section.md"
{
  echo "## ROS bags: reading speed (\`scripts/bench/ros2.sh\`)"
  echo
  echo "The DIS bag (4427 scans, 5484 odometry, 110 s) as ROS 1 (bz2 chunks) and converted to ROS 2 by"
  echo "\`tests/node/ros2_bags.js\`, read to the end through \`io.RosbagSource\` / \`io.Ros2BagSource\`"
  echo "(decompression, CRCs, CDR decoding, frames; no SLAM), median of $repeats passes."
  echo "MB/s = bytes of the bag on disk / wall time (target ≥ 50). $("$root/scripts/bench/machine_info.sh")"
  echo
  echo "| bag | storage | size [MB] | frames | time [s] | MB/s |"
  echo "|---|---|---|---|---|---|"
  tail -n +2 "$work/table.tsv" | while IFS=$'\t' read -r path bytes frames secs mbs; do
    name="$(basename "$path")"
    case "$name" in
      *.bag) storage="ROS 1, bz2 chunks" ;;
      dis_none.mcap) storage="MCAP, uncompressed, indexed" ;;
      dis_lz4) storage="rosbag2 folder, MCAP lz4, indexed" ;;
      dis_zstd.mcap) storage="MCAP, zstd, indexed" ;;
      dis_unindexed_lz4.mcap) storage="MCAP, lz4, no summary (linear scan)" ;;
      dis_db3) storage="rosbag2 folder, SQLite .db3" ;;
      *) storage="?" ;;
    esac
    printf '| %s | %s | %s | %s | %s | %s |\n' "$name" "$storage" \
      "$(awk -v b="$bytes" 'BEGIN { printf "%.1f", b / 1e6 }')" "$frames" "$secs" "$mbs"
  done
} > "$section"
mkdir -p "$(dirname "$doc")"
python3 "$root/scripts/bench/update_section.py" ros2 "$doc" < "$section"
cat "$section"
