"""Sequential convex optimisation (SCO) of a B-spline motion: the steps of `planning.trajopt.optimizer`.

`SplineProblem` holds what depends only on the number of pieces N and the end configurations
(difference, sample and limit matrices, the end rays). Two SCO loops (L1 penalty methods with
a trust region; each iteration one QP, `planning.trajopt.qp`) share it:

- `sco_fixed_step`: the control points at a fixed knot step h, minimising the weighted
  squared velocity/acceleration/jerk fractions of the limits; the limits and the clearance
  are soft (penalised slacks), the caller re-times the result exactly.
- `sco_free_step`: the control points and h together, minimising the duration N h (plus the
  same regulariser at the starting step); the limits are hard rows linearised in h from
  below (h^2 >= 2 h0 h - h0^2, h^3 >= 3 h0^2 h - 2 h0^3), so every QP solution respects the
  true limits at its h; the clearance is soft. A step is kept when the merit falls and the
  sampled clearance stays above the floor; the trust region follows the ratio of actual to
  predicted decrease.
"""

from __future__ import annotations

import math
import time
from functools import lru_cache

import numpy as np
import scipy.sparse as sp

from manip.collision.clearance import ClearanceModel
from manip.limits import JointLimits
from manip.planning.trajopt import bspline, qp, sco_kernels
from manip.planning.trajopt.settings import TrajOptSettings


@lru_cache(maxsize=16)
def _blocks(n: int, dof: int, samples_per_interval: int) -> dict:
    """The blocks of `SplineProblem` that depend only on N, the dof and the sampling (read-only,
    shared by every problem of that size: building them costs ~1.2 ms)."""
    free = np.arange(3, n)
    fixed = np.setdiff1d(np.arange(n + 3), free)
    D = {k: bspline.difference_matrix(n + 3, k) for k in (1, 2, 3)}
    B, sample_t = bspline.basis_matrix(n, samples_per_interval)
    eye = np.eye(dof)
    limit_G, limit_order, limit_slack, per_order = [], [], [], {}
    for k in (1, 2, 3):
        Df = D[k][:, free]
        rows = np.flatnonzero(np.any(Df != 0, axis=1))
        G = np.kron(eye, Df[rows])
        limit_G += [G, -G]
        limit_order += [(k, rows.size)] * 2
        limit_slack += [np.repeat((k - 1) * dof + np.arange(dof), rows.size)] * 2
        # (fixed points' rows of the limit rows, D on the fixed points, Df^T Df, Df^T)
        per_order[k] = (D[k][rows][:, fixed], D[k][:, fixed], Df.T @ Df, Df.T)
    limit_G = np.vstack(limit_G)
    limit_slack = np.concatenate(limit_slack)
    limit_G_csc = sp.csc_matrix(limit_G)  # the QP's rows are assembled from its columns (`qp.inequality_rows`)
    limit_G_csc.sort_indices()
    # the limit rows come in runs of one slack (order, joint) each, every slack twice (+G, -G)
    runs = np.flatnonzero(np.diff(limit_slack, prepend=-1) != 0)
    run_slack = limit_slack[runs]
    blocks = {"free": free, "fixed": fixed, "D": D, "B": B, "sample_t": sample_t, "B_free": B[:, free],
              "B_fixed": B[:, fixed], "limit_G": limit_G, "limit_G_sparse": sp.csr_matrix(limit_G),
              "limit_G_csc": limit_G_csc, "limit_order": limit_order, "limit_slack": limit_slack,
              "limit_runs": runs, "limit_run_pairs": np.stack([np.flatnonzero(run_slack == j) for j in range(3 * dof)]),
              "per_order": per_order}
    for a in [v for v in blocks.values() if isinstance(v, np.ndarray)] + [m for t in per_order.values() for m in t]:
        a.flags.writeable = False
    return blocks


