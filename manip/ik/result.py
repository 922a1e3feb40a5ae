"""What the IK solver returns: `IKStatus`, `IKResult`, `BatchIKResult` and `IKSolutions`."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from manip import curobo_names
from manip.errors import InvalidInputError
from manip.host_array import HostArray, host
from manip.status import Status, no_truth_value, truth_is_success

#: A validity check for candidate solutions: Q (K, dof) -> (K,) bool (True = acceptable).
ValidityFn = Callable[[np.ndarray], np.ndarray]

class IKStatus(Status):
    """Outcome of an IK query; `hint` says what it means and what to change."""

    SUCCESS = "success"
    NOT_CONVERGED = "not_converged"
    OUT_OF_REACH = "out_of_reach"
    REJECTED_BY_VALIDITY = "rejected_by_validity"
    TIME_LIMIT = "time_limit"

    @classmethod
    def _hints(cls) -> dict:
        return _HINTS


_HINTS = {
    IKStatus.SUCCESS: "a configuration within the joint limits reaches the goal within the tolerances",
    IKStatus.NOT_CONVERGED: (
        "no configuration within the joint limits reached the goal in max_attempts restarts: "
        "check that the pose is reachable (position and orientation), or raise max_attempts"
    ),
    IKStatus.OUT_OF_REACH: (
        "the goal position is farther from the arm's first joint than the arm can reach: "
        "move the goal closer to the robot (or the robot closer to the goal)"
    ),
    IKStatus.REJECTED_BY_VALIDITY: (
        "solutions were found but validity_fn rejected every one (e.g. all in collision): "
        "raise max_attempts, or relax the goal or the validity check"
    ),
    IKStatus.TIME_LIMIT: "time_limit ran out before a solution was found: raise time_limit",
}


def _freeze(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class IKResult:
    """Result of one IK query.

    Attributes:
        success: True when `q` reaches the goal within the tolerances and the joint limits, a
            (1, 1) bool `HostArray` as cuRobo's `IKResult.success` of `solve_single` (batch, seeds):
            `bool()`, `if`, `[0]`, `.item()` (a Python bool), `.cpu()` as on cuRobo's tensor.
        q: (dof,) the solution, or the best configuration found when `success` is False
            (always within the joint limits).
        position_error: distance [m] between the goal and the link's position at `q`, (1, 1) as
            cuRobo's (`float()`, `.item()` and `f"{...:.4f}"` read the number).
        rotation_error: angle [rad] between the goal and the link's orientation at `q`, (1, 1).
        solution: (1, 1, dof) read-only `q` as cuRobo's `IKResult.solution` (batch, seeds, dof).
        status: why it succeeded or failed (see `IKStatus.hint`).
        iterations: solver iterations over all attempts.
        solve_time: wall time [s].
        attempts: attempts made (the first from `seed_q`, then random restarts).
        message: a one-line detail of this call's failure ("" on success).
    """

    __bool__ = truth_is_success   # `if result:` tests `.success` (not the object)

    success: bool
    q: np.ndarray
    position_error: float
    rotation_error: float
    status: IKStatus
    iterations: int
    solve_time: float
    attempts: int
    message: str = ""

    def __post_init__(self):
        # cuRobo's IKResult holds tensors: `result.success.item()`, `.cpu()`, `.tolist()` run as written
        object.__setattr__(self, "success", host(bool(self.success), shape=(1, 1)))
        object.__setattr__(self, "position_error", host(float(self.position_error), np.float64, (1, 1)))
        object.__setattr__(self, "rotation_error", host(float(self.rotation_error), np.float64, (1, 1)))

    @property
    def solution(self) -> HostArray:
        """`q` as cuRobo's (batch, seeds, dof) = (1, 1, dof) `solution` (`solution[success]` is (1, dof))."""
        return host(self.q, shape=(1, 1, -1))

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's (solution, js_solution, ...) say where manip has them
        if name.startswith("_"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.IK_RESULT, name)


