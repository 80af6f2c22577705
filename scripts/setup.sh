#!/usr/bin/env bash
# Installs the Debian packages rrr_slam needs and builds it (with its tests)
# into ./_build (not build/: rosrun ignores a package's build/ folder). Safe to
# run again: apt and the build are incremental.
#   scripts/setup.sh [--doc]   (--doc: also the tools of scripts/rviz_screenshot.sh)
set -euo pipefail
cd "$(dirname "$0")/.."

# The install list is derived from package.xml (scripts/debian_packages.sh).
PACKAGE_LIST=$(bash scripts/debian_packages.sh "$@")
mapfile -t PACKAGES <<<"$PACKAGE_LIST"
not_installed() {
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
  done
}
mapfile -t missing < <(not_installed)
if [ "${#missing[@]}" -gt 0 ]; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || {
      echo "setup: ${#missing[@]} Debian packages are missing (${missing[*]}) and installing" \
        "them needs root: run this script as root, or install sudo" >&2
      exit 1
    }
    SUDO="sudo"
  fi
  echo "setup: installing ${#missing[@]} Debian packages"
  # A new machine may still be running its first apt job: wait for its lock.
  APT=(apt-get -o DPkg::Lock::Timeout=600)
  $SUDO "${APT[@]}" update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive "${APT[@]}" install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
  mapfile -t still_missing < <(not_installed)
  if [ "${#still_missing[@]}" -gt 0 ]; then
    echo "setup: apt-get finished but these packages are not installed: ${still_missing[*]}" >&2
    exit 1
  fi
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
