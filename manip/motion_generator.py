"""`MotionGenerator`: the public entry point for kinematics, collision checking and planning.

The pipeline of every plan (each stage timed in `PlanResult.timings`):

1. validate the start (`PlanContext.check_start`): joint limits (a start up to 1e-4 rad
   outside is accepted), self and world collision; failures return INVALID_START_* statuses;
2. goals: joint goals are checked (INVALID_GOAL); pose goals become several collision-free
   IK solutions (IK_FAIL when there is none);
3. path: the straight joint-space line when it is valid, else the coarse-to-fine
   RRT-Connect search towards all goal configurations at once (`planning.search`);
4. shortcut: batched random shortcutting, optionally clearance smoothing (`planning.optimize`);
5. timing: ruckig segments with blended corners (`manip.timing`);
6. validate: the returned samples are checked densely against the exact collision model
   (`planning.finish`). Only a trajectory that passes is returned with `success=True`; one
   that fails is planned again (MAX_ATTEMPTS);
7. trajectory optimisation (`planning.refine`, `planning.trajopt`): the valid trajectory of a
   searched path seeds a B-spline optimiser; its result replaces the seed only when it is
   faster and passes the same dense validation (`PlanResult.source == "trajopt"`).

The planners are handed a `planning.Validity` (collision and limit questions) and a
`PlanContext` (options, deadline, random generator, timings); this class only orchestrates.
"""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from manip.collision import CollisionChecker, WorldConfig
from manip.collision.clearance import ClearanceModel
from manip.errors import InvalidInputError
from manip.ik import BatchIKResult, IKResult, IKSolver
from manip.kinematics import Kinematics
from manip.planning.context import START_LIMIT_TOLERANCE, PlanContext
from manip.planning.finish import time_and_validate
from manip.planning.linear import linear_path
from manip.planning.optimize import smooth_path
from manip.planning.options import PlanOptions
from manip.planning.refine import refine, scaled_limits
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.search import search_path
from manip.planning.shortcut import shortcut
from manip.planning.validity import Validity
from manip.pose import Pose
from manip.robot_config import RobotConfig, load_robot_config
from manip.sim_bridge import world_config_from_sim
from manip.timing import TimingLimits
from manip.timing.bounds import rest_to_rest_time
from manip.validation import positive

logger = logging.getLogger(__name__)

__all__ = ["MotionGenerator", "START_LIMIT_TOLERANCE"]

#: Random IK starts tried for a pose goal when the first round finds no collision-free solution.
IK_RETRY_ATTEMPTS = 400
#: Plans tried when a path's timed trajectory fails the dense validation.
MAX_ATTEMPTS = 4
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

#: The Isaac Sim tutorial wrapper's names, which moved to `manip.TutorialMotionGen`.
TUTORIAL_NAMES = frozenset({
    "init_motion_gen", "motion_generate", "update_obstacle_from_world", "update_obstacle_from_isaac_sim",
    "convert_solution_to_actions", "convert_solution_to_isaac_sim_action", "ik_batch", "set_constraint",
    "reset_constraint", "wxyz_to_xyzw", "wxzy_to_xyzw", "xyzw_to_wxyz",
})


