#!/usr/bin/env bash
# Installs the Debian packages rrr_slam needs and builds it (with its tests)
# into ./_build (not build/: rosrun ignores a package's build/ folder). Safe to run again: apt and the build are incremental.
set -euo pipefail
cd "$(dirname "$0")/.."

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
PACKAGES=(
  build-essential cmake catkin ros-message-generation ros-message-runtime libroscpp-dev
  ros-std-msgs libstd-msgs-dev ros-geometry-msgs libgeometry-msgs-dev ros-nav-msgs libnav-msgs-dev
  ros-visualization-msgs libvisualization-msgs-dev libtf2-ros-dev libtf2-geometry-msgs-dev
  librosbag-dev librostest-dev python3-rostest python3-roslaunch python3-rosbag
  python3-rostopic python3-rosnode python3-rosservice rosbash
  python3-std-msgs python3-geometry-msgs python3-nav-msgs python3-visualization-msgs python3-tf2-msgs
  libsuitesparse-dev libeigen3-dev libboost-math-dev libgtest-dev libcli11-dev
  nlohmann-json3-dev libbenchmark-dev python3-matplotlib python3-numpy
  libopenblas0-serial
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian packages"
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# catkin needs Debian's python, not a pyenv/venv one.
export PATH=/usr/bin:$PATH
export ROS_HOME=${ROS_HOME:-$(mktemp -d)} ROS_HOSTNAME=localhost
cmake -S . -B _build -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 >_build.log 2>&1 \
  || { cat _build.log; exit 1; }
cmake --build _build -j2 >>_build.log 2>&1 || { tail -50 _build.log; exit 1; }
cmake --build _build -j2 --target tests >>_build.log 2>&1 || { tail -50 _build.log; exit 1; }
rm -f _build.log
echo "setup: built into $(pwd)/_build (rrr: _build/devel/lib/rrr_slam/rrr)"
