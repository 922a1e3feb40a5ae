"""RoboPlan peer: C++ RRT-Connect on Pinocchio + coal, its shortcutter and its TOPP-RA.

Set-up (untimed, once): the example-robot-data Panda URDF/SRDF (the same files as
`load_robot_config("franka")`), fingers fixed at 0.04 m, the Franka acceleration limits of
`robots/franka/robot.yaml` imported as a RoboPlan joint-limits config (velocity limits come
from the URDF and equal the robot config's).

Per problem (untimed): the obstacles are added to the RoboPlan scene (obstacle-obstacle
pairs disabled) and the planner objects are built over that scene.

Timed: `SimpleIk` for pose goals (collision-checked, seeded at the start configuration,
random restarts), `RRT` with `rrt_connect=True` and an edge collision-check step of
0.01 rad (RoboPlan's default 0.05 returns colliding paths), `PathShortcutter` at the same
step, `PathParameterizerTOPPRA` sampling at 0.01 s.
"""

from __future__ import annotations

import itertools
import logging
import os
import tempfile
import time
from typing import Any

import numpy as np

import roboplan.core as rc
import roboplan.rrt as rr
import roboplan.simple_ik as rsi
import roboplan.toppra as rtp
from manip.errors import InvalidInputError
from manip.robot_config import RobotConfig, load_robot_config

from . import PlannerOutput
from ._common import (
    DEFAULT_TIMEOUT_S,
    EDGE_RESOLUTION,
    FINGER_OPENING,
    IK_POSITION_TOL,
    IK_ROTATION_TOL,
    SAMPLE_DT,
    check_goal_kind,
    finite_difference_jerk,
    goal_pose,
    problem_arrays,
    world_obstacles,
)

log = logging.getLogger(__name__)

_GROUP = "arm"  # the SRDF's 7-joint group
_COLOR = np.array([0.8, 0.2, 0.2, 1.0])
SPLINE_MODES = ("Hermite", "Cubic", "Adaptive", "LinearBlend")


