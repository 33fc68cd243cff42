#!/usr/bin/env bash
# Installs the Debian 12 packages plugslam needs to build and test. Idempotent: packages already
# present are skipped, so a second run does not touch the network.
# Needs root for apt-get: run as root, or as a user with sudo. Without either it installs nothing,
# prints the one apt-get command to run as root, and fails (scripts/apt-install.sh).
set -euo pipefail
PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config git
  libeigen3-dev libyaml-cpp-dev libspdlog-dev libfmt-dev
  libboost-dev libboost-filesystem-dev libsuitesparse-dev
  libcli11-dev libnanoflann-dev libgtest-dev libgmock-dev
  zlib1g-dev liblz4-dev libbz2-dev libreadline-dev libpng-dev
  time python3
  libopencv-core-dev libopencv-imgproc-dev libopencv-features2d-dev libopencv-calib3d-dev
  libopencv-imgcodecs-dev
  nlohmann-json3-dev libjpeg62-turbo-dev
  libzstd-dev libsqlite3-dev
  libcairo2-dev fonts-dejavu-core
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  # The built-in page's Node packages (npm ci from runtime/web's lockfile).
  exec "$(dirname "$0")/install-web-deps.sh"
fi
"$(dirname "$0")/apt-install.sh" install-deps "${missing[@]}"
"$(dirname "$0")/install-web-deps.sh"
