#!/usr/bin/env bash
# Installs every Debian package the workspace needs (run as root on Debian 12). Idempotent:
# when everything is already installed it does nothing.
set -euo pipefail

PACKAGES=(
  build-essential cmake catkin python3-catkin-pkg
  libeigen3-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libsuitesparse-dev
  libgtest-dev googletest libbenchmark-dev
  python3-matplotlib python3-numpy
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi
echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
