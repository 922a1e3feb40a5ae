"""`MotionGenerator`: the public entry point for kinematics, collision checking and planning.

The pipeline of every plan (each stage timed in `PlanResult.timings`):

1. validate the start (`PlanContext.check_start`): joint limits (a start up to 1e-4 rad
   outside is accepted), self and world collision; failures return INVALID_START_* statuses;
2. goals: joint goals are checked (INVALID_GOAL); pose goals become several collision-free
   IK solutions (IK_FAIL when there is none);
3. path: the straight joint-space line when it is valid, else the coarse-to-fine
   RRT-Connect search towards all goal configurations at once (`planning.path.search`);
4. shortcut: batched random shortcutting, optionally clearance smoothing (`planning.path.smoothing`);
5. timing: ruckig segments with blended corners (`manip.timing`);
6. validate: the continuous interpolation of the returned samples is certified
   collision-free against the exact collision model (`planning.time_and_validate`,
   `CollisionChecker.certify_path`). Only a trajectory that passes is returned with
   `success=True`; one that fails is planned again (`planning.pipeline`);
7. trajectory optimisation (`planning.trajopt.refine`, `planning.trajopt.optimizer`): the valid trajectory of a
   searched path seeds a B-spline optimiser; its result replaces the seed only when it is
   faster and passes the same validation (`PlanResult.source == "trajopt"`).

The planners are handed a `planning.Validity` (collision and limit questions) and a
`PlanContext` (options, deadline, random generator, timings); this class checks the start
and the goals and hands them to `planning.pipeline.plan_to_configs`, which runs the attempts.

Guarantees of a trajectory returned with `success=True` (`planning.time_and_validate`): it starts at
the start and ends at the goal at rest, keeps the position, velocity, acceleration and
jerk limits, and its continuous interpolation (straight joint-space lines between the
samples) is certified collision-free against the exact meshes with the padding
(`CollisionChecker.certify_path`, conservative advancement), not only at sampled
configurations.

Threading contract: one MotionGenerator may be shared by threads. `fk`, `ik`, `batch_ik`,
`check_collision`, `distance` and the `plan_*` calls may run concurrently (Pinocchio's work
space is per thread, the compiled kernels release the GIL, nothing shared is written).
World edits (`update_world`, `add_obstacle`, `remove_obstacle`, `attach_object`,
`detach_object`) may run concurrently with them: edits are serialised, each query and
each whole plan reads one snapshot of the world taken when it starts, and an edit applies
to the calls that start after it. Changing the defaults (`velocity_scale`, ...) while
other threads plan is not supported.
"""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from manip import curobo_names
from manip.collision import CollisionChecker, WorldConfig
from manip.collision.arm_clearance import arm_clearance
from manip.errors import InvalidInputError
from manip.ik import BatchIKResult, IKResult, IKSolver
from manip.kinematics import Kinematics
from manip.planning.arms import (
    check_goals,
    held_batch_ik,
    held_validity,
    held_view,
    plan_link_lines,
    plan_link_poses,
)
from manip.planning.constrained import with_constraints
from manip.planning.context import START_LIMIT_TOLERANCE, PlanContext
from manip.planning.goal_configurations import (
    explain_rejected_batch_ik,
    explain_rejected_ik,
    note_whole_turns,
    plan_to_poses,
)
from manip.planning.grasp import Stages, finger_links, plan_grasp, plan_place
from manip.planning.grasp_plan import GraspPlan
from manip.planning.linear_motion import (
    LINEAR_DEVIATION,
    LINEAR_SPLINE_DEVIATION,
    MAX_LINEAR_POINTS,
    plan_linear,
)
from manip.planning.options import PlanOptions
from manip.planning.pipeline import plan_to_configs
from manip.planning.result import PlanResult, PlanResults
from manip.planning.validity import Validity
from manip.pose import Pose
from manip.robot_arms import arm_specs, state_columns
from manip.robot_config import (
    RobotConfig,
    compose_robot_config,
    config_from_urdf,
    load_robot_config,
)
from manip.validation import as_real_array, flag, fraction, positive
from manip.world_edits import WorldEdits

logger = logging.getLogger(__name__)

__all__ = ["LINEAR_DEVIATION", "LINEAR_SPLINE_DEVIATION", "MAX_LINEAR_POINTS", "START_LIMIT_TOLERANCE", "MotionGenerator"]

