"""Planning for robots of several arms (`manip.robot_arms`): one arm's goals, or several links at once.

A multi-arm robot plans in its combined configuration (each arm's joints in turn). Two kinds
of pose goals:

- one link's pose (`plan_pose(..., link="left_panda_hand")`, `ik(..., link=...)`): only the
  arm that carries the link moves; the other arms' joints are held where the start (the IK
  seed) has them, by pinning their position limits (`Kinematics.pinned`), so every stage of
  the plan (IK restarts, the path search's samples, shortcuts, the optimiser's bounds) keeps
  them there: the returned trajectory has them constant;
- several links' poses (`plan_poses(start_q, {"left_panda_hand": ..., "right_panda_hand": ...})`):
  each link's arm gets its IK solutions (the other arms held at the start, so a solution is
  free of the world and of its own arm; when that finds none, collisions with the other arms
  are ignored at this stage), the combinations are checked as whole configurations (arm
  against arm included) and ranked by the time-optimal motion to each, and one trajectory
  moves every arm at once: all links arrive together. Arms without a goal are held. With
  `linear=True` each link instead follows the straight line to its goal, all links at the
  same fraction of their lines at every point (`plan_link_lines`).

The combined configuration is planned and certified as one robot's: every pair of parts of
two arms is checked on the exact meshes, as a link pair of one arm is.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from manip.collision.clearance import ClearanceModel
from manip.constraints.relative import RelativePoseConstraint
from manip.errors import InvalidInputError, UnknownNameError
from manip.ik import IKSolver
from manip.ik.result import BatchIKResult
from manip.kinematics import Kinematics
from manip.planning.constrained import with_constraints
from manip.planning.context import PlanContext
from manip.planning.goal_configurations import IK_TOWARD_START, nearest_turn
from manip.planning.linear_motion import plan_linear_links
from manip.planning.path.goals import order_goals
from manip.planning.pipeline import plan_to_configs
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.validity import Validity
from manip.pose import Pose
from manip.robot_arms import Arm
from manip.robot_config import RobotConfig

#: Goal configurations of `plan_poses` handed to the planner at most (the best ranked of every
#: combination of the links' IK solutions).
MAX_COMBINED_GOALS = 48


def arm_of(config: RobotConfig, link: str) -> Arm | None:
    """The arm that carries `link` (by its name's prefix), or None (a one-arm robot, or a link of
    the combined base)."""
    for arm in config.arms:
        if arm.owns(link):
            return arm
    return None


def free_joints(config: RobotConfig, links: list[str]) -> np.ndarray:
    """(dof,) bool: the joints of the arms that carry `links` (all joints on a one-arm robot)."""
    if not config.arms:
        return np.ones(config.dof, dtype=bool)
    free = np.zeros(config.dof, dtype=bool)
    for link in links:
        arm = arm_of(config, link)
        if arm is not None:
            free[arm.columns[0]:arm.columns[1]] = True
    return free


def solver_like(solver: IKSolver, kinematics: Kinematics) -> IKSolver:
    """An IK solver with `solver`'s settings on `kinematics` (a pinned view: `Kinematics.pinned`)."""
    return IKSolver(kinematics, position_tolerance=solver.position_tolerance,
                    rotation_tolerance=solver.rotation_tolerance, max_iterations=solver.max_iterations,
                    max_attempts=solver.max_attempts, seed=solver.seed, damping=solver.damping,
                    max_step=solver.max_step)


def held_view(config: RobotConfig, kinematics: Kinematics, solver: IKSolver, links: list[str],
              q: np.ndarray) -> tuple[Kinematics, IKSolver]:
    """(kinematics, IK solver) that move only the arms of `links`, the other joints held at `q`
    (dof,); the given ones on a one-arm robot (nothing to hold)."""
    free = free_joints(config, links)
    if free.all():
        return kinematics, solver
    pinned = kinematics.pinned(q, free)
    return pinned, solver_like(solver, pinned)


