"""Compiled projection and certificate of one `OrientationConstraint` (its hot paths).

The constrained search projects every step onto the cone and certifies every step's
segment; in NumPy each call costs 0.1-0.5 ms of array overhead around a few microseconds of
kinematics. These kernels do the same arithmetic per configuration in one call:

- `project_tilt`: `constraints.project`'s damped Gauss-Newton for the one row of the tilt;
- `hold_tilt`: `constraints.certify`'s proof for each segment: the ends, the first cut into
  the pieces the ends' depth would certify (at most `first_split`), then bisection of the
  pieces still open (depth first, at most `max_depth` halvings).

The tilt is computed as `OrientationConstraint.tilt` (arccos of u . d, u the link's axis in
the world) and its gradient as `OrientationConstraint.residual_and_jacobian`.
"""

from __future__ import annotations

import math

import numpy as np

from manip.jit import kernel
from manip.kinematics import chain_frames, frame_jacobian_into


@kernel
def _axis_up(q, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, axis, R, p, Rf, pf, Jac, u):
    """The link's axis in the world into u (3,) at q (dof,) (and its frame Jacobian into Jac (6, dof))."""
    chain_frames(q, q_index, parent, table, R, p)
    frame_jacobian_into(R, p, chain, axes, revolute, q_index, f_joint, f_R, f_p, Rf, pf, Jac)
    for r in range(3):
        u[r] = Rf[r, 0] * axis[0] + Rf[r, 1] * axis[1] + Rf[r, 2] * axis[2]


@kernel
def _tilt_at(q, q_index, parent, table, f_joint, f_R, axis, direction, R, p):
    """The tilt [rad] at q (dof,): arccos(u . d) of the link's axis u (kinematics only, no Jacobian)."""
    chain_frames(q, q_index, parent, table, R, p)
    c = 0.0
    for r in range(3):
        ur = 0.0
        for k in range(3):
            rk = R[f_joint, r, 0] * f_R[0, k] + R[f_joint, r, 1] * f_R[1, k] + R[f_joint, r, 2] * f_R[2, k]
            ur += rk * axis[k]
        c += ur * direction[r]
    return math.acos(min(1.0, max(-1.0, c)))


@kernel
def project_tilt(q0, lower, upper, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, axis,
                 direction, tolerance, margin, damping, max_steps):
    """(q (dof,), converged): q0 moved until its tilt is <= tolerance - margin / 2 (Gauss-Newton
    aiming at tolerance - margin, damped, clipped to [lower, upper]; at most max_steps steps)."""
    dof = q0.shape[0]
    J = table.shape[0]
    R = np.empty((J + 1, 3, 3))
    p = np.empty((J + 1, 3))
    Rf = np.empty((3, 3))
    pf = np.empty(3)
    Jac = np.empty((6, dof))
    u = np.empty(3)
    g = np.empty(dof)
    q = q0.copy()
    for _ in range(max_steps + 1):
        _axis_up(q, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, axis, R, p, Rf, pf, Jac, u)
        c0 = u[1] * direction[2] - u[2] * direction[1]
        c1 = u[2] * direction[0] - u[0] * direction[2]
        c2 = u[0] * direction[1] - u[1] * direction[0]
        s = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
        r = math.atan2(s, u[0] * direction[0] + u[1] * direction[1] + u[2] * direction[2]) - tolerance
        if r <= -0.5 * margin:
            return q, True
        inv = 1.0 / max(s, 1e-12)  # theta = 0 or pi: a zero gradient
        gg = 0.0
        for j in range(dof):
            g[j] = -(c0 * inv * Jac[3, j] + c1 * inv * Jac[4, j] + c2 * inv * Jac[5, j]) / margin
            gg += g[j] * g[j]
        x = ((r + margin) / margin) / (gg + damping)
        for j in range(dof):
            q[j] = min(upper[j], max(lower[j], q[j] - g[j] * x))
    return q, False


