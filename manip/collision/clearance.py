"""Linearised clearance to the world: signed distances of the robot's sphere cover and their
gradients with respect to the joint positions, for trajectory optimisation.

The cover's balls hold every point of the link meshes (`manip.collision.spheres`), so a ball's
clearance is a lower bound of the link's true distance: keeping it above a margin keeps the
exact geometry at least that far from the obstacles. For each configuration, each moving
joint body and each obstacle, the nearest ball gives one term when it is closer than an
activation distance: its signed distance `d` and `grad = n^T J_p` (dof,), where `n` is the
obstacle's distance gradient at the ball's centre (unit, by central differences on the
closed-form distance) and `J_p` (3, dof) the translational Jacobian of the centre. An
occupancy map (`manip.collision.occupancy`) gives its terms the same way, from the exact
distance to its cells (`occupancy_kernels.map_nearest_terms`).
"""

from __future__ import annotations

import copy
import math
from typing import NamedTuple

import numpy as np

from manip.collision.broadphase import _obstacle_sd, _place, obstacle_local
from manip.collision.occupancy_kernels import map_nearest_terms
from manip.jit import kernel

#: Central-difference step [m] of the obstacle distance gradient at a ball centre.
_NORMAL_STEP = 1e-5
#: Rounding allowance [m] of the lower bounds `_nearest_terms` skips balls by.
_BOUND_SLACK = 1e-9
#: Consecutive configurations whose bodies' centres `_nearest_terms` bounds together.
_GROUP = 8


class ClearanceTerms(NamedTuple):
    """Active clearance terms of a batch of configurations (T terms).

    Attributes:
        config: (T,) index of the configuration of each term.
        distance: (T,) signed distance [m] of the nearest ball of one body to one obstacle.
        gradient: (T, dof) its gradient with respect to the joint positions [m/rad].
    """

    config: np.ndarray
    distance: np.ndarray
    gradient: np.ndarray


