"""benchmarks/mbm.py: a returned trajectory that fails verification is counted, never a success."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def driver():
    spec = importlib.util.spec_from_file_location("mbm_driver", ROOT / "benchmarks" / "mbm.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["mbm_driver"] = mod
    spec.loader.exec_module(mod)
    return mod


class StraightLine:
    """Joint-space straight line, quintic timing slow enough for every limit; ignores obstacles."""

    name = "straight"

    def plan(self, problem, goal_kind="joint", seed=0):
        from benchmarks.peers import PlannerOutput

        if goal_kind != "joint":
            return PlannerOutput(False, "UNSUPPORTED", 0.001)
        d = problem.goal - problem.start
        T = 4.0 * max(1.0, np.abs(d).max())
        t = np.linspace(0.0, T, 401)
        tau = t / T
        s = 10 * tau**3 - 15 * tau**4 + 6 * tau**5
        sd = (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / T
        q = problem.start + s[:, None] * d
        return PlannerOutput(True, "SUCCESS", 0.002, times=t, positions=q, velocities=sd[:, None] * d)


def test_driver_counts_invalid_trajectories(driver, tmp_path, monkeypatch):
    monkeypatch.setattr(driver, "build_planner", lambda name, timeout: StraightLine())
    out = tmp_path / "r.json"
    rc = driver.main(["--dataset", "none", "--seeded", "2", "--planners", "straight", "--goal", "both",
                      "--json", str(out), "--no-progress"])
    assert rc == 0
    rep = json.loads(out.read_text())
    p = rep["planners"]["straight"]
    runs = rep["runs"]
    n_valid = rep["valid_problems"]
    assert n_valid == 10 and p["valid_problems"] == 20 and len(runs) == 20
    j = p["by_goal"]["joint"]
    # every joint plan is claimed; the obstructed ones must be counted invalid, not solved
    assert j["claimed_success"] == 10
    assert j["solved"] + j["invalid_returned"] == 10
    assert j["invalid_returned"] >= 3
    assert p["by_goal"]["pose"]["solved"] == 0
    assert j["success_rate"] == pytest.approx(j["solved"] / 10)
    assert set(p["plan_time_s"]) >= {"mean", "median", "p75", "p98"}
    for key in ("motion_time_s", "path_length_rad", "invalid_returned", "by_scene"):
        assert key in p
    assert sum(s["invalid_returned"] for s in p["by_scene"].values()) == p["invalid_returned"]
    assert all(r["verified"] == (r["claimed"] and not r["reasons"]) for r in runs)
