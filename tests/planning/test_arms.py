"""Planning for several arms (`manip.planning.arms`): one arm's goal holds the others, several
links' goals arrive together in one motion, and the goals are checked."""

from __future__ import annotations

import numpy as np
import pytest

from manip import MotionGenerator, Pose
from manip.benchmarking.verify import Verifier
from manip.errors import InvalidInputError, UnknownNameError

TABLE = {"cuboid": {"table": {"dims": [0.8, 1.6, 0.04], "pose": [0.55, 0.0, -0.02, 1, 0, 0, 0]},
                    "post": {"dims": [0.06, 0.06, 0.25], "pose": [0.45, 0.0, 0.125, 1, 0, 0, 0]}}}
DOWN = [0.0, 1.0, 0.0, 0.0]


@pytest.fixture(scope="module")
def dual() -> MotionGenerator:
    return MotionGenerator("dual_franka", TABLE)


@pytest.fixture(scope="module")
def verifier(dual) -> Verifier:
    return Verifier(dual.config)


def _verified(verifier, result, start):
    traj = result.trajectory
    verdict = verifier.verify_trajectory(TABLE, traj.times, traj.positions, traj.velocities, traj.accelerations,
                                         start_q=start, goal_q=result.goal_q)
    assert verdict.valid, verdict


@pytest.mark.parametrize("link,goal", [("left_panda_hand", Pose([0.5, 0.25, 0.25], DOWN)),
                                       ("right_panda_hand", Pose([0.4, -0.3, 0.35], DOWN))])
def test_plan_pose_of_one_hand_keeps_the_other_arm_still(dual, verifier, link, goal):
    q0 = dual.default_joint_positions
    result = dual.plan_pose(q0, goal, link=link, seed=1)
    assert result.success, result.message
    moving = dual.config.arms[0 if link.startswith("left") else 1]
    held = np.ones(14, dtype=bool)
    held[moving.columns[0]:moving.columns[1]] = False
    P = result.trajectory.positions
    assert np.array_equal(P[:, held], np.broadcast_to(q0[held], P[:, held].shape))
    assert np.abs(P[:, ~held] - q0[~held]).max() > 0.1
    assert dual.fk(result.goal_q, link).distance(goal)[0] < 1e-3
    _verified(verifier, result, q0)


def test_ik_of_one_link_moves_only_its_arm(dual):
    seed = dual.default_joint_positions.copy()
    seed[7] = 0.4
    for attempt in range(3):
        r = dual.ik(Pose([0.45, -0.1 * attempt, 0.3], DOWN), link="left_panda_hand", seed_q=seed, seed=attempt)
        assert r.success
        np.testing.assert_array_equal(r.q[7:], seed[7:])
    batch = dual.batch_ik(Pose.stack([Pose([0.5, -0.3, 0.2], DOWN), Pose([0.3, -0.5, 0.3], DOWN)]),
                          link="right_panda_hand", seed_q=seed)
    assert batch.success.all()
    np.testing.assert_array_equal(batch.q[:, :7], np.broadcast_to(seed[:7], (2, 7)))


def test_batch_ik_holds_each_rows_other_arm_at_that_rows_seed(dual):
    seeds = np.repeat(dual.default_joint_positions[None], 3, axis=0)
    seeds[:, 0] = [-0.6, 0.0, 0.6]             # the left arm turned three ways: the right arm's IK keeps each
    seeds[2, 3] = -1.2
    goals = Pose.stack([Pose([0.5, -0.3, 0.2], DOWN), Pose([0.3, -0.4, 0.3], DOWN), Pose([0.45, -0.2, 0.25], DOWN)])
    batch = dual.batch_ik(goals, link="right_panda_hand", seed_q=seeds, collision_free=True)
    assert batch.success.all()
    np.testing.assert_array_equal(batch.q[:, :7], seeds[:, :7])
    for i in range(3):
        assert dual.fk(batch.q[i], "right_panda_hand").distance(goals[i])[0] < 1e-3
        assert not dual.check_collision(batch.q[i])
    # rows sharing the held values are solved together and give the same answer as alone
    alone = dual.batch_ik(goals[[0]], link="right_panda_hand", seed_q=seeds[[0]], collision_free=True)
    np.testing.assert_allclose(alone.q[0, :7], seeds[0, :7])


def test_plan_poses_moves_both_hands_in_one_motion(dual, verifier):
    q0 = dual.default_joint_positions
    goals = {"left_panda_hand": Pose([0.45, 0.15, 0.35], DOWN), "right_panda_hand": Pose([0.55, -0.2, 0.2], DOWN)}
    result = dual.plan_poses(q0, goals, seed=0)
    assert result.success, result.message
    assert result.position_error < 1e-3 and result.rotation_error < 1e-2
    for link, goal in goals.items():
        assert dual.fk(result.trajectory.positions[-1], link).distance(goal)[0] < 1e-3
    P = result.trajectory.positions
    # both arms move, and both are under way together (one trajectory, not one arm after the other)
    moving = np.abs(np.diff(P, axis=0)) > 1e-9
    assert np.any(moving[:, :7] & moving[:, 7:].any(axis=1, keepdims=True))
    _verified(verifier, result, q0)


