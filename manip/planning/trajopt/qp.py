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
#: of it). 1e-6 against PIQP's 1e-8 on 223 QPs recorded from MotionBenchMaker plans: 15.2
#: interior-point iterations against 16.5 (-8 %), solutions within 2e-3 rad; whole plans
#: (MBM 8/scene, joint and pose goals, ~50 each): the same mean motion time and QPs to 0.01 %
#: (1e-5: -13 % iterations, but motion times move by up to 1.8 % on a set).
PIQP_EPS = 1e-6

_SOLVER_OPTIONS = {"osqp": {"eps_abs": 1e-6, "eps_rel": 1e-6, "polish": True, "verbose": False}}


@kernel
def _nonzeros_by_row(M: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(data, indices, indptr) of M (r, c) compressed by rows (= M.T in CSC)."""
    r, c = M.shape
    nnz = 0
    for i in range(r):
        for j in range(c):
            if M[i, j] != 0.0:
                nnz += 1
    data = np.empty(nnz)
    indices = np.empty(nnz, np.int32)
    indptr = np.empty(r + 1, np.int32)
    k = 0
    for i in range(r):
        indptr[i] = k
        for j in range(c):
            v = M[i, j]
            if v != 0.0:
                data[k] = v
                indices[k] = j
                k += 1
    indptr[r] = k
    return data, indices, indptr


def csc_of_transpose(MT: np.ndarray) -> sp.csc_matrix:
    """The CSC matrix M (c, r) of its dense transpose MT (r, c) (row i of MT = column i of M)."""
    MT = np.ascontiguousarray(MT, dtype=float)
    data, indices, indptr = _nonzeros_by_row(MT)
    return sp.csc_matrix((data, indices, indptr), shape=(MT.shape[1], MT.shape[0]))


def with_columns(M: sp.csc_matrix, extra: int) -> sp.csc_matrix:
    """M (r, c) with `extra` empty columns appended (CSC)."""
    indptr = np.concatenate([M.indptr, np.full(extra, M.indptr[-1], dtype=M.indptr.dtype)])
    return sp.csc_matrix((M.data, M.indices, indptr), shape=(M.shape[0], M.shape[1] + extra))


def regularised(P: sp.csc_matrix, extra: int) -> sp.csc_matrix:
    """The block-diagonal [[P, 0], [0, SLACK_REGULARISATION I (extra)]] (CSC)."""
    n = P.shape[0]
    return sp.csc_matrix(
        (np.concatenate([P.data, np.full(extra, SLACK_REGULARISATION)]),
         np.concatenate([P.indices, n + np.arange(extra, dtype=P.indices.dtype)]),
         np.concatenate([P.indptr, P.indptr[-1] + 1 + np.arange(extra, dtype=P.indptr.dtype)])),
        shape=(n + extra, n + extra),
    )


def installed_solvers() -> list[str]:
    """The solvers `solve` can use: "piqp" (called directly) and those qpsolvers has installed."""
    import qpsolvers  # only off the default path (its import costs ~70 ms per process)

    return sorted({"piqp", *qpsolvers.available_solvers})


def solver_available(name: object) -> bool:
    """True when `solve` can use the solver `name`."""
    return name == "piqp" or (isinstance(name, str) and name in installed_solvers())


def solve(P: sp.csc_matrix, q: np.ndarray, G_T: np.ndarray, h: np.ndarray, A: sp.csc_matrix | None,
          b: np.ndarray | None, lb: np.ndarray, ub: np.ndarray, solver: str) -> np.ndarray | None:
    """argmin 1/2 z^T P z + q^T z subject to G z <= h, A z = b, lb <= z <= ub, or None when
    the solver fails.

    Args:
        P: (n, n) positive semidefinite (CSC).
        q: (n,).
        G_T: (n, k) the inequality rows, transposed (dense).
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
        qp.setup(P, q, A, b, csc_of_transpose(G_T), None, h, lb, ub)
        return qp.result.x.copy() if qp.solve() == piqp.PIQP_SOLVED else None
    import qpsolvers  # only off the default path (its import costs ~70 ms per process)

    G = csc_of_transpose(G_T)
    if solver in qpsolvers.dense_solvers:  # the others take CSC matrices
        P, G = P.toarray(), G.toarray()
        A = None if A is None else A.toarray()
    return qpsolvers.solve_qp(P, q, G, h, A, b, lb=lb, ub=ub, solver=solver, **_SOLVER_OPTIONS.get(solver, {}))
