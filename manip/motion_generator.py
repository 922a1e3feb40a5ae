"""`MotionGenerator`: the public entry point for kinematics, collision checking and planning.

The pipeline of every plan (each stage timed in `PlanResult.timings`):

1. validate the start: joint limits (a start up to 1e-4 rad outside is accepted), self and
   world collision; failures return INVALID_START_* statuses;
2. goals: joint goals are checked (INVALID_GOAL); pose goals become several collision-free
   IK solutions (IK_FAIL when there is none);
3. path: the straight joint-space line when it is valid, else RRT-Connect towards all goal
   configurations at once, its edges checked at the coarse `search_resolution`; the path is
   then re-checked at the fine `resolution` and failing edges are searched again finely;
4. optimise: batched random shortcutting, optionally a clearance-aware smoothing of the
   waypoints (`optimize_clearance=True`); corners are then blended by the timing stage;
5. timing: ruckig state-to-state segments under velocity, acceleration and jerk limits
   (linear motions: one time scaling along a spline through their IK points);
6. validate: the returned samples are checked densely (their linear interpolation, with
   consecutive checked configurations at most `resolution` rad apart) against the exact
   collision model; limits were checked by the timing stage. Only a trajectory that passes
   is returned with `success=True`; one that fails is planned again (MAX_ATTEMPTS).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence

import numpy as np

from manip.collision import CollisionChecker, WorldConfig
from manip.errors import InvalidInputError
from manip.ik import IKResult, IKSolver
from manip.kinematics import Kinematics
from manip.planning.optimize import smooth_path
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.rrt_connect import rrt_connect
from manip.planning.shortcut import shortcut
from manip.pose import Pose
from manip.robot_config import RobotConfig, load_robot_config
from manip.timing import time_parameterize, time_parameterize_dense
from manip.trajectory import Trajectory
from manip.tutorial_api import TutorialAPI

logger = logging.getLogger(__name__)

#: A start this far outside a joint limit [rad] is accepted (and kept as given): simulated
#: joints settle a few microradians past a limit the previous motion ended on.
START_LIMIT_TOLERANCE = 1e-4
#: Position-limit tolerance [rad] of trajectories whose start is inside the limits.
LIMIT_TOLERANCE = 1e-6
#: Random IK starts tried for a pose goal when the first round finds no collision-free solution.
IK_RETRY_SEEDS = 400
#: An advancing tree stops this many check steps before its first contact.
ADVANCE_BACKOFF_STEPS = 3
#: Edges of a coarse search path replaced by fine searches before giving up on the path.
MAX_REPAIRS = 6
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


class MotionGenerator(TutorialAPI):
    """Kinematics, collision checking and motion planning for one robot.

    Args:
        robot: a robot name under `robots/` ("franka") or a path to a robot.yaml.
        world: obstacles in the robot base frame (a WorldConfig or a cuRobo-style dict).
        padding: extra clearance [m] kept from the world (default: the robot config's).
        time_budget: default planning time budget [s] per call.
        interpolation_dt: default trajectory sample period [s] (1/60 s, the simulator's).
        resolution: collision-check resolution along motions [rad] (joint-space L-inf);
            every returned path and trajectory is checked at least this densely.
        search_resolution: coarser resolution of the path search's edge checks [rad]; the
            found path is re-checked (and repaired) at `resolution`.
        seed: default random seed of IK restarts and sampling-based planning.

    The Isaac Sim tutorial wrapper's names (`init_motion_gen`, `motion_generate`, ...) come
    from `TutorialAPI`; `TutorialMotionGen` also gives `fk` / `ik` the wrapper's lists.
    """

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
        self._ik = IKSolver(self.kinematics, seed=seed)
        self.time_budget = _positive(time_budget, "time_budget")
        self.interpolation_dt = _positive(interpolation_dt, "interpolation_dt")
        self.resolution = _positive(resolution, "resolution")
        self.search_resolution = _positive(search_resolution, "search_resolution")
        self.seed = int(seed)
        self.velocity_scale = 1.0
        self.acceleration_scale = 1.0
        if world is not None:
            self.update_world(world)

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
        """Joint positions placing `link` (default `ee_link`) at `goal`.

        A single Pose gives an IKResult; a batched Pose gives the batch result of
        `IKSolver.solve_batch`. With `collision_free=True` only configurations free of
        collisions with the world and the robot itself count as solutions (single goals).
        Other keyword arguments go to the IKSolver.
        """
        if not isinstance(goal, Pose):
            raise InvalidInputError(f"goal must be a manip.Pose; got {type(goal).__name__}")
        link = link or self.ee_link
        self.kinematics.frame_id(link)
        if seed_q is not None:
            seed_q = self.kinematics.check_q(seed_q, "seed_q")
        if goal.is_batch:
            return self._ik.solve_batch(goal, link, seed_q=seed_q, **kwargs)
        if collision_free:
            kwargs.setdefault("validity_fn", self._valid_batch)
        return self._ik.solve(goal, link, seed_q=seed_q, **kwargs)

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

    def attach_object(self, name_or_shape, q: np.ndarray | Sequence[float] | None = None, link: str | None = None, **kwargs):
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
        from manip.sim_bridge import world_config_from_sim  # duck-typed reader, no sim import

        cfg = world_config_from_sim(world, robot, ignore)
        self.update_world(cfg)
        return cfg

    # ------------------------------------------------------------------ planning
    def plan_joints(self, start_q, goal_q, **options) -> PlanResult:
        """Plan a collision-free, time-parameterised motion from `start_q` to `goal_q`.

        Args:
            start_q: (dof,) start configuration [rad] (at rest).
            goal_q: (dof,) goal configuration [rad].
            **options: `time_budget` [s], `seed`, `dt` [s] (sample period),
                `velocity_scale` and `acceleration_scale` in (0, 1] (the latter also scales
                jerk), `duration` [s] (stretch the motion to this length; fails with
                TRAJOPT_FAIL if it is shorter than feasible), `optimize_clearance` (push
                the path's waypoints away from obstacles after shortcutting; costs tens of
                ms in cluttered scenes, off by default).
        """
        t0 = time.perf_counter()
        ctx = _Context(self, options, t0)
        start = ctx.start(start_q)
        goal = self.kinematics.check_q(goal_q, "goal_q")
        if goal.ndim != 1:
            raise InvalidInputError(f"goal_q must have shape ({self.robot_dof},); got {goal.shape}")
        if ctx.failed:
            return ctx.result()
        problem = self._goal_problem(goal)
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

        Collision-free IK solutions of every pose are planned to at once; the result's
        `goal_index` says which pose was reached.
        """
        t0 = time.perf_counter()
        ctx = _Context(self, options, t0)
        link = link or self.ee_link
        self.kinematics.frame_id(link)
        if not isinstance(goals, Pose):
            raise InvalidInputError(f"goals must be a manip.Pose; got {type(goals).__name__}")
        if not goals.is_batch:
            goals = Pose.stack([goals])
        start = ctx.start(start_q)
        if ctx.failed:
            return ctx.result()
        t_ik = time.perf_counter()
        configs, owners = [], []
        for i, g in enumerate(goals):
            sols = self._ik.solve_many(
                g, link, n=options.get("ik_solutions", 6), seed_q=start, validity_fn=self._valid_batch,
            )
            if len(sols) == 0:
                # tight goals (a hand between obstacles, a joint on its limit) have few
                # collision-free solutions: search many more random starts for one
                sols = self._ik.solve_many(
                    g, link, n=2, seed_q=start, validity_fn=self._valid_batch, num_seeds=IK_RETRY_SEEDS,
                    seed=int(ctx.rng.integers(2**31)),
                )
            for q in sols:
                configs.append(q)
                owners.append(i)
        ctx.timings["ik"] = time.perf_counter() - t_ik
        if not configs:
            return ctx.fail(PlanStatus.IK_FAIL, "no collision-free IK solution within the joint limits")
        configs = np.asarray(configs)
        order = np.argsort(np.linalg.norm(configs - start, axis=1), kind="stable")
        result = self._plan_to_configs(ctx, start, configs[order])
        if result.success:
            reached = result.goal_q
            k = int(order[np.argmin(np.linalg.norm(configs[order] - reached, axis=1))])
            achieved = self.kinematics.fk(reached, link)
            dp, dr = achieved.distance(goals[owners[k]])
            result = _replace(result, position_error=float(dp), rotation_error=float(dr), goal_index=owners[k])
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

    # ------------------------------------------------------------------ internals
    def _valid_batch(self, Q: np.ndarray) -> np.ndarray:
        return ~self.checker.in_collision_batch(np.atleast_2d(Q))

    def _motion_valid(self, q0: np.ndarray, q1: np.ndarray, resolution: float | None = None) -> bool:
        return bool(self.checker.motion_valid(q0, q1, resolution=resolution or self.resolution))

    def _segments_valid(self, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        """(M,) validity of segments at the fine resolution, screened at the search one."""
        ok = self._segments_screen(Q0, Q1)
        if ok.any() and self.search_resolution > self.resolution:
            ok[ok] = self.checker.motion_valid_batch(Q0[ok], Q1[ok], resolution=self.resolution)
        return ok

    def _segments_screen(self, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        """(M,) validity at the search resolution (a necessary condition, cheaper)."""
        return self.checker.motion_valid_batch(Q0, Q1, resolution=max(self.resolution, self.search_resolution))

    def _limit_excess(self, q: np.ndarray) -> float:
        """How far [rad] `q` lies outside the joint limits (0 inside)."""
        return float(max(0.0, np.max(self.kinematics.lower - q), np.max(q - self.kinematics.upper)))

    def _advance(self, q0: np.ndarray, q1: np.ndarray, resolution: float | None = None) -> np.ndarray | None:
        """The farthest configuration on q0 -> q1 reachable without collision, kept a few
        check steps short of the first contact (None if there is no room to move)."""
        resolution = resolution or self.resolution
        t = self.checker.first_collision(q0, q1, resolution=resolution)
        if t is None:
            return q1.copy()
        steps = self.checker.segment_steps(q0, q1, resolution)
        t_stop = t - ADVANCE_BACKOFF_STEPS / steps
        if t_stop <= 0:
            return None
        return q0 + t_stop * (q1 - q0)

    def _goal_problem(self, goal: np.ndarray) -> str:
        bad = self.kinematics.limit_violations(goal)
        if bad:
            return "goal outside the joint limits: " + "; ".join(bad)
        if self.checker.in_collision(goal):
            return "goal in collision: " + _describe_contacts(self.checker.collision_report(goal))
        return ""

    def _plan_to_configs(self, ctx: "_Context", start: np.ndarray, goals: np.ndarray) -> PlanResult:
        """Path, optimisation, timing and validation to the best reachable of `goals` (G, dof).

        A path whose timed trajectory fails the dense validation (a graze between the
        configurations the search checked) is planned again, until the budget runs out.
        """
        result = None
        for attempt in range(1, MAX_ATTEMPTS + 1):
            result = self._plan_once(ctx, start, goals, attempt)
            if result.success or result.status is not PlanStatus.TRAJOPT_FAIL or time.perf_counter() > ctx.deadline:
                break
            logger.info("attempt %d: %s; planning again", attempt, result.message)
        return result

    def _plan_once(self, ctx: "_Context", start: np.ndarray, goals: np.ndarray, attempt: int) -> PlanResult:
        t = time.perf_counter()
        path = None
        if attempt == 1:
            for g in goals[:3]:
                if self._motion_valid(start, g):
                    path = np.stack([start, g])
                    break
        iterations = 0
        if path is None:
            path, iterations = self._search(ctx, start, goals)
        ctx.timings["plan"] = ctx.timings.get("plan", 0.0) + time.perf_counter() - t
        if path is None:
            status = PlanStatus.TIMEOUT if time.perf_counter() > ctx.deadline else PlanStatus.PLAN_FAIL
            return ctx.fail(status, f"no collision-free path found ({iterations} iterations)", attempts=attempt)
        goal_q = path[-1].copy()
        t = time.perf_counter()
        if len(path) > 2:
            path = shortcut(path, self._segments_valid, ctx.rng, ctx.deadline, screen=self._segments_screen)
            if ctx.optimize_clearance:
                path = smooth_path(path, self.checker, self._motion_valid, ctx.deadline)
        ctx.timings["optimize"] = ctx.timings.get("optimize", 0.0) + time.perf_counter() - t
        return self._time_and_validate(ctx, path, goal_q, attempt)

    def _search(self, ctx: "_Context", start: np.ndarray, goals: np.ndarray) -> tuple[np.ndarray | None, int]:
        """RRT-Connect with coarse edge checks, then every edge re-checked at the fine
        resolution; an edge that fails is replaced by a fine-resolution search between its
        endpoints (coarse-to-fine: most of the search space is far from obstacles)."""
        coarse = max(self.resolution, self.search_resolution)
        path, iterations = rrt_connect(
            start, goals, self.kinematics.lower, self.kinematics.upper,
            lambda a, b: self._motion_valid(a, b, coarse), ctx.rng, ctx.deadline,
            advance=lambda a, b: self._advance(a, b, coarse),
        )
        for _ in range(MAX_REPAIRS):
            if path is None or coarse == self.resolution:
                break
            ok = self._segments_valid(path[:-1], path[1:])
            if ok.all():
                break
            s = int(np.argmin(ok))
            sub, more = rrt_connect(
                path[s], path[s + 1][None], self.kinematics.lower, self.kinematics.upper, self._motion_valid,
                ctx.rng, ctx.deadline, advance=self._advance,
            )
            iterations += more
            path = None if sub is None else np.concatenate([path[:s], sub, path[s + 2 :]])
        else:
            if path is not None and not self._segments_valid(path[:-1], path[1:]).all():
                path = None
        return path, iterations

    def _time_and_validate(
        self, ctx: "_Context", path: np.ndarray, goal_q: np.ndarray, attempts: int, deviation: float = 0.05,
        dense_deviation: float | None = None,
    ) -> PlanResult:
        """Time the path (corners blended within `deviation` rad, else stopping at each) and validate.

        With `dense_deviation` given (a dense path sampled from a smooth curve, e.g. a
        linear motion), one smooth motion along a spline through its points, within
        `dense_deviation` rad of the path, is tried first (`time_parameterize_dense`).
        """
        t = time.perf_counter()
        validate_before = ctx.timings.get("validate", 0.0)
        traj = None
        reason = ""
        for mode in (("along_path",) if dense_deviation is not None else ()) + ("blend", "exact"):
            timing_fn = time_parameterize_dense if mode == "along_path" else time_parameterize
            mode_options = {} if mode == "along_path" else {"mode": mode}
            timed = timing_fn(
                path,
                self.config.velocity_limits,
                self.config.acceleration_limits,
                self.config.jerk_limits,
                dt=ctx.dt,
                joint_names=self.joint_names,
                lower_limits=self.kinematics.lower,
                upper_limits=self.kinematics.upper,
                position_tolerance=max(LIMIT_TOLERANCE, self._limit_excess(path[0])),
                deviation_tolerance=dense_deviation if mode == "along_path" else deviation,
                velocity_scale=ctx.velocity_scale,
                acceleration_scale=ctx.acceleration_scale,
                jerk_scale=ctx.acceleration_scale,
                duration=ctx.duration,
                **mode_options,
            )
            if not timed.success:
                reason = timed.message
                continue
            tv = time.perf_counter()
            ok, why = self._validate(timed.trajectory, path[0], goal_q)
            ctx.timings["validate"] = ctx.timings.get("validate", 0.0) + time.perf_counter() - tv
            if ok:
                traj = timed.trajectory
                break
            reason = why
        ctx.timings["timing"] = ctx.timings.get("timing", 0.0) + time.perf_counter() - t - (
            ctx.timings.get("validate", 0.0) - validate_before
        )
        if traj is None:
            return ctx.fail(
                PlanStatus.TRAJOPT_FAIL, f"no valid timed trajectory: {reason}", path=path, goal_q=goal_q, attempts=attempts
            )
        ctx.timings["total"] = time.perf_counter() - ctx.t0
        return PlanResult(
            success=True, status=PlanStatus.SUCCESS, trajectory=traj, path=path, goal_q=goal_q,
            timings=dict(ctx.timings), position_error=0.0, rotation_error=0.0, attempts=attempts,
            message="",
        )

    def _validate(self, traj: Trajectory, start: np.ndarray, goal: np.ndarray) -> tuple[bool, str]:
        """Dense collision check of the trajectory as returned, and its endpoints.

        The returned samples are what a user executes and what a verifier checks: their
        linear interpolation is checked so that consecutive checked configurations are at
        most `resolution` apart (the true motion between samples strays from that line by
        less than max|acceleration| dt^2 / 8, e.g. 0.3 mrad at 1/60 s). Limits were checked
        by the timing stage on the exact profile and on the samples.
        """
        if np.max(np.abs(traj.positions[0] - start)) > 1e-9 or np.max(np.abs(traj.positions[-1] - goal)) > 1e-6:
            return False, "trajectory does not start at the start or end at the goal"
        check = self.checker.path_valid(traj.positions, resolution=self.resolution)
        if not check.valid:
            return False, f"timed trajectory collides near t = {traj.times[check.first_invalid_segment]:.3f} s"
        return True, ""

    def _plan_linear(self, start_q, goal: Pose, link: str, options: dict) -> PlanResult:
        """Straight-line motion of `link` from its current pose to `goal`."""
        t0 = time.perf_counter()
        ctx = _Context(self, options, t0)
        self.kinematics.frame_id(link)
        start = ctx.start(start_q)
        if ctx.failed:
            return ctx.result()
        t = time.perf_counter()
        from manip.planning.linear import linear_path  # local: only linear motions need it

        path, why = linear_path(
            self.kinematics, self._ik, start, goal, link,
            step=options.get("linear_step", 0.005), valid_batch=self._valid_batch, motion_valid=self._motion_valid,
        )
        ctx.timings["ik"] = time.perf_counter() - t
        if path is None:
            return ctx.fail(PlanStatus.LINEAR_PATH_FAIL, why)
        result = self._time_and_validate(ctx, path, path[-1].copy(), 1, deviation=LINEAR_DEVIATION,
                                         dense_deviation=LINEAR_SPLINE_DEVIATION)
        if result.success:
            dp, dr = self.kinematics.fk(result.goal_q, link).distance(goal)
            result = _replace(result, position_error=float(dp), rotation_error=float(dr))
        return result


class TutorialMotionGen(MotionGenerator):
    """A MotionGenerator whose `fk` / `ik` follow the Isaac Sim tutorial wrapper.

    `fk(joint_angles)` -> [x, y, z, qx, qy, qz, qw] of `ee_link`; `ik(pose_xyzw,
    seed_joint_angles=None)` -> collision-free joint angles (a list) or None. Every other
    name is MotionGenerator's, including the wrapper's names from `TutorialAPI`.
    """

    def fk(self, joint_angles, link: str | None = None) -> list[float]:  # type: ignore[override]
        """[x, y, z, qx, qy, qz, qw] of `link` (default `ee_link`) at the joint angles (dof,)."""
        q = self.kinematics.check_q(joint_angles, "joint_angles")
        return self.kinematics.fk(q, link or self.ee_link).to_xyz_xyzw().tolist()

    def ik(self, pose_xyzw, seed_joint_angles=None) -> list[float] | None:  # type: ignore[override]
        """Collision-free joint angles placing `ee_link` at [x, y, z, qx, qy, qz, qw], or None."""
        seed = self.default_joint_positions if seed_joint_angles is None else self.kinematics.check_q(seed_joint_angles)
        res = self._ik.solve(Pose.from_xyz_xyzw(pose_xyzw), self.ee_link, seed_q=seed, validity_fn=self._valid_batch)
        return res.q.tolist() if res.success else None


class _Context:
    """Per-call planning state: options, deadline, random generator, timings, failure."""

    def __init__(self, mg: MotionGenerator, options: dict, t0: float):
        known = {
            "time_budget", "seed", "dt", "velocity_scale", "acceleration_scale", "duration", "ik_solutions", "linear_step",
            "optimize_clearance",
        }
        unknown = set(options) - known
        if unknown:
            raise InvalidInputError(f"unknown planning option(s) {sorted(unknown)}; valid: {sorted(known)}")
        self.mg = mg
        self.t0 = t0
        self.deadline = t0 + _positive(options.get("time_budget", mg.time_budget), "time_budget")
        self.rng = np.random.default_rng(options.get("seed", mg.seed))
        self.dt = _positive(options.get("dt", mg.interpolation_dt), "dt")
        self.velocity_scale = _fraction(options.get("velocity_scale", mg.velocity_scale), "velocity_scale")
        self.acceleration_scale = _fraction(options.get("acceleration_scale", mg.acceleration_scale), "acceleration_scale")
        self.duration = None if options.get("duration") is None else _positive(options["duration"], "duration")
        self.optimize_clearance = bool(options.get("optimize_clearance", False))
        self.timings: dict[str, float] = {}
        self._failure: PlanResult | None = None

    @property
    def failed(self) -> bool:
        return self._failure is not None

    def result(self) -> PlanResult:
        assert self._failure is not None
        return self._failure

    def start(self, start_q) -> np.ndarray:
        """Validated start; records an INVALID_START_* failure instead of raising."""
        mg = self.mg
        q = mg.kinematics.check_q(start_q, "start_q")
        if q.ndim != 1:
            raise InvalidInputError(f"start_q must have shape ({mg.robot_dof},); got {q.shape}")
        bad = mg.kinematics.limit_violations(q, START_LIMIT_TOLERANCE)
        if bad:
            self.fail(PlanStatus.INVALID_START_JOINT_LIMITS, "start outside the joint limits: " + "; ".join(bad))
            return q
        if mg.checker.in_collision(q):
            report = mg.checker.collision_report(q)
            status = (
                PlanStatus.INVALID_START_WORLD_COLLISION if report.world_collision else PlanStatus.INVALID_START_SELF_COLLISION
            )
            self.fail(status, "start in collision: " + _describe_contacts(report))
        return q

    def fail(self, status: PlanStatus, message: str, path=None, goal_q=None, attempts: int = 1) -> PlanResult:
        self.timings["total"] = time.perf_counter() - self.t0
        logger.info("planning failed: %s (%s)", status.name, message)
        self._failure = PlanResult(
            success=False, status=status, path=path, goal_q=goal_q, timings=dict(self.timings), message=message,
            attempts=attempts,
        )
        return self._failure


def _describe_contacts(report) -> str:
    """'a touches b (1.2 mm deep)' for the deepest few contacts of a CollisionReport."""
    parts = [f"{c.a} touches {c.b} ({max(0.0, -c.distance) * 1e3:.1f} mm deep, {c.kind})" for c in report.contacts[:3]]
    more = len(report.contacts) - 3
    return "; ".join(parts) + (f"; and {more} more" if more > 0 else "")


def _replace(result: PlanResult, **changes) -> PlanResult:
    from dataclasses import replace

    return replace(result, **changes)


def _positive(value: float, name: str) -> float:
    v = float(value)
    if not np.isfinite(v) or v <= 0:
        raise InvalidInputError(f"{name} must be a positive finite number; got {value!r}")
    return v


def _fraction(value: float, name: str) -> float:
    v = float(value)
    if not (0.0 < v <= 1.0):
        raise InvalidInputError(f"{name} must be in (0, 1]; got {value!r}")
    return v
