"""Inverse kinematics: damped least squares (Levenberg-Marquardt) with joint limits and restarts.

`IKSolver.solve` finds one configuration for one goal, each attempt one compiled (numba)
descent (`_lm_lanes`, on the same kinematics tables as `Kinematics.joint_transforms`);
`IKSolver.solve_batch` iterates all goals of a batched Pose at once in NumPy
(`Kinematics.frame_jacobians`), re-seeding only the ones that have not converged;
`IKSolver.solve_many` runs all its attempts in one compiled call and returns several distinct
solutions of one goal, nearest the seed first.

The iteration (for one goal) is

    e  = [p_goal - p(q);  log(R_goal R(q)^T)]                 (6,), world-aligned
    dq = J^T (J J^T + lambda I)^-1 e,   lambda = damping * |e|^2 + 1e-9
    q  <- clip(q + dq, lower, upper)

with J the (6, 7) world-aligned frame Jacobian. The damping that grows with the squared
error is Sugihara's choice (T. Sugihara, "Solvability-unconcerned inverse kinematics by the
Levenberg-Marquardt method", IEEE T-RO 2011): long, careful steps far from the goal,
Gauss-Newton (quadratic) convergence close to it. Joints sitting at a limit whose step
points outwards are removed from J for that step (their columns zeroed), so the other
joints make up for them instead of the step being lost to the clip. The clip keeps every
iterate within the joint limits, so the answer never needs clamping afterwards. The step
is scaled so no joint moves more than `max_step`. An attempt stops when the error is below
the internal tolerance (1e-5 m / 1e-5 rad, much tighter than the success tolerances), when
it has not improved for a few iterations, or after `max_iterations`; the next attempt
starts from a uniformly random configuration within the limits.

The batch solver runs one "lane" per attempt; once most goals are solved, the remaining
ones get several lanes at once (parallel random restarts), so a few hard goals cost a few
small NumPy iterations instead of many sequential attempts.

mink (a QP per step) was measured for comparison in benchmarks/kinematics.py: the same
success rate on reachable poses, several times the median time per solve (BENCHMARKS.md).

Every claimed success is re-checked with an independent forward kinematics (Pinocchio's
full model, fingers included, a different code path from the solver's) and against the
joint limits; a solution that fails the check is discarded, never reported.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from typing import NamedTuple

import numpy as np
import pinocchio as pin
from numba import njit

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.kinematics import Kinematics, chain_frames, frame_jacobian_into
from manip.pose import Pose

logger = logging.getLogger(__name__)

#: A validity check for candidate solutions: Q (K, dof) -> (K,) bool (True = acceptable).
ValidityFn = Callable[[np.ndarray], np.ndarray]

_INTERNAL_TOLERANCE = 1e-5  # [m] and [rad]: an attempt converges below this
_STALL_ITERATIONS = 5       # an attempt stops when its error has not improved for this many iterations
_MIN_DAMPING = 1e-9
_CHOLESKY_MIN_BATCH = 256  # batches at least this large use the vectorised Cholesky solve
_MIN_LANES = 256            # the batch solver adds parallel restarts for unsolved goals below this many lanes


class IKStatus(Enum):
    """Outcome of an IK query. `hint` says what to change when it is not SUCCESS."""

    SUCCESS = "SUCCESS"
    NOT_CONVERGED = "NOT_CONVERGED"
    OUT_OF_REACH = "OUT_OF_REACH"
    REJECTED_BY_VALIDITY = "REJECTED_BY_VALIDITY"
    TIME_LIMIT = "TIME_LIMIT"

    @property
    def hint(self) -> str:
        """What the status means and what to change."""
        return _HINTS[self]


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


@dataclass(frozen=True)
class IKResult:
    """Result of one IK query.

    Attributes:
        success: True when `q` reaches the goal within the tolerances and the joint limits.
        q: (dof,) the solution, or the best configuration found when `success` is False
            (always within the joint limits).
        position_error: distance [m] between the goal and the link's position at `q`.
        rotation_error: angle [rad] between the goal and the link's orientation at `q`.
        status: why it succeeded or failed (see `IKStatus.hint`).
        iterations: solver iterations over all attempts.
        solve_time: wall time [s].
        attempts: attempts made (the first from the seed, then random restarts).
    """

    success: bool
    q: np.ndarray
    position_error: float
    rotation_error: float
    status: IKStatus
    iterations: int
    solve_time: float
    attempts: int


@dataclass(frozen=True)
class BatchIKResult:
    """Result of a batched IK query (N goals). Index it to get one goal's `IKResult`.

    Attributes:
        success: (N,) bool.
        q: (N, dof) solutions (the best configuration found where `success` is False).
        position_error: (N,) [m].
        rotation_error: (N,) [rad].
        status: N `IKStatus` values.
        iterations: (N,) solver iterations spent on each goal.
        attempts: (N,) attempts made for each goal.
        solve_time: wall time [s] of the whole batch.
    """

    success: np.ndarray
    q: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    status: tuple[IKStatus, ...]
    iterations: np.ndarray
    attempts: np.ndarray
    solve_time: float

    def __len__(self) -> int:
        return self.q.shape[0]

    def __getitem__(self, i: int) -> IKResult:
        return IKResult(
            success=bool(self.success[i]),
            q=self.q[i],
            position_error=float(self.position_error[i]),
            rotation_error=float(self.rotation_error[i]),
            status=self.status[i],
            iterations=int(self.iterations[i]),
            solve_time=self.solve_time,
            attempts=int(self.attempts[i]),
        )

    @property
    def success_rate(self) -> float:
        """Fraction of goals solved."""
        return float(np.mean(self.success)) if len(self) else 0.0


def _log3_batch(E: np.ndarray) -> np.ndarray:
    """Rotation vectors (N, 3) of rotation matrices E (N, 3, 3), robust up to pi.

    theta = arccos((tr E - 1) / 2) and the axis from the skew part, E - E^T = 2 sin(theta) [axis]x;
    rotations near pi (where sin(theta) vanishes) go through the quaternion instead.
    """
    v = 0.5 * np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0], E[:, 1, 0] - E[:, 0, 1]], axis=1)
    cos = np.clip(0.5 * (E[:, 0, 0] + E[:, 1, 1] + E[:, 2, 2] - 1.0), -1.0, 1.0)
    theta = np.arccos(cos)
    sin = np.sqrt(np.maximum(1.0 - cos * cos, 0.0))
    # theta / sin(theta) -> 1 + theta^2 / 6 as theta -> 0
    factor = np.where(theta < 1e-4, 1.0 + theta * theta / 6.0, theta / np.maximum(sin, 1e-300))
    out = v * factor[:, None]
    near_pi = theta > np.pi - 1e-2
    if near_pi.any():
        qe = quat.from_matrix(E[near_pi])  # w >= 0
        s = np.linalg.norm(qe[:, 1:], axis=1)
        out[near_pi] = qe[:, 1:] * (2.0 * np.arctan2(s, qe[:, 0]) / s)[:, None]
    return out


@njit(cache=True, nogil=True)
def _log3_into(E, out):
    """Rotation vector out (3,) of the rotation matrix E (3, 3), robust up to pi (see `_log3_batch`)."""
    cos = min(max(0.5 * (E[0, 0] + E[1, 1] + E[2, 2] - 1.0), -1.0), 1.0)
    theta = math.acos(cos)
    if theta > math.pi - 1e-2:  # through the quaternion (w >= 0)
        tr = E[0, 0] + E[1, 1] + E[2, 2]
        if tr > 0.0:
            s = math.sqrt(tr + 1.0) * 2.0
            w, x, y, z = 0.25 * s, (E[2, 1] - E[1, 2]) / s, (E[0, 2] - E[2, 0]) / s, (E[1, 0] - E[0, 1]) / s
        elif E[0, 0] > E[1, 1] and E[0, 0] > E[2, 2]:
            s = math.sqrt(1.0 + E[0, 0] - E[1, 1] - E[2, 2]) * 2.0
            w, x, y, z = (E[2, 1] - E[1, 2]) / s, 0.25 * s, (E[0, 1] + E[1, 0]) / s, (E[0, 2] + E[2, 0]) / s
        elif E[1, 1] > E[2, 2]:
            s = math.sqrt(1.0 + E[1, 1] - E[0, 0] - E[2, 2]) * 2.0
            w, x, y, z = (E[0, 2] - E[2, 0]) / s, (E[0, 1] + E[1, 0]) / s, 0.25 * s, (E[1, 2] + E[2, 1]) / s
        else:
            s = math.sqrt(1.0 + E[2, 2] - E[0, 0] - E[1, 1]) * 2.0
            w, x, y, z = (E[1, 0] - E[0, 1]) / s, (E[0, 2] + E[2, 0]) / s, (E[1, 2] + E[2, 1]) / s, 0.25 * s
        if w < 0.0:
            w, x, y, z = -w, -x, -y, -z
        sn = math.sqrt(x * x + y * y + z * z)
        f = 2.0 * math.atan2(sn, w) / sn
        out[0], out[1], out[2] = x * f, y * f, z * f
        return
    sin = math.sqrt(max(1.0 - cos * cos, 0.0))
    f = 0.5 * (1.0 + theta * theta / 6.0 if theta < 1e-4 else theta / sin)
    out[0] = f * (E[2, 1] - E[1, 2])
    out[1] = f * (E[0, 2] - E[2, 0])
    out[2] = f * (E[1, 0] - E[0, 1])


@njit(cache=True, nogil=True)
def _dls_step(Jac, e, lam, dq):
    """dq = J^T (J J^T + lam I)^-1 e (damped least squares; Cholesky of the 6x6 matrix)."""
    m, n = Jac.shape
    A = np.empty((m, m))
    for r in range(m):
        for c in range(r + 1):
            acc = 0.0
            for k in range(n):
                acc += Jac[r, k] * Jac[c, k]
            A[r, c] = acc
        A[r, r] += lam
    L = np.zeros((m, m))
    for j in range(m):
        d = A[j, j]
        for k in range(j):
            d -= L[j, k] * L[j, k]
        L[j, j] = math.sqrt(d)
        for i in range(j + 1, m):
            acc = A[i, j]
            for k in range(j):
                acc -= L[i, k] * L[j, k]
            L[i, j] = acc / L[j, j]
    y = np.empty(m)
    for i in range(m):
        acc = e[i]
        for k in range(i):
            acc -= L[i, k] * y[k]
        y[i] = acc / L[i, i]
    for i in range(m - 1, -1, -1):
        acc = y[i]
        for k in range(i + 1, m):
            acc -= L[k, i] * y[k]
        y[i] = acc / L[i, i]
    for k in range(n):
        acc = 0.0
        for r in range(m):
            acc += Jac[r, k] * y[r]
        dq[k] = acc


@njit(cache=True, nogil=True)
def _lm_lanes(Q0, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, R_goal, p_goal, lower, upper,
              tol_p, tol_r, damping, min_damping, max_step, max_iterations, stall):
    """One damped-least-squares descent from each row of Q0 (K, dof) to one frame pose.

    Stops at convergence (tol_p [m], tol_r [rad]), after `max_iterations`, or when the error
    has not improved by 2 % for `stall` iterations. Joints at a limit that the step would push
    further take no part in it; steps are scaled to at most `max_step` [rad] and kept within
    the limits. Returns (Q (K, dof), position errors (K,), rotation errors (K,), iterations (K,)).
    """
    K, dof = Q0.shape
    J = table.shape[0]
    R = np.empty((J + 1, 3, 3))
    p = np.empty((J + 1, 3))
    Rf = np.empty((3, 3))
    pf = np.empty(3)
    E = np.empty((3, 3))
    Jac = np.empty((6, dof))
    e = np.empty(6)
    w = np.empty(3)
    dq = np.empty(dof)
    Q = Q0.copy()
    ep_out = np.empty(K)
    er_out = np.empty(K)
    it_out = np.zeros(K, dtype=np.int64)
    for k in range(K):
        q = Q[k]
        best = np.inf
        best_it = 0
        it = 0
        while True:
            chain_frames(q, q_index, parent, table, R, p)
            frame_jacobian_into(R, p, chain, axes, revolute, q_index, f_joint, f_R, f_p, Rf, pf, Jac)
            for r in range(3):
                e[r] = p_goal[r] - pf[r]
                for c in range(3):  # R_goal Rf^T
                    E[r, c] = R_goal[r, 0] * Rf[c, 0] + R_goal[r, 1] * Rf[c, 1] + R_goal[r, 2] * Rf[c, 2]
            _log3_into(E, w)
            e[3], e[4], e[5] = w[0], w[1], w[2]
            ep = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
            er = math.sqrt(e[3] * e[3] + e[4] * e[4] + e[5] * e[5])
            if (ep <= tol_p and er <= tol_r) or it >= max_iterations:
                break
            err2 = ep * ep + er * er
            if err2 < best * 0.98:
                best = err2
                best_it = it
            elif it - best_it >= stall:
                break
            lam = damping * err2 + min_damping
            _dls_step(Jac, e, lam, dq)
            blocked = False
            for i in range(dof):
                if (q[i] <= lower[i] and dq[i] < 0.0) or (q[i] >= upper[i] and dq[i] > 0.0):
                    blocked = True
                    for r in range(6):
                        Jac[r, i] = 0.0
            if blocked:  # joints held at a limit take no part in this step; the others compensate
                _dls_step(Jac, e, lam, dq)
            big = 0.0
            for i in range(dof):
                big = max(big, abs(dq[i]))
            scale = max_step / big if big > max_step else 1.0
            for i in range(dof):
                q[i] = min(max(q[i] + dq[i] * scale, lower[i]), upper[i])
            it += 1
        ep_out[k] = ep
        er_out[k] = er
        it_out[k] = it
    return Q, ep_out, er_out, it_out


class _Attempts(NamedTuple):
    found: list[np.ndarray]
    best_q: np.ndarray
    best_error: tuple[float, float]
    iterations: int
    attempts: int
    status: IKStatus


class _LazyRng:
    """A np.random.Generator created on first use (most solves never restart)."""

    def __init__(self, seed: int):
        self._seed = seed
        self._rng: np.random.Generator | None = None

    def uniform(self, low: np.ndarray, high: np.ndarray, size: tuple[int, ...] | None = None) -> np.ndarray:
        if self._rng is None:
            self._rng = np.random.default_rng(self._seed)
        return self._rng.uniform(low, high, size)


def _solve_spd(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """x (N, m, 1) solving A x = b for symmetric positive definite A (N, m, m), b (N, m, 1).

    Large batches use a Cholesky factorisation vectorised over the batch (each scalar
    operation runs on N values at once: ~3x faster than LAPACK per 6x6 matrix at N = 1000);
    rows it cannot factor (a pivot <= 0 from rounding) and small batches go to np.linalg.solve.
    """
    n_batch, m = A.shape[0], A.shape[1]
    if n_batch < _CHOLESKY_MIN_BATCH:
        return np.linalg.solve(A, b)
    M = np.ascontiguousarray(np.moveaxis(A, 0, -1))  # (m, m, N)
    L = np.zeros_like(M)
    with np.errstate(invalid="ignore", divide="ignore"):
        for j in range(m):
            d = M[j, j] - np.einsum("kn,kn->n", L[j, :j], L[j, :j]) if j else M[j, j].copy()
            L[j, j] = np.sqrt(d)
            if j + 1 < m:
                s = M[j + 1 :, j] - (np.einsum("ikn,kn->in", L[j + 1 :, :j], L[j, :j]) if j else 0.0)
                L[j + 1 :, j] = s / L[j, j]
        bt = b[:, :, 0].T
        y = np.empty((m, n_batch))
        for i in range(m):
            y[i] = (bt[i] - (np.einsum("kn,kn->n", L[i, :i], y[:i]) if i else 0.0)) / L[i, i]
        x = np.empty_like(y)
        for i in reversed(range(m)):
            x[i] = (y[i] - (np.einsum("kn,kn->n", L[i + 1 :, i], x[i + 1 :]) if i + 1 < m else 0.0)) / L[i, i]
    x = x.T[:, :, None]
    bad = ~np.all(np.isfinite(x[:, :, 0]), axis=1)
    if bad.any():
        x[bad] = np.linalg.solve(A[bad], b[bad])
    return x


def _freeze(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


class IKSolver:
    """Levenberg-Marquardt inverse kinematics with joint limits and random restarts.

    Goals are poses of a link (any frame of the model) in the robot's base frame.

    Args:
        kinematics: the robot's kinematics.
        position_tolerance: success threshold on the position error [m].
        rotation_tolerance: success threshold on the rotation error [rad].
        max_iterations: iterations per attempt.
        max_attempts: attempts per goal: the first from the seed, the others from uniformly
            random configurations within the joint limits.
        seed: seed of the random restarts; the same inputs and seed give the same answer.
        damping: Levenberg-Marquardt damping gain (lambda = damping * |e|^2).
        max_step: largest change of one joint per iteration [rad].

    Raises:
        InvalidInputError: if a parameter is not positive.
    """

    def __init__(
        self,
        kinematics: Kinematics,
        *,
        position_tolerance: float = 1e-3,
        rotation_tolerance: float = 0.01,
        max_iterations: int = 60,
        max_attempts: int = 100,
        seed: int = 0,
        damping: float = 0.03,
        max_step: float = 1.0,
    ):
        if not isinstance(kinematics, Kinematics):
            raise InvalidInputError(f"kinematics must be a manip.Kinematics, got {type(kinematics).__name__}")
        for name, value in (
            ("position_tolerance", position_tolerance),
            ("rotation_tolerance", rotation_tolerance),
            ("max_iterations", max_iterations),
            ("max_attempts", max_attempts),
            ("damping", damping),
            ("max_step", max_step),
        ):
            if not np.isfinite(value) or value <= 0:
                raise InvalidInputError(f"{name} must be a positive number, got {value}")
        self.kinematics = kinematics
        self.position_tolerance = float(position_tolerance)
        self.rotation_tolerance = float(rotation_tolerance)
        self.max_iterations = int(max_iterations)
        self.max_attempts = int(max_attempts)
        self.seed = int(seed)
        self.damping = float(damping)
        self.max_step = float(max_step)
        self._tol_p = min(_INTERNAL_TOLERANCE, self.position_tolerance)
        self._tol_r = min(_INTERNAL_TOLERANCE, self.rotation_tolerance)
        self._model = kinematics.model
        self._data = kinematics.model.createData()
        # Independent check: the full model (fingers at their planning positions), its own data.
        self._check_model = kinematics.full_model
        self._check_data = kinematics.full_model.createData()
        self._check_q_index = np.array(
            [kinematics.full_model.joints[kinematics.full_model.getJointId(j)].idx_q for j in kinematics.joint_names]
        )
        self._reach_cache: dict[int, tuple[np.ndarray, float]] = {}
        self._check_frame_ids: dict[int, int] = {}

    # ------------------------------------------------------------------ public API
    def solve(
        self,
        goal: Pose,
        link: str | None = None,
        seed_q: np.ndarray | None = None,
        *,
        validity_fn: ValidityFn | None = None,
        num_solutions: int = 1,
        seed: int | None = None,
        time_limit: float | None = None,
    ) -> IKResult:
        """Solve IK for one goal pose.

        Args:
            goal: single Pose of `link` in the base frame.
            link: frame to place at the goal (default: the robot's `ee_link`).
            seed_q: (dof,) start of the first attempt and the reference for "nearest"
                (default: the robot's default configuration). Clipped to the limits as a start.
            validity_fn: optional Q (K, dof) -> (K,) bool; solutions it rejects do not count.
            num_solutions: keep restarting until this many solutions are found (or
                `max_attempts` run out) and return the one nearest `seed_q`.
            seed: seed of the random restarts (default: the solver's).
            time_limit: optional wall-time budget [s].

        Returns:
            IKResult; `q` is the solution nearest `seed_q` among those found.

        Raises:
            InvalidInputError: goal not a single Pose, bad seed_q, bad num_solutions.
            UnknownNameError: unknown link (the message lists the frames).
        """
        t0 = time.perf_counter()
        self._check_goal(goal, batched=False)
        fid = self.kinematics.frame_id(link if link is not None else self.kinematics.config.ee_link)
        q_ref = self._check_seed(seed_q, None)
        if num_solutions < 1:
            raise InvalidInputError(f"num_solutions must be >= 1, got {num_solutions}")
        rng = _LazyRng(self.seed if seed is None else seed)
        R_goal = goal.rotation
        p_goal = goal.position

        if self._out_of_reach(fid, p_goal[None])[0]:
            ep, er = self._pose_error(q_ref, fid, R_goal, p_goal)
            return IKResult(False, _freeze(q_ref.copy()), ep, er, IKStatus.OUT_OF_REACH, 0, time.perf_counter() - t0, 0)

        lo, hi = self.kinematics.lower, self.kinematics.upper
        out = self._run_attempts(
            fid, R_goal, p_goal, np.clip(q_ref, lo, hi), self.max_attempts, rng, validity_fn, num_solutions, t0, time_limit
        )
        elapsed = time.perf_counter() - t0
        if out.found:
            sols = np.array(out.found)
            q = sols[np.argmin(np.linalg.norm(sols - q_ref, axis=1))]
            ep, er = self._pose_error(q, fid, R_goal, p_goal)
            return IKResult(True, _freeze(q.copy()), ep, er, IKStatus.SUCCESS, out.iterations, elapsed, out.attempts)
        logger.debug("IK failed (%s) after %d attempts", out.status.name, out.attempts)
        return IKResult(
            False, _freeze(out.best_q.copy()), out.best_error[0], out.best_error[1], out.status,
            out.iterations, elapsed, out.attempts,
        )

    def solve_batch(
        self,
        goals: Pose,
        link: str | None = None,
        seed_q: np.ndarray | None = None,
        *,
        validity_fn: ValidityFn | None = None,
        seed: int | None = None,
        time_limit: float | None = None,
    ) -> BatchIKResult:
        """Solve IK for every goal of a batched Pose at once (vectorised NumPy).

        Each goal's first attempt starts from `seed_q`; goals that stall or run out of
        iterations restart from random configurations until `max_attempts`. The first
        verified solution of each goal is returned (use `solve` with `num_solutions` or
        `solve_many` for the nearest of several).

        Args:
            goals: batched Pose (N goals) of `link` in the base frame.
            link: frame to place at the goals (default: the robot's `ee_link`).
            seed_q: (dof,) or (N, dof) starts of the first attempts (default: the default
                configuration).
            validity_fn: optional Q (K, dof) -> (K,) bool; rejected solutions restart.
            seed: seed of the random restarts (default: the solver's).
            time_limit: optional wall-time budget [s] for the whole batch.

        Returns:
            BatchIKResult with (N,) arrays.

        Raises:
            InvalidInputError: goals not a batched Pose, bad seed_q.
            UnknownNameError: unknown link.
        """
        t0 = time.perf_counter()
        self._check_goal(goals, batched=True)
        fid = self.kinematics.frame_id(link if link is not None else self.kinematics.config.ee_link)
        n = len(goals)
        q_ref = self._check_seed(seed_q, n)
        rng = np.random.default_rng(self.seed if seed is None else seed)
        out = self._batch_core(
            goals.rotation, goals.position, fid, np.broadcast_to(q_ref, (n, self.kinematics.dof)),
            rng, validity_fn, self.max_attempts, t0, time_limit,
        )
        q, success, ep, er, iters, attempts, status = out
        return BatchIKResult(
            success=_freeze(success), q=_freeze(q), position_error=_freeze(ep), rotation_error=_freeze(er),
            status=tuple(status), iterations=_freeze(iters), attempts=_freeze(attempts),
            solve_time=time.perf_counter() - t0,
        )

    def solve_many(
        self,
        goal: Pose,
        link: str | None = None,
        n: int = 8,
        seed_q: np.ndarray | None = None,
        *,
        validity_fn: ValidityFn | None = None,
        num_seeds: int | None = None,
        min_distance: float = 0.05,
        seed: int | None = None,
    ) -> np.ndarray:
        """Several distinct solutions of one goal, nearest `seed_q` first.

        Runs `num_seeds` attempts (the first from `seed_q`, the others from random
        configurations) and keeps, in attempt order, the verified solutions that
        `validity_fn` accepts, dropping near-duplicates, up to `n`.

        Args:
            goal: single Pose of `link` in the base frame.
            link: frame to place at the goal (default: the robot's `ee_link`).
            n: largest number of solutions to return.
            seed_q: (dof,) reference configuration (default: the default configuration).
            validity_fn: optional Q (K, dof) -> (K,) bool filter (e.g. collision-free).
            num_seeds: most attempts made (default max(4 n, 16)).
            min_distance: two solutions closer than this [rad, max over joints] count as one.
            seed: seed of the random starts (default: the solver's).

        Returns:
            (K, dof) solutions, K <= n (K = 0 when none was found), sorted by Euclidean
            joint-space distance to `seed_q`.

        Raises:
            InvalidInputError: goal not a single Pose, bad seed_q, n or num_seeds < 1.
            UnknownNameError: unknown link.
        """
        self._check_goal(goal, batched=False)
        fid = self.kinematics.frame_id(link if link is not None else self.kinematics.config.ee_link)
        q_ref = self._check_seed(seed_q, None)
        if n < 1:
            raise InvalidInputError(f"n must be >= 1, got {n}")
        m = max(4 * n, 16) if num_seeds is None else int(num_seeds)
        if m < 1:
            raise InvalidInputError(f"num_seeds must be >= 1, got {num_seeds}")
        rng = _LazyRng(self.seed if seed is None else seed)
        k = self.kinematics
        if self._out_of_reach(fid, goal.position[None])[0]:
            return np.empty((0, k.dof))
        R_goal, p_goal = goal.rotation, goal.position
        # every attempt at once (one compiled call), then the filters in attempt order
        Q0 = np.vstack([np.clip(q_ref, k.lower, k.upper)[None], rng.uniform(k.lower, k.upper, (m - 1, k.dof))])
        Q, ep, er, _ = self._descend(Q0, fid, R_goal, p_goal)
        idx = np.flatnonzero((ep <= self.position_tolerance) & (er <= self.rotation_tolerance))
        if idx.size:
            idx = idx[self._verify_batch(Q[idx], fid, np.broadcast_to(R_goal, (idx.size, 3, 3)),
                                         np.broadcast_to(p_goal, (idx.size, 3)))]
        if idx.size and validity_fn is not None:
            idx = idx[np.asarray(validity_fn(Q[idx]), dtype=bool).reshape(-1)]
        kept: list[np.ndarray] = []
        for i in idx:
            if any(np.max(np.abs(Q[i] - other)) < min_distance for other in kept):
                continue
            kept.append(Q[i])
            if len(kept) == n:
                break
        sols = np.array(kept).reshape(-1, k.dof)
        return sols[np.argsort(np.linalg.norm(sols - q_ref, axis=1), kind="stable")]

    # ------------------------------------------------------------------ validation
    def _check_goal(self, goal: object, batched: bool) -> None:
        if not isinstance(goal, Pose):
            raise InvalidInputError(
                f"goal must be a manip.Pose (position [m], quaternion (w, x, y, z)); got {type(goal).__name__}"
            )
        if batched and not goal.is_batch:
            raise InvalidInputError("solve_batch needs a batched Pose (position (N, 3)); use solve for one goal")
        if not batched and goal.is_batch:
            raise InvalidInputError(
                f"solve needs a single Pose; got a batch of {len(goal)} (use solve_batch, or index the batch)"
            )

    def _check_seed(self, seed_q: np.ndarray | None, n: int | None) -> np.ndarray:
        k = self.kinematics
        if seed_q is None:
            return k.config.default_joint_positions.astype(float).copy()
        q = k.check_q(seed_q, "seed_q")
        if n is None and q.ndim != 1:
            raise InvalidInputError(f"seed_q must have shape ({k.dof},) for joints {list(k.joint_names)}; got {q.shape}")
        if n is not None and q.ndim == 2 and q.shape[0] != n:
            raise InvalidInputError(f"seed_q must have shape ({k.dof},) or ({n}, {k.dof}) for {n} goals; got {q.shape}")
        return q.copy()

    # ------------------------------------------------------------------ reach bound
    def _reach(self, fid: int) -> tuple[np.ndarray, float]:
        """(anchor (3,), radius [m]): the frame's origin always lies within the ball.

        The anchor is the origin of the first joint of the chain (fixed in the base frame);
        the radius sums the lengths of the fixed offsets after it (triangle inequality,
        rotations preserve lengths). Chains with prismatic joints get an infinite radius.
        """
        if fid not in self._reach_cache:
            model = self._model
            frame = model.frames[fid]
            radius = float(np.linalg.norm(frame.placement.translation))
            j = frame.parentJoint
            anchor = np.zeros(3)
            specs = self.kinematics._joints
            if j == 0:
                anchor, radius = frame.placement.translation.copy(), 0.0
            while j > 0:
                spec = specs[j - 1]
                if not spec.revolute:
                    radius = np.inf
                if spec.parent == 0:
                    anchor = spec.p_placement.copy()
                else:
                    radius += float(np.linalg.norm(spec.p_placement))
                j = spec.parent
            self._reach_cache[fid] = (anchor, radius)
        return self._reach_cache[fid]

    def _out_of_reach(self, fid: int, p_goal: np.ndarray) -> np.ndarray:
        anchor, radius = self._reach(fid)
        return np.linalg.norm(p_goal - anchor, axis=-1) > radius + self.position_tolerance

    # ------------------------------------------------------------------ single solve
    def _run_attempts(
        self,
        fid: int,
        R_goal: np.ndarray,
        p_goal: np.ndarray,
        q_first: np.ndarray,
        max_attempts: int,
        rng: _LazyRng | np.random.Generator,
        validity_fn: ValidityFn | None,
        num_solutions: int,
        t0: float,
        time_limit: float | None,
    ) -> _Attempts:
        """Attempts from q_first, then from random configurations, until enough solutions."""
        lo, hi = self.kinematics.lower, self.kinematics.upper
        found: list[np.ndarray] = []
        best_q, best_cost, best_err = q_first, np.inf, (np.inf, np.inf)
        iterations = attempts = rejected = 0
        timed_out = False
        for attempt in range(max_attempts):
            if time_limit is not None and time.perf_counter() - t0 > time_limit:
                timed_out = True
                break
            q0 = q_first if attempt == 0 else rng.uniform(lo, hi)
            q, ep, er, its = self._attempt(q0, fid, R_goal, p_goal)
            iterations += its
            attempts += 1
            if ep <= self.position_tolerance and er <= self.rotation_tolerance and self._verify(q, fid, R_goal, p_goal):
                if validity_fn is None or bool(np.asarray(validity_fn(q[None])).reshape(-1)[0]):
                    found.append(q)
                    if len(found) >= num_solutions:
                        break
                    continue
                rejected += 1
            cost = ep / self.position_tolerance + er / self.rotation_tolerance
            if cost < best_cost:
                best_q, best_cost, best_err = q, cost, (ep, er)
        if found:
            status = IKStatus.SUCCESS
        elif timed_out:
            status = IKStatus.TIME_LIMIT
        elif rejected:
            status = IKStatus.REJECTED_BY_VALIDITY
        else:
            status = IKStatus.NOT_CONVERGED
        if not np.isfinite(best_err[0]):
            best_err = self._pose_error(best_q, fid, R_goal, p_goal)
        return _Attempts(found, best_q, best_err, iterations, attempts, status)

    def _attempt(self, q: np.ndarray, fid: int, R_goal: np.ndarray, p_goal: np.ndarray) -> tuple[np.ndarray, float, float, int]:
        """One descent from q (`_lm_lanes`). Returns (q, position error, rotation error, iterations)."""
        Q, ep, er, it = self._descend(q[None], fid, R_goal, p_goal)
        return Q[0], float(ep[0]), float(er[0]), int(it[0])

    def _descend(self, Q0: np.ndarray, fid: int, R_goal: np.ndarray, p_goal: np.ndarray):
        """`_lm_lanes` from every row of Q0 (K, dof): (Q, position errors, rotation errors, iterations)."""
        k = self.kinematics
        return _lm_lanes(np.ascontiguousarray(Q0, dtype=np.float64), *k.fk_tables(), *k.jacobian_tables(fid),
                         np.ascontiguousarray(R_goal, dtype=np.float64), np.ascontiguousarray(p_goal, dtype=np.float64),
                         k.lower, k.upper, self._tol_p, self._tol_r, self.damping, _MIN_DAMPING, self.max_step,
                         self.max_iterations, _STALL_ITERATIONS)

    def _pose_error(self, q: np.ndarray, fid: int, R_goal: np.ndarray, p_goal: np.ndarray) -> tuple[float, float]:
        M = self.kinematics.frame_transform(q, fid)
        return float(np.linalg.norm(p_goal - M.translation)), float(np.linalg.norm(pin.log3(R_goal @ M.rotation.T)))

    def _verify(self, q: np.ndarray, fid: int, R_goal: np.ndarray, p_goal: np.ndarray) -> bool:
        """Independent check of one solution: joint limits and the full model's FK."""
        return bool(self._verify_batch(q[None], fid, R_goal[None], p_goal[None])[0])

    def _verify_batch(self, Q: np.ndarray, fid: int, R_goal: np.ndarray, p_goal: np.ndarray) -> np.ndarray:
        """Independent check of solutions Q (K, dof) for goals (K, 3, 3), (K, 3): (K,) bool.

        Uses Pinocchio's full model (fingers included, its own data), not the solver's
        reduced model or batched NumPy kinematics, and the rotation angle from the trace
        (cos(theta) = (tr(R_goal^T R) - 1) / 2), not the solver's logarithm.
        """
        k = self.kinematics
        ok = np.all((Q >= k.lower) & (Q <= k.upper), axis=1)
        model, data = self._check_model, self._check_data
        cfid = self._check_frame_ids.get(fid)
        if cfid is None:
            cfid = self._check_frame_ids[fid] = model.getFrameId(self._model.frames[fid].name)
        q_full = k.locked_configuration.copy()
        idx = self._check_q_index
        R = np.empty((Q.shape[0], 3, 3))
        p = np.empty((Q.shape[0], 3))
        for i in range(Q.shape[0]):
            q_full[idx] = Q[i]
            pin.forwardKinematics(model, data, q_full)
            M = pin.updateFramePlacement(model, data, cfid)
            R[i] = M.rotation
            p[i] = M.translation
        ep = np.linalg.norm(p - p_goal, axis=1)
        cos = np.clip(0.5 * (np.einsum("nij,nij->n", R_goal, R) - 1.0), -1.0, 1.0)
        er = np.arccos(cos)
        good = ok & (ep <= self.position_tolerance) & (er <= self.rotation_tolerance)
        for i in np.flatnonzero(~good):
            logger.warning(
                "IK discarded a solution that failed the independent check (%.3g m, %.3g rad, limits: %s)",
                ep[i], er[i], k.limit_violations(Q[i]) or "ok",
            )
        return good

    # ------------------------------------------------------------------ batch solve
    def _batch_core(
        self,
        R_goal: np.ndarray,
        p_goal: np.ndarray,
        fid: int,
        q_start: np.ndarray,
        rng: np.random.Generator,
        validity_fn: ValidityFn | None,
        max_attempts: int,
        t0: float,
        time_limit: float | None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[IKStatus]]:
        """Vectorised LM over "lanes": one attempt each, several lanes per goal when few remain.

        Every goal starts with one lane from its `q_start`. A lane that ends without a
        verified, valid solution restarts from a random configuration while its goal has
        attempts left; when fewer than `_MIN_LANES` lanes are running, the goals still
        unsolved (whose seeded attempt has failed) get extra lanes (parallel random
        restarts), so stragglers cost a few NumPy iterations rather than many sequential
        attempts. A goal is done at its first verified solution.
        """
        k = self.kinematics
        n, dof = q_start.shape
        lo, hi = k.lower, k.upper
        q0 = np.clip(q_start, lo, hi).astype(float)
        success = np.zeros(n, dtype=bool)
        done = np.zeros(n, dtype=bool)
        rejected = np.zeros(n, dtype=bool)
        ep_out = np.full(n, np.inf)
        er_out = np.full(n, np.inf)
        best_cost = np.full(n, np.inf)
        q_out = q0.copy()
        iters = np.zeros(n, dtype=int)
        attempts = np.zeros(n, dtype=int)
        status: list[IKStatus] = [IKStatus.NOT_CONVERGED] * n
        seed_over = np.zeros(n, dtype=bool)  # the goal's seeded first attempt has ended

        far = self._out_of_reach(fid, p_goal)
        for i in np.flatnonzero(far):
            status[i] = IKStatus.OUT_OF_REACH
        done |= far
        if far.any():
            Rf, pf = k.frame_transforms(q0[far], [fid])
            ep_out[far] = np.linalg.norm(p_goal[far] - pf[:, 0], axis=1)
            er_out[far] = np.linalg.norm(_log3_batch(R_goal[far] @ np.swapaxes(Rf[:, 0], 1, 2)), axis=1)

        # lane state
        goal = np.flatnonzero(~far)
        Q = q0[goal]
        Rg, pg = R_goal[goal], p_goal[goal]  # per-lane goals
        attempts[goal] = 1
        it_attempt = np.zeros(goal.size, dtype=int)
        best_err = np.full(goal.size, np.inf)
        best_it = np.zeros(goal.size, dtype=int)

        tol_p, tol_r = self._tol_p, self._tol_r
        eye6 = np.eye(6)
        while goal.size:
            if time_limit is not None and time.perf_counter() - t0 > time_limit:
                for i in np.unique(goal):
                    status[i] = IKStatus.TIME_LIMIT
                break
            R, p, J = k.frame_jacobians(Q, fid)
            e = np.empty((goal.size, 6))
            e[:, :3] = pg - p
            e[:, 3:] = _log3_batch(Rg @ np.swapaxes(R, 1, 2))
            ep = np.sqrt(np.einsum("ij,ij->i", e[:, :3], e[:, :3]))
            er = np.sqrt(np.einsum("ij,ij->i", e[:, 3:], e[:, 3:]))
            err2 = ep * ep + er * er

            improved = err2 < best_err * 0.98
            best_err[improved] = err2[improved]
            best_it[improved] = it_attempt[improved]
            ended = (
                ((ep <= tol_p) & (er <= tol_r))
                | (it_attempt - best_it >= _STALL_ITERATIONS)
                | (it_attempt >= self.max_iterations)
            )
            restart = np.zeros(goal.size, dtype=bool)
            if ended.any():
                e_idx = np.flatnonzero(ended)
                good = e_idx[(ep[e_idx] <= self.position_tolerance) & (er[e_idx] <= self.rotation_tolerance)]
                if good.size:
                    good = good[self._verify_batch(Q[good], fid, Rg[good], pg[good])]
                if good.size and validity_fn is not None:
                    ok = np.asarray(validity_fn(Q[good]), dtype=bool).reshape(-1)
                    rejected[goal[good[~ok]]] = True
                    good = good[ok]
                # first solution of each goal (several lanes of one goal may finish together)
                g, first = np.unique(goal[good], return_index=True)
                good_first = good[first]
                success[g] = True
                done[g] = True
                q_out[g] = Q[good_first]
                ep_out[g], er_out[g] = ep[good_first], er[good_first]
                for i in g:
                    status[i] = IKStatus.SUCCESS
                failed = np.setdiff1d(e_idx, good, assume_unique=True)
                seed_over[goal[failed]] = True
                cost = ep[failed] / self.position_tolerance + er[failed] / self.rotation_tolerance
                for lane, c in zip(failed, cost):  # few per iteration
                    gi = goal[lane]
                    if c < best_cost[gi] and not success[gi]:
                        best_cost[gi] = c
                        q_out[gi] = Q[lane]
                        ep_out[gi], er_out[gi] = ep[lane], er[lane]
                    if attempts[gi] < max_attempts and not done[gi]:
                        attempts[gi] += 1
                        restart[lane] = True

            step = ~ended & ~done[goal]
            if step.any():
                s = slice(None) if step.all() else np.flatnonzero(step)
                Js = J[s]
                JsT = np.swapaxes(Js, 1, 2)
                lam = self.damping * err2[s] + _MIN_DAMPING
                es = e[s][:, :, None]
                dq = (JsT @ _solve_spd(Js @ JsT + lam[:, None, None] * eye6, es))[:, :, 0]
                Qs = Q[s]
                blocked = ((Qs <= lo) & (dq < 0)) | ((Qs >= hi) & (dq > 0))
                b = np.flatnonzero(blocked.any(axis=1))
                if b.size:
                    # joints held at a limit take no part in the step; the others compensate
                    Jb = Js[b] * ~blocked[b][:, None, :]
                    Ab = Jb @ np.swapaxes(Jb, 1, 2) + lam[b, None, None] * eye6
                    dq[b] = (np.swapaxes(Jb, 1, 2) @ _solve_spd(Ab, es[b]))[:, :, 0]
                big = np.abs(dq).max(axis=1)
                scale = np.where(big > self.max_step, self.max_step / np.maximum(big, 1e-300), 1.0)
                Q[s] = np.clip(Qs + dq * scale[:, None], lo, hi)
                iters[goal[s]] += 1
                it_attempt[s] += 1
            restart &= ~done[goal]
            if restart.any():
                r = np.flatnonzero(restart)
                Q[r] = rng.uniform(lo, hi, (r.size, dof))
                it_attempt[r] = 0
                best_err[r] = np.inf
                best_it[r] = 0
            keep = step | restart
            if not keep.all():
                goal, Q, Rg, pg = goal[keep], Q[keep], Rg[keep], pg[keep]
                it_attempt, best_err, best_it = it_attempt[keep], best_err[keep], best_it[keep]

            # parallel restarts for the stragglers
            if goal.size < _MIN_LANES:
                # only goals whose first (seeded) attempt failed: a seeded solution stays the answer
                open_goals = np.flatnonzero(~done & seed_over & (attempts < max_attempts))
                if open_goals.size:
                    per_goal = max(1, (_MIN_LANES - goal.size) // open_goals.size)
                    extra = np.minimum(per_goal, max_attempts - attempts[open_goals])
                    new_goal = np.repeat(open_goals, extra)
                    attempts[open_goals] += extra
                    goal = np.concatenate([goal, new_goal])
                    Rg = np.concatenate([Rg, R_goal[new_goal]])
                    pg = np.concatenate([pg, p_goal[new_goal]])
                    Q = np.concatenate([Q, rng.uniform(lo, hi, (new_goal.size, dof))])
                    it_attempt = np.concatenate([it_attempt, np.zeros(new_goal.size, dtype=int)])
                    best_err = np.concatenate([best_err, np.full(new_goal.size, np.inf)])
                    best_it = np.concatenate([best_it, np.zeros(new_goal.size, dtype=int)])

        for i in np.flatnonzero(~done):
            if status[i] is IKStatus.NOT_CONVERGED and rejected[i]:
                status[i] = IKStatus.REJECTED_BY_VALIDITY
        return q_out, success, ep_out, er_out, iters, attempts, status
