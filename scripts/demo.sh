#!/usr/bin/env bash
# The main job on the built-in default world, no input files needed:
# simulate a grid city with false loop closures, verify it with RRR, and
# score the result against the simulation's ground truth.
set -euo pipefail
cd "$(dirname "$0")/.."
RRR=_build/devel/lib/rrr_slam/rrr
OUT=${1:-demo_output}
mkdir -p "$OUT"
"$RRR" simulate --false-loops 60 --group 3 -o "$OUT/world.g2o" -t "$OUT/false_loops.txt" \
  --ground-truth "$OUT/ground_truth.g2o"
"$RRR" verify "$OUT/world.g2o" --window 10 -o "$OUT/verified.g2o" -r "$OUT/report.json"
echo -n "odometry alone: "
"$RRR" evaluate "$OUT/report.json" --map "$OUT/world.g2o" --false-loops "$OUT/false_loops.txt" \
  --gt-g2o "$OUT/ground_truth.g2o" | sed 's/.*ATE/ATE/'
echo -n "after RRR:      "
"$RRR" evaluate "$OUT/report.json" --map "$OUT/verified.g2o" --false-loops "$OUT/false_loops.txt" \
  --gt-g2o "$OUT/ground_truth.g2o" --json "$OUT/scores.json"
echo "outputs in $OUT/: verified.g2o (optimized, accepted loops only), report.json, scores.json"
