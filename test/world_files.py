"""Worlds the Python integration tests replay, and reading their g2o files."""
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
DATASETS = pathlib.Path(os.environ.get("RRR_DATASETS", ROOT.parent / "shared" / "datasets"))


def generated_and_bicocca():
    """pytest parameters: "simulated" (a world the test generates), and
    Bicocca 25b 0.150 from RRR_DATASETS, skipped with the reason if missing."""
    yield pytest.param("simulated", id="simulated")
    bicocca = DATASETS / "bicocca25b" / "B25b_0.150.g2o"
    yield pytest.param(bicocca, id="bicocca_0.150", marks=pytest.mark.skipif(
        not bicocca.exists(), reason=f"Bicocca 25b not found at {bicocca} (set RRR_DATASETS)"))


def loop_pairs(g2o):
    """The (from, to) ids of every edge of `g2o` that is not odometry."""
    pairs = set()
    for line in pathlib.Path(g2o).read_text().splitlines():
        fields = line.split()
        if fields and fields[0].startswith("EDGE") and abs(int(fields[1]) - int(fields[2])) != 1:
            pairs.add((int(fields[1]), int(fields[2])))
    return pairs
