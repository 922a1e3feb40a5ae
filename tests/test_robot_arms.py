"""Multi-arm robots (`manip.robot_arms`, `robots/dual_franka`, `MotionGenerator.from_robots`):
the composed model is each arm's model at its base pose, arm-arm contacts are found and planned
around with a certificate, and bad input raises naming the argument."""

from __future__ import annotations

import numpy as np
import pytest

from manip import MotionGenerator, Pose
from manip.benchmarking.verify import Verifier
from manip.errors import InvalidInputError, RobotConfigError, UnknownNameError
from manip.robot_config import load_robot_config

LEFT_REACHING = np.array([-1.57, 0.3, 0.0, -1.6, 0.0, 1.8, 0.785])   # left arm turned towards the right one
RIGHT_REACHING = np.array([1.57, 0.0, 0.0, -2.2, 0.0, 1.8, 0.785])   # right arm turned towards the left one


@pytest.fixture(scope="module")
def dual() -> MotionGenerator:
    return MotionGenerator("dual_franka")


@pytest.fixture(scope="module")
def franka() -> MotionGenerator:
    return MotionGenerator("franka")


def test_dual_franka_names_joints_and_limits(dual, franka):
    c = dual.config
    assert dual.robot_dof == 14
    assert c.arm_joints[:2] == ("left_panda_joint1", "left_panda_joint2")
    assert c.arm_joints[7] == "right_panda_joint1"
    assert [a.name for a in c.arms] == ["left", "right"]
    assert c.arms[1].columns == (7, 14) and c.arms[1].ee_link == "right_panda_hand"
    np.testing.assert_array_equal(c.lower_limits, np.r_[franka.config.lower_limits, franka.config.lower_limits])
    np.testing.assert_array_equal(c.jerk_limits, np.r_[franka.config.jerk_limits, franka.config.jerk_limits])
    # each arm's SRDF pairs, prefixed; no pair between the arms is disabled
    assert len(c.disabled_collision_pairs) == 2 * len(franka.config.disabled_collision_pairs)
    assert all(a.split("_")[0] == b.split("_")[0] for a, b in c.disabled_collision_pairs)
    np.testing.assert_allclose(c.arms[0].base_pose.position, [0.0, 0.35, 0.0])
    np.testing.assert_allclose(c.arms[1].base_pose.position, [0.0, -0.35, 0.0])


@pytest.mark.parametrize("arm", [0, 1])
def test_combined_fk_is_each_arms_fk_at_its_base_pose(dual, franka, arm):
    rng = np.random.default_rng(arm)
    lo, hi = dual.config.lower_limits, dual.config.upper_limits
    Q = rng.uniform(lo, hi, (20, 14))
    a = dual.config.arms[arm]
    for link in ("panda_hand", "panda_link4", "panda_hand_tcp"):
        combined = dual.fk(Q, a.prefix + link)
        alone = a.base_pose @ franka.fk(Q[:, a.columns[0]:a.columns[1]], link)
        np.testing.assert_allclose(combined.position, alone.position, atol=1e-12)
        np.testing.assert_allclose(np.abs(np.sum(combined.quaternion * alone.quaternion, axis=1)), 1.0, atol=1e-12)


def test_from_robots_mixes_arms_with_rotated_bases():
    turn = Pose([0.1, -0.4, 0.05], [np.cos(0.3), 0.0, 0.0, np.sin(0.3)])   # 0.6 rad about z
    mg = MotionGenerator.from_robots({"left": ("franka", Pose([0.0, 0.4, 0.0])), "right": ("ur5", turn)})
    ur5 = MotionGenerator("ur5")
    assert mg.robot_dof == 13 and mg.config.arm_joints[7] == "right_shoulder_pan_joint"
    q = np.r_[mg.config.default_joint_positions]
    q[7:] = np.array([0.3, -1.2, 1.1, -1.0, 0.4, 0.2])
    expect = turn @ ur5.fk(q[7:], "tool0")
    got = mg.fk(q, "right_tool0")
    np.testing.assert_allclose(got.position, expect.position, atol=1e-12)
    assert abs(abs(float(got.quaternion @ expect.quaternion)) - 1.0) < 1e-12


def test_dual_ur5_plans_its_arms_together():
    mg = MotionGenerator("dual_ur5")
    ur5 = MotionGenerator("ur5")
    assert mg.robot_dof == 12 and mg.config.arms[1].ee_link == "right_tool0"
    q0 = mg.default_joint_positions
    goal = q0.copy()
    goal[[0, 6]] = [0.8, -0.8]          # both shoulders turn, towards each other's side
    np.testing.assert_allclose(mg.fk(goal, "right_tool0").position,
                               (mg.config.arms[1].base_pose @ ur5.fk(goal[6:], "tool0")).position, atol=1e-12)
    result = mg.plan_joints(q0, goal, seed=0)
    assert result.success, result.message
    assert mg.checker.certify_path(result.trajectory.positions).certified


