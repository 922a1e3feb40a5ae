"""Path shortening: batched random shortcuts and removal of redundant waypoints.

Candidate straight segments are checked many at a time (`segments_valid(Q0, Q1) -> (M,)
bool`), which costs about one collision-checker call per round instead of one per candidate.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

SegmentsValid = Callable[[np.ndarray, np.ndarray], np.ndarray]

#: Candidates screened in the first batch of `remove_redundant` and of a shortcut round (then
#: twice as many each time, until one passes); None: all at once. The same answers either way.
SCREEN_BATCH: int | None = 4


def path_length(path: np.ndarray) -> float:
    """Sum of joint-space L2 segment lengths [rad] of a (K, dof) path."""
    return float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1)))


def remove_redundant(
    path: np.ndarray, segments_valid: SegmentsValid, screen: SegmentsValid | None = None,
    screened: SegmentsValid | None = None,
) -> np.ndarray:
    """Greedy pruning: from each kept waypoint, jump to the farthest one reachable directly.

    Args:
        path: (K, dof) a valid path [rad].
        segments_valid: the validity the result must have.
        screen: an optional cheaper necessary condition of `segments_valid` (e.g. a coarser
            resolution): all jumps from a waypoint are screened in one batch, then only the
            screened ones get `segments_valid`, farthest first, until one passes (the same
            result as checking them all, for fewer checks).
        screened: `segments_valid` of segments that passed `screen` (the rest of the check,
            e.g. `Validity.screened`: the screen is not run twice); default `segments_valid`.
    """
    screened = segments_valid if screened is None else screened
    path = np.asarray(path, dtype=float)
    out = [path[0]]
    i = 0
    n = len(path)
    while i < n - 1:
        j = i + 1
        if i + 2 <= n - 1:
            targets = np.arange(n - 1, i + 1, -1)  # farthest first
            starts = np.repeat(path[i][None], len(targets), axis=0)
            if screen is None:
                ok = segments_valid(starts, path[targets])
                if ok.any():
                    j = int(targets[np.argmax(ok)])
            else:
                k = _first_passing(starts, path[targets], screen, screened)
                if k is not None:
                    j = int(targets[k])
        out.append(path[j])
        i = j
    return np.asarray(out)


def _first_passing(Q0: np.ndarray, Q1: np.ndarray, screen: SegmentsValid, screened: SegmentsValid) -> int | None:
    """The first m of the candidate segments Q0[m] -> Q1[m] (M, dof) in their order that passes
    `screen` and then `screened` (None: none does). They are screened `SCREEN_BATCH` at a time
    (growing), so candidates after the answer are mostly never checked; every candidate before
    it is, so the answer is the one of screening them all at once."""
    M = Q0.shape[0]
    s, size = 0, SCREEN_BATCH or M
    while s < M:
        e = min(M, s + size)
        for k in (s + np.flatnonzero(screen(Q0[s:e], Q1[s:e]))).tolist():
            if screened(Q0[k:k + 1], Q1[k:k + 1])[0]:
                return k
        s, size = e, 2 * size
    return None


def _points_at(path: np.ndarray, cum: np.ndarray, seg: np.ndarray, s: np.ndarray) -> tuple[list[int], np.ndarray]:
    """The segments (C,) and points (C, dof) at arc lengths s (C,) [rad] along `path` (K, dof),
    whose segment lengths are seg (K-1,) and their cumulative sums cum (K,)."""
    i = np.minimum(np.searchsorted(cum, s, side="right") - 1, len(seg) - 1)
    return i.tolist(), path[i] + (path[i + 1] - path[i]) * ((s - cum[i]) / np.maximum(seg[i], 1e-12))[:, None]


def shortcut(
    path: np.ndarray,
    segments_valid: SegmentsValid,
    rng: np.random.Generator,
    deadline: float,
    *,
    rounds: int = 3,
    candidates: int = 16,
    screen: SegmentsValid | None = None,
    screened: SegmentsValid | None = None,
) -> np.ndarray:
    """Shorten `path` (K, dof) by replacing sub-paths with straight segments.

    Each round draws `candidates` pairs of points anywhere along the path (not only at
    waypoints), checks their straight segments in one batch and applies the valid one that
    saves the most length. The points lie on already-valid segments, so the result stays
    valid. Deterministic for a given generator state.

    Three rounds by default (BENCHMARKS.md, "Constants").

    Args:
        segments_valid: the validity the result must have (e.g. a fine-resolution check).
        screen: an optional cheaper check run on every candidate first (e.g. a coarser
            resolution); only the most promising screened candidates get `segments_valid`.
        screened: `segments_valid` of segments that passed `screen` (`remove_redundant`).
    """
    path = remove_redundant(np.asarray(path, dtype=float), segments_valid, screen, screened)
    screened = segments_valid if screened is None else screened
    for _ in range(rounds):
        if len(path) <= 2 or time.perf_counter() > deadline:
            break
        seg = np.linalg.norm(np.diff(path, axis=0), axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        total = cum[-1]
        if total <= 1e-9:
            break
        pairs = np.sort(rng.uniform(0.0, total, (candidates, 2)), axis=1)
        (I0, P0), (I1, P1) = _points_at(path, cum, seg, pairs[:, 0]), _points_at(path, cum, seg, pairs[:, 1])
        Q0, Q1, idx, saving = [], [], [], []
        for c, (s0, s1) in enumerate(pairs.tolist()):
            i0, i1 = I0[c], I1[c]
            if i0 == i1:
                continue
            gain = (s1 - s0) - float(np.linalg.norm(P1[c] - P0[c]))
            if gain <= 1e-6:
                continue
            Q0.append(P0[c])
            Q1.append(P1[c])
            idx.append((i0, i1))
            saving.append(gain)
        if not Q0:
            continue
        Q0a, Q1a = np.asarray(Q0), np.asarray(Q1)
        if screen is None:
            ok = segments_valid(Q0a, Q1a)
            best = int(np.argmax(np.where(ok, saving, -np.inf))) if ok.any() else None
        else:   # the largest saving first (a stable order: the first of equal savings)
            order = np.argsort(-np.asarray(saving), kind="stable")
            k = _first_passing(Q0a[order], Q1a[order], screen, screened)
            best = None if k is None else int(order[k])
        if best is None:
            continue
        i0, i1 = idx[best]
        path = np.concatenate([path[: i0 + 1], Q0[best][None], Q1[best][None], path[i1 + 1 :]])
        keep = np.concatenate([[True], np.linalg.norm(np.diff(path, axis=0), axis=1) > 1e-9])
        path = path[keep]
    return remove_redundant(path, segments_valid, screen, screened)