def joint_tables(kin) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The joints' tables of the clearance gradients of `Kinematics` kin: q_index (J,), axes,
    revolute (of `kin.joint_axes`, `kin.joint_revolute`), ancestors (J + 1, J + 1) bool:
    ancestors[j, k], joint k (1-based) moves the frame of joint j (1-based); row 0 = universe."""
    q_index, parent, _ = kin.fk_tables()
    J = len(q_index)
    ancestors = np.zeros((J + 1, J + 1), dtype=bool)
    for j in range(1, J + 1):
        a = j
        while a > 0:
            ancestors[j, a] = True
            a = int(parent[a - 1])
    return np.asarray(q_index), np.asarray(kin.joint_axes), np.asarray(kin.joint_revolute), ancestors


class ClearanceModel:
    """Clearance terms of a robot against its checker's current world (read at each call).

    Args:
        checker: a `CollisionChecker`; its fine sphere cover, obstacles and kinematics are used.
    """

    def __init__(self, checker):
        self.checker = checker
        self.dof = checker.kinematics.dof
        self._q_index, self._axes, self._revolute, self._ancestors = joint_tables(checker.kinematics)

    def bound_to(self, checker) -> ClearanceModel:
        """This model reading `checker` (e.g. a world snapshot of the same robot), sharing the
        robot-derived tables instead of building them again."""
        model = copy.copy(self)
        model.checker = checker
        return model

    def _tables(self, fine, moving: np.ndarray) -> tuple:
        """Balls sorted by body (joint), with each body's bounding ball; cached per cover."""
        # keyed by the cover object itself (kept alive here, so a rebuilt cover, e.g. after a
        # gripper change, can never be mistaken for this one)
        if getattr(self, "_cache_fine", None) is not fine or self._cache_moving != moving.size:
            joint, centres, radii, bodies, start, count, bc, br = balls_by_body(fine, moving)
            self._cache_fine, self._cache_moving = fine, moving.size
            self._cache = (centres, radii, joint, bodies, start, count, bc, br)
        return self._cache

    def terms(self, Q: np.ndarray, activation: float) -> ClearanceTerms:
        """The terms of configurations Q (N, dof) closer than `activation` [m] (padding not included)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        st = self.checker.state
        if len(st.obstacles) == 0:  # occupancy maps are obstacles too
            return self._empty()
        return self._terms_at(st, *st.joint_transforms(Q), activation)

    def _empty(self) -> ClearanceTerms:
        return ClearanceTerms(np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros((0, self.dof)))

    def terms_at(self, R: np.ndarray, p: np.ndarray, activation: float) -> ClearanceTerms:
        """`terms` of the configurations whose joint frames are R (N, J+1, 3, 3), p (N, J+1, 3)
        (`CollisionState.joint_transforms`), for a caller that has them already."""
        return self._terms_at(self.checker.state, R, p, activation)

    def _terms_at(self, st, R: np.ndarray, p: np.ndarray, activation: float) -> ClearanceTerms:
        """`terms_at` on the checker's state st (read once by the caller: a checker's `state` costs
        a few us)."""
        fine = st.fine
        if getattr(self, "_moving_of", None) is not fine:  # the moving balls, per cover (as `_tables`)
            self._moving_of, self._moving = fine, np.flatnonzero(fine.joint != 0)
        moving = self._moving
        if len(st.obstacles) == 0 or moving.size == 0:
            return self._empty()
        tables = self._tables(fine, moving)
        n_i, s_i, _, dist, x, normal = _nearest_terms(R, p, *tables, float(activation), *st.obstacle_tables)
        for o, grid in st.occupancy_maps:   # occupancy maps: their own distances (`collision.occupancy`)
            extra = map_nearest_terms(R, p, *tables, float(activation), *grid)
            n_i, s_i, dist, x, normal = (np.concatenate(c) for c in zip((n_i, s_i, dist, x, normal), extra))
        sj = tables[2]
        if n_i.size == 0:
            return self._empty()
        grad = _term_gradients(R, p, n_i, sj[s_i], x, normal, self._ancestors, self._axes, self._revolute,
                               self._q_index, self.dof)
        return ClearanceTerms(n_i, dist, grad)


def balls_by_body(fine, moving: np.ndarray) -> tuple:
    """The balls `moving` (indices) of a sphere cover sorted by body (joint), and each body's
    bounding ball: (joint (S,), centres (S, 3) [m], radii (S,) [m], bodies (B,), start (B,),
    count (B,): body b's balls are [start[b], start[b] + count[b]), body centres (B, 3) in its
    joint frame [m], body radii (B,) [m])."""
    order = moving[np.argsort(fine.joint[moving], kind="stable")]
    joint = np.ascontiguousarray(fine.joint[order], dtype=np.int64)
    centres = np.ascontiguousarray(fine.centres[order], dtype=float)
    radii = np.ascontiguousarray(fine.radii[order], dtype=float)
    bodies, start, count = np.unique(joint, return_index=True, return_counts=True)
    bc = np.empty((bodies.size, 3))
    br = np.empty(bodies.size)
    for b in range(bodies.size):
        c, r = centres[start[b] : start[b] + count[b]], radii[start[b] : start[b] + count[b]]
        bc[b] = ((c - r[:, None]).min(axis=0) + (c + r[:, None]).max(axis=0)) / 2
        br[b] = float((np.linalg.norm(c - bc[b], axis=1) + r).max())
    return (joint, centres, radii, bodies.astype(np.int64), start.astype(np.int64), count.astype(np.int64), bc, br)


@kernel
def _term_gradients(R, p, n_i, body, x, normal, ancestors, axes, revolute, q_index, dof):
    """grad[t] = n_t^T J_p(x_t) (T, dof): the normal times the translational Jacobian of each
    term's ball centre x_t on body `body[t]` (a joint index) at configuration n_i[t]."""
    T = n_i.shape[0]
    grad = np.zeros((T, dof))
    for t in range(T):
        n = n_i[t]
        for k in range(1, q_index.shape[0] + 1):
            if not ancestors[body[t], k]:
                continue
            e = axes[k - 1]
            a0 = R[n, k, 0, 0] * e[0] + R[n, k, 0, 1] * e[1] + R[n, k, 0, 2] * e[2]  # world axis of joint k
            a1 = R[n, k, 1, 0] * e[0] + R[n, k, 1, 1] * e[1] + R[n, k, 1, 2] * e[2]
            a2 = R[n, k, 2, 0] * e[0] + R[n, k, 2, 1] * e[1] + R[n, k, 2, 2] * e[2]
            if revolute[k - 1]:
                r0 = x[t, 0] - p[n, k, 0]
                r1 = x[t, 1] - p[n, k, 1]
                r2 = x[t, 2] - p[n, k, 2]
                c0, c1, c2 = a1 * r2 - a2 * r1, a2 * r0 - a0 * r2, a0 * r1 - a1 * r0
            else:
                c0, c1, c2 = a0, a1, a2
            grad[t, q_index[k - 1]] += normal[t, 0] * c0 + normal[t, 1] * c1 + normal[t, 2] * c2
    return grad


