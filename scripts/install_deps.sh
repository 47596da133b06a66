#!/usr/bin/env bash
# Installs what risas needs to build and test on Debian 12, from Debian's own
# archive (ROS 1 included; no ROS apt repository). Does nothing when all of it
# is already installed. Uses sudo when not run as root.
set -euo pipefail

packages=(
  build-essential cmake pkg-config libgtest-dev libeigen3-dev libopencv-dev zlib1g-dev
  ros-core-dev rosbash python3-rostest catkin
  libnodeletlib-dev libnodeletlib-tools libimage-transport-dev libcv-bridge-dev ros-image-view libimage-view-dev
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  python3-sensor-msgs libtf2-ros-dev libopenni2-dev libcamera-info-manager-dev
  libpcl-dev python3-matplotlib libimage-geometry-dev libtf2-eigen-dev
  ros-image-proc libimage-proc-dev rviz xvfb xdotool imagemagick libgl1-mesa-dri fonts-dejavu-core
  libnav-msgs-dev libstd-srvs-dev python3-nav-msgs
  clang libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
echo "installing ${#missing[@]} missing packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" > /dev/null
