"""Task-level motions: `plan_grasp` (free motion, linear approach, lift) and `plan_place`
(free or constrained motion, linear descent, release, linear retreat).

Every stage is an ordinary certified plan (`planning.pipeline`, `planning.linear_motion`) on
its own view of the generator's world; the generator itself is not changed (attach the
object with `MotionGenerator.attach_object` when the grasp is executed). The views:

- approach: the object is an obstacle, and only the gripper's finger links may touch it
  (`CollisionChecker.allowing`; every other pair, the fingers against everything else
  included, is checked and certified as usual);
- lift (grasp) / descent (place): the object is attached to the link at the grasp
  (`CollisionChecker.fork` + `attach_object`); it may touch only the obstacles it touches at
  the grasp (the support it is lifted from) or at the placement (the support it is put on);
- retreat (place): the object is released into the world at its placement; only the fingers
  may touch it.

Constraints (`PlanOptions.constraints`, `plan_place(constraints=...)`) hold while the object is
held: the lift of `plan_grasp`, the free motion and the descent of `plan_place`.

Candidates (grasp or placement poses) are tried in the order of the time-optimal motion
from the start to their goal configuration (`planning.path.goals.order_goals`, as goal
sets are): for each, the goal and the pre-pose get IK, the linear stages are planned, then
the free motion to the pre-pose; the first candidate whose stages all succeed is returned
(at most MAX_TRIED are tried). A failure says which stage of which candidates failed and why.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from manip.collision import CollisionChecker, CollisionReport
from manip.constraints import Constraint
from manip.errors import InvalidInputError, UnknownNameError
from manip.ik import IKSolver, IKStatus
from manip.limits import JointLimits
from manip.planning.constrained import with_constraints
from manip.planning.context import PlanContext
from manip.planning.goal_configurations import nearest_solution_problem
from manip.planning.grasp_plan import GraspPlan, failure_message, join
from manip.planning.linear_motion import plan_linear
from manip.planning.path.goals import order_goals
from manip.planning.pipeline import plan_to_configs
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.validity import Validity, describe_contacts
from manip.pose import Pose
from manip.validation import positive

#: An attached object this close [m] to an obstacle at the grasp (placement) may touch it
#: during the lift (descent): the support it is lifted from (put on), up to IK's tolerance.
SUPPORT_GAP = 2e-3
#: IK attempts per candidate of the first pass (the second searches with the solver's own).
QUICK_ATTEMPTS = 4
#: Candidates whose linear stages are planned at most (in the ranked order) before giving up.
MAX_TRIED = 24


@dataclass(frozen=True)
class Stages:
    """What the task planners use of a `MotionGenerator` (its public parts).

    Attributes:
        context: options (dict) -> a `PlanContext` (the generator's defaults applied).
        validity: the generator's `Validity` (kinematics and resolutions).
        checker: the generator's `CollisionChecker` (forked / viewed, never edited).
        ik_solver: the generator's `IKSolver`.
        limits: the robot's `JointLimits`.
        clearance: the generator's `ClearanceModel`.
        finger_links: the gripper's finger links (the only links that may touch the object).
    """

    context: Callable[[dict], PlanContext]
    validity: Validity
    checker: CollisionChecker
    ik_solver: IKSolver
    limits: JointLimits
    clearance: object
    finger_links: tuple[str, ...]

    def view(self, checker: CollisionChecker, constraints=()) -> Validity:
        """A validity on `checker` (a snapshot or view) with the generator's resolutions."""
        v = self.validity
        return with_constraints(Validity(checker.snapshot(), v.kinematics, v.resolution, v.search_resolution),
                                constraints)


def finger_links(kinematics, gripper, link: str) -> tuple[str, ...]:
    """The links moved by the gripper's joints (the fingers); without a gripper, the links of
    the body that carries `link`."""
    full = kinematics.full_model
    if gripper is not None:
        joints = {full.getJointId(j) for j in gripper.joints}
        return tuple(sorted({f.name for f in full.frames if f.parentJoint in joints and f.name in _bodies(full)}))
    joint = kinematics.model.frames[kinematics.frame_id(link)].parentJoint
    return tuple(sorted({f.name for f in kinematics.model.frames if f.parentJoint == joint}))


def _bodies(model) -> set[str]:
    return {f.name for f in model.frames if f.type == pin.FrameType.BODY}


def _poses(value, what: str) -> Pose:
    if not isinstance(value, Pose):
        raise InvalidInputError(f"{what} must be a manip.Pose (batched: one pose per candidate); got "
                                f"{type(value).__name__}")
    if value.is_batch and len(value) == 0:
        raise InvalidInputError(f"{what} must hold at least one pose; got an empty batch")
    return value if value.is_batch else Pose.stack([value])


def _shift(pose: Pose, offset: np.ndarray) -> Pose:
    return Pose(pose.position + offset, pose.quaternion)


def _touching(checker: CollisionChecker, q: np.ndarray, name: str) -> list[tuple[str, str]]:
    """(name, obstacle) for every obstacle the attached object `name` touches at q (comes
    within the padding + SUPPORT_GAP of: a support it rests on, up to IK's tolerance)."""
    near = checker.fork()
    near.padding = checker.padding + SUPPORT_GAP
    report = near.collision_report(q)
    return [(name, c.b) for c in report.contacts if c.kind == "attached_world" and c.a == name]


def _ik(stages: Stages, goal: Pose, link: str, seed_q: np.ndarray, validity: Validity, ctx: PlanContext):
    """IK of `goal` from `seed_q` that `validity` accepts: first without the checks (the
    solution nearest the seed is usually it), then searched with them. When every solution
    is rejected, the message names what the one nearest `seed_q` touches."""
    seed = int(ctx.rng.integers(2**31))
    r = _quick(stages.ik_solver).solve(goal, link, seed_q=seed_q, seed=seed)
    if r.success and validity.configs(r.q[None])[0]:
        return r
    r = stages.ik_solver.solve(goal, link, seed_q=seed_q, validity_fn=validity.configs, seed=seed)
    if r.status is IKStatus.REJECTED_BY_VALIDITY:
        problem = nearest_solution_problem(stages.ik_solver, goal, link, seed_q, validity, seed)
        if problem:
            r = replace(r, message=f"every solution found in {r.attempts} attempt(s) is rejected; the one nearest "
                                   f"the start: {problem}")
    return r


def plan_grasp(stages: Stages, start_q: np.ndarray, grasps: Pose, object_name: str, *, approach: float, lift: float,
               link: str, options: dict) -> GraspPlan:
    """`MotionGenerator.plan_grasp` (see the module docstring and the method)."""
    t0 = time.perf_counter()
    grasps = _poses(grasps, "grasps")
    approach = positive(approach, "approach", "m")
    lift = positive(lift, "lift", "m")
    world = stages.checker.snapshot()
    if object_name not in world.world:
        raise UnknownNameError("object_name: obstacle", object_name, world.world.names)
    ctx = stages.context(options)
    constraints = ctx.options.constraints  # they hold while the object is held: the lift
    free = stages.view(world)
    start = ctx.check_start(start_q, free.kinematics, free)
    if ctx.failed:
        return _failed(ctx.result(), t0)
    kin = free.kinematics
    touch = stages.view(world.allowing([(f, object_name) for f in stages.finger_links]))
    q, ok = _first_solutions(stages, grasps, link, start, touch.configs, ctx)
    failures: list = []
    def stages_of(i: int):
        """(pre-grasp configuration, approach, lift) of candidate i, or None (failure recorded)."""
        g = grasps[i]
        pre = _shift(g, -approach * g.rotation[:, 2])
        r_pre = _ik(stages, pre, link, q[i], free, ctx)
        if not r_pre.success:
            failures.append((i, "pre-grasp IK", PlanStatus.IK_FAIL, r_pre.message or r_pre.status.name))
            return None
        seg_a = plan_linear(stages.context(options), touch, stages.ik_solver, r_pre.q, g, link, limits=stages.limits)
        if not seg_a.success:
            failures.append((i, "approach", seg_a.status, seg_a.message))
            return None
        q_g = seg_a.goal_q
        held = stages.checker.fork()
        held.attach_object(object_name, q=q_g, link=link)
        held_from = tuple(c.at_start(kin, q_g) for c in constraints)   # a relative pose: as held at the grasp
        lifting = stages.view(held.allowing(_touching(held.snapshot(), q_g, object_name)), held_from)
        up = _shift(kin.fk(q_g, link), np.array([0.0, 0.0, lift]))
        seg_l = plan_linear(stages.context(options), lifting, stages.ik_solver, q_g, up, link, limits=stages.limits)
        if not seg_l.success:
            failures.append((i, "lift", seg_l.status, seg_l.message))
            return None
        return r_pre.q, seg_a, seg_l

    def search(i: int) -> np.ndarray | None:
        r = _ik(stages, grasps[i], link, start, touch, ctx)
        if not r.success:
            failures.append((i, "grasp IK", PlanStatus.IK_FAIL, r.message or r.status.name))
        return r.q if r.success else None

    return _two_passes(stages, options, free, start, q, ok, search, stages_of, ("free", "approach", "lift"), failures,
                       "grasp", t0, ctx)


def plan_place(stages: Stages, start_q: np.ndarray, placements: Pose, *, retreat: float, approach: float, link: str,
               constraints: tuple[Constraint, ...], options: dict) -> GraspPlan:
    """`MotionGenerator.plan_place` (see the module docstring and the method)."""
    t0 = time.perf_counter()
    placements = _poses(placements, "placements")
    retreat = positive(retreat, "retreat", "m")
    approach = positive(approach, "approach", "m")
    world = stages.checker.snapshot()
    attached = world.attached_objects
    if len(attached) != 1:
        raise InvalidInputError(f"plan_place needs exactly one attached object (MotionGenerator.attach_object); "
                                f"attached: {sorted(attached)}")
    name, att = next(iter(attached.items()))
    ctx = stages.context({**options, "constraints": constraints})
    kin = stages.validity.kinematics
    q0 = kin.check_q(start_q, "start_q")
    # bound to the start (`Constraint.at_start`: a relative pose is held as it is there)
    bound = tuple(c.at_start(kin, q0) for c in ctx.options.constraints) if q0.ndim == 1 else ctx.options.constraints
    carry = stages.view(world, bound)
    start = ctx.check_start(start_q, carry.kinematics, carry)
    if ctx.failed:
        return _failed(ctx.result(), t0)
    kin = carry.kinematics
    # the carrying link's pose that puts the object at each placement, then `link`'s
    T_carry_link = kin.fk(start, att.link).inverse() @ kin.fk(start, link)
    goals = Pose.stack([p @ att.pose_in_link.inverse() @ T_carry_link for p in placements])
    # at the placement the object may rest on a support: that contact is allowed, so a
    # configuration in collision only through it is a candidate
    def placeable(Q: np.ndarray) -> np.ndarray:
        return np.array([not _other_contacts(world, q_, name) for q_ in np.atleast_2d(Q)])

    q, ok = _first_solutions(stages, goals, link, start, placeable, ctx)
    failures: list = []
    def stages_of(i: int):
        """(above-placement configuration, descent, retreat) of candidate i, or None (failure recorded)."""
        q_p = q[i]
        putting = stages.view(world.allowing(_touching(world, q_p, name)), bound)
        above = _shift(goals[i], np.array([0.0, 0.0, approach]))
        r_above = _ik(stages, above, link, q_p, carry, ctx)
        if not r_above.success:
            failures.append((i, "above-placement IK", PlanStatus.IK_FAIL, r_above.message or r_above.status.name))
            return None
        seg_d = plan_linear(stages.context({**options, "constraints": constraints}), putting, stages.ik_solver,
                            r_above.q, goals[i], link, limits=stages.limits)
        if not seg_d.success:
            failures.append((i, "descend", seg_d.status, seg_d.message))
            return None
        q_d = seg_d.goal_q
        released = stages.checker.fork()
        released.detach_object(q_d, name)
        leaving = stages.view(released.allowing([(f, name) for f in stages.finger_links]))
        T = kin.fk(q_d, link)
        back = _shift(T, -retreat * T.rotation[:, 2])
        seg_r = plan_linear(stages.context(options), leaving, stages.ik_solver, q_d, back, link, limits=stages.limits)
        if not seg_r.success:
            failures.append((i, "retreat", seg_r.status, seg_r.message))
            return None
        return r_above.q, seg_d, seg_r

    def search(i: int) -> np.ndarray | None:
        seed = int(ctx.rng.integers(2**31))
        r = stages.ik_solver.solve(goals[i], link, seed_q=start, validity_fn=placeable, seed=seed)
        if not r.success:
            why = r.message or r.status.name
            if r.status is IKStatus.REJECTED_BY_VALIDITY:  # name what the solution nearest the start touches
                near = stages.ik_solver.solve_many(goals[i], link, n=1, seed_q=start, seed=seed)
                if len(near):
                    others = [c for c in world.collision_report(near[0]).contacts
                              if not (c.kind == "attached_world" and c.a == name)]
                    why = (f"every solution found in {r.attempts} attempt(s) is rejected; the one nearest the start "
                           f"touches more than the placement's support: {describe_contacts(CollisionReport(True, tuple(others)))}")
            failures.append((i, "placement IK", PlanStatus.IK_FAIL, why))
        return r.q if r.success else None

    return _two_passes(stages, {**options, "constraints": constraints}, carry, start, q, ok, search, stages_of,
                       ("free", "descend", "retreat"), failures, "placement", t0, ctx)


def _other_contacts(checker: CollisionChecker, q: np.ndarray, name: str) -> bool:
    """True when q collides other than through the attached object `name` touching the world."""
    return any(not (c.kind == "attached_world" and c.a == name) for c in checker.collision_report(q).contacts)


def _quick(solver: IKSolver) -> IKSolver:
    """`solver`'s settings with QUICK_ATTEMPTS attempts per goal (a reachable pose converges
    in one or two; an unreachable one would burn all of the solver's)."""
    return IKSolver(solver.kinematics, position_tolerance=solver.position_tolerance,
                    rotation_tolerance=solver.rotation_tolerance, max_iterations=solver.max_iterations,
                    max_attempts=QUICK_ATTEMPTS, seed=solver.seed, damping=solver.damping, max_step=solver.max_step)


def _first_solutions(stages: Stages, goals: Pose, link: str, start: np.ndarray, valid, ctx: PlanContext):
    """(q (N, dof), ok (N,)): one batched IK of every candidate pose from `start`, without
    collision checks (most converge at once), then `valid` on the solutions."""
    r = _quick(stages.ik_solver).solve_batch(goals, link, seed_q=start, seed=int(ctx.rng.integers(2**31)))
    q, ok = np.array(r.q), np.array(r.solved)
    if ok.any():
        ok[ok] = valid(q[ok])
    return q, ok


def _two_passes(stages: Stages, options: dict, validity: Validity, start: np.ndarray, q: np.ndarray, ok: np.ndarray,
                search: Callable, stages_of: Callable, names: tuple, failures: list, what: str, t0: float,
                ctx: PlanContext) -> GraspPlan:
    """`_sequence` over the candidates whose first IK solution was valid (ranked by the motion
    to it); if none gives a plan, IK searched with the validity (`search(i)`: q or None) for
    the others, and `_sequence` over those."""
    limits = ctx.scaled_limits(stages.limits)

    def ranked(idx: np.ndarray) -> list[int]:
        return [int(idx[k]) for k in order_goals(start, q[idx], limits)] if idx.size else []

    plan = _sequence(stages, options, validity, start, ranked(np.flatnonzero(ok)), stages_of, names, failures,
                     len(q), what, t0)
    if plan.success or ok.all():
        return plan
    found = []
    for i in np.flatnonzero(~ok):
        qi = search(int(i))
        if qi is not None:
            q[i] = qi
            found.append(int(i))
    return _sequence(stages, options, validity, start, ranked(np.array(found, dtype=int)), stages_of, names,
                     failures, len(q), what, t0)


def _sequence(stages: Stages, options: dict, validity: Validity, start: np.ndarray, order: list[int],
              stages_of: Callable, names: tuple, failures: list, candidates: int, what: str, t0: float) -> GraspPlan:
    """The first candidate of `order` (at most MAX_TRIED) whose linear stages (`stages_of(i)`:
    (pre-configuration, stage 2, stage 3) or None) and free motion from `start` succeed."""
    timings = {"candidates": 0.0, "free": 0.0}
    for i in order[:MAX_TRIED]:
        t = time.perf_counter()
        found = stages_of(i)
        timings["candidates"] += time.perf_counter() - t
        if found is None:
            continue
        q_pre, seg_2, seg_3 = found
        t = time.perf_counter()
        seg_f = plan_to_configs(stages.context(options), validity, start, q_pre[None], limits=stages.limits,
                                clearance=stages.clearance)
        timings["free"] += time.perf_counter() - t
        if not seg_f.success:
            failures.append((i, "free motion", seg_f.status, seg_f.message))
            continue
        segments = (seg_f, seg_2, seg_3)
        for name, seg in zip(names[1:], segments[1:]):
            timings[name] = seg.timings.get("total", 0.0)
        timings["total"] = time.perf_counter() - t0
        skipped = "; ".join(f"candidate {j}: {stage}: {status.name}: {why}" for j, stage, status, why in failures[:8])
        return GraspPlan(True, PlanStatus.SUCCESS, f"candidates skipped: {skipped}" if skipped else "", i, segments,
                         names, join([s.trajectory for s in segments]), timings)
    status = failures[-1][2] if failures else PlanStatus.IK_FAIL
    timings["total"] = time.perf_counter() - t0
    return GraspPlan(False, status, failure_message(failures, candidates, what), timings=timings)


def _failed(result: PlanResult, t0: float) -> GraspPlan:
    return GraspPlan(False, result.status, result.message, segments=(result,), stages=("free",),
                     timings={"total": time.perf_counter() - t0})
