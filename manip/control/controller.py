"""`ReactiveController`: differential inverse kinematics as one small QP per control step.

Each `step(q, target, dt)` linearises the robot at `q` and solves, over the joint
displacement dq of the step, the weighted tasks of `manip.control.tasks` (end-effector
frame towards the target, posture towards a rest configuration, damping) subject to hard
limits:

- joint positions within the robot configuration's limits (as mink's
  `ConfigurationLimit`: at most `limit_gain` of the remaining range per step), joint
  velocities within its velocity limits times `velocity_scale` (as mink's
  `VelocityLimit`) and joint accelerations within its acceleration limits (from the
  previous step's velocities): bounds on the QP's variables (`manip.control.limits`);
- no pair of robot geom and obstacle, and no checked self-collision pair, closer than
  `safety_margin` (`manip.control.collision.CollisionLimit`).

The result is `q + dq` and dq / dt. Nothing is planned: the controller reacts to the
current target and world at every step, so it follows a moving target and moving
obstacles, but it only descends locally. When the target cannot be reached (out of
reach, or behind an obstacle) the arm moves as close as the limits allow and stops
there, at `safety_margin` from the obstacle; when the target comes back it follows it
again. It can get stuck behind an obstacle that a planner (`manip.MotionGenerator`) would
go around; such steps are reported `StepStatus.STALLED` (`stall_time`).

Everything is in the robot base frame: targets, and obstacles (`manip.collision.WorldConfig`,
the MotionGenerator's world; or read from a `manip.sim` World with `set_world(world,
robot)`). The kinematics and collision geometry are the robot's MuJoCo model
(`manip.control.model`), the one `manip.sim` simulates: the controller works with or
without the simulator.

Example::

    from manip.control import ReactiveController
    from manip.collision import Cuboid, WorldConfig

    ctrl = ReactiveController("franka", WorldConfig([Cuboid("box", [0.1, 0.4, 0.3], [0.5, 0, 0.15])]))
    q = ctrl.rest_configuration
    for k in range(600):
        target = [0.4, 0.2 * np.sin(k / 60), 0.4]          # base frame [m]; or a Pose
        r = ctrl.step(q, target, dt=1 / 60)
        q = r.q   # send r.q (and r.velocities) to the robot
"""

from __future__ import annotations

import logging
import math
import time
from typing import Any

import mink
import mujoco
import numpy as np

from manip.collision.shapes import as_pose
from manip.collision.world import WorldConfig
from manip.control.collision import CollisionLimit, robot_collision_geoms, self_collision_pairs, self_pair_margins
from manip.control.limits import StepBounds
from manip.control.model import ControlModel
from manip.control.obstacles import geom_shape
from manip.control.progress import ProgressMonitor
from manip.control.results import StepResult, StepStatus
from manip.control.solvers import DEFAULT_SOLVER, check_solver, solve_qp
from manip.control.targets import as_target
from manip.control.tasks import Tasks, TaskWeights
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.robot_config import RobotConfig, load_robot_config
from manip.validation import as_real_array, fraction, non_negative, positive

logger = logging.getLogger(__name__)

#: Added to the QP Hessian's diagonal so that it is positive definite whatever the weights.
_REGULARISATION = 1e-9


