"""Projection of a configuration onto the set where constraints hold (with their margin).

Gauss-Newton on the active rows (those above -margin): dq = -J^+ (r + margin), J the rows'
Jacobian scaled by 1/margin (so rows of different units weigh alike), damped, clipped to
the joint limits, until every row is <= -margin / 2 or MAX_STEPS steps.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from manip.constraints.base import Constraint
from manip.kinematics import Kinematics

#: Gauss-Newton steps of one projection at most.
MAX_STEPS = 12
#: Damping of the least-squares step (Levenberg-Marquardt, in units of the scaled rows).
DAMPING = 1e-6


def project(constraints: Sequence[Constraint], kinematics: Kinematics, q: np.ndarray, *,
            max_steps: int = MAX_STEPS) -> np.ndarray | None:
    """`q` (dof,) moved into the allowed set, at least half of each constraint's margin inside
    (a configuration already there is returned as given); None when it did not converge.
    """
    if len(constraints) == 1:  # one constraint: its compiled projection, when it has one
        out = constraints[0].project_alone(kinematics, np.array(q, dtype=float), max_steps, DAMPING)
        if out is not NotImplemented:
            return out
    q = np.array(q, dtype=float)[None]
    lower, upper = kinematics.lower, kinematics.upper
    margins = [c.margin for c in constraints]
    for _ in range(max_steps + 1):
        rows, jacs, done = [], [], True
        for c, m in zip(constraints, margins):
            r, J = c.residual_and_jacobian(kinematics, q)
            r, J = r[0], J[0]
            if r.max() > -0.5 * m:
                done = False
            active = r > -m
            if active.any():
                rows.append((r[active] + m) / m)
                jacs.append(J[active] / m)
        if done or not rows:
            return q[0]
        r = rows[0] if len(rows) == 1 else np.concatenate(rows)
        J = jacs[0] if len(jacs) == 1 else np.concatenate(jacs)
        if J.shape[0] == 1:  # one active row (an orientation): the least-squares step in closed form
            dq = J[0] * -(r[0] / (J[0] @ J[0] + DAMPING))
        else:
            dq = -J.T @ np.linalg.solve(J @ J.T + DAMPING * np.eye(J.shape[0]), r)
        q = np.clip(q + dq, lower, upper)
    return None


def satisfied(constraints: Sequence[Constraint], kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
    """(N,) True where every constraint holds at Q (N, dof) (violation <= 0)."""
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    ok = np.ones(Q.shape[0], dtype=bool)
    for c in constraints:
        ok &= c.violation(kinematics, Q) <= 0.0
    return ok