def held_batch_ik(config: RobotConfig, kinematics: Kinematics, solver: IKSolver, goals: Pose, link: str,
                  seed_q: np.ndarray | None, default_q: np.ndarray, **kwargs) -> BatchIKResult:
    """`IKSolver.solve_batch` of `goals` (N poses) moving only `link`'s arm: the other arms held
    at each row's own `seed_q` (N, dof) values (at `seed_q` (dof,), or `default_q`, for every row).

    Rows that hold the other arms at the same values are solved in one batch.
    """
    seeds = default_q if seed_q is None else np.asarray(seed_q, dtype=float)
    free = free_joints(config, [link])
    if free.all() or seeds.ndim == 1 or len(seeds) != len(goals):  # one held configuration (or the solver's error)
        return held_view(config, kinematics, solver, [link], np.atleast_2d(seeds)[0])[1].solve_batch(
            goals, link, seed_q=seed_q, **kwargs)
    keys, group = np.unique(seeds[:, ~free], axis=0, return_inverse=True)
    group = group.reshape(-1)
    parts = []
    for k in range(len(keys)):
        rows = np.flatnonzero(group == k)
        arm_solver = held_view(config, kinematics, solver, [link], seeds[rows[0]])[1]
        parts.append((rows, arm_solver.solve_batch(goals[rows], link, seed_q=seeds[rows], **kwargs)))
    if len(parts) == 1:
        return parts[0][1]
    n = len(seeds)
    out = {name: np.empty((n,) + np.shape(getattr(parts[0][1], name))[1:], dtype=getattr(parts[0][1], name).dtype)
           for name in ("success", "q", "position_error", "rotation_error", "iterations", "attempts")}
    status, message = [None] * n, [""] * n
    for rows, res in parts:
        for name, arr in out.items():
            arr[rows] = getattr(res, name)
        for i, r in enumerate(rows):
            status[r] = res.status[i]
            message[r] = res.message[i] if res.message else ""
    return BatchIKResult(**out, status=tuple(status), solve_time=sum(res.solve_time for _, res in parts),
                         message=tuple(message))


def held_validity(validity: Validity, kinematics: Kinematics) -> Validity:
    """`validity`'s checks (world snapshot, resolutions, constraints) on a pinned `kinematics`."""
    base = Validity(validity.checker, kinematics, validity.resolution, validity.search_resolution, validity.certified)
    return with_constraints(base, validity.constraints)


def shared_attachment(parts, kinematics: Kinematics, links, allowed=()) -> tuple[str, tuple[str, ...]]:
    """(carrying link, allowed links) of an object held by two links (`attach_object(link=(a, b))`):
    it moves with `a`; the links rigidly carried with `b` (its hand and fingers: the parts on
    b's joint, `RobotGeometry.parts`) and `allowed` are never checked against it.

    Raises:
        InvalidInputError: not two distinct link names. UnknownNameError: an unknown link.
    """
    if len(links) != 2 or not all(isinstance(n, str) for n in links) or links[0] == links[1]:
        raise InvalidInputError(f"link must be one link name or two distinct ones (a, b); got {links!r}")
    joint = kinematics.model.frames[kinematics.frame_id(links[1], "link")].parentJoint
    held = [p.link for p in parts if p.joint == joint]
    return links[0], tuple(dict.fromkeys([*allowed, *held]))


