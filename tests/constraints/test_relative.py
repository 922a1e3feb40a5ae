"""`RelativePoseConstraint` (issue 30): its residual is the relative pose's change, its Jacobian
matches finite differences, its segment bound holds, plans keep it over the continuous motion
(sampled at 1 kHz), an object held by two hands moves with them, and bad input raises."""

from __future__ import annotations

import numpy as np
import pytest

from manip import quaternion as quat
from manip import InvalidInputError, MotionGenerator, Pose, RelativePoseConstraint, UnknownNameError
from manip.collision.shapes import Cuboid
from manip.constraints import certify_constraints

EPS = 1e-6
DOWN = [0.0, 1.0, 0.0, 0.0]
HANDS = ("left_panda_hand", "right_panda_hand")


@pytest.fixture(scope="module")
def dual() -> MotionGenerator:
    return MotionGenerator("dual_franka", {"cuboid": {"table": {"dims": [0.8, 1.6, 0.04],
                                                                "pose": [0.55, 0, -0.02, 1, 0, 0, 0]}}})


@pytest.fixture(scope="module")
def configs(dual):
    k = dual.kinematics
    return np.random.default_rng(5).uniform(k.lower, k.upper, (10, k.dof))


def test_residual_is_the_change_of_the_relative_pose(dual, configs):
    k = dual.kinematics
    c = RelativePoseConstraint(*HANDS, position_tolerance=0.01, rotation_tolerance=0.05).at_start(k, configs[0])
    ref = dual.fk(configs[0], HANDS[0]).inverse() @ dual.fk(configs[0], HANDS[1])
    for q in configs:
        rel = dual.fk(q, HANDS[0]).inverse() @ dual.fk(q, HANDS[1])
        dp, dr = rel.distance(ref)
        np.testing.assert_allclose(c.residual(k, q[None])[0], [dp / 0.01 - 1, dr / 0.05 - 1], atol=1e-8)
    assert np.allclose(c.residual(k, configs[:1])[0], -1.0)


def test_jacobian_matches_finite_differences(dual, configs):
    k = dual.kinematics
    c = RelativePoseConstraint(*HANDS).at_start(k, configs[0] + 0.05)
    for q in configs:
        J = c.jacobian(k, q[None])[0]
        fd = np.array([(c.residual(k, (q + EPS * e)[None])[0] - c.residual(k, (q - EPS * e)[None])[0]) / (2 * EPS)
                       for e in np.eye(k.dof)]).T
        np.testing.assert_allclose(J, fd, atol=1e-5 * max(1.0, np.abs(fd).max()))


def test_segment_bound_holds_along_sampled_segments(dual):
    k = dual.kinematics
    rng = np.random.default_rng(7)
    Q0 = rng.uniform(k.lower, k.upper, (40, k.dof))
    Q1 = np.clip(Q0 + rng.normal(0.0, 0.2, Q0.shape), k.lower, k.upper)
    c = RelativePoseConstraint(*HANDS).at_start(k, Q0[0])
    L = c.segment_bound(k, Q0, Q1)
    t = np.linspace(0.0, 1.0, 401)
    for q0, q1, bound in zip(Q0, Q1, L):
        r = c.residual(k, q0 + t[:, None] * (q1 - q0))
        assert np.abs(np.diff(r, axis=0)).max() / (t[1] - t[0]) <= bound * (1 + 1e-9)


def test_joints_moving_both_links_change_nothing(dual):
    # two links of one arm: the joints above both move them rigidly together
    k = dual.kinematics
    q = dual.default_joint_positions
    c = RelativePoseConstraint("left_panda_link5", "left_panda_hand").at_start(k, q)
    q1 = q.copy()
    q1[:4] += 0.5        # joints 1-4 move both links
    q1[7:] += 0.3        # the other arm moves neither
    assert c.segment_bound(k, q[None], q1[None])[0] == 0.0
    assert c.residual(k, q1[None]).max() == pytest.approx(-1.0)


def test_a_carry_keeps_the_relative_pose_at_1khz(dual):
    grasp = dual.plan_poses(dual.default_joint_positions, {HANDS[0]: Pose([0.5, 0.15, 0.2], DOWN),
                                                          HANDS[1]: Pose([0.5, -0.15, 0.2], DOWN)}, seed=0)
    assert grasp.success, grasp.message
    start = grasp.goal_q
    hold = RelativePoseConstraint(*HANDS, position_tolerance=0.005, rotation_tolerance=0.02)
    result = dual.plan_poses(start, {HANDS[0]: Pose([0.42, 0.1, 0.45], DOWN), HANDS[1]: Pose([0.42, -0.2, 0.45], DOWN)},
                             constraints=(hold,), seed=0)
    assert result.success, result.message
    bound = hold.at_start(dual.kinematics, start)
    dense = result.trajectory.resample(0.001).positions
    assert bound.residual(dual.kinematics, dense).max() <= 0.0
    assert certify_constraints((bound,), dual.kinematics, result.trajectory.positions).certified


