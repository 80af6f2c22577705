#!/usr/bin/env bash
# Makes every figure of doc/images/ again from the benchmarks that measure
# them (BENCHMARKS.md names each with its table):
#   join_families.png  precision and recall per method and family of several
#                      chains (bench/join_families.py; needs the datasets)
#   time_vs_size.png   verification time against graph size per method
#                      (bench/time_vs_size.py; built-in worlds)
#   node_mission.png   rrr_node's update time over a 100,000-keyframe mission
#                      (bench/node_scaling.py --world 100000)
#   rviz_fleet.png     three simulated robots in rviz, each in its colour
#                      (scripts/rviz_fleet_screenshot.sh)
# Takes about an hour and a half on 2 cores; run it on a quiet machine, after
# scripts/setup.sh. Benchmark outputs go to bench/out/.
#   scripts/figures.sh [FIGURE...]   (default: all four, by name without .png)
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH=/usr/bin:$PATH
IMAGES=doc/images
mkdir -p "$IMAGES" bench/out
figures=("$@")
[ ${#figures[@]} -gt 0 ] || figures=(join_families time_vs_size node_mission rviz_fleet)
for figure in "${figures[@]}"; do
  echo "figures: $figure"
  case "$figure" in
    join_families)
      bench/join_families.py --out bench/out/join_families
      bench/plot_families.py bench/out/join_families/results.json "$IMAGES/join_families.png" ;;
    time_vs_size)
      bench/time_vs_size.py --poses 1000 3000 10000 30000 --timeout 200 --out bench/out/time_vs_size
      cp bench/out/time_vs_size/time_vs_size.png "$IMAGES/" ;;
    node_mission)
      bench/node_scaling.py --world 100000 --outliers 2000 --play 4 --database --procedures map \
        --limit 1500 --plot "$IMAGES/node_mission.png" ;;
    rviz_fleet)
      bash scripts/rviz_fleet_screenshot.sh "$IMAGES/rviz_fleet.png" ;;
    *)
      echo "figures: unknown figure $figure (join_families, time_vs_size, node_mission, rviz_fleet)" >&2
      exit 2 ;;
  esac
done
