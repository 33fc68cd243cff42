#!/usr/bin/env bash
# Issue 19's frame-rate target: the built-in page renders >= 30 fps with a 1,000-local-map 2D
# session, counted in headless Chromium (Debian's, software GL: no GPU on these machines). The
# session is synthetic (runtime/web/bench/synthetic_session.mjs: the channels' messages of 1,000
# local maps of 600 points, 10 trajectory poses, about 2 loop closures each), since no log here
# has 1,000 local maps; drawing cost depends on how much is drawn, not where it came from.
# Writes the table into docs/benchmarks.md (section viewer_page). Run scripts/build.sh first.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
web="$root/runtime/web"
[ -f "$root/build/web/index.html" ] || { echo "build the page first: scripts/build.sh" >&2; exit 1; }
rows=""
for maps in 100 1000 3000; do
  json=$(node "$web/bench/fps.mjs" --maps "$maps" --points 600 --seconds 5 --json)
  echo "$json"
  rows+=$(python3 -c "
import json, sys; r = json.loads(sys.argv[1])
print(f\"| {r['maps']} | {r['points_per_map']} | {r['mapSourcePoints']} | {r['mapPoints']} | {r['loopVertices'] // 2} | {r['drawCalls']} | {r['fps']:.1f} |\")" "$json")$'\n'
done
{
  echo "## Built-in page: frame rate"
  echo
  echo "$("$(dirname "$0")/machine_info.sh")"
  echo "Command: \`scripts/bench/viewer_page.sh\` (runtime/web/bench/fps.mjs). Headless Debian Chromium"
  echo "$(/usr/bin/chromium --version 2>/dev/null | head -1), software rendering (SwiftShader), 1280x800 viewport, follow-the-robot on,"
  echo "every layer shown. Frames counted over 5 s of requestAnimationFrame, one full render each."
  echo "Target: >= 30 fps with 1,000 local maps."
  echo
  echo "| local maps | points per map | map points | drawn (one per pixel) | loop closures | draw calls | fps |"
  echo "|---|---|---|---|---|---|---|"
  printf "%s" "$rows"
} | python3 "$(dirname "$0")/update_section.py" viewer_page "$root/docs/benchmarks.md"
echo "wrote docs/benchmarks.md (viewer_page)"
