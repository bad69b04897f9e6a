#!/usr/bin/env bash
# Installs every Debian package the workspace needs (run as root on Debian 12). Idempotent:
# when everything is already installed it does nothing.
set -euo pipefail

PACKAGES=(
  build-essential cmake catkin python3-catkin-pkg
  libeigen3-dev libceres-dev libboost-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libsuitesparse-dev libopenblas-dev
  libgtest-dev googletest libbenchmark-dev
  # the readers' fuzz targets (fuzz/, scripts/fuzz.sh): clang's libFuzzer and sanitizers
  clang libclang-rt-14-dev
  python3-matplotlib python3-numpy
  # sweeps beyond one machine: the mpi backend of flagella_sweep
  openmpi-bin libopenmpi-dev
  # ROS 1 (Debian's own packages, under /usr) and LCM
  ros-core-dev ros-base-dev rosbash rosout python3-rostest python3-roslaunch python3-rosbag
  python3-rospy python3-rostopic python3-rosnode python3-rosservice python3-rosunit
  librostest-dev librosbag-dev libroscpp-dev libtf2-ros-dev libtf2-eigen-dev
  libtf2-geometry-msgs-dev libsensor-msgs-dev libgeometry-msgs-dev libvisualization-msgs-dev
  libnav-msgs-dev libdiagnostic-msgs-dev libstd-srvs-dev ros-message-generation
  ros-message-runtime ros-core-python-dev python3-tf2-msgs python3-sensor-msgs python3-nav-msgs
  python3-std-srvs python3-diagnostic-msgs python3-visualization-msgs python3-geometry-msgs
  python3-rosgraph-msgs tf2-tools
  liblcm-dev liblcm-bin libglib2.0-dev pkg-config
  # headless rviz for the rendering test
  rviz xvfb xauth x11-utils libgl1-mesa-dri imagemagick
)

# roslaunch resolves the name "localhost" itself: a machine without it (a bare chroot or
# container without /etc/hosts) cannot run any ROS session. Add the standard entry if missing.
if ! getent hosts localhost > /dev/null; then
  echo "setup: 'localhost' does not resolve; adding '127.0.0.1 localhost' to /etc/hosts"
  echo "127.0.0.1 localhost" >> /etc/hosts
fi

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