@kernel(inline="always")
def _sd_subgradient(x, o, oR, oc, oh, orho, ocyl, g):
    """g (3,) = a subgradient of obstacle o's signed distance at the point x (3,) (base frame;
    the shapes are convex, so sd(y) >= sd(x) + g . (y - x) for every y). False when none is at
    hand (x on a cylinder's axis)."""
    l0, l1, l2 = obstacle_local(x, o, oR, oc)
    s2 = 1.0 if l2 >= 0.0 else -1.0
    z = abs(l2) - oh[o, 2]
    if ocyl[o]:
        rad = math.sqrt(l0 * l0 + l1 * l1)
        if rad < 1e-12:
            return False
        u0, u1 = l0 / rad, l1 / rad
        r = rad - oh[o, 0]
        if r > 0.0 or z > 0.0:  # outside: the unit vector from the nearest surface point
            rr, zz = max(r, 0.0), max(z, 0.0)
            norm = math.sqrt(rr * rr + zz * zz)
            k0, k1, k2 = rr / norm * u0, rr / norm * u1, zz / norm * s2
        elif r > z:  # inside: the gradient of the larger of the two depths
            k0, k1, k2 = u0, u1, 0.0
        else:
            k0, k1, k2 = 0.0, 0.0, s2
    else:
        s0 = 1.0 if l0 >= 0.0 else -1.0
        s1 = 1.0 if l1 >= 0.0 else -1.0
        a, b = abs(l0) - oh[o, 0], abs(l1) - oh[o, 1]
        if a > 0.0 or b > 0.0 or z > 0.0:
            aa, bb, zz = max(a, 0.0), max(b, 0.0), max(z, 0.0)
            norm = math.sqrt(aa * aa + bb * bb + zz * zz)
            k0, k1, k2 = aa / norm * s0, bb / norm * s1, zz / norm * s2
        elif a >= b and a >= z:
            k0, k1, k2 = s0, 0.0, 0.0
        elif b >= z:
            k0, k1, k2 = 0.0, s1, 0.0
        else:
            k0, k1, k2 = 0.0, 0.0, s2
    for r_ in range(3):
        g[r_] = oR[o, r_, 0] * k0 + oR[o, r_, 1] * k1 + oR[o, r_, 2] * k2
    return True


