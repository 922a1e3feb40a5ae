"""`IKSolver`: damped least squares (Levenberg-Marquardt) with joint limits and restarts.

`IKSolver.solve` finds one configuration for one goal, each attempt one compiled (numba)
descent (`kernels._lm_lanes`, on the same kinematics tables as `Kinematics.joint_transforms`);
`IKSolver.solve_batch` iterates all goals of a batched Pose at once in NumPy
(`Kinematics.frame_jacobians`, `manip.ik.batch`), re-starting only the ones that have not
converged; `IKSolver.solve_many` runs all its attempts in one compiled call and returns
several distinct solutions of one goal, nearest `seed_q` first.

The iteration and its stopping rules are described in `manip.ik.kernels`.

mink (a QP per step) was measured for comparison in benchmarks/kinematics.py: the same
success rate on reachable poses, several times the median time per solve (BENCHMARKS.md).

Every claimed success is re-checked with an independent forward kinematics (Pinocchio's
full model, fingers included, a different code path from the solver's) and against the
joint limits; a solution that fails the check is discarded, never reported.
"""

from __future__ import annotations

import logging
import threading
import time
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from manip import curobo_names
from manip.errors import InvalidInputError
from manip.ik import goalset
from manip.ik.attempts import LazyRng, at_least_one, call_attempts, renamed
from manip.ik.batch import run_lanes
from manip.ik.goalset import GoalsetIKResult
from manip.ik.kernels import _INTERNAL_TOLERANCE, _MIN_DAMPING, _STALL_ITERATIONS, _lm_lanes, _slide_lanes
from manip.ik.result import BatchIKResult, IKResult, IKSolutions, IKStatus, ValidityFn, _freeze
from manip.kinematics import Kinematics
from manip.pose import Pose
from manip.validation import flag, integer, non_negative, positive

logger = logging.getLogger(__name__)

#: `solve_many(toward_seed=True)`: the self-motion iteration (`kernels._slide_lanes`): the
#: fraction of the way to the reference taken per step, the damping of its pseudo-inverse,
#: its largest self-motion step [rad], its iterations at most and the step [rad] below which
#: it has arrived (BENCHMARKS.md, "Constants").
SLIDE_GAIN = 1.0
SLIDE_DAMPING = 1e-6
SLIDE_STEP = 0.2
SLIDE_ITERATIONS = 30
SLIDE_TOLERANCE = 5e-3
#: `IKSolver(max_attempts=)`'s default: attempts per goal (the first from `seed_q`).
MAX_ATTEMPTS = 100


class _Attempts(NamedTuple):
    found: list[np.ndarray]
    best_q: np.ndarray
    best_error: tuple[float, float]
    iterations: int
    attempts: int
    status: IKStatus


def _distinct(Q: np.ndarray, min_distance: float, n: int) -> np.ndarray:
    """Indices of the rows of Q (K, dof) kept in order, each at least `min_distance` [rad, max
    over joints] from every row kept before it, at most n of them."""
    kept: list[int] = []
    for i in range(Q.shape[0]):
        if not kept or np.abs(Q[kept] - Q[i]).max(axis=1).min() >= min_distance:
            kept.append(i)
            if len(kept) == n:
                break
    return np.array(kept, dtype=np.int64)


