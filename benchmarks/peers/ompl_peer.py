"""OMPL peer: RRT-Connect with a pinocchio + coal validity checker, simplification, TOPP-RA.

Set-up (untimed, once): the example-robot-data Panda URDF (collision meshes) in pinocchio,
fingers fixed at 0.04 m, self-collision pairs = all pairs minus the SRDF's disabled pairs;
an OMPL 7-D `RealVectorStateSpace` bounded by the robot config's joint limits, with a
state-validity resolution of 0.01 rad (L2) along edges.

Per problem (untimed): the obstacles are added as coal boxes/cylinders (robot-obstacle pairs
only) and a broadphase manager (dynamic AABB tree) is built over them.

Timed: a damped-least-squares IK (pinocchio, random restarts, collision-checked) for pose
goals; `RRTConnect` (OMPL's default range) with a Python validity callback; OMPL's
`PathSimplifier` (`SimpleSetup.simplifySolution`); TOPP-RA (`toppra`, seidel solver,
constant-acceleration output) under the Franka velocity and acceleration limits along a path
that stops at each waypoint (a cubic blend along each straight segment, so the time-parameterised
motion stays on the checked polyline); sampling every 0.01 s.

OMPL's random generator is process-global: `seed` is applied once, when the first peer is
built (OMPL refuses later seeds); runs are reproducible for the same sequence of problems.
"""

from __future__ import annotations

import logging
import time
from typing import Any

import numpy as np
import pinocchio as pin
import toppra
import toppra.algorithm
import toppra.constraint
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

import coal
from manip.errors import InvalidInputError
from manip.robot_config import RobotConfig, load_robot_config

from . import PlannerOutput
from ._common import (
    DEFAULT_TIMEOUT_S,
    EDGE_RESOLUTION,
    FINGER_OPENING,
    IK_POSITION_TOL,
    IK_ROTATION_TOL,
    check_goal_kind,
    finite_difference_jerk,
    goal_pose,
    problem_arrays,
    uniform_times,
    world_obstacles,
)

log = logging.getLogger(__name__)

_OMPL_SEEDED = False


def _seed_ompl_once(seed: int) -> None:
    global _OMPL_SEEDED
    if not _OMPL_SEEDED:
        ou.setLogLevel(ou.LogLevel.LOG_ERROR)
        ou.RNG.setSeed(int(seed) + 1)  # OMPL needs a seed > 0
        _OMPL_SEEDED = True


class StopAtWaypointsPath(toppra.interpolator.AbstractGeometricPath):
    """A joint-space polyline as a C^1 geometric path that rests at every waypoint.

    Segment i (path parameter s in [s_i, s_i+1], of parameter length S_i = max(L_i, min_length)
    where L_i is its L2 length [rad]) is q(s) = q_i + (q_i+1 - q_i) h(u), u = (s - s_i) / S_i,
    h(u) = 3u^2 - 2u^3: it stays on the straight segment (what the planner collision-checked)
    and dq/ds = 0 at the waypoints (the joint velocity is zero there). `min_length` keeps very short segments from producing
    huge path curvatures (and TOPP-RA failures).

    Args:
        waypoints: (K, n) configurations, K >= 2; repeated consecutive ones are dropped.
        min_length: smallest parameter length of a segment [rad].
    """

    def __init__(self, waypoints: np.ndarray, min_length: float = 0.05) -> None:
        W = np.asarray(waypoints, dtype=float)
        d = np.diff(W, axis=0)
        L = np.linalg.norm(d, axis=1)
        keep = np.concatenate([[True], L > 1e-12])
        W = W[keep]
        d = np.diff(W, axis=0)
        L = np.linalg.norm(d, axis=1)
        if len(W) < 2:
            raise InvalidInputError("a path needs at least two distinct waypoints")
        S = np.maximum(L, min_length)
        self._W, self._d, self._L = W, d, S
        self._s = np.concatenate([[0.0], np.cumsum(S)])

    @property
    def dof(self) -> int:
        return self._W.shape[1]

    @property
    def path_interval(self) -> np.ndarray:
        return np.array([0.0, self._s[-1]])

    @property
    def waypoints(self):
        return self._s.copy(), self._W.copy()

    @property
    def knots(self) -> np.ndarray:
        """(K,) path parameters of the waypoints."""
        return self._s.copy()

    def __call__(self, path_positions, order: int = 0) -> np.ndarray:
        s = np.atleast_1d(np.asarray(path_positions, dtype=float))
        i = np.clip(np.searchsorted(self._s, s, side="right") - 1, 0, len(self._L) - 1)
        L = self._L[i]
        u = np.clip((s - self._s[i]) / L, 0.0, 1.0)
        if order == 0:
            out = self._W[i] + self._d[i] * (3 * u**2 - 2 * u**3)[:, None]
        elif order == 1:
            out = self._d[i] * ((6 * u - 6 * u**2) / L)[:, None]
        elif order == 2:
            out = self._d[i] * ((6 - 12 * u) / L**2)[:, None]
            # At an interior waypoint dq/ds = 0 and d2q/ds2 jumps from -6 d_prev / S_prev^2
            # to 6 d_next / S_next^2. The joint acceleration there is d2q/ds2 * sd^2 on either
            # side, so report, per joint, the side of larger magnitude: a TOPP-RA gridpoint
            # at the waypoint then bounds the arriving motion as well as the leaving one.
            k = np.searchsorted(self._s, s)
            at = (k > 0) & (k < len(self._s) - 1)
            at &= np.isclose(s, self._s[np.clip(k, 0, len(self._s) - 1)], rtol=0, atol=1e-12)
            for j in np.flatnonzero(at):
                left = -6 * self._d[k[j] - 1] / self._L[k[j] - 1] ** 2
                right = out[j]
                out[j] = np.where(np.abs(left) > np.abs(right), left, right)
        else:
            raise InvalidInputError(f"order must be 0, 1 or 2; got {order}")
        return out[0] if np.ndim(path_positions) == 0 else out


