"""The QP of a control step, solved through qpsolvers.

The step's QP is small and dense: 7 variables with simple bounds (joint position,
velocity and acceleration limits) and the few collision rows that are active (0 to ~8).
Measured on 1,300 of these QPs from the figure-eight of examples/follow_target.py (the
box in the way), through `qpsolvers.solve_qp`, on the 2-core machine under load:

=========  ===========  ==========  =========================================
solver     median [us]  p99 [us]    largest difference from DAQP's solution
=========  ===========  ==========  =========================================
daqp       64           314         (reference; exact active-set solution)
quadprog   62           521         3e-14 (exact too; raises on infeasible QPs)
piqp       67           160         8.5e-4 rad (interior point, default tolerances)
proxqp     153          357         7.5e-3 rad
osqp       1772         2677        3.0e-2 rad (ADMM, sparse matrices)
=========  ===========  ==========  =========================================

DAQP is the default: as fast as quadprog and as exact (active-set solvers finish such a
small QP in a handful of iterations), and it reports an infeasible QP as such instead of
raising. The first-order solvers' (PIQP, ProxQP, OSQP) default tolerances leave errors of
1e-3 to 3e-2 rad per step, which show as jitter in the command.
"""

from __future__ import annotations

import logging
import warnings

import numpy as np
import qpsolvers

from manip.errors import InvalidInputError

logger = logging.getLogger(__name__)

#: The QP solver used unless another is named.
DEFAULT_SOLVER = "daqp"
#: The solvers this controller was measured with (any qpsolvers backend installed works).
MEASURED_SOLVERS = ("daqp", "quadprog", "piqp", "proxqp", "osqp")


def check_solver(solver: str) -> str:
    """`solver` if qpsolvers has it installed.

    Raises:
        InvalidInputError: unknown or not installed (the message lists the installed ones
            and the pip package to add).
    """
    if not isinstance(solver, str):
        raise InvalidInputError(f"solver must be a qpsolvers backend name; got {solver!r}")
    if solver not in qpsolvers.available_solvers:
        raise InvalidInputError(
            f"solver {solver!r} is not available; installed QP solvers: {', '.join(sorted(qpsolvers.available_solvers))} "
            f"(install one with pip, e.g. 'pip install daqp', 'pip install quadprog', 'pip install proxsuite', "
            f"'pip install osqp')"
        )
    return solver


def solve_qp(P: np.ndarray, c: np.ndarray, G: np.ndarray | None, h: np.ndarray | None, lb: np.ndarray,
             ub: np.ndarray, solver: str) -> np.ndarray | None:
    """argmin 1/2 x'Px + c'x subject to G x <= h and lb <= x <= ub, or None if the solver
    found no solution."""
    try:
        if solver not in qpsolvers.dense_solvers:  # sparse-only solvers (OSQP, SCS, Clarabel, ...)
            import scipy.sparse as sp

            P = sp.csc_matrix(P)
            G = sp.csc_matrix(G) if G is not None else None
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                x = qpsolvers.solve_qp(P, c, G, h, lb=lb, ub=ub, solver=solver)
        else:
            x = qpsolvers.solve_qp(P, c, G, h, lb=lb, ub=ub, solver=solver)
    except Exception as exc:  # solvers raise their own errors for infeasible problems (quadprog: ValueError)
        logger.debug("QP solver %s failed: %s", solver, exc)
        return None
    if x is None or not np.all(np.isfinite(x)):
        return None
    return np.asarray(x, dtype=float)
