"""Numerical kernels of the IK solver: the rotation logarithm, the damped least-squares step.

`_lm_lanes` is the compiled (numba) descent of `IKSolver.solve` and `IKSolver.solve_many`,
one damped-least-squares descent per start, on the same kinematics tables as
`Kinematics.joint_transforms`; `_log3_batch` and `_solve_spd` are the vectorised NumPy
pieces of the batch solver (`manip.ik.batch`).

The iteration (for one goal) is

    e  = [p_goal - p(q);  log(R_goal R(q)^T)]                 (6,), world-aligned
    dq = J^T (J J^T + lambda I)^-1 e,   lambda = damping * |e|^2 + 1e-9
    q  <- clip(q + dq, lower, upper)

with J the (6, 7) world-aligned frame Jacobian. The damping that grows with the squared
error is Sugihara's choice (T. Sugihara, "Solvability-unconcerned inverse kinematics by the
Levenberg-Marquardt method", IEEE T-RO 2011): long, careful steps far from the goal,
Gauss-Newton (quadratic) convergence close to it. Joints sitting at a limit whose step
points outwards are removed from J for that step (their columns zeroed), so the other
joints make up for them instead of the step being lost to the clip. The clip keeps every
iterate within the joint limits, so the answer never needs clamping afterwards. The step
is scaled so no joint moves more than `max_step`. An attempt stops when the error is below
the internal tolerance (1e-5 m / 1e-5 rad, much tighter than the success tolerances), when
it has not improved for a few iterations, or after `max_iterations`; the next attempt
starts from a uniformly random configuration within the limits.
"""

from __future__ import annotations

import math

import numpy as np

from manip import quaternion as quat
from manip.jit import kernel
from manip.kinematics import chain_frames, frame_jacobian_into

_INTERNAL_TOLERANCE = 1e-5  # [m] and [rad]: an attempt converges below this
_STALL_ITERATIONS = 5       # an attempt stops when its error has not improved for this many iterations
_MIN_DAMPING = 1e-9
_CHOLESKY_MIN_BATCH = 256  # batches at least this large use the vectorised Cholesky solve


def _log3_batch(E: np.ndarray) -> np.ndarray:
    """Rotation vectors (N, 3) of rotation matrices E (N, 3, 3), robust up to pi.

    theta = arccos((tr E - 1) / 2) and the axis from the skew part, E - E^T = 2 sin(theta) [axis]x;
    rotations near pi (where sin(theta) vanishes) go through the quaternion instead.
    """
    v = 0.5 * np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0], E[:, 1, 0] - E[:, 0, 1]], axis=1)
    cos = np.clip(0.5 * (E[:, 0, 0] + E[:, 1, 1] + E[:, 2, 2] - 1.0), -1.0, 1.0)
    theta = np.arccos(cos)
    sin = np.sqrt(np.maximum(1.0 - cos * cos, 0.0))
    # theta / sin(theta) -> 1 + theta^2 / 6 as theta -> 0
    factor = np.where(theta < 1e-4, 1.0 + theta * theta / 6.0, theta / np.maximum(sin, 1e-300))
    out = v * factor[:, None]
    near_pi = theta > np.pi - 1e-2
    if near_pi.any():
        qe = quat.from_matrix(E[near_pi])  # w >= 0
        s = np.linalg.norm(qe[:, 1:], axis=1)
        out[near_pi] = qe[:, 1:] * (2.0 * np.arctan2(s, qe[:, 0]) / s)[:, None]
    return out


