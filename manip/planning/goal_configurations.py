"""Pose goals to goal configurations: collision-free IK solutions, or why there is none.

`goal_configurations` turns the poses of `plan_pose` / `plan_goalset` into joint goals for
the planner: several collision-free IK solutions per pose (moved along the arm's self-motion
towards the start, and turned by whole turns of +-2 pi joints to the values nearest the start),
a many-start search for tight goals, and, when no pose has one, the most
telling reason found (out of reach; in collision, and with what; not converged).
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from manip.collision.clearance import ClearanceModel
from manip.ik import BatchIKResult, IKResult, IKSolver, IKStatus
from manip.kinematics import Kinematics
from manip.limits import JointLimits
from manip.planning.context import PlanContext
from manip.planning.path.goals import order_goals
from manip.planning.pipeline import plan_to_configs
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.validity import Validity
from manip.pose import Pose

#: Random IK starts tried for a pose goal when the first round finds no collision-free solution.
IK_RETRY_ATTEMPTS = 400
#: IK_FAIL messages report the first of these reasons found among the poses of a goal set
#: (a pose out of reach says more than one whose solutions collide, which says more than one
#: where IK did not converge).
IK_FAILURE_ORDER = (IKStatus.OUT_OF_REACH, IKStatus.REJECTED_BY_VALIDITY, IKStatus.NOT_CONVERGED)
#: Pose goals of redundant arms: each IK solution is also offered moved along its self-motion
#: towards the start (`IKSolver.solve_many(toward_seed=True)`): nearer goals, shorter motions.
IK_TOWARD_START = True


def goal_configurations(ik_solver: IKSolver, ctx: PlanContext, validity: Validity, start: np.ndarray, goals: Pose,
                        link: str) -> tuple[np.ndarray, list[int], str]:
    """Collision-free IK solutions of the poses `goals` for `link`.

    Args:
        ik_solver: the robot's IK solver.
        ctx: the plan's context (options: `ik_solutions`, and `seed`, which seeds the IK restarts; its
            generator seeds the retries).
        validity: the plan's validity checks (the world snapshot).
        start: (dof,) the start configuration [rad] (the IK seed).
        goals: a Pose or a batched Pose (a goal set).
        link: the frame that must reach the poses.

    Returns:
        (M, dof) configurations [rad], the pose index of each (M,), and, when M == 0, why
        (an IK_FAIL message; "" otherwise).
    """
    configs, owners, reasons = [], [], []
    for i, g in enumerate(goals):
        sols = ik_solver.solve_many(g, link, n=ctx.options.ik_solutions, seed_q=start, validity_fn=validity.configs,
                                    toward_seed=IK_TOWARD_START, seed=ctx.options.seed)
        if len(sols) == 0:
            # tight goals (a hand between obstacles, a joint on its limit) have few
            # collision-free solutions: search many more random starts for one
            sols = ik_solver.solve_many(g, link, n=2, seed_q=start, validity_fn=validity.configs,
                                        attempts=IK_RETRY_ATTEMPTS, seed=int(ctx.rng.integers(2**31)))
        for q in sols:
            near = nearest_turn(q, start, ik_solver.kinematics)
            if np.any(near != q):  # the same placements a whole turn of some joint nearer the start
                configs.append(near)
                owners.append(i)
            configs.append(q)
            owners.append(i)
        if len(sols) == 0:
            reasons.append(_ik_failure(ik_solver, sols, g, link, start, validity, ctx.options.seed))
    why = ""
    if not configs:
        # one reason per pose; the first of the most telling kind (see IK_FAILURE_ORDER)
        rank = {s: k for k, s in enumerate(IK_FAILURE_ORDER)}
        status, detail = min(reasons, key=lambda r: rank.get(r[0], len(rank)))
        which = "" if len(goals) == 1 else f" for any of the {len(goals)} poses"
        why = f"no collision-free IK solution within the joint limits{which}: {status.name}: {detail}"
    return np.asarray(configs).reshape(-1, ik_solver.kinematics.dof), owners, why


def nearest_turn(q: np.ndarray, start: np.ndarray, kinematics: Kinematics) -> np.ndarray:
    """`q` (dof,) with each revolute joint moved by whole turns (2 pi) to the value nearest `start`
    (dof,) within the joint limits [rad]: the same link placements (the same pose, the same
    contacts) with the shortest turn of each joint (a prismatic joint's 2 pi would be a
    displacement: never moved). IK solutions of joints that turn +-2 pi (UR, Kinova, xArm) may
    lie up to a turn further than needed: a longer motion, and in clutter a harder one."""
    turns = np.arange(-_MAX_TURNS, _MAX_TURNS + 1) * (2.0 * np.pi)
    cand = q[:, None] + turns[None, :]  # (dof, turns)
    ok = (cand >= kinematics.lower[:, None]) & (cand <= kinematics.upper[:, None])
    ok &= _revolute_dofs(kinematics)[:, None]
    ok[:, _MAX_TURNS] = True  # q itself (inside its limits as an IK solution)
    cost = np.where(ok, np.abs(cand - start[:, None]), np.inf)
    return cand[np.arange(len(q)), np.argmin(cost, axis=1)]


def note_whole_turns(result: PlanResult, start: np.ndarray, goal: np.ndarray, kinematics: Kinematics,
                     names: list[str]) -> PlanResult:
    """`result` of a joint goal (dof,); when no path was found (PLAN_FAIL, TIMEOUT), its message
    also names the joints the goal turns more than pi from `start` (dof,) where whole turns less
    give the same placements within the limits (a joint goal is reached as given: such a goal
    asks the arm to wind round, which clutter may forbid). Other results unchanged."""
    if result.status not in (PlanStatus.PLAN_FAIL, PlanStatus.TIMEOUT):
        return result
    near = nearest_turn(goal, start, kinematics)
    moved = np.flatnonzero(near != goal)
    if not len(moved):
        return result
    turns = ", ".join(f"{names[j]} by {goal[j] - start[j]:+.2f} rad" for j in moved)
    alt = ", ".join(f"{names[j]} at {near[j]:.3f} rad" for j in moved)
    return replace(result, message=f"{result.message}; the goal turns {turns} from the start, which a joint goal "
                                   f"asks as given; the same placements with {alt} (whole turns less) are a shorter "
                                   f"motion: pass that goal if the turn is not needed")


def _revolute_dofs(kinematics: Kinematics) -> np.ndarray:
    """(dof,) bool: the entries of q that only revolute joints read."""
    q_index, _, _ = kinematics.fk_tables()
    out = np.ones(kinematics.dof, dtype=bool)
    np.logical_and.at(out, np.asarray(q_index), np.asarray(kinematics.joint_revolute, dtype=bool))
    return out


#: Whole turns `nearest_turn` considers each way (limits span at most 4 pi on the bundled arms).
_MAX_TURNS = 2


def _ik_failure(ik_solver: IKSolver, sols, goal: Pose, link: str, start: np.ndarray,
                validity: Validity, seed: int) -> tuple[IKStatus, str]:
    """(IKStatus, detail) of a pose without collision-free IK solutions. When solutions exist
    but all collide, one of them (the nearest the start) says with what."""
    if sols.status is not IKStatus.REJECTED_BY_VALIDITY:
        return sols.status, sols.message
    problem = nearest_solution_problem(ik_solver, goal, link, start, validity, seed)
    if problem is None:
        return sols.status, "every IK solution found is in collision"
    return sols.status, f"every IK solution found is in collision; the one nearest the start: {problem}"


def nearest_solution_problem(ik_solver: IKSolver, goal: Pose, link: str, seed_q: np.ndarray | None,
                             validity: Validity, seed: int | None) -> str | None:
    """What `validity` finds wrong with the IK solution of `goal` nearest `seed_q` (dof,) found
    without it (`Validity.goal_problem`, e.g. "goal in collision: panda_hand touches table
    (3.1 mm deep, ...)"); None when IK finds no solution at all."""
    found = ik_solver.solve_many(goal, link, n=1, seed_q=seed_q, seed=seed)
    if len(found) == 0:
        return None
    return validity.goal_problem(found[0]) or "in collision"


def explain_rejected_ik(result: IKResult, ik_solver: IKSolver, goal: Pose, link: str, seed_q: np.ndarray | None,
                        validity: Validity, seed: int | None) -> IKResult:
    """`result` of a collision-free IK query (`MotionGenerator.ik(collision_free=True)`), its
    message naming what the solution nearest `seed_q` touches when every solution was rejected
    (as `plan_pose`'s IK_FAIL messages do); any other result unchanged."""
    if result.status is not IKStatus.REJECTED_BY_VALIDITY:
        return result
    problem = nearest_solution_problem(ik_solver, goal, link, seed_q, validity, seed)
    if problem is None:
        return result
    return replace(result, message=f"every solution found in {result.attempts} attempt(s) is in collision "
                                   f"(collision_free=True); the one nearest seed_q: {problem}")


def explain_rejected_batch_ik(result: BatchIKResult, validity: Validity) -> BatchIKResult:
    """`result` of a collision-free batched IK query (`MotionGenerator.batch_ik(collision_free=True)`),
    the message of each goal whose every solution was rejected naming what the best one found
    (its `q` row) touches, as `explain_rejected_ik` does for one goal; other rows unchanged."""
    rows = [i for i, s in enumerate(result.status) if s is IKStatus.REJECTED_BY_VALIDITY]
    if not rows:
        return result
    message = list(result.message) if result.message else [""] * len(result)
    for i in rows:
        problem = validity.goal_problem(np.asarray(result.q[i]))
        if problem:  # the best row may be a lane that did not converge: then the message stays
            message[i] = (f"every solution found in {int(result.attempts[i])} attempt(s) is in collision "
                          f"(collision_free=True); the best one found: {problem}")
    return replace(result, message=tuple(message))


def plan_to_poses(ctx: PlanContext, validity: Validity, start: np.ndarray, goals: Pose, link: str, *,
                  kinematics: Kinematics, ik_solver: IKSolver, limits: JointLimits,
                  clearance: ClearanceModel) -> PlanResult:
    """A plan from the checked `start` (dof,) to whichever pose of `goals` (batched) is best reached
    by `link` (`MotionGenerator.plan_goalset`): collision-free IK solutions of every pose, ranked
    by the motion they allow (`planning.path.goals`), planned to at once; the result's
    `goal_index` says which pose was reached, `position_error` [m] / `rotation_error` [rad] how well.
    """
    t_ik = time.perf_counter()
    configs, owners, why = goal_configurations(ik_solver, ctx, validity, start, goals, link)
    ctx.add_time("ik", t_ik)
    if not len(configs):
        return ctx.fail(*constrained_goal_failure(ik_solver, ctx, validity, start, goals, link, why))
    order = order_goals(start, configs, ctx.scaled_limits(limits))
    ctx.check_sample_count(start, configs[order[0]], limits)
    result = plan_to_configs(ctx, validity, start, configs[order], limits=limits, clearance=clearance)
    if result.success:
        reached = result.goal_q
        k = int(order[np.argmin(np.linalg.norm(configs[order] - reached, axis=1))])
        dp, dr = kinematics.fk(reached, link).distance(goals[owners[k]])
        result = replace(result, position_error=float(dp), rotation_error=float(dr), goal_index=owners[k])
    return result


def constrained_goal_failure(ik_solver: IKSolver, ctx: PlanContext, validity: Validity, start: np.ndarray,
                             goals: Pose, link: str, why: str) -> tuple[PlanStatus, str]:
    """(status, message) of goal poses without a valid IK solution: INVALID_GOAL_CONSTRAINT
    when collision-free solutions exist but each violates a constraint of `validity` (the
    message describes the one nearest the start), else IK_FAIL with `why`."""
    if not validity.constraints:
        return PlanStatus.IK_FAIL, why
    free = validity.unconstrained()
    configs, _, _ = goal_configurations(ik_solver, ctx, free, start, goals, link)
    if not len(configs):
        return PlanStatus.IK_FAIL, why
    nearest = configs[np.argmin(np.linalg.norm(configs - start, axis=1))]
    which = "the goal pose" if len(goals) == 1 else f"the {len(goals)} goal poses"
    return PlanStatus.INVALID_GOAL_CONSTRAINT, (
        f"every collision-free IK solution of {which} violates a constraint; the one nearest the start: "
        f"{validity.constraint_problem(nearest)}")