@dataclass(frozen=True)
class BatchIKResult:
    """Result of a batched IK query (N goals). Index it to get one goal's `IKResult`.

    Attributes:
        success: (N, 1) bool, as cuRobo's `solve_batch` (batch, return_seeds = 1): a `HostArray`
            (`.cpu().numpy()` as cuRobo's tensor; so are the errors and `solution`).
            `solution[success]` (cuRobo's) and `q[success[:, 0]]` are the (K, dof) solved rows;
            `solved` is the same mask as (N,).
        q: (N, dof) solutions (the best configuration found where `success` is False).
        position_error: (N, 1) [m].
        rotation_error: (N, 1) [rad].
        status: N `IKStatus` values.
        iterations: (N,) solver iterations spent on each goal.
        attempts: (N,) attempts made for each goal.
        solve_time: wall time [s] of the whole batch.
        message: N one-line details of the failures ("" where solved).
    """

    __bool__ = no_truth_value   # one success per item: `.success.all()` / `.any()`

    success: np.ndarray
    q: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    status: tuple[IKStatus, ...]
    iterations: np.ndarray
    attempts: np.ndarray
    solve_time: float
    message: tuple[str, ...] = ()

    def __post_init__(self):
        # cuRobo's batch results hold (batch, seeds) tensors: `result.success.cpu().numpy()` runs as
        # written; (N,) or (N, 1) arrays are accepted, (N, 1) kept
        n = np.shape(self.q)[0]
        for name in ("success", "position_error", "rotation_error"):
            value = np.asarray(getattr(self, name))
            if value.shape not in ((n,), (n, 1)):
                raise InvalidInputError(f"BatchIKResult.{name} must be (N,) or (N, 1) with N = {n} (q's rows); "
                                        f"got shape {value.shape}")
            object.__setattr__(self, name, host(value, shape=(n, 1)))

    @property
    def solved(self) -> HostArray:
        """(N,) bool: `success` as one flag per goal (`q[solved]` is the (K, dof) solved rows)."""
        return host(self.success, shape=(-1,))

    @property
    def solution(self) -> HostArray:
        """(N, 1, dof) `q` as cuRobo's `solution` (batch, seeds, dof): `solution[success]` is (K, dof)."""
        return host(self.q, shape=(len(self), 1, np.shape(self.q)[1]))

    def __len__(self) -> int:
        return self.q.shape[0]

    def __getitem__(self, i: int) -> IKResult:
        return IKResult(
            success=bool(self.success[i, 0]),
            q=self.q[i],
            position_error=float(self.position_error[i, 0]),
            rotation_error=float(self.rotation_error[i, 0]),
            status=self.status[i],
            iterations=int(self.iterations[i]),
            solve_time=self.solve_time,
            attempts=int(self.attempts[i]),
            message=self.message[i] if self.message else "",
        )

    @property
    def success_rate(self) -> float:
        """Fraction of goals solved."""
        return float(np.mean(self.success)) if len(self) else 0.0

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's (solution, js_solution, ...) say where manip has them
        if name.startswith("_"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.IK_RESULT, name)


@dataclass(frozen=True, eq=False)
class IKSolutions:
    """Several distinct solutions of one goal (`IKSolver.solve_many`), nearest `seed_q` first.

    Behaves as the sequence of its rows: `len(sols)`, `for q in sols`, `sols[i]` and
    `np.asarray(sols)` all read `q`.

    Attributes:
        q: (K, dof) read-only solutions, K <= n (K = 0 when none was found).
        status: SUCCESS when K >= 1, else why none was found (see `IKStatus.hint`).
        message: a one-line detail of the failure ("" when K >= 1).
        attempts: attempts made (the first from `seed_q`, the others from random starts).
    """

    __bool__ = truth_is_success   # `if result:` tests `.success` (not the object)

    q: np.ndarray
    status: IKStatus
    message: str = ""
    attempts: int = 0

    @property
    def success(self) -> HostArray:
        """True when at least one solution was found (a (1,) bool array: `.item()` is a bool)."""
        return host(self.status is IKStatus.SUCCESS, shape=(1,))

    def __len__(self) -> int:
        return self.q.shape[0]

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter(self.q)

    def __getitem__(self, i):
        return self.q[i]

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        return np.array(self.q, dtype=dtype, copy=True) if copy else np.asarray(self.q, dtype=dtype)
