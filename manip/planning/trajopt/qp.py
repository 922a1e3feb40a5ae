"""The QP of one trajectory-optimisation step (`planning.trajopt.optimizer`), assembled and solved.

Variables z = [x (dof * m, joint-major control points), limit slacks (S), ray parameters (R),
clearance slacks (T)]; the clearance slacks come last so that the equality rows (the end
rays) have the same sparse structure whatever the number of clearance rows. The matrices go
straight to PIQP's sparse interface as CSC (for a QP this small, qpsolvers' checks and
conversions would cost more than the solve); any other solver is called through `qpsolvers`.
"""

from __future__ import annotations

import numpy as np
import piqp
import scipy.sparse as sp

from manip.jit import kernel

#: Regularisation of the slack and ray variables (their objective is linear).
SLACK_REGULARISATION = 1e-9

#: PIQP's absolute tolerance (primal and dual residuals, duality gap; the relative ones a tenth
#: of it), and its Ruiz equilibration scaling the objective too (`preconditioner_scale_cost`;
#: PIQP's default False) in one pass (PIQP's 10). Whole plans (MotionBenchMaker 20/scene, joint and
#: pose goals, seeds 0 and 1, 250 plans each) against 1e-6 / False / 10: the same QPs and motions
#: within noise (mean motion time / lower bound and path length within -0.5 .. +0.2 %), PIQP's
#: CPU per QP 0.76 x (9.7 interior-point iterations against 13.5, a cheaper setup); on 338 recorded QPs
#: the control points within 1.1e-3 rad of the 1e-6 solutions (median; max 1.5e-2). BENCHMARKS.md, "Round eleven".
PIQP_EPS = 3e-4
PIQP_SCALE_COST = True
PIQP_PRECONDITIONER_ITER = 1

_SOLVER_OPTIONS = {"osqp": {"eps_abs": 1e-6, "eps_rel": 1e-6, "polish": True, "verbose": False}}


@kernel
def _inequality_rows(lim_indptr, lim_indices, lim_data, keep, extra_col, extra_val, n_extra, n_rays, gradient,
                     config, B_free):
    """(data, indices, indptr, L) of `inequality_rows`' G in CSC; L: the limit rows kept."""
    nx = lim_indptr.shape[0] - 1
    rows = keep.shape[0]
    T, dof = gradient.shape
    m = B_free.shape[1]
    nz = nx + n_extra + n_rays + T
    new = np.full(rows, -1, np.int64)  # the kept limit rows' row indices in G
    L = 0
    for r in range(rows):
        if keep[r]:
            new[r] = L
            L += 1
    # the clearance rows touching each free point (its basis weight at the row's sample is not 0)
    by_point = np.empty((m, T), np.int64)
    on_point = np.zeros(m, np.int64)
    for t in range(T):
        for jj in range(m):
            if B_free[config[t], jj] != 0.0:
                by_point[jj, on_point[jj]] = t
                on_point[jj] += 1
    # the kept rows of each extra variable, in order
    by_extra = np.empty((n_extra, L), np.int64)
    on_extra = np.zeros(n_extra, np.int64)
    for r in range(rows):
        if keep[r] and extra_val[r] != 0.0:
            e = extra_col[r]
            by_extra[e, on_extra[e]] = r
            on_extra[e] += 1
    size = lim_indptr[nx] + dof * on_point.sum() + on_extra.sum() + T  # at most
    data = np.empty(size)
    indices = np.empty(size, np.int32)
    indptr = np.empty(nz + 1, np.int32)
    k = 0
    for j in range(nx):  # a control-point coordinate: its limit rows, then its clearance rows
        indptr[j] = k
        for p in range(lim_indptr[j], lim_indptr[j + 1]):
            r = lim_indices[p]
            if keep[r]:
                data[k] = lim_data[p]
                indices[k] = new[r]
                k += 1
        i, jj = j // m, j % m
        for q in range(on_point[jj]):
            t = by_point[jj, q]
            v = -(gradient[t, i] * B_free[config[t], jj])
            if v != 0.0:
                data[k] = v
                indices[k] = L + t
                k += 1
    for e in range(n_extra):  # the extra variables: their entries in the limit rows
        indptr[nx + e] = k
        for q in range(on_extra[e]):
            r = by_extra[e, q]
            data[k] = extra_val[r]
            indices[k] = new[r]
            k += 1
    for e in range(n_rays):  # the ray parameters: in no inequality
        indptr[nx + n_extra + e] = k
    for t in range(T):  # each clearance row's slack
        indptr[nx + n_extra + n_rays + t] = k
        data[k] = -1.0
        indices[k] = L + t
        k += 1
    indptr[nz] = k
    return data[:k], indices[:k], indptr, L


def inequality_rows(limit_G: sp.csc_matrix, keep: np.ndarray, extra_col: np.ndarray, extra_val: np.ndarray,
                    n_extra: int, n_rays: int, gradient: np.ndarray, config: np.ndarray,
                    B_free: np.ndarray) -> sp.csc_matrix:
    """The inequality rows G (L + T, nz) of one SCO step's QP (CSC), straight from their parts.

    Variables z = [x (nx = dof * m, joint-major), `n_extra` extra variables, `n_rays` ray
    parameters, T clearance slacks]. Rows: the limit rows of `limit_G` (rows, nx) where `keep`
    (rows,) is True, each with `extra_val[r]` in extra column `extra_col[r]`; then T clearance
    rows, row t = -gradient[t] (T, dof) times the sample's basis weights B_free[config[t]]
    (config (T,), B_free (M, m)) on x, and -1 on its slack. Exact zeros are left out.
    """
    gradient = np.ascontiguousarray(gradient, dtype=float)
    config = np.ascontiguousarray(config, dtype=np.int64)
    data, indices, indptr, L = _inequality_rows(limit_G.indptr, limit_G.indices, limit_G.data, keep, extra_col,
                                                extra_val, n_extra, n_rays, gradient, config, B_free)
    return csc(data, indices, indptr, (L + gradient.shape[0], indptr.size - 1))


