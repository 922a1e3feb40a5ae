"""Clearance between the arms of a multi-arm robot, for trajectory optimisation.

`ClearanceModel` gives the optimiser the robot's clearance to the world; with two arms the
nearest thing to an arm is often the other arm, which the world terms do not see (the
optimised motion then fails the exact validation and the plan falls back to a slower
timing). `ArmClearance` adds, for each configuration and each pair of moving bodies (joint
frames) of two different arms (`RobotConfig.arms`), the nearest pair of their sphere-cover
balls when closer than the activation distance: its signed distance
d = |x_a - x_b| - r_a - r_b [m] (a lower bound of the two links' true distance, as the balls
hold the meshes) and its gradient n^T (J_p(x_a) - J_p(x_b)) with n = (x_a - x_b) / |x_a - x_b|.
Body pairs whose bounding balls are farther apart than the activation are skipped.
"""

from __future__ import annotations

import math

import numpy as np

from manip.collision.broadphase import _distance, _place
from manip.collision.clearance import ClearanceModel, ClearanceTerms, balls_by_body, joint_tables
from manip.jit import kernel


class ArmClearance:
    """A `ClearanceModel` plus the terms between the arms (see the module docstring).

    Args:
        clearance: the world clearance model of the robot's checker.
        arm_of_joint: (J + 1,) int: the arm of each joint frame (-1 for the base, frame 0).
    """

    def __init__(self, clearance: ClearanceModel, arm_of_joint: np.ndarray):
        self.clearance = clearance
        self.checker = clearance.checker
        self.dof = clearance.dof
        self.arm_of_joint = np.asarray(arm_of_joint, dtype=np.int64)
        self._q_index, self._axes, self._revolute, self._ancestors = joint_tables(self.checker.kinematics)
        self._cache = None

    def bound_to(self, checker) -> ArmClearance:
        """This model reading `checker` (a world snapshot of the same robot)."""
        out = ArmClearance.__new__(ArmClearance)
        out.__dict__.update(self.__dict__)
        out.clearance = self.clearance.bound_to(checker)
        out.checker = checker
        return out

    def _tables(self, fine) -> tuple:
        """The moving balls sorted by body, each body's bounding ball and slice, and the pairs of
        bodies of two different arms; cached per cover, keyed by the cover object itself (kept
        alive here, so a rebuilt cover, e.g. after an attach, can never be mistaken for this
        one; world snapshots share the checker's cover), as `ClearanceModel`."""
        if self._cache is None or self._cache[0] is not fine:
            _joint, centres, radii, bodies, start, count, bc, br = balls_by_body(fine, np.flatnonzero(fine.joint != 0))
            arm = self.arm_of_joint[bodies]
            pa, pb = np.triu_indices(bodies.size, 1)
            cross = (arm[pa] != arm[pb]) & (arm[pa] >= 0) & (arm[pb] >= 0)
            self._cache = (fine, bodies, start, count, centres, radii, bc, br, pa[cross], pb[cross])
        return self._cache[1:]

    def terms(self, Q: np.ndarray, activation: float) -> ClearanceTerms:
        """The world terms of configurations Q (N, dof), then the arm-arm terms closer than `activation` [m]."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        st = self.checker.state
        R, p = st.joint_transforms(Q)
        base = self.clearance.terms_at(R, p, activation)
        tables = self._tables(st.fine)
        if tables[-1].size == 0:
            return base
        n, d, grad = _arm_terms(R, p, *tables, float(activation), self._ancestors, self._axes, self._revolute,
                                self._q_index, self.dof)
        if n.size == 0:
            return base
        return ClearanceTerms(np.concatenate([base.config, n]), np.concatenate([base.distance, d]),
                              np.concatenate([base.gradient, grad], axis=0))


@kernel
def _arm_terms(R, p, bodies, start, count, centres, radii, bc, br, pa, pb, activation, ancestors, axes, revolute,
               q_index, dof):
    """The arm-arm terms of N configurations: for each configuration and each body pair (pa[e],
    pb[e]) (indices into `bodies`) whose bounding balls come closer than `activation` [m], the
    nearest pair of their balls when closer than `activation`.

    The search is exact: a ball of body a whose distance to body b's bounding ball (which holds
    all of b's balls) is already no closer than the best pair found cannot give a nearer pair.

    Returns:
        n (T,) int64 configuration, distance (T,) [m], gradient (T, dof) n^T (J_p(x_a) - J_p(x_b)),
        n the unit vector from x_b to x_a.
    """
    N = R.shape[0]
    B = bodies.shape[0]
    E = pa.shape[0]
    S = centres.shape[0]
    cap = N * E  # at most one term per configuration and body pair
    n_out = np.empty(cap, dtype=np.int64)
    d_out = np.empty(cap)
    xa_out = np.empty((cap, 3))
    xb_out = np.empty((cap, 3))
    ja_out = np.empty(cap, dtype=np.int64)
    jb_out = np.empty(cap, dtype=np.int64)
    T = 0
    xbody = np.empty((B, 3))
    xs = np.empty((S, 3))
    placed = np.zeros(B, dtype=np.bool_)
    for n in range(N):
        for b in range(B):
            _place(R, p, n, bodies[b], bc[b], xbody[b])
        placed[:] = False
        for e in range(E):
            a, b = pa[e], pb[e]
            if _distance(xbody, a, xbody, b) - br[a] - br[b] >= activation:
                continue
            for body in (a, b):
                if not placed[body]:
                    for s in range(start[body], start[body] + count[body]):
                        _place(R, p, n, bodies[body], centres[s], xs[s])
                    placed[body] = True
            best = activation
            ia, ib = -1, -1
            for s in range(start[a], start[a] + count[a]):
                if _distance(xs, s, xbody, b) - radii[s] - br[b] >= best:
                    continue
                for k in range(start[b], start[b] + count[b]):
                    d = _distance(xs, s, xs, k) - radii[s] - radii[k]
                    if d < best:
                        best, ia, ib = d, s, k
            if ia < 0:
                continue
            n_out[T], d_out[T], ja_out[T], jb_out[T] = n, best, bodies[a], bodies[b]
            for r in range(3):
                xa_out[T, r] = xs[ia, r]
                xb_out[T, r] = xs[ib, r]
            T += 1
    grad = np.zeros((T, dof))
    for t in range(T):
        n = n_out[t]
        nx, ny, nz = xa_out[t, 0] - xb_out[t, 0], xa_out[t, 1] - xb_out[t, 1], xa_out[t, 2] - xb_out[t, 2]
        norm = max(math.sqrt(nx * nx + ny * ny + nz * nz), 1e-12)
        nx, ny, nz = nx / norm, ny / norm, nz / norm
        for side in range(2):
            body = ja_out[t] if side == 0 else jb_out[t]
            sign = 1.0 if side == 0 else -1.0
            for k in range(1, ancestors.shape[0]):
                if not ancestors[body, k]:
                    continue
                e = axes[k - 1]
                a0 = R[n, k, 0, 0] * e[0] + R[n, k, 0, 1] * e[1] + R[n, k, 0, 2] * e[2]
                a1 = R[n, k, 1, 0] * e[0] + R[n, k, 1, 1] * e[1] + R[n, k, 1, 2] * e[2]
                a2 = R[n, k, 2, 0] * e[0] + R[n, k, 2, 1] * e[1] + R[n, k, 2, 2] * e[2]
                if revolute[k - 1]:
                    if side == 0:
                        r0, r1, r2 = xa_out[t, 0] - p[n, k, 0], xa_out[t, 1] - p[n, k, 1], xa_out[t, 2] - p[n, k, 2]
                    else:
                        r0, r1, r2 = xb_out[t, 0] - p[n, k, 0], xb_out[t, 1] - p[n, k, 1], xb_out[t, 2] - p[n, k, 2]
                    c0, c1, c2 = a1 * r2 - a2 * r1, a2 * r0 - a0 * r2, a0 * r1 - a1 * r0
                else:
                    c0, c1, c2 = a0, a1, a2
                grad[t, q_index[k - 1]] += sign * (nx * c0 + ny * c1 + nz * c2)
    return n_out[:T].copy(), d_out[:T].copy(), grad


def arm_clearance(checker, config) -> ClearanceModel | ArmClearance:
    """The clearance model of the optimiser: with the arm-arm terms for a multi-arm robot
    (`config.arms`), the world's alone otherwise."""
    model = ClearanceModel(checker)
    if not config.arms:
        return model
    kin = checker.kinematics
    arm_of_joint = np.full(kin.model.njoints, -1, dtype=np.int64)
    for j in range(1, kin.model.njoints):
        for i, arm in enumerate(config.arms):
            if arm.owns(kin.model.names[j]):
                arm_of_joint[j] = i
    return ArmClearance(model, arm_of_joint)
