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

#: Samples of the first batch of `first_collision` (the rest go `chunk` at a time).
FIRST_HIT_LEAD = 4
#: Samples of the first batch of `motion_valid` (bisection order; then `chunk`, then the rest).
MOTION_LEAD = 8


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


def _steps(q0: np.ndarray, q1: np.ndarray, resolution: float) -> int:
    """ceil(max|q1 - q0| / resolution), at least 1: the intervals a segment is split into."""
    return max(1, int(math.ceil(float(np.abs(q1 - q0).max()) / resolution - 1e-12)))


@functools.lru_cache(maxsize=512)
def _fractions(n: int) -> np.ndarray:
    """`_coarse_to_fine(n) / n`: the sample parameters t in [0, 1] in bisection order; cached."""
    out = _coarse_to_fine(n) / n
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
        return self._motion_free(q0, q1, self.segment_steps(q0, q1, resolution), chunk)

    def _motion_free(self, q0: np.ndarray, q1: np.ndarray, steps: int, chunk: int = 32) -> bool:
        """`motion_valid` of checked endpoints split into `steps` intervals (no input checks):
        the samples in bisection order, `MOTION_LEAD` first, then `chunk`, then the rest (a
        batch of at most twice its size takes the rest with it)."""
        t = _fractions(steps)
        Q = q0[None] + t[:, None] * (q1 - q0)[None]
        s, N = 0, Q.shape[0]
        for size in (min(MOTION_LEAD, chunk), chunk):
            if N - s <= 2 * size:
                break
            if self._check(Q[s:s + size], stop_at_first=True).any():
                return False
            s += size
        return not self._check(Q[s:], stop_at_first=True).any()

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
        return self._first_hit(q0, q1, self.segment_steps(q0, q1, resolution), chunk)

    def _first_hit(self, q0: np.ndarray, q1: np.ndarray, steps: int, chunk: int = 48, start: int = 0) -> float | None:
        """`first_collision` of checked endpoints split into `steps` intervals (no input checks),
        from sample `start` on (1: q0 is known to be free).

        The first batch holds only `FIRST_HIT_LEAD` samples: a tree pushing against an
        obstacle usually collides within a few steps (MotionBenchMaker searches: 70 % of the
        advances collide, 90 % of those within 4 samples), and each later batch `chunk`.
        """
        t_all = np.arange(steps + 1) / steps
        d = q1 - q0
        s = start
        size = FIRST_HIT_LEAD
        while s <= steps:
            t = t_all[s:s + size]
            hit = self._check(q0[None] + t[:, None] * d[None], stop_at_first=True, deepest_first=False)
            if hit.any():
                return float(t[np.argmax(hit)])
            s += size
            size = chunk
        return None

    @consistent
    def _advance_to(self, q0: np.ndarray, q1: np.ndarray, resolution: float) -> tuple[float | None, int]:
        """(`first_collision`, `segment_steps`) of one segment from a collision-free q0 (a node
        of a search tree: its own sample is not checked again), for planners that pass their
        own finite (dof,) arrays and a positive resolution (no input checks)."""
        steps = _steps(q0, q1, resolution)
        return self._first_hit(q0, q1, steps, start=1), steps

    @consistent
    def _segments_free(self, Q0: np.ndarray, Q1: np.ndarray, resolution: float) -> np.ndarray:
        """`motion_valid_batch` for planners that pass their own finite (M, dof) arrays of
        the same shape and a positive resolution (no input checks)."""
        return self._segments_valid(Q0, Q1, resolution)

    @consistent
    def _motion_free_at(self, q0: np.ndarray, q1: np.ndarray, resolution: float) -> bool:
        """`motion_valid` for planners that pass their own finite (dof,) arrays and a positive
        resolution (no input checks)."""
        return self._motion_free(q0, q1, _steps(q0, q1, resolution))

    @staticmethod
    def segment_steps(q0: np.ndarray, q1: np.ndarray, resolution: float = 0.01) -> int:
        """Number of intervals `motion_valid` splits q0 -> q1 into: ceil(max|q1 - q0| / resolution), >= 1."""
        resolution = positive(resolution, "resolution", "rad")
        return _steps(np.asarray(q0, dtype=float), np.asarray(q1, dtype=float), resolution)

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
        fractions = [_fractions(k) for k in steps.tolist()]
        # each segment's first `coarse` samples (bisection order) for all segments in one batch
        seg = np.repeat(np.arange(M), np.minimum(steps + 1, coarse))
        t = np.concatenate([f[:coarse] for f in fractions])
        hit = self._check(Q0[seg] + t[:, None] * D[seg], group=seg)
        valid[seg[hit]] = False
        # then the remaining samples of the segments still valid
        rest = np.flatnonzero(valid & (steps + 1 > coarse))
        if rest.size:
            seg = np.repeat(rest, steps[rest] + 1 - coarse)
            t = np.concatenate([fractions[m][coarse:] for m in rest.tolist()])
            hit = self._check(Q0[seg] + t[:, None] * D[seg], group=seg)
            valid[seg[hit]] = False
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
            bad = bool(self._check(path, inside=True)[0])
            return PathCheck(not bad, 0 if bad else None)
        ok = self._segments_valid(path[:-1], path[1:], resolution)
        if ok.all():
            return PathCheck(True, None)
        return PathCheck(False, int(np.argmin(ok)))
