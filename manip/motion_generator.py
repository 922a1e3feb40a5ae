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
import math
import time
import warnings
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from manip.collision import CollisionChecker, WorldConfig
from manip.collision.clearance import ClearanceModel
from manip.errors import InvalidInputError
from manip.ik import BatchIKResult, IKResult, IKSolver
from manip.kinematics import Kinematics
from manip.perception import integrate_depth, integrate_pointcloud
from manip.planning.context import START_LIMIT_TOLERANCE, PlanContext
from manip.planning.goal_configurations import goal_configurations
from manip.planning.time_and_validate import time_and_validate
from manip.planning.path.goals import order_goals
from manip.planning.path.linear import linear_path
from manip.planning.options import PlanOptions
from manip.planning.pipeline import plan_to_configs
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.validity import Validity
from manip.pose import Pose
from manip.robot_config import RobotConfig, config_from_urdf, load_robot_config
from manip.sim_bridge import world_config_from_sim
from manip.validation import as_real_array, flag, positive

logger = logging.getLogger(__name__)

__all__ = ["MotionGenerator", "START_LIMIT_TOLERANCE"]

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

#: The Isaac Sim tutorial wrapper's names, which moved to `manip.TutorialMotionGen` (asking a
#: MotionGenerator for one raises an AttributeError saying where it went).
TUTORIAL_NAMES = frozenset({
    "init_motion_gen", "motion_generate", "update_obstacle_from_world", "update_obstacle_from_isaac_sim",
    "convert_solution_to_actions", "convert_solution_to_isaac_sim_action", "ik_batch", "set_constraint",
    "reset_constraint", "wxyz_to_xyzw", "wxzy_to_xyzw", "xyzw_to_wxyz",
})


