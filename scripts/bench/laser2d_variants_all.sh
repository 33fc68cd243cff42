#!/usr/bin/env bash
# Writes the degraded variants of every shared CARMEN log (scripts/bench/laser2d_variants.py)
# into out/bench/laser2d_variants/NAME/VARIANT.log.gz, where scripts/bench/laser2d_robust.sweep.yaml
# reads them: the sweep's datasets are files, and these are made, never stored.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
data="${PLUGSLAM_DATA:-$root/../shared/data}"
out="${1:-$root/out/bench/laser2d_variants}"
for dir in "$data"/laser2d/*/; do
  log=$(ls "$dir"/*.log.gz 2>/dev/null | head -n1 || true)
  [ -n "$log" ] || continue
  python3 "$root/scripts/bench/laser2d_variants.py" "$log" "$out/$(basename "$dir")"
done
echo "variants in $out"