@kernel
def _log3_into(E, out):
    """Rotation vector out (3,) of the rotation matrix E (3, 3), robust up to pi (see `_log3_batch`)."""
    cos = min(max(0.5 * (E[0, 0] + E[1, 1] + E[2, 2] - 1.0), -1.0), 1.0)
    theta = math.acos(cos)
    if theta > math.pi - 1e-2:  # through the quaternion (w >= 0)
        tr = E[0, 0] + E[1, 1] + E[2, 2]
        if tr > 0.0:
            s = math.sqrt(tr + 1.0) * 2.0
            w, x, y, z = 0.25 * s, (E[2, 1] - E[1, 2]) / s, (E[0, 2] - E[2, 0]) / s, (E[1, 0] - E[0, 1]) / s
        elif E[0, 0] > E[1, 1] and E[0, 0] > E[2, 2]:
            s = math.sqrt(1.0 + E[0, 0] - E[1, 1] - E[2, 2]) * 2.0
            w, x, y, z = (E[2, 1] - E[1, 2]) / s, 0.25 * s, (E[0, 1] + E[1, 0]) / s, (E[0, 2] + E[2, 0]) / s
        elif E[1, 1] > E[2, 2]:
            s = math.sqrt(1.0 + E[1, 1] - E[0, 0] - E[2, 2]) * 2.0
            w, x, y, z = (E[0, 2] - E[2, 0]) / s, (E[0, 1] + E[1, 0]) / s, 0.25 * s, (E[1, 2] + E[2, 1]) / s
        else:
            s = math.sqrt(1.0 + E[2, 2] - E[0, 0] - E[1, 1]) * 2.0
            w, x, y, z = (E[1, 0] - E[0, 1]) / s, (E[0, 2] + E[2, 0]) / s, (E[1, 2] + E[2, 1]) / s, 0.25 * s
        if w < 0.0:
            w, x, y, z = -w, -x, -y, -z
        sn = math.sqrt(x * x + y * y + z * z)
        f = 2.0 * math.atan2(sn, w) / sn
        out[0], out[1], out[2] = x * f, y * f, z * f
        return
    sin = math.sqrt(max(1.0 - cos * cos, 0.0))
    f = 0.5 * (1.0 + theta * theta / 6.0 if theta < 1e-4 else theta / sin)
    out[0] = f * (E[2, 1] - E[1, 2])
    out[1] = f * (E[0, 2] - E[2, 0])
    out[2] = f * (E[1, 0] - E[0, 1])


@kernel
def _dls_step(Jac, e, lam, dq):
    """dq = J^T (J J^T + lam I)^-1 e (damped least squares; Cholesky of the 6x6 matrix)."""
    m, n = Jac.shape
    A = np.empty((m, m))
    for r in range(m):
        for c in range(r + 1):
            acc = 0.0
            for k in range(n):
                acc += Jac[r, k] * Jac[c, k]
            A[r, c] = acc
        A[r, r] += lam
    L = np.zeros((m, m))
    for j in range(m):
        d = A[j, j]
        for k in range(j):
            d -= L[j, k] * L[j, k]
        L[j, j] = math.sqrt(d)
        for i in range(j + 1, m):
            acc = A[i, j]
            for k in range(j):
                acc -= L[i, k] * L[j, k]
            L[i, j] = acc / L[j, j]
    y = np.empty(m)
    for i in range(m):
        acc = e[i]
        for k in range(i):
            acc -= L[i, k] * y[k]
        y[i] = acc / L[i, i]
    for i in range(m - 1, -1, -1):
        acc = y[i]
        for k in range(i + 1, m):
            acc -= L[k, i] * y[k]
        y[i] = acc / L[i, i]
    for k in range(n):
        acc = 0.0
        for r in range(m):
            acc += Jac[r, k] * y[r]
        dq[k] = acc


@kernel
def _work_arrays(joints, dof):
    """Work arrays of `_pose_error_into` for a chain of `joints` joints: R, p, Rf, pf, E, w, Jac, e."""
    return (np.empty((joints + 1, 3, 3)), np.empty((joints + 1, 3)), np.empty((3, 3)), np.empty(3), np.empty((3, 3)),
            np.empty(3), np.empty((6, dof)), np.empty(6))


@kernel
def _pose_error_into(q, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, R_goal, p_goal, R, p, Rf, pf,
                     E, w, Jac, e):
    """Frame Jacobian Jac (6, dof) and pose error e (6,) = [p_goal - p(q); log(R_goal R(q)^T)] at q
    (world-aligned; R, p, Rf, pf, E, w are work arrays); returns (|e_p| [m], |e_r| [rad])."""
    chain_frames(q, q_index, parent, table, R, p)
    frame_jacobian_into(R, p, chain, axes, revolute, q_index, f_joint, f_R, f_p, Rf, pf, Jac)
    for r in range(3):
        e[r] = p_goal[r] - pf[r]
        for c in range(3):
            E[r, c] = R_goal[r, 0] * Rf[c, 0] + R_goal[r, 1] * Rf[c, 1] + R_goal[r, 2] * Rf[c, 2]
    _log3_into(E, w)
    e[3], e[4], e[5] = w[0], w[1], w[2]
    return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]), math.sqrt(e[3] * e[3] + e[4] * e[4] + e[5] * e[5])


