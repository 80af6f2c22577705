#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/: clang with AddressSanitizer and
# UndefinedBehaviorSanitizer) into <build>/fuzz and runs each one: the g2o
# reader, the session database reader, the node's message conversion and
# the map procedure's saved state.
# <build> is the catkin build of scripts/setup.sh (for the message headers):
# RRR_BUILD_DIR, default _build.
#
#   scripts/fuzz.sh [--seconds S | --runs N] [TARGET...]
#
# Each target runs S seconds (default 60) or N inputs, from its corpus in
# <build>/fuzz/corpus/TARGET (kept between runs) and seeds made by
# fuzz/make_seeds plus the first lines of every g2o file under RRR_DATASETS
# (default ../shared/datasets) when they are there. Prints one line per
# target; exits non-zero on the first crash, sanitizer report, leak or hang
# (the input is kept under <build>/fuzz/artifacts/).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH=/usr/bin:$PATH
limit=(-max_total_time=60)
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) limit=(-max_total_time="$2"); shift 2 ;;
    --runs) limit=(-runs="$2"); shift 2 ;;
    -*) echo "fuzz: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(g2o_reader session_reader msg_conversion map_state)

catkin_build=$(realpath "${RRR_BUILD_DIR:-_build}")
build=$catkin_build/fuzz
headers=$catkin_build/devel/include
cmake -S fuzz -B "$build" -DCMAKE_CXX_COMPILER=clang++ \
  -DRRR_MSG_INCLUDE_DIR="$headers" >"$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j2 >"$build.build.log" 2>&1 ||
  { tail -40 "$build.build.log"; exit 1; }

seeds=$build/seeds
rm -rf "$seeds"
"$build/make_seeds" "$seeds"
datasets=${RRR_DATASETS:-$(dirname "$PWD")/shared/datasets}
if [ -d "$datasets" ]; then
  find "$datasets" -name '*.g2o' -print0 | sort -z | while IFS= read -r -d '' f; do
    head -n 40 "$f" >"$seeds/g2o_reader/$(basename "$f").head"
  done
else
  echo "fuzz: no datasets at $datasets (set RRR_DATASETS); generated seeds only"
fi

mkdir -p "$build/artifacts"
for target in "${targets[@]}"; do
  corpus=$build/corpus/$target
  mkdir -p "$corpus"
  log=$build/$target.log
  start=$(date +%s)
  status=0
  "$build/${target}_fuzzer" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$build/artifacts/$target-" \
    "$corpus" "$seeds/$target" >"$log" 2>&1 || status=$?
  runs=$(grep -oE 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -oE '[0-9]+$' || echo 0)
  echo "fuzz: $target: $runs inputs in $(( $(date +%s) - start )) s, exit $status (log $log)"
  if [ "$status" -ne 0 ]; then
    grep -E 'ERROR|SUMMARY|Test unit written' "$log" | head -20
    exit "$status"
  fi
done
