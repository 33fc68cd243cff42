#!/usr/bin/env bash
# Installs what is needed, builds the host and the plugins the default pipeline loads (not the
# tests), and runs plugslam on its built-in default pipeline (configs/sim2d_double_laser.yaml,
# the config runtime/src/cli.cpp's defaultConfigPath() names).
# Outputs land in out/demo (trajectory, map, run.json, session).
#   scripts/demo.sh [OUTDIR]
#   scripts/demo.sh --print-targets   prints the build targets the demo needs and exits
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

# The host, and one plugin target per name in the default config's `plugins:` list.
demo_targets() {
  local list
  local config="$root/configs/sim2d_double_laser.yaml"
  local base
  # A config may start from another (`base: FILE`, beside it): its plugins are the base's.
  while :; do
    list="$(sed -n 's/^plugins:[[:space:]]*\[\(.*\)\][[:space:]]*\(#.*\)\{0,1\}$/\1/p' "$config")"
    [ -z "$list" ] || break
    base="$(sed -n 's/^base:[[:space:]]*\([^[:space:]#]*\).*$/\1/p' "$config")"
    [ -n "$base" ] || { echo "demo.sh: no 'plugins: [...]' line in $config or a base" >&2; exit 1; }
    config="$(dirname "$config")/$base"
  done
  local targets="plugslam"
  for p in ${list//,/ }; do targets+=" plugslam_plugin_$p"; done
  echo "$targets"
}
if [ "${1:-}" = "--print-targets" ]; then
  demo_targets
  exit 0
fi
targets="$(demo_targets)"
"$root/scripts/install-deps.sh"
PLUGSLAM_TARGETS="$targets" "$root/scripts/build.sh"
"$root/build/bin/plugslam" run -o "${1:-$root/out/demo}"
