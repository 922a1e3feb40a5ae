"""Path shortening: random shortcuts, then removal of redundant waypoints."""

from __future__ import annotations

import time

import numpy as np

from manip.planning.rrt_connect import MotionCheck


def path_length(path: np.ndarray) -> float:
    """Sum of joint-space L2 segment lengths [rad] of a (K, dof) path."""
    return float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1)))


def remove_redundant(path: np.ndarray, motion_valid: MotionCheck) -> np.ndarray:
    """Greedy pruning: from each kept waypoint, jump to the farthest one reachable directly."""
    out = [path[0]]
    i = 0
    n = len(path)
    while i < n - 1:
        j = n - 1
        while j > i + 1 and not motion_valid(path[i], path[j]):
            j -= 1
        out.append(path[j])
        i = j
    return np.asarray(out)


def shortcut(
    path: np.ndarray,
    motion_valid: MotionCheck,
    rng: np.random.Generator,
    deadline: float,
    max_attempts: int = 100,
) -> np.ndarray:
    """Shorten `path` (K, dof) by replacing random sub-paths with straight segments.

    Each attempt picks two points on the path (anywhere along segments, not only at
    waypoints) and keeps the straight segment between them when it is valid.
    """
    path = remove_redundant(np.asarray(path, dtype=float), motion_valid)
    for _ in range(max_attempts):
        if len(path) <= 2 or time.perf_counter() > deadline:
            break
        seg = np.linalg.norm(np.diff(path, axis=0), axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        total = cum[-1]
        if total <= 1e-9:
            break
        s0, s1 = np.sort(rng.uniform(0.0, total, 2))
        i0 = int(np.searchsorted(cum, s0, side="right") - 1)
        i1 = int(np.searchsorted(cum, s1, side="right") - 1)
        if i0 == i1:
            continue
        i0, i1 = min(i0, len(seg) - 1), min(i1, len(seg) - 1)
        q0 = path[i0] + (path[i0 + 1] - path[i0]) * ((s0 - cum[i0]) / max(seg[i0], 1e-12))
        q1 = path[i1] + (path[i1 + 1] - path[i1]) * ((s1 - cum[i1]) / max(seg[i1], 1e-12))
        if motion_valid(q0, q1):
            path = np.concatenate([path[: i0 + 1], q0[None], q1[None], path[i1 + 1 :]])
            # drop zero-length segments created at waypoints
            keep = np.concatenate([[True], np.linalg.norm(np.diff(path, axis=0), axis=1) > 1e-9])
            path = path[keep]
    return remove_redundant(path, motion_valid)