class IKSolver:
    """Levenberg-Marquardt inverse kinematics with joint limits and random restarts.

    Goals are poses of a link (any frame of the model) in the robot's base frame.

    Args:
        kinematics: the robot's kinematics.
        position_tolerance: success threshold on the position error [m].
        rotation_tolerance: success threshold on the rotation error [rad].
        max_iterations: iterations per attempt.
        max_attempts: attempts per goal: the first from `seed_q`, the others from uniformly
            random configurations within the joint limits (default `MAX_ATTEMPTS`).
        seed: seed of the random restarts; the same inputs and seed give the same answer.
        damping: Levenberg-Marquardt damping gain (lambda = damping * |e|^2).
        max_step: largest change of one joint per iteration [rad].
        num_seeds: cuRobo's name (`IKSolverConfig`) of `max_attempts`; deprecated, give one of them.

    Raises:
        InvalidInputError: if a parameter is not positive, or both max_attempts and num_seeds are given.
    """

    def __init__(
        self,
        kinematics: Kinematics,
        *,
        position_tolerance: float = 1e-3,
        rotation_tolerance: float = 0.01,
        max_iterations: int = 60,
        max_attempts: int | None = None,
        seed: int = 0,
        damping: float = 0.03,
        max_step: float = 1.0,
        num_seeds: int | None = None,
    ):
        if not isinstance(kinematics, Kinematics):
            raise InvalidInputError(f"kinematics must be a manip.Kinematics, got {type(kinematics).__name__}")
        self.kinematics = kinematics
        self.position_tolerance = positive(position_tolerance, "position_tolerance", "m")
        self.rotation_tolerance = positive(rotation_tolerance, "rotation_tolerance", "rad")
        self.max_iterations = integer(max_iterations, "max_iterations", 1)
        num_seeds = None if num_seeds is None else at_least_one(num_seeds, "num_seeds")
        max_attempts = renamed("num_seeds", num_seeds, "max_attempts", max_attempts, stacklevel=3)
        self.max_attempts = integer(MAX_ATTEMPTS if max_attempts is None else max_attempts, "max_attempts", 1)
        self.seed = integer(seed, "seed", 0)
        self.damping = positive(damping, "damping")
        self.max_step = positive(max_step, "max_step", "rad")
        #: The descent's own stopping tolerances [m], [rad] (at most the reported ones).
        self.internal_tolerances = (min(_INTERNAL_TOLERANCE, self.position_tolerance),
                                    min(_INTERNAL_TOLERANCE, self.rotation_tolerance))
        self._tol_p, self._tol_r = self.internal_tolerances
        self._model = kinematics.model
        # Independent check: the full model (fingers at their planning positions), its own
        # data (one per thread: a solver may be shared by threads).
        self._check_model = kinematics.full_model
        self._local = threading.local()
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
        max_attempts: int | None = None,
        num_seeds: int | None = None,
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
            max_attempts: this call's attempts (default: the solver's `max_attempts`);
                `num_seeds`, cuRobo's `solve_single` name, is its deprecated name.

        Returns:
            IKResult; `q` is the solution nearest `seed_q` among those found; on failure
            `message` says what went wrong in this call.

        Raises:
            InvalidInputError: goal not a single Pose, bad seed_q, bad num_solutions or
                max_attempts (or both max_attempts and num_seeds).
            UnknownNameError: unknown link (the message lists the frames).
        """
        t0 = time.perf_counter()
        fid, q_ref = self._prepare(goal, link, seed_q, batched=False)
        at_least_one(num_solutions, "num_solutions")
        attempts = call_attempts(self.max_attempts, max_attempts, num_seeds)
        seed, time_limit = self._call_options(seed, time_limit, validity_fn)
        rng = LazyRng(seed)
        R_goal = goal.rotation
        p_goal = goal.position

        if self.out_of_reach(fid, p_goal[None])[0]:
            ep, er = self._pose_error(q_ref, fid, R_goal, p_goal)
            status = IKStatus.OUT_OF_REACH
            return IKResult(False, _freeze(q_ref.copy()), ep, er, status, 0, time.perf_counter() - t0, 0,
                            self._failure_message(status, 0, ep, er, fid, p_goal, time_limit))

        lo, hi = self.kinematics.lower, self.kinematics.upper
        out = self._run_attempts(
            fid, R_goal, p_goal, np.clip(q_ref, lo, hi), attempts, rng, validity_fn, num_solutions, t0, time_limit
        )
        elapsed = time.perf_counter() - t0
        if out.found:
            sols = np.array(out.found)
            q = sols[np.argmin(np.linalg.norm(sols - q_ref, axis=1))]
            ep, er = self._pose_error(q, fid, R_goal, p_goal)
            return IKResult(True, _freeze(q.copy()), ep, er, IKStatus.SUCCESS, out.iterations, elapsed, out.attempts)
        logger.debug("IK failed (%s) after %d attempts", out.status.name, out.attempts)
        ep, er = out.best_error
        return IKResult(
            False, _freeze(out.best_q.copy()), ep, er, out.status, out.iterations, elapsed, out.attempts,
            self._failure_message(out.status, out.attempts, ep, er, fid, p_goal, time_limit),
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
        max_attempts: int | None = None,
        num_seeds: int | None = None,
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
            max_attempts: this call's attempts per goal (default: the solver's); `num_seeds`
                (cuRobo's `solve_batch` name) is its deprecated name.

        Returns:
            BatchIKResult: `q` (N, dof); `success` and the errors (N, 1) as cuRobo's.

        Raises:
            InvalidInputError: goals not a batched Pose, bad seed_q or max_attempts.
            UnknownNameError: unknown link.
        """
        t0 = time.perf_counter()
        fid, q_ref = self._prepare(goals, link, seed_q, batched=True)
        n = len(goals)
        attempts = call_attempts(self.max_attempts, max_attempts, num_seeds)
        seed, time_limit = self._call_options(seed, time_limit, validity_fn)
        rng = np.random.default_rng(seed)
        out = run_lanes(
            self, goals.rotation, goals.position, fid, np.broadcast_to(q_ref, (n, self.kinematics.dof)),
            rng, validity_fn, attempts, t0, time_limit,
        )
        q, success, ep, er, iters, attempts, status = out
        message = [""] * n
        for i in np.flatnonzero(~success):
            message[i] = self._failure_message(status[i], attempts[i], ep[i], er[i], fid, goals.position[i], time_limit)
        return BatchIKResult(
            success=_freeze(success), q=_freeze(q), position_error=_freeze(ep), rotation_error=_freeze(er),
            status=tuple(status), iterations=_freeze(iters), attempts=_freeze(attempts),
            solve_time=time.perf_counter() - t0, message=tuple(message),
        )

    def solve_many(
        self,
        goal: Pose,
        link: str | None = None,
        n: int = 8,
        seed_q: np.ndarray | None = None,
        *,
        validity_fn: ValidityFn | None = None,
        attempts: int | None = None,
        min_distance: float = 0.05,
        seed: int | None = None,
        num_seeds: int | None = None,
        toward_seed: bool = False,
    ) -> IKSolutions:
        """Several distinct solutions of one goal, nearest `seed_q` first.

        Runs `attempts` descents (the first from `seed_q`, the others from random
        configurations) and keeps, in attempt order, the verified solutions that
        `validity_fn` accepts, dropping near-duplicates, up to `n`.

        Args:
            goal: single Pose of `link` in the base frame.
            link: frame to place at the goal (default: the robot's `ee_link`).
            n: largest number of solutions to return.
            seed_q: (dof,) reference configuration (default: the default configuration).
            validity_fn: optional Q (K, dof) -> (K,) bool filter (e.g. collision-free).
            attempts: how many attempts to make: the first from `seed_q`, the others random
                restarts (default max(4 n, 16)).
            min_distance: two solutions closer than this [rad, max over joints] count as one.
            seed: seed of the random starts (default: the solver's).
            num_seeds: deprecated name of `attempts`.
            toward_seed: also move each solution along its self-motion (the configurations
                that keep the frame on the goal; redundant arms only, dof > 6) towards
                `seed_q`, to the nearest such configuration on its branch, and offer that one
                (when verified and valid) just before it.

        Returns:
            IKSolutions: `q` (K, dof), K <= n (K = 0 when none was found), sorted by
            Euclidean joint-space distance to `seed_q`, with the status, a message when
            none was found and the attempts made. It iterates, indexes and converts
            (`np.asarray`) as the (K, dof) array of solutions.

        Raises:
            InvalidInputError: goal not a single Pose, bad seed_q, n or attempts < 1, both
                attempts and num_seeds given.
            UnknownNameError: unknown link.
        """
        fid, q_ref = self._prepare(goal, link, seed_q, batched=False)
        at_least_one(n, "n")
        attempts = renamed("num_seeds", num_seeds, "attempts", attempts, stacklevel=3)
        m = max(4 * n, 16) if attempts is None else at_least_one(attempts, "attempts")
        min_distance = positive(min_distance, "min_distance", "rad")
        toward_seed = flag(toward_seed, "toward_seed")
        seed, _ = self._call_options(seed, None, validity_fn)
        rng = LazyRng(seed)
        k = self.kinematics
        R_goal, p_goal = goal.rotation, goal.position
        if self.out_of_reach(fid, p_goal[None])[0]:
            status = IKStatus.OUT_OF_REACH
            return IKSolutions(_freeze(np.empty((0, k.dof))), status,
                               self._failure_message(status, 0, np.inf, np.inf, fid, p_goal, None), 0)
        # every attempt at once (one compiled call), then the filters in attempt order
        Q0 = np.vstack([np.clip(q_ref, k.lower, k.upper)[None], rng.uniform(k.lower, k.upper, (m - 1, k.dof))])
        Q, ep, er, _ = self._descend(Q0, fid, R_goal, p_goal)
        idx = np.flatnonzero(self._solved(Q, ep, er, fid, R_goal, p_goal))
        if idx.size and toward_seed and k.dof > 6:
            # the distinct solutions, each after its slid version
            Q, idx = self._with_slid(Q, idx[_distinct(Q[idx], min_distance, idx.size)], q_ref, fid, R_goal, p_goal)
        verified = idx.size
        if idx.size and validity_fn is not None:
            idx = idx[np.asarray(validity_fn(Q[idx]), dtype=bool).reshape(-1)]
        sols = Q[idx[_distinct(Q[idx], min_distance, n)]]
        sols = _freeze(sols[np.argsort(np.linalg.norm(sols - q_ref, axis=1), kind="stable")])
        if len(sols):
            return IKSolutions(sols, IKStatus.SUCCESS, "", m)
        status = IKStatus.REJECTED_BY_VALIDITY if verified else IKStatus.NOT_CONVERGED
        best = int(np.argmin(ep / self.position_tolerance + er / self.rotation_tolerance))
        return IKSolutions(sols, status, self._failure_message(status, m, ep[best], er[best], fid, p_goal, None), m)

    def solve_goalset(self, goals: Pose, link: str | None = None, seed_q=None, **options) -> GoalsetIKResult:
        """cuRobo's goal-set IK: reach one pose of `goals` (G poses); `goalset_index` says which
        (`manip.ik.goalset`)."""
        return goalset.solve_goalset(self, goals, link, seed_q, **options)

    def solve_batch_goalset(self, goal_sets, link: str | None = None, seed_q=None, **options) -> GoalsetIKResult:
        """B goal sets (B Poses of G poses) at once, one row each (`manip.ik.goalset`)."""
        return goalset.solve_batch_goalset(self, goal_sets, link, seed_q, **options)

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's (solve_single, ...) say where manip has them
        if name.startswith("_"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.IK_SOLVER, name)

    @property
    def _check_data(self):
        """The calling thread's Pinocchio data of the full model."""
        data = getattr(self._local, "check_data", None)
        if data is None:
            data = self._local.check_data = self._check_model.createData()
        return data

    # ------------------------------------------------------------------ validation
    def _prepare(self, goal: object, link: str | None, seed_q: np.ndarray | None, batched: bool) -> tuple[int, np.ndarray]:
        """Checks of a call's goal (a single or a batched Pose), link and seed_q:
        (frame id, reference configuration (dof,) or (N, dof))."""
        self._check_goal(goal, batched)
        fid = self.kinematics.frame_id(link if link is not None else self.kinematics.config.ee_link, "link")
        return fid, self._check_seed_q(seed_q, len(goal) if batched else None)

    def _call_options(self, seed, time_limit, validity_fn) -> tuple[int, float | None]:
        """The call's (seed, time_limit), validated; validity_fn must be callable or None."""
        seed = self.seed if seed is None else integer(seed, "seed", 0)
        if time_limit is not None:
            time_limit = non_negative(time_limit, "time_limit", "s")
        if validity_fn is not None and not callable(validity_fn):
            raise InvalidInputError(f"validity_fn must be a callable Q (K, dof) -> (K,) bool; got {validity_fn!r}")
        return seed, time_limit

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

    def _check_seed_q(self, seed_q: np.ndarray | None, n: int | None) -> np.ndarray:
        k = self.kinematics
        if seed_q is None:
            return k.config.default_joint_positions.astype(float).copy()
        q = k.check_q(seed_q, "seed_q")
        if n is None and q.ndim != 1:
            raise InvalidInputError(f"seed_q must have shape ({k.dof},) for joints {list(k.joint_names)}; got {q.shape}")
        if n is not None and q.ndim == 2 and q.shape[0] != n:
            raise InvalidInputError(f"seed_q must have shape ({k.dof},) or ({n}, {k.dof}) for {n} goals; got {q.shape}")
        return q.copy()

    def _failure_message(self, status: IKStatus, attempts: int, ep: float, er: float, fid: int,
                         p_goal: np.ndarray, time_limit: float | None) -> str:
        """The one-line detail of a failed query ("" for SUCCESS)."""
        if status is IKStatus.SUCCESS:
            return ""
        if status is IKStatus.OUT_OF_REACH:
            anchor, radius = self._reach(fid)
            return (f"the goal position is {np.linalg.norm(p_goal - anchor):.3f} m from the first joint of the chain "
                    f"to '{self._model.frames[fid].name}', which reaches at most {radius:.3f} m")
        if status is IKStatus.TIME_LIMIT:
            return f"time_limit {time_limit:g} s ran out after {attempts} attempt(s)"
        if status is IKStatus.REJECTED_BY_VALIDITY:
            return f"validity_fn rejected every solution found in {attempts} attempt(s)"
        return (f"no attempt of {attempts} converged: the best ended {ep:.3g} m and {er:.3g} rad from the goal "
                f"(tolerances {self.position_tolerance:g} m, {self.rotation_tolerance:g} rad)")

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
            specs = self.kinematics.joint_specs
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

    def out_of_reach(self, fid: int, p_goal: np.ndarray) -> np.ndarray:
        """(N,) bool: goal positions p_goal (N, 3) [m] of frame `fid` farther from the chain's
        first moving joint than the chain can reach (plus the position tolerance)."""
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
        rng: LazyRng | np.random.Generator,
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

    def _solved(self, Q: np.ndarray, ep: np.ndarray, er: np.ndarray, fid: int, R_goal: np.ndarray,
                p_goal: np.ndarray, among: np.ndarray | None = None) -> np.ndarray:
        """(K,) bool: rows of Q (K, dof) within the tolerances (errors ep, er (K,)) and verified
        by `_verify_batch`, only among the rows `among` (K,) bool when given."""
        ok = (ep <= self.position_tolerance) & (er <= self.rotation_tolerance)
        if among is not None:
            ok &= among
        if ok.any():
            m = int(ok.sum())
            ok[ok] = self.verify_batch(Q[ok], fid, np.broadcast_to(R_goal, (m, 3, 3)), np.broadcast_to(p_goal, (m, 3)))
        return ok

    def _with_slid(self, Q: np.ndarray, idx: np.ndarray, q_ref: np.ndarray, fid: int, R_goal: np.ndarray,
                   p_goal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(Q with the verified solutions Q[idx] moved along their self-motion towards q_ref
        appended, the indices of the slid ones that verify and are nearer q_ref, each just
        before its own)."""
        k = self.kinematics
        R = np.ascontiguousarray(R_goal, dtype=np.float64)
        p = np.ascontiguousarray(p_goal, dtype=np.float64)
        S, _, _ = _slide_lanes(np.ascontiguousarray(Q[idx]), np.ascontiguousarray(q_ref, dtype=np.float64),
                               *k.fk_tables(), *k.jacobian_tables(fid), R, p, k.lower, k.upper, SLIDE_GAIN,
                               SLIDE_DAMPING, SLIDE_STEP, SLIDE_ITERATIONS, SLIDE_TOLERANCE,
                               self.position_tolerance * 0.1, self.rotation_tolerance * 0.1)
        S, ep, er, _ = self._descend(S, fid, R_goal, p_goal)  # back onto the goal to the solver's tolerance
        nearer = np.linalg.norm(S - q_ref, axis=1) < np.linalg.norm(Q[idx] - q_ref, axis=1)
        ok = self._solved(S, ep, er, fid, R_goal, p_goal, nearer)
        order = np.empty(2 * idx.size, dtype=np.int64)
        order[0::2] = Q.shape[0] + np.arange(idx.size)
        order[1::2] = idx
        keep = np.concatenate([ok[:, None], np.ones((idx.size, 1), dtype=bool)], axis=1).ravel()
        return np.vstack([Q, S]), order[keep]

    def _pose_error(self, q: np.ndarray, fid: int, R_goal: np.ndarray, p_goal: np.ndarray) -> tuple[float, float]:
        M = self.kinematics.frame_transform(q, fid)
        return float(np.linalg.norm(p_goal - M.translation)), float(np.linalg.norm(pin.log3(R_goal @ M.rotation.T)))

    def _verify(self, q: np.ndarray, fid: int, R_goal: np.ndarray, p_goal: np.ndarray) -> bool:
        """Independent check of one solution: joint limits and the full model's FK."""
        return bool(self.verify_batch(q[None], fid, R_goal[None], p_goal[None])[0])

    def verify_batch(self, Q: np.ndarray, fid: int, R_goal: np.ndarray, p_goal: np.ndarray) -> np.ndarray:
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
