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

from manip.collision.clearance import ClearanceModel, ClearanceTerms, balls_by_body
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
        kin = self.checker.kinematics
        q_index, parent, _ = kin.fk_tables()
        J = len(q_index)
        self._q_index = np.asarray(q_index)
        self._axes = np.asarray(kin.joint_axes)
        self._revolute = np.asarray(kin.joint_revolute)
        self._ancestors = np.zeros((J + 1, J + 1), dtype=bool)
        for j in range(1, J + 1):
            a = j
            while a > 0:
                self._ancestors[j, a] = True
                a = int(parent[a - 1])
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
        bodies of two different arms; cached per cover (by content: a world snapshot's state
        hands out its own copy of the same cover)."""
        key = hash((fine.joint.tobytes(), fine.radii.tobytes(), np.ascontiguousarray(fine.centres).tobytes()))
        if self._cache is None or self._cache[0] != key:
            joint, centres, radii, bodies, start, count, bc, br = balls_by_body(fine, np.flatnonzero(fine.joint != 0))
            arm = self.arm_of_joint[bodies]
            pa, pb = np.triu_indices(bodies.size, 1)
            cross = (arm[pa] != arm[pb]) & (arm[pa] >= 0) & (arm[pb] >= 0)
            self._cache = (key, joint, centres, radii, bodies, start, count, bc, br, pa[cross], pb[cross])
        return self._cache[1:]

    def terms(self, Q: np.ndarray, activation: float) -> ClearanceTerms:
        """The world terms of configurations Q (N, dof), then the arm-arm terms closer than `activation` [m]."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        base = self.clearance.terms(Q, activation)
        st = self.checker.state
        joint, centres, radii, bodies, start, count, bc, br, pa, pb = self._tables(st.fine)
        if pa.size == 0:
            return base
        R, p = st.joint_transforms(Q)
        BC = np.einsum("nbij,bj->nbi", R[:, bodies], bc) + p[:, bodies]              # (N, B, 3)
        gap = np.linalg.norm(BC[:, pa] - BC[:, pb], axis=2) - br[pa] - br[pb]       # (N, P)
        n_act, p_act = np.nonzero(gap < activation)
        if n_act.size == 0:
            return base
        n_act = n_act.astype(np.int64)
        d, grad = _nearest_ball_pairs(R, p, n_act, pa[p_act], pb[p_act], bodies, start, count, centres, radii,
                                      float(activation), self._ancestors, self._axes, self._revolute, self._q_index,
                                      self.dof)
        keep = d < activation
        if not keep.any():
            return base
        return ClearanceTerms(np.concatenate([base.config, n_act[keep]]), np.concatenate([base.distance, d[keep]]),
                              np.concatenate([base.gradient, grad[keep]], axis=0))

@kernel
def _nearest_ball_pairs(R, p, n_act, a_act, b_act, bodies, start, count, centres, radii, activation, ancestors, axes,
                        revolute, q_index, dof):
    """For each (configuration n_act[t], body a_act[t] of one arm, body b_act[t] of another) the
    nearest pair of their balls: its distance (T,) [m] and, when below `activation`, its
    gradient (T, dof) n^T (J_p(x_a) - J_p(x_b)), n the unit vector from x_b to x_a."""
    T = n_act.shape[0]
    d_out = np.full(T, np.inf)
    grad = np.zeros((T, dof))
    xa = np.empty(3)
    xb = np.empty(3)
    y = np.empty(3)
    for t in range(T):
        n, a, b = n_act[t], a_act[t], b_act[t]
        ja, jb = bodies[a], bodies[b]
        K = count[b]
        Y = np.empty((K, 3))
        for k in range(K):
            c = centres[start[b] + k]
            for r in range(3):
                Y[k, r] = R[n, jb, r, 0] * c[0] + R[n, jb, r, 1] * c[1] + R[n, jb, r, 2] * c[2] + p[n, jb, r]
        for s in range(start[a], start[a] + count[a]):
            c = centres[s]
            for r in range(3):
                y[r] = R[n, ja, r, 0] * c[0] + R[n, ja, r, 1] * c[1] + R[n, ja, r, 2] * c[2] + p[n, ja, r]
            for k in range(K):
                d = math.sqrt((y[0] - Y[k, 0]) ** 2 + (y[1] - Y[k, 1]) ** 2 + (y[2] - Y[k, 2]) ** 2) \
                    - radii[s] - radii[start[b] + k]
                if d < d_out[t]:
                    d_out[t] = d
                    for r in range(3):
                        xa[r] = y[r]
                        xb[r] = Y[k, r]
        if d_out[t] >= activation:
            continue
        nx, ny, nz = xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]
        norm = max(math.sqrt(nx * nx + ny * ny + nz * nz), 1e-12)
        nx, ny, nz = nx / norm, ny / norm, nz / norm
        for side in range(2):
            body = ja if side == 0 else jb
            sign = 1.0 if side == 0 else -1.0
            for k in range(1, ancestors.shape[0]):
                if not ancestors[body, k]:
                    continue
                e = axes[k - 1]
                a0 = R[n, k, 0, 0] * e[0] + R[n, k, 0, 1] * e[1] + R[n, k, 0, 2] * e[2]
                a1 = R[n, k, 1, 0] * e[0] + R[n, k, 1, 1] * e[1] + R[n, k, 1, 2] * e[2]
                a2 = R[n, k, 2, 0] * e[0] + R[n, k, 2, 1] * e[1] + R[n, k, 2, 2] * e[2]
                if revolute[k - 1]:
                    x = xa if side == 0 else xb
                    r0, r1, r2 = x[0] - p[n, k, 0], x[1] - p[n, k, 1], x[2] - p[n, k, 2]
                    c0, c1, c2 = a1 * r2 - a2 * r1, a2 * r0 - a0 * r2, a0 * r1 - a1 * r0
                else:
                    c0, c1, c2 = a0, a1, a2
                grad[t, q_index[k - 1]] += sign * (nx * c0 + ny * c1 + nz * c2)
    return d_out, grad


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