class OMPLPeer:
    """OMPL 2.0 RRT-Connect + simplification + TOPP-RA on the example-robot-data Panda.

    Args:
        config: robot configuration (default `load_robot_config("franka")`).
        timeout_s: RRT-Connect planning budget per problem [s].
        edge_resolution: L2 step between validity checks along edges [rad].
        ik_timeout_s: budget of the pose-goal IK [s].
        simplify_time_s: OMPL simplification budget [s]; 0 runs `simplifyMax`.
        grid_step: TOPP-RA grid spacing along the path [rad of path length].
        limit_scale: fraction (0, 1] of the velocity and acceleration limits given to
            TOPP-RA. TOPP-RA enforces them at gridpoints only; at a 0.01 rad grid the
            sampled trajectory overshoots by up to ~0.5 % between gridpoints, so the
            default 0.995 keeps it within the true limits.
        seed: OMPL's process-global seed, applied once for the first peer built.

    Raises:
        InvalidInputError: an option out of range.
    """

    name = "ompl"

    def __init__(
        self,
        config: RobotConfig | None = None,
        timeout_s: float = DEFAULT_TIMEOUT_S,
        edge_resolution: float = EDGE_RESOLUTION,
        ik_timeout_s: float = 1.0,
        simplify_time_s: float = 0.0,
        grid_step: float = 0.01,
        limit_scale: float = 0.995,
        seed: int = 0,
    ) -> None:
        if not (0 < limit_scale <= 1):
            raise InvalidInputError(f"limit_scale must be in (0, 1]; got {limit_scale}")
        for what, v in (("timeout_s", timeout_s), ("edge_resolution", edge_resolution), ("ik_timeout_s", ik_timeout_s), ("grid_step", grid_step)):
            if not (np.isfinite(v) and v > 0):
                raise InvalidInputError(f"{what} must be > 0; got {v}")
        if not simplify_time_s >= 0:
            raise InvalidInputError(f"simplify_time_s must be >= 0; got {simplify_time_s}")
        _seed_ompl_once(seed)
        self.config = c = config if config is not None else load_robot_config("franka")
        self.timeout_s = float(timeout_s)
        self.edge_resolution = float(edge_resolution)
        self.ik_timeout_s = float(ik_timeout_s)
        self.simplify_time_s = float(simplify_time_s)
        self.grid_step = float(grid_step)
        self.limit_scale = float(limit_scale)
        self.joint_names = tuple(c.arm_joints)
        self.dof = len(self.joint_names)

        self.model = pin.buildModelFromUrdf(str(c.urdf_path))
        self.data = self.model.createData()
        robot_geom = pin.buildGeomFromUrdf(self.model, str(c.urdf_path), pin.COLLISION, package_dirs=list(c.package_dirs))
        robot_geom.addAllCollisionPairs()
        pin.removeCollisionPairs(self.model, robot_geom, str(c.srdf_path))
        self._robot_geom = robot_geom
        self._n_robot = robot_geom.ngeoms
        self._arm_idx = np.array([self.model.joints[self.model.getJointId(j)].idx_q for j in c.arm_joints])
        self._q = pin.neutral(self.model)
        for j in (c.gripper.joints if c.gripper is not None else ()):
            self._q[self.model.joints[self.model.getJointId(j)].idx_q] = FINGER_OPENING
        self._ee = self.model.getFrameId(c.ee_link)
        self.lower = np.asarray(c.lower_limits, dtype=float)
        self.upper = np.asarray(c.upper_limits, dtype=float)
        self.vlim = np.asarray(c.velocity_limits, dtype=float)
        self.alim = np.asarray(c.acceleration_limits, dtype=float)

        self.space = ob.RealVectorStateSpace(self.dof)
        bounds = ob.RealVectorBounds(self.dof)
        for i in range(self.dof):
            bounds.setLow(i, float(self.lower[i]))
            bounds.setHigh(i, float(self.upper[i]))
        self.space.setBounds(bounds)
        self._gm = self._gd = self._bp = None

    # ------------------------------------------------------------------ collision world
    def _build_world(self, world: dict) -> None:
        gm = self._robot_geom.copy()
        for ob_ in world_obstacles(world):
            shape = coal.Box(*ob_.size) if ob_.kind == "box" else coal.Cylinder(*ob_.size)
            M = pin.SE3(ob_.T[:3, :3].copy(), ob_.T[:3, 3].copy())
            gid = gm.addGeometryObject(pin.GeometryObject(f"world/{ob_.name}", 0, 0, M, shape))
            for r in range(self._n_robot):
                gm.addCollisionPair(pin.CollisionPair(r, gid))
        gd = gm.createData()
        # The broadphase manager keeps pointers to gm/gd: keep them alive on self.
        self._gm, self._gd = gm, gd
        self._bp = pin.BroadPhaseManager_DynamicAABBTreeCollisionManager(self.model, gm, gd)

    def _full(self, q: np.ndarray) -> np.ndarray:
        full = self._q.copy()
        full[self._arm_idx] = q
        return full

    def is_valid(self, q: np.ndarray) -> bool:
        """Arm configuration `q` (7,) within limits and free of self and world collision."""
        if np.any(q < self.lower) or np.any(q > self.upper):
            return False
        return not pin.computeCollisions(self.model, self.data, self._bp, self._full(q), True)

    # ------------------------------------------------------------------ IK
    def _ik(self, target: pin.SE3, start: np.ndarray, rng: np.random.Generator, deadline: float) -> np.ndarray | None:
        """Damped least squares on the LOCAL frame error, random restarts, collision-checked."""
        model, data, fid = self.model, self.data, self._ee
        seed_q = start.copy()
        while time.perf_counter() < deadline:
            q = seed_q
            for _ in range(100):
                full = self._full(q)
                pin.framesForwardKinematics(model, data, full)
                M = data.oMf[fid]
                err = pin.log6(M.actInv(target)).vector  # twist taking M to target, LOCAL frame
                pos_err = np.linalg.norm(target.translation - M.translation)
                rot_err = np.linalg.norm(err[3:])
                if pos_err < IK_POSITION_TOL and rot_err < IK_ROTATION_TOL:
                    if self.is_valid(q):
                        return q
                    break
                J = pin.computeFrameJacobian(model, data, full, fid, pin.LOCAL)[:, self._arm_idx]
                dq = J.T @ np.linalg.solve(J @ J.T + 1e-6 * np.eye(6), err)
                q = np.clip(q + dq, self.lower, self.upper)
            seed_q = rng.uniform(self.lower, self.upper)
        return None

    # ------------------------------------------------------------------ planning
    def plan(self, problem: Any, goal_kind: str = "joint", seed: int = 0) -> PlannerOutput:
        """Plan one problem (see `PlannerOutput` for what is timed).

        Args:
            problem: an `MBMProblem` (world, start (7,), goal (7,), joint_names).
            goal_kind: "joint" or "pose" (IK of the goal's `panda_hand` pose first).
            seed: seeds the IK restarts (OMPL's own generator is process-global).

        Raises:
            InvalidInputError: malformed problem or goal kind.
        """
        check_goal_kind(goal_kind)
        start, goal = problem_arrays(problem, self.joint_names)
        target = None
        if goal_kind == "pose":
            T = goal_pose(problem).as_matrix()
            target = pin.SE3(T[:3, :3].copy(), T[:3, 3].copy())

        t_setup = time.perf_counter()
        self._build_world(problem.world)
        ss = og.SimpleSetup(self.space)
        n = self.dof
        ss.setStateValidityChecker(lambda s: self.is_valid(np.array(s[0:n])))
        si = ss.getSpaceInformation()
        si.setStateValidityCheckingResolution(self.edge_resolution / self.space.getMaximumExtent())
        ss.setPlanner(og.RRTConnect(si))
        setup_s = time.perf_counter() - t_setup

        stages: dict[str, float] = {}
        t0 = time.perf_counter()

        def fail(status: str) -> PlannerOutput:
            return PlannerOutput(False, status, time.perf_counter() - t0, setup_time_s=setup_s, stage_times_s=stages)

        if target is not None:
            q_goal = self._ik(target, start, np.random.default_rng(seed), t0 + self.ik_timeout_s)
            stages["ik"] = time.perf_counter() - t0
            if q_goal is None:
                return fail("IK_FAIL")
            goal = q_goal

        t1 = time.perf_counter()
        s0, s1 = self.space.allocState(), self.space.allocState()
        for i in range(self.dof):
            s0[i] = float(start[i])
            s1[i] = float(goal[i])
        ss.setStartAndGoalStates(s0, s1)
        status = ss.solve(self.timeout_s)
        stages["plan"] = time.perf_counter() - t1
        st = status.getStatus()
        T_ = ob.PlannerStatus.PlannerStatusType
        if st == T_.INVALID_START:
            return fail("INVALID_START")
        if st == T_.INVALID_GOAL:
            return fail("INVALID_GOAL")
        if st != T_.EXACT_SOLUTION or not ss.haveExactSolutionPath():
            return fail("PLAN_FAIL")

        t2 = time.perf_counter()
        ss.simplifySolution(self.simplify_time_s)
        W = np.array([[s[i] for i in range(self.dof)] for s in ss.getSolutionPath().getStates()])
        stages["shortcut"] = time.perf_counter() - t2

        t3 = time.perf_counter()
        try:
            path = StopAtWaypointsPath(W)
            times, P, V, A = self._time_parameterize(path)
        except (InvalidInputError, ValueError, RuntimeError) as exc:
            stages["time_parameterization"] = time.perf_counter() - t3
            log.warning("TOPP-RA failed: %s", exc)
            return fail("TIMING_FAIL")
        J = finite_difference_jerk(times, A)
        stages["time_parameterization"] = time.perf_counter() - t3
        return PlannerOutput(
            True,
            "SUCCESS",
            time.perf_counter() - t0,
            times,
            P,
            V,
            A,
            J,
            claims_jerk_limits=False,
            setup_time_s=setup_s,
            stage_times_s=stages,
            goal_configuration=np.asarray(goal, dtype=float).copy(),
            n_waypoints=len(W),
        )

    def _time_parameterize(self, path: StopAtWaypointsPath) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """TOPP-RA under the velocity and acceleration limits; samples every 0.01 s."""
        knots = path.knots
        grid = [knots[:1]]
        for k, (a, b) in enumerate(zip(knots[:-1], knots[1:])):
            n = max(40, int(np.ceil((b - a) / self.grid_step)))
            seg = np.linspace(a, b, n + 1)[1:]
            grid.append(seg)
        gridpoints = np.concatenate(grid)
        v, a = self.limit_scale * self.vlim, self.limit_scale * self.alim
        vel = toppra.constraint.JointVelocityConstraint(np.stack([-v, v], axis=1))
        acc = toppra.constraint.JointAccelerationConstraint(
            np.stack([-a, a], axis=1),
            discretization_scheme=toppra.constraint.DiscretizationType.Interpolation,
        )
        algo = toppra.algorithm.TOPPRA([vel, acc], path, gridpoints=gridpoints, solver_wrapper="seidel", parametrizer="ParametrizeConstAccel")
        traj = algo.compute_trajectory(0.0, 0.0)
        if traj is None:
            raise RuntimeError("TOPP-RA found no feasible parameterisation")
        times = uniform_times(float(traj.duration))
        return times, traj(times), traj(times, 1), traj(times, 2)
