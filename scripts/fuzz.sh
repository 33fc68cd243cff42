#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang + ASan + UBSan into build-fuzz/ and runs
# each for SECONDS (default 60), seeded from tests/bad_input, the small valid files next to it and
# tests/fuzz/regressions. Prints executions per target; exits 1 if any target found a crash
# (the input is kept in build-fuzz/artifacts/TARGET/; add it to tests/fuzz/regressions/TARGET/
# once fixed).
#   scripts/fuzz.sh [SECONDS] [TARGET...]     e.g. scripts/fuzz.sh 300 fuzz_graph
# PLUGSLAM_LOCK=FILE wraps the build and every run in `flock FILE` (shared build machines).
# Every run is also appended to build-fuzz/fuzz-history.tsv; as the corpus is kept between runs,
# the summary gives each target's executions in this run and in total over the history (delete
# both build-fuzz/corpus and the history to start a campaign afresh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_config fuzz_carmen fuzz_rosbag fuzz_mcap fuzz_graph fuzz_archive fuzz_trajectory
  fuzz_image fuzz_camera_files fuzz_foxglove)
build="${PLUGSLAM_FUZZ_DIR:-$root/build-fuzz}"
lock=()
[ -n "${PLUGSLAM_LOCK:-}" ] && lock=(flock "$PLUGSLAM_LOCK")
cxx="${CXX:-$(command -v clang++ || command -v clang++-14)}"
cc="${CC:-$(command -v clang || command -v clang-14)}"
[ -x "$cxx" ] || { echo "fuzz.sh: clang++ not found (apt-get install clang)" >&2; exit 2; }

export CCACHE_BASEDIR="$root"
"${lock[@]}" cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_C_COMPILER="$cc" -DPLUGSLAM_FUZZ=ON \
  -DPLUGSLAM_BUILD_TESTS=OFF > "$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
"${lock[@]}" cmake --build "$build" -j "${PLUGSLAM_JOBS:-2}" --target "${targets[@]}"

bad="$root/tests/bad_input"
seed_files() {  # files seeding one target
  case "$1" in
    fuzz_config) ls "$bad"/cases/yaml_*.yaml "$bad"/base/*.yaml "$root"/configs/*.yaml ;;
    fuzz_carmen) ls "$bad"/cases/carmen_*.log "$bad"/base/good.log ;;
    fuzz_rosbag) ls "$bad"/cases/bag_*.bag "$bad"/base/good.bag ;;
    fuzz_graph) ls "$bad"/cases/g2o_*.g2o "$bad"/cases/toro_*.toro "$bad"/base/good.g2o "$bad"/base/good.toro ;;
    fuzz_archive) ls "$bad"/cases/archive_* "$bad"/base/good.plsb "$bad"/base/good_archive.yaml ;;
    fuzz_trajectory) ls "$bad"/cases/tum_*.tum "$bad"/cases/kitti_*.kitti "$bad"/cases/g2o_traj_*.g2o \
                        "$bad"/base/ref.tum "$bad"/base/ref.kitti ;;
    fuzz_image) find "$bad"/cases -path '*/cam_*' \( -name '*.png' -o -name '*.jpg' \) | sort ;;
    fuzz_camera_files) find "$bad"/cases -path '*/cam_*' \( -name '*.txt' -o -name '*.csv' \
                         -o -name '*.yaml' \) | sort ;;
    fuzz_foxglove) ls "$root"/tests/fuzz/seeds/foxglove/* ;;
  esac 2>/dev/null || true
}

status=0
summary="$build/fuzz-summary.txt"
history="$build/fuzz-history.tsv"
: > "$summary"
[ -f "$history" ] || printf 'date\ttarget\tseconds\texecs\tcov\tcorpus\texit\n' > "$history"
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t"
  seeds="$build/seeds/$t"
  artifacts="$build/artifacts/$t"
  mkdir -p "$corpus" "$seeds" "$artifacts"
  rm -f "$seeds"/*
  i=0
  for f in $(seed_files "$t"); do
    i=$((i + 1))
    if [ "$t" = fuzz_trajectory ]; then
      # The first byte picks the reader (0 TUM, 1 KITTI, 2 g2o, 3 auto-detect).
      case "$f" in *.tum) b='\x00' ;; *.kitti) b='\x01' ;; *.g2o) b='\x02' ;; *) b='\x03' ;; esac
      { printf "$b"; cat "$f"; } > "$seeds/$i"
      { printf '\x03'; cat "$f"; } > "$seeds/$i.auto"
    elif [ "$t" = fuzz_image ]; then
      # The first byte picks the decoder (0 as stored, 3 depth).
      case "$f" in */depth/*) b='\x03' ;; *) b='\x00' ;; esac
      { printf "$b"; cat "$f"; } > "$seeds/$i"
    elif [ "$t" = fuzz_camera_files ]; then
      # The first byte picks the parser (see tests/fuzz/fuzz_camera_files.cpp).
      case "$f" in
        */calib*.txt) b='\x00' ;; */times.txt) b='\x01' ;; */timestamps.txt) b='\x02' ;;
        */data.csv) b='\x03' ;; */sensor.yaml) b='\x04' ;; */camera-intrinsics.txt) b='\x07' ;;
        */pose.txt) b='\x08' ;; *) b='\x06' ;;
      esac
      { printf "$b"; cat "$f"; } > "$seeds/$i"
    else
      cp "$f" "$seeds/$i"
    fi
  done
  [ -d "$root/tests/fuzz/regressions/$t" ] && cp "$root/tests/fuzz/regressions/$t"/* "$seeds/" 2>/dev/null || true
  log="$build/$t.log"
  echo "== $t: ${seconds}s, $(ls "$seeds" | wc -l) seeds"
  set +e
  ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1" UBSAN_OPTIONS="print_stacktrace=1" \
    "${lock[@]}" "$build/fuzz/$t" "$corpus" "$seeds" -max_total_time="$seconds" -rss_limit_mb=2048 \
    -max_len=65536 -timeout=20 -print_final_stats=1 -artifact_prefix="$artifacts/" > "$log" 2>&1
  rc=$?
  set -e
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(date -u +%FT%TZ)" "$t" "$seconds" "${execs:-0}" \
    "${cov:-?}" "$(ls "$corpus" | wc -l)" "$rc" >> "$history"
  total=$(awk -F'\t' -v t="$t" '$2 == t { n += $4; r += 1 } END { printf "%d execs over %d runs", n, r }' "$history")
  line="$t: ${execs:-?} execs in ${seconds}s, cov ${cov:-?}, corpus $(ls "$corpus" | wc -l), exit $rc; total $total"
  echo "$line" | tee -a "$summary"
  if [ $rc -ne 0 ]; then
    status=1
    grep -m5 -E 'ERROR|SUMMARY|==[0-9]+==|Test unit written' "$log" || true
  fi
done
echo "summary: $summary"
exit $status
