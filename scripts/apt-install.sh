#!/usr/bin/env bash
# apt-install.sh WHO PACKAGE...: installs Debian packages with apt-get, as root or through sudo.
# A user who is neither root nor has sudo (a default Debian install gives none) gets the one
# apt-get line to run as root, and the script fails without installing anything. WHO names the
# caller in the messages.
set -euo pipefail
who="$1"
shift
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if ! command -v sudo > /dev/null 2>&1; then
    echo "$who: $# packages are missing and installing them needs root" \
         "(this user is not root and there is no sudo). As root, run:" >&2
    echo "  apt-get update && apt-get install -y --no-install-recommends $*" >&2
    echo "then run this script again." >&2
    exit 1
  fi
  SUDO="sudo"
fi
echo "$who: installing $*"
$SUDO apt-get update -qq
# env after sudo: sudo does not pass the caller's environment on.
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@"