class SplineProblem:
    """The QP data that depend only on N, the start and the goal (the constant blocks, per joint)."""

    def __init__(self, n: int, dof: int, s: TrajOptSettings, start: np.ndarray, goal: np.ndarray):
        self.n, self.dof = n, dof
        b = _blocks(n, dof, s.samples_per_interval)
        self.free, self.fixed = b["free"], b["fixed"]  # indices of the free / fixed control points
        self.c_fixed = np.empty((n + 3, dof))
        self.c_fixed[:3] = start
        self.c_fixed[n:] = goal
        self.D, self.B, self.sample_t, self.B_free = b["D"], b["B"], b["sample_t"], b["B_free"]
        self.rays: list = []  # (control point index, anchor (dof,), direction (dof,))
        self._ray_rows: dict = {}  # ray_rows() by gap
        self.ends_tied = 0
        fixed_c = self.c_fixed[self.fixed]
        self.q_fixed = b["B_fixed"] @ fixed_c  # (M, dof) fixed points' share
        # limit rows: per order, rows touching a free point; G = +-kron(I, Df), rhs = lim -+ fixed share
        self.limit_G, self.limit_order = b["limit_G"], b["limit_order"]
        # the same rows sparse (~1 % filled): their products with x, without a threaded dense BLAS call;
        # and by columns, for the QP's assembly
        self.limit_G_sparse, self.limit_G_csc = b["limit_G_sparse"], b["limit_G_csc"]
        self.limit_slack = b["limit_slack"]  # (L,) each row's slack: (order - 1) * dof + joint
        # (runs,) first row of each run of rows of one slack; (3 dof, 2) the two runs of each slack
        self.limit_runs, self.limit_run_pairs = b["limit_runs"], b["limit_run_pairs"]
        limit_fixed, self.cost = [], {}
        for k in (1, 2, 3):
            rows_fixed, D_fixed, DtD, Dt = b["per_order"][k]
            share = (rows_fixed @ fixed_c).T.ravel()  # joint-major (dof * R,)
            limit_fixed += [share, -share]
            self.cost[k] = (DtD, Dt @ (D_fixed @ fixed_c))  # (m, m), (m, dof)
        self.limit_fixed = np.concatenate(limit_fixed)  # (L,) the fixed points' share of each limit row

    def set_rays(self, d_start: np.ndarray | None, d_goal: np.ndarray | None, points: int) -> None:
        """Tie the first `points` free control points to start + a d_start and the last ones to
        goal + b d_goal (0 <= a, b <= 1); None leaves that end free."""
        n = self.n
        self.rays = []
        self._ray_rows = {}
        self.ends_tied = (d_start is not None) + (d_goal is not None)
        for k in range(points):
            if d_start is not None:
                self.rays.append((3 + k, self.c_fixed[0], d_start))
            if d_goal is not None:
                self.rays.append((n - 1 - k, self.c_fixed[n], d_goal))

    def ray_rows(self, gap: int, after: int = 0) -> tuple[sp.csc_matrix | None, np.ndarray | None]:
        """The end rays' equalities A z = b (A over the columns [x, `gap` others, R, `after` others],
        `planning.trajopt.qp`), or (None, None) without rays."""
        if not self.rays:
            return None, None
        if (gap, after) in self._ray_rows:
            return self._ray_rows[gap, after]
        if after:
            A, b = self.ray_rows(gap)
            self._ray_rows[gap, after] = qp.with_columns(A, after), b
            return self._ray_rows[gap, after]
        m, dof = self.free.size, self.dof
        A = np.zeros((len(self.rays) * dof, dof * m + gap + len(self.rays)))
        b = np.zeros(len(self.rays) * dof)
        for r, (k, anchor, d) in enumerate(self.rays):
            for i in range(dof):
                A[r * dof + i, i * m + (k - 3)] = 1.0
                A[r * dof + i, dof * m + gap + r] = -d[i]
                b[r * dof + i] = anchor[i]
        A_csc = _csc(A)  # exact zeros left out, row indices sorted
        self._ray_rows[gap, 0] = A_csc, b
        return self._ray_rows[gap, 0]

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


