"""Planner regression: MotionGenerator on MotionBenchMaker problems and on the seeded scenes.

Every trajectory the planner returns with `success=True` is judged by the independent
verifier (`manip.benchmarking.verify`: exact meshes, dense 0.01 rad check, limits, jerk,
start and goal at rest). The figure the project promises is >= 99.5 % success with zero
invalid trajectories; on a sample of n plans a planner that truly succeeds 99.5 % of the
time fails at least twice with probability 1 - 0.995^n - n 0.005 0.995^(n-1) (1.9 % for
n = 42, 1.0 % for n = 30), so each sample allows ONE failure and NO invalid trajectory.
Planning is seeded and the time budget generous, so a failure is reproducible.
"""

from __future__ import annotations

import numpy as np
import pytest

from manip.benchmarking.mbm_problems import MBM_SCENES, default_dataset_path, goal_pose, load_mbm_problems
from manip.benchmarking.scenes import SCENE_KINDS, make_problems
from manip.benchmarking.verify import default_verifier

try:
    from manip import MotionGenerator, WorldConfig
except ImportError:  # until the lead exports them from manip/__init__.py
    from manip.collision import WorldConfig
    from manip.motion_generator import MotionGenerator

DATASET = default_dataset_path()
MBM_PER_SCENE = 3  # first 3 valid problems of each of the 7 scenes -> 21 problems, 42 plans
SEEDED_PER_KIND = 3  # 5 kinds -> 15 problems, 30 plans
ALLOWED_FAILURES = 1  # see the module docstring
#: Generous, so that results depend on the seed, not on how loaded the machine is (speed is
#: measured by benchmarks/mbm.py, not here).
TIME_BUDGET = 30.0


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka")


def _run(mg: MotionGenerator, problems) -> tuple[int, list[str], list[str]]:
    """Plan every problem to its joint and its pose goal; return (plans, failures, invalid)."""
    verifier = default_verifier()
    failures: list[str] = []
    invalid: list[str] = []
    n = 0
    for p in problems:
        mg.update_world(WorldConfig.from_dict(p.world))
        for kind in ("joint", "pose"):
            n += 1
            if kind == "joint":
                r = mg.plan_joints(p.start, p.goal, seed=0, time_budget=TIME_BUDGET)
                extra = {}
            else:
                g = goal_pose(p)
                r = mg.plan_pose(p.start, g, link="panda_hand", seed=0, time_budget=TIME_BUDGET)
                extra = {"goal_pose": g}
            if not r.success:
                failures.append(f"{p.name} {kind}: {r.status.name} {r.message}")
                continue
            tr = r.trajectory
            v = verifier.verify_trajectory(
                p, tr.times, tr.positions, tr.velocities, tr.accelerations, tr.jerks, check_jerk=True, **extra
            )
            if not v.valid:
                invalid.append(f"{p.name} {kind}: {'; '.join(v.reasons)}")
    return n, failures, invalid


def test_motionbenchmaker_subset(mg):
    verifier = default_verifier()
    problems = []
    for scene in MBM_SCENES:
        valid = [p for p in load_mbm_problems(DATASET, scenes=[scene], limit_per_scene=12) if verifier.check_problem(p).valid]
        assert len(valid) >= MBM_PER_SCENE, scene
        problems += valid[:MBM_PER_SCENE]
    n, failures, invalid = _run(mg, problems)
    assert not invalid, "returned trajectories that fail verification:\n" + "\n".join(invalid)
    assert len(failures) <= ALLOWED_FAILURES, f"{len(failures)} of {n} plans failed:\n" + "\n".join(failures)


def test_seeded_scenes(mg):
    problems = [p for kind in SCENE_KINDS for p in make_problems(kind, SEEDED_PER_KIND, seed=0)]
    n, failures, invalid = _run(mg, problems)
    assert not invalid, "returned trajectories that fail verification:\n" + "\n".join(invalid)
    assert len(failures) <= ALLOWED_FAILURES, f"{len(failures)} of {n} plans failed:\n" + "\n".join(failures)


def test_planning_is_deterministic_for_a_seed(mg):
    p = make_problems("shelf", 1, seed=3)[0]
    mg.update_world(WorldConfig.from_dict(p.world))
    a = mg.plan_joints(p.start, p.goal, seed=5)
    b = mg.plan_joints(p.start, p.goal, seed=5)
    assert a.status == b.status
    if a.success:
        np.testing.assert_array_equal(a.trajectory.positions, b.trajectory.positions)


#: Trajectory-quality thresholds on the subset below (measured 2026-11-22: ratio of means
#: about 1.29 with the optimiser, 1.5-1.6 without; path length about 1.2x the straight line),
#: with margin. Not timed: the optimiser is bounded by iteration counts, so these are
#: deterministic for a seed.
MAX_MOTION_RATIO = 1.40
MIN_IMPROVEMENT = 0.92  # trajopt ratio <= this x the shortcut pipeline's on the same problems
#: Path length on the same subset (measured 2026-11-23: joint goals 1.076 x the straight line;
#: pose goals 3.87 rad mean, 1.10 x the lower bound), with margin.
MAX_PATH_RATIO = 1.15
MAX_POSE_PATH = 4.1  # [rad]
MAX_POSE_MOTION_RATIO = 1.25


def _path_length(positions: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(positions, axis=0), axis=1).sum())


def test_motion_quality_on_a_motionbenchmaker_subset(mg):
    from manip.benchmarking.quality import lower_bound_time

    verifier = default_verifier()
    cfg = mg.config
    times = {True: [], False: []}
    bounds = []
    paths, lines = [], []
    pose_paths, pose_times, pose_bounds = [], [], []
    limits = (cfg.velocity_limits, cfg.acceleration_limits, cfg.jerk_limits)
    for scene in MBM_SCENES:
        problems = [p for p in load_mbm_problems(DATASET, scenes=[scene], limit_per_scene=8)
                    if verifier.check_problem(p).valid][:2]
        for p in problems:
            mg.update_world(WorldConfig.from_dict(p.world))
            for trajopt in (True, False):
                r = mg.plan_joints(p.start, p.goal, seed=0, time_budget=TIME_BUDGET, trajopt=trajopt)
                assert r.success, f"{p.name}: {r.status.name} {r.message}"
                times[trajopt].append(r.motion_time)
                if trajopt:
                    paths.append(_path_length(r.trajectory.positions))
                    lines.append(float(np.linalg.norm(p.goal - p.start)))
            bounds.append(lower_bound_time(p.start, p.goal, *limits))
            r = mg.plan_pose(p.start, goal_pose(p), link="panda_hand", seed=0, time_budget=TIME_BUDGET)
            assert r.success, f"{p.name} (pose goal): {r.status.name} {r.message}"
            pose_paths.append(_path_length(r.trajectory.positions))
            pose_times.append(r.motion_time)
            pose_bounds.append(lower_bound_time(p.start, r.goal_q, *limits))
    ratio = {k: sum(v) / sum(bounds) for k, v in times.items()}
    assert ratio[True] <= MAX_MOTION_RATIO, ratio
    assert ratio[True] <= MIN_IMPROVEMENT * ratio[False], ratio
    assert sum(paths) / sum(lines) <= MAX_PATH_RATIO, sum(paths) / sum(lines)
    assert np.mean(pose_paths) <= MAX_POSE_PATH, np.mean(pose_paths)
    assert sum(pose_times) / sum(pose_bounds) <= MAX_POSE_MOTION_RATIO, sum(pose_times) / sum(pose_bounds)
