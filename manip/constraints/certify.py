"""Certify that constraints hold over the continuous joint-space interpolation of a path.

For each segment q(t) = q_a + t (q_b - q_a) and constraint, with v_a, v_b its violation at
the ends and L its `segment_bound` (every residual row changes at most L |t - s| between
t and s), the violation is at most min(v_a + t L, v_b + (1 - t) L) <= (v_a + v_b + L) / 2
anywhere on the segment. A segment whose bound is not <= 0 is bisected (the halves' L
halve; the midpoint is evaluated) until every piece is proved, a sample violating the
constraint is found, or MAX_DEPTH halvings did not close the proof. A segment is first cut
into the number of pieces its ends' depth inside the set would certify (at most
FIRST_SPLIT); all segments of a path are processed together, one batched evaluation per level.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from manip.constraints.base import Constraint
from manip.kinematics import Kinematics

#: A segment is not certified after this many halvings (2^-30 of its length).
MAX_DEPTH = 30
#: The deviation allowance of a timed motion (`certify_constraints(..., deviation)`) is used
#: for a constraint when its bound is at most this share of the constraint's margin; a
#: tighter constraint (or a coarser bound) is certified on the samples' polyline only.
DEVIATION_SHARE = 0.5
#: The first cut of an open segment: at most this many pieces, evaluated in one batch.
FIRST_SPLIT = 32


class ConstraintCertificate(NamedTuple):
    """Result of `certify_constraints` (the fields of `MotionCertificate`).

    Attributes:
        certified: True when every constraint holds over the whole continuous interpolation.
        first_failed_segment: the first segment s (path[s] -> path[s+1]) not certified, or None.
        reason: "" when certified; "constraint" when a configuration on that segment violates
            a constraint, "constraint_uncertified" when the proof did not close.
        pair: (the failed constraint's description at the worst configuration found, "") or None.
        queries: configurations evaluated.
    """

    certified: bool
    first_failed_segment: int | None = None
    reason: str = ""
    pair: tuple[str, str] | None = None
    queries: int = 0


def segments_hold(constraints: Sequence[Constraint], kinematics: Kinematics, Q0: np.ndarray, Q1: np.ndarray,
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Which segments Q0[i] -> Q1[i] (M, dof) keep every constraint over their whole length.

    Returns:
        (ok (M,) bool, bad (M,) bool: a configuration on the segment violates a constraint,
        worst (M, dof): for a failed segment, the configuration where that was found (or the
        last one evaluated)).
    """
    Q0 = np.atleast_2d(np.asarray(Q0, dtype=float))
    Q1 = np.atleast_2d(np.asarray(Q1, dtype=float))
    M = Q0.shape[0]
    ok = np.ones(M, dtype=bool)
    bad = np.zeros(M, dtype=bool)
    worst = Q0.copy()
    for c in constraints:
        idx = np.flatnonzero(ok)
        if idx.size == 0:
            break
        c_ok, c_bad, c_worst, _ = _hold(c, kinematics, Q0[idx], Q1[idx])
        ok[idx] = c_ok
        bad[idx] = c_bad
        worst[idx[~c_ok]] = c_worst[~c_ok]
    return ok, bad, worst


def _hold(c: Constraint, kin: Kinematics, Q0: np.ndarray, Q1: np.ndarray, slack: np.ndarray | None = None):
    """`segments_hold` for one constraint: (ok, bad, worst, evaluations). `slack` (M,) [its
    unit]: segment i must keep the violation <= -slack[i] (0 when None)."""
    M = Q0.shape[0]
    extra = np.zeros(M) if slack is None else np.asarray(slack, dtype=float)
    fast = c.hold_alone(kin, Q0, Q1, extra)  # the constraint's compiled proof, when it has one
    if fast is not NotImplemented:
        return fast
    ok = np.ones(M, dtype=bool)
    bad = np.zeros(M, dtype=bool)
    worst = Q0.copy()
    v = c.violation(kin, np.concatenate([Q0, Q1])) + np.concatenate([extra, extra])
    va, vb = v[:M], v[M:]
    L = c.segment_bound(kin, Q0, Q1)
    evaluations = 2 * M
    for Qx, vx in ((Q0, va), (Q1, vb)):
        hit = ok & (vx > 0)
        ok[hit], bad[hit] = False, True
        worst[hit] = Qx[hit]
    # pieces still open: owner segment, ends, violations, bound
    open_ = ok & (0.5 * (va + vb + L) > 0)
    seg, qa, qb, a, b, bound = (np.flatnonzero(open_), Q0[open_], Q1[open_], va[open_], vb[open_], L[open_])
    if seg.size:
        # one batched evaluation first: each open segment cut into the pieces its ends'
        # depth would certify (at most FIRST_SPLIT), then bisection of what stays open
        pieces = np.clip(np.ceil(2.0 * bound / np.maximum(-(a + b), 1e-9 * np.maximum(bound, 1.0))), 2,
                         FIRST_SPLIT).astype(np.int64)
        owner = np.repeat(np.arange(seg.size), pieces)
        k = np.arange(owner.size) - np.repeat(np.cumsum(pieces) - pieces, pieces)
        t0, t1 = k / pieces[owner], (k + 1) / pieces[owner]
        d = (qb - qa)[owner]
        inner = t1 < 1.0
        v_in = c.violation(kin, qa[owner][inner] + t1[inner, None] * d[inner]) + extra[seg[owner][inner]]
        evaluations += int(inner.sum())
        v1 = b[owner].copy()
        v1[inner] = v_in
        v0 = np.empty_like(v1)
        v0[k == 0] = a[owner][k == 0]
        v0[k > 0] = v1[np.flatnonzero(k > 0) - 1]
        for o, q in zip(owner[inner][v_in > 0], (qa[owner][inner] + t1[inner, None] * d[inner])[v_in > 0]):
            if ok[seg[o]]:
                ok[seg[o]], bad[seg[o]] = False, True
                worst[seg[o]] = q
        h = bound[owner] / pieces[owner]
        keep = ok[seg[owner]] & (0.5 * (v0 + v1 + h) > 0)
        seg, qa, qb = seg[owner][keep], (qa[owner] + t0[:, None] * d)[keep], (qa[owner] + t1[:, None] * d)[keep]
        a, b, bound = v0[keep], v1[keep], h[keep]
    depth = 0
    while seg.size:
        if depth >= MAX_DEPTH:
            ok[seg] = False
            worst[seg] = 0.5 * (qa + qb)
            break
        qm = 0.5 * (qa + qb)
        vm = c.violation(kin, qm) + extra[seg]
        evaluations += qm.shape[0]
        hit = vm > 0
        if hit.any():
            for s, q in zip(seg[hit], qm[hit]):
                if ok[s]:
                    ok[s], bad[s] = False, True
                    worst[s] = q
        half = 0.5 * bound
        # the two halves of every piece whose segment is still fine
        seg2 = np.concatenate([seg, seg])
        qa2, qb2 = np.concatenate([qa, qm]), np.concatenate([qm, qb])
        a2, b2 = np.concatenate([a, vm]), np.concatenate([vm, b])
        h2 = np.concatenate([half, half])
        keep = ok[seg2] & (0.5 * (a2 + b2 + h2) > 0)
        seg, qa, qb, a, b, bound = seg2[keep], qa2[keep], qb2[keep], a2[keep], b2[keep], h2[keep]
        depth += 1
    return ok, bad, worst, evaluations


def certify_constraints(constraints: Sequence[Constraint], kinematics: Kinematics,
                        path: np.ndarray, deviation: np.ndarray | None = None) -> ConstraintCertificate:
    """Prove every constraint holds over the straight interpolation of `path` (K, dof) (module doc).

    With `deviation` (K-1, dof) [rad]: a motion that strays at most deviation[s] (per joint)
    from segment s (e.g. a timed trajectory between its samples, `trajectory_deviation`) is
    proved too: each segment keeps every constraint `segment_bound` of that displacement
    inside, for each constraint whose allowance is at most DEVIATION_SHARE of its margin
    (the others: the polyline only).

    Returns:
        ConstraintCertificate (certified, or the first failed segment and why).
    """
    Q = np.atleast_2d(np.asarray(path, dtype=float))
    if Q.shape[0] == 1:
        Q = np.vstack([Q, Q])
    queries = 0
    first, reason, text = None, "", ""
    for c in constraints:
        slack = None
        if deviation is not None:
            D = np.asarray(deviation, dtype=float)
            slack = c.segment_bound(kinematics, np.zeros_like(D), D)
            if slack.max(initial=0.0) > DEVIATION_SHARE * c.margin:
                slack = None  # too coarse a bound for this constraint: its samples' polyline only
        ok, bad, worst, n = _hold(c, kinematics, Q[:-1], Q[1:], slack)
        queries += n
        if not ok.all():
            s = int(np.argmin(ok))
            if first is None or s < first:
                first = s
                reason = "constraint" if bad[s] else "constraint_uncertified"
                text = c.explain(kinematics, worst[s])
    if first is None:
        return ConstraintCertificate(True, queries=queries)
    return ConstraintCertificate(False, first, reason, (text, ""), queries)


def trajectory_deviation(accelerations: np.ndarray, dt: float, jerk: np.ndarray) -> np.ndarray:
    """(K-1, dof) [rad]: how far a motion sampled every `dt` [s] can stray from the straight
    line between consecutive samples: |a| dt^2 / 8 with |a| bounded over the interval by the
    larger of the two samples' |acceleration| (K, dof) plus `jerk` (dof,) [rad/s^3] x dt / 2
    (the jerk limit the motion keeps)."""
    A = np.abs(np.asarray(accelerations, dtype=float))
    # |a| rises above the larger end by at most jerk x dt / 2 (up at the jerk, then down to the other end)
    amax = np.maximum(A[:-1], A[1:]) + 0.5 * np.asarray(jerk, dtype=float) * dt
    return amax * dt * dt / 8.0
