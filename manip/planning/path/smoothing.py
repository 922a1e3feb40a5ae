"""Path optimisation: smoothness and clearance of a piecewise-linear joint path.

After shortcutting, a path is a few waypoints joined by straight segments that often graze
obstacles. A few projected-gradient steps move each interior waypoint towards the midpoint
of its neighbours (shorter, smoother) and away from obstacles where the clearance is below
a margin (the gradient of the collision checker's sphere-model clearance, by central finite
differences in one batch). A move is kept only when both segments it touches stay valid, so
the result is always at least as valid as the input.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np


def smooth_path(
    path: np.ndarray,
    checker,
    motion_valid: Callable[[np.ndarray, np.ndarray], bool],
    deadline: float,
    *,
    iterations: int = 8,
    margin: float = 0.03,
    smooth_gain: float = 0.3,
    clearance_gain: float = 0.5,
    max_step: float = 0.1,
    fd_step: float = 1e-3,
) -> np.ndarray:
    """Improve the interior waypoints of `path` (K, dof); endpoints never move.

    Args:
        path: (K, dof) valid waypoints [rad].
        checker: provides `world_clearance_batch(Q (N, dof)) -> (N,)` [m].
        motion_valid: straight-segment validity check.
        deadline: `time.perf_counter()` value to stop at.
        iterations: gradient steps.
        margin: clearance [m] below which waypoints are pushed away from obstacles.
        smooth_gain: fraction of the way to the neighbours' midpoint per step.
        clearance_gain: step [rad per m of missing clearance, per unit gradient].
        max_step: largest move of a waypoint per step (L-inf) [rad].
        fd_step: finite-difference step [rad].
    """
    path = np.array(path, dtype=float)
    k, dof = path.shape
    if k <= 2:
        return path
    eye = np.eye(dof) * fd_step
    for _ in range(iterations):
        if time.perf_counter() > deadline:
            break
        inner = path[1:-1]
        probes = np.concatenate([inner[:, None, :] + eye, inner[:, None, :] - eye], axis=1).reshape(-1, dof)
        values = np.asarray(checker.world_clearance_batch(np.concatenate([inner, probes])))
        clearance = values[: len(inner)]
        plus = values[len(inner):].reshape(len(inner), 2, dof)
        grad = (plus[:, 0] - plus[:, 1]) / (2 * fd_step)
        moved = False
        for i in range(1, k - 1):
            step = smooth_gain * (0.5 * (path[i - 1] + path[i + 1]) - path[i])
            deficit = margin - clearance[i - 1]
            g = grad[i - 1]
            if deficit > 0 and np.linalg.norm(g) > 1e-9:
                step = step + clearance_gain * deficit * g / np.linalg.norm(g)
            scale = np.max(np.abs(step)) / max_step
            if scale > 1:
                step = step / scale
            if np.max(np.abs(step)) < 1e-4:
                continue
            candidate = path[i] + step
            if checker.kinematics.within_limits(candidate) and motion_valid(path[i - 1], candidate) and motion_valid(
                candidate, path[i + 1]
            ):
                path[i] = candidate
                moved = True
        if not moved:
            break
    return path
