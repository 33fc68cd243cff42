# Sourced by the bench scripts that take the build folder (PLUGSLAM_BUILD_DIR, default build/)
# rather than the host itself (common.sh's PLUGSLAM_BIN):
#   . "$(dirname "$0")/build_paths.sh"
# sets the checkout (root), the data (data, PLUGSLAM_DATA, default ../shared/data next to the
# checkout) and the host in that build folder (plugslam). It checks nothing: each script says
# itself what it misses, in its own order.
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
data="${PLUGSLAM_DATA:-$root/../shared/data}"
plugslam="${PLUGSLAM_BUILD_DIR:-$root/build}/bin/plugslam"