def sco_fixed_step(prob: SplineProblem, c0: np.ndarray, h: float, radius: float, *, limits: JointLimits,
                   clearance: ClearanceModel, margin: float, settings: TrajOptSettings, deadline: float,
                   max_solves: float = np.inf, iterations: int | None = None):
    """Sequential convex optimisation at step h (an L1 penalty method with a trust region).

    `limits`: the call's scaled limits (with position limits); `margin` [m]; `radius`: the
    trust region's first radius [rad]; `deadline`: a `time.perf_counter()` value;
    `iterations`: at most (None: `settings.iterations`).

    The velocity, acceleration and jerk limits at step h and the clearance above `margin`
    are soft (slack variables with `s.penalty`): the QP is always feasible, and the caller
    re-times the result exactly. A step is accepted when the true merit (objective plus the
    penalties of the limit excess and of the sampled clearance below the margin) decreases,
    else its half (`s.line_search` times) is tried; otherwise the trust region halves.

    Returns:
        (ok: the clearance stayed above the seed's floor, control points, QPs solved, why not
        ok, the trust region's radius at the end [rad]).
    """
    s = settings
    lower, upper = limits.lower, limits.upper
    c = c0.copy()
    solves = 0
    row_lim = _row_limits(prob, h, limits)
    h_lim = row_lim - prob.limit_fixed  # the limit rows' right-hand sides
    S = 3 * prob.dof  # one slack per derivative order and joint, >= 0, L1-penalised (-1 in its limit rows)
    slack_col, slack_val = prob.limit_slack.copy(), np.full(prob.limit_slack.size, -1.0)
    slack_cost, slack_lb, slack_ub = np.full(S, s.penalty), np.zeros(S), np.full(S, np.inf)
    P_sparse, q_lin = _objective(prob, h, limits, s)
    regularised: dict = {}  # `qp.regularised(P_sparse, extra)` by extra
    activation = margin + s.activation
    terms = clearance.terms(prob.B @ c, activation)
    floor = min(margin, _min_distance(terms, activation)) - 1e-3  # never worse than the seed
    merit = _merit(P_sparse, q_lin, c, prob, terms, margin, s.penalty, h_lim)
    nx = P_sparse.shape[0]
    for _ in range(s.iterations if iterations is None else iterations):
        if time.perf_counter() > deadline or solves >= max_solves:
            break
        h_col = _collision_rows(prob, c, terms, margin)
        x0 = c[3 : prob.n]
        # rows: limit rows in use (> 1 - LIMIT_ROW_SLACK of their limit; the others cannot
        # become active within the trust region's first steps, and limits are soft anyway: the
        # result is re-timed exactly), then collision rows, each with its own slack (L1)
        keep, _ = _limit_rows(prob, x0, row_lim, s)
        z = _solve_qp(prob, P_sparse, q_lin, keep, slack_col, slack_val, S, h_lim[keep], terms, h_col, x0, radius,
                      lower, upper, s, slack_cost, slack_lb, slack_ub, regularised)
        solves += 1
        if z is None:
            return False, c0, solves, "the QP solver failed", radius
        x = np.clip(z[:nx].reshape(prob.dof, -1).T, lower, upper)
        c_new = prob.control(x)
        terms_new = clearance.terms(prob.B @ c_new, activation)
        merit_new = _merit(P_sparse, q_lin, c_new, prob, terms_new, margin, s.penalty, h_lim)
        for _ in range(s.line_search if merit_new > merit else 0):
            # half the step first (one clearance evaluation instead of a QP; a convex
            # combination keeps the bounds and the end rays)
            c_new = 0.5 * (c + c_new)
            terms_new = clearance.terms(prob.B @ c_new, activation)
            merit_new = _merit(P_sparse, q_lin, c_new, prob, terms_new, margin, s.penalty, h_lim)
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