#: The Isaac Sim tutorial wrapper's names, which moved to `manip.TutorialMotionGen` (asking a
#: MotionGenerator for one raises an AttributeError saying where it went).
TUTORIAL_NAMES = frozenset({
    "init_motion_gen", "motion_generate", "update_obstacle_from_world", "update_obstacle_from_isaac_sim",
    "convert_solution_to_actions", "convert_solution_to_isaac_sim_action", "ik_batch", "set_constraint",
    "reset_constraint", "wxyz_to_xyzw", "wxzy_to_xyzw", "xyzw_to_wxyz",
})


class MotionGenerator(WorldEdits):
    """Kinematics, collision checking and motion planning for one robot.

    Args:
        robot: a robot name under `robots/` ("franka", in any case) or a path to a robot.yaml, or a RobotConfig.
        world: obstacles in the robot base frame (a WorldConfig or a cuRobo-style dict).
        padding: extra clearance [m] kept from the world (default: the robot config's).
        time_budget: default planning time budget [s] per call.
        interpolation_dt: default trajectory sample period [s] (1/60 s, the simulator's).
        resolution: collision-check resolution along motions [rad] (joint-space L-inf) of
            the path search and repair; returned trajectories are in addition certified
            collision-free over their whole continuous interpolation.
        search_resolution: coarser resolution of the path search's edge checks [rad]; the
            found path is re-checked (and repaired) at `resolution`.
        seed: default random seed of IK restarts and sampling-based planning.
        velocity_scale, acceleration_scale: default factors in (0, 1] on the velocity and on the
            acceleration and jerk limits (cuRobo's MotionGenConfig arguments; the attributes of the
            same names, and the per-call options, override them).

    Configurations (`start_q`, `goal_q`, `q`, `seed_q`) are the arm joints, (dof,) in
    `joint_names` order; a robot with a gripper also takes its full state (dof + G,), the
    gripper's G joints last, as `franka.get_joint_positions()` gives (7 + 2 values): the
    gripper's values are ignored, and trajectories are the arm joints' only.

    The Isaac Sim tutorial wrapper's names (`motion_generate`, ...) live on
    `manip.TutorialMotionGen`, which holds a MotionGenerator.
    """

    #: Set by `manip.compat` to wrap a MotionGenerator in the tutorial wrapper (deprecated names).

    def __init__(
        self,
        robot: str | RobotConfig = "franka",
        world: WorldConfig | dict | None = None,
        *,
        padding: float | None = None,
        time_budget: float = 5.0,
        interpolation_dt: float = 1.0 / 60.0,
        resolution: float = 0.01,
        search_resolution: float = 0.08,
        seed: int = 0,
        velocity_scale: float = 1.0,
        acceleration_scale: float = 1.0,
    ):
        if isinstance(robot, RobotConfig):
            self.config = robot
        elif isinstance(robot, (str, Path)):
            self.config = load_robot_config(robot)
        else:
            raise InvalidInputError(
                f"robot must be a robot name (e.g. 'franka'), a path to a robot.yaml or a RobotConfig; got {robot!r}"
            )
        # option-like arguments first: a bad one fails before the robot's models are built
        self.defaults = PlanOptions(time_budget=time_budget, dt=interpolation_dt, seed=seed)
        resolution = positive(resolution, "resolution", "rad")
        search_resolution = positive(search_resolution, "search_resolution", "rad")
        velocity_scale = fraction(velocity_scale, "velocity_scale")
        acceleration_scale = fraction(acceleration_scale, "acceleration_scale")
        self.kinematics = Kinematics(self.config)
        self.checker = CollisionChecker(self.config, self.kinematics, None, padding=padding)
        self.validity = Validity(self.checker, self.kinematics, resolution, search_resolution)
        self.clearance = arm_clearance(self.checker, self.config)   # + the arm-arm terms of a multi-arm robot
        self.ik_solver = IKSolver(self.kinematics, seed=seed)
        #: The robot's `JointLimits` (`config.limits`; `timing_limits` is the old name).
        self.limits = self.config.limits
        self.timing_limits = self.limits
        self.velocity_scale = velocity_scale
        self.acceleration_scale = acceleration_scale
        if world is not None:
            self.update_world(world)

    @classmethod
    def from_urdf(cls, urdf: str | Path, srdf: str | Path | None = None, *, base_link: str | None = None,
                  ee_link: str | None = None, **kwargs) -> MotionGenerator:
        """A MotionGenerator for a robot without a folder, from its URDF (and SRDF).

        Limits, defaults and the warnings for assumed values: `manip.robot_config.config_from_urdf`
        (acceleration 10 rad/s^2, jerk 500 rad/s^3 unless given). `kwargs` go to
        `config_from_urdf` (arm_joints, default_joint_positions, acceleration_limits,
        jerk_limits, name) or else to the constructor (world, padding, time_budget, ...).
        """
        names = ("arm_joints", "default_joint_positions", "acceleration_limits", "jerk_limits", "name")
        constructor = ("world", "padding", "time_budget", "interpolation_dt", "resolution", "search_resolution", "seed",
                       "velocity_scale", "acceleration_scale")
        unknown = sorted(set(kwargs) - set(names) - set(constructor))
        if unknown:
            raise InvalidInputError(f"MotionGenerator.from_urdf got unknown arguments {unknown}; valid: urdf, srdf, "
                                    f"base_link, ee_link, {', '.join(names + constructor)}")
        config = config_from_urdf(urdf, srdf, base_link=base_link, ee_link=ee_link,
                                  **{k: kwargs.pop(k) for k in names if k in kwargs})
        return cls(config, **kwargs)

    @classmethod
    def from_robots(cls, arms: dict, *, name: str | None = None, base_link: str | None = None,
                    **kwargs) -> MotionGenerator:
        """A MotionGenerator for several arms as one robot, from their robots and base poses.

        `arms` maps a name prefix to (robot, base pose): `{"left": ("franka", Pose([0, 0.35, 0])),
        "right": ("ur5", Pose([0, -0.35, 0]))}` (a robot: a shipped name, a robot folder or a
        RobotConfig; a base pose: the arm's base link in the combined base frame, `base_link`,
        default "base"). Names are prefixed ("left_panda_joint1"); a configuration is each arm's
        joints in turn. `kwargs` go to the constructor. See `manip.robot_arms`.
        """
        specs = arm_specs(arms)
        config = compose_robot_config(specs, name=name or "+".join(s.prefix.rstrip("_") for s in specs),
                                      base_link=base_link)
        return cls(config, **kwargs)

    # ------------------------------------------------------------------ defaults
    @property
    def time_budget(self) -> float:
        """Default planning time budget [s]."""
        return self.defaults.time_budget

    @property
    def interpolation_dt(self) -> float:
        """Default trajectory sample period [s]."""
        return self.defaults.dt

    @property
    def seed(self) -> int:
        """Default random seed."""
        return self.defaults.seed

    @property
    def resolution(self) -> float:
        """Collision-check resolution along motions [rad]."""
        return self.validity.resolution

    @property
    def search_resolution(self) -> float:
        """Edge-check resolution of the path search [rad]."""
        return self.validity.search_resolution

    # ------------------------------------------------------------------ robot facts
    @property
    def joint_names(self) -> list[str]:
        """The planned (arm) joints, in the order of every q."""
        return list(self.kinematics.joint_names)

    @property
    def robot_dof(self) -> int:
        """Number of planned joints."""
        return self.kinematics.dof

    @property
    def default_joint_positions(self) -> np.ndarray:
        """(dof,) the ready (retract) configuration [rad]."""
        return self.config.default_joint_positions.copy()

    @property
    def lower_limits(self) -> np.ndarray:
        """(dof,) lower position limits [rad]."""
        return self.config.lower_limits.copy()

    @property
    def upper_limits(self) -> np.ndarray:
        """(dof,) upper position limits [rad]."""
        return self.config.upper_limits.copy()

    @property
    def velocity_limits(self) -> np.ndarray:
        """(dof,) velocity limits [rad/s]."""
        return self.config.velocity_limits.copy()

    @property
    def acceleration_limits(self) -> np.ndarray:
        """(dof,) acceleration limits [rad/s^2]."""
        return self.config.acceleration_limits.copy()

    @property
    def jerk_limits(self) -> np.ndarray:
        """(dof,) jerk limits [rad/s^3]."""
        return self.config.jerk_limits.copy()

    @property
    def ee_link(self) -> str:
        """The default link of pose goals and `fk`."""
        return self.config.ee_link

    @property
    def base_link(self) -> str:
        """The frame every pose and obstacle is expressed in."""
        return self.config.base_link

    # ------------------------------------------------------------------ kinematics
    def fk(self, q: np.ndarray | Sequence[float], link: str | None = None) -> Pose:
        """Pose of `link` (default `ee_link`) in the base frame.

        Args:
            q: (dof,) -> a single Pose, or (N, dof) -> a batched Pose [rad].
            link: any frame of the URDF (None: `ee_link`).
        """
        return self.kinematics.fk(self._arm_q(q, "q"), self._link(link))

    def ik(
        self,
        goal: Pose,
        link: str | None = None,
        seed_q: np.ndarray | None = None,
        *,
        collision_free: bool = False,
        **kwargs,
    ) -> IKResult:
        """Joint positions placing `link` (default `ee_link`) at the single Pose `goal`.

        With `collision_free=True` only configurations free of collisions with the world and
        the robot itself count as solutions (the world as it is when the call starts).
        When every solution found collides, `message` says what the one nearest `seed_q` touches.
        Other keyword arguments go to `IKSolver.solve`. A batched Pose is deprecated here:
        use `batch_ik`. On a multi-arm robot only the link's arm moves: the other joints keep
        their `seed_q` values (default: the default configuration; `manip.planning.arms`).
        """
        if not isinstance(goal, Pose):
            raise InvalidInputError(f"goal must be a manip.Pose; got {type(goal).__name__}")
        if goal.is_batch:
            warnings.warn("MotionGenerator.ik with a batched Pose is deprecated: use batch_ik", DeprecationWarning,
                          stacklevel=2)
            return self.batch_ik(goal, link, seed_q, collision_free=collision_free, **kwargs)  # type: ignore[return-value]
        link = self._link(link)
        if seed_q is not None:
            seed_q = self.kinematics.check_q(self._arm_q(seed_q, "seed_q"), "seed_q")
        solver = self._arm_solver(link, seed_q)
        if not flag(collision_free, "collision_free") or "validity_fn" in kwargs:
            return solver.solve(goal, link, seed_q=seed_q, **kwargs)
        validity = self._validity()  # a failure names what the solution nearest seed_q touches
        result = solver.solve(goal, link, seed_q=seed_q, validity_fn=validity.configs, **kwargs)
        return explain_rejected_ik(result, solver, goal, link, seed_q, validity, kwargs.get("seed"))

    def batch_ik(self, goals: Pose, link: str | None = None, seed_q: np.ndarray | None = None, *,
                 collision_free: bool = False, **kwargs) -> BatchIKResult:
        """Joint positions for each pose of the batched Pose `goals` (N poses), in one batch.

        Args:
            goals: a batched Pose (N,) in the base frame.
            link: any frame of the URDF (default `ee_link`).
            seed_q: (dof,) or (N, dof) configurations to start from [rad] (a multi-arm robot
                holds its other arms at each row's values, as `ik`).
            collision_free: only configurations free of collisions with the world and the
                robot itself count as solutions (as in `ik`).
            **kwargs: as `IKSolver.solve_batch`.
        """
        if not isinstance(goals, Pose):
            raise InvalidInputError(f"goals must be a manip.Pose; got {type(goals).__name__}")
        link = self._link(link)
        if seed_q is not None:
            seed_q = self.kinematics.check_q(self._arm_q(seed_q, "seed_q"), "seed_q")
        # a failure of collision_free=True names what the best solution touches (as `ik`); not a caller's validity_fn
        validity = self._validity() if flag(collision_free, "collision_free") and "validity_fn" not in kwargs else None
        kwargs.setdefault("validity_fn", validity.configs if validity else None)
        goals = goals if goals.is_batch else Pose.stack([goals])
        result = held_batch_ik(self.config, self.kinematics, self.ik_solver, goals, link, seed_q,
                               self.default_joint_positions, **kwargs)
        return explain_rejected_batch_ik(result, validity) if validity else result

    def _arm_q(self, q, what: str):
        """`q` with the gripper's values of a full robot state dropped: (..., dof + G) ->
        (..., dof), when the robot has a gripper of G joints (the Franka's state from
        `franka.get_joint_positions()`: 7 arm joints, then 2 fingers). Any other shape is
        returned as given (the callers' checks name what is valid), except one longer than
        dof, which raises saying which values to pass.
        """
        if q is None or isinstance(q, Pose):
            return q
        a = as_real_array(q, what)
        n, gripper = self.robot_dof, self.config.gripper
        g = len(gripper.joints) if gripper is not None else 0
        if a.ndim not in (1, 2) or a.shape[-1] <= n:
            return a
        if g and a.shape[-1] == n + g:  # a multi-arm robot: each arm's state in turn (`robot_arms`)
            return a[..., state_columns(self.config.arms)] if self.config.arms else a[..., :n]
        full = f" or ({n + g},): a full robot state, the gripper's joints {list(gripper.joints)} last" if g else ""
        head = f"{what}[:{n}]" if a.ndim == 1 else f"{what}[:, :{n}]"
        raise InvalidInputError(
            f"{what} must have shape ({n},) (the arm joints {self.joint_names}){full}; got {a.shape}. If its first "
            f"{n} values are the arm joints in this order, pass {head}."
        )

    def _arm_solver(self, link: str, seed_q: np.ndarray | None):
        """The IK solver moving only `link`'s arm, the others held at `seed_q` (`planning.arms`)."""
        q = self.default_joint_positions if seed_q is None else np.atleast_2d(seed_q)[0]
        return held_view(self.config, self.kinematics, self.ik_solver, [link], q)[1]

    def _link(self, link) -> str:
        """`link` checked as a frame name; None means `ee_link` (an empty or non-string name raises)."""
        if link is None:
            return self.ee_link
        self.kinematics.frame_id(link, "link")
        return link

    def _validity(self, ctx: PlanContext | None = None, start_q=None) -> Validity:
        """Collision questions against one snapshot of the world (taken now), and the plan's
        constraints (`ctx.options.constraints`, `planning.constrained`), bound to `start_q`
        (`Constraint.at_start`: a relative pose is held at its value there)."""
        v = self.validity
        v = Validity(self.checker.snapshot(), v.kinematics, v.resolution, v.search_resolution)
        if ctx is None or not ctx.options.constraints:
            return v
        q = None if start_q is None else self.kinematics.check_q(self._arm_q(start_q, "start_q"), "start_q")
        bound = [c if q is None or q.ndim != 1 else c.at_start(self.kinematics, q) for c in ctx.options.constraints]
        return with_constraints(v, bound)

    def _one_q(self, q, what: str) -> np.ndarray:
        q = self.kinematics.check_q(self._arm_q(q, what), what)
        if q.ndim != 1:
            raise InvalidInputError(f"{what} must have shape ({self.robot_dof},) (one configuration); got {q.shape}")
        return q

    # ------------------------------------------------------------------ planning
    def plan_joints(self, start_q, goal_q, **options) -> PlanResult:
        """Plan a collision-free, time-parameterised motion from `start_q` to `goal_q`.

        Args:
            start_q: (dof,) start configuration [rad] (at rest); a full robot state (arm then
                gripper joints, e.g. `franka.get_joint_positions()`) is taken as its arm joints.
            goal_q: (dof,) goal configuration [rad]; a goal up to 1e-4 rad outside a
                joint limit is moved onto the limit (like a start, see
                `START_LIMIT_TOLERANCE`), one further out is INVALID_GOAL.
            **options: any field of `manip.planning.PlanOptions` (`time_budget` [s], `seed`,
                `dt` [s], `velocity_scale`, `acceleration_scale`, `duration` [s],
                `optimize_clearance`, `trajopt`, `smoothness`, ...); unknown names raise
                InvalidInputError listing the valid ones.
        """
        ctx = self._context(options)
        validity = self._validity(ctx, start_q)
        start = ctx.check_start(self._arm_q(start_q, "start_q"), self.kinematics, validity)
        goal = ctx.check_goal(self._arm_q(goal_q, "goal_q"), self.kinematics, validity)
        if ctx.failed:
            return ctx.result()
        ctx.check_sample_count(start, goal, self.limits)
        result = plan_to_configs(ctx, validity, start, goal[None, :], limits=self.limits, clearance=self.clearance)
        return note_whole_turns(result, start, goal, self.kinematics, self.config.arm_joints)

    def plan_pose(self, start_q, goal: Pose, link: str | None = None, *, linear: bool = False, **options) -> PlanResult:
        """Plan a motion that brings `link` (default `ee_link`) to the pose `goal`.

        Args:
            start_q: (dof,) start configuration [rad] (or a full robot state, see `plan_joints`).
            goal: a single Pose in the base frame.
            link: any frame of the URDF; on a multi-arm robot only its arm moves, the other
                arms keep their start (`manip.planning.arms`).
            linear: move the link along the straight line from its start pose to the goal,
                interpolating the orientation (keep it by giving the start orientation).
            **options: as `plan_joints`.
        """
        if not isinstance(goal, Pose) or goal.is_batch:
            raise InvalidInputError("goal must be a single manip.Pose (use plan_goalset for several)")
        start_q = self._arm_q(start_q, "start_q")
        if flag(linear, "linear"):
            return self._plan_linear(start_q, goal, self._link(link), options)
        return self.plan_goalset(start_q, Pose.stack([goal]), link, **options)

    def plan_poses(self, start_q, goals: dict[str, Pose], *, linear: bool = False, **options) -> PlanResult:
        """One motion bringing several links (one per arm) to their poses together.

        `goals` maps a link name to a Pose in the base frame, e.g. both hands of a two-arm
        robot; one trajectory moves their arms at once and every link arrives at its end.
        Arms without a goal keep their start. `linear=True`: each link moves on the straight
        line to its goal, all at the same fraction of their lines (as `plan_pose(...,
        linear=True)` for one). Logic and guarantees: `manip.planning.arms`. `options` as `plan_joints`.
        """
        ctx = self._context(options)
        goals = check_goals(self.config, self.kinematics, goals)
        validity = self._validity(ctx, start_q)
        start = ctx.check_start(self._arm_q(start_q, "start_q"), self.kinematics, validity)
        if ctx.failed:
            return ctx.result()
        if flag(linear, "linear"):
            return plan_link_lines(ctx, validity, start, goals, config=self.config, kinematics=self.kinematics,
                                   solver=self.ik_solver)
        return plan_link_poses(ctx, validity, start, goals, config=self.config, kinematics=self.kinematics,
                               solver=self.ik_solver, limits=self.limits, clearance=self.clearance)

    def plan_goalset(self, start_q, goals: Pose, link: str | None = None, **options) -> PlanResult:
        """Plan to whichever of several poses (a batched Pose) is best reached.

        Collision-free IK solutions of every pose (for a redundant arm, each also moved along
        its self-motion towards the start) are planned to at once, the ones reachable fastest
        (by the time-optimal rest-to-rest duration from the start; among those within 10 % of
        the fastest, the shortest first: `planning.path.goals`) first; the result's
        `goal_index` says which pose was reached.
        """
        ctx = self._context(options)
        link = self._link(link)
        if not isinstance(goals, Pose):
            raise InvalidInputError(f"goals must be a manip.Pose; got {type(goals).__name__}")
        if not goals.is_batch:
            goals = Pose.stack([goals])
        if len(goals) == 0:
            raise InvalidInputError("goals must hold at least one pose; got an empty batch")
        validity = self._validity(ctx, start_q)
        start = ctx.check_start(self._arm_q(start_q, "start_q"), self.kinematics, validity)
        if ctx.failed:
            return ctx.result()
        # a multi-arm robot moves only the link's arm (`planning.arms`)
        kin, solver = held_view(self.config, self.kinematics, self.ik_solver, [link], start)
        if kin is not self.kinematics:
            validity = held_validity(validity, kin)
        return plan_to_poses(ctx, validity, start, goals, link, kinematics=kin, ik_solver=solver, limits=kin.limits,
                             clearance=self.clearance)

    def plan_batch(self, start_qs, goals, link: str | None = None, **options) -> PlanResults:
        """Plan several problems: `goals` is (N, dof) joint goals, a batched Pose or a list of Poses.
        One start (dof,) serves every goal; no goals (N = 0, an empty list too) give []. A list of
        N PlanResults with cuRobo's batch reads (`.success` (N,), `PlanResults`)."""
        start_qs = np.atleast_2d(self.kinematics.check_q(self._arm_q(start_qs, "start_qs"), "start_qs"))
        if isinstance(goals, (list, tuple)) and not goals:
            goals = np.zeros((0, self.robot_dof))
        if isinstance(goals, (list, tuple)) and all(isinstance(g, Pose) for g in goals):
            goals = Pose.stack(list(goals))
        if isinstance(goals, Pose):
            goal_list = list(goals) if goals.is_batch else [goals]
        else:
            if isinstance(goals, (list, tuple)) and any(isinstance(g, Pose) for g in goals):
                raise InvalidInputError("goals must be all joint configurations or all Poses, not a mix")
            goal_list = list(np.atleast_2d(self.kinematics.check_q(self._arm_q(goals, "goals"), "goals")))
        if len(start_qs) == 1 and len(goal_list) != 1:
            start_qs = np.repeat(start_qs, len(goal_list), axis=0)
        if len(start_qs) != len(goal_list):
            raise InvalidInputError(f"plan_batch needs as many start_qs as goals; got {len(start_qs)} and {len(goal_list)}")
        PlanOptions().updated(options)  # a bad option fails before any planning
        out = PlanResults()
        for s, g in zip(start_qs, goal_list):
            if isinstance(g, Pose):
                out.append(self.plan_pose(s, g, link, **options))
            else:
                out.append(self.plan_joints(s, g, **options))
        return out

    # ------------------------------------------------------------------ task-level motions
    def plan_grasp(self, start_q, grasps: Pose, object_name: str, *, approach: float = 0.10, lift: float = 0.10,
                   link: str | None = None, **options) -> GraspPlan:
        """Grasp the obstacle `object_name` at the best of the candidate poses `grasps` (a batched
        Pose of `link`, default `ee_link`): a free motion to the pre-grasp (`approach` [m] back
        along the link's z axis), a linear approach during which only the gripper's fingers may
        touch the object, then, with the object attached, a linear lift of `lift` [m] up (world
        z). `options` as `plan_joints` (`constraints` hold while the object is held: the
        lift). The generator's world is not changed: attach the object when the grasp is
        executed. How candidates are chosen, and what each stage may touch: `manip.planning.grasp`.
        """
        link = self._link(link)
        return plan_grasp(self._stages(link), self._arm_q(start_q, "start_q"), grasps, object_name,
                          approach=approach, lift=lift, link=link, options=options)

    def plan_place(self, start_q, placements: Pose, *, retreat: float = 0.10, approach: float = 0.10,
                   link: str | None = None, constraints=(), **options) -> GraspPlan:
        """Put the attached object at the best of `placements` (a batched Pose of the object's goal
        poses): a free motion (keeping `constraints`) to `approach` [m] above the placement, a
        linear descent (keeping them too), release, a linear retreat of `retreat` [m] back along
        `link`'s z axis (default the carrying link). The generator's world is not changed:
        detach the object when it is released (`manip.planning.grasp`).
        """
        attached = self.checker.attached_objects
        link = self._link(link if link is not None or len(attached) != 1 else next(iter(attached.values())).link)
        return plan_place(self._stages(link), self._arm_q(start_q, "start_q"), placements, retreat=retreat,
                          approach=approach, link=link, constraints=constraints, options=options)

    def _stages(self, link: str) -> Stages:
        return Stages(self._context, self.validity, self.checker, self.ik_solver, self.limits, self.clearance,
                      finger_links(self.kinematics, self.config.gripper, link))

    # ------------------------------------------------------------------ orchestration
    def _context(self, options: dict) -> PlanContext:
        t0 = time.perf_counter()
        base = self.defaults
        if self.velocity_scale != 1.0 or self.acceleration_scale != 1.0:
            base = replace(base, velocity_scale=self.velocity_scale, acceleration_scale=self.acceleration_scale)
        return PlanContext(base.updated(options), t0)

    def _plan_linear(self, start_q, goal: Pose, link: str, options: dict) -> PlanResult:
        """Straight-line motion of `link` from its current pose to `goal` (`planning.linear_motion`)."""
        ctx = self._context(options)
        validity = self._validity(ctx, start_q)
        start = ctx.check_start(start_q, self.kinematics, validity)
        if ctx.failed:
            return ctx.result()
        kin, solver = held_view(self.config, self.kinematics, self.ik_solver, [link], start)
        validity = validity if kin is self.kinematics else held_validity(validity, kin)
        return plan_linear(ctx, validity, solver, start, goal, link, limits=kin.limits)

    # ------------------------------------------------------------------ removed names
    def __getattr__(self, name: str):
        if name in TUTORIAL_NAMES:
            raise AttributeError(
                f"MotionGenerator.{name} moved to manip.TutorialMotionGen (deprecated here in 0.1, removed in 0.2): "
                f"wrap the generator, TutorialMotionGen(motion_gen=mg).{name}(...), or build the wrapper directly, "
                f"TutorialMotionGen('franka')"
            )
        raise curobo_names.missing(type(self).__name__, {**curobo_names.ROBOT_WORLD, **curobo_names.MOTION_GEN}, name)
