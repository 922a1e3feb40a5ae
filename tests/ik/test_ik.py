"""Inverse kinematics on the real Franka model: success, limits, nearest-to-seed, failures, errors."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from manip.errors import InvalidInputError, ManipError, UnknownNameError
from manip.ik import BatchIKResult, IKResult, IKSolutions, IKSolver, IKStatus
from manip.kinematics import Kinematics
from manip.status import Status
from manip.pose import Pose

HAND = "panda_hand"
POS_TOL, ROT_TOL = 1e-3, 0.01


@pytest.fixture(scope="module")
def solver(franka_kinematics: Kinematics) -> IKSolver:
    return IKSolver(franka_kinematics, seed=0)


def random_configs(k: Kinematics, n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(k.lower, k.upper, (n, k.dof))


def assert_reaches(k: Kinematics, q: np.ndarray, goal: Pose, link: str = HAND) -> None:
    """An independent check of a claimed solution: limits and the Pose of `Kinematics.fk`."""
    assert k.within_limits(q), k.limit_violations(q)
    dp, dr = k.fk(q, link).distance(goal)
    assert dp <= POS_TOL and dr <= ROT_TOL, (dp, dr)


# ---------------------------------------------------------------------- single solves
def test_random_reachable_poses_are_solved_within_limits(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    Q = random_configs(k, 40, seed=11)
    for q_true in Q:
        goal = k.fk(q_true, HAND)
        r = solver.solve(goal, HAND)
        assert isinstance(r, IKResult)
        assert r.success and r.status is IKStatus.SUCCESS, (q_true, r)
        assert r.message == ""
        assert r.q.shape == (k.dof,)
        assert r.position_error <= POS_TOL and r.rotation_error <= ROT_TOL
        assert r.attempts >= 1 and r.iterations >= 0 and r.solve_time > 0
        assert_reaches(k, r.q, goal)
        # the reported errors are the errors at the returned q
        dp, dr = k.fk(r.q, HAND).distance(goal)
        assert r.position_error == pytest.approx(float(dp), abs=1e-9)
        assert r.rotation_error == pytest.approx(float(dr), abs=1e-6)


def test_converges_much_tighter_than_the_success_tolerance(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    errors = []
    for q_true in random_configs(k, 20, seed=12):
        r = solver.solve(k.fk(q_true, HAND), HAND)
        assert r.success
        errors.append((r.position_error, r.rotation_error))
    assert np.max(errors) <= 1e-4


def test_goals_at_joint_limits_give_solutions_within_limits(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    rng = np.random.default_rng(3)
    for j in range(k.dof):
        for bound in (k.lower, k.upper):
            q_true = rng.uniform(k.lower, k.upper)
            q_true[j] = bound[j]
            goal = k.fk(q_true, HAND)
            r = solver.solve(goal, HAND)
            assert r.success, (j, r.status)
            assert_reaches(k, r.q, goal)


@pytest.mark.parametrize("link", ["panda_hand_tcp", "panda_link7", "panda_link8"])
def test_other_links(solver: IKSolver, franka_kinematics: Kinematics, link: str):
    k = franka_kinematics
    for q_true in random_configs(k, 5, seed=5):
        goal = k.fk(q_true, link)
        r = solver.solve(goal, link)
        assert r.success
        assert_reaches(k, r.q, goal, link)


def test_default_link_is_the_ee_link(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    q_true = random_configs(k, 1, seed=8)[0]
    r = solver.solve(k.fk(q_true, k.config.ee_link))
    assert r.success
    assert_reaches(k, r.q, k.fk(q_true, k.config.ee_link), k.config.ee_link)


def test_seed_near_a_solution_returns_that_solution(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    rng = np.random.default_rng(21)
    margin = 0.1 * (k.upper - k.lower)
    for _ in range(10):
        q_true = rng.uniform(k.lower + margin, k.upper - margin)
        seed_q = q_true + rng.normal(scale=0.03, size=k.dof)
        r = solver.solve(k.fk(q_true, HAND), HAND, seed_q=seed_q)
        assert r.success
        assert r.attempts == 1
        assert np.max(np.abs(r.q - q_true)) < 0.05


def test_more_solutions_never_move_the_answer_away_from_the_seed(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    for i, q_true in enumerate(random_configs(k, 6, seed=31)):
        goal = k.fk(q_true, HAND)
        seed_q = k.config.default_joint_positions
        one = solver.solve(goal, HAND, seed_q=seed_q, seed=i)
        many = solver.solve(goal, HAND, seed_q=seed_q, num_solutions=6, seed=i)
        assert one.success and many.success
        # same random stream: the first solution is among the six, the nearest is returned
        assert np.linalg.norm(many.q - seed_q) <= np.linalg.norm(one.q - seed_q) + 1e-12
        assert_reaches(k, many.q, goal)


def test_same_seed_same_answer(franka_kinematics: Kinematics):
    k = franka_kinematics
    goals = [k.fk(q, HAND) for q in random_configs(k, 5, seed=41)]
    a = [IKSolver(k, seed=3).solve(g, HAND, seed_q=np.zeros(7)).q for g in goals]
    b = [IKSolver(k, seed=3).solve(g, HAND, seed_q=np.zeros(7)).q for g in goals]
    np.testing.assert_array_equal(np.array(a), np.array(b))


def test_far_goal_fails_cleanly_with_out_of_reach(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    r = solver.solve(Pose(np.array([2.0, 0.0, 0.5])), HAND)
    assert not r.success
    assert r.status is IKStatus.OUT_OF_REACH
    assert "closer" in r.status.hint
    assert "reaches at most" in r.message
    assert k.within_limits(r.q)
    assert r.position_error > 1.0


def test_unreachable_goal_within_the_reach_bound_is_not_converged(franka_kinematics: Kinematics):
    k = franka_kinematics
    s = IKSolver(k, max_attempts=10)
    # below the base, pointing up: inside the reach ball, not reachable
    r = s.solve(Pose(np.array([0.0, 0.0, -0.4])), HAND)
    assert not r.success
    assert r.status is IKStatus.NOT_CONVERGED
    assert r.attempts == 10
    assert "no attempt of 10 converged" in r.message
    assert k.within_limits(r.q)
    dp, dr = k.fk(r.q, HAND).distance(Pose(np.array([0.0, 0.0, -0.4])))
    assert r.position_error == pytest.approx(float(dp), abs=1e-9)
    assert r.position_error > POS_TOL or r.rotation_error > ROT_TOL


def test_too_few_iterations_is_not_converged(franka_kinematics: Kinematics):
    k = franka_kinematics
    s = IKSolver(k, max_iterations=1, max_attempts=1)
    q_true = np.array([1.5, 0.5, -1.0, -1.0, 1.0, 2.5, -1.0])
    r = s.solve(k.fk(q_true, HAND), HAND)
    assert not r.success and r.status is IKStatus.NOT_CONVERGED and r.attempts == 1


def test_validity_fn_is_respected(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    calls = []

    def first_joint_positive(Q: np.ndarray) -> np.ndarray:
        calls.append(Q.shape)
        return Q[:, 0] > 0.0

    for q_true in random_configs(k, 5, seed=51):
        q_true[0] = abs(q_true[0])
        goal = k.fk(q_true, HAND)
        r = solver.solve(goal, HAND, seed_q=np.array([-1.0, 0, 0, -2.0, 0, 2.0, 0]), validity_fn=first_joint_positive)
        assert r.success and r.q[0] > 0
        assert_reaches(k, r.q, goal)
    assert calls and all(shape[1] == k.dof for shape in calls)


def test_validity_fn_rejecting_everything(franka_kinematics: Kinematics):
    k = franka_kinematics
    s = IKSolver(k, max_attempts=3)
    goal = k.fk(k.config.default_joint_positions, HAND)
    r = s.solve(goal, HAND, validity_fn=lambda Q: np.zeros(len(Q), dtype=bool))
    assert not r.success and r.status is IKStatus.REJECTED_BY_VALIDITY
    assert "validity_fn" in r.message and "3 attempt" in r.message


def test_time_limit(solver: IKSolver, franka_kinematics: Kinematics):
    goal = franka_kinematics.fk(random_configs(franka_kinematics, 1, seed=1)[0], HAND)
    r = solver.solve(goal, HAND, time_limit=0.0)
    assert not r.success and r.status is IKStatus.TIME_LIMIT
    assert "time_limit" in r.message


def test_a_wrong_solution_is_never_reported(franka_kinematics: Kinematics, monkeypatch: pytest.MonkeyPatch):
    """If the descent claims convergence at a wrong q, the independent check discards it."""
    k = franka_kinematics
    s = IKSolver(k, max_attempts=4)
    goal = k.fk(random_configs(k, 1, seed=2)[0], HAND)
    lying = lambda q0, fid, R, p: (np.clip(q0, k.lower, k.upper), 0.0, 0.0, 1)  # noqa: E731
    monkeypatch.setattr(s, "_attempt", lying)
    r = s.solve(goal, HAND)
    assert not r.success and r.status is IKStatus.NOT_CONVERGED


def test_status_values_are_lowercase_with_a_hint_for_every_member():
    assert issubclass(IKStatus, Status)
    for status in IKStatus:
        assert status.value == status.name.lower()
        assert status.hint and isinstance(status.hint, str)
        assert str(status) == status.name
    assert IKStatus("not_converged") is IKStatus.NOT_CONVERGED


def test_every_failure_has_a_message(franka_kinematics: Kinematics):
    k = franka_kinematics
    s = IKSolver(k, max_attempts=2)
    goal = k.fk(k.config.default_joint_positions, HAND)
    failures = [
        s.solve(Pose(np.array([2.0, 0.0, 0.5])), HAND),
        s.solve(Pose(np.array([0.0, 0.0, -0.4])), HAND),
        s.solve(goal, HAND, validity_fn=lambda Q: np.zeros(len(Q), dtype=bool)),
        s.solve(goal, HAND, time_limit=0.0),
    ]
    assert {r.status for r in failures} == set(IKStatus) - {IKStatus.SUCCESS}
    for r in failures:
        assert not r.success and r.message and "\n" not in r.message, r
    b = s.solve_batch(Pose.stack([goal, Pose(np.array([0.0, 0.0, -0.4]))]), HAND)
    assert b.success[0] and b.message[0] == ""
    assert not b.success[1] and b.message[1] and b[1].message == b.message[1]


def test_result_is_frozen(solver: IKSolver, franka_kinematics: Kinematics):
    r = solver.solve(franka_kinematics.fk(franka_kinematics.config.default_joint_positions, HAND), HAND)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.success = False  # type: ignore[misc]
    with pytest.raises(ValueError):
        r.q[0] = 1.0


# ---------------------------------------------------------------------- solve_many
def test_solve_many_distinct_sorted_and_valid(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    q_true = np.array([0.3, 0.2, -0.4, -2.0, 0.5, 2.0, 0.3])
    goal = k.fk(q_true, HAND)
    seed_q = k.config.default_joint_positions
    sols = solver.solve_many(goal, HAND, n=6, seed_q=seed_q)
    assert isinstance(sols, IKSolutions)
    assert sols.success and sols.status is IKStatus.SUCCESS and sols.message == ""
    assert sols.attempts == max(4 * 6, 16)
    assert sols.q.ndim == 2 and sols.q.shape[1] == k.dof
    assert 2 <= len(sols) <= 6
    d = np.linalg.norm(sols.q - seed_q, axis=1)
    assert np.all(np.diff(d) >= 0)
    for i in range(len(sols)):
        assert_reaches(k, sols[i], goal)
        for j in range(i):
            assert np.max(np.abs(sols[i] - sols[j])) >= 0.05
    only_positive = solver.solve_many(goal, HAND, n=6, seed_q=seed_q, validity_fn=lambda Q: Q[:, 6] > 0.0)
    assert np.all(only_positive.q[:, 6] > 0)


def test_solve_many_result_behaves_as_its_rows(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    goal = k.fk(np.array([0.3, 0.2, -0.4, -2.0, 0.5, 2.0, 0.3]), HAND)
    sols = solver.solve_many(goal, HAND, n=4)
    rows = list(sols)
    assert len(rows) == len(sols) == sols.q.shape[0] >= 1
    for row, q in zip(rows, sols.q):
        np.testing.assert_array_equal(row, q)
    np.testing.assert_array_equal(sols[0], sols.q[0])
    np.testing.assert_array_equal(sols[-1], sols.q[-1])
    a = np.asarray(sols)
    assert a.shape == (len(sols), k.dof)
    np.testing.assert_array_equal(a, sols.q)
    assert np.asarray(sols, dtype=np.float32).dtype == np.float32
    np.testing.assert_array_equal(np.array(sols), sols.q)
    with pytest.raises(ValueError):
        sols.q[0, 0] = 1.0  # read-only, like IKResult.q
    with pytest.raises(dataclasses.FrozenInstanceError):
        sols.status = IKStatus.TIME_LIMIT  # type: ignore[misc]


def test_solve_many_out_of_reach_is_empty(solver: IKSolver):
    sols = solver.solve_many(Pose(np.array([0.0, 2.0, 0.0])), HAND, n=4)
    assert sols.q.shape == (0, 7) and len(sols) == 0 and list(sols) == []
    assert np.asarray(sols).shape == (0, 7)
    assert not sols.success and sols.status is IKStatus.OUT_OF_REACH
    assert "reaches at most" in sols.message
    assert sols.attempts == 0


def test_solve_many_unreachable_in_ball_and_rejected(solver: IKSolver):
    # below the base, pointing up: inside the reach ball, not reachable
    sols = solver.solve_many(Pose(np.array([0.0, 0.0, -0.4])), HAND, n=2, attempts=12)
    assert len(sols) == 0 and sols.status is IKStatus.NOT_CONVERGED
    assert sols.attempts == 12 and "12" in sols.message and "converged" in sols.message
    goal = solver.kinematics.fk(solver.kinematics.config.default_joint_positions, HAND)
    none = solver.solve_many(goal, HAND, n=2, validity_fn=lambda Q: np.zeros(len(Q), dtype=bool))
    assert len(none) == 0 and none.status is IKStatus.REJECTED_BY_VALIDITY
    assert "validity_fn" in none.message


def test_solve_many_num_seeds_is_a_deprecated_name_of_attempts(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    goal = k.fk(np.array([0.3, 0.2, -0.4, -2.0, 0.5, 2.0, 0.3]), HAND)
    new = solver.solve_many(goal, HAND, n=3, attempts=20, seed=4)
    with pytest.warns(DeprecationWarning, match="num_seeds.*attempts"):
        old = solver.solve_many(goal, HAND, n=3, num_seeds=20, seed=4)
    np.testing.assert_array_equal(old.q, new.q)
    assert old.attempts == new.attempts == 20
    with pytest.raises(InvalidInputError, match="attempts"):
        solver.solve_many(goal, HAND, attempts=5, num_seeds=5)
    with pytest.raises(InvalidInputError, match="attempts must be"):
        solver.solve_many(goal, HAND, attempts=0)


def test_solve_many_toward_seed_offers_the_nearest_configuration_of_each_branch(solver: IKSolver,
                                                                                franka_kinematics: Kinematics):
    """With toward_seed the solutions include, for each branch, the configuration of its
    self-motion nearest seed_q: there the step towards seed_q has no component left that keeps
    the hand on the goal (it is orthogonal to the self-motion), unless a joint is at its limit
    or the arm is near a singularity (where the self-motion's tangent is not J's null space)."""
    k = franka_kinematics
    rng = np.random.default_rng(5)
    closer = checked = 0
    for q_true in random_configs(k, 12, seed=71):
        goal = k.fk(q_true, HAND)
        seed_q = np.clip(q_true + rng.normal(0.0, 0.8, k.dof), k.lower, k.upper)
        plain = solver.solve_many(goal, HAND, n=8, seed_q=seed_q, seed=3)
        slid = solver.solve_many(goal, HAND, n=8, seed_q=seed_q, seed=3, toward_seed=True)
        assert slid.success and len(slid) >= len(plain) > 0
        for q in slid:
            assert_reaches(k, q, goal)
        d_plain = np.linalg.norm(plain.q - seed_q, axis=1).min()
        d_slid = np.linalg.norm(slid.q - seed_q, axis=1)
        assert d_slid.min() <= d_plain + 1e-9 and np.all(np.diff(d_slid) >= 0)
        closer += d_slid.min() < d_plain - 1e-3
        q = slid.q[0]
        if np.any(np.minimum(q - k.lower, k.upper - q) < 1e-3):
            continue  # held by a limit: the nearest point of the branch lies on the boundary
        fid = k.model.getFrameId(HAND)
        k.frame_transform(q, fid)
        J = k.frame_jacobian(q, fid)
        if np.linalg.svd(J, compute_uv=False).min() < 0.05:
            continue  # near a singularity
        null = np.eye(k.dof) - np.linalg.pinv(J) @ J
        towards = seed_q - q
        assert np.linalg.norm(null @ towards) <= 0.02 * max(np.linalg.norm(towards), 1.0)
        checked += 1
    assert checked >= 6 and closer >= 6  # the plain solutions are rarely the nearest of their branch


def test_solve_many_toward_seed_is_checked_and_a_no_op_without_redundancy(solver: IKSolver,
                                                                            franka_kinematics: Kinematics):
    goal = franka_kinematics.fk(np.array([0.3, 0.2, -0.4, -2.0, 0.5, 2.0, 0.3]), HAND)
    for bad in (1, "yes", None):
        with pytest.raises(InvalidInputError, match="toward_seed must be True or False"):
            solver.solve_many(goal, HAND, toward_seed=bad)
    from manip.robot_config import load_robot_config

    ur5 = Kinematics(load_robot_config("ur5"))
    six = IKSolver(ur5, seed=0)
    tool = ur5.config.ee_link
    goal = ur5.fk(np.array([0.3, -1.2, 1.4, -1.0, -1.5, 0.4]), tool)
    a = six.solve_many(goal, tool, n=6, seed=2)
    b = six.solve_many(goal, tool, n=6, seed=2, toward_seed=True)
    assert len(a) >= 1
    np.testing.assert_array_equal(a.q, b.q)


# ---------------------------------------------------------------------- batch
def test_batch_solves_reachable_and_flags_unreachable(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    Q = random_configs(k, 150, seed=61)
    goals = k.fk(Q, HAND)
    goals = Pose.stack([goals, Pose(np.array([0.0, 0.0, 2.5]))])
    b = solver.solve_batch(goals, HAND)
    assert isinstance(b, BatchIKResult) and len(b) == 151
    assert b.q.shape == (151, k.dof)
    assert b.success[:150].all()
    assert not b.success[150] and b.status[150] is IKStatus.OUT_OF_REACH
    assert all(s is IKStatus.SUCCESS for s in b.status[:150])
    assert np.all(b.position_error[:150] <= POS_TOL) and np.all(b.rotation_error[:150] <= ROT_TOL)
    assert k.within_limits(b.q).all()
    # independent check of every claimed success, and the reported errors
    dp, dr = k.fk(b.q, HAND).distance(goals)
    np.testing.assert_allclose(b.position_error[:, 0], dp, atol=1e-9)   # (N, 1) as cuRobo's
    assert np.all(dp[:150] <= POS_TOL) and np.all(dr[:150] <= ROT_TOL)
    r0 = b[0]
    assert isinstance(r0, IKResult) and r0.success and r0.q.shape == (k.dof,)
    assert r0.message == "" and all(m == "" for m in b.message[:150])
    assert "reaches at most" in b.message[150] and b[150].message == b.message[150]
    assert b.success_rate == pytest.approx(150 / 151)


def test_batch_with_unreachable_in_ball_goal_and_validity(franka_kinematics: Kinematics):
    k = franka_kinematics
    s = IKSolver(k)
    Q = random_configs(k, 20, seed=71)
    Q[:, 0] = np.abs(Q[:, 0])
    goals = Pose.stack([k.fk(Q, HAND), Pose(np.array([0.0, 0.0, -0.4]))])
    b = s.solve_batch(goals, HAND, validity_fn=lambda X: X[:, 0] > 0)
    assert b.success[:20].all() and np.all(b.q[:20, 0] > 0)
    assert not b.success[20] and b.status[20] is IKStatus.NOT_CONVERGED
    assert b.attempts[20] == s.max_attempts
    assert k.within_limits(b.q[20])
    b2 = s.solve_batch(goals[:3], HAND, validity_fn=lambda X: np.zeros(len(X), dtype=bool))
    assert all(st is IKStatus.REJECTED_BY_VALIDITY for st in b2.status)


def test_batch_per_goal_seeds_and_determinism(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    Q = random_configs(k, 30, seed=81)
    goals = k.fk(Q, HAND)
    b = solver.solve_batch(goals, HAND, seed_q=Q)  # seeded at the answer: converged at once
    assert b.success.all() and np.all(b.attempts == 1)
    np.testing.assert_allclose(b.q, Q, atol=1e-9)
    c1 = solver.solve_batch(goals, HAND, seed=5)
    c2 = solver.solve_batch(goals, HAND, seed=5)
    np.testing.assert_array_equal(c1.q, c2.q)


# ---------------------------------------------------------------------- bad input
def test_bad_input_raises_manip_errors(solver: IKSolver, franka_kinematics: Kinematics):
    k = franka_kinematics
    goal = k.fk(k.config.default_joint_positions, HAND)
    batch = k.fk(random_configs(k, 3, seed=0), HAND)
    with pytest.raises(InvalidInputError, match="manip.Pose"):
        solver.solve((0.4, 0.0, 0.4), HAND)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="solve_batch"):
        solver.solve(batch, HAND)
    with pytest.raises(InvalidInputError, match="batched Pose"):
        solver.solve_batch(goal, HAND)
    with pytest.raises(InvalidInputError, match="non-finite"):
        solver.solve(goal, HAND, seed_q=np.array([0, 0, 0, np.nan, 0, 0, 0.0]))
    with pytest.raises(InvalidInputError, match="panda_joint7"):
        solver.solve(goal, HAND, seed_q=np.zeros(6))
    with pytest.raises(InvalidInputError, match=r"\(3, 7\)"):
        solver.solve_batch(batch, HAND, seed_q=np.zeros((2, 7)))
    with pytest.raises(UnknownNameError, match="panda_hand") as exc:
        solver.solve(goal, "panda_palm")
    assert isinstance(exc.value, ManipError) and "panda_link7" in str(exc.value)
    with pytest.raises(InvalidInputError, match="num_solutions"):
        solver.solve(goal, HAND, num_solutions=0)
    with pytest.raises(InvalidInputError, match="n must be"):
        solver.solve_many(goal, HAND, n=0)


@pytest.mark.parametrize(
    "kwargs", [{"position_tolerance": 0.0}, {"rotation_tolerance": -1.0}, {"max_attempts": 0}, {"max_iterations": 0}]
)
def test_bad_solver_parameters(franka_kinematics: Kinematics, kwargs: dict):
    with pytest.raises(InvalidInputError, match=next(iter(kwargs))):
        IKSolver(franka_kinematics, **kwargs)


def test_num_seeds_is_curobos_name_of_max_attempts(franka_kinematics: Kinematics):
    """cuRobo's `IKSolverConfig.load_from_robot_config(num_seeds=...)` (random starts per goal) is
    manip's `max_attempts`: the same solver, a DeprecationWarning naming manip's name."""
    k = franka_kinematics
    with pytest.warns(DeprecationWarning, match="num_seeds.*max_attempts"):
        old = IKSolver(k, num_seeds=3, seed=2)
    new = IKSolver(k, max_attempts=3, seed=2)
    assert old.max_attempts == new.max_attempts == 3
    assert IKSolver(k).max_attempts == 100  # the default is unchanged
    goal = k.fk(np.array([2.5, 1.5, -2.5, -0.5, 2.5, 3.5, -2.5]), HAND)  # far from the default: restarts
    a, b = old.solve(goal, HAND), new.solve(goal, HAND)
    assert a.attempts == b.attempts <= 3
    np.testing.assert_array_equal(a.q, b.q)
    with pytest.raises(InvalidInputError, match="max_attempts"):
        IKSolver(k, num_seeds=5, max_attempts=5)
    for bad in (0, -4, 2.5, True, "8"):
        with pytest.raises(InvalidInputError, match="num_seeds must be an integer >= 1"):
            IKSolver(k, num_seeds=bad)


def test_compiled_rotation_log_matches_pinocchio_up_to_pi():
    """The IK error's rotation part (compiled log3) is Pinocchio's log3, including the
    near-pi rotations where the axis comes from the quaternion instead of the skew part."""
    from manip.ik.kernels import _log3_into

    rng = np.random.default_rng(3)
    axes = rng.normal(size=(60, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    angles = np.concatenate([rng.uniform(0.0, np.pi, 30), np.pi - np.geomspace(1e-9, 2e-2, 20),
                             np.geomspace(1e-12, 1e-3, 10)])
    out = np.empty(3)
    for axis, angle in zip(axes, angles):
        E = pin.exp3(axis * angle)
        _log3_into(E, out)
        expected = pin.log3(E)
        # at pi, +axis and -axis are the same rotation
        if angle > np.pi - 1e-6 and np.dot(out, expected) < 0:
            expected = -expected
        np.testing.assert_allclose(out, expected, atol=1e-7)
    _log3_into(np.eye(3), out)
    assert np.all(out == 0.0)
