#!/usr/bin/env bash
# Replays Bicocca 25b (default level 0.150) through rrr_node with rviz under
# Xvfb and saves a screenshot of the corrected trajectory and the coloured
# loops. Needs the datasets (RRR_DATASETS or ../shared/datasets); sets up the
# package with its documentation tools (Xvfb, ImageMagick) first.
#   scripts/rviz_screenshot.sh [LEVEL] [OUTPUT.png] [RATE]
set -euo pipefail
cd "$(dirname "$0")/.."
LEVEL=${1:-0.150}
OUT=${2:-doc/images/rviz_bicocca_${LEVEL}.png}
RATE=${3:-20}
DATA=${RRR_DATASETS:-$(pwd)/../shared/datasets}/bicocca25b
[ -f "$DATA/B25b_$LEVEL.g2o" ] || { echo "Bicocca 25b not found in $DATA (set RRR_DATASETS)"; exit 1; }
bash scripts/setup.sh --doc
export PATH=/usr/bin:$PATH ROS_HOSTNAME=localhost ROS_HOME=${ROS_HOME:-$(mktemp -d)}
export ROS_MASTER_URI=http://localhost:11531
set +u; source _build/devel/setup.bash; set -u
WORK=$(mktemp -d)
_build/devel/lib/rrr_slam/rrr to-bag "$DATA/B25b_$LEVEL.g2o" --timestamps "$DATA/B25b_timestamps.txt" -o "$WORK/input.bag"
mkdir -p "$(dirname "$OUT")"
xvfb-run -a -s "-screen 0 1280x1024x24" bash -c "
  export LIBGL_ALWAYS_SOFTWARE=1
  roslaunch -p 11531 rrr_slam replay.launch bag:=$WORK/input.bag rate:=$RATE cluster_window:=50 rviz:=true >$WORK/launch.log 2>&1 &
  LAUNCH=\$!
  # Wait until the node has every odometry message, then judge what is pending.
  N=\$(grep -c VERTEX_SE2 '$DATA/B25b_$LEVEL.g2o')
  for i in \$(seq 1 900); do
    sleep 2
    rosservice call /rrr_node/get_status 2>/dev/null | grep -q \"odometry_received: \$N\$\" && break
  done
  rosservice call /rrr_node/finish
  sleep 8
  import -window root '$OUT'
  kill \$LAUNCH; wait \$LAUNCH || true
"
echo "wrote $OUT"
