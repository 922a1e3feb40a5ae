"""Trajectory optimisation: fast, short, smooth motions from a collision-free seed.

The motion is a uniform cubic B-spline at rest at both ends (`planning.bspline`), whose
velocity, acceleration, jerk and position limits are linear constraints on its control
points that hold for the continuous motion. For a fixed duration, sequential convex
optimisation (trust region) improves the control points; each iteration solves one QP
(PIQP's sparse interface; any other `solver` through `qpsolvers`):

- minimise the squared velocities (each as a fraction of its limit: at a fixed duration
  this straightens the path and flattens the speed profile, the shape of a time-optimal
  motion) plus a jerk term (dominant with `smoothness="smooth"`);
- subject to the trust region, with the limits at the target duration and the clearance
  of the robot's sphere cover above `margin` (linearised at samples of the current motion,
  `collision.clearance`) as L1 penalties (TrajOpt's formulation: every QP is feasible);
- at an end whose configuration is near an obstacle (where the sphere cover is too coarse),
  the first/last piece stays on the seed's first/last straight segment.

The outer loop looks for the shortest duration (cuRobo's idea): after each solve the motion
is uniformly re-timed until a limit is active (exact: the limits are linear in the control
points), and the next target lies 30 % of the way from the longest target not reached (at
first the straight line's lower bound) to the best duration so far; when the seed's
duration gives nothing usable, the search starts once more from the seed's spline at a
duration where it is within the limits (`TrajOptSettings.second_chance`). The result is
certified by the caller against the exact meshes; on any failure the caller keeps the
seed trajectory.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from manip.collision.clearance import ClearanceModel
from manip.errors import InvalidInputError
from manip.planning import bspline, qp
from manip.trajectory import PiecewiseJerkProfile
from manip.validation import flag, integer, non_negative, per_joint, positive

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class TrajOptSettings:
    """Settings of the trajectory optimiser.

    Attributes:
        intervals: B-spline pieces N (N - 3 free control points per joint).
        samples_per_interval: collision samples per piece.
        margin: sphere-cover clearance [m] kept from obstacles (on top of the padding).
        activation: terms farther than margin + activation are left out of the QP [m].
        iterations: SCO iterations per duration (at most).
        tolerance: an SCO stops when a step lowers the merit by less than this fraction
            (3e-3 against 1e-3 on MotionBenchMaker 15/scene joint and pose goals: -4 % QPs,
            the same mean duration; 1e-2: -11 % QPs, +0.15 %).
        limit_row_slack: limit rows used less than (1 - this) of their limit at the
            current point are left out of the QP (they are soft, and the result is re-timed
            exactly).
        trust_region: largest move of a control point per iteration [rad] at first and at
            most; it halves after a rejected step, and each duration round starts at twice
            the previous round's final radius.
        line_search: halvings of a step that does not lower the merit tried before the
            trust region shrinks (each costs a clearance evaluation, not a QP; 1 measured
            on MotionBenchMaker 32/scene joint goals: -1.5 % duration, -1 % QPs against 0).
        ray_points: control points tied to the seed's first / last segment at an end near
            an obstacle (each keeps one more piece of the motion on that segment).
        rounds: durations tried (the seed's first, then by bisection towards the lower bound).
        second_chance: when the seed's duration gives no usable motion (none, or none
            faster than `max_duration`), start once more from the spline fitted to the seed
            at the duration where it is within the limits (the fit of a ruckig-timed polyline
            exceeds the acceleration limits about 1.9 x at the seed's own duration).
        bisection: where the next duration lies between the longest infeasible and the
            shortest feasible one (0.5: halfway; 0.3 measured on MotionBenchMaker 32/scene
            joint goals: -0.5 % duration and -5 % QPs against 0.5).
        duration_tolerance: the search stops once the best duration is within this fraction
            of the longest target not reached (0.05: +0.6 % duration, -12 % QPs; 0.02:
            -0.2 % duration, +10 % QPs, against 0.03 on MotionBenchMaker 16/scene).
        penalty: weight of the clearance violation [1/m] (L1) against the objective.
        velocity_weight, acceleration_weight, jerk_weight: objective weights (terms are
            squared fractions of the limits).
        solver: a `qpsolvers` solver name ("osqp", "daqp", ...).
    """

    intervals: int = 16
    samples_per_interval: int = 5
    margin: float = 0.008
    activation: float = 0.02
    iterations: int = 6
    tolerance: float = 3e-3
    limit_row_slack: float = 0.6
    trust_region: float = 0.3
    rounds: int = 6
    ray_points: int = 1
    bisection: float = 0.3
    duration_tolerance: float = 0.03
    penalty: float = 1e4
    second_chance: bool = True
    line_search: int = 1
    velocity_weight: float = 1.0
    acceleration_weight: float = 0.01
    jerk_weight: float = 0.001
    solver: str = "piqp"

    def __post_init__(self) -> None:
        def name(field: str) -> str:
            return f"TrajOptSettings.{field}"

        for field, least in (("intervals", 4), ("samples_per_interval", 1), ("iterations", 1), ("rounds", 1),
                             ("ray_points", 1), ("line_search", 0)):
            integer(getattr(self, field), name(field), least)
        for field in ("bisection", "duration_tolerance", "limit_row_slack"):
            if not 0.0 < non_negative(getattr(self, field), name(field)) < 1.0:
                raise InvalidInputError(f"{name(field)} must be a number in (0, 1); got {getattr(self, field)!r}")
        for field in ("margin", "activation", "tolerance", "velocity_weight", "acceleration_weight", "jerk_weight"):
            non_negative(getattr(self, field), name(field))
        positive(self.trust_region, name("trust_region"), "rad")
        positive(self.penalty, name("penalty"))
        flag(self.second_chance, name("second_chance"))
        if not qp.solver_available(self.solver):
            raise InvalidInputError(f"TrajOptSettings.solver must be 'piqp' or an installed qpsolvers solver "
                                    f"({', '.join(qp.installed_solvers())}); got {self.solver!r}")
        if self.intervals >= 8 and self.ray_points > self.intervals // 2 - 2:  # rays need N >= 8
            raise InvalidInputError(f"TrajOptSettings.ray_points must be <= intervals // 2 - 2 = "
                                    f"{self.intervals // 2 - 2}; got {self.ray_points}")


SMOOTH = TrajOptSettings(velocity_weight=0.05, acceleration_weight=0.05, jerk_weight=1.0)


@dataclass(frozen=True)
class TrajOptResult:
    """Outcome of `optimize_trajectory`.

    Attributes:
        success: True when `profile` is within the limits and its sampled sphere clearance
            satisfied the constraints (the exact certificate is the caller's).
        profile: the motion (None on failure).
        control: (N + 3, dof) its control points [rad].
        duration: its duration [s].
        solves: QPs solved.
        message: why it failed ("" on success).
        ends_tied: ends (0, 1 or 2) whose first / last pieces were kept on the seed's
            straight segments (`TrajOptSettings.ray_points`; ends near an obstacle).
    """

    success: bool
    profile: PiecewiseJerkProfile | None
    control: np.ndarray | None
    duration: float
    solves: int
    message: str = ""
    ends_tied: int = 0


class _Problem:
    """The QP data that depend only on N and the limits (the constant blocks, per joint)."""

    def __init__(self, n: int, dof: int, s: TrajOptSettings, start: np.ndarray, goal: np.ndarray):
        self.n, self.dof = n, dof
        self.free = np.arange(3, n)  # indices of the free control points
        self.fixed = np.setdiff1d(np.arange(n + 3), self.free)
        self.c_fixed = np.empty((n + 3, dof))
        self.c_fixed[:3] = start
        self.c_fixed[n:] = goal
        self.D = {k: bspline.difference_matrix(n + 3, k) for k in (1, 2, 3)}
        self.B, self.sample_t = bspline.basis_matrix(n, s.samples_per_interval)
        self.B_free = self.B[:, self.free]
        self.rays: list = []
        self.ends_tied = 0
        self.ray_A = self.ray_b = None
        self.q_fixed = self.B[:, self.fixed] @ self.c_fixed[self.fixed]  # (M, dof) fixed points' share
        eye = np.eye(dof)
        # limit rows: per order, rows touching a free point; G = +-kron(I, Df), rhs = lim -+ fixed share
        self.limit_G, self.limit_fixed, self.limit_order, self.limit_slack = [], [], [], []
        self.cost = {}
        for k in (1, 2, 3):
            D = self.D[k]
            Df = D[:, self.free]
            rows = np.flatnonzero(np.any(Df != 0, axis=1))
            G = np.kron(eye, Df[rows])
            self.limit_G += [G, -G]
            fixed = (D[rows][:, self.fixed] @ self.c_fixed[self.fixed]).T.ravel()  # joint-major (dof * R,)
            self.limit_fixed += [fixed, -fixed]
            self.limit_order += [(k, rows.size)] * 2
            self.limit_slack += [np.repeat((k - 1) * dof + np.arange(dof), rows.size)] * 2
            self.cost[k] = (Df.T @ Df, Df.T @ (D[:, self.fixed] @ self.c_fixed[self.fixed]))  # (m, m), (m, dof)
        self.limit_G = np.vstack(self.limit_G)
        self.limit_slack = np.concatenate(self.limit_slack)  # (L,) which limit slack each row may use
        slack = np.zeros((self.limit_G.shape[0], 3 * dof))
        slack[np.arange(slack.shape[0]), self.limit_slack] = -1.0
        self.limit_G_slack = np.hstack([self.limit_G, slack])  # (L, dof * m + 3 dof): rows with their slacks

    def set_rays(self, d_start: np.ndarray | None, d_goal: np.ndarray | None, points: int) -> None:
        """Tie the first `points` free control points to start + a d_start and the last ones to
        goal + b d_goal (0 <= a, b <= 1); None leaves that end free."""
        n, m, dof = self.n, self.free.size, self.dof
        self.rays = []
        self.ends_tied = (d_start is not None) + (d_goal is not None)
        for k in range(points):
            if d_start is not None:
                self.rays.append((3 + k, self.c_fixed[0], d_start))
            if d_goal is not None:
                self.rays.append((n - 1 - k, self.c_fixed[n], d_goal))
        if not self.rays:
            return
        A = np.zeros((len(self.rays) * dof, dof * m + 3 * dof + len(self.rays)))  # columns [x, S, R] (planning.qp)
        b = np.zeros(len(self.rays) * dof)
        for r, (k, anchor, d) in enumerate(self.rays):
            for i in range(dof):
                A[r * dof + i, i * m + (k - 3)] = 1.0
                A[r * dof + i, dof * m + 3 * dof + r] = -d[i]
                b[r * dof + i] = anchor[i]
        self.ray_A, self.ray_b = qp.csc_of_transpose(A.T), b

    def project_rays(self, c: np.ndarray) -> np.ndarray:
        """c with the tied control points projected onto their rays."""
        c = c.copy()
        for k, anchor, d in self.rays:
            a = np.clip((c[k] - anchor) @ d / max(d @ d, 1e-18), 0.0, 1.0)
            c[k] = anchor + a * d
        return c

    def control(self, x: np.ndarray) -> np.ndarray:
        """Full control points (N + 3, dof) of the free ones x (N - 3, dof)."""
        c = self.c_fixed.copy()
        c[3 : self.n] = x
        return c


def optimize_trajectory(
    seed_positions: np.ndarray,
    seed_times: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    jmax: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    clearance: ClearanceModel,
    padding: float,
    deadline: float,
    *,
    settings: TrajOptSettings = TrajOptSettings(),
    min_duration: float = 0.0,
    max_duration: float = np.inf,
    max_solves: int | float = np.inf,
    end_rays: bool = True,
) -> TrajOptResult:
    """Optimise a rest-to-rest motion seeded by a sampled one (e.g. a timed collision-free path).

    Args:
        seed_positions: (T, dof) samples of a limit-respecting motion, collision-free or
            nearly so (its sampled sphere clearance is the floor the result keeps) [rad].
        seed_times: (T,) their times [s] (the last is the seed's duration).
        vmax, amax, jmax: (dof,) velocity, acceleration, jerk limits (already scaled).
        lower, upper: (dof,) position limits [rad].
        clearance: the sphere-cover clearance model of the robot and world.
        padding: clearance the planner keeps [m] (added to `settings.margin`).
        deadline: `time.perf_counter()` value to stop at (the best result so far is kept).
        settings: see TrajOptSettings.
        min_duration: a lower bound of the duration [s] (e.g. the straight line's): the
            first target not reached (see `TrajOptSettings.duration_tolerance`).
        max_duration: the duration to beat [s] (e.g. the seed's): the search stops before
            a target this long (it could only give slower motions).
        max_solves: QPs at most (a count, so the result does not depend on the machine).
        end_rays: keep the motion's first and last two pieces on the seed's first and last
            straight segments (the seed must be a polyline's timing; the pieces near a goal
            that almost touches an obstacle are then exactly as free as the seed's).
    """
    seed_positions, seed_times = _check_seed(seed_positions, seed_times)
    if not (max_solves >= 1):
        raise InvalidInputError(f"max_solves must be >= 1; got {max_solves!r}")
    if not (np.isfinite(min_duration) and min_duration >= 0.0 and max_duration > 0.0):
        raise InvalidInputError(f"min_duration must be finite and >= 0 and max_duration > 0 [s]; got {min_duration!r}, "
                                f"{max_duration!r}")
    dof = seed_positions.shape[1]
    vmax, amax, jmax = (per_joint(v, dof, name, positive=True) for v, name in
                        ((vmax, "vmax"), (amax, "amax"), (jmax, "jmax")))
    lower, upper = per_joint(lower, dof, "lower", positive=False), per_joint(upper, dof, "upper", positive=False)
    non_negative(padding, "padding", "m")
    start, goal = seed_positions[0], seed_positions[-1]
    n = settings.intervals
    prob = _Problem(n, dof, settings, start, goal)
    c = bspline.control_from_samples(seed_positions, np.asarray(seed_times, float), float(seed_times[-1]), n)
    c[3:n] = np.clip(c[3:n], lower, upper)
    if end_rays and n >= 8:
        # an end near an obstacle keeps the seed's approach (the sphere cover is too coarse there)
        near = clearance.terms(np.stack([start, goal]), padding + settings.margin + settings.activation).config
        d_start, d_goal = _end_directions(seed_positions)
        prob.set_rays(d_start if 0 in near else None, d_goal if 1 in near else None, settings.ray_points)
        c = prob.project_rays(c)
    margin = padding + settings.margin
    h = float(seed_times[-1]) / n
    h_floor = max(min_duration, 0.0) / n  # no motion is faster than the lower bound
    h_max = max_duration / n
    h_low = h_floor
    fit = c
    second_chance = settings.second_chance
    best: tuple[np.ndarray, float] | None = None
    solves = 0
    message = ""
    radius = settings.trust_region
    for _ in range(settings.rounds):
        if time.perf_counter() > deadline or solves >= max_solves:
            break
        ok, c_new, used, why, radius = _sco(prob, c, h, radius, vmax, amax, jmax, lower, upper, clearance, margin,
                                            settings, deadline, max_solves - solves)
        # the next round starts from twice the last step size (a step rejected there would
        # be rejected at the same shape again)
        radius = min(settings.trust_region, 2.0 * radius)
        solves += used
        # the optimised shape, uniformly re-timed until a limit is active (limits are soft in the QP)
        h_star = bspline.limit_step(c_new, vmax, amax, jmax) if ok else np.inf
        logger.debug("trajopt: target T = %.3f s: %s, feasible T = %.3f s (%d QPs) %s", n * h,
                     "ok" if ok else "failed", n * h_star, used, why)
        if ok and (best is None or h_star < best[1]):
            best = (c_new, h_star)
        if second_chance and (best is None or best[1] >= h_max):
            # nothing usable at the seed's duration (the spline fitted to the seed exceeds the
            # limits there, and repairing both limits and clearance failed): once more from
            # the fit, at the duration where it is within the limits
            second_chance = False
            c, h, h_low, radius = fit, max(h, bspline.limit_step(fit, vmax, amax, jmax)), h_floor, settings.trust_region
            continue
        if best is None:
            message = why
            break
        if not ok or h_star > h * 1.02:
            h_low = max(h_low, h)  # this target was not reached
        if ok:
            c = c_new  # the next round goes on from this shape (straighter, even if not faster yet)
        h_best = best[1]
        if h_best - h_low <= settings.duration_tolerance * h_best:
            break
        # between the unreached target and the best (a target at or above max_duration
        # could only give slower motions than the one to beat)
        h = h_low + settings.bisection * (min(h_best, h_max) - h_low)
        if h >= h_max:
            break
    if best is None:
        return TrajOptResult(False, None, None, float("nan"), solves, message or "no time left", prob.ends_tied)
    c, h = best
    return TrajOptResult(True, bspline.to_profile(c, h), c, n * h, solves, "", prob.ends_tied)


def _sco(prob: _Problem, c0, h, radius, vmax, amax, jmax, lower, upper, clearance, margin, s: TrajOptSettings,
         deadline, max_solves=np.inf):
    """Sequential convex optimisation at step h (an L1 penalty method with a trust region).

    The velocity, acceleration and jerk limits at step h and the clearance above `margin`
    are soft (slack variables with `s.penalty`): the QP is always feasible, and the caller
    re-times the result exactly. A step is accepted when the true merit (objective plus the
    penalties of the limit excess and of the sampled clearance below the margin) decreases,
    else its half (`s.line_search` times) is tried; otherwise the trust region halves.

    Returns:
        (ok: the clearance stayed above the seed's floor, control points, QPs solved, why not
        ok, the trust region's radius at the end [rad]).
    """
    c = c0.copy()
    solves = 0
    G_lim, h_lim = _limit_rows(prob, h, vmax, amax, jmax)
    G_lim_slack = prob.limit_G_slack  # the same rows with their slack columns (-1)
    row_lim = _row_limits(prob, h, vmax, amax, jmax)
    P, q_lin = _objective(prob, h, vmax, amax, jmax, s)
    P_sparse = sp.csc_matrix(P)
    activation = margin + s.activation
    terms = clearance.terms(prob.B @ c, activation)
    floor = min(margin, _min_distance(terms, activation)) - 1e-3  # never worse than the seed
    merit = _merit(P, q_lin, c, prob, terms, margin, s.penalty, G_lim, h_lim)
    nx = P.shape[0]
    for _ in range(s.iterations):
        if time.perf_counter() > deadline or solves >= max_solves:
            break
        G_col, h_col = _collision_rows(prob, c, terms, margin)
        x0 = c[3 : prob.n]
        # rows: limit rows in use (> 1 - LIMIT_ROW_SLACK of their limit; the others cannot
        # become active within the trust region's first steps, and limits are soft anyway: the
        # result is re-timed exactly), then collision rows, each with its own slack (L1)
        keep = G_lim @ x0.T.ravel() - h_lim > -s.limit_row_slack * row_lim
        z = _solve_qp(prob, P_sparse, q_lin, G_lim_slack[keep], h_lim[keep], G_col, h_col, x0, radius, lower, upper, s)
        solves += 1
        if z is None:
            return False, c0, solves, "the QP solver failed", radius
        x = np.clip(z[:nx].reshape(prob.dof, -1).T, lower, upper)
        c_new = prob.control(x)
        terms_new = clearance.terms(prob.B @ c_new, activation)
        merit_new = _merit(P, q_lin, c_new, prob, terms_new, margin, s.penalty, G_lim, h_lim)
        for _ in range(s.line_search if merit_new > merit else 0):
            # half the step first (one clearance evaluation instead of a QP; a convex
            # combination keeps the bounds and the end rays)
            c_new = 0.5 * (c + c_new)
            terms_new = clearance.terms(prob.B @ c_new, activation)
            merit_new = _merit(P, q_lin, c_new, prob, terms_new, margin, s.penalty, G_lim, h_lim)
            if merit_new <= merit:
                break
        if merit_new > merit:
            radius *= 0.5  # the linearisation was too optimistic: smaller steps
            if radius < 1e-3:
                break
            continue
        step = float(np.max(np.abs(c_new - c)))
        converged = step < 1e-3 or merit - merit_new <= s.tolerance * abs(merit)
        c, terms, merit = c_new, terms_new, merit_new
        if converged:
            break
    if _min_distance(terms, activation) < floor:
        return False, c0, solves, "the clearance could not be kept at this duration", radius
    return True, c, solves, "", radius


def _check_seed(positions, times) -> tuple[np.ndarray, np.ndarray]:
    """The seed as float arrays (T, dof), (T,); raises InvalidInputError on bad shapes or values."""
    q = np.asarray(positions, dtype=float)
    t = np.asarray(times, dtype=float)
    if q.ndim != 2 or q.shape[0] < 2:
        raise InvalidInputError(f"seed_positions must have shape (T, dof) with T >= 2; got {q.shape}")
    if t.shape != (q.shape[0],):
        raise InvalidInputError(f"seed_times must have shape ({q.shape[0]},) like seed_positions' rows; got {t.shape}")
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(t))):
        raise InvalidInputError("seed_positions and seed_times must be finite")
    if t[0] != 0.0 or np.any(np.diff(t) <= 0):
        raise InvalidInputError("seed_times must start at 0 and increase strictly [s]")
    return q, t


def _end_directions(seed_positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directions [rad] of the seed's first and last straight stretches: from the start to the
    first sample where the motion turns, and from the goal back to the last such sample."""
    q = seed_positions

    def last_on_line(q0: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """From q0 to the farthest of `rows` (in order) still on the line through the first that moves."""
        direction = None
        best = None
        for r in rows:
            v = r - q0
            n = np.linalg.norm(v)
            if n < 1e-12:
                continue
            if direction is None:
                direction = v / n
            elif np.linalg.norm(v - (v @ direction) * direction) > 1e-6:
                break
            best = r
        if best is None:
            return rows[-1] - q0 if len(rows) else np.zeros_like(q0)
        return best - q0

    return last_on_line(q[0], q[1:]), last_on_line(q[-1], q[-2::-1])


def _merit(P, q_lin, c, prob: _Problem, terms, margin: float, penalty: float, G_lim, h_lim) -> float:
    """Objective plus L1 penalties of the sampled clearance below `margin` [m] and of the
    limits' excess: per derivative order and joint, the largest excess of its rows (in units
    of the limits' per-step values), as the QP's one slack per order and joint counts it."""
    x = c[3 : prob.n].T.ravel()
    violation = np.maximum(0.0, margin - terms.distance).sum() if terms.distance.size else 0.0
    largest = np.zeros(3 * prob.dof)
    np.maximum.at(largest, prob.limit_slack, G_lim @ x - h_lim)
    excess = largest.sum()
    return float(0.5 * x @ P @ x + q_lin @ x + penalty * (violation + excess))


def _solve_qp(prob: _Problem, P: sp.csc_matrix, q_lin, G_lim, h_lim, G_col, h_col, x0, radius, lower, upper,
              s: TrajOptSettings):
    """One SCO step's QP; the solution z = [x (dof * m), limit slacks (3 dof), ray parameters
    (R), clearance slacks (T)] (`planning.qp`), or None when the solver fails.

    minimise 1/2 x^T P x + q^T x + penalty * (slacks), subject to the kept limit rows and the
    clearance rows (each with its slack >= 0), the trust region and the position limits
    around x0 (m, dof), and the end rays (equalities).
    """
    nx, S, R = P.shape[0], 3 * prob.dof, len(prob.rays)
    L, T = h_lim.size, h_col.size
    nz = nx + S + R + T
    G_T = np.zeros((nz, L + T))
    G_T[: nx + S, :L] = G_lim.T
    G_T[:nx, L:] = G_col.T
    G_T[nx + S + R + np.arange(T), L + np.arange(T)] = -1.0
    h = np.concatenate([h_lim, h_col])
    qz = np.concatenate([q_lin, np.full(S, s.penalty), np.zeros(R), np.full(T, s.penalty)])
    lb = np.concatenate([np.maximum(lower[None, :], x0 - radius).T.ravel(), np.zeros(S + R + T)])
    ub = np.concatenate([np.minimum(upper[None, :], x0 + radius).T.ravel(), np.full(S, np.inf), np.ones(R),
                         np.full(T, np.inf)])
    A = qp.with_columns(prob.ray_A, T) if R else None
    return qp.solve(qp.regularised(P, nz - nx), qz, G_T, h, A, prob.ray_b if R else None, lb, ub, s.solver)


def _min_distance(terms, activation: float) -> float:
    return float(terms.distance.min()) if terms.distance.size else activation


def _limit_rows(prob: _Problem, h: float, vmax, amax, jmax) -> tuple[np.ndarray, np.ndarray]:
    """G x <= hv for the velocity, acceleration and jerk limits at step h (joint-major x)."""
    rhs = []
    lims = {1: vmax * h, 2: amax * h**2, 3: jmax * h**3}
    for (order, rows), fixed in zip(prob.limit_order, prob.limit_fixed):
        rhs.append(np.repeat(lims[order], rows) - fixed)
    return prob.limit_G, np.concatenate(rhs)


def _row_limits(prob: _Problem, h: float, vmax, amax, jmax) -> np.ndarray:
    """(L,) the limit of each limit row at step h [rad of control-point difference]."""
    lims = np.concatenate([vmax * h, amax * h**2, jmax * h**3])  # indexed like limit_slack
    return lims[prob.limit_slack]


def _objective(prob: _Problem, h: float, vmax, amax, jmax, s: TrajOptSettings):
    """P, q of 1/2 x^T P x + q^T x: weighted squared limit fractions of velocity, acceleration, jerk."""
    m = prob.free.size
    P = np.zeros((prob.dof * m, prob.dof * m))
    q = np.zeros(prob.dof * m)
    for order, lim, w in ((1, vmax * h, s.velocity_weight), (2, amax * h**2, s.acceleration_weight),
                          (3, jmax * h**3, s.jerk_weight)):
        DtD, Dtf = prob.cost[order]
        for i in range(prob.dof):
            k = 2 * w / lim[i] ** 2
            P[i * m : (i + 1) * m, i * m : (i + 1) * m] += k * DtD
            q[i * m : (i + 1) * m] += k * Dtf[:, i]
    P[np.diag_indices_from(P)] += 1e-6
    return P, q


def _collision_rows(prob: _Problem, c: np.ndarray, terms, margin: float):
    """G x <= hv linearising every clearance term: d + g . (q_m(x) - q_m) >= margin (before slack)."""
    if terms.config.size == 0:
        return np.zeros((0, prob.dof * prob.free.size)), np.zeros(0)
    q_m = prob.B[terms.config] @ c  # (T, dof)
    target = margin
    # g . (Bf x + fixed share) >= target - d + g . q_m
    Bf = prob.B_free[terms.config]  # (T, m)
    g = terms.gradient
    rhs = target - terms.distance + np.einsum("td,td->t", g, q_m - prob.q_fixed[terms.config])
    G = -(g[:, :, None] * Bf[:, None, :]).reshape(g.shape[0], -1)  # joint-major: (T, dof * m)
    return G, -rhs