class RoboPlanPeer:
    """RoboPlan 0.7 RRT-Connect + shortcutting + TOPP-RA on the example-robot-data Panda.

    Args:
        config: robot configuration (default `load_robot_config("franka")`).
        timeout_s: RRT-Connect planning budget per problem [s].
        edge_resolution: collision-check step along edges, shortcuts and blends [rad].
        spline_mode: RoboPlan's TOPP-RA path spline: "Hermite" (stops at every waypoint;
            RoboPlan's default), "Cubic", "Adaptive" or "LinearBlend" (straight segments
            joined by collision-checked corner blends; falls back to Hermite). Default
            "LinearBlend": see README.md for why.
        ik_timeout_s: SimpleIk budget for pose goals [s].
        shortcut_max_iters: iterations of RoboPlan's random shortcutter (its default 100).
        limit_scale: fraction (0, 1] of the velocity and acceleration limits given to
            RoboPlan's TOPP-RA (its `velocity_scale` and `acceleration_scale`); the default
            0.995 matches the OMPL peer's margin for TOPP-RA's between-gridpoint overshoot.

    Raises:
        InvalidInputError: an option out of range.
    """

    name = "roboplan"

    def __init__(
        self,
        config: RobotConfig | None = None,
        timeout_s: float = DEFAULT_TIMEOUT_S,
        edge_resolution: float = EDGE_RESOLUTION,
        spline_mode: str = "LinearBlend",
        ik_timeout_s: float = 1.0,
        shortcut_max_iters: int = 100,
        limit_scale: float = 0.995,
    ) -> None:
        if spline_mode not in SPLINE_MODES:
            raise InvalidInputError(f"spline_mode must be one of {SPLINE_MODES}; got {spline_mode!r}")
        for what, v in (("timeout_s", timeout_s), ("edge_resolution", edge_resolution), ("ik_timeout_s", ik_timeout_s)):
            if not (np.isfinite(v) and v > 0):
                raise InvalidInputError(f"{what} must be > 0; got {v}")
        if not (0 < limit_scale <= 1):
            raise InvalidInputError(f"limit_scale must be in (0, 1]; got {limit_scale}")
        self.config = config if config is not None else load_robot_config("franka")
        self.timeout_s = float(timeout_s)
        self.edge_resolution = float(edge_resolution)
        self.spline_mode = spline_mode
        self.ik_timeout_s = float(ik_timeout_s)
        self.shortcut_max_iters = int(shortcut_max_iters)
        self.limit_scale = float(limit_scale)
        self.joint_names = tuple(self.config.arm_joints)

        desc = rc.loadUrdfSceneDescription(str(self.config.urdf_path), [str(p) for p in self.config.package_dirs])
        self.scene = rc.Scene("panda", desc)
        self.scene.importSrdf(self.config.srdf_path.read_text())
        self._import_limits()
        if tuple(self.scene.getJointGroupInfo(_GROUP).joint_names) != self.joint_names:
            raise InvalidInputError(f"RoboPlan group '{_GROUP}' joints differ from the robot config's {self.joint_names}")
        q = np.array(self.scene.getCurrentJointPositions(), dtype=float)
        q[len(self.joint_names):] = FINGER_OPENING  # finger 1 (finger 2 mimics it)
        self.scene.setJointPositions(q)
        self._n_full = q.size

    def _import_limits(self) -> None:
        """Give RoboPlan the Franka acceleration (and jerk) limits of the robot config."""
        cfg = self.config
        lines = ["joint_limits:"]
        for j, a, jk in zip(cfg.arm_joints, cfg.acceleration_limits, cfg.jerk_limits):
            lines += [f"  {j}:", f"    max_acceleration: [{float(a)!r}]", f"    max_jerk: [{float(jk)!r}]"]
        fd, path = tempfile.mkstemp(suffix=".yaml", prefix="manip_roboplan_limits_")
        try:
            with os.fdopen(fd, "w") as f:
                f.write("\n".join(lines) + "\n")
            self.scene.importJointLimitsFromConfig(rc.loadJointLimitsConfig(path))
        finally:
            os.unlink(path)
        _, vmax = self.scene.getVelocityLimitVectors(_GROUP)
        _, amax = self.scene.getAccelerationLimitVectors(_GROUP)
        if not (np.allclose(vmax, cfg.velocity_limits) and np.allclose(amax, cfg.acceleration_limits)):
            raise InvalidInputError(f"RoboPlan limits {vmax}, {amax} differ from the robot config's")

    def _full(self, q: np.ndarray) -> np.ndarray:
        out = np.full(self._n_full, FINGER_OPENING)
        out[: len(q)] = q
        return out

    def _add_world(self, world: dict) -> list[str]:
        names: list[str] = []
        try:
            for k, ob in enumerate(world_obstacles(world)):
                name = f"obstacle{k}_{ob.name}"
                T = np.asfortranarray(ob.T)
                if ob.kind == "box":
                    self.scene.addBoxGeometry(name, "universe", rc.Box(*ob.size), T, _COLOR)
                else:
                    r, h = ob.size
                    self.scene.addCylinderGeometry(name, "universe", rc.Cylinder(r, h), T, _COLOR)
                names.append(name)
            if len(names) > 1:
                self.scene.setCollisions(list(itertools.combinations(names, 2)), False)
        except Exception:
            self._remove_world(names)
            raise
        return names

    def _remove_world(self, names: list[str]) -> None:
        for n in names:
            self.scene.removeGeometry(n)

    def plan(self, problem: Any, goal_kind: str = "joint", seed: int = 0) -> PlannerOutput:
        """Plan one problem (see `PlannerOutput` for what is timed).

        Args:
            problem: an `MBMProblem` (world, start (7,), goal (7,), joint_names).
            goal_kind: "joint" (plan to `problem.goal`) or "pose" (IK of the goal's
                `panda_hand` pose first).
            seed: seeds RoboPlan's RRT, shortcutter and IK random number generators.

        Raises:
            InvalidInputError: malformed problem or goal kind.
        """
        check_goal_kind(goal_kind)
        start, goal = problem_arrays(problem, self.joint_names)
        target = goal_pose(problem) if goal_kind == "pose" else None

        t_setup = time.perf_counter()
        names = self._add_world(problem.world)
        try:
            rrt = rr.RRT(
                self.scene,
                rr.RRTOptions(
                    group_name=_GROUP,
                    max_nodes=10_000_000,
                    collision_check_step_size=self.edge_resolution,
                    max_planning_time=self.timeout_s,
                    rrt_connect=True,
                ),
            )
            rrt.setRngSeed(int(seed))
            shortcutter = rc.PathShortcutter(
                self.scene,
                rc.PathShortcuttingOptions(
                    group_name=_GROUP, max_step_size=self.edge_resolution, max_iters=self.shortcut_max_iters, seed=int(seed)
                ),
            )
            toppra = rtp.PathParameterizerTOPPRA(self.scene, _GROUP)
            toppra_options = rtp.TOPPRAOptions(
                dt=SAMPLE_DT,
                mode=getattr(rtp.SplineFittingMode, self.spline_mode),
                velocity_scale=self.limit_scale,
                acceleration_scale=self.limit_scale,
                max_adaptive_step_size=self.edge_resolution,
            )
            ik = None
            if target is not None:
                ik = rsi.SimpleIk(
                    self.scene,
                    rsi.SimpleIkOptions(
                        group_name=_GROUP,
                        max_iters=100,
                        max_time=self.ik_timeout_s,
                        max_restarts=1_000_000,
                        max_linear_error_norm=IK_POSITION_TOL,
                        max_angular_error_norm=IK_ROTATION_TOL,
                        check_collisions=True,
                    ),
                )
                ik.setRngSeed(int(seed))
            setup_s = time.perf_counter() - t_setup
            return self._plan_timed(start, goal, target, rrt, shortcutter, toppra, toppra_options, ik, setup_s)
        finally:
            self._remove_world(names)

    def _plan_timed(self, start, goal, target, rrt, shortcutter, toppra, toppra_options, ik, setup_s) -> PlannerOutput:
        stages: dict[str, float] = {}
        t0 = time.perf_counter()

        def fail(status: str) -> PlannerOutput:
            return PlannerOutput(False, status, time.perf_counter() - t0, setup_time_s=setup_s, stage_times_s=stages)

        names = list(self.joint_names)
        if target is not None:
            sol = rc.JointConfiguration()
            ok = ik.solveIk(
                rc.CartesianConfiguration(self.config.base_link, self.config.ee_link, np.asfortranarray(target.as_matrix())),
                rc.JointConfiguration(names, start),
                sol,
            )
            stages["ik"] = time.perf_counter() - t0
            if not ok:
                return fail("IK_FAIL")
            goal = np.array(sol.positions, dtype=float)[: len(names)]

        t1 = time.perf_counter()
        try:
            path = rrt.plan(rc.JointConfiguration(names, start), rc.JointConfiguration(names, goal))
        except RuntimeError as exc:
            stages["plan"] = time.perf_counter() - t1
            msg = str(exc)
            low = msg.lower()
            if "start" in low and ("collision" in low or "valid" in low or "limit" in low):
                return fail("INVALID_START")
            if "goal" in low and ("collision" in low or "valid" in low or "limit" in low):
                return fail("INVALID_GOAL")
            if "timed out" in low or "time" in low:
                return fail("PLAN_FAIL")
            return fail(f"ERROR: {msg}")
        stages["plan"] = time.perf_counter() - t1
        if len(path.positions) < 2:
            return fail("PLAN_FAIL")

        t2 = time.perf_counter()
        short = shortcutter.shortcut(path)
        stages["shortcut"] = time.perf_counter() - t2

        t3 = time.perf_counter()
        try:
            traj = toppra.generate(short, toppra_options)
        except RuntimeError as exc:
            stages["time_parameterization"] = time.perf_counter() - t3
            log.warning("RoboPlan TOPP-RA failed: %s", exc)
            return fail("TIMING_FAIL")
        times = np.asarray(traj.times, dtype=float)
        if times.size < 2:
            stages["time_parameterization"] = time.perf_counter() - t3
            return fail("TIMING_FAIL")
        P = np.asarray(traj.positions, dtype=float)
        V = np.asarray(traj.velocities, dtype=float)
        A = np.asarray(traj.accelerations, dtype=float)
        J = finite_difference_jerk(times, A)
        stages["time_parameterization"] = time.perf_counter() - t3
        plan_time = time.perf_counter() - t0
        if tuple(traj.joint_names) != self.joint_names:
            return fail(f"ERROR: RoboPlan returned joints {traj.joint_names}, expected {self.joint_names}")
        return PlannerOutput(
            True,
            "SUCCESS",
            plan_time,
            times - times[0],
            P,
            V,
            A,
            J,
            claims_jerk_limits=False,
            setup_time_s=setup_s,
            stage_times_s=stages,
            goal_configuration=np.asarray(goal, dtype=float).copy(),
            n_waypoints=len(short.positions),
        )
