"""The fuzz targets (fuzz/, scripts/fuzz.sh) each run FUZZ_SECONDS (default
60) under AddressSanitizer and UndefinedBehaviorSanitizer with no crash,
sanitizer report, leak or hang, from their seeds and kept corpus.

Run by `scripts/test.sh` through catkin's run_tests with RRR_BUILD_DIR set to
the build folder; long runs are in RELIABILITY.md.
"""
import os
import pathlib
import re
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
SECONDS = int(os.environ.get("FUZZ_SECONDS", "60"))


@pytest.mark.parametrize("target", ["g2o_reader", "session_reader", "msg_conversion", "map_state"])
def test_fuzz_target_survives(target):
    result = subprocess.run(["bash", ROOT / "scripts" / "fuzz.sh", "--seconds", str(SECONDS),
                             target], capture_output=True, text=True, timeout=3600)
    print(result.stdout)
    assert result.returncode == 0, result.stdout + result.stderr
    runs = re.search(rf"fuzz: {target}: (\d+) inputs", result.stdout)
    assert runs and int(runs.group(1)) > 1000, result.stdout
