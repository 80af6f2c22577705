#!/usr/bin/env bash
# Runs every test of the package (unit, tool and integration tests) in the
# build made by scripts/setup.sh; exits non-zero if any test fails.
set -uo pipefail
cd "$(dirname "$0")/.."
export PATH=/usr/bin:$PATH
export ROS_HOME=${ROS_HOME:-$(mktemp -d)} ROS_HOSTNAME=localhost
rm -rf _build/test_results
# run_tests always exits 0; catkin_test_results tells the truth.
cmake --build _build --target run_tests -- -j1 >_build/run_tests.log 2>&1
summary=$(catkin_test_results _build/test_results --verbose)
status=$?
echo "$summary" | tail -40
echo "(full test output: _build/run_tests.log)"
# The plain closing line, counted from the JUnit files (catkin's summary counts
# each gtest case twice; pytest writes a file on one line).
count() { cat _build/test_results/*/*.xml | grep -oE "$1" | wc -l; }
total=$(count '<testcase ')
failed=$(count '<(failure|error)[ >]')
skipped=$(count '<skipped')
echo "tests: $((total - failed - skipped)) passed, $failed failed, $skipped skipped"
# Name what was skipped and why (e.g. the datasets are not there).
/usr/bin/python3 - _build/test_results <<'PY'
import glob, sys, xml.etree.ElementTree as ET
reasons = {}
for path in glob.glob(sys.argv[1] + "/*/*.xml"):
    for case in ET.parse(path).iter("testcase"):
        skipped = case.find("skipped")
        if skipped is not None:
            why = (skipped.get("message") or skipped.text or "").strip().splitlines()
            reasons.setdefault(why[0] if why else "no reason given", []).append(
                f"{case.get('classname')}.{case.get('name')}")
for why, cases in sorted(reasons.items()):
    print(f"skipped {len(cases)}: {why}")
    for name in cases[:5]:
        print(f"  {name}")
    if len(cases) > 5:
        print(f"  ... and {len(cases) - 5} more")
PY
exit $status
