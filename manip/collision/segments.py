"""Checks of straight joint-space segments and piecewise-linear paths, sampled densely.

`SegmentChecks` is a part of `CollisionChecker` (a mixin): it samples the segments at a
joint resolution, in bisection order (coarse first), and asks the checker's
`_check(Q, stop_at_first, group, deepest_first)` about the samples, stopping as soon as the
answer is known.
"""

from __future__ import annotations

import functools
import math
from typing import Callable, TypeVar

import numpy as np

from manip.collision.results import PathCheck
from manip.errors import InvalidInputError
from manip.validation import positive


_F = TypeVar("_F", bound=Callable)


def consistent(method: _F) -> _F:
    """Run a read-only method of a `CollisionChecker` on a snapshot of it.

    A checker whose world is edited by another thread could otherwise be read half-way
    through an edit; on a snapshot (`CollisionChecker.snapshot`) every table belongs to
    one state of the world. A method called on a snapshot runs on it directly.
    """

    @functools.wraps(method)
    def wrapper(self, *args, **kwargs):
        if not self._is_snapshot:
            self = self.snapshot()
        return method(self, *args, **kwargs)

    return wrapper  # type: ignore[return-value]


@functools.lru_cache(maxsize=512)
def _coarse_to_fine(n: int) -> np.ndarray:
    """Indices 0..n ordered endpoints first, then by halving strides (bisection order); cached."""
    idx = np.arange(n + 1)
    level = np.zeros(n + 1, dtype=np.int64)
    inner = idx[1:n]
    if inner.size:
        # trailing zero bits of the index: large strides first
        tz = np.zeros(inner.size, dtype=np.int64)
        x = inner.copy()
        for _ in range(64):
            m = (x & 1) == 0
            if not m.any():
                break
            tz[m] += 1
            x[m] >>= 1
        level[1:n] = 64 - tz
    out = idx[np.argsort(level, kind="stable")]
    out.setflags(write=False)
    return out


