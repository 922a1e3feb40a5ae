"""The batch solver of `IKSolver.solve_batch`: damped least squares over "lanes" in NumPy.

Every goal of the batch is iterated at once (`Kinematics.frame_jacobians`), one lane per
attempt; once most goals are solved, the remaining ones get several lanes at once (parallel
random restarts), so a few hard goals cost a few small NumPy iterations instead of many
sequential attempts. The step is the one of `manip.ik.kernels._lm_lanes`, vectorised.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from manip.ik.kernels import _MIN_DAMPING, _STALL_ITERATIONS, _log3_batch, _solve_spd
from manip.ik.result import IKStatus, ValidityFn

_MIN_LANES = 256  # the batch solver adds parallel restarts for unsolved goals below this many lanes


def run_lanes(
    solver: Any,  # the IKSolver whose tables and settings the lanes use
    R_goal: np.ndarray,
    p_goal: np.ndarray,
    fid: int,
    q_start: np.ndarray,
    rng: np.random.Generator,
    validity_fn: ValidityFn | None,
    max_attempts: int,
    t0: float,
    time_limit: float | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[IKStatus]]:
    """Vectorised LM over "lanes": one attempt each, several lanes per goal when few remain.

    Every goal starts with one lane from its `q_start`. A lane that ends without a
    verified, valid solution restarts from a random configuration while its goal has
    attempts left; when fewer than `_MIN_LANES` lanes are running, the goals still
    unsolved (whose first attempt, from q_start, has failed) get extra lanes (parallel random
    restarts), so stragglers cost a few NumPy iterations rather than many sequential
    attempts. A goal is done at its first verified solution.
    """
    k = solver.kinematics
    n, dof = q_start.shape
    lo, hi = k.lower, k.upper
    q0 = np.clip(q_start, lo, hi).astype(float)
    success = np.zeros(n, dtype=bool)
    done = np.zeros(n, dtype=bool)
    rejected = np.zeros(n, dtype=bool)
    ep_out = np.full(n, np.inf)
    er_out = np.full(n, np.inf)
    best_cost = np.full(n, np.inf)
    q_out = q0.copy()
    iters = np.zeros(n, dtype=int)
    attempts = np.zeros(n, dtype=int)
    status: list[IKStatus] = [IKStatus.NOT_CONVERGED] * n
    first_over = np.zeros(n, dtype=bool)  # the goal's first attempt (from q_start) has ended

    far = solver.out_of_reach(fid, p_goal)
    for i in np.flatnonzero(far):
        status[i] = IKStatus.OUT_OF_REACH
    done |= far
    if far.any():
        Rf, pf = k.frame_transforms(q0[far], [fid])
        ep_out[far] = np.linalg.norm(p_goal[far] - pf[:, 0], axis=1)
        er_out[far] = np.linalg.norm(_log3_batch(R_goal[far] @ np.swapaxes(Rf[:, 0], 1, 2)), axis=1)

    # lane state
    goal = np.flatnonzero(~far)
    Q = q0[goal]
    Rg, pg = R_goal[goal], p_goal[goal]  # per-lane goals
    attempts[goal] = 1
    it_attempt = np.zeros(goal.size, dtype=int)
    best_err = np.full(goal.size, np.inf)
    best_it = np.zeros(goal.size, dtype=int)

    tol_p, tol_r = solver.internal_tolerances
    eye6 = np.eye(6)
    while goal.size:
        if time_limit is not None and time.perf_counter() - t0 > time_limit:
            for i in np.unique(goal):
                status[i] = IKStatus.TIME_LIMIT
            break
        R, p, J = k.frame_jacobians(Q, fid)
        e = np.empty((goal.size, 6))
        e[:, :3] = pg - p
        e[:, 3:] = _log3_batch(Rg @ np.swapaxes(R, 1, 2))
        ep = np.sqrt(np.einsum("ij,ij->i", e[:, :3], e[:, :3]))
        er = np.sqrt(np.einsum("ij,ij->i", e[:, 3:], e[:, 3:]))
        err2 = ep * ep + er * er

        improved = err2 < best_err * 0.98
        best_err[improved] = err2[improved]
        best_it[improved] = it_attempt[improved]
        ended = (
            ((ep <= tol_p) & (er <= tol_r))
            | (it_attempt - best_it >= _STALL_ITERATIONS)
            | (it_attempt >= solver.max_iterations)
        )
        restart = np.zeros(goal.size, dtype=bool)
        if ended.any():
            e_idx = np.flatnonzero(ended)
            good = e_idx[(ep[e_idx] <= solver.position_tolerance) & (er[e_idx] <= solver.rotation_tolerance)]
            if good.size:
                good = good[solver.verify_batch(Q[good], fid, Rg[good], pg[good])]
            if good.size and validity_fn is not None:
                ok = np.asarray(validity_fn(Q[good]), dtype=bool).reshape(-1)
                rejected[goal[good[~ok]]] = True
                good = good[ok]
            # first solution of each goal (several lanes of one goal may finish together)
            g, first = np.unique(goal[good], return_index=True)
            good_first = good[first]
            success[g] = True
            done[g] = True
            q_out[g] = Q[good_first]
            ep_out[g], er_out[g] = ep[good_first], er[good_first]
            for i in g:
                status[i] = IKStatus.SUCCESS
            failed = np.setdiff1d(e_idx, good, assume_unique=True)
            first_over[goal[failed]] = True
            cost = ep[failed] / solver.position_tolerance + er[failed] / solver.rotation_tolerance
            for lane, c in zip(failed, cost):  # few per iteration
                gi = goal[lane]
                if c < best_cost[gi] and not success[gi]:
                    best_cost[gi] = c
                    q_out[gi] = Q[lane]
                    ep_out[gi], er_out[gi] = ep[lane], er[lane]
                if attempts[gi] < max_attempts and not done[gi]:
                    attempts[gi] += 1
                    restart[lane] = True

        step = ~ended & ~done[goal]
        if step.any():
            s = slice(None) if step.all() else np.flatnonzero(step)
            Js = J[s]
            JsT = np.swapaxes(Js, 1, 2)
            lam = solver.damping * err2[s] + _MIN_DAMPING
            es = e[s][:, :, None]
            dq = (JsT @ _solve_spd(Js @ JsT + lam[:, None, None] * eye6, es))[:, :, 0]
            Qs = Q[s]
            blocked = ((Qs <= lo) & (dq < 0)) | ((Qs >= hi) & (dq > 0))
            b = np.flatnonzero(blocked.any(axis=1))
            if b.size:
                # joints held at a limit take no part in the step; the others compensate
                Jb = Js[b] * ~blocked[b][:, None, :]
                Ab = Jb @ np.swapaxes(Jb, 1, 2) + lam[b, None, None] * eye6
                dq[b] = (np.swapaxes(Jb, 1, 2) @ _solve_spd(Ab, es[b]))[:, :, 0]
            big = np.abs(dq).max(axis=1)
            scale = np.where(big > solver.max_step, solver.max_step / np.maximum(big, 1e-300), 1.0)
            Q[s] = np.clip(Qs + dq * scale[:, None], lo, hi)
            iters[goal[s]] += 1
            it_attempt[s] += 1
        restart &= ~done[goal]
        if restart.any():
            r = np.flatnonzero(restart)
            Q[r] = rng.uniform(lo, hi, (r.size, dof))
            it_attempt[r] = 0
            best_err[r] = np.inf
            best_it[r] = 0
        keep = step | restart
        if not keep.all():
            goal, Q, Rg, pg = goal[keep], Q[keep], Rg[keep], pg[keep]
            it_attempt, best_err, best_it = it_attempt[keep], best_err[keep], best_it[keep]

        # parallel restarts for the stragglers
        if goal.size < _MIN_LANES:
            # only goals whose first attempt (from q_start) failed: a solution from q_start stays the answer
            open_goals = np.flatnonzero(~done & first_over & (attempts < max_attempts))
            if open_goals.size:
                per_goal = max(1, (_MIN_LANES - goal.size) // open_goals.size)
                extra = np.minimum(per_goal, max_attempts - attempts[open_goals])
                new_goal = np.repeat(open_goals, extra)
                attempts[open_goals] += extra
                goal = np.concatenate([goal, new_goal])
                Rg = np.concatenate([Rg, R_goal[new_goal]])
                pg = np.concatenate([pg, p_goal[new_goal]])
                Q = np.concatenate([Q, rng.uniform(lo, hi, (new_goal.size, dof))])
                it_attempt = np.concatenate([it_attempt, np.zeros(new_goal.size, dtype=int)])
                best_err = np.concatenate([best_err, np.full(new_goal.size, np.inf)])
                best_it = np.concatenate([best_it, np.zeros(new_goal.size, dtype=int)])

    for i in np.flatnonzero(~done):
        if status[i] is IKStatus.NOT_CONVERGED and rejected[i]:
            status[i] = IKStatus.REJECTED_BY_VALIDITY
    return q_out, success, ep_out, er_out, iters, attempts, status
