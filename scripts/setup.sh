#!/usr/bin/env bash
# Installs the Debian packages rrr_slam needs and builds it (with its tests)
# into ./_build (not build/: rosrun ignores a package's build/ folder). Safe to
# run again: apt and the build are incremental.
#   scripts/setup.sh [--doc]   (--doc: also the tools of scripts/rviz_screenshot.sh)
set -euo pipefail
cd "$(dirname "$0")/.."

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
# The install list is derived from package.xml (scripts/debian_packages.sh).
PACKAGE_LIST=$(bash scripts/debian_packages.sh "$@")
mapfile -t PACKAGES <<<"$PACKAGE_LIST"
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