def test_an_arm_arm_collision_is_found_and_planned_around_with_a_certificate(dual):
    meet = np.r_[LEFT_REACHING, RIGHT_REACHING]
    report = dual.checker.distance_report(meet)
    assert report.distance < 0
    assert {report.closest.a.split("_")[0], report.closest.b.split("_")[0]} == {"left", "right"}
    # the left arm swings through where the right one reaches: both ends free, the line not
    start, goal = meet.copy(), meet.copy()
    start[0], goal[0] = -2.5, -0.6
    assert not dual.check_collision(start) and not dual.check_collision(goal)
    cert = dual.checker.certify_path(np.stack([start, goal]))
    assert not cert.certified and {n.split("_")[0] for n in cert.pair} == {"left", "right"}
    result = dual.plan_joints(start, goal, seed=0)
    assert result.success, result.message
    traj = result.trajectory
    assert dual.checker.certify_path(traj.positions).certified
    verdict = Verifier(dual.config).verify_trajectory({}, traj.times, traj.positions, traj.velocities,
                                                      traj.accelerations, start_q=start, goal_q=goal)
    assert verdict.valid, verdict


def test_a_full_state_is_each_arms_state_in_turn(dual):
    q = dual.default_joint_positions
    fingers = np.array([0.04, 0.04])
    full = np.r_[q[:7], fingers, q[7:], fingers]          # left.get_joint_positions(), right's
    assert dual.fk(full, "right_panda_hand").distance(dual.fk(q, "right_panda_hand"))[0] == 0.0


def test_robot_folder_of_arms_is_written_not_coded(tmp_path):
    (tmp_path / "two").mkdir()
    (tmp_path / "two" / "robot.yaml").write_text(
        "name: two\narms:\n"
        "  - {robot: franka, prefix: a, base_pose: [0, 0.5, 0]}\n"
        "  - {robot: ur5, prefix: b, base_pose: [0, -0.5, 0, 0, 0, 0, 1]}\n")
    config = load_robot_config(tmp_path / "two")
    assert config.dof == 13 and config.ee_link == "a_panda_hand" and config.arms[1].robot == "ur5"
    mg = MotionGenerator(tmp_path / "two")
    assert not mg.check_collision(mg.default_joint_positions)


def test_bad_arms_raise_naming_the_argument(tmp_path):
    with pytest.raises(UnknownNameError, match="arm 'right'.*frank"):
        MotionGenerator.from_robots({"left": ("franka", Pose([0, 0.35, 0])), "right": ("frank", Pose([0, -0.35, 0]))})
    with pytest.raises(InvalidInputError, match="duplicate prefix 'left_'"):
        MotionGenerator.from_robots({"left": ("franka", Pose([0, 0.35, 0])), "left_": ("franka", Pose([0, -0.35, 0]))})
    with pytest.raises(InvalidInputError, match="prefixes 'a_' and 'a_b_' overlap"):
        MotionGenerator.from_robots({"a": ("franka", Pose([0, 0.35, 0])), "a_b": ("franka", Pose([0, -0.35, 0]))})
    with pytest.raises(InvalidInputError, match=r"arms\['left'\] must be \(robot, base_pose\)"):
        MotionGenerator.from_robots({"left": "franka"})
    with pytest.raises(InvalidInputError, match="base pose"):
        MotionGenerator.from_robots({"left": ("franka", [0, 1])})
    with pytest.raises(InvalidInputError, match="at least one arm"):
        MotionGenerator.from_robots({})
    (tmp_path / "robot.yaml").write_text(
        "arms:\n  - {robot: franka, prefix: a, base_pose: [0, 0.5, 0]}\n  - {robot: ur5, prefix: a, base_pose: [0, 0, 0]}\n")
    with pytest.raises(RobotConfigError, match="duplicate prefix 'a_'"):
        load_robot_config(tmp_path)
    (tmp_path / "robot.yaml").write_text("arms:\n  - {robot: franka, prefix: a, base_pose: [0, 0, 0]}\nurdf: x.urdf\n")
    with pytest.raises(RobotConfigError, match="unknown key"):
        load_robot_config(tmp_path)


def test_overlapping_bases_raise_naming_the_arms():
    # two Pandas 10 cm apart: their base links (fixed, never checked by the planner) intersect
    with pytest.raises(InvalidInputError, match="arms 'left' and 'right' overlap.*left_panda_link0.*right_panda_link0"):
        MotionGenerator.from_robots({"left": ("franka", Pose([0, 0.05, 0])), "right": ("franka", Pose([0, -0.05, 0]))})
    # apart (30 cm), the same robots load
    mg = MotionGenerator.from_robots({"left": ("franka", Pose([0, 0.15, 0])), "right": ("franka", Pose([0, -0.15, 0]))})
    assert [a.name for a in mg.config.arms] == ["left", "right"]


def test_a_start_of_the_wrong_length_raises_naming_it(dual):
    with pytest.raises(InvalidInputError, match="start_q"):
        dual.plan_joints(np.zeros(7), dual.default_joint_positions)
    with pytest.raises(InvalidInputError, match="start_q"):
        dual.plan_poses(np.zeros(9), {"left_panda_hand": dual.fk(dual.default_joint_positions, "left_panda_hand")})