@kernel
def hold_tilt(Q0, Q1, slack, weights, q_index, parent, table, f_joint, f_R, axis, direction, tolerance,
              first_split, max_depth):
    """(ok (M,), bad (M,), worst (M, dof), evaluations): which segments Q0[i] -> Q1[i] keep the
    tilt <= tolerance - slack[i] over their whole length (`constraints.certify._hold`); the
    bound of a piece of length h of a segment is h sum_k weights_k |Q1 - Q0|_k."""
    M, dof = Q0.shape
    J = table.shape[0]
    R = np.empty((J + 1, 3, 3))
    p = np.empty((J + 1, 3))
    ok = np.ones(M, dtype=np.bool_)
    bad = np.zeros(M, dtype=np.bool_)
    worst = Q0.copy()
    evaluations = 0
    x = np.empty(dof)
    # open pieces (depth first): ends t0, t1 along the segment, their violations, depth
    stack_t = np.empty((max_depth + 2) * 2 + first_split, dtype=np.float64)
    stack_u = np.empty_like(stack_t)
    stack_a = np.empty_like(stack_t)
    stack_b = np.empty_like(stack_t)
    stack_d = np.empty(stack_t.shape[0], dtype=np.int64)
    vin = np.empty(first_split + 1)
    for i in range(M):
        va = _tilt_at(Q0[i], q_index, parent, table, f_joint, f_R, axis, direction, R, p) - tolerance + slack[i]
        vb = _tilt_at(Q1[i], q_index, parent, table, f_joint, f_R, axis, direction, R, p) - tolerance + slack[i]
        evaluations += 2
        if va > 0.0 or vb > 0.0:
            ok[i], bad[i] = False, True
            if va <= 0.0:
                worst[i] = Q1[i]
            continue
        L = 0.0
        for j in range(dof):
            L += abs(Q1[i, j] - Q0[i, j]) * weights[j]
        if not 0.5 * (va + vb + L) > 0.0:
            continue
        pieces = int(min(first_split, max(2.0, math.ceil(2.0 * L / max(-(va + vb), 1e-9 * max(L, 1.0))))))
        h = L / pieces
        vin[0] = va
        vin[pieces] = vb
        for k in range(1, pieces):  # every inner cut first (as the batched proof does)
            t = k / pieces
            for j in range(dof):
                x[j] = Q0[i, j] + t * (Q1[i, j] - Q0[i, j])
            v = _tilt_at(x, q_index, parent, table, f_joint, f_R, axis, direction, R, p) - tolerance + slack[i]
            evaluations += 1
            vin[k] = v
            if v > 0.0 and ok[i]:
                ok[i], bad[i] = False, True
                worst[i] = x
        if not ok[i]:
            continue
        top = 0
        for k in range(pieces):
            if 0.5 * (vin[k] + vin[k + 1] + h) > 0.0:
                stack_t[top], stack_u[top], stack_a[top], stack_b[top], stack_d[top] = (
                    k / pieces, (k + 1) / pieces, vin[k], vin[k + 1], 0)
                top += 1
        while top > 0 and ok[i]:
            top -= 1
            t0, t1, a, b, depth = stack_t[top], stack_u[top], stack_a[top], stack_b[top], stack_d[top]
            if depth >= max_depth:
                ok[i] = False
                for j in range(dof):
                    d = Q1[i, j] - Q0[i, j]
                    worst[i, j] = 0.5 * ((Q0[i, j] + t0 * d) + (Q0[i, j] + t1 * d))
                break
            tm = 0.5 * (t0 + t1)
            for j in range(dof):
                d = Q1[i, j] - Q0[i, j]
                x[j] = 0.5 * ((Q0[i, j] + t0 * d) + (Q0[i, j] + t1 * d))
            vm = _tilt_at(x, q_index, parent, table, f_joint, f_R, axis, direction, R, p) - tolerance + slack[i]
            evaluations += 1
            if vm > 0.0:
                ok[i], bad[i] = False, True
                worst[i] = x
                break
            half = h * 0.5 ** (depth + 1)
            if 0.5 * (vm + b + half) > 0.0:
                stack_t[top], stack_u[top], stack_a[top], stack_b[top], stack_d[top] = tm, t1, vm, b, depth + 1
                top += 1
            if 0.5 * (a + vm + half) > 0.0:
                stack_t[top], stack_u[top], stack_a[top], stack_b[top], stack_d[top] = t0, tm, a, vm, depth + 1
                top += 1
    return ok, bad, worst, evaluations
