"""Straight-line (Cartesian) motions of a link: a dense joint path by incremental IK."""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np

from manip import quaternion as quat
from manip.pose import Pose

#: Largest joint change [rad] allowed between IK solutions of consecutive line points (at
#: most 5 mm / 0.05 rad apart); a bigger jump means the arm flips through a singularity.
MAX_JOINT_JUMP = 0.1
#: The IK points of a line are checked in groups of this many as they are found, so a line
#: that collides early is given up before the rest is solved.
CHECK_EVERY = 8


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
    return linear_paths(kinematics, [(link, goal, ik_solver, None)], start, step=step, valid_batch=valid_batch,
                        motion_valid=motion_valid)


def linear_paths(
    kinematics,
    targets: list[tuple[str, Pose, object, np.ndarray | None]],
    start: np.ndarray,
    *,
    step: float,
    valid_batch: Callable[[np.ndarray], np.ndarray],
    motion_valid: Callable[[np.ndarray, np.ndarray], bool],
    carrier: tuple[Pose, Pose] | None = None,
    describe: Callable[[np.ndarray], str] | None = None,
) -> tuple[np.ndarray | None, str]:
    """Joint path (M, dof) moving several links, each on the straight line from its pose at
    `start` to its goal, together: every link at the same fraction of its line at each point
    (so all arrive together), the point count set by the longest line (`step` [m], 0.05 rad).

    Args:
        targets: per link (link, goal Pose, its IK solver, free (dof,) bool: the joints its IK
            sets, those of the arm that carries it; None: all). The links' joints must not
            overlap (one link per arm).
        start: (dof,) [rad].
        carrier: (its pose at the start, at the goal): the links move rigidly with one frame
            (a held object's) whose origin moves on the straight line and whose orientation is
            interpolated by slerp, each link keeping its start pose in that frame (its goal
            Pose is then where it ends up; give goals that keep the pose in the frame).
        describe: what a refused configuration (dof,) touches, for the reason (optional).

    Returns:
        (path, "") or (None, reason).
    """
    if carrier is not None:
        c0, c1 = carrier
        held = [c0.inverse() @ kinematics.fk(start, link) for link, _, _, _ in targets]
        targets = [(link, c1 @ h, solver, free) for (link, _, solver, free), h in zip(targets, held)]
    lines = []
    n = 1
    for link, goal, solver, free in targets:
        if solver.out_of_reach(kinematics.frame_id(link), goal.position[None])[0]:   # say why, not where IK gave up
            where = f" ('{link}')" if len(targets) > 1 else ""
            return None, f"the line{where} ends out of reach: " + solver.solve(goal, link, seed_q=start).message
        p0 = kinematics.fk(start, link)
        dist = float(np.linalg.norm(goal.position - p0.position))
        angle = float(quat.angle_between(p0.quaternion, goal.quaternion))
        n = max(n, int(np.ceil(max(dist / step, angle / 0.05))))
        lines.append((link, p0, goal, solver, free))
    if carrier is not None:  # the links' arcs: their lever arms about the frame's origin turn too
        lever = max(float(np.linalg.norm(h.position)) for h in held)
        n = max(n, int(np.ceil(lever * float(quat.angle_between(c0.quaternion, c1.quaternion)) / step)))
    s = np.linspace(0.0, 1.0, n + 1)[1:]
    if carrier is None:
        points = [(p0.position + s[:, None] * (goal.position - p0.position), _slerp(p0.quaternion, goal.quaternion, s))
                  for _, p0, goal, _, _ in lines]
    else:
        frames = Pose(c0.position + s[:, None] * (c1.position - c0.position), _slerp(c0.quaternion, c1.quaternion, s))
        points = [((f := frames @ h).position, f.quaternion) for h in held]
    path = [start]
    q = start
    many = len(lines) > 1
    for i in range(n):
        q_next = q.copy()
        for (link, _, _, solver, free), (positions, quats) in zip(lines, points):
            res = solver.solve(Pose(positions[i], quats[i]), link, seed_q=q)
            where = f" ('{link}')" if many else ""
            if not res.success:
                return None, f"IK fails on the line{where} at {s[i] * 100:.0f}% ({res.status.name})"
            moved = res.q if free is None else np.where(free, res.q, q_next)
            jump = float(np.max(np.abs(moved - q)))
            if jump > MAX_JOINT_JUMP:
                return None, f"the arm{where} would jump {jump:.2f} rad at {s[i] * 100:.0f}% of the line"
            q_next = moved
        q = q_next
        path.append(q)
        if i % CHECK_EVERY == CHECK_EVERY - 1 or i == n - 1:  # fail early: the IK points so far
            first = len(path) - CHECK_EVERY if i >= CHECK_EVERY else 1
            ok = valid_batch(np.asarray(path[first:]))
            if not np.all(ok):
                k = first + int(np.argmin(ok))  # the first refused point
                what = f": {describe(path[k])}" if describe is not None else ""
                return None, f"the straight line collides at {s[k - 1] * 100:.0f}% of the line{what}"
    path = np.asarray(path)
    for k, (a, b) in enumerate(itertools.pairwise(path)):
        if not motion_valid(a, b):
            at = f"{(s[k - 1] if k else 0.0) * 100:.0f}-{s[k] * 100:.0f}%"
            return None, f"the straight line collides between its IK points at {at} of the line"
    return path, ""
