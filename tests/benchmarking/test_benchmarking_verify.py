"""The independent verifier: it must catch collisions, limit violations and missed goals."""

from __future__ import annotations

import numpy as np
import pytest

from manip.benchmarking.mbm_problems import default_dataset_path, load_mbm_problems
from manip.benchmarking.verify import Verifier, default_verifier
from manip.pose import Pose

Q0 = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])  # the Franka's ready configuration
Q1 = Q0 + np.array([1.0, 0.3, 0.0, 0.3, 0.0, -0.2, 0.0])
# panda_hand passes (0.298, 0.163, 0.604) half-way from Q0 to Q1 (and is >= 0.15 m from it at the ends).
HAND_MID = [0.298, 0.163, 0.604]


def quintic(q_a: np.ndarray, q_b: np.ndarray, duration: float, dt: float = 1 / 120):
    """Rest-to-rest quintic blend: max |v| = 1.875 d/T, |a| = 5.774 d/T^2, |j| = 60 d/T^3."""
    t = np.arange(0.0, duration + 1e-12, dt)
    if t[-1] < duration - 1e-12:
        t = np.append(t, duration)
    tau = t / duration
    s = 10 * tau**3 - 15 * tau**4 + 6 * tau**5
    sd = (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / duration
    sdd = (60 * tau - 180 * tau**2 + 120 * tau**3) / duration**2
    sddd = (60 - 360 * tau + 360 * tau**2) / duration**3
    d = q_b - q_a
    return t, q_a + s[:, None] * d, sd[:, None] * d, sdd[:, None] * d, sddd[:, None] * d


@pytest.fixture(scope="module")
def verifier() -> Verifier:
    return default_verifier()


def test_free_trajectory_is_valid_with_metrics(verifier):
    t, q, v, a, j = quintic(Q0, Q1, 2.0)
    r = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_q=Q1, check_jerk=True)
    assert r.valid, r.reasons
    assert r.motion_time == pytest.approx(2.0)
    assert r.path_length == pytest.approx(np.linalg.norm(Q1 - Q0), rel=1e-6)
    assert r.max_velocity_ratio == pytest.approx(1.875 * 1.0 / 2.0 / 2.175, rel=1e-3)
    assert r.max_acceleration == pytest.approx(5.7735 * 1.0 / 4.0, rel=1e-3)
    assert r.max_jerk == pytest.approx(60 * 1.0 / 8.0, rel=1e-3)
    # dense: no two checked configurations further apart than 0.01 rad
    assert r.n_checked >= np.abs(Q1 - Q0).max() / 0.01


def test_trajectory_through_an_obstacle_is_rejected(verifier):
    t, q, v, a, j = quintic(Q0, Q1, 2.0)
    world = {"cuboid": {"block": {"dims": [0.03, 0.03, 0.03], "pose": HAND_MID + [1, 0, 0, 0]}}}
    # start and goal themselves are free
    assert verifier.in_collision(Q0, world) is None and verifier.in_collision(Q1, world) is None
    r = verifier.verify_trajectory(world, t, q, v, a, j, start_q=Q0, goal_q=Q1)
    assert not r.valid
    assert r.collision_pair is not None and r.collision_pair[1] == "world/block"
    assert 0.5 < r.collision_at < 1.5
    assert any("collision" in s for s in r.reasons)


def test_thin_obstacle_between_samples_is_caught_by_densification(verifier):
    # Two samples only: both free, the straight segment between them crosses a 5 mm plate.
    world = {"cuboid": {"plate": {"dims": [0.3, 0.005, 0.3], "pose": HAND_MID + [1, 0, 0, 0]}}}
    t = np.array([0.0, 10.0])
    q = np.stack([Q0, Q1])
    assert verifier.in_collision(Q0, world) is None and verifier.in_collision(Q1, world) is None
    r = verifier.verify_trajectory(world, t, q, start_q=Q0, goal_q=Q1)
    assert not r.valid and r.collision_pair[1] == "world/plate"
    # Without densification (resolution wider than the step) the same segment would pass.
    coarse = Verifier("franka", resolution=10.0)
    assert coarse.verify_trajectory(world, t, q, start_q=Q0, goal_q=Q1).valid


def test_cylinder_obstacle_uses_radius_and_height(verifier):
    t, q, v, a, j = quintic(Q0, Q1, 2.0)
    hit = {"cylinder": {"pole": {"radius": 0.02, "height": 0.6, "pose": HAND_MID + [1, 0, 0, 0]}}}
    assert not verifier.verify_trajectory(hit, t, q, v, a, j, start_q=Q0, goal_q=Q1).valid
    # the same pole lying flat 0.3 m above the hand's path is free
    above = {"cylinder": {"pole": {"radius": 0.02, "height": 0.2,
                                   "pose": [0.298, 0.163, 0.95, 0.7071068, 0.7071068, 0, 0]}}}
    assert verifier.verify_trajectory(above, t, q, v, a, j, start_q=Q0, goal_q=Q1).valid