@kernel
def _lm_lanes(Q0, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, R_goal, p_goal, lower, upper,
              tol_p, tol_r, damping, min_damping, max_step, max_iterations, stall):
    """One damped-least-squares descent from each row of Q0 (K, dof) to one frame pose.

    Stops at convergence (tol_p [m], tol_r [rad]), after `max_iterations`, or when the error
    has not improved by 2 % for `stall` iterations. Joints at a limit that the step would push
    further take no part in it; steps are scaled to at most `max_step` [rad] and kept within
    the limits. Returns (Q (K, dof), position errors (K,), rotation errors (K,), iterations (K,)).
    """
    K, dof = Q0.shape
    R, p, Rf, pf, E, w, Jac, e = _work_arrays(table.shape[0], dof)
    dq = np.empty(dof)
    Q = Q0.copy()
    ep_out = np.empty(K)
    er_out = np.empty(K)
    it_out = np.zeros(K, dtype=np.int64)
    for k in range(K):
        q = Q[k]
        best = np.inf
        best_it = 0
        it = 0
        while True:
            ep, er = _pose_error_into(q, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, R_goal,
                                      p_goal, R, p, Rf, pf, E, w, Jac, e)
            if (ep <= tol_p and er <= tol_r) or it >= max_iterations:
                break
            err2 = ep * ep + er * er
            if err2 < best * 0.98:
                best = err2
                best_it = it
            elif it - best_it >= stall:
                break
            lam = damping * err2 + min_damping
            _dls_step(Jac, e, lam, dq)
            blocked = False
            for i in range(dof):
                if (q[i] <= lower[i] and dq[i] < 0.0) or (q[i] >= upper[i] and dq[i] > 0.0):
                    blocked = True
                    for r in range(6):
                        Jac[r, i] = 0.0
            if blocked:  # joints held at a limit take no part in this step; the others compensate
                _dls_step(Jac, e, lam, dq)
            big = 0.0
            for i in range(dof):
                big = max(big, abs(dq[i]))
            scale = max_step / big if big > max_step else 1.0
            for i in range(dof):
                q[i] = min(max(q[i] + dq[i] * scale, lower[i]), upper[i])
            it += 1
        ep_out[k] = ep
        er_out[k] = er
        it_out[k] = it
    return Q, ep_out, er_out, it_out