class MotionGenerator:
    """Kinematics, collision checking and motion planning for one robot.

    Args:
        robot: a robot name under `robots/` ("franka") or a path to a robot.yaml, or a RobotConfig.
        world: obstacles in the robot base frame (a WorldConfig or a cuRobo-style dict).
        padding: extra clearance [m] kept from the world (default: the robot config's).
        time_budget: default planning time budget [s] per call.
        interpolation_dt: default trajectory sample period [s] (1/60 s, the simulator's).
        resolution: collision-check resolution along motions [rad] (joint-space L-inf);
            every returned path and trajectory is checked at least this densely.
        search_resolution: coarser resolution of the path search's edge checks [rad]; the
            found path is re-checked (and repaired) at `resolution`.
        seed: default random seed of IK restarts and sampling-based planning.

    The Isaac Sim tutorial wrapper's names (`motion_generate`, ...) live on
    `manip.TutorialMotionGen`, which holds a MotionGenerator.
    """

    #: Set by `manip.compat` to wrap a MotionGenerator in the tutorial wrapper (deprecated names).
    _tutorial_factory: Callable | None = None

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
        self.config = robot if isinstance(robot, RobotConfig) else load_robot_config(robot)
        self.kinematics = Kinematics(self.config)
        self.checker = CollisionChecker(self.config, self.kinematics, None, padding=padding)
        self.validity = Validity(
            self.checker, self.kinematics, positive(resolution, "resolution", "rad"),
            positive(search_resolution, "search_resolution", "rad"),
        )
        self.clearance = ClearanceModel(self.checker)
        self.ik_solver = IKSolver(self.kinematics, seed=seed)
        self.timing_limits = TimingLimits.from_robot(self.config)
        self.defaults = PlanOptions(time_budget=time_budget, dt=interpolation_dt, seed=seed)
        self.velocity_scale = 1.0
        self.acceleration_scale = 1.0
        if world is not None:
            self.update_world(world)

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
            link: any frame of the URDF.
        """
        return self.kinematics.fk(q, link or self.ee_link)

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
        the robot itself count as solutions. Other keyword arguments go to `IKSolver.solve`.
        A batched Pose is deprecated here: use `batch_ik`.
        """
        if not isinstance(goal, Pose):
            raise InvalidInputError(f"goal must be a manip.Pose; got {type(goal).__name__}")
        if goal.is_batch:
            warnings.warn("MotionGenerator.ik with a batched Pose is deprecated: use batch_ik", DeprecationWarning,
                          stacklevel=2)
            return self.batch_ik(goal, link, seed_q, **kwargs)  # type: ignore[return-value]
        link = link or self.ee_link
        self.kinematics.frame_id(link)
        if seed_q is not None:
            seed_q = self.kinematics.check_q(seed_q, "seed_q")
        if collision_free:
            kwargs.setdefault("validity_fn", self.validity.configs)
        return self.ik_solver.solve(goal, link, seed_q=seed_q, **kwargs)

    def batch_ik(self, goals: Pose, link: str | None = None, seed_q: np.ndarray | None = None, **kwargs) -> BatchIKResult:
        """Joint positions for each pose of the batched Pose `goals` (N poses), in one batch.

        Args:
            goals: a batched Pose (N,) in the base frame.
            link: any frame of the URDF (default `ee_link`).
            seed_q: (dof,) or (N, dof) configurations to start from [rad].
            **kwargs: as `IKSolver.solve_batch`.
        """
        if not isinstance(goals, Pose):
            raise InvalidInputError(f"goals must be a manip.Pose; got {type(goals).__name__}")
        link = link or self.ee_link
        self.kinematics.frame_id(link)
        if seed_q is not None:
            seed_q = self.kinematics.check_q(seed_q, "seed_q")
        return self.ik_solver.solve_batch(goals if goals.is_batch else Pose.stack([goals]), link, seed_q=seed_q,
                                          **kwargs)

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

    def check_collision(self, q: np.ndarray | Sequence[float]) -> bool:
        """True when `q` (dof,) collides with the world, an attached object or itself."""
        return bool(self.checker.in_collision(self.kinematics.check_q(q)))

    def distance(self, q: np.ndarray | Sequence[float]) -> float:
        """Signed distance [m] of `q` (dof,) to the world and to itself (< 0: penetration)."""
        return float(self.checker.distance(self.kinematics.check_q(q)))

    def attach_object(self, name_or_shape, q: np.ndarray | Sequence[float] | None = None, link: str | None = None,
                      **kwargs):
        """Carry an obstacle (or a new shape) with `link` (default the end-effector).

        The named obstacle leaves the world and moves rigidly with the link from its pose at
        configuration `q` (default: the default configuration).
        """
        qq = self.default_joint_positions if q is None else self.kinematics.check_q(q)
        return self.checker.attach_object(name_or_shape, q=qq, link=link or self.ee_link, **kwargs)

    def detach_object(self, q: np.ndarray | Sequence[float] | None = None, **kwargs):
        """Put attached objects back into the world at their pose at configuration `q`."""
        qq = self.default_joint_positions if q is None else self.kinematics.check_q(q)
        return self.checker.detach_object(qq, **kwargs)

    def update_world_from_sim(self, world, robot, ignore: Sequence[str] = ()) -> WorldConfig:
        """Read every collision object of a `manip.sim` World into the planner's world.

        Objects are expressed in the robot's base frame. The robot itself and objects whose
        name or prim path starts with an entry of `ignore` are skipped. Attached objects
        stay attached. Returns the new WorldConfig.
        """
        cfg = world_config_from_sim(world, robot, ignore)
        self.update_world(cfg)
        return cfg

    # ------------------------------------------------------------------ planning
    def plan_joints(self, start_q, goal_q, **options) -> PlanResult:
        """Plan a collision-free, time-parameterised motion from `start_q` to `goal_q`.

        Args:
            start_q: (dof,) start configuration [rad] (at rest).
            goal_q: (dof,) goal configuration [rad].
            **options: any field of `manip.planning.PlanOptions` (`time_budget` [s], `seed`,
                `dt` [s], `velocity_scale`, `acceleration_scale`, `duration` [s],
                `optimize_clearance`, `trajopt`, `smoothness`, ...); unknown names raise
                InvalidInputError listing the valid ones.
        """
        ctx = self._context(options)
        start = ctx.check_start(start_q, self.kinematics, self.validity)
        goal = self.kinematics.check_q(goal_q, "goal_q")
        if goal.ndim != 1:
            raise InvalidInputError(f"goal_q must have shape ({self.robot_dof},); got {goal.shape}")
        if ctx.failed:
            return ctx.result()
        problem = self.validity.goal_problem(goal)
        if problem:
            return ctx.fail(PlanStatus.INVALID_GOAL, problem)
        return self._plan_to_configs(ctx, start, goal[None, :])

    def plan_pose(self, start_q, goal: Pose, link: str | None = None, *, linear: bool = False, **options) -> PlanResult:
        """Plan a motion that brings `link` (default `ee_link`) to the pose `goal`.

        Args:
            start_q: (dof,) start configuration [rad].
            goal: a single Pose in the base frame.
            link: any frame of the URDF.
            linear: move the link along the straight line from its start pose to the goal,
                interpolating the orientation (keep it by giving the start orientation).
            **options: as `plan_joints`.
        """
        if not isinstance(goal, Pose) or goal.is_batch:
            raise InvalidInputError("goal must be a single manip.Pose (use plan_goalset for several)")
        if linear:
            return self._plan_linear(start_q, goal, link or self.ee_link, options)
        return self.plan_goalset(start_q, Pose.stack([goal]), link, **options)

    def plan_goalset(self, start_q, goals: Pose, link: str | None = None, **options) -> PlanResult:
        """Plan to whichever of several poses (a batched Pose) is best reached.

        Collision-free IK solutions of every pose are planned to at once, the ones reachable
        fastest (by the time-optimal rest-to-rest duration from the start) first; the
        result's `goal_index` says which pose was reached.
        """
        ctx = self._context(options)
        link = link or self.ee_link
        self.kinematics.frame_id(link)
        if not isinstance(goals, Pose):
            raise InvalidInputError(f"goals must be a manip.Pose; got {type(goals).__name__}")
        if not goals.is_batch:
            goals = Pose.stack([goals])
        start = ctx.check_start(start_q, self.kinematics, self.validity)
        if ctx.failed:
            return ctx.result()
        t_ik = time.perf_counter()
        configs, owners = self._goal_configs(ctx, start, goals, link)
        ctx.add_time("ik", t_ik)
        if not len(configs):
            return ctx.fail(PlanStatus.IK_FAIL, "no collision-free IK solution within the joint limits")
        # the goal reached fastest first: the time-optimal rest-to-rest duration (a lower bound
        # of any motion to it), not the joint-space distance
        vmax, amax, jmax = scaled_limits(self.timing_limits, ctx)
        bounds = [rest_to_rest_time(start, q, vmax, amax, jmax) for q in configs]
        order = np.argsort(bounds, kind="stable")
        result = self._plan_to_configs(ctx, start, configs[order])
        if result.success:
            reached = result.goal_q
            k = int(order[np.argmin(np.linalg.norm(configs[order] - reached, axis=1))])
            dp, dr = self.kinematics.fk(reached, link).distance(goals[owners[k]])
            result = replace(result, position_error=float(dp), rotation_error=float(dr), goal_index=owners[k])
        return result

    def plan_batch(self, start_qs, goals, link: str | None = None, **options) -> list[PlanResult]:
        """Plan several problems: `goals` is (N, dof) joint goals or a batched Pose."""
        start_qs = np.atleast_2d(self.kinematics.check_q(start_qs, "start_qs"))
        if isinstance(goals, Pose):
            goal_list = list(goals) if goals.is_batch else [goals]
        else:
            goal_list = list(np.atleast_2d(self.kinematics.check_q(goals, "goals")))
        if len(start_qs) == 1 and len(goal_list) > 1:
            start_qs = np.repeat(start_qs, len(goal_list), axis=0)
        if len(start_qs) != len(goal_list):
            raise InvalidInputError(f"plan_batch needs as many starts as goals; got {len(start_qs)} and {len(goal_list)}")
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

    def _goal_configs(self, ctx: PlanContext, start: np.ndarray, goals: Pose, link: str) -> tuple[np.ndarray, list[int]]:
        """(M, dof) collision-free IK solutions of the poses and, for each, its pose index."""
        configs, owners = [], []
        for i, g in enumerate(goals):
            sols = self.ik_solver.solve_many(
                g, link, n=ctx.options.ik_solutions, seed_q=start, validity_fn=self.validity.configs,
            )
            if len(sols) == 0:
                # tight goals (a hand between obstacles, a joint on its limit) have few
                # collision-free solutions: search many more random starts for one
                sols = self.ik_solver.solve_many(
                    g, link, n=2, seed_q=start, validity_fn=self.validity.configs, attempts=IK_RETRY_ATTEMPTS,
                    seed=int(ctx.rng.integers(2**31)),
                )
            for q in sols:
                configs.append(q)
                owners.append(i)
        return np.asarray(configs).reshape(-1, self.robot_dof), owners

    def _plan_to_configs(self, ctx: PlanContext, start: np.ndarray, goals: np.ndarray) -> PlanResult:
        """Path, shortcutting, timing and validation to the best reachable of `goals` (G, dof).

        A path whose timed trajectory fails the dense validation (a graze between the
        configurations the search checked) is planned again, until the budget runs out.
        """
        result = None
        for attempt in range(1, MAX_ATTEMPTS + 1):
            result = self._plan_once(ctx, start, goals, attempt)
            if result.success or result.status is not PlanStatus.TRAJOPT_FAIL or ctx.time_left < 0:
                break
            logger.info("attempt %d: %s; planning again", attempt, result.message)
        return result

    def _plan_once(self, ctx: PlanContext, start: np.ndarray, goals: np.ndarray, attempt: int) -> PlanResult:
        t = time.perf_counter()
        path, source, iterations = None, "shortcut", 0
        if attempt == 1:
            for g in goals[:3]:
                if self.validity.motion(start, g):
                    path, source = np.stack([start, g]), "straight_line"
                    break
        if path is None:
            path, iterations = search_path(start, goals, self.validity, ctx.rng, ctx.deadline)
        ctx.add_time("plan", t)
        if path is None:
            status = PlanStatus.TIMEOUT if ctx.time_left < 0 else PlanStatus.PLAN_FAIL
            return ctx.fail(status, f"no collision-free path found ({iterations} iterations)", attempts=attempt)
        goal_q = path[-1].copy()
        t = time.perf_counter()
        if len(path) > 2:
            path = shortcut(path, self.validity.segments, ctx.rng, ctx.deadline, screen=self.validity.screen)
            if ctx.options.optimize_clearance:
                path = smooth_path(path, self.checker, self.validity.motion, ctx.deadline)
        ctx.add_time("optimize", t)
        traj, why = time_and_validate(ctx, path, goal_q, self.timing_limits, self.validity)
        if traj is None:
            return ctx.fail(PlanStatus.TRAJOPT_FAIL, f"no valid timed trajectory: {why}", path=path, goal_q=goal_q,
                            attempts=attempt)
        if ctx.options.trajopt and source == "shortcut":
            t = time.perf_counter()
            better = refine(ctx, traj, self.timing_limits, self.validity, self.clearance, self.checker.padding)
            ctx.add_time("trajopt", t)
            if better is not None:
                traj, source = better, "trajopt"
        return ctx.succeed(traj, path, goal_q, attempt, source)

    def _plan_linear(self, start_q, goal: Pose, link: str, options: dict) -> PlanResult:
        """Straight-line motion of `link` from its current pose to `goal`."""
        ctx = self._context(options)
        self.kinematics.frame_id(link)
        start = ctx.check_start(start_q, self.kinematics, self.validity)
        if ctx.failed:
            return ctx.result()
        t = time.perf_counter()
        path, why = linear_path(
            self.kinematics, self.ik_solver, start, goal, link, step=ctx.options.linear_step,
            valid_batch=self.validity.configs, motion_valid=self.validity.motion,
        )
        ctx.add_time("ik", t)
        if path is None:
            return ctx.fail(PlanStatus.LINEAR_PATH_FAIL, why)
        goal_q = path[-1].copy()
        traj, why = time_and_validate(ctx, path, goal_q, self.timing_limits, self.validity,
                                      deviation=LINEAR_DEVIATION, dense_deviation=LINEAR_SPLINE_DEVIATION)
        if traj is None:
            return ctx.fail(PlanStatus.TRAJOPT_FAIL, f"no valid timed trajectory: {why}", path=path, goal_q=goal_q)
        dp, dr = self.kinematics.fk(goal_q, link).distance(goal)
        result = ctx.succeed(traj, path, goal_q, 1, "linear")
        return replace(result, position_error=float(dp), rotation_error=float(dr))

    # ------------------------------------------------------------------ deprecated names
    def __getattr__(self, name: str):
        if name in TUTORIAL_NAMES:
            factory = type(self)._tutorial_factory
            if factory is None:
                raise AttributeError(f"MotionGenerator.{name} moved to manip.TutorialMotionGen")
            warnings.warn(
                f"MotionGenerator.{name} is deprecated: use manip.TutorialMotionGen (it holds a MotionGenerator)",
                DeprecationWarning, stacklevel=2,
            )
            if "_tutorial_view" not in self.__dict__:
                self.__dict__["_tutorial_view"] = factory(self)
            return getattr(self.__dict__["_tutorial_view"], name)
        raise AttributeError(f"'{type(self).__name__}' object has no attribute '{name}'")
