"""Position-only inverse kinematics: a frame's origin to a point, any orientation.

`manip.ik.IKSolver` solves full poses; Isaac's `compute_inverse_kinematics` without a
target orientation asks for the position only. This is the same damped least squares
(`manip.ik.kernels`), on the three position rows of the frame Jacobian:

    e  = p_goal - p(q)                                  (3,) [m]
    dq = J_p^T (J_p J_p^T + lambda I)^-1 e,   lambda = damping * |e|^2 + 1e-9
    q  <- clip(q + dq, lower, upper)

with the step scaled so no joint moves more than `max_step`. Each start (the seeds, then
uniformly random configurations within the limits, drawn from `seed`) iterates until the
error is below a hundredth of the tolerance, stops improving, or `max_iterations` pass.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from manip.kinematics import Kinematics

#: Damping gain and largest joint step [rad] of one iteration (IKSolver's defaults).
DAMPING = 0.03
MAX_STEP = 1.0
_STALL = 5


class PositionIKResult(NamedTuple):
    """success: the error is within the tolerance; q: (dof,) the best configuration found
    (within the limits); error: its position error [m]; attempts: starts tried."""

    success: bool
    q: np.ndarray
    error: float
    attempts: int


def _descend(kin: Kinematics, fid: int, p_goal: np.ndarray, q: np.ndarray, stop: float,
             max_iterations: int) -> tuple[np.ndarray, float]:
    best_q, best_e, stalled = q, np.inf, 0
    for _ in range(max_iterations):
        e = p_goal - kin.frame_transform(q, fid).translation
        err = float(np.linalg.norm(e))
        if err < best_e - 1e-12:
            best_q, best_e, stalled = q, err, 0
        else:
            stalled += 1
        if err < stop or stalled >= _STALL:
            break
        J = kin.frame_jacobian(q, fid)[:3]
        dq = J.T @ np.linalg.solve(J @ J.T + (DAMPING * err * err + 1e-9) * np.eye(3), e)
        scale = np.abs(dq).max() / MAX_STEP
        if scale > 1.0:
            dq /= scale
        q = np.clip(q + dq, kin.lower, kin.upper)
    return best_q, best_e


def solve_position(kin: Kinematics, fid: int, p_goal: np.ndarray, seeds: list[np.ndarray], *,
                   tolerance: float, max_attempts: int = 100, max_iterations: int = 60,
                   seed: int = 0) -> PositionIKResult:
    """Joint positions placing frame `fid`'s origin at `p_goal` (the kinematics' base frame).

    Args:
        kin: the robot's kinematics.
        fid: the frame's index (`kin.frame_id`).
        p_goal: (3,) target position [m].
        seeds: (dof,) configurations tried first, in order (clipped to the limits).
        tolerance: success threshold on the position error [m].
        max_attempts: starts in all, seeds included.
        max_iterations: iterations per start.
        seed: seed of the random starts.
    """
    rng = np.random.default_rng(seed)
    best = (np.clip(seeds[0], kin.lower, kin.upper) if seeds else 0.5 * (kin.lower + kin.upper), np.inf)
    for k in range(max_attempts):
        start = seeds[k] if k < len(seeds) else rng.uniform(kin.lower, kin.upper)
        q, err = _descend(kin, fid, p_goal, np.clip(np.asarray(start, dtype=float), kin.lower, kin.upper),
                          0.01 * tolerance, max_iterations)
        if err < best[1]:
            best = (q, err)
        if err <= tolerance:
            return PositionIKResult(True, q.copy(), err, k + 1)
    return PositionIKResult(False, np.array(best[0]), float(best[1]), max_attempts)
