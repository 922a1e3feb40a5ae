"""benchmarks/qp_prototype.py: the banded interior-point prototype against PIQP on recorded QPs."""

from __future__ import annotations


import numpy as np
import pytest
from robot_constants import REPO_ROOT, load_script


@pytest.fixture(scope="module")
def prototype():
    return load_script(REPO_ROOT / "benchmarks" / "qp_prototype.py", "qp_prototype")


def test_the_prototype_solves_recorded_qps_as_piqp_does(prototype):
    qps = prototype.record(1, ["box_panda"])
    assert len(qps) >= 4  # one problem, joint and pose goals: the optimiser's QPs were recorded
    result = prototype.compare(qps)
    assert result["qps"] == len(qps)
    assert result["mismatched"] <= len(qps) // 10
    assert result["errors"].size >= len(qps) // 2  # compared where both solved
    # PIQP stops at 1e-6 absolute: the two solutions agree to about that, relative to the motion
    assert np.all(result["errors"] < 1e-3)
    assert "status differs on" in result["text"] and "CPU per QP" in result["text"]
