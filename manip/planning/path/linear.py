"""Straight-line (Cartesian) motions of a link: a dense joint path by incremental IK."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from manip import quaternion as quat
from manip.pose import Pose

#: Largest joint change [rad] allowed between IK solutions of consecutive line points (at
#: most 5 mm / 0.05 rad apart); a bigger jump means the arm flips through a singularity.
MAX_JOINT_JUMP = 0.1


def _slerp(q0: np.ndarray, q1: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Spherical interpolation of unit quaternions (w, x, y, z) at fractions s (M,)."""
    d = float(np.dot(q0, q1))
    if d < 0:
        q1, d = -q1, -d
    if d > 0.9995:
        out = q0 + s[:, None] * (q1 - q0)
        return out / np.linalg.norm(out, axis=1, keepdims=True)
    theta = np.arccos(d)
    return (np.sin((1 - s) * theta)[:, None] * q0 + np.sin(s * theta)[:, None] * q1) / np.sin(theta)


def linear_path(
    kinematics,
    ik_solver,
    start: np.ndarray,
    goal: Pose,
    link: str,
    *,
    step: float,
    valid_batch: Callable[[np.ndarray], np.ndarray],
    motion_valid: Callable[[np.ndarray, np.ndarray], bool],
) -> tuple[np.ndarray | None, str]:
    """Joint path (M, dof) moving `link` on the straight line from its pose at `start` to `goal`.

    The orientation is interpolated by slerp (constant when the goal keeps the start's).
    Each point is solved by IK seeded with the previous solution.

    Returns:
        (path, "") or (None, reason).
    """
    p0 = kinematics.fk(start, link)
    dist = float(np.linalg.norm(goal.position - p0.position))
    angle = float(quat.angle_between(p0.quaternion, goal.quaternion))
    n = max(1, int(np.ceil(max(dist / step, angle / 0.05))))
    s = np.linspace(0.0, 1.0, n + 1)[1:]
    positions = p0.position + s[:, None] * (goal.position - p0.position)
    quats = _slerp(p0.quaternion, goal.quaternion, s)
    path = [start]
    q = start
    for i in range(n):
        target = Pose(positions[i], quats[i])
        res = ik_solver.solve(target, link, seed_q=q)
        if not res.success:
            return None, f"IK fails on the line at {s[i] * 100:.0f}% ({res.status.name})"
        if np.max(np.abs(res.q - q)) > MAX_JOINT_JUMP:
            return None, f"the arm would jump {np.max(np.abs(res.q - q)):.2f} rad at {s[i] * 100:.0f}% of the line"
        q = res.q
        path.append(q)
    path = np.asarray(path)
    if not np.all(valid_batch(path[1:])):
        return None, "the straight line collides"
    for a, b in zip(path[:-1], path[1:]):
        if not motion_valid(a, b):
            return None, "the straight line collides"
    return path, ""