def test_velocity_and_acceleration_limits(verifier):
    # 0.5 s for 1 rad on joint 1: |v| = 3.75 rad/s > 2.175, |a| = 23 rad/s^2 > 15.
    t, q, v, a, j = quintic(Q0, Q1, 0.5)
    r = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_q=Q1)
    assert not r.valid
    assert any(s.startswith("velocity limit") for s in r.reasons)
    assert any(s.startswith("acceleration limit") for s in r.reasons)
    # The finite differences catch it even when the planner does not report derivatives.
    r2 = verifier.verify_trajectory({}, t, q, start_q=Q0, goal_q=Q1)
    assert any(s.startswith("velocity limit") for s in r2.reasons)
    assert r2.max_velocity_ratio > 1.5


def test_jerk_is_checked_only_when_claimed(verifier):
    # 1 rad in 0.45 s on joint 1 would be too fast; use a small motion: 0.05 rad in 0.2 s
    # gives |j| = 60 * 0.05 / 0.008 = 375 rad/s^3 (< 500), and 0.1 rad gives 750 (> 500).
    qb = Q0 + np.array([0.1, 0, 0, 0, 0, 0, 0])
    t, q, v, a, j = quintic(Q0, qb, 0.2, dt=1 / 1000)
    claimed = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_q=qb, check_jerk=True)
    assert not claimed.valid and any(s.startswith("jerk limit") for s in claimed.reasons)
    assert claimed.max_jerk == pytest.approx(750, rel=2e-2)
    unclaimed = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_q=qb)
    assert unclaimed.valid, unclaimed.reasons
    qs = Q0 + np.array([0.05, 0, 0, 0, 0, 0, 0])
    t, q, v, a, j = quintic(Q0, qs, 0.2, dt=1 / 1000)
    assert verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_q=qs, check_jerk=True).valid


def test_position_limit_violation(verifier):
    # joint 4's upper limit is -0.0698 rad
    qb = Q0.copy()
    qb[3] = -0.03
    t, q, v, a, j = quintic(Q0, qb, 3.0)
    r = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_q=qb)
    assert not r.valid and any(s.startswith("position limit: panda_joint4") for s in r.reasons)


def test_wrong_goal_and_wrong_start_are_rejected(verifier):
    t, q, v, a, j = quintic(Q0, Q1, 2.0)
    off = Q1 + np.array([0, 0, 0, 0, 0, 0, 0.01])
    r = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_q=off)
    assert not r.valid and r.goal_joint_error == pytest.approx(0.01)
    r = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0 + 1e-4, goal_q=Q1)
    assert not r.valid and any("start_q" in s for s in r.reasons)
    # not at rest at the end
    v_bad = v.copy()
    v_bad[-1, 0] = 0.1
    r = verifier.verify_trajectory({}, t, q, v_bad, a, j, start_q=Q0, goal_q=Q1)
    assert not r.valid and any("end at rest" in s for s in r.reasons)


def test_pose_goal_tolerances(verifier, franka_kinematics):
    t, q, v, a, j = quintic(Q0, Q1, 2.0)
    g = franka_kinematics.fk(Q1, "panda_hand")
    assert verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_pose=g).valid
    shifted = Pose(g.position + np.array([0.0, 0.0015, 0.0]), g.quaternion)
    r = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_pose=shifted)
    assert not r.valid and r.goal_position_error == pytest.approx(0.0015, abs=1e-9)
    half = 0.015 / 2  # 0.015 rad about z
    turned = Pose(g.position, np.asarray(
        (Pose(np.zeros(3), np.array([np.cos(half), 0, 0, np.sin(half)])) @ Pose(np.zeros(3), g.quaternion)).quaternion))
    r = verifier.verify_trajectory({}, t, q, v, a, j, start_q=Q0, goal_pose=turned)
    assert not r.valid and r.goal_rotation_error == pytest.approx(0.015, abs=1e-6)


def test_malformed_output_is_invalid_not_an_exception(verifier):
    assert not verifier.verify_trajectory({}, np.array([0.0, 1.0]), np.zeros((3, 7))).valid
    assert not verifier.verify_trajectory({}, np.array([0.0, 0.0]), np.stack([Q0, Q0])).valid
    assert not verifier.verify_trajectory({}, np.array([0.0, 1.0]), np.stack([Q0, Q0 * np.nan])).valid


def test_mbm_problem_validity_and_broadphase_agree_with_all_pairs(verifier):
    problems = load_mbm_problems(default_dataset_path(), limit_per_scene=10)
    invalid = {p.name: verifier.check_problem(p) for p in problems}
    invalid = {k: v for k, v in invalid.items() if not v.valid}
    # The dataset README: 7 of the first 70 are infeasible for the example-robot-data Panda
    # (six cage_panda goals with a finger in an obstacle, one table_under goal past joint 4).
    assert len(invalid) == 7
    assert sum(k.startswith("cage_panda") and v.codes == ("goal_world_collision",) for k, v in invalid.items()) == 6
    assert invalid["table_under_pick_panda/3"].codes == ("goal_joint_limits",)
    # The AABB-tree screen never misses a contact that the all-pairs test finds.
    rng = np.random.default_rng(0)
    c = verifier.config
    n_hit = 0
    for p in problems[::7]:
        Q = rng.uniform(c.lower_limits, c.upper_limits, size=(40, 7))
        for qi in Q:
            exact = verifier.in_collision(qi, p.world) is not None
            fast = verifier.first_collision(qi[None], p.world, broadphase=True) is not None
            assert exact == fast
            n_hit += exact
    assert 0 < n_hit < 400