def _line_fraction(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(fraction along a -> b, distance from the line [m]) of points (N, 3)."""
    d = b - a
    f = (points - a) @ d / (d @ d)
    return f, np.linalg.norm(points - (a + f[:, None] * d), axis=1)


def test_plan_poses_linear_moves_both_hands_on_their_lines_together(dual, verifier):
    q0 = dual.default_joint_positions
    hands = ("left_panda_hand", "right_panda_hand")
    starts = {h: dual.fk(q0, h) for h in hands}
    goals = {"left_panda_hand": Pose(starts["left_panda_hand"].position + [0.05, -0.05, -0.15],
                                     starts["left_panda_hand"].quaternion),
             "right_panda_hand": Pose(starts["right_panda_hand"].position + [-0.03, 0.0, -0.08],
                                      starts["right_panda_hand"].quaternion)}
    result = dual.plan_poses(q0, goals, linear=True, seed=0)
    assert result.success, result.message
    assert result.source == "linear" and result.position_error < 1e-3
    P = result.trajectory.resample(0.002).positions
    fractions = []
    for h in hands:
        f, off = _line_fraction(dual.fk(P, h).position, starts[h].position, goals[h].position)
        assert off.max() < 2e-3, (h, off.max())            # on its straight line throughout
        fractions.append(f)
    # together: both hands at the same fraction of their lines at every sample, and both arrive
    assert np.abs(fractions[0] - fractions[1]).max() < 0.02
    assert abs(fractions[0][-1] - 1) < 1e-3 and abs(fractions[1][-1] - 1) < 1e-3
    _verified(verifier, result, q0)
    # one goal: the other arm is held, as plan_pose(..., linear=True)
    one = dual.plan_poses(q0, {"left_panda_hand": goals["left_panda_hand"]}, linear=True, seed=0)
    assert one.success, one.message
    held = one.trajectory.positions[:, 7:]
    np.testing.assert_array_equal(held, np.broadcast_to(q0[7:], held.shape))


def test_plan_poses_hands_passing_each_other(dual, verifier):
    # the left hand goes right of the post, the right hand left of it: the arms cross
    q0 = dual.default_joint_positions
    goals = {"left_panda_hand": Pose([0.5, -0.15, 0.3], DOWN), "right_panda_hand": Pose([0.35, 0.15, 0.45], DOWN)}
    result = dual.plan_poses(q0, goals, seed=0)
    assert result.success, result.message
    _verified(verifier, result, q0)


def test_plan_poses_bad_goals_raise_naming_them(dual):
    q0 = dual.default_joint_positions
    with pytest.raises(UnknownNameError, match="goals: link.*'left_panda_hnd'"):
        dual.plan_poses(q0, {"left_panda_hnd": Pose([0.5, 0.2, 0.3], DOWN)})
    with pytest.raises(InvalidInputError, match="give one link per arm"):
        dual.plan_poses(q0, {"left_panda_hand": Pose([0.5, 0.2, 0.3], DOWN),
                             "left_panda_link4": Pose([0.3, 0.2, 0.5], DOWN)})
    with pytest.raises(InvalidInputError, match=r"goals\['right_panda_hand'\] must be a single manip.Pose"):
        dual.plan_poses(q0, {"right_panda_hand": [0.5, 0.2, 0.3]})
    with pytest.raises(InvalidInputError, match="non-empty dict"):
        dual.plan_poses(q0, {})
    with pytest.raises(UnknownNameError, match="link of an arm"):
        dual.plan_poses(q0, {"base": Pose([0.5, 0.2, 0.3], DOWN)})


def test_a_straight_line_of_one_hand_keeps_the_other_arm_still(dual):
    q0 = dual.default_joint_positions
    start = dual.fk(q0, "right_panda_hand")
    goal = Pose(start.position + [0.1, 0.05, -0.15], start.quaternion)
    result = dual.plan_pose(q0, goal, link="right_panda_hand", linear=True)
    assert result.success, result.message
    P = result.trajectory.positions
    assert np.array_equal(P[:, :7], np.broadcast_to(q0[:7], (len(P), 7)))
    hand = dual.fk(P, "right_panda_hand").position
    line = goal.position - start.position
    off_line = np.linalg.norm(np.cross(hand - start.position, line / np.linalg.norm(line)), axis=1)
    assert off_line.max() < 2e-3