def with_columns(M: sp.csc_matrix, extra: int) -> sp.csc_matrix:
    """M (r, c) with `extra` empty columns appended (CSC)."""
    indptr = np.concatenate([M.indptr, np.full(extra, M.indptr[-1], dtype=M.indptr.dtype)])
    return csc(M.data, M.indices, indptr, (M.shape[0], M.shape[1] + extra))


def regularised(P: sp.csc_matrix, extra: int) -> sp.csc_matrix:
    """The block-diagonal [[P, 0], [0, SLACK_REGULARISATION I (extra)]] (CSC)."""
    n = P.shape[0]
    return csc(np.concatenate([P.data, np.full(extra, SLACK_REGULARISATION)]),
               np.concatenate([P.indices, n + np.arange(extra, dtype=P.indices.dtype)]),
               np.concatenate([P.indptr, P.indptr[-1] + 1 + np.arange(extra, dtype=P.indptr.dtype)]),
               (n + extra, n + extra))


def _unchecked_csc(data: np.ndarray, indices: np.ndarray, indptr: np.ndarray, shape: tuple) -> sp.csc_matrix:
    """The CSC matrix of these arrays, taken as they are (scipy's constructor, ~40 us, checks the
    index types and contents; a QP's assembly makes three)."""
    M = sp.csc_matrix.__new__(sp.csc_matrix)
    M.data, M.indices, M.indptr, M._shape, M._maxprint = data, indices, indptr, shape, 50
    return M


def _checked_csc(data: np.ndarray, indices: np.ndarray, indptr: np.ndarray, shape: tuple) -> sp.csc_matrix:
    return sp.csc_matrix((data, indices, indptr), shape=shape)


def _unchecked_works() -> bool:
    """True when this scipy's csc_matrix built by `_unchecked_csc` behaves as the checked one
    (it sets scipy's own attributes: a scipy release could rename them)."""
    try:
        args = (np.array([1.0, 2.0]), np.array([1, 0], np.int32), np.array([0, 1, 2], np.int32), (2, 2))
        M, C = _unchecked_csc(*args), _checked_csc(*args)
        return M.shape == C.shape and M.nnz == C.nnz and np.array_equal(M.toarray(), C.toarray()) and \
            np.array_equal(M @ np.array([1.0, 3.0]), C @ np.array([1.0, 3.0]))
    except Exception:  # noqa: BLE001 (any failure means: use the checked constructor)
        return False


def csc(data: np.ndarray, indices: np.ndarray, indptr: np.ndarray, shape: tuple) -> sp.csc_matrix:
    """A CSC matrix (shape (r, c)) of data (nnz,), int32 row indices (nnz,) sorted within each
    column and int32 column pointers (c + 1,), without copies; the caller guarantees the
    structure (the QP's parts are built valid), so scipy's checks are skipped when this scipy
    allows it."""
    return _CSC(data, indices, indptr, shape)


_CSC = _unchecked_csc if _unchecked_works() else _checked_csc


def installed_solvers() -> list[str]:
    """The solvers `solve` can use: "piqp" (called directly) and those qpsolvers has installed."""
    import qpsolvers  # only off the default path (its import costs ~70 ms per process)

    return sorted({"piqp", *qpsolvers.available_solvers})


def solver_available(name: object) -> bool:
    """True when `solve` can use the solver `name`."""
    return name == "piqp" or (isinstance(name, str) and name in installed_solvers())


def solve(P: sp.csc_matrix, q: np.ndarray, G: sp.csc_matrix, h: np.ndarray, A: sp.csc_matrix | None,
          b: np.ndarray | None, lb: np.ndarray, ub: np.ndarray, solver: str) -> np.ndarray | None:
    """argmin 1/2 z^T P z + q^T z subject to G z <= h, A z = b, lb <= z <= ub, or None when
    the solver fails.

    Args:
        P: (n, n) positive semidefinite (CSC).
        q: (n,).
        G: (k, n) the inequality rows (CSC).
        h: (k,).
        A, b: (e, n) (CSC), (e,); None for no equalities.
        lb, ub: (n,) bounds (+-inf for none).
        solver: "piqp" (its sparse interface) or any `qpsolvers` solver name.
    """
    if solver == "piqp":
        qp = piqp.SparseSolver()
        qp.settings.verbose = False
        qp.settings.eps_abs = qp.settings.eps_duality_gap_abs = PIQP_EPS
        qp.settings.eps_rel = qp.settings.eps_duality_gap_rel = PIQP_EPS * 0.1
        qp.settings.preconditioner_scale_cost = PIQP_SCALE_COST
        qp.settings.preconditioner_iter = PIQP_PRECONDITIONER_ITER
        qp.setup(P, q, A, b, G, None, h, lb, ub)
        return qp.result.x.copy() if qp.solve() == piqp.PIQP_SOLVED else None
    import qpsolvers  # only off the default path (its import costs ~70 ms per process)

    if solver in qpsolvers.dense_solvers:  # the others take CSC matrices
        P, G = P.toarray(), G.toarray()
        A = None if A is None else A.toarray()
    return qpsolvers.solve_qp(P, q, G, h, A, b, lb=lb, ub=ub, solver=solver, **_SOLVER_OPTIONS.get(solver, {}))