def check_goals(config: RobotConfig, kinematics: Kinematics, goals: object) -> dict[str, Pose]:
    """`plan_poses`' goals checked: a non-empty dict link -> single Pose, one link per arm.

    Raises:
        InvalidInputError: not a dict, empty, a value not a single Pose, two links of one arm.
        UnknownNameError: a link the robot does not have (the frames are listed).
    """
    if not isinstance(goals, Mapping) or not goals:
        raise InvalidInputError(f"goals must be a non-empty dict link name -> manip.Pose; got {goals!r}")
    out: dict[str, Pose] = {}
    arms: dict[str, str] = {}
    for link, pose in goals.items():
        kinematics.frame_id(link, "goals: link")
        if not isinstance(pose, Pose) or pose.is_batch:
            raise InvalidInputError(f"goals[{link!r}] must be a single manip.Pose; got {type(pose).__name__}")
        arm = arm_of(config, link)
        key = arm.name if arm is not None else ""
        if key in arms:
            raise InvalidInputError(f"goals: '{arms[key]}' and '{link}' are both moved by "
                                    f"{'arm ' + repr(key) if key else 'the same joints'}; give one link per arm"
                                    + (f" (arms: {', '.join(a.name for a in config.arms)})" if config.arms else ""))
        if arm is None and config.arms:
            raise UnknownNameError("goals: link of an arm", link, [a.ee_link for a in config.arms])
        arms[key] = link
        out[link] = pose
    return out


def _link_solutions(ctx: PlanContext, validity: Validity, kinematics: Kinematics, solver: IKSolver,
                    config: RobotConfig, start: np.ndarray, link: str, goal: Pose) -> np.ndarray:
    """(K, dof) IK solutions of one link's goal, its arm alone moving (see the module docstring)."""
    kin, arm_solver = held_view(config, kinematics, solver, [link], start)
    sols = arm_solver.solve_many(goal, link, n=ctx.options.ik_solutions, seed_q=start, validity_fn=validity.configs,
                                 toward_seed=IK_TOWARD_START, seed=ctx.options.seed)
    if len(sols) == 0:  # perhaps blocked by another arm where it starts, which also moves
        sols = arm_solver.solve_many(goal, link, n=ctx.options.ik_solutions, seed_q=start,
                                     toward_seed=IK_TOWARD_START, seed=int(ctx.rng.integers(2**31)))
    Q = np.asarray(sols.q, dtype=float).reshape(-1, kin.dof)
    # the same placements turned nearest the start (`goal_configurations.nearest_turn`), first
    near = np.array([nearest_turn(q, start, kin) for q in Q]).reshape(-1, kin.dof)
    moved = np.any(near != Q, axis=1)
    return np.concatenate([near[moved], Q])


def plan_link_poses(ctx: PlanContext, validity: Validity, start: np.ndarray, goals: dict[str, Pose], *,
                    config: RobotConfig, kinematics: Kinematics, solver: IKSolver, limits,
                    clearance: ClearanceModel) -> PlanResult:
    """One motion bringing every link of `goals` to its pose at once (see the module docstring).

    Args:
        ctx: the plan's context; validity: its world snapshot; start: (dof,) checked start [rad].
        goals: link -> Pose in the base frame (`check_goals`).
        config, kinematics, solver, limits, clearance: the robot's.

    Returns:
        The PlanResult; IK_FAIL names the link without a solution, or says that no combination
        of the links' solutions is collision-free. `position_error` / `rotation_error` are the
        largest over the links.
    """
    carried = _rigid_carry(ctx, validity, start, goals, config=config, kinematics=kinematics, solver=solver)
    if carried is not None:
        return carried
    t_ik = time.perf_counter()
    per_link = []
    for link, goal in goals.items():
        sols = _link_solutions(ctx, validity, kinematics, solver, config, start, link, goal)
        if len(sols) == 0:
            ctx.add_time("ik", t_ik)
            return ctx.fail(PlanStatus.IK_FAIL, f"no IK solution within the joint limits for '{link}' at {goal}")
        per_link.append((free_joints(config, [link]), sols))
    combos = []
    for choice in itertools.product(*(range(len(s)) for _, s in per_link)):
        q = start.copy()
        for (free, sols), k in zip(per_link, choice):
            q[free] = sols[k][free]
        combos.append(q)
    configs = np.asarray(combos)
    configs = configs[validity.configs(configs)]
    ctx.add_time("ik", t_ik)
    if not len(configs):
        return ctx.fail(PlanStatus.IK_FAIL, f"no collision-free combination of the IK solutions of {list(goals)} "
                                            f"({len(combos)} tried: the arms collide with each other or the world)")
    order = order_goals(start, configs, ctx.scaled_limits(limits))[:MAX_COMBINED_GOALS]
    held = free_joints(config, list(goals))
    if not held.all():  # arms without a goal stay where they are
        kin = kinematics.pinned(start, held)
        validity = held_validity(validity, kin)
        limits = kin.limits
    ctx.check_sample_count(start, configs[order[0]], limits)
    result = plan_to_configs(ctx, validity, start, configs[order], limits=limits, clearance=clearance)
    if result.success:
        errors = np.array([kinematics.fk(result.goal_q, link).distance(goal) for link, goal in goals.items()])
        result = replace(result, position_error=float(errors[:, 0].max()), rotation_error=float(errors[:, 1].max()),
                         goal_index=0)
    return result


