"""benchmarks/mbm.py: a returned trajectory that fails verification is counted, never a success."""

from __future__ import annotations

import json

import numpy as np
import pytest
from robot_constants import REPO_ROOT, load_script

ROOT = REPO_ROOT


@pytest.fixture(scope="module")
def driver():
    return load_script(ROOT / "benchmarks" / "mbm.py", "mbm_driver")


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
    monkeypatch.setattr(driver, "build_planner", lambda name, timeout, **kw: StraightLine())
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
    # per-problem quality numbers: every joint run has its lower bound; a valid motion is never faster
    for r in runs:
        if r["goal"] == "joint":
            assert r["lower_bound_s"] > 0 and r["straight_line_rad"] > 0
        if r["verified"]:
            assert r["lower_bound_s"] <= r["motion_time_s"] + 1e-9
            assert r["motion_time_ratio"] == pytest.approx(r["motion_time_s"] / r["lower_bound_s"])
            assert r["path_length_ratio"] == pytest.approx(1.0, abs=1e-6)  # a straight line
    for key in ("lower_bound_s", "motion_time_ratio", "path_length_ratio", "motion_time_ratio_of_means",
                "path_length_ratio_of_means"):
        assert key in j and key in j["by_scene"]["seeded_table"]


def _run(driver, scene, motion, lb, path, line, verified=True, goal="joint"):
    return driver.Run("p", goal, scene, 1, "SUCCESS", True, verified, 0.01, motion_time_s=motion, lower_bound_s=lb,
                      motion_time_ratio=motion / lb if lb > 0 else float("nan"), path_length_rad=path,
                      straight_line_rad=line, path_length_ratio=path / line, max_jerk=100.0)


def test_summary_ratio_columns_on_hand_made_runs(driver):
    runs = [
        _run(driver, "a", 2.0, 1.0, 3.0, 1.0),  # ratios 2, 3
        _run(driver, "a", 3.0, 3.0, 4.0, 4.0),  # ratios 1, 1
        _run(driver, "b", 4.0, 2.0, 6.0, 2.0),  # ratios 2, 3
        _run(driver, "b", 99.0, 1.0, 99.0, 1.0, verified=False),  # invalid: excluded from the means
    ]
    s = driver.summarize(runs, 4)
    assert s["solved"] == 3 and s["invalid_returned"] == 1 and s["success_rate"] == pytest.approx(0.75)
    assert s["motion_time_s"]["mean"] == pytest.approx(3.0)
    assert s["lower_bound_s"]["mean"] == pytest.approx(2.0)
    assert s["motion_time_ratio_of_means"] == pytest.approx(3.0 / 2.0)
    assert s["motion_time_ratio"]["mean"] == pytest.approx((2 + 1 + 2) / 3)
    assert s["path_length_rad"]["mean"] == pytest.approx(13.0 / 3)
    assert s["path_length_ratio_of_means"] == pytest.approx(13.0 / 7.0)
    assert s["path_length_ratio"]["mean"] == pytest.approx((3 + 1 + 3) / 3)
    assert s["max_jerk"]["mean"] == pytest.approx(100.0)

    entry = driver.summarize_planner(runs, ["joint"], ["a", "b"], {"a": 2, "b": 2})
    sa = entry["by_goal"]["joint"]["by_scene"]["a"]
    assert sa["motion_time_ratio_of_means"] == pytest.approx(5.0 / 4.0)
    assert sa["motion_time_ratio"]["mean"] == pytest.approx(1.5)
    assert entry["by_scene"]["b"]["invalid_returned"] == 1

    report = {"planners": {"manip": entry}, "invalid_problems": {"count": 0, "by_reason": {}}, "problems": 4,
              "label": "before"}
    table = driver.markdown_tables(report)
    row = next(line for line in table.splitlines() if line.startswith("| manip (before) | joint | 3/4"))
    assert "| 3.00 | 2.00 | 1.50 / 1.67 |" in row and "| 1.86 / 2.33 |" in row


def test_merge_reports_labels_rows(driver):
    runs = [_run(driver, "a", 2.0, 1.0, 3.0, 1.0)]
    entry = driver.summarize_planner(runs, ["joint"], ["a"], {"a": 1})
    base = {"invalid_problems": {"count": 0, "by_reason": {}}, "problems": 1, "valid_problems": 1, "goal_kinds": ["joint"],
            "machine": {"commit": "x"}, "wall_time_s": 1.0}
    a = dict(base, label="before", planners={"manip": dict(entry)})
    b = dict(base, label="after", planners={"manip": dict(entry)})
    c = dict(base, label=None, planners={"manip": dict(entry)})
    m = driver.merge_reports([a, b, c], ["A", "B", "C"])
    assert list(m["planners"]) == ["manip (before)", "manip (after)", "manip"]
    table = driver.markdown_tables(m)
    assert "| manip (before) | joint |" in table and "| manip (after) | joint |" in table
    m2 = driver.merge_reports([c, c], ["C1", "C2"])
    assert list(m2["planners"]) == ["manip", "manip (C2)"]


def test_curobo_limits_config_and_manip_planner(driver):
    cfg = driver.benchmark_config(curobo_limits=True)
    assert np.all(cfg.acceleration_limits == 15.0) and np.all(cfg.jerk_limits == 500.0)
    base = driver.benchmark_config()
    np.testing.assert_array_equal(cfg.velocity_limits, base.velocity_limits)
    assert not np.all(base.acceleration_limits == 15.0)
    planner = driver.build_planner("manip", None, config=cfg)
    np.testing.assert_array_equal(planner.mg.acceleration_limits, 15.0)
    assert driver.same_limits(driver.planner_limits(planner, base.limits), cfg.limits)
    assert not driver.same_limits(base.limits, cfg.limits)


def test_unknown_plan_option_fails_loudly(driver, monkeypatch):
    from manip.errors import InvalidInputError

    with pytest.raises(InvalidInputError, match="no_such_option"):
        driver.build_planner("manip", None, plan_options={"no_such_option": 1})

    def reject(name, timeout, **kw):
        raise InvalidInputError("unknown planning option(s) ['smoothness']")

    monkeypatch.setattr(driver, "build_planner", reject)
    rc = driver.main(["--dataset", "none", "--seeded", "1", "--planners", "manip", "--goal", "joint",
                      "--smoothness", "smooth", "--no-progress"])
    assert rc == 2
