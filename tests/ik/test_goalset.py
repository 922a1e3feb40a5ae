"""cuRobo's goal-set IK (`IKSolver.solve_goalset` / `solve_batch_goalset`) raised an AttributeError
pointing to `solve_batch`: a cuRobo grasp script giving several grasp poses stopped there. Now it
reaches one pose of each set and says which (`goalset_index`), in cuRobo's shapes: `success`,
errors and `goalset_index` (B, 1), `solution` (B, 1, dof)."""

from __future__ import annotations

import numpy as np
import pytest

from manip import InvalidInputError, MotionGenerator, Pose
from manip.host_array import HostArray

TABLE = {"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]}}}
DOWN = [0, 1, 0, 0]                       # (w, x, y, z): the hand pointing down
FAR = Pose([3.0, 0.0, 0.5], DOWN)         # out of the arm's reach
LEFT, RIGHT = Pose([0.45, 0.25, 0.3], DOWN), Pose([0.45, -0.25, 0.3], DOWN)


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka", TABLE)


def test_solve_goalset_reaches_one_pose_and_says_which(mg):
    ik = mg.ik_solver
    goals = Pose.stack([FAR, RIGHT, Pose([2.5, 1.0, 0.2], DOWN)])   # only pose 1 is reachable
    result = ik.solve_goalset(goals)
    assert result.success.shape == result.position_error.shape == result.goalset_index.shape == (1, 1)
    assert result.solution.shape == (1, 1, 7) and isinstance(result.goalset_index, HostArray)
    assert result.success.item() is True and result.goalset_index.item() == 1
    assert result.goal_success.tolist() == [[False, True, False]]
    q = result.solution[result.success][0]                         # cuRobo's line: (K, dof)
    dp, dr = mg.fk(q).distance(goals[result.goalset_index.item()])
    assert dp < ik.position_tolerance and dr < ik.rotation_tolerance


def test_solve_goalset_keeps_the_pose_nearest_the_seed(mg):
    ik = mg.ik_solver
    q_left, q_right = ik.solve(LEFT).q, ik.solve(RIGHT).q
    goals = Pose.stack([LEFT, RIGHT])
    assert ik.solve_goalset(goals, seed_q=q_left).goalset_index.item() == 0
    assert ik.solve_goalset(goals, seed_q=q_right).goalset_index.item() == 1


def test_solve_batch_goalset_one_row_per_set(mg):
    ik = mg.ik_solver
    sets = [Pose.stack([FAR, LEFT]), Pose.stack([RIGHT, FAR]), Pose.stack([FAR, FAR])]
    result = ik.solve_batch_goalset(sets)
    assert result.success.shape == result.goalset_index.shape == (3, 1) and result.solution.shape == (3, 1, 7)
    assert result.solved.tolist() == [True, True, False] and result.goalset_index[:2, 0].tolist() == [1, 0]
    for b in range(2):
        dp, _ = mg.fk(result.q[b]).distance(sets[b][int(result.goalset_index[b, 0])])
        assert dp < ik.position_tolerance
    assert "no pose of the goal set (2) was reached" in result.message[2]
    flat = ik.solve_batch_goalset(Pose.stack([FAR, LEFT, RIGHT, FAR]), n_goalset=2)    # one Pose, set by set
    assert flat.goal_index.tolist() == [1, 0] and flat.solved.tolist() == [True, True]


@pytest.mark.parametrize("call, kwargs, match", [
    ("set", {"goals": LEFT}, "goals must be a batched manip.Pose of G >= 1 poses"),
    ("set", {"goals": Pose.stack([LEFT]), "seed_q": np.zeros((2, 7))}, r"seed_q must be \(dof,\) = \(7,\)"),
    ("batch", {"goal_sets": [Pose.stack([LEFT]), Pose.stack([LEFT, RIGHT])]}, r"the same number of poses G .*\[1, 2\]"),
    ("batch", {"goal_sets": Pose.stack([LEFT, RIGHT, FAR])}, "needs n_goalset=G"),
    ("batch", {"goal_sets": Pose.stack([LEFT, RIGHT, FAR]), "n_goalset": 2}, "dividing the 3 poses"),
    ("batch", {"goal_sets": [Pose.stack([LEFT])] * 2, "seed_q": np.zeros((3, 7))}, r"one row per goal set \(2, 7\)"),
    ("batch", {"goal_sets": []}, "non-empty list of B batched Poses"),
])
def test_bad_goal_sets_say_what_is_valid(mg, call, kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        if call == "set":
            mg.ik_solver.solve_goalset(**kwargs)
        else:
            mg.ik_solver.solve_batch_goalset(**kwargs)