class MotionGenerator:
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
        self.kinematics = Kinematics(self.config)
        self.checker = CollisionChecker(self.config, self.kinematics, None, padding=padding)
        self.validity = Validity(self.checker, self.kinematics, resolution, search_resolution)
        self.clearance = ClearanceModel(self.checker)
        self.ik_solver = IKSolver(self.kinematics, seed=seed)
        #: The robot's `JointLimits` (`config.limits`; `timing_limits` is the old name).
        self.limits = self.config.limits
        self.timing_limits = self.limits
        self.velocity_scale = 1.0
        self.acceleration_scale = 1.0
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
        constructor = ("world", "padding", "time_budget", "interpolation_dt", "resolution", "search_resolution", "seed")
        unknown = sorted(set(kwargs) - set(names) - set(constructor))
        if unknown:
            raise InvalidInputError(f"MotionGenerator.from_urdf got unknown arguments {unknown}; valid: urdf, srdf, "
                                    f"base_link, ee_link, {', '.join(names + constructor)}")
        config = config_from_urdf(urdf, srdf, base_link=base_link, ee_link=ee_link,
                                  **{k: kwargs.pop(k) for k in names if k in kwargs})
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
        Other keyword arguments go to `IKSolver.solve`. A batched Pose is deprecated here:
        use `batch_ik`.
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
        if flag(collision_free, "collision_free"):
            kwargs.setdefault("validity_fn", self._validity().configs)
        return self.ik_solver.solve(goal, link, seed_q=seed_q, **kwargs)

    def batch_ik(self, goals: Pose, link: str | None = None, seed_q: np.ndarray | None = None, *,
                 collision_free: bool = False, **kwargs) -> BatchIKResult:
        """Joint positions for each pose of the batched Pose `goals` (N poses), in one batch.

        Args:
            goals: a batched Pose (N,) in the base frame.
            link: any frame of the URDF (default `ee_link`).
            seed_q: (dof,) or (N, dof) configurations to start from [rad].
            collision_free: only configurations free of collisions with the world and the
                robot itself count as solutions (as in `ik`).
            **kwargs: as `IKSolver.solve_batch`.
        """
        if not isinstance(goals, Pose):
            raise InvalidInputError(f"goals must be a manip.Pose; got {type(goals).__name__}")
        link = self._link(link)
        if seed_q is not None:
            seed_q = self.kinematics.check_q(self._arm_q(seed_q, "seed_q"), "seed_q")
        if flag(collision_free, "collision_free"):
            kwargs.setdefault("validity_fn", self._validity().configs)
        return self.ik_solver.solve_batch(goals if goals.is_batch else Pose.stack([goals]), link, seed_q=seed_q,
                                          **kwargs)

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
        if g and a.shape[-1] == n + g:
            return a[..., :n]
        full = f" or ({n + g},): a full robot state, the gripper's joints {list(gripper.joints)} last" if g else ""
        head = f"{what}[:{n}]" if a.ndim == 1 else f"{what}[:, :{n}]"
        raise InvalidInputError(
            f"{what} must have shape ({n},) (the arm joints {self.joint_names}){full}; got {a.shape}. If its first "
            f"{n} values are the arm joints in this order, pass {head}."
        )

    def _link(self, link) -> str:
        """`link` checked as a frame name; None means `ee_link` (an empty or non-string name raises)."""
        if link is None:
            return self.ee_link
        self.kinematics.frame_id(link, "link")
        return link

    def _validity(self) -> Validity:
        """Collision questions against one snapshot of the world (taken now)."""
        v = self.validity
        return Validity(self.checker.snapshot(), v.kinematics, v.resolution, v.search_resolution)

    # ------------------------------------------------------------------ world
    @property
    def world(self) -> WorldConfig:
        """The planner's current obstacles (a copy)."""
        return self.checker.world

    def update_world(self, world: WorldConfig | dict) -> None:
        """Replace every obstacle with those of `world` (a WorldConfig or cuRobo-style dict)."""
        if isinstance(world, dict):
            world = WorldConfig.from_dict(world)
        if not isinstance(world, WorldConfig):
            raise InvalidInputError(f"world must be a WorldConfig or a dict; got {type(world).__name__}")
        self.checker.set_world(world)

    def add_obstacle(self, obstacle) -> None:
        """Add one obstacle (Cuboid, Sphere, Cylinder, Capsule or Mesh)."""
        self.checker.add_obstacle(obstacle)

    def remove_obstacle(self, name: str) -> None:
        """Remove the obstacle called `name` (UnknownNameError lists the names)."""
        self.checker.remove_obstacle(name)

    def update_obstacle_pose(self, name: str, pose: Pose | Sequence[float]) -> None:
        """Move the obstacle called `name` to `pose` (a Pose, [x, y, z, qw, qx, qy, qz], or a
        position [x, y, z] alone, which keeps the obstacle's rotation).

        `add_obstacle`, `remove_obstacle` and this are incremental (well under a millisecond
        with a thousand obstacles, `benchmarks/world_edits.py`); `update_world` rebuilds all.
        """
        self.checker.update_obstacle_pose(name, pose)

    def check_collision(self, q: np.ndarray | Sequence[float]) -> bool:
        """True when `q` (dof,) collides with the world, an attached object or itself."""
        return bool(self.checker.in_collision(self._one_q(q, "q")))

    def distance(self, q: np.ndarray | Sequence[float]) -> float:
        """Signed distance [m] of `q` (dof,) to the world and to itself (< 0: penetration)."""
        return float(self.checker.distance(self._one_q(q, "q")))

    def attach_object(self, name_or_shape, q: np.ndarray | Sequence[float] | None = None, link: str | None = None,
                      **kwargs):
        """Carry an obstacle (or a new shape) with `link` (default the end-effector).

        The named obstacle leaves the world and moves rigidly with the link from its pose at
        configuration `q` (default: the default configuration).
        """
        qq = self.default_joint_positions if q is None else self._one_q(q, "q")
        return self.checker.attach_object(name_or_shape, q=qq, link=self._link(link), **kwargs)

    def detach_object(self, q: np.ndarray | Sequence[float] | None = None, **kwargs):
        """Put attached objects back into the world at their pose at configuration `q`."""
        qq = self.default_joint_positions if q is None else self._one_q(q, "q")
        return self.checker.detach_object(qq, **kwargs)

    def _one_q(self, q, what: str) -> np.ndarray:
        q = self.kinematics.check_q(self._arm_q(q, what), what)
        if q.ndim != 1:
            raise InvalidInputError(f"{what} must have shape ({self.robot_dof},) (one configuration); got {q.shape}")
        return q

    def update_world_from_sim(self, world, robot, ignore: Sequence[str] = ()) -> WorldConfig:
        """Read every collision object of a `manip.sim` World into the planner's world.

        Objects are expressed in the robot's base frame. The robot itself and objects whose
        name or prim path starts with an entry of `ignore` are skipped. Attached objects
        stay attached. Returns the new WorldConfig.

        The ground plane (or table) the robot stands on stays an obstacle and needs no
        `ignore`: an obstacle wholly below the base frame's xy-plane (its top within 1 mm of
        z = 0) is not checked against the links fixed to the base (panda_link0), which no
        motion moves; every moving link is checked against it.

        Raises:
            InvalidInputError: called before the World's first `reset()`.
        """
        cfg = world_config_from_sim(world, robot, ignore)
        self.update_world(cfg)
        return cfg

    def update_world_from_depth(self, depth, intrinsics, camera_pose, *, name="camera", resolution=0.02, q=None,
                                max_range=3.0, unknown="free", bounds=None, self_margin=0.01):
        """Integrate a depth image into the occupancy obstacle `name` (`manip.perception.integrate`)."""
        return integrate_depth(self.checker, depth, intrinsics, camera_pose, q=q, name=name,
                               resolution=resolution, max_range=max_range, unknown=unknown, bounds=bounds, self_margin=self_margin)

    def update_world_from_pointcloud(self, points, origin=None, *, name="camera", resolution=0.02, q=None,
                                     max_range=3.0, unknown="free", bounds=None, self_margin=0.01):
        """Integrate a point cloud [m] (base frame) seen from `origin` into the map `name` (as above)."""
        return integrate_pointcloud(self.checker, points, origin, q=q, name=name, resolution=resolution,
                                    max_range=max_range, unknown=unknown, bounds=bounds, self_margin=self_margin)

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
        validity = self._validity()
        start = ctx.check_start(self._arm_q(start_q, "start_q"), self.kinematics, validity)
        goal = ctx.check_goal(self._arm_q(goal_q, "goal_q"), self.kinematics, validity)
        if ctx.failed:
            return ctx.result()
        ctx.check_sample_count(start, goal, self.limits)
        return plan_to_configs(ctx, validity, start, goal[None, :], limits=self.limits, clearance=self.clearance)

    def plan_pose(self, start_q, goal: Pose, link: str | None = None, *, linear: bool = False, **options) -> PlanResult:
        """Plan a motion that brings `link` (default `ee_link`) to the pose `goal`.

        Args:
            start_q: (dof,) start configuration [rad] (or a full robot state, see `plan_joints`).
            goal: a single Pose in the base frame.
            link: any frame of the URDF.
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
        validity = self._validity()
        start = ctx.check_start(self._arm_q(start_q, "start_q"), self.kinematics, validity)
        if ctx.failed:
            return ctx.result()
        t_ik = time.perf_counter()
        configs, owners, why = goal_configurations(self.ik_solver, ctx, validity, start, goals, link)
        ctx.add_time("ik", t_ik)
        if not len(configs):
            return ctx.fail(PlanStatus.IK_FAIL, why)
        # the goals ranked by the motion they allow (`planning.path.goals`), not by joint-space distance
        order = order_goals(start, configs, ctx.scaled_limits(self.limits))
        ctx.check_sample_count(start, configs[order[0]], self.limits)
        result = plan_to_configs(ctx, validity, start, configs[order], limits=self.limits,
                                 clearance=self.clearance)
        if result.success:
            reached = result.goal_q
            k = int(order[np.argmin(np.linalg.norm(configs[order] - reached, axis=1))])
            dp, dr = self.kinematics.fk(reached, link).distance(goals[owners[k]])
            result = replace(result, position_error=float(dp), rotation_error=float(dr), goal_index=owners[k])
        return result

    def plan_batch(self, start_qs, goals, link: str | None = None, **options) -> list[PlanResult]:
        """Plan several problems: `goals` is (N, dof) joint goals, a batched Pose or a list of Poses."""
        start_qs = np.atleast_2d(self.kinematics.check_q(self._arm_q(start_qs, "start_qs"), "start_qs"))
        if isinstance(goals, (list, tuple)) and goals and all(isinstance(g, Pose) for g in goals):
            goals = Pose.stack(list(goals))
        if isinstance(goals, Pose):
            goal_list = list(goals) if goals.is_batch else [goals]
        else:
            if isinstance(goals, (list, tuple)) and any(isinstance(g, Pose) for g in goals):
                raise InvalidInputError("goals must be all joint configurations or all Poses, not a mix")
            goal_list = list(np.atleast_2d(self.kinematics.check_q(self._arm_q(goals, "goals"), "goals")))
        if len(start_qs) == 1 and len(goal_list) > 1:
            start_qs = np.repeat(start_qs, len(goal_list), axis=0)
        if len(start_qs) != len(goal_list):
            raise InvalidInputError(f"plan_batch needs as many start_qs as goals; got {len(start_qs)} and {len(goal_list)}")
        PlanOptions().updated(options)  # a bad option fails before any planning
        out = []
        for s, g in zip(start_qs, goal_list):
            if isinstance(g, Pose):
                out.append(self.plan_pose(s, g, link, **options))
            else:
                out.append(self.plan_joints(s, g, **options))
        return out

    # ------------------------------------------------------------------ orchestration
    def _context(self, options: dict) -> PlanContext:
        t0 = time.perf_counter()
        base = self.defaults
        if self.velocity_scale != 1.0 or self.acceleration_scale != 1.0:
            base = replace(base, velocity_scale=self.velocity_scale, acceleration_scale=self.acceleration_scale)
        return PlanContext(base.updated(options), t0)

    def _plan_linear(self, start_q, goal: Pose, link: str, options: dict) -> PlanResult:
        """Straight-line motion of `link` from its current pose to `goal`."""
        ctx = self._context(options)
        validity = self._validity()
        start = ctx.check_start(start_q, self.kinematics, validity)
        if ctx.failed:
            return ctx.result()
        length = float(np.linalg.norm(goal.position - self.kinematics.fk(start, link).position))
        points = length / ctx.options.linear_step
        if points > MAX_LINEAR_POINTS:
            raise InvalidInputError(
                f"linear_step: a {length:.4g} m line at linear_step = {ctx.options.linear_step:.3g} m needs "
                f"{math.ceil(points)} IK points; at most MAX_LINEAR_POINTS = {MAX_LINEAR_POINTS} "
                f"(give linear_step >= {length / MAX_LINEAR_POINTS:.3g} m)"
            )
        t = time.perf_counter()
        path, why = linear_path(
            self.kinematics, self.ik_solver, start, goal, link, step=ctx.options.linear_step,
            valid_batch=validity.configs, motion_valid=validity.motion,
        )
        ctx.add_time("ik", t)
        if path is None:
            return ctx.fail(PlanStatus.LINEAR_PATH_FAIL, why)
        goal_q = path[-1].copy()
        ctx.check_sample_count(start, goal_q, self.limits)
        traj, why = time_and_validate(ctx, path, goal_q, limits=self.limits, validity=validity,
                                      deviation=LINEAR_DEVIATION, dense_deviation=LINEAR_SPLINE_DEVIATION)
        if traj is None:
            return ctx.fail(PlanStatus.TRAJOPT_FAIL, f"no valid timed trajectory: {why}", path=path, goal_q=goal_q)
        dp, dr = self.kinematics.fk(goal_q, link).distance(goal)
        result = ctx.succeed(traj, path, goal_q, 1, "linear")
        return replace(result, position_error=float(dp), rotation_error=float(dr))

    # ------------------------------------------------------------------ removed names
    def __getattr__(self, name: str):
        if name in TUTORIAL_NAMES:
            raise AttributeError(
                f"MotionGenerator.{name} moved to manip.TutorialMotionGen (deprecated here in 0.1, removed in 0.2): "
                f"wrap the generator, TutorialMotionGen(motion_gen=mg).{name}(...), or build the wrapper directly, "
                f"TutorialMotionGen('franka')"
            )
        raise AttributeError(f"'{type(self).__name__}' object has no attribute '{name}'")