def plan_link_lines(ctx: PlanContext, validity: Validity, start: np.ndarray, goals: dict[str, Pose], *,
                    config: RobotConfig, kinematics: Kinematics, solver: IKSolver) -> PlanResult:
    """`plan_poses(..., linear=True)`: every link of `goals` moves on the straight line from its
    pose at `start` to its goal, all at the same fraction of their lines at each point (they
    arrive together), each line followed by IK of its own arm (`planning.linear_motion`);
    arms without a goal are held. The result is timed and certified as every linear motion.
    """
    kin = kinematics
    moving = free_joints(config, list(goals))
    if not moving.all():
        kin = kinematics.pinned(start, moving)
        validity = held_validity(validity, kin)
    targets = []
    for link, goal in goals.items():
        arm_solver = held_view(config, kinematics, solver, [link], start)[1]
        targets.append((link, goal, arm_solver, free_joints(config, [link]) if config.arms else None))
    return plan_linear_links(ctx, validity, start, targets, limits=kin.limits)


def _rigid_carry(ctx: PlanContext, validity: Validity, start: np.ndarray, goals: dict[str, Pose], *,
                 config: RobotConfig, kinematics: Kinematics, solver: IKSolver) -> PlanResult | None:
    """The first try of a carry: when the plan holds a `RelativePoseConstraint` between the two
    links of `goals` and the goals keep it, both links moved rigidly as one held object on its
    straight line (its midpoint on the straight line, its orientation by slerp; link a ends on
    its goal, link b where the held pose puts it), followed by IK, certified with the
    constraint, timed (`plan_link_lines` with a carrier). The successful result, or None
    (then the plan searches as for any goals): the straight carry collides, leaves the
    constraint, or ends link b farther from its goal than IK's tolerances.
    """
    hold = next((c for c in validity.constraints if isinstance(c, RelativePoseConstraint)
                 and {c.link_a, c.link_b} == set(goals) and c.reference is not None), None)
    if hold is None:
        return None
    a, b = hold.link_a, hold.link_b
    Ta, Tb = kinematics.fk(start, a), kinematics.fk(start, b)
    move = goals[a] @ Ta.inverse()                                 # the held object's motion
    dp, dr = (move @ Tb).distance(goals[b])
    if dp > solver.position_tolerance or dr > solver.rotation_tolerance:
        return None
    c0 = Pose((Ta.position + Tb.position) / 2, Ta.quaternion)
    kin, moving = kinematics, free_joints(config, [a, b])
    if not moving.all():
        kin = kinematics.pinned(start, moving)
        validity = held_validity(validity, kin)
    targets = [(link, goals[link], held_view(config, kinematics, solver, [link], start)[1],
                free_joints(config, [link]) if config.arms else None) for link in (a, b)]
    result = plan_linear_links(ctx, validity, start, targets, limits=kin.limits, carrier=(c0, move @ c0))
    if result.success:
        errors = np.array([kinematics.fk(result.goal_q, link).distance(goals[link]) for link in (a, b)])
        if errors[:, 0].max() <= solver.position_tolerance and errors[:, 1].max() <= solver.rotation_tolerance:
            return result
    ctx.clear_failure()
    return None