def sco_free_step(prob: SplineProblem, c0: np.ndarray, *, limits: JointLimits, clearance: ClearanceModel,
                  margin: float, settings: TrajOptSettings, deadline: float, h_floor: float,
                  max_solves: float = np.inf) -> tuple[np.ndarray, int]:
    """SCO over the control points and the knot step h together, from c0 (N + 3, dof).

    Minimises `s.time_weight` h / h0 (h0: c0's step) plus the regulariser of `_objective` at
    h0 and the L1 penalty of the sampled clearance below `margin` [m]; the limits are hard
    rows, linear in h from below (every QP solution respects the true limits at its own h),
    and h >= `h_floor` [s]. A step is kept when the merit falls and the sampled clearance
    stays above c0's (less 1 mm, never above the margin).

    Returns:
        (control points (N + 3, dof) no worse than c0, QPs solved); their shortest step is
        `bspline.limit_step`.
    """
    s = settings
    lower, upper = limits.lower, limits.upper
    n, dof = prob.n, prob.dof
    c = c0.copy()
    h_ref = _polygon_step(c, limits)
    P_sparse, q_lin = _objective(prob, h_ref, limits, s)
    regularised: dict = {}  # `qp.regularised(P_sparse, extra)` by extra
    nx, R = P_sparse.shape[0], len(prob.rays)
    order = prob.limit_slack // dof + 1  # (L,) the derivative order of each limit row
    h_column = np.zeros(order.size, dtype=np.int64)  # every limit row has h in extra column 0
    activation = margin + s.activation
    terms = clearance.terms(prob.B @ c, activation)
    floor = min(margin, _min_distance(terms, activation)) - 1e-3
    weight = s.time_weight / h_ref

    def merit_of(c_: np.ndarray, terms_) -> tuple[float, float]:
        """(the merit of c_, its `_polygon_step`)."""
        x = c_[3:n].T.ravel()
        h_ = _polygon_step(c_, limits)
        return float(weight * h_ + 0.5 * x @ _csc_matvec(P_sparse, x) + q_lin @ x + s.penalty * _violation(terms_, margin)), h_

    merit, h_c = merit_of(c, terms)  # h_c: c's `_polygon_step`
    radius = s.trust_region
    solves = 0
    while solves < min(s.free_iterations, max_solves) and time.perf_counter() <= deadline:
        h = h_c
        x0 = c[3:n]
        row_lim = _row_limits(prob, h, limits)
        keep, h_lim = _limit_rows(prob, x0, row_lim, s)
        # G x <= lim(h') - fixed share, with lim(h') >= lim(h) (k h' / h - (k - 1)) for order k
        k, lim = order[keep], row_lim[keep]
        h_col = _collision_rows(prob, c, terms, margin)
        h_col_of_rows = -row_lim * order / h  # the rows' entries in the h column
        z = _solve_qp(prob, P_sparse, q_lin, keep, h_column, h_col_of_rows, 1, h_lim[keep] - k * lim, terms, h_col,
                      x0, radius, lower, upper, s,
                      np.array([weight]), np.array([max(h_floor, 0.5 * h)]), np.array([2.0 * h]), regularised)
        solves += 1
        if z is None:
            break
        xz = z[:nx]
        predicted = merit - float(0.5 * xz @ _csc_matvec(P_sparse, xz) + q_lin @ xz + weight * z[nx] + s.penalty * z[nx + 1 + R:].sum())
        c_new = prob.control(np.clip(xz.reshape(dof, -1).T, lower, upper))
        step = float(np.max(np.abs(c_new - c)))
        for half in range(s.line_search + 1):
            if half:  # half the step (a clearance evaluation, not a QP; keeps the bounds and rays)
                c_new, predicted, step = 0.5 * (c + c_new), 0.5 * predicted, 0.5 * step
            terms_new = clearance.terms(prob.B @ c_new, activation)
            merit_new, h_new = merit_of(c_new, terms_new)
            better = merit_new < merit and _min_distance(terms_new, activation) >= floor
            if better or predicted <= s.tolerance * weight * h:
                break
        if better:
            ratio = (merit - merit_new) / max(predicted, 1e-12)
            c, terms, merit, h_c = c_new, terms_new, merit_new, h_new
        if predicted <= s.tolerance * weight * h:
            break  # less than `tolerance` of the duration left to gain, by the model
        if not better or ratio < 0.25:
            radius = 0.5 * step  # the linearisation was too optimistic
        elif ratio > 0.75 and step > 0.9 * radius:
            radius = min(s.trust_region, 2.0 * radius)
        if radius < 1e-3:
            break
    return c, solves