def test_an_object_held_by_two_hands_moves_with_them(dual):
    q = dual.plan_poses(dual.default_joint_positions, {HANDS[0]: Pose([0.5, 0.14, 0.3], [0, 0.7071068, 0.7071068, 0]),
                                                      HANDS[1]: Pose([0.5, -0.14, 0.3], [0, 0.7071068, 0.7071068, 0])},
                        seed=0).goal_q
    from manip import Cuboid
    tcp_l, tcp_r = dual.fk(q, "left_panda_hand_tcp"), dual.fk(q, "right_panda_hand_tcp")
    box = Cuboid("bar", [0.09, np.linalg.norm(tcp_l.position - tcp_r.position) + 0.1, 0.04],
                 Pose((tcp_l.position + tcp_r.position) / 2))
    dual.attach_object(box, q=q, link=HANDS)
    try:
        assert not dual.check_collision(q)           # both hands hold it (9 cm across the 8 cm open fingers)
        held = dual.checker.attached_objects["bar"]
        assert held.link == HANDS[0]                 # it moves with the first hand
        assert {"right_panda_hand", "right_panda_leftfinger", "right_panda_rightfinger"} <= set(held.allowed_links)
        # without the second hand's allowance the right fingers would touch it: the hold is real
        dual.detach_object(q)
        dual.attach_object("bar", q=q, link=HANDS[0])
        assert dual.check_collision(q)
    finally:
        dual.detach_object(q)
        dual.remove_obstacle("bar")


def test_bad_input_raises_naming_the_argument(dual):
    with pytest.raises(InvalidInputError, match="position_tolerance"):
        RelativePoseConstraint(*HANDS, position_tolerance=0.0)
    with pytest.raises(InvalidInputError, match="rotation_tolerance"):
        RelativePoseConstraint(*HANDS, rotation_tolerance=4.0)
    with pytest.raises(InvalidInputError, match="two different frames"):
        RelativePoseConstraint(HANDS[0], HANDS[0])
    with pytest.raises(InvalidInputError, match="link_b"):
        RelativePoseConstraint(HANDS[0], "")
    with pytest.raises(UnknownNameError, match="link_b.*right_panda_hnd"):
        dual.plan_joints(dual.default_joint_positions, dual.default_joint_positions,
                         constraints=(RelativePoseConstraint(HANDS[0], "right_panda_hnd"),))
    with pytest.raises(InvalidInputError, match="two distinct"):
        dual.attach_object("x", link=(HANDS[0], HANDS[0]))


def _carry_start(dual):
    grasp = dual.plan_poses(dual.default_joint_positions, {HANDS[0]: Pose([0.5, 0.15, 0.2], DOWN),
                                                          HANDS[1]: Pose([0.5, -0.15, 0.2], DOWN)}, seed=0)
    assert grasp.success, grasp.message
    return grasp.goal_q


def test_a_turning_carry_moves_the_held_object_on_its_straight_line(dual):
    start = _carry_start(dual)
    hold = RelativePoseConstraint(*HANDS, position_tolerance=0.005, rotation_tolerance=0.02)
    # the object between the hands: 10 cm up and aside, turned 0.4 rad about z
    Ta = dual.fk(start, HANDS[0])
    centre = (Ta.position + dual.fk(start, HANDS[1]).position) / 2
    turn = Pose(centre + [-0.05, 0.05, 0.1], quat.from_axis_angle([0, 0, 1], 0.4)) @ Pose(-centre)
    goals = {h: turn @ dual.fk(start, h) for h in HANDS}
    result = dual.plan_poses(start, goals, constraints=(hold,), seed=0)
    assert result.success, result.message
    assert result.source == "linear"                       # the straight carry, not a searched path
    dense = result.trajectory.resample(0.001).positions
    assert hold.at_start(dual.kinematics, start).residual(dual.kinematics, dense).max() <= 0.0
    mid = (dual.fk(dense, HANDS[0]).position + dual.fk(dense, HANDS[1]).position) / 2
    d = turn.position + turn.rotation @ centre - centre    # the midpoint's displacement
    f = (mid - centre) @ d / (d @ d)
    assert np.linalg.norm(mid - (centre + f[:, None] * d), axis=1).max() < 2e-3
    for h in HANDS:
        assert dual.fk(result.goal_q, h).distance(goals[h])[0] < 1e-3


def test_a_blocked_straight_carry_is_searched_around(dual):
    start = _carry_start(dual)
    hold = RelativePoseConstraint(*HANDS, position_tolerance=0.005, rotation_tolerance=0.02)
    step = Pose([-0.15, 0.0, 0.0])                         # both hands 15 cm back
    goals = {h: step @ dual.fk(start, h) for h in HANDS}
    dual.add_obstacle(Cuboid("wall", [0.02, 0.6, 0.1], Pose([0.42, 0.0, 0.17])))   # in the hands' way: over it
    try:
        result = dual.plan_poses(start, goals, constraints=(hold,), seed=0, time_budget=30.0)
    finally:
        dual.remove_obstacle("wall")
    assert result.success, result.message
    assert result.source != "linear"
    dense = result.trajectory.resample(0.001).positions
    assert hold.at_start(dual.kinematics, start).residual(dual.kinematics, dense).max() <= 0.0
