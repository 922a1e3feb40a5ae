"""Straight-line (Cartesian) motions of a link: `plan_linear`.

The link moves along the straight line from its pose at the start to the goal pose (the
orientation interpolated), through dense IK points (`planning.path.linear.linear_path`) that
the validity accepts, timed as one smooth motion along them and certified like every plan
(`planning.time_and_validate`). `MotionGenerator.plan_pose(..., linear=True)`,
`plan_poses(..., linear=True)` (several links, each on its own line, together) and the grasp
stages (`planning.grasp`) call it, each with its own validity (a world snapshot, the plan's
constraints, allowed contacts).
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

from manip.errors import InvalidInputError
from manip.ik import IKSolver
from manip.limits import JointLimits
from manip.planning.context import PlanContext
from manip.planning.path.linear import linear_paths
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.time_and_validate import time_and_validate
from manip.planning.validity import Validity
from manip.pose import Pose

#: Largest joint-space deviation [rad] of a linear motion's timing from its dense IK path
#: (about 1 mm at the hand).
LINEAR_DEVIATION = 1e-3
#: Linear motions are first timed as one smooth motion along a spline through their IK
#: points (`time_parameterize_dense`). The spline passes through every point; between
#: points it may stray this far [rad] from the joint-space polyline, which is itself only a
#: chord approximation of the IK curve (measured at 2 cm steps: the spline stays within
#: 0.01 mm of the Cartesian line, the polyline 0.1-0.2 mm off it, while the two differ by
#: up to 1.8 mrad). The bound only rejects a fit gone wrong.
LINEAR_SPLINE_DEVIATION = 1e-2
#: Largest number of IK points of a linear motion (`linear_step` [m] must be at least the
#: line's length over this): more is refused with an InvalidInputError naming linear_step.
MAX_LINEAR_POINTS = 10_000


def plan_linear(ctx: PlanContext, validity: Validity, ik_solver: IKSolver, start_q: np.ndarray, goal: Pose,
                link: str, *, limits: JointLimits) -> PlanResult:
    """Straight-line motion of `link` from its pose at `start_q` (dof,) to `goal` (a single Pose).

    Returns:
        PlanResult: LINEAR_PATH_FAIL when the line cannot be followed (IK breaks, jumps or
        the validity refuses a point or a step), TRAJOPT_FAIL when no timing of it validates.

    Raises:
        InvalidInputError: `linear_step` too small for the line's length (MAX_LINEAR_POINTS).
    """
    return plan_linear_links(ctx, validity, start_q, [(link, goal, ik_solver, None)], limits=limits)


def plan_linear_links(ctx: PlanContext, validity: Validity, start_q: np.ndarray, targets: list, *,
                      limits: JointLimits, carrier: tuple[Pose, Pose] | None = None) -> PlanResult:
    """Straight-line motions of several links at once (`planning.path.linear.linear_paths`):
    each link on its own line, all at the same fraction of their lines, arriving together.

    Args:
        targets: per link (link, goal Pose, its IK solver, free (dof,) bool or None), as
            `linear_paths`.
        carrier: the links moved rigidly with this frame (its start and goal poses), as
            `linear_paths`.

    Returns / Raises: as `plan_linear`; `position_error` / `rotation_error` are the largest
    over the links.
    """
    kinematics = validity.kinematics
    start = ctx.check_start(start_q, kinematics, validity)
    if ctx.failed:
        return ctx.result()
    for link, goal, _, _ in targets:
        length = float(np.linalg.norm(goal.position - kinematics.fk(start, link).position))
        points = length / ctx.options.linear_step
        if points > MAX_LINEAR_POINTS:
            raise InvalidInputError(
                f"linear_step: a {length:.4g} m line at linear_step = {ctx.options.linear_step:.3g} m needs "
                f"{math.ceil(points)} IK points; at most MAX_LINEAR_POINTS = {MAX_LINEAR_POINTS} "
                f"(give linear_step >= {length / MAX_LINEAR_POINTS:.3g} m)"
            )
    t = time.perf_counter()
    path, why = linear_paths(
        kinematics, targets, start, step=ctx.options.linear_step,
        valid_batch=validity.configs, motion_valid=validity.motion, carrier=carrier,
        describe=lambda q: validity.goal_problem(q).removeprefix("goal ") or "refused",
    )
    if path is None and validity.constraints:
        why = _left_constraint(ctx, validity, targets, start, carrier) or why
    ctx.add_time("ik", t)
    if path is None:
        return ctx.fail(PlanStatus.LINEAR_PATH_FAIL, why)
    goal_q = path[-1].copy()
    ctx.check_sample_count(start, goal_q, limits)
    traj, why = time_and_validate(ctx, path, goal_q, limits=limits, validity=validity,
                                  deviation=LINEAR_DEVIATION, dense_deviation=LINEAR_SPLINE_DEVIATION)
    if traj is None:
        return ctx.fail(PlanStatus.TRAJOPT_FAIL, f"no valid timed trajectory: {why}", path=path, goal_q=goal_q)
    errors = np.array([kinematics.fk(goal_q, link).distance(goal) for link, goal, _, _ in targets])
    result = ctx.succeed(traj, path, goal_q, 1, "linear")
    return replace(result, position_error=float(errors[:, 0].max()), rotation_error=float(errors[:, 1].max()))


def _left_constraint(ctx: PlanContext, validity: Validity, targets: list, start: np.ndarray,
                     carrier: tuple[Pose, Pose] | None) -> str:
    """Why a line refused by a constrained validity failed, when the line is free of
    collisions (the same line on the unconstrained validity): where it first leaves a
    constraint and by how much; "" otherwise (it collides, or leaves one only between points)."""
    free = validity.unconstrained()
    path, _ = linear_paths(validity.kinematics, targets, start, step=ctx.options.linear_step,
                           valid_batch=free.configs, motion_valid=free.motion, carrier=carrier)
    if path is None:
        return ""
    for i, q in enumerate(path):
        problem = validity.constraint_problem(q)
        if problem:
            return f"the straight line leaves a constraint at {100 * i / (len(path) - 1):.0f}% of the line: {problem}"
    return ""
