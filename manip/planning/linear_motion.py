"""Straight-line motions of a link (`plan_pose(..., linear=True)`): dense IK along the line, then timing.

The joint path comes from incremental IK at `linear_step` [m] along the line
(`planning.path.linear`); it is timed as one smooth motion along a spline through its points
(`time_parameterize_dense`), else by the other timings, and validated as every plan is
(`planning.time_and_validate`: limits, certified continuous collision-freedom).
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

from manip.errors import InvalidInputError
from manip.ik import IKSolver
from manip.kinematics import Kinematics
from manip.limits import JointLimits
from manip.planning.context import PlanContext
from manip.planning.path.linear import linear_path
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


def plan_linear(ctx: PlanContext, validity: Validity, start: np.ndarray, goal: Pose, link: str, *,
                kinematics: Kinematics, ik_solver: IKSolver, limits: JointLimits) -> PlanResult:
    """Straight-line motion of `link` from its pose at the checked `start` (dof,) to `goal`.

    Raises:
        InvalidInputError: the line needs more than MAX_LINEAR_POINTS IK points at `linear_step`.
    """
    length = float(np.linalg.norm(goal.position - kinematics.fk(start, link).position))
    points = length / ctx.options.linear_step
    if points > MAX_LINEAR_POINTS:
        raise InvalidInputError(
            f"linear_step: a {length:.4g} m line at linear_step = {ctx.options.linear_step:.3g} m needs "
            f"{math.ceil(points)} IK points; at most MAX_LINEAR_POINTS = {MAX_LINEAR_POINTS} "
            f"(give linear_step >= {length / MAX_LINEAR_POINTS:.3g} m)"
        )
    t = time.perf_counter()
    path, why = linear_path(
        kinematics, ik_solver, start, goal, link, step=ctx.options.linear_step,
        valid_batch=validity.configs, motion_valid=validity.motion,
    )
    ctx.add_time("ik", t)
    if path is None:
        return ctx.fail(PlanStatus.LINEAR_PATH_FAIL, why)
    goal_q = path[-1].copy()
    ctx.check_sample_count(start, goal_q, limits)
    traj, why = time_and_validate(ctx, path, goal_q, limits=limits, validity=validity,
                                  deviation=LINEAR_DEVIATION, dense_deviation=LINEAR_SPLINE_DEVIATION)
    if traj is None:
        return ctx.fail(PlanStatus.TRAJOPT_FAIL, f"no valid timed trajectory: {why}", path=path, goal_q=goal_q)
    dp, dr = kinematics.fk(goal_q, link).distance(goal)
    result = ctx.succeed(traj, path, goal_q, 1, "linear")
    return replace(result, position_error=float(dp), rotation_error=float(dr))