@kernel
def _nearest_terms(R, p, centres, radii, joint, bodies, start, count, body_centre, body_radius, activation,
                   oR, oc, oh, orho, ocyl):
    """For each (configuration, body, obstacle) the nearest ball, kept when closer than `activation`.

    A body whose bounding ball is farther than `activation` from an obstacle is skipped. The
    obstacles are convex, so a subgradient g of the distance at the body's centre x_b bounds
    every ball's distance from below, sd(x_b) + g . (x_s - x_b) - r_s: the ball of the lowest
    bound is measured first and only the balls whose bound is not above its distance (or the
    activation) after it, in order (`_BOUND_SLACK` for rounding), so the nearest ball, the
    first of equals, is the one a search of every ball finds.

    Returns:
        (n, s, o (T,) int64, distance (T,) [m], centre x (T, 3), unit normal (T, 3)).
    """
    N = R.shape[0]
    B = bodies.shape[0]
    O = oc.shape[0]
    best_d = np.full((N, B, O), np.inf)
    best_s = np.zeros((N, B, O), dtype=np.int64)
    x = np.empty(3)
    g = np.empty(3)
    gb = np.empty(3)
    low = np.empty(centres.shape[0])
    XB = np.empty((N, B, 3))  # the bodies' centres
    for n in range(N):
        for b in range(B):
            _place(R, p, n, bodies[b], body_centre[b], XB[n, b])
    gc = np.empty(3)
    for b in range(B):
        jb = bodies[b]
        for n0 in range(0, N, _GROUP):
            n1 = min(N, n0 + _GROUP)
            # the ball holding the body's centres of configurations n0..n1-1: an obstacle farther
            # than the activation from it (the distance is 1-Lipschitz) is far from all of them
            for k in range(3):
                lo_k, hi_k = XB[n0, b, k], XB[n0, b, k]
                for n in range(n0 + 1, n1):
                    lo_k, hi_k = min(lo_k, XB[n, b, k]), max(hi_k, XB[n, b, k])
                gc[k] = 0.5 * (lo_k + hi_k)
            gr = 0.0
            for n in range(n0, n1):
                e0, e1, e2 = XB[n, b, 0] - gc[0], XB[n, b, 1] - gc[1], XB[n, b, 2] - gc[2]
                gr = max(gr, math.sqrt(e0 * e0 + e1 * e1 + e2 * e2))
            for o in range(O):
                if _obstacle_sd(gc, o, oR, oc, oh, orho, ocyl) - gr - body_radius[b] > activation + _BOUND_SLACK:
                    continue
                for n in range(n0, n1):
                    xb = XB[n, b]
                    sd_b = _obstacle_sd(xb, o, oR, oc, oh, orho, ocyl)
                    if not sd_b - body_radius[b] < activation:
                        continue
                    first, end = start[b], start[b] + count[b]
                    bound = activation + _BOUND_SLACK
                    t = -1
                    d_t = np.inf
                    if _sd_subgradient(xb, o, oR, oc, oh, orho, ocyl, g):
                        for k in range(3):  # the subgradient in the body's frame
                            gb[k] = R[n, jb, 0, k] * g[0] + R[n, jb, 1, k] * g[1] + R[n, jb, 2, k] * g[2]
                        lowest = np.inf
                        for s in range(first, end):
                            low[s] = sd_b - radii[s] + (gb[0] * (centres[s, 0] - body_centre[b, 0])
                                                        + gb[1] * (centres[s, 1] - body_centre[b, 1])
                                                        + gb[2] * (centres[s, 2] - body_centre[b, 2]))
                            if low[s] < lowest:
                                lowest, t = low[s], s
                        if lowest > bound:
                            continue  # no ball within the activation distance
                        _place(R, p, n, joint[t], centres[t], x)
                        d_t = _obstacle_sd(x, o, oR, oc, oh, orho, ocyl) - radii[t]
                        bound = min(bound, d_t + _BOUND_SLACK)
                    else:
                        for s in range(first, end):
                            low[s] = -np.inf
                    for s in range(first, end):
                        if low[s] > bound:
                            continue  # farther than a ball measured
                        if s == t:
                            d = d_t
                        else:
                            _place(R, p, n, joint[s], centres[s], x)
                            d = _obstacle_sd(x, o, oR, oc, oh, orho, ocyl) - radii[s]
                        if d < best_d[n, b, o]:
                            best_d[n, b, o] = d
                            best_s[n, b, o] = s
    T = 0
    for n in range(N):
        for b in range(B):
            for o in range(O):
                if best_d[n, b, o] < activation:
                    T += 1
    n_out = np.empty(T, dtype=np.int64)
    s_out = np.empty(T, dtype=np.int64)
    o_out = np.empty(T, dtype=np.int64)
    d_out = np.empty(T)
    x_out = np.empty((T, 3))
    nrm = np.empty((T, 3))
    y = np.empty(3)
    t = 0
    for n in range(N):
        for b in range(B):
            for o in range(O):
                if best_d[n, b, o] < activation:
                    s = best_s[n, b, o]
                    n_out[t], s_out[t], o_out[t], d_out[t] = n, s, o, best_d[n, b, o]
                    _place(R, p, n, joint[s], centres[s], x_out[t])
                    norm = 0.0
                    for k in range(3):
                        y[:] = x_out[t]
                        y[k] += _NORMAL_STEP
                        hi = _obstacle_sd(y, o, oR, oc, oh, orho, ocyl)
                        y[k] -= 2 * _NORMAL_STEP
                        lo = _obstacle_sd(y, o, oR, oc, oh, orho, ocyl)
                        nrm[t, k] = (hi - lo) / (2 * _NORMAL_STEP)
                        norm += nrm[t, k] ** 2
                    norm = max(math.sqrt(norm), 1e-12)
                    for k in range(3):
                        nrm[t, k] /= norm
                    t += 1
    return n_out, s_out, o_out, d_out, x_out, nrm
