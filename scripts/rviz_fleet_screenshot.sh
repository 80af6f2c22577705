#!/usr/bin/env bash
# Runs the simulated fleet of launch/fleet.launch (three robots, each its own
# process at 50 Hz, one rrr_node) with rviz under Xvfb, and saves a
# screenshot once every robot has driven its part: each robot's corrected
# path in its own colour, the loops accepted green and rejected red. Needs
# no dataset; sets up the package with its documentation tools (Xvfb,
# ImageMagick) first.
#   scripts/rviz_fleet_screenshot.sh [OUTPUT.png]
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-doc/images/rviz_fleet.png}
bash scripts/setup.sh --doc
export PATH=/usr/bin:$PATH ROS_HOSTNAME=localhost ROS_HOME=${ROS_HOME:-$(mktemp -d)}
export ROS_MASTER_URI=http://localhost:11532
set +u; source _build/devel/setup.bash; set -u
WORK=$(mktemp -d)
mkdir -p "$(dirname "$OUT")"
xvfb-run -a -s "-screen 0 1280x1024x24" bash -c "
  export LIBGL_ALWAYS_SOFTWARE=1
  roslaunch -p 11532 rrr_slam fleet.launch rviz:=true >$WORK/launch.log 2>&1 &
  LAUNCH=\$!
  # Wait until the node has every robot's keyframes (3000 in all).
  for i in \$(seq 1 300); do
    sleep 2
    rosservice call /rrr_node/get_status 2>/dev/null | grep -q 'keyframes: 3000\$' && break
  done
  rosservice call /rrr_node/finish
  sleep 8
  import -window root '$OUT'
  kill \$LAUNCH; wait \$LAUNCH || true
"
echo "wrote $OUT"
