"""Ruckig segments between waypoints (`time_parameterize`'s building blocks).

A segment joins two waypoints [rad] with given velocities [rad/s] and zero accelerations
at both ends; `assemble` concatenates segments into one `PiecewiseJerkProfile`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import ruckig

from manip.jit import kernel
from manip.limits import JointLimits
from manip.timing.shared import LIMIT_MARGIN, RUCKIG_ERRORS, RestToRest, RuckigFailure
from manip.trajectory import PiecewiseJerkProfile

# Deviation is measured on each segment every this many seconds (at most).
DEVIATION_STEP = 0.01


@dataclass
class Segment:
    """One ruckig segment between two waypoints: constant-jerk pieces per joint (local times)."""

    duration: float
    knots: np.ndarray  # (dof, 9) local times
    p: np.ndarray  # (dof, 8)
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray
    pos_min: np.ndarray  # (dof,)
    pos_max: np.ndarray
    deviation: float = 0.0  # from the input path [rad] (set by the caller)


class SegmentSolver:
    """Reuses one ruckig instance for state-to-state segments with zero end accelerations.

    Args:
        limits: the velocity, acceleration and jerk limits of the motion; the segments keep
            `used` = these times (1 - LIMIT_MARGIN).
    """

    def __init__(self, limits: JointLimits):
        self.dof = limits.dof
        m = 1.0 - LIMIT_MARGIN
        self.used = limits.scaled(m, m, jerk=m)
        self.otg = ruckig.Ruckig(self.dof)
        self.inp = ruckig.InputParameter(self.dof)
        self.inp.max_velocity = self.used.velocity.tolist()
        self.inp.max_acceleration = self.used.acceleration.tolist()
        self.inp.max_jerk = self.used.jerk.tolist()
        zeros = [0.0] * self.dof
        self.inp.current_acceleration = zeros
        self.inp.target_acceleration = zeros
        self.inp.synchronization = ruckig.Synchronization.Phase
        self.traj = ruckig.Trajectory(self.dof)
        self.line = RestToRest()  # 1-D problem along a straight line (rest to rest)

    def solve_line(self, p0: np.ndarray, p1: np.ndarray) -> Segment:
        """Rest-to-rest along the straight line p0 -> p1 (exact; time-optimal for that line).

        Ruckig's phase synchronisation falls back to time synchronisation (which leaves
        the line) when the scaled profile of the slowest joint breaks another joint's
        limit, so the line is timed as a 1-D problem in its arc length `s` instead:
        `q = p0 + u s` with `|u| = 1` and the limits `min_d limit_d / |u_d|` on `s`.
        """
        d = p1 - p0
        length = float(np.linalg.norm(d))
        dof = self.dof
        if length == 0.0:
            z = np.zeros((dof, 8))
            return Segment(0.0, np.zeros((dof, 9)), np.repeat(p0[:, None], 8, axis=1), z, z.copy(), z.copy(),
                            p0.copy(), p0.copy())
        u = d / length
        mag = np.abs(u)
        nz = mag > 0
        try:
            res = self.line.calculate(
                length,
                float(np.min(self.used.velocity[nz] / mag[nz])),
                float(np.min(self.used.acceleration[nz] / mag[nz])),
                float(np.min(self.used.jerk[nz] / mag[nz])),
            )
        except RUCKIG_ERRORS as e:
            raise RuckigFailure(f"ruckig rejected a straight segment of length {length} rad: {e}") from e
        if res != ruckig.Result.Working:
            raise RuckigFailure(f"ruckig returned {res} on a straight segment of length {length} rad")
        prof = self.line.rest_profile("segment")
        duration = float(self.line.traj.duration)
        knots1 = np.zeros(9)
        knots1[1:8] = np.cumsum(prof.t)
        knots1[8] = max(duration, knots1[7])
        js = np.zeros(8)
        js[:7] = prof.j
        uc = u[:, None]
        seg = Segment(
            duration,
            np.repeat(knots1[None, :], dof, axis=0),
            p0[:, None] + uc * np.asarray(prof.p)[None, :],
            uc * np.asarray(prof.v)[None, :],
            uc * np.asarray(prof.a)[None, :],
            uc * js[None, :],
            np.minimum(p0, p1),
            np.maximum(p0, p1),
        )
        return seg

    def solve(self, p0: np.ndarray, v0: np.ndarray, p1: np.ndarray, v1: np.ndarray) -> Segment:
        """From p0 [rad] at velocity v0 [rad/s] to p1 at v1, all (dof,), phase-synchronised."""
        inp = self.inp
        inp.current_position = p0.tolist()
        inp.current_velocity = v0.tolist()
        inp.target_position = p1.tolist()
        inp.target_velocity = v1.tolist()
        try:
            res = self.otg.calculate(inp, self.traj)
        except RUCKIG_ERRORS as e:
            raise RuckigFailure(f"ruckig rejected the segment from {p0} / {v0} to {p1} / {v1}: {e}") from e
        if res != ruckig.Result.Working:
            raise RuckigFailure(f"ruckig returned {res} from {p0} / {v0} to {p1} / {v1}")
        tr = self.traj
        duration = float(tr.duration)
        dof = self.dof
        t = np.empty((dof, 7))
        j = np.empty((dof, 8))
        a = np.empty((dof, 8))
        v = np.empty((dof, 8))
        p = np.empty((dof, 8))
        for d, prof in enumerate(tr.profiles[0]):
            if prof.brake.duration > 0 or prof.accel.duration > 0:
                raise RuckigFailure("ruckig used a brake/accel pre-trajectory (input outside limits?)")
            t[d] = prof.t
            j[d, :7] = prof.j
            a[d] = prof.a
            v[d] = prof.v
            p[d] = prof.p
        j[:, 7] = 0.0  # after the profile: hold (ruckig integrates with zero jerk)
        knots = np.zeros((dof, 9))
        knots[:, 1:8] = np.cumsum(t, axis=1)
        knots[:, 8] = np.maximum(duration, knots[:, 7])
        ext = tr.position_extrema
        pos_min = np.array([b.min for b in ext])
        pos_max = np.array([b.max for b in ext])
        return Segment(duration, knots, p, v, a, j, pos_min, pos_max)


def segment_deviation(seg: Segment, sub_path: np.ndarray) -> float:
    """Distance of the segment's motion from the stretch `sub_path` of the input path [rad].

    Sampled every <= `DEVIATION_STEP`; the blend planner adds the sampling error bound.
    """
    if seg.duration <= 0:
        return 0.0
    n = max(8, int(np.ceil(seg.duration / DEVIATION_STEP)) + 1)
    ts = np.linspace(0.0, seg.duration, n)
    return float(max_polyline_distance(seg.knots, seg.p, seg.v, seg.a, seg.j, ts,
                                        np.ascontiguousarray(sub_path, dtype=np.float64)))


@kernel
def max_polyline_distance(knots, p0, v0, a0, j, ts, path):  # pragma: no cover - compiled
    """max over the times ts (N,) of the Euclidean distance [rad] from the constant-jerk
    pieces (`evaluate_pieces`' arrays: knots (dof, M+1), p0, v0, a0, j (dof, M)) to the
    polyline `path` (P, dof): `polyline_distances(evaluate_pieces(...)[0], path).max()` in
    one compiled loop, without the (N, P, dof) temporaries."""
    dof, m = p0.shape
    segs = path.shape[0] - 1
    q = np.empty(dof)
    worst = 0.0
    for n in range(ts.shape[0]):
        t = ts[n]
        for d in range(dof):
            k = 0
            for c in range(1, m):
                if t >= knots[d, c]:
                    k += 1
            tau = t - knots[d, k]
            q[d] = p0[d, k] + tau * (v0[d, k] + tau * (a0[d, k] / 2.0 + tau * j[d, k] / 6.0))
        best = math.inf
        if segs < 1:
            s2 = 0.0
            for d in range(dof):
                s2 += (q[d] - path[0, d]) ** 2
            best = math.sqrt(s2)
        for s in range(segs):
            dd = 0.0
            rd = 0.0
            for d in range(dof):
                e = path[s + 1, d] - path[s, d]
                dd += e * e
                rd += (q[d] - path[s, d]) * e
            lam = min(max(rd / dd, 0.0), 1.0) if dd > 0 else 0.0
            s2 = 0.0
            for d in range(dof):
                r = q[d] - path[s, d] - lam * (path[s + 1, d] - path[s, d])
                s2 += r * r
            dist = math.sqrt(s2)
            if dist < best:
                best = dist
        if best > worst:
            worst = best
    return worst


def assemble(segments: list[Segment], goal: np.ndarray) -> PiecewiseJerkProfile:
    """Concatenate segments into one profile, ending with the exact `goal` (dof,) [rad] at rest."""
    dof = goal.size
    knots, p, v, a, j = [], [], [], [], []
    offset = 0.0
    for seg in segments:
        knots.append(np.minimum(seg.knots[:, :8], seg.duration) + offset)
        p.append(seg.p)
        v.append(seg.v)
        a.append(seg.a)
        j.append(seg.j)
        offset += seg.duration
    zeros = np.zeros((dof, 1))
    knots += [np.full((dof, 1), offset), np.full((dof, 1), offset)]
    p.append(goal[:, None])
    v.append(zeros)
    a.append(zeros)
    j.append(zeros)
    return PiecewiseJerkProfile(
        knots=np.concatenate(knots, axis=1),
        p0=np.concatenate(p, axis=1),
        v0=np.concatenate(v, axis=1),
        a0=np.concatenate(a, axis=1),
        j=np.concatenate(j, axis=1),
    )
