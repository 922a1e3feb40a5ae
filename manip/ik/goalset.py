"""Goal-set IK, cuRobo's `IKSolver.solve_goalset` / `solve_batch_goalset`: reach one pose of a
set (e.g. several grasps of an object) and say which (`goalset_index`).

Every pose of every set is solved (one `IKSolver.solve_batch` call over B x G goals, each from
the problem's `seed_q`); each problem keeps, among its solved poses, the solution nearest its
`seed_q` (cuRobo keeps its lowest-cost seed: pose error plus a pull to the retract
configuration), or, when none was solved, its least wrong pose (position and rotation errors
over their tolerances).

Shapes, as cuRobo's (`return_seeds` = 1): cuRobo's goal set is one Pose of (B, G, 3) positions;
manip's Pose holds (N, 3), so a goal set is a batched Pose of G poses and a batch of goal sets is
a sequence of B such Poses (or one Pose of B x G poses, set by set, with `n_goalset=G`). The
result's `success`, errors and `goalset_index` are (B, 1), `solution` (B, 1, dof), `q` (B, dof).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from manip.errors import InvalidInputError
from manip.host_array import HostArray, host
from manip.ik.result import BatchIKResult, _freeze
from manip.pose import Pose


@dataclass(frozen=True)
class GoalsetIKResult(BatchIKResult):
    """`BatchIKResult` of B goal sets (one row per set) with `goalset_index`.

    Attributes:
        goalset_index: (B, 1) int, the pose of each set that `q` reaches (the least wrong pose
            where `success` is False), as cuRobo's `IKResult.goalset_index`.
        goal_success: (B, G) bool, which poses of each set were solved.
        (the others as `BatchIKResult`, one row per goal set; `iterations` and `attempts` summed
        over the set's poses.)
    """

    goalset_index: np.ndarray = None
    goal_success: np.ndarray = None

    def __post_init__(self):
        super().__post_init__()
        n = len(self)
        index = np.asarray(self.goalset_index)
        if index.shape not in ((n,), (n, 1)) or not np.issubdtype(index.dtype, np.integer):
            raise InvalidInputError(f"GoalsetIKResult.goalset_index must be (N,) or (N, 1) integers with N = {n}; "
                                    f"got shape {index.shape}, dtype {index.dtype}")
        object.__setattr__(self, "goalset_index", host(index, shape=(n, 1)))
        object.__setattr__(self, "goal_success", host(np.asarray(self.goal_success, dtype=bool)))

    @property
    def goal_index(self) -> HostArray:
        """(B,) int: `goalset_index` as one index per set (manip's `PlanResult.goal_index` name)."""
        return host(self.goalset_index, shape=(-1,))


def _goal_set(goals: object, what: str) -> Pose:
    if not isinstance(goals, Pose) or not goals.is_batch or len(goals) == 0:
        raise InvalidInputError(f"{what} must be a batched manip.Pose of G >= 1 poses (Pose.stack([...]) or "
                                f"Pose(positions (G, 3), quaternions (G, 4))); got {type(goals).__name__}"
                                + (f" of {len(goals)} poses" if isinstance(goals, Pose) and goals.is_batch else ""))
    return goals


def _goal_sets(goal_sets: object, n_goalset: int | None) -> tuple[Pose, int, int]:
    """The B x G poses, set by set, as one batched Pose, with B and G."""
    if isinstance(goal_sets, Pose):
        goals = _goal_set(goal_sets, "goal_sets")
        if n_goalset is None:
            raise InvalidInputError("one batched Pose of several goal sets needs n_goalset=G (the poses per set, "
                                    "set by set); or pass a list of B batched Poses of G poses each")
        if isinstance(n_goalset, bool) or not isinstance(n_goalset, (int, np.integer)) or n_goalset < 1 \
                or len(goals) % n_goalset:
            raise InvalidInputError(f"n_goalset must be a whole number >= 1 dividing the {len(goals)} poses; "
                                    f"got {n_goalset!r}")
        return goals, len(goals) // int(n_goalset), int(n_goalset)
    if n_goalset is not None:
        raise InvalidInputError("n_goalset is for one batched Pose of B x G poses; a list of goal sets gives G")
    if not isinstance(goal_sets, Sequence) or not goal_sets:
        raise InvalidInputError(f"goal_sets must be a non-empty list of B batched Poses of G poses each (or one "
                                f"Pose of B x G poses with n_goalset=G); got {type(goal_sets).__name__}")
    sets = [_goal_set(g, f"goal_sets[{i}]") for i, g in enumerate(goal_sets)]
    sizes = {len(g) for g in sets}
    if len(sizes) != 1:
        raise InvalidInputError(f"every goal set must have the same number of poses G (as cuRobo's (B, G) goal "
                                f"Pose); got {[len(g) for g in sets]}")
    goals = Pose(np.concatenate([g.position for g in sets]), np.concatenate([g.quaternion for g in sets]))
    return goals, len(sets), sizes.pop()


def _seeds(solver, seed_q, b: int, g: int) -> np.ndarray | None:
    """Each problem's seed repeated for its G poses ((B x G, dof)), or None (the default)."""
    if seed_q is None:
        return None
    q = np.asarray(seed_q, dtype=float)
    dof = solver.kinematics.dof
    if q.shape == (dof,):
        return q
    if q.shape != (b, dof):
        raise InvalidInputError(f"seed_q must be (dof,) = ({dof},) or one row per goal set ({b}, {dof}); got shape "
                                f"{q.shape}")
    return np.repeat(q, g, axis=0)


def solve_batch_goalset(solver, goal_sets, link: str | None = None, seed_q=None, *, n_goalset: int | None = None,
                        **options) -> GoalsetIKResult:
    """B goal sets at once: for each, one pose of its G reached (see the module).

    Args:
        solver: the `IKSolver`.
        goal_sets: B batched Poses of G poses each (or one Pose of B x G poses with `n_goalset`).
        link: frame to place (default: the robot's `ee_link`).
        seed_q: (dof,) or (B, dof) start of each set's first attempts and the reference for
            "nearest" (default: the default configuration).
        n_goalset: G, when `goal_sets` is one Pose.
        **options: `IKSolver.solve_batch`'s (validity_fn, seed, time_limit, max_attempts).

    Returns:
        GoalsetIKResult: one row per set; `goalset_index` (B, 1) the pose reached.

    Raises:
        InvalidInputError: bad goal sets, seed_q or options; UnknownNameError: unknown link.
    """
    goals, b, g = _goal_sets(goal_sets, n_goalset)
    seeds = _seeds(solver, seed_q, b, g)
    res = solver.solve_batch(goals, link, seeds, **options)
    ok = np.asarray(res.success).reshape(b, g)
    ep = np.asarray(res.position_error).reshape(b, g)
    er = np.asarray(res.rotation_error).reshape(b, g)
    q = np.asarray(res.q).reshape(b, g, -1)
    ref = np.broadcast_to(solver.kinematics.config.default_joint_positions if seed_q is None else np.asarray(seed_q, dtype=float),
                          (b, q.shape[2]))
    distance = np.linalg.norm(q - ref[:, None], axis=2)
    wrong = ep / solver.position_tolerance + er / solver.rotation_tolerance
    pick = np.where(ok.any(axis=1), np.argmin(np.where(ok, distance, np.inf), axis=1), np.argmin(wrong, axis=1))
    rows = np.arange(b)
    flat = rows * g + pick
    message = tuple("" if ok[i, pick[i]] else
                    f"no pose of the goal set ({g}) was reached; the least wrong, pose {pick[i]}: {res.message[flat[i]]}"
                    for i in rows)
    return GoalsetIKResult(
        success=_freeze(ok[rows, pick].copy()), q=_freeze(q[rows, pick].copy()),
        position_error=_freeze(ep[rows, pick].copy()), rotation_error=_freeze(er[rows, pick].copy()),
        status=tuple(res.status[i] for i in flat),
        iterations=_freeze(np.asarray(res.iterations).reshape(b, g).sum(axis=1)),
        attempts=_freeze(np.asarray(res.attempts).reshape(b, g).sum(axis=1)),
        solve_time=res.solve_time, message=message, goalset_index=pick.astype(np.int64), goal_success=ok,
    )


def solve_goalset(solver, goals: Pose, link: str | None = None, seed_q=None, **options) -> GoalsetIKResult:
    """One goal set: reach one pose of `goals` (a batched Pose of G poses); see `solve_batch_goalset`.

    Returns:
        GoalsetIKResult of one row: `success` (1, 1), `solution` (1, 1, dof), `goalset_index`
        (1, 1) as cuRobo's; `q[0]` is the (dof,) solution.
    """
    goals = _goal_set(goals, "goals")
    if seed_q is not None and np.shape(seed_q) != (solver.kinematics.dof,):
        raise InvalidInputError(f"seed_q must be (dof,) = ({solver.kinematics.dof},) for one goal set; got shape "
                                f"{np.shape(seed_q)}")
    return solve_batch_goalset(solver, [goals], link, seed_q, **options)
