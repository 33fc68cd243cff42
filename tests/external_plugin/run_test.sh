#!/usr/bin/env bash
# Installs plugslam into a temporary prefix, builds tests/external_plugin/project against that
# installed SDK (find_package(plugslam) + plugslam_add_plugin), installs the plugin there and has
# the installed plugslam load it.
set -euo pipefail
src="$1"; build="$2"
work="$(mktemp -d /tmp/plugslam-external.XXXXXX)"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
export CCACHE_DISABLE=1
cmake -S "$src/tests/external_plugin/project" -B "$work/build" -G Ninja \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_INSTALL_PREFIX="$prefix" > "$work/configure.log"
cmake --build "$work/build" > "$work/build.log"
cmake --install "$work/build" > /dev/null
test -f "$prefix/lib/plugslam/plugins/plugslam_mycue.so"
out="$(env -u PLUGSLAM_PLUGIN_PATH "$prefix/bin/plugslam" describe mycue.Echo)"
echo "$out"
grep -q "mycue.Echo (PreProcessor, plugin mycue)" <<< "$out"
out="$(env -u PLUGSLAM_PLUGIN_PATH "$prefix/bin/plugslam" describe mycue.LandmarkSlice)"
echo "$out"
grep -q "mycue.LandmarkSlice (AlignerSlice2D, plugin mycue)" <<< "$out"
grep -q "reads the scene entry of this name" <<< "$out"
out="$(env -u PLUGSLAM_PLUGIN_PATH "$prefix/bin/plugslam" plugins)"
grep -q "mycue 0.3.0" <<< "$out"
grep -q "$prefix/lib/plugslam/plugins" <<< "$out"
echo "external plugin: OK"