class ReactiveController:
    """A reactive end-effector controller (a QP per step, built on mink).

    Args:
        robot: robot configuration name or `RobotConfig` (default "franka").
        world: obstacles in the robot base frame (a `WorldConfig`; None = none).
        frame: the controlled frame, a site or body of the robot's MuJoCo model (default:
            the configuration's `tcp_link`, else its `ee_link`; for the Franka
            "panda_hand_tcp", between the fingertips).
        solver: qpsolvers backend (default "daqp"; see `manip.control.solvers`).
        weights: task weights (`TaskWeights`); keywords of `set_weights` change single ones.
        rest_configuration: (dof,) the posture task's target [rad] (default the
            configuration's `default_joint_positions`).
        safety_margin: distance [m] kept from obstacles and between checked robot links
            (default 0.01). Links closer than twice this at the configuration's default joint
            positions keep half their distance there instead (`self_margins`; e.g. three
            pairs of the UR10's, 18-20 mm apart); links touching there are not checked.
        detection_distance: pairs closer than this [m] are constrained (default 0.1; must
            exceed the margin).
        collision_gain: fraction of the distance above the margin a pair may close per
            step, (0, 1] (default 0.1: near an obstacle the arm slows down smoothly, over
            about dt / 0.1 = 0.17 s at 60 Hz).
        limit_gain: fraction of the remaining joint range a joint may use per step, (0, 1]
            (default 0.95).
        velocity_scale: fraction of the configuration's velocity limits used, (0, 1]
            (default 1).
        acceleration_scale: fraction of the configuration's acceleration limits used,
            (0, 1], or None for no acceleration limit (default 1). The limit applies from
            the velocities of the previous step (or those passed to `step`); after
            `reset()` the first step starts from rest.
        max_speed: the controlled frame is sent at most this far towards the target per
            second [m/s] (default 1.0): a target that jumps is approached at this speed
            instead of in one step at the joints' velocity limits.
        max_angular_speed: the same for the orientation [rad/s] (default 2.5).
        self_collision: also keep the robot's links apart (default True).
        stall_time: steps are reported `StepStatus.STALLED` once, over this long [s], the
            steps together have not brought the frame 1 mm (or 0.01 rad; a tenth of the
            error if less) closer to their targets, and the target is not reached (default
            2.0; None = never; `manip.control.progress`).

    Raises:
        UnknownNameError / RobotConfigError: bad robot.
        UnknownFrameError (an InvalidInputError): `frame` is not a site or body.
        InvalidInputError: any other bad argument (the message names it).
    """

    def __init__(
        self,
        robot: str | RobotConfig = "franka",
        world: WorldConfig | None = None,
        *,
        frame: str | None = None,
        solver: str = DEFAULT_SOLVER,
        weights: TaskWeights | None = None,
        rest_configuration=None,
        safety_margin: float = 0.01,
        detection_distance: float = 0.1,
        collision_gain: float = 0.1,
        limit_gain: float = 0.95,
        velocity_scale: float = 1.0,
        acceleration_scale: float | None = 1.0,
        max_speed: float = 1.0,
        max_angular_speed: float = 2.5,
        self_collision: bool = True,
        stall_time: float | None = 2.0,
    ):
        self._config = robot if isinstance(robot, RobotConfig) else load_robot_config(robot)
        self._solver = check_solver(solver)
        if weights is not None and not isinstance(weights, TaskWeights):
            raise InvalidInputError(f"weights must be a TaskWeights; got {type(weights).__name__}")
        self._weights = weights if weights is not None else TaskWeights()
        self._margin = non_negative(safety_margin, "safety_margin", "m")
        self._detection = positive(detection_distance, "detection_distance", "m")
        if self._detection <= self._margin:
            raise InvalidInputError(f"detection_distance ({self._detection} m) must exceed safety_margin ({self._margin} m)")
        self._collision_gain = fraction(collision_gain, "collision_gain")
        self._limit_gain = fraction(limit_gain, "limit_gain")
        self._velocity_scale = fraction(velocity_scale, "velocity_scale")
        self._self_collision = bool(self_collision)
        cfg = self._config
        self._use_acceleration = acceleration_scale is not None
        self._limits = cfg.limits.scaled(
            self._velocity_scale, 1.0 if acceleration_scale is None else fraction(acceleration_scale,
                                                                                 "acceleration_scale"))
        self._v_prev: np.ndarray | None = None
        self._max_speed = positive(max_speed, "max_speed", "m/s")
        self._max_angular_speed = positive(max_angular_speed, "max_angular_speed", "rad/s")
        self._rest = self._check_q(cfg.default_joint_positions if rest_configuration is None else rest_configuration,
                                   "rest_configuration")
        if world is not None and not isinstance(world, WorldConfig):
            raise InvalidInputError(
                f"world must be a manip.collision.WorldConfig (use set_world(world, robot) for a manip.sim World); "
                f"got {type(world).__name__}"
            )
        self._world = world.copy() if world is not None else WorldConfig()
        default_frame = cfg.tcp_link or cfg.ee_link
        self._frame_name = frame if frame is not None else default_frame
        self._progress = None if stall_time is None else ProgressMonitor(stall_time)
        self._previous = None  # the previous step's (target, (position, orientation) errors, dt)
        self._build()

    # ------------------------------------------------------------------ building
    def _build(self) -> None:
        """(Re)build the model, mink configuration, tasks and limits for the current world."""
        self._model = ControlModel(self._config, self._world)
        m = self._model.model
        frame_type, frame_id = self._model.frame(self._frame_name, "frame")
        self._conf = mink.Configuration(m)
        self._model.write_obstacle_poses(self._conf.data)
        self._tasks = Tasks(m, frame_type, frame_id, self._model.q_to_qpos(self._rest), self._weights)
        robot_geoms = robot_collision_geoms(m, self._model.robot_bodies)
        obstacle_pairs = [(g, o) for o in self._model.obstacle_geoms.values() for g in robot_geoms]
        self_pairs, self_margins = [], np.zeros(0)
        if self._self_collision:
            disabled = {frozenset(p) for p in self._config.disabled_collision_pairs}
            home = mujoco.MjData(m)
            home.qpos[:] = self._model.q_to_qpos(self._config.default_joint_positions)
            mujoco.mj_kinematics(m, home)
            self_pairs, self_margins = self_pair_margins(m, home, self_collision_pairs(m, self._model.robot_bodies,
                                                                                      disabled), self._margin)
        first = not hasattr(self, "_collision")
        self._collision = CollisionLimit(m, obstacle_pairs, self_pairs, self._margin, self._detection,
                                         self._collision_gain, self_margins)
        if first and self.self_margins:
            logger.info("%s: self pairs closer than 2 x safety_margin (%.3f m) at the default joint positions keep "
                        "half that distance: %s", self._config.name, self._margin,
                        ", ".join(f"{a}-{b} {1000 * v:.1f} mm" for (a, b), v in self.self_margins.items()))
        self._joint_limits = StepBounds(self._limits, self._limit_gain, use_acceleration=self._use_acceleration)

    # ------------------------------------------------------------------ properties
    @property
    def config(self) -> RobotConfig:
        return self._config

    @property
    def dof(self) -> int:
        """Number of controlled (arm) joints."""
        return self._config.dof

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The arm joints, in the order of `q`."""
        return tuple(self._config.arm_joints)

    @property
    def frame(self) -> str:
        """The controlled frame (site or body of the robot's model)."""
        return self._frame_name

    @frame.setter
    def frame(self, name: str) -> None:
        frame_type, frame_id = self._model.frame(name, "frame")
        self._frame_name = name
        self._tasks = Tasks(self._model.model, frame_type, frame_id, self._model.q_to_qpos(self._rest), self._weights)

    @property
    def solver(self) -> str:
        """The qpsolvers backend."""
        return self._solver

    @solver.setter
    def solver(self, name: str) -> None:
        self._solver = check_solver(name)

    @property
    def weights(self) -> TaskWeights:
        return self._weights

    def set_weights(self, weights: TaskWeights | None = None, **changes: float) -> TaskWeights:
        """Replace the task weights, or change some (`set_weights(orientation=0.0)` for
        position-only tracking). Returns the new weights.

        Raises:
            InvalidInputError: an unknown keyword or an invalid value.
        """
        if weights is not None and not isinstance(weights, TaskWeights):
            raise InvalidInputError(f"weights must be a TaskWeights; got {type(weights).__name__}")
        base = weights if weights is not None else self._weights
        valid = set(TaskWeights.__dataclass_fields__)
        unknown = sorted(set(changes) - valid)
        if unknown:
            raise InvalidInputError(f"unknown weight {unknown[0]!r}; valid: {', '.join(sorted(valid))}")
        new = TaskWeights(**{**base.__dict__, **changes})
        self._weights = new
        self._tasks.set_weights(new)
        return new

    @property
    def rest_configuration(self) -> np.ndarray:
        """(dof,) the posture task's target [rad] (a copy)."""
        return self._rest.copy()

    @rest_configuration.setter
    def rest_configuration(self, q) -> None:
        self._rest = self._check_q(q, "rest_configuration")
        self._tasks.set_rest(self._model.q_to_qpos(self._rest))

    @property
    def lower_limits(self) -> np.ndarray:
        return self._limits.lower.copy()

    @property
    def upper_limits(self) -> np.ndarray:
        return self._limits.upper.copy()

    @property
    def velocity_limits(self) -> np.ndarray:
        """(dof,) the velocity limits the controller keeps [rad/s] (configuration's times
        `velocity_scale`)."""
        return self._limits.velocity.copy()

    @property
    def acceleration_limits(self) -> np.ndarray | None:
        """(dof,) the acceleration limits the controller keeps [rad/s^2], or None."""
        return self._limits.acceleration.copy() if self._use_acceleration else None

    def reset(self) -> None:
        """Forget the previous step's velocities (the next step starts from rest) and the
        progress towards the target (`stall_time` counts again)."""
        self._v_prev = None
        self._previous = None
        if self._progress is not None:
            self._progress.reset()

    @property
    def safety_margin(self) -> float:
        return self._margin

    @property
    def self_margins(self) -> dict[tuple[str, str], float]:
        """The self pairs (body names) whose margin [m] is below `safety_margin`: pairs closer
        than twice the margin at the configuration's default joint positions keep half that
        distance (`manip.control.collision.self_pair_margins`). Empty for most robots."""
        m, lim = self._model.model, self._collision
        out = {}
        for (g1, g2), margin in zip(lim.pairs[lim.n_obstacle_pairs:], lim.margins[lim.n_obstacle_pairs:]):
            if margin < self._margin:
                key = (m.body(int(m.geom_bodyid[g1])).name, m.body(int(m.geom_bodyid[g2])).name)
                out[key] = min(float(margin), out.get(key, math.inf))
        return out

    @property
    def collision_pair_counts(self) -> tuple[int, int]:
        """(robot-obstacle pairs, self-collision pairs) checked at every step."""
        return self._collision.n_obstacle_pairs, self._collision.n_pairs - self._collision.n_obstacle_pairs

    def frame_pose(self, q) -> Pose:
        """The controlled frame's pose at the joint positions q (dof,) [rad], base frame."""
        self._conf.update(self._model.q_to_qpos(self._check_q(q, "q")))
        T = self._conf.get_transform_frame_to_world(self._tasks.frame_id, self._tasks.frame_type)
        return Pose(T.translation().copy(), T.rotation().wxyz.copy())

    @property
    def model(self):
        """The controller's `mujoco.MjModel` (robot arm and obstacles, base frame)."""
        return self._model.model

    # ------------------------------------------------------------------ world
    @property
    def world(self) -> WorldConfig:
        """The obstacles the controller avoids (a copy, base frame, current poses)."""
        out = WorldConfig()
        for ob in self._world:
            out.add(ob.with_pose(self._model.pose_of(ob.name)))
        return out

    def set_world(self, world: Any, robot: Any = None, ignore=()) -> None:
        """Avoid the obstacles of `world` from now on.

        Args:
            world: a `WorldConfig` (base frame), or a `manip.sim` World after `reset()`
                (its collision shapes are read with `manip.sim_bridge.world_config_from_sim`;
                then `robot` is required).
            robot: the simulated robot (a `manip.sim` Articulation): its base pose maps the
                World to the base frame and its own geoms are skipped.
            ignore: with a simulated World, names or prim-path prefixes to leave out.

        Obstacles of the same names and shapes as the current ones are only moved (cheap);
        otherwise the controller's model is rebuilt (a few ms).

        Raises:
            InvalidInputError: anything else as `world`, or a sim World without `robot`.
        """
        if not isinstance(world, WorldConfig):
            if hasattr(world, "scene") and hasattr(world.scene, "get_collision_objects"):
                if robot is None:
                    raise InvalidInputError("set_world(world, robot): reading a simulated World needs the robot "
                                            "articulation (its base pose and its own geoms)")
                from manip.sim_bridge import world_config_from_sim

                world = world_config_from_sim(world, robot, ignore=ignore)
            else:
                raise InvalidInputError(f"world must be a WorldConfig or a manip.sim World; got {type(world).__name__}")
        same = world.names == self._world.names and all(
            geom_shape(ob).same_as(self._model.shapes[ob.name]) for ob in world
        )
        self._world = world.copy()
        if same:
            for ob in world:
                self._model.set_obstacle_pose(self._conf.data, ob.name, ob.pose)
        else:
            self._build()

    def add_obstacle(self, obstacle) -> None:
        """Add one obstacle (a `manip.collision` shape, base frame); rebuilds the model.

        Raises:
            InvalidInputError: not a shape, or its name is taken.
        """
        world = self.world
        world.add(obstacle)
        self.set_world(world)

    def remove_obstacle(self, name: str) -> None:
        """Stop avoiding obstacle `name`; rebuilds the model.

        Raises:
            UnknownNameError: no such obstacle (lists the names).
        """
        world = self.world
        world.remove(name)
        self.set_world(world)

    def set_obstacle_pose(self, name: str, pose) -> None:
        """Move obstacle `name` to `pose` (a Pose, [x, y, z] or [x, y, z, qw, qx, qy, qz];
        base frame). Cheap: call it every step for a moving obstacle.

        Raises:
            UnknownNameError: no such obstacle. InvalidInputError: a bad pose.
        """
        self._model.set_obstacle_pose(self._conf.data, name, as_pose(pose, f"obstacle {name!r}"))

    # ------------------------------------------------------------------ kinematics
    def _check_q(self, q, what: str = "q") -> np.ndarray:
        a = as_real_array(q, what)
        if a.shape != (self.dof,):
            raise InvalidInputError(
                f"{what} must have shape ({self.dof},) (one value per arm joint: {', '.join(self._config.arm_joints)}); "
                f"got {a.shape}"
            )
        if not np.all(np.isfinite(a)):
            raise InvalidInputError(f"{what} must be finite; got {a.tolist()}")
        return np.array(a, dtype=float)

    def forward_kinematics(self, q, frame: str | None = None) -> Pose:
        """Pose of `frame` (default the controlled frame) at `q`, in the base frame.

        Raises:
            InvalidInputError: bad `q`; UnknownFrameError: bad `frame`.
        """
        q = self._check_q(q)
        ftype, fid = self._model.frame(frame, "frame") if frame is not None else (self._tasks.frame_type,
                                                                                self._tasks.frame_id)
        self._conf.update(self._model.q_to_qpos(q))
        T = self._conf.get_transform_frame_to_world(fid, ftype)
        return Pose(T.translation(), T.rotation().wxyz)

    def clearance(self, q) -> tuple[float, float]:
        """(obstacle, self-collision) smallest distances [m] at `q` over every checked pair
        (inf if there is none; negative if penetrating)."""
        q = self._check_q(q)
        self._conf.update(self._model.q_to_qpos(q))
        return self._collision.distances(self._conf.data)

    # ------------------------------------------------------------------ control
    def step(self, q, target, dt: float, velocity=None) -> StepResult:
        """One control step from configuration `q` towards `target`.

        Args:
            q: (dof,) current arm joint positions [rad] (measured, or the last command).
            target: the controlled frame's target in the base frame: a `Pose`, a position
                (3,) (orientation free), [x, y, z, qw, qx, qy, qz] or a 4x4 transform.
            dt: the control period [s] (> 0): the step's displacement is velocities * dt.
            velocity: (dof,) current joint velocities [rad/s] for the acceleration limit
                (default: the previous step's velocities; zero after `reset()`).

        Returns:
            StepResult: `q` (the next configuration), `velocities`, status, errors and
            clearances. If the QP fails the arm holds (status HELD, zero velocity).

        Raises:
            InvalidInputError: a wrong shape, a NaN/inf, or dt <= 0 (the message names the
                argument); the controller's state is unchanged then.
        """
        t0 = time.perf_counter()
        q = self._check_q(q, "q")
        tgt = as_target(target, "target")
        dt = positive(dt, "dt", "s")
        v0 = self._check_q(velocity, "velocity") if velocity is not None else self._v_prev
        if v0 is None:
            v0 = np.zeros(self.dof)
        conf = self._conf
        conf.update(self._model.q_to_qpos(q))
        ftype, fid = self._tasks.frame_type, self._tasks.frame_id
        T = conf.get_transform_frame_to_world(fid, ftype)
        p_now = T.translation()
        R_now = T.rotation()
        position_error, orientation_error = self._errors(T, tgt)
        reach = self._max_speed * dt
        p_goal = tgt.position if position_error <= reach else p_now + (tgt.position - p_now) * (reach / position_error)
        if tgt.position_only:
            R_goal = R_now
        else:
            R_target = mink.SO3(wxyz=tgt.orientation)
            turn = self._max_angular_speed * dt
            if orientation_error <= turn:
                R_goal = R_target
            else:
                R_goal = R_now @ mink.SO3.exp((R_now.inverse() @ R_target).log() * (turn / orientation_error))
        goal = mink.SE3.from_rotation_and_translation(R_goal, p_goal)
        self._tasks.set_target(goal, tgt.position_only)

        H, c = self._tasks.objective(conf, _REGULARISATION)
        con = self._collision.compute_qp_inequalities(conf, dt)
        idx = self._model.qpos_index  # arm joint k is the model's dof idx[k] (hinge/slide joints only)
        x = self._solve(H, c, con, q, dt, v0, idx)
        if x is None and self._use_acceleration:
            # Stopping for an obstacle may need more deceleration than allowed: joint and
            # collision limits come first.
            x = self._solve(H, c, con, q, dt, None, idx)
        status = StepStatus.SOLVED
        if x is None:
            status = StepStatus.HELD
            logger.debug("reactive controller: QP failed (%s); holding", self._solver)
            dq = np.zeros(self.dof)
        else:
            dq = x[idx]
        q_next = self._joint_limits.clamp(q, dq, dt)
        if self._progress is not None:
            # progress made since the previous step, towards the previous step's target: from the
            # configuration this step starts at (the arm's, when it lags the command)
            prev = self._previous
            if prev is not None and self._progress.update(prev[1], self._errors(T, prev[0]), prev[2]) and x is not None:
                status = StepStatus.STALLED
            self._previous = (tgt, (position_error, orientation_error), dt)
        velocities = (q_next - q) / dt
        self._v_prev = velocities
        return StepResult(
            q=q_next,
            velocities=velocities,
            status=status,
            position_error=position_error,
            orientation_error=orientation_error,
            obstacle_clearance=float(self._collision.obstacle_clearance),
            self_clearance=float(self._collision.self_clearance),
            active_collision_rows=int(self._collision.active_rows),
            solve_time=time.perf_counter() - t0,
        )

    @staticmethod
    def _errors(T, tgt) -> tuple[float, float]:
        """(position [m], orientation [rad]) errors of the frame at pose T (mink.SE3) towards the target."""
        p_err = float(np.linalg.norm(tgt.position - T.translation()))
        if tgt.position_only:
            return p_err, 0.0
        return p_err, 2.0 * math.acos(min(abs(float(T.rotation().wxyz @ tgt.orientation)), 1.0))

    def _solve(self, H, c, con, q, dt, v0, idx) -> np.ndarray | None:
        lb, ub = self._joint_limits.bounds(q, dt, v0)
        lb_m, ub_m = np.empty_like(lb), np.empty_like(ub)
        lb_m[idx], ub_m[idx] = lb, ub
        return solve_qp(H, c, con.G, con.h, lb_m, ub_m, self._solver)

    def __repr__(self) -> str:
        n_obs, n_self = self.collision_pair_counts
        return (f"ReactiveController({self._config.name!r}, frame={self._frame_name!r}, solver={self._solver!r}, "
                f"{len(self._world)} obstacles, {n_obs} obstacle pairs, {n_self} self pairs)")
