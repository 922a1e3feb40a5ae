"""Joint-trajectory and benchmark plots (matplotlib only; no viser needed)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("matplotlib", reason="plots need matplotlib (the dev extra)")
imageio = pytest.importorskip("imageio.v3", reason="reading the PNG needs imageio (the video extra)")

from benchmarks.plots import samples_by_planner  # noqa: E402
from manip import MotionGenerator  # noqa: E402
from manip.errors import InvalidInputError  # noqa: E402
from manip.viz.plots import plot_benchmark_distributions, plot_joint_trajectory, robot_limits  # noqa: E402
from robot_constants import REPO_ROOT  # noqa: E402

ROOT = REPO_ROOT


@pytest.fixture(scope="module")
def motions():
    mg = MotionGenerator("franka", seed=0)
    q0 = mg.default_joint_positions
    q1 = q0 + np.array([0.8, 0.3, 0.0, 0.4, 0.0, -0.3, 0.5])
    a, b = mg.plan_joints(q0, q1), mg.plan_joints(q1, q0)
    assert a.success and b.success
    return mg, [a.trajectory, b.trajectory]


def test_joint_plot_is_written_with_limits(motions, tmp_path):
    mg, trajs = motions
    png = plot_joint_trajectory(trajs, tmp_path / "joints.png", limits=robot_limits(mg))
    image = imageio.imread(png)
    assert image.shape[:2] == (990, 900)  # 10 x 11 in at 90 dpi: four panels
    assert np.unique(image.reshape(-1, image.shape[-1]), axis=0).shape[0] > 50  # lines drawn, not blank


def test_joint_plot_refuses_bad_input(motions, tmp_path):
    mg, trajs = motions
    with pytest.raises(InvalidInputError, match="unknown limit 'speed'"):
        plot_joint_trajectory(trajs, tmp_path / "x.png", limits={"speed": mg.velocity_limits})
    with pytest.raises(InvalidInputError, match="7 entries"):
        plot_joint_trajectory(trajs, tmp_path / "x.png", limits={"velocity": np.ones(6)})
    with pytest.raises(InvalidInputError, match="non-empty"):
        plot_joint_trajectory([], tmp_path / "x.png")


def test_benchmark_samples_group_verified_runs_by_planner_and_label():
    runs = [
        {"planner": "manip", "label": None, "verified": True, "plan_time_s": 0.1, "motion_time_s": 1.5},
        {"planner": "manip", "label": None, "verified": False, "plan_time_s": 9.0, "motion_time_s": float("nan")},
        {"planner": "manip", "label": "before", "verified": True, "plan_time_s": 0.3, "motion_time_s": 1.7},
        {"planner": "ompl", "label": None, "verified": True, "plan_time_s": 0.5, "motion_time_s": 3.0},
    ]
    samples = samples_by_planner(runs)
    assert samples == {"manip": {"planning_time": [0.1], "motion_time": [1.5]},
                       "manip (before)": {"planning_time": [0.3], "motion_time": [1.7]},
                       "ompl": {"planning_time": [0.5], "motion_time": [3.0]}}
    with pytest.raises(InvalidInputError, match="motion_time"):
        plot_benchmark_distributions({"manip": {"planning_time": [0.1]}}, "x.png")


def test_mbm_writes_the_plot_of_its_runs(tmp_path):
    png = tmp_path / "mbm.png"
    cmd = [sys.executable, str(ROOT / "benchmarks" / "mbm.py"), "--dataset", "none", "--seeded", "1",
           "--planners", "manip", "--goal", "joint", "--no-progress", "--json", str(tmp_path / "run.json")]
    proc = subprocess.run(cmd + ["--plot", str(png)], capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert imageio.imread(png).shape[:2] == (405, 990)  # 11 x 4.5 in at 90 dpi
    report = json.loads((tmp_path / "run.json").read_text())
    solved = [r for r in report["runs"] if r["verified"]]
    assert solved and samples_by_planner(report["runs"])["manip"]["planning_time"] == [r["plan_time_s"] for r in solved]
    again = tmp_path / "again.png"  # and from the saved report, without planning
    proc = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "mbm.py"), "--from-json", str(tmp_path / "run.json"),
                           "--plot", str(again)], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert again.stat().st_size > 10_000


def test_motion_generation_example_writes_its_joint_plot(tmp_path):
    png = tmp_path / "joints.png"
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "motion_generation.py"), "--plot", str(png)],
                          capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert f"plot written to {png}" in proc.stdout
    assert imageio.imread(png).shape[:2] == (990, 900)