def _polygon_step(c: np.ndarray, limits: JointLimits) -> float:
    """The shortest step h [s] at which the control points' differences (N + 3, dof) respect
    the limits as the QP rows count them (velocity by the control polygon, so h >=
    `bspline.limit_step`)."""
    r1, r2, r3 = sco_kernels.polygon_ratios(c, limits.velocity, limits.acceleration, limits.jerk)
    return float(max(r1, math.sqrt(r2), np.cbrt(r3), 1e-9))


def _limit_rows(prob: SplineProblem, x0: np.ndarray, row_lim: np.ndarray, s: TrajOptSettings):
    """(keep (L,) bool: the limit rows in use at x0 (m, dof), more than 1 - `s.limit_row_slack`
    of their limit `row_lim` (L,); h_lim (L,): their right-hand sides, row_lim - fixed share)."""
    G = prob.limit_G_sparse
    return sco_kernels.limit_rows(G.indptr, G.indices, G.data, x0.T.ravel(), row_lim, prob.limit_fixed,
                                  float(s.limit_row_slack))


def _merit(P: sp.csc_matrix, q_lin, c, prob: SplineProblem, terms, margin: float, penalty: float, h_lim) -> float:
    """Objective plus L1 penalties of the sampled clearance below `margin` [m] and of the
    limits' excess: per derivative order and joint, the largest excess of its rows (in units
    of the limits' per-step values), as the QP's one slack per order and joint counts it."""
    x = c[3 : prob.n].T.ravel()
    run_max = np.maximum.reduceat(_csr_matvec(prob.limit_G_sparse, x) - h_lim, prob.limit_runs)
    pairs = prob.limit_run_pairs
    largest = np.maximum(np.maximum(run_max[pairs[:, 0]], run_max[pairs[:, 1]]), 0.0)
    return float(0.5 * x @ _csc_matvec(P, x) + q_lin @ x + penalty * (_violation(terms, margin) + largest.sum()))


def _violation(terms, margin: float) -> float:
    """Sum [m] of the sampled clearance terms' shortfall below `margin`."""
    return float(np.maximum(0.0, margin - terms.distance).sum()) if terms.distance.size else 0.0


def _solve_qp(prob: SplineProblem, P: sp.csc_matrix, q_lin, keep, extra_col, extra_val, E: int, h_lim, terms, h_col,
              x0, radius, lower, upper, s: TrajOptSettings, q_extra, lb_extra, ub_extra, regularised: dict):
    """One SCO step's QP; the solution z = [x (dof * m), E extra variables, ray parameters (R),
    clearance slacks (T)] (`planning.trajopt.qp`), or None when the solver fails.

    minimise 1/2 x^T P x + q^T x + q_extra . extra + penalty * (clearance slacks), subject to
    the limit rows of `prob` where `keep` (each with `extra_val` in the extra column `extra_col`)
    <= h_lim (of the kept rows), the clearance rows of `terms` <= h_col (each with its slack
    >= 0), the trust region and the position limits around x0 (m, dof), lb_extra <= extra <=
    ub_extra (E,), and the end rays (equalities). The extra variables: the limit slacks of
    `sco_fixed_step` or the step h of `sco_free_step`. `regularised`: the caller's cache of
    `qp.regularised(P, extra)` by extra (P is the same for all of one SCO loop's QPs).
    """
    nx, R = P.shape[0], len(prob.rays)
    T = h_col.size
    nz = nx + E + R + T
    G = qp.inequality_rows(prob.limit_G_csc, keep, extra_col, extra_val, E, R, terms.gradient, terms.config,
                           prob.B_free)
    h = np.concatenate([h_lim, h_col])
    qz = np.concatenate([q_lin, q_extra, np.zeros(R), np.full(T, s.penalty)])
    lb, ub = sco_kernels.bounds(x0, float(radius), lower, upper, lb_extra, ub_extra, R, T)
    P_reg = regularised.get(nz - nx)
    if P_reg is None:
        P_reg = regularised[nz - nx] = qp.regularised(P, nz - nx)
    A, b = prob.ray_rows(E, T)
    return qp.solve(P_reg, qz, G, h, A, b, lb, ub, s.solver)


