"""Lines of cuRobo scripts that read results as torch tensors, and cuRobo's per-call IK names.

cuRobo's results hold tensors: `if result.success.item():`, `result.success.cpu().numpy()`,
`result.position_error.item()`. manip's results answer them (`manip.host_array`), and
`solve_single(..., num_seeds=)` maps onto `IKSolver.solve(..., max_attempts=)`.
"""

from __future__ import annotations

import pickle
import re
from dataclasses import replace

import numpy as np
import pytest

from manip import InvalidInputError, MotionGenerator, Pose
from manip.host_array import HostArray, host

TABLE = {"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]}}}
DOWN = [0, 1, 0, 0]  # (w, x, y, z): the hand pointing down
REACHABLE = Pose([0.5, 0.2, 0.3], DOWN)
IN_TABLE = Pose([0.5, 0.0, 0.0], DOWN)


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka", TABLE)


def test_plan_result_success_reads_as_curobos_tensor(mg):
    result = mg.plan_pose(mg.default_joint_positions, REACHABLE)
    assert result.success.item() is True                     # `if result.success.item():`
    assert result.success.cpu().numpy().item() is True and result.success.tolist() == [True]
    assert result.success.detach().cpu() == True and bool(result.success)
    assert isinstance(result.position_error.item(), float) and result.position_error.item() < 1e-3
    # cuRobo's MotionGenResult of plan_single holds (1,) tensors: `result.success[0]` indexes them
    # (it raised IndexError on a 0-d array), and they convert and format as the number they hold
    assert result.success.shape == (1,) and result.position_error.shape == result.rotation_error.shape == (1,)
    assert result.success[0] and result.success[0].item() is True and bool(result.success[0])
    assert float(result.position_error) < 1e-3 and f"{result.position_error:.2f}" == "0.00"
    assert int(result.success) == 1 and f"{result.success}" == "True"
    # a failed plan: False the same way, and a replace() keeps the type
    failed = mg.plan_pose(mg.default_joint_positions, IN_TABLE)
    assert failed.success.item() is False and not failed and not failed.success[0]
    assert replace(failed, success=True).success.item() is True
    assert replace(failed, success=True).success.shape == (1,)
    # a list of them stacks into a (B, 1) bool array, as torch.stack / cat would give (B,)
    assert np.concatenate([result.success, failed.success]).tolist() == [True, False]
    assert pickle.loads(pickle.dumps(result)).success.item() is True
    with pytest.raises(InvalidInputError, match="CPU"):
        result.success.cuda()
    assert result.success.to("cpu") is result.success
    with pytest.raises(InvalidInputError, match=r"got .to\('cuda:0'\)"):
        result.success.to("cuda:0")


def test_batch_plan_results_read_as_curobos_batched_result(mg):
    """`plan_batch` gives the N results in a list that also reads as cuRobo's batched
    MotionGenResult: `result.success` (N,) (an AttributeError on a list before)."""
    results = mg.plan_batch(mg.default_joint_positions, [REACHABLE, IN_TABLE])
    assert isinstance(results, list) and len(results) == 2 and results[0].success.item() is True
    assert isinstance(results.success, HostArray) and results.success.shape == (2,)
    assert results.success.cpu().numpy().tolist() == [True, False] and not results.success.all()
    assert results.position_error.shape == (2,) and results.position_error[0] < 1e-3
    assert [s.name for s in results.status] == ["SUCCESS", "IK_FAIL"]
    paths = results.get_paths()
    assert paths[0] is results[0].trajectory and paths[1] is None
    with pytest.raises(AttributeError, match="no 'interpolation_dt' \\(cuRobo's name\\); manip's equivalent"):
        _ = results.interpolation_dt
    assert mg.plan_batch(mg.default_joint_positions, []) == [] and mg.plan_batch(
        mg.default_joint_positions, []).success.shape == (0,)
    assert np.concatenate([r.success for r in results]).tolist() == [True, False]
    with pytest.raises(TypeError, match=r"one-element arrays convert to float; this one has shape \(2,\)"):
        float(host([1.0, 2.0]))


def test_ik_results_read_as_curobos_tensors(mg):
    one = mg.ik(REACHABLE)
    assert one.success.item() is True and one.position_error.item() < 1e-3
    # cuRobo's solve_single gives (batch, seeds) = (1, 1) tensors
    assert one.success.shape == one.position_error.shape == one.rotation_error.shape == (1, 1)
    assert one.success[0][0] and one.success[0].item() is True and f"{one.position_error:.1f}" == "0.0"
    batch = mg.batch_ik(Pose.stack([REACHABLE, IN_TABLE]), collision_free=True)
    assert isinstance(batch.success, HostArray)
    np.testing.assert_array_equal(batch.success.cpu().numpy(), [[True], [False]])
    assert type(batch.success.cpu().numpy()) is np.ndarray
    assert batch.success.tolist() == [[True], [False]] and batch.position_error.cpu().numpy().shape == (2, 1)
    assert not batch.success.flags.writeable
    assert mg.ik_solver.solve_many(REACHABLE, n=2).success.item() is True
    assert batch[0].success.shape == (1, 1) and batch[1].success.item() is False


def test_batch_ik_results_have_curobos_solve_batch_shapes(mg):
    """cuRobo's `solve_batch` returns (batch, return_seeds) = (N, 1) `success` / `position_error` /
    `rotation_error` and an (N, 1, dof) `solution`, so `solution[success]` is the (K, dof) solved
    rows (manip's were (N,) with no `solution`: that line raised an AttributeError)."""
    goals = Pose.stack([REACHABLE, IN_TABLE, Pose([0.4, -0.2, 0.4], DOWN)])
    for batch in (mg.batch_ik(goals, collision_free=True), mg.ik_solver.solve_batch(goals)):
        n = len(goals)
        assert batch.success.shape == batch.position_error.shape == batch.rotation_error.shape == (n, 1)
        assert batch.solution.shape == (n, 1, 7) and isinstance(batch.solution, HostArray)
        good = batch.solution[batch.success]                   # cuRobo's line
        assert good.shape == (int(batch.success.sum()), 7)
        np.testing.assert_array_equal(good, batch.q[batch.solved])    # manip's (N,) mask
        for i in np.flatnonzero(batch.solved):                # each solution reaches its goal
            dp, _ = mg.fk(batch.q[i]).distance(goals[i])
            assert dp == pytest.approx(float(batch.position_error[i, 0]), abs=1e-9) and dp < 5e-3
        assert batch.success[0].item() is True and bool(batch[0].success) and batch[0].q.shape == (7,)
    assert mg.batch_ik(goals, collision_free=True).solved.tolist() == [True, False, True]
    assert float(mg.batch_ik(goals).success_rate) == pytest.approx(1.0)
    with pytest.raises(InvalidInputError, match=r"success must be \(N,\) or \(N, 1\) with N = 3"):
        replace(batch, success=np.ones(2, dtype=bool))


def test_num_seeds_per_call_is_curobos_name_of_max_attempts(mg):
    """cuRobo's `solve_single(goal, num_seeds=n)`: the starts tried for this call (a TypeError before)."""
    with pytest.warns(DeprecationWarning, match="num_seeds is deprecated; use max_attempts"):
        few = mg.ik(IN_TABLE, collision_free=True, num_seeds=3)
    assert few.attempts == 3 and not few.success
    assert mg.ik(IN_TABLE, collision_free=True, max_attempts=5).attempts == 5
    with pytest.warns(DeprecationWarning):
        r = mg.ik_solver.solve(REACHABLE, num_seeds=2)
    assert r.success and r.attempts <= 2
    with pytest.warns(DeprecationWarning):
        b = mg.batch_ik(Pose.stack([IN_TABLE, IN_TABLE]), collision_free=True, num_seeds=4)
    assert b.attempts.tolist() == [4, 4]
    with pytest.raises(InvalidInputError, match="give max_attempts only"):
        mg.ik_solver.solve(REACHABLE, num_seeds=2, max_attempts=3)
    with pytest.raises(InvalidInputError, match="num_seeds"):
        mg.ik_solver.solve(REACHABLE, num_seeds=0)
    with pytest.raises(InvalidInputError, match="max_attempts"):
        mg.ik_solver.solve_batch(Pose.stack([REACHABLE]), max_attempts=1.5)


def test_collision_free_batch_ik_names_what_a_rejected_goal_touches(mg):
    """`batch_ik(collision_free=True)` says what the best solution of a goal in the table touches,
    as `ik(collision_free=True)` does (it said only that validity_fn rejected every solution)."""
    result = mg.batch_ik(Pose.stack([IN_TABLE, REACHABLE, IN_TABLE]), collision_free=True)
    assert result.success.tolist() == [[False], [True], [False]]
    for i in (0, 2):
        assert result.status[i].name == "REJECTED_BY_VALIDITY"
        assert re.search(r"in collision \(collision_free=True\); the best one found: goal in collision: "
                         r"panda_hand touches table \(\d+\.\d mm deep", result.message[i]), result.message[i]
    assert result.message[1] == ""
    # a validity_fn of the caller's own keeps the generic message
    own = mg.batch_ik(Pose.stack([IN_TABLE]), validity_fn=lambda Q: np.zeros(len(Q), dtype=bool))
    assert own.status[0].name == "REJECTED_BY_VALIDITY" and "touches" not in own.message[0]


def test_curobos_robot_world_names_point_to_manips(mg):
    """A cuRobo RobotWorld script's calls on the MotionGenerator built in its place name manip's
    equivalent (a bare "no attribute" before), and every named equivalent exists."""
    from manip import curobo_names

    for name in ("get_collision_distance", "get_self_collision_distance", "get_kinematics", "collision_constraint",
                 "get_world_self_collision_distance_from_joints", "validate", "sample"):
        with pytest.raises(AttributeError, match=rf"no '{name}' \(cuRobo's name\); manip's equivalent: "):
            getattr(mg, name)
    for name, where in curobo_names.ROBOT_WORLD.items():
        if where.startswith("nothing"):
            continue
        for ref in re.findall(r"(?<![\w.])((?:checker|kinematics)\.\w+|[a-z_]+)\(", where):
            obj = mg
            for part in ref.split("."):
                obj = getattr(obj, part)   # raises if the table names something manip lacks
    # what get_world_self_collision_distance_from_joints gives, the manip way
    q = np.vstack([mg.default_joint_positions, mg.ik(IN_TABLE).q])
    clearance = mg.checker.world_clearance_batch(q)
    assert clearance[0] > 0 and clearance[1] <= 0
    assert mg.checker.in_collision_batch(q).tolist() == [False, True]