class SegmentChecks:
    """`motion_valid`, `first_collision`, `motion_valid_batch`, `path_valid` and `segment_steps`.

    Needs, from the class it is mixed into: `kinematics`, `_check`, `_one_q` and `_rows`.
    """

    @consistent
    def motion_valid(self, q0: np.ndarray, q1: np.ndarray, resolution: float = 0.01, chunk: int = 32) -> bool:
        """True if the straight joint-space segment q0 -> q1 is collision-free.

        Checks q0, q1 and evenly spaced configurations between them such that consecutive
        checked configurations differ by at most `resolution` [rad] on every joint (L-inf),
        in bisection order (coarse first), stopping at the first collision.

        Args:
            q0, q1: (dof,) endpoints.
            resolution: largest joint step between checked configurations [rad] > 0.
            chunk: size of the first (coarse) batch.
        """
        q0, q1 = self._one_q(q0, "q0"), self._one_q(q1, "q1")
        steps = self.segment_steps(q0, q1, resolution)
        order = _coarse_to_fine(steps)
        t = order / steps
        Q = q0[None] + t[:, None] * (q1 - q0)[None]
        if Q.shape[0] <= 2 * chunk:
            return not self._check(Q, stop_at_first=True).any()
        if self._check(Q[:chunk], stop_at_first=True).any():
            return False
        return not self._check(Q[chunk:], stop_at_first=True).any()

    @consistent
    def first_collision(self, q0: np.ndarray, q1: np.ndarray, resolution: float = 0.01, chunk: int = 48) -> float | None:
        """Advance along the straight segment q0 -> q1 until the first collision.

        The segment is sampled like `motion_valid` and checked in order, in chunks.

        Args:
            q0, q1: (dof,) endpoints.
            resolution: largest joint step between checked configurations [rad] > 0.
            chunk: configurations checked per batch.

        Returns:
            None if the whole segment is free, else the parameter t in [0, 1] of the first
            colliding sample (q0 + t (q1 - q0)); every sample before it is free, so the
            configuration one sample earlier (t - 1/steps, see `segment_steps`) is a valid
            place to stop (RRT-Connect's "connect" in one call).
        """
        q0, q1 = self._one_q(q0, "q0"), self._one_q(q1, "q1")
        steps = self.segment_steps(q0, q1, resolution)
        t_all = np.arange(steps + 1) / steps
        d = q1 - q0
        for s in range(0, steps + 1, chunk):
            t = t_all[s:s + chunk]
            hit = self._check(q0[None] + t[:, None] * d[None], stop_at_first=True, deepest_first=False)
            if hit.any():
                return float(t[np.argmax(hit)])
        return None

    @staticmethod
    def segment_steps(q0: np.ndarray, q1: np.ndarray, resolution: float = 0.01) -> int:
        """Number of intervals `motion_valid` splits q0 -> q1 into: ceil(max|q1 - q0| / resolution), >= 1."""
        resolution = positive(resolution, "resolution", "rad")
        return max(1, int(math.ceil(float(np.abs(np.asarray(q1) - np.asarray(q0)).max()) / resolution - 1e-12)))

    @consistent
    def motion_valid_batch(self, Q0: np.ndarray, Q1: np.ndarray, resolution: float = 0.01) -> np.ndarray:
        """(M,) bool: `motion_valid` of the M straight segments Q0[m] -> Q1[m], checked together.

        All segments' coarse samples (endpoints and midpoints) are checked in one batch first,
        then the remaining samples of the segments still valid, so that several candidate
        edges (RRT extensions, shortcuts) cost about one call.

        Args:
            Q0, Q1: (M, dof) segment endpoints.
            resolution: largest joint step between checked configurations [rad] > 0.
        """
        Q0, Q1 = self._rows(Q0, "Q0"), self._rows(Q1, "Q1")
        if Q0.shape != Q1.shape:
            raise InvalidInputError(f"Q0 and Q1 must have the same shape (M, {self.kinematics.dof}); got {Q0.shape} and {Q1.shape}")
        return self._segments_valid(Q0, Q1, positive(resolution, "resolution", "rad"))

    def _segments_valid(self, Q0: np.ndarray, Q1: np.ndarray, resolution: float, coarse: int = 9) -> np.ndarray:
        M = Q0.shape[0]
        valid = np.ones(M, dtype=bool)
        if M == 0:
            return valid
        D = Q1 - Q0
        steps = np.maximum(1, np.ceil(np.abs(D).max(axis=1) / resolution - 1e-12).astype(np.int64))
        first_q, first_seg, rest_q, rest_seg = [], [], [], []
        for m in range(M):
            order = _coarse_to_fine(int(steps[m]))
            t = order / steps[m]
            S = Q0[m] + t[:, None] * D[m]
            first_q.append(S[:coarse])
            first_seg.append(np.full(min(coarse, S.shape[0]), m))
            if S.shape[0] > coarse:
                rest_q.append(S[coarse:])
                rest_seg.append(np.full(S.shape[0] - coarse, m))
        seg = np.concatenate(first_seg)
        hit = self._check(np.concatenate(first_q), group=seg)
        valid[np.unique(seg[hit])] = False
        if rest_q and valid.any():
            Qr = np.concatenate(rest_q)
            seg = np.concatenate(rest_seg)
            keep = valid[seg]
            if keep.any():
                hit = self._check(Qr[keep], group=seg[keep])
                valid[np.unique(seg[keep][hit])] = False
        return valid

    @consistent
    def path_valid(self, path: np.ndarray, resolution: float = 0.01) -> PathCheck:
        """Check a piecewise-linear joint path (K, dof) densely (see `motion_valid`).

        Returns:
            PathCheck(valid, first_invalid_segment): segment s joins path[s] and path[s+1];
            for a single-configuration path a collision gives segment 0.
        """
        path = self.kinematics.check_q(path, "path")
        if path.ndim != 2 or path.shape[0] < 1:
            raise InvalidInputError(f"path must have shape (K, {self.kinematics.dof}) with K >= 1; got {path.shape}")
        resolution = positive(resolution, "resolution", "rad")
        if path.shape[0] == 1:
            bad = bool(self._check(path)[0])
            return PathCheck(not bad, 0 if bad else None)
        ok = self._segments_valid(path[:-1], path[1:], resolution)
        if ok.all():
            return PathCheck(True, None)
        return PathCheck(False, int(np.argmin(ok)))
