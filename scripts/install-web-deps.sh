#!/usr/bin/env bash
# What the built-in page (runtime/web) and the viewer's Node tests (tests/node) need: Node.js
# (Debian's nodejs and npm where no node is installed) and their npm packages, exactly as each
# folder's package-lock.json pins them (npm ci; skipped when node_modules already matches).
# With --browser, also Debian's chromium for the page's end-to-end tests (playwright-core drives
# it; it never downloads a browser).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
need=()
command -v node > /dev/null || need+=(nodejs)
command -v npm > /dev/null || need+=(npm)
if [ "${1:-}" = "--browser" ] && [ ! -x /usr/bin/chromium ]; then need+=(chromium); fi
if [ ${#need[@]} -gt 0 ]; then "$root/scripts/apt-install.sh" install-web-deps "${need[@]}"; fi
# The page (runtime/web) and the viewer's Node tests (tests/node: protocol, schemas, MCAP).
for dir in runtime/web tests/node; do
  stamp="$root/$dir/node_modules/.package-lock.json"
  if [ ! -f "$stamp" ] || [ "$root/$dir/package-lock.json" -nt "$stamp" ]; then
    echo "install-web-deps: npm ci in $dir"
    (cd "$root/$dir" && npm ci --no-audit --no-fund --loglevel=error)
  fi
done