def _solve_spd(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """x (N, m, 1) solving A x = b for symmetric positive definite A (N, m, m), b (N, m, 1).

    Large batches use a Cholesky factorisation vectorised over the batch (each scalar
    operation runs on N values at once: ~3x faster than LAPACK per 6x6 matrix at N = 1000);
    rows it cannot factor (a pivot <= 0 from rounding) and small batches go to np.linalg.solve.
    """
    n_batch, m = A.shape[0], A.shape[1]
    if n_batch < _CHOLESKY_MIN_BATCH:
        return np.linalg.solve(A, b)
    M = np.ascontiguousarray(np.moveaxis(A, 0, -1))  # (m, m, N)
    L = np.zeros_like(M)
    with np.errstate(invalid="ignore", divide="ignore"):
        for j in range(m):
            d = M[j, j] - np.einsum("kn,kn->n", L[j, :j], L[j, :j]) if j else M[j, j].copy()
            L[j, j] = np.sqrt(d)
            if j + 1 < m:
                s = M[j + 1 :, j] - (np.einsum("ikn,kn->in", L[j + 1 :, :j], L[j, :j]) if j else 0.0)
                L[j + 1 :, j] = s / L[j, j]
        bt = b[:, :, 0].T
        y = np.empty((m, n_batch))
        for i in range(m):
            y[i] = (bt[i] - (np.einsum("kn,kn->n", L[i, :i], y[:i]) if i else 0.0)) / L[i, i]
        x = np.empty_like(y)
        for i in reversed(range(m)):
            x[i] = (y[i] - (np.einsum("kn,kn->n", L[i + 1 :, i], x[i + 1 :]) if i + 1 < m else 0.0)) / L[i, i]
    x = x.T[:, :, None]
    bad = ~np.all(np.isfinite(x[:, :, 0]), axis=1)
    if bad.any():
        x[bad] = np.linalg.solve(A[bad], b[bad])
    return x


@kernel
def _slide_lanes(Q0, q_ref, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, R_goal, p_goal, lower,
                 upper, gain, lam, max_step, max_iterations, tol_step, tol_p, tol_r):
    """Each row of Q0 (K, dof) (a solution of one frame pose) moved along its self-motion towards q_ref.

    A predictor-corrector walk on the configurations that keep the frame on the goal: each
    step moves by the part of gain (q_ref - q) that leaves the frame in place to first order,
    (I - J+ J) gain (q_ref - q) with J+ = J^T (J J^T + lam I)^-1, at most `step` [rad] (joints at
    a limit that it would push further take no part), then up to 4 Newton corrections J+ e back
    onto the goal (within tol_p [m] and tol_r [rad]). A step that does not get back, or gets
    no nearer q_ref, is undone and `step` halves; one that does is kept and `step` doubles (at
    most `max_step`). Stops when `step` falls below `tol_step` [rad] (locally the configuration
    of the branch nearest q_ref) or after `max_iterations` steps. Rows of Q0 that are not
    within the tolerances of the goal are returned as they are.
    Returns (Q (K, dof), position errors (K,), rotation errors (K,)).
    """
    K, dof = Q0.shape
    R, p, Rf, pf, E, w, Jac, e = _work_arrays(table.shape[0], dof)
    Jv = np.empty(6)
    dq = np.empty(dof)
    v = np.empty(dof)
    Q = Q0.copy()
    ep_out = np.empty(K)
    er_out = np.empty(K)
    for k in range(K):
        q = Q[k]
        ep, er = _pose_error_into(q, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, R_goal, p_goal,
                                  R, p, Rf, pf, E, w, Jac, e)
        ep_out[k], er_out[k] = ep, er
        if ep > tol_p or er > tol_r:
            continue
        d_now = 0.0
        for i in range(dof):
            d_now += (q[i] - q_ref[i]) ** 2
        step = max_step
        q_try = np.empty(dof)
        for _ in range(max_iterations):
            if step < tol_step:
                break
            # predictor: the self-motion part of the way to q_ref (Jac and e are at q)
            for i in range(dof):
                v[i] = gain * (q_ref[i] - q[i])
            for attempt in range(2):
                for r in range(6):
                    acc = 0.0
                    for i in range(dof):
                        acc += Jac[r, i] * v[i]
                    Jv[r] = acc
                _dls_step(Jac, Jv, lam, dq)
                blocked = False
                for i in range(dof):
                    dq[i] = v[i] - dq[i]
                    if (q[i] <= lower[i] and dq[i] < 0.0) or (q[i] >= upper[i] and dq[i] > 0.0):
                        blocked = True
                        v[i] = 0.0
                        for r in range(6):
                            Jac[r, i] = 0.0
                if not blocked:
                    break
            big = 0.0
            for i in range(dof):
                big = max(big, abs(dq[i]))
            scale = step / big if big > step else 1.0
            for i in range(dof):
                q_try[i] = min(max(q[i] + scale * dq[i], lower[i]), upper[i])
            # corrector: Newton steps back onto the goal
            ok = False
            for c in range(5):
                ep, er = _pose_error_into(q_try, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p,
                                          R_goal, p_goal, R, p, Rf, pf, E, w, Jac, e)
                if ep <= tol_p and er <= tol_r:
                    ok = True
                    break
                if c == 4:
                    break
                _dls_step(Jac, e, lam, dq)
                for i in range(dof):
                    q_try[i] = min(max(q_try[i] + dq[i], lower[i]), upper[i])
            d_try = 0.0
            for i in range(dof):
                d_try += (q_try[i] - q_ref[i]) ** 2
            if ok and d_try < d_now:
                for i in range(dof):
                    q[i] = q_try[i]
                d_now = d_try
                ep_out[k], er_out[k] = ep, er
                step = min(2.0 * step, max_step)
            else:
                step *= 0.5
            # Jac and e at q for the next predictor
            _pose_error_into(q, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p, R_goal, p_goal, R, p,
                             Rf, pf, E, w, Jac, e)
    return Q, ep_out, er_out