def _csc_matvec(M: sp.csc_matrix, x: np.ndarray) -> np.ndarray:
    """M @ x (M CSC (r, c), x (c,) contiguous), bit for bit SciPy's product without its dispatch
    (~8 of its ~10 us; a few per SCO iteration)."""
    return sco_kernels.csc_matvec(M.indptr, M.indices, M.data, x, M.shape[0])


def _csr_matvec(M: sp.csr_matrix, x: np.ndarray) -> np.ndarray:
    """M @ x (M CSR (r, c), x (c,) contiguous), as `_csc_matvec`."""
    return sco_kernels.csr_matvec(M.indptr, M.indices, M.data, x)


def _min_distance(terms, activation: float) -> float:
    return float(terms.distance.min()) if terms.distance.size else activation


def _csc(P: np.ndarray) -> sp.csc_matrix:
    """`sp.csc_matrix(P)` of a dense P (the same nonzeros in the same order), without scipy's
    conversion through COO."""
    cols, rows = np.nonzero(P.T)  # by column, rows ascending (exact zeros left out)
    indptr = np.zeros(P.shape[1] + 1, dtype=np.int32)
    np.cumsum(np.bincount(cols, minlength=P.shape[1]), out=indptr[1:])
    return qp.csc(P.T[cols, rows], rows.astype(np.int32), indptr, P.shape)  # valid by construction


def _row_limits(prob: SplineProblem, h: float, limits: JointLimits) -> np.ndarray:
    """(L,) the limit of each limit row at step h [rad of control-point difference]."""
    lims = np.concatenate([limits.velocity * h, limits.acceleration * h**2, limits.jerk * h**3])  # indexed like limit_slack
    return lims[prob.limit_slack]


def _objective(prob: SplineProblem, h: float, limits: JointLimits, s: TrajOptSettings):
    """P (CSC (dof m, dof m)), q (dof m,) of 1/2 x^T P x + q^T x: weighted squared limit fractions of
    velocity, acceleration, jerk (P block diagonal, one block per joint, plus 1e-6 I)."""
    m, dof = prob.free.size, prob.dof
    blocks = np.zeros((dof, m, m))  # P's diagonal block of each joint, the orders added in turn
    q = np.zeros((dof, m))
    for order, lim, w in ((1, limits.velocity * h, s.velocity_weight),
                          (2, limits.acceleration * h**2, s.acceleration_weight),
                          (3, limits.jerk * h**3, s.jerk_weight)):
        DtD, Dtf = prob.cost[order]
        k = np.array([2 * w / lim[i] ** 2 for i in range(dof)])
        blocks += k[:, None, None] * DtD
        q += k[:, None] * Dtf.T
    blocks.reshape(dof, m * m)[:, :: m + 1] += 1e-6  # the diagonal
    # straight to CSC (the dense P's nonzeros by column, rows ascending, as `_csc` of it): per
    # joint, per column, the block's nonzero rows
    Bt = blocks.transpose(0, 2, 1)
    joint, col, row = np.nonzero(Bt)
    indptr = np.zeros(dof * m + 1, dtype=np.int32)
    np.cumsum(np.bincount(joint * m + col, minlength=dof * m), out=indptr[1:])
    return qp.csc(Bt[joint, col, row], (joint * m + row).astype(np.int32), indptr, (dof * m, dof * m)), q.ravel()


def _collision_rows(prob: SplineProblem, c: np.ndarray, terms, margin: float) -> np.ndarray:
    """hv (T,) of the rows G x <= hv linearising every clearance term: d + g . (q_m(x) - q_m) >=
    margin (before slack); G's rows, -g (x) the sample's basis weights on the free points, are
    assembled with the QP (`qp.inequality_rows`)."""
    if terms.config.size == 0:
        return np.zeros(0)
    q_m = prob.B[terms.config] @ c  # (T, dof)
    # g . (Bf x + fixed share) >= margin - d + g . q_m
    rhs = margin - terms.distance + np.einsum("td,td->t", terms.gradient, q_m - prob.q_fixed[terms.config])
    return -rhs
