"""An independent judge of motion planning problems and trajectories.

This module shares no collision code with `manip`'s planner: it builds its own exact-mesh
model of the robot (Pinocchio `buildGeomFromUrdf`, COLLISION meshes of the URDF, fingers at
their planning opening) and of the world (coal Box / Cylinder / Sphere / Capsule / mesh),
and asks `pinocchio.computeCollisions` (coal, no padding) whether any pair touches; a part
wholly inside another's closed mesh, which touches no triangle, is found by `verify_inside`
(robot links' closed meshes and the world's `"solid": true` meshes; the world's other meshes,
closed or open, are surfaces as manip reads them: only contacts with their triangles count).
Self-collision pairs are all pairs of robot geometries minus the SRDF's disabled pairs.

What `verify_trajectory` checks, and with which tolerance:

- collision: every given sample, plus configurations linearly interpolated between
  consecutive samples so that no two consecutive checked configurations differ by more
  than `resolution` (default 0.01 rad) on any joint (L-inf);
- position limits: every sample within [lower - 1e-6, upper + 1e-6] rad (the 1e-6 rad is
  the "hair outside" a start may be; a trajectory may not go further);
- velocity and acceleration limits: from the given arrays AND from divided differences of
  the positions (by the mean value theorem a divided difference of a C^k trajectory equals
  a derivative somewhere on its interval, so it can never exceed the true maximum). A
  relative tolerance of 1e-3 (`rel_tol`) covers floating-point noise only;
- jerk: reported (given array and third divided differences); checked against the robot's
  jerk limit (same tolerance) only when `check_jerk=True`, i.e. for planners that claim
  jerk-limited trajectories;
- endpoints: first sample within 1e-6 rad (L-inf) of the start; last sample within
  1e-3 rad (L-inf) of a joint goal, or, for a pose goal, within 1 mm and 0.01 rad of it at
  `panda_hand`; first and last velocities (when given) below 1e-4 rad/s ("at rest").
"""

from __future__ import annotations

import json
import logging
import math
from collections import OrderedDict
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import coal
import numpy as np
import pinocchio as pin

from manip.benchmarking.mbm_problems import MBMProblem
from manip.benchmarking.verify_inside import InsideTest, inline_mesh, surface_meshes
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.robot_config import RobotConfig, load_robot_config
from manip.urdf import build_model

log = logging.getLogger(__name__)

#: Tolerances of the verifier (see the module docstring).
POSITION_LIMIT_TOL = 1e-6  # [rad]
START_TOL = 1e-6  # [rad] L-inf
JOINT_GOAL_TOL = 1e-3  # [rad] L-inf
POSE_GOAL_POSITION_TOL = 1e-3  # [m]
POSE_GOAL_ROTATION_TOL = 1e-2  # [rad]
REST_VELOCITY_TOL = 1e-4  # [rad/s]
REL_TOL = 1e-3  # relative slack on velocity/acceleration/jerk limits (numerical noise only)
RESOLUTION = 0.01  # [rad] L-inf distance between consecutive collision-checked configurations


@dataclass(frozen=True)
class ProblemValidity:
    """Whether a problem's start and goal are feasible for the robot model.

    Attributes:
        valid: start and goal are within the joint limits and free of self and world collision.
        codes: machine-readable reasons, e.g. ("goal_world_collision",); empty when valid.
        reasons: human-readable reasons (which joint, which pair).
    """

    valid: bool
    codes: tuple[str, ...] = ()
    reasons: tuple[str, ...] = ()


@dataclass(frozen=True)
class Verification:
    """The verdict on one trajectory and its quality metrics.

    Attributes:
        valid: every check passed.
        reasons: one line per failed check (empty when valid).
        motion_time: duration of the trajectory [s].
        path_length: sum of the joint-space (L2) lengths of its segments [rad].
        max_velocity_ratio: max over samples and joints of |v| / v_max (given and
            finite-difference velocities).
        max_acceleration: max |a| over samples and joints [rad/s^2] (given and divided differences).
        max_acceleration_ratio: max of |a| / a_max.
        max_jerk: max |j| [rad/s^3] (given and third divided differences).
        max_jerk_ratio: max of |j| / j_max.
        collision_at: time [s] of the first configuration found in collision, or None.
        collision_pair: names of the two geometries in contact there, or None.
        n_checked: number of configurations collision-checked.
        start_error: L-inf distance of the first sample to the start [rad] (nan if unchecked).
        goal_joint_error: L-inf distance of the last sample to a joint goal [rad] (nan if none).
        goal_position_error: distance to a pose goal [m] (nan if none).
        goal_rotation_error: rotation angle to a pose goal [rad] (nan if none).
    """

    valid: bool
    reasons: tuple[str, ...]
    motion_time: float = math.nan
    path_length: float = math.nan
    max_velocity_ratio: float = math.nan
    max_acceleration: float = math.nan
    max_acceleration_ratio: float = math.nan
    max_jerk: float = math.nan
    max_jerk_ratio: float = math.nan
    collision_at: float | None = None
    collision_pair: tuple[str, str] | None = None
    n_checked: int = 0
    start_error: float = math.nan
    goal_joint_error: float = math.nan
    goal_position_error: float = math.nan
    goal_rotation_error: float = math.nan


def _se3_from_pose7(pose: Any, what: str) -> pin.SE3:
    p = np.asarray(pose, dtype=float).reshape(-1)
    if p.shape != (7,) or not np.all(np.isfinite(p)):
        raise InvalidInputError(f"{what}: pose must be 7 finite numbers [x, y, z, qw, qx, qy, qz]; got {pose}")
    q = p[3:]
    n = np.linalg.norm(q)
    if n < 1e-9:
        raise InvalidInputError(f"{what}: zero quaternion in pose {pose}")
    w, x, y, z = q / n
    return pin.SE3(pin.Quaternion(w, x, y, z).matrix(), p[:3].copy())


def _capsule_frame(base: np.ndarray, tip: np.ndarray) -> pin.SE3:
    axis = tip - base
    length = np.linalg.norm(axis)
    z = np.array([0.0, 0.0, 1.0])
    if length < 1e-12:
        return pin.SE3(np.eye(3), 0.5 * (base + tip))
    u = axis / length
    R = pin.Quaternion.FromTwoVectors(z, u).matrix()
    return pin.SE3(R, 0.5 * (base + tip))


def world_geometries(world: dict) -> list[tuple[str, Any, pin.SE3]]:
    """coal shapes and placements (in the base frame) of a cuRobo-format world dict.

    Supported: cuboid (dims, pose), cylinder (radius, height, pose), sphere (radius,
    position or pose), capsule (radius, base, tip, optional pose), mesh (file_path, pose,
    optional scale).

    Raises:
        InvalidInputError: unknown object kind or malformed entry.
    """
    if hasattr(world, "to_dict") and not isinstance(world, dict):
        world = world.to_dict()
    if not isinstance(world, dict):
        raise InvalidInputError(f"world must be a dict in cuRobo's world format; got {type(world).__name__}")
    kinds = {"cuboid", "cylinder", "sphere", "capsule", "mesh"}
    out: list[tuple[str, Any, pin.SE3]] = []
    for kind, objs in world.items():
        if kind not in kinds:
            raise InvalidInputError(f"world kind '{kind}' not supported; valid: {sorted(kinds)}")
        for name, o in (objs or {}).items():
            what = f"{kind} '{name}'"
            try:
                if kind == "cuboid":
                    d = [float(v) for v in o["dims"]]
                    if len(d) != 3 or min(d) <= 0:
                        raise InvalidInputError(f"{what}: dims must be 3 positive lengths [m]; got {d}")
                    out.append((name, coal.Box(*d), _se3_from_pose7(o["pose"], what)))
                elif kind == "cylinder":
                    r, h = float(o["radius"]), float(o["height"])
                    out.append((name, coal.Cylinder(r, h), _se3_from_pose7(o["pose"], what)))
                elif kind == "sphere":
                    r = float(o["radius"])
                    if "pose" in o:
                        M = _se3_from_pose7(o["pose"], what)
                    else:
                        M = pin.SE3(np.eye(3), np.asarray(o["position"], dtype=float).reshape(3))
                    out.append((name, coal.Sphere(r), M))
                elif kind == "capsule":
                    r = float(o["radius"])
                    base = np.asarray(o["base"], dtype=float).reshape(3)
                    tip = np.asarray(o["tip"], dtype=float).reshape(3)
                    M_obj = _se3_from_pose7(o.get("pose", [0, 0, 0, 1, 0, 0, 0]), what)
                    out.append((name, coal.Capsule(r, float(np.linalg.norm(tip - base))), M_obj * _capsule_frame(base, tip)))
                elif kind == "mesh":
                    scale = np.asarray(o.get("scale", [1.0, 1.0, 1.0]), dtype=float).reshape(-1)
                    if scale.size == 1:
                        scale = np.repeat(scale, 3)
                    if "vertices" in o:  # given inline (`Mesh.to_dict` of a mesh built from arrays)
                        bvh = inline_mesh(o["vertices"], o["faces"], scale, what)
                    else:
                        bvh = coal.MeshLoader().load(str(Path(o["file_path"]).expanduser()), scale)
                    out.append((name, bvh, _se3_from_pose7(o["pose"], what)))
            except (KeyError, TypeError, ValueError) as exc:
                if isinstance(exc, InvalidInputError):
                    raise
                raise InvalidInputError(f"{what}: malformed entry {o!r} ({exc})") from None
    return out


@dataclass
class _WorldModel:
    gm: pin.GeometryModel
    gd: pin.GeometryData
    bp: Any  # pin.BroadPhaseManager_DynamicAABBTreeCollisionManager over gm/gd
    inside: InsideTest  # parts wholly inside another part's closed mesh (which coal does not see)
    surfaces: set[int]  # geometry ids of the world's surface meshes (nothing is inside them)


class Verifier:
    """Exact-mesh collision, limit and goal checks for one robot.

    Args:
        robot: robot name or `RobotConfig` (default: "franka").
        resolution: max L-inf distance between consecutive collision-checked configurations [rad].
        world_cache: how many worlds to keep built (a world's geometry is rebuilt otherwise).
    """

    def __init__(self, robot: str | RobotConfig = "franka", resolution: float = RESOLUTION, world_cache: int = 4):
        if resolution <= 0:
            raise InvalidInputError(f"resolution must be > 0 rad; got {resolution}")
        self.config = robot if isinstance(robot, RobotConfig) else load_robot_config(robot)
        self.resolution = float(resolution)
        c = self.config
        self.model = build_model(c.urdf_path)  # continuous joints made revolute, as Kinematics
        self.data = self.model.createData()
        self._robot_geom = pin.buildGeomFromUrdf(
            self.model, str(c.urdf_path), pin.COLLISION, package_dirs=list(c.package_dirs)
        )
        self._robot_geom.addAllCollisionPairs()
        # the config's disabled pairs: the SRDF's (or the adjacent links without one) + the yaml's
        disabled = {frozenset(p) for p in c.disabled_collision_pairs}
        links = [self.model.frames[g.parentFrame].name for g in self._robot_geom.geometryObjects]
        self._self_pairs = [(p.first, p.second) for p in self._robot_geom.collisionPairs
                            if frozenset((links[p.first], links[p.second])) not in disabled]
        self._n_robot = self._robot_geom.ngeoms
        # configuration template: arm joints set per call, the rest (fingers) at planning positions
        self._q0 = pin.neutral(self.model)
        self._arm_idx = np.array([self.model.joints[self.model.getJointId(j)].idx_q for j in c.arm_joints])
        if c.gripper is not None:
            for j, v in zip(c.gripper.joints, c.gripper.planning_positions):
                self._q0[self.model.joints[self.model.getJointId(j)].idx_q] = v
        self.lower = c.lower_limits.copy()
        self.upper = c.upper_limits.copy()
        self._ee_frame = self.model.getFrameId(c.ee_link)
        self._worlds: OrderedDict[str, _WorldModel] = OrderedDict()
        self._world_cache = max(1, int(world_cache))
        self._empty = self._build_world({})

    # ------------------------------------------------------------------ world models
    def _build_world(self, world: dict) -> _WorldModel:
        gm = self._robot_geom.copy()
        gm.removeAllCollisionPairs()
        for a, b in self._self_pairs:
            gm.addCollisionPair(pin.CollisionPair(a, b))
        for name, shape, M in world_geometries(world):
            gid = gm.addGeometryObject(pin.GeometryObject(f"world/{name}", 0, 0, M, shape))
            for r in range(self._n_robot):
                gm.addCollisionPair(pin.CollisionPair(r, gid))
        gd = gm.createData()
        # The broadphase manager keeps raw pointers to gm and gd: _WorldModel keeps them alive.
        bp = pin.BroadPhaseManager_DynamicAABBTreeCollisionManager(self.model, gm, gd)
        surfaces = {gm.getGeometryId(f"world/{name}") for name in surface_meshes(world)}
        inside = InsideTest(gm, [(cp.first, cp.second) for cp in gm.collisionPairs], surfaces=surfaces)
        return _WorldModel(gm, gd, bp, inside, surfaces)

    def _world(self, world: dict | None) -> _WorldModel:
        if not world:
            return self._empty
        if hasattr(world, "to_dict") and not isinstance(world, dict):
            world = world.to_dict()
        key = json.dumps(world, sort_keys=True, default=str)
        hit = self._worlds.get(key)
        if hit is not None:
            self._worlds.move_to_end(key)
            return hit
        built = self._build_world(world)
        self._worlds[key] = built
        while len(self._worlds) > self._world_cache:
            self._worlds.popitem(last=False)
        return built

    def _full_q(self, q: np.ndarray) -> np.ndarray:
        full = self._q0.copy()
        full[self._arm_idx] = q
        return full

    def _first_contact(self, gm: pin.GeometryModel, gd: pin.GeometryData) -> tuple[str, str]:
        for k, cp in enumerate(gm.collisionPairs):
            if gd.collisionResults[k].isCollision():
                return gm.geometryObjects[cp.first].name, gm.geometryObjects[cp.second].name
        return ("?", "?")  # pragma: no cover

    def in_collision(self, q: np.ndarray, world: dict | None = None) -> tuple[str, str] | None:
        """The first pair in contact at arm configuration `q` (7,), or None when free.

        Every active pair is tested (no broadphase).
        """
        w = self._world(world)
        if pin.computeCollisions(self.model, self.data, w.gm, w.gd, self._full_q(np.asarray(q, float)), True):
            return self._first_contact(w.gm, w.gd)
        return w.inside.first(w.gd)

    def first_collision(
        self, Q: np.ndarray, world: dict | None = None, broadphase: bool = True
    ) -> tuple[int, tuple[str, str]] | None:
        """Index of the first configuration of `Q` (N, 7) in collision and the pair, or None.

        Args:
            Q: (N, 7) arm configurations [rad].
            world: obstacles (cuRobo world dict) or None.
            broadphase: screen each configuration with coal's dynamic AABB tree (about 7x
                faster on MBM scenes); a configuration the screen flags is confirmed by
                testing every pair. False tests every pair of every configuration.
        """
        w = self._world(world)
        Qf = np.repeat(self._q0[None, :], len(Q), axis=0)
        Qf[:, self._arm_idx] = Q
        model, data, cc = self.model, self.data, pin.computeCollisions
        gm, gd, bp = w.gm, w.gd, w.bp
        for i in range(len(Qf)):
            if not (broadphase and not cc(model, data, bp, Qf[i], True)) and cc(model, data, gm, gd, Qf[i], True):
                return i, self._first_contact(gm, gd)
            pin.updateGeometryPlacements(model, data, gm, gd, Qf[i])
            inside = w.inside.first(gd)
            if inside is not None:
                return i, inside
        return None

    # ------------------------------------------------------------------ helpers
    def densify(self, times: np.ndarray, positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Samples plus linear interpolations so consecutive configurations differ by <= resolution.

        Returns:
            (t (M,), Q (M, 7)) including every original sample.
        """
        d = np.abs(np.diff(positions, axis=0)).max(axis=1) if len(positions) > 1 else np.zeros(0)
        n = np.maximum(1, np.ceil(d / self.resolution - 1e-12).astype(int))
        seg = np.repeat(np.arange(len(n)), n)
        frac = np.concatenate([np.arange(k) / k for k in n]) if len(n) else np.zeros(0)
        Q = positions[seg] + frac[:, None] * (positions[seg + 1] - positions[seg])
        t = times[seg] + frac * (times[seg + 1] - times[seg])
        Q = np.vstack([Q, positions[-1:]])
        t = np.concatenate([t, times[-1:]])
        return t, Q

    def hand_pose_error(self, q: np.ndarray, goal: Pose) -> tuple[float, float]:
        """(position error [m], rotation error [rad]) of `ee_link` at `q` to `goal`."""
        pin.framesForwardKinematics(self.model, self.data, self._full_q(q))
        M = self.data.oMf[self._ee_frame]
        gp = np.asarray(goal.position, dtype=float).reshape(3)
        w, x, y, z = np.asarray(goal.quaternion, dtype=float).reshape(4)
        R_goal = pin.Quaternion(w, x, y, z).normalized().matrix()
        pos_err = float(np.linalg.norm(M.translation - gp))
        rot_err = float(np.linalg.norm(pin.log3(R_goal.T @ M.rotation)))
        return pos_err, rot_err

    # ------------------------------------------------------------------ problems
    def check_configuration(self, q: np.ndarray, world: dict | None, label: str) -> tuple[list[str], list[str]]:
        """Codes and reasons why `q` is infeasible (limits, self collision, world collision)."""
        codes: list[str] = []
        reasons: list[str] = []
        q = np.asarray(q, dtype=float)
        bad = [
            f"{n}={v:.4f} not in [{lo:.4f}, {hi:.4f}]"
            for n, v, lo, hi in zip(self.config.arm_joints, q, self.lower, self.upper)
            if v < lo - POSITION_LIMIT_TOL or v > hi + POSITION_LIMIT_TOL
        ]
        if bad:
            codes.append(f"{label}_joint_limits")
            reasons.append(f"{label} outside joint limits: {', '.join(bad)}")
        w = self._world(world)
        gm, gd = w.gm, w.gd
        pin.computeCollisions(self.model, self.data, gm, gd, self._full_q(q), False)
        self_hits, world_hits = [], []
        for k, cp in enumerate(gm.collisionPairs):
            if gd.collisionResults[k].isCollision():
                a, b = gm.geometryObjects[cp.first].name, gm.geometryObjects[cp.second].name
                (world_hits if b.startswith("world/") else self_hits).append(f"{a}-{b}")
        inside = w.inside.first(gd)  # placements updated by computeCollisions
        if inside is not None:
            hits = world_hits if "world/" in inside[0] + inside[1] else self_hits
            hits.append(f"{inside[0]}-{inside[1]} (wholly inside)")
        if self_hits:
            codes.append(f"{label}_self_collision")
            reasons.append(f"{label} in self collision: {', '.join(self_hits)}")
        if world_hits:
            codes.append(f"{label}_world_collision")
            reasons.append(f"{label} in world collision: {', '.join(world_hits)}")
        return codes, reasons

    def check_problem(self, problem: MBMProblem) -> ProblemValidity:
        """Whether the start and the goal of `problem` are feasible (limits, self, world)."""
        c1, r1 = self.check_configuration(problem.start, problem.world, "start")
        c2, r2 = self.check_configuration(problem.goal, problem.world, "goal")
        return ProblemValidity(not (c1 or c2), tuple(c1 + c2), tuple(r1 + r2))

    # ------------------------------------------------------------------ trajectories
    def verify_trajectory(
        self,
        problem_or_world: MBMProblem | dict | None,
        times: np.ndarray,
        positions: np.ndarray,
        velocities: np.ndarray | None = None,
        accelerations: np.ndarray | None = None,
        jerks: np.ndarray | None = None,
        *,
        start_q: np.ndarray | None = None,
        goal_q: np.ndarray | None = None,
        goal_pose: Pose | None = None,
        check_jerk: bool = False,
        broadphase: bool = True,
        velocity_limits: np.ndarray | None = None,
        acceleration_limits: np.ndarray | None = None,
        jerk_limits: np.ndarray | None = None,
    ) -> Verification:
        """Judge a time-parameterised joint trajectory (see the module docstring for the checks).

        Args:
            problem_or_world: an `MBMProblem` (its world, its start and, unless `goal_pose`
                or `goal_q` is given, its joint goal) or a world dict in cuRobo's format.
            times: (T,) strictly increasing sample times [s].
            positions: (T, 7) arm configurations [rad].
            velocities: (T, 7) [rad/s], optional.
            accelerations: (T, 7) [rad/s^2], optional.
            jerks: (T, 7) [rad/s^3], optional.
            start_q: (7,) the start the trajectory must begin at (default: the problem's).
            goal_q: (7,) joint goal (default: the problem's unless `goal_pose` is given).
            goal_pose: pose goal for `ee_link` (panda_hand) in the base frame.
            check_jerk: also fail trajectories whose jerk exceeds the jerk limits.
            broadphase: screen configurations with an AABB tree first (see `first_collision`).
            velocity_limits, acceleration_limits, jerk_limits: (7,) overrides of the
                robot configuration's limits.

        Returns:
            A `Verification`; `valid` is False with reasons for any violated check.
        """
        if isinstance(problem_or_world, MBMProblem):
            world = problem_or_world.world
            if start_q is None:
                start_q = problem_or_world.start
            if goal_q is None and goal_pose is None:
                goal_q = problem_or_world.goal
        else:
            world = problem_or_world
        c = self.config
        vmax = np.asarray(c.velocity_limits if velocity_limits is None else velocity_limits, dtype=float)
        amax = np.asarray(c.acceleration_limits if acceleration_limits is None else acceleration_limits, dtype=float)
        jmax = np.asarray(c.jerk_limits if jerk_limits is None else jerk_limits, dtype=float)
        dof = c.dof

        reasons: list[str] = []
        t = np.asarray(times, dtype=float).reshape(-1) if times is not None else np.zeros(0)
        P = np.asarray(positions, dtype=float) if positions is not None else np.zeros((0, dof))
        if P.ndim != 2 or P.shape[1] != dof or len(P) < 1 or len(t) != len(P):
            return Verification(False, (f"malformed trajectory: times {t.shape}, positions {P.shape}; need (T,) and (T, {dof})",))
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(P))):
            return Verification(False, ("trajectory has non-finite times or positions",))
        if len(t) > 1 and np.any(np.diff(t) <= 0):
            return Verification(False, ("times are not strictly increasing",))

        arrays = {}
        for nm, a in (("velocities", velocities), ("accelerations", accelerations), ("jerks", jerks)):
            if a is None:
                continue
            a = np.asarray(a, dtype=float)
            if a.shape != P.shape or not np.all(np.isfinite(a)):
                reasons.append(f"{nm} malformed or non-finite: shape {a.shape}, need {P.shape}")
                continue
            arrays[nm] = a

        motion_time = float(t[-1] - t[0])
        path_length = float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum()) if len(P) > 1 else 0.0

        # ---- position limits
        lo_v = P < self.lower - POSITION_LIMIT_TOL
        hi_v = P > self.upper + POSITION_LIMIT_TOL
        if lo_v.any() or hi_v.any():
            i, j = np.argwhere(lo_v | hi_v)[0]
            reasons.append(
                f"position limit: {c.arm_joints[j]}={P[i, j]:.6f} at t={t[i]:.3f}s not in [{self.lower[j]:.4f}, {self.upper[j]:.4f}]"
            )

        # ---- derivatives: divided differences (lower bounds on the true maxima) and given arrays
        dt = np.diff(t)
        # divided differences: d1 = [q_i, q_i+1], d2 = [q_i..q_i+2], d3 = [q_i..q_i+3];
        # k! * d_k equals the k-th derivative somewhere in the interval (mean value theorem).
        d1 = np.diff(P, axis=0) / dt[:, None] if len(P) > 1 else np.zeros((0, dof))
        d2 = np.diff(d1, axis=0) / (t[2:] - t[:-2])[:, None] if len(P) > 2 else np.zeros((0, dof))
        d3 = np.diff(d2, axis=0) / (t[3:] - t[:-3])[:, None] if len(P) > 3 else np.zeros((0, dof))
        v_fd, a_fd, j_fd = d1, 2.0 * d2, 6.0 * d3

        def _max_abs(*arrs: np.ndarray) -> np.ndarray:
            m = np.zeros(dof)
            for a in arrs:
                if a is not None and len(a):
                    m = np.maximum(m, np.abs(a).max(axis=0))
            return m

        v_abs = _max_abs(v_fd, arrays.get("velocities"))
        a_abs = _max_abs(a_fd, arrays.get("accelerations"))
        j_abs = _max_abs(j_fd, arrays.get("jerks"))
        v_ratio = float((v_abs / vmax).max())
        a_ratio = float((a_abs / amax).max())
        j_ratio = float((j_abs / jmax).max())
        for label, ratio, absval, lim, unit in (
            ("velocity", v_ratio, v_abs, vmax, "rad/s"),
            ("acceleration", a_ratio, a_abs, amax, "rad/s^2"),
        ):
            if ratio > 1.0 + REL_TOL:
                j = int(np.argmax(absval / lim))
                reasons.append(f"{label} limit: {c.arm_joints[j]} reaches {absval[j]:.4g} {unit} > {lim[j]:.4g} ({ratio:.3f}x)")
        if check_jerk and j_ratio > 1.0 + REL_TOL:
            j = int(np.argmax(j_abs / jmax))
            reasons.append(f"jerk limit: {c.arm_joints[j]} reaches {j_abs[j]:.4g} rad/s^3 > {jmax[j]:.4g} ({j_ratio:.3f}x)")

        # ---- endpoints
        start_err = math.nan
        if start_q is not None:
            start_err = float(np.abs(P[0] - np.asarray(start_q, dtype=float)).max())
            if start_err > START_TOL:
                reasons.append(f"does not start at start_q: L-inf error {start_err:.3g} rad > {START_TOL:g}")
        if "velocities" in arrays:
            V = arrays["velocities"]
            v0, v1 = float(np.abs(V[0]).max()), float(np.abs(V[-1]).max())
            if v0 > REST_VELOCITY_TOL:
                reasons.append(f"does not start at rest: |v|={v0:.3g} rad/s")
            if v1 > REST_VELOCITY_TOL:
                reasons.append(f"does not end at rest: |v|={v1:.3g} rad/s")
        goal_err = pos_err = rot_err = math.nan
        if goal_q is not None:
            goal_err = float(np.abs(P[-1] - np.asarray(goal_q, dtype=float)).max())
            if goal_err > JOINT_GOAL_TOL:
                reasons.append(f"joint goal missed: L-inf error {goal_err:.3g} rad > {JOINT_GOAL_TOL:g}")
        if goal_pose is not None:
            pos_err, rot_err = self.hand_pose_error(P[-1], goal_pose)
            if pos_err > POSE_GOAL_POSITION_TOL or rot_err > POSE_GOAL_ROTATION_TOL:
                reasons.append(
                    f"pose goal missed at {c.ee_link}: {pos_err * 1e3:.2f} mm, {rot_err:.4f} rad "
                    f"(tolerance {POSE_GOAL_POSITION_TOL * 1e3:g} mm, {POSE_GOAL_ROTATION_TOL:g} rad)"
                )

        # ---- dense exact collision check
        td, Qd = self.densify(t, P)
        hit = self.first_collision(Qd, world, broadphase=broadphase)
        col_t, col_pair = None, None
        n_checked = len(Qd)
        if hit is not None:
            i, col_pair = hit
            col_t = float(td[i])
            n_checked = i + 1
            reasons.append(f"collision at t={col_t:.3f}s: {col_pair[0]} - {col_pair[1]}")

        return Verification(
            valid=not reasons,
            reasons=tuple(reasons),
            motion_time=motion_time,
            path_length=path_length,
            max_velocity_ratio=v_ratio,
            max_acceleration=float(a_abs.max()),
            max_acceleration_ratio=a_ratio,
            max_jerk=float(j_abs.max()),
            max_jerk_ratio=j_ratio,
            collision_at=col_t,
            collision_pair=col_pair,
            n_checked=n_checked,
            start_error=start_err,
            goal_joint_error=goal_err,
            goal_position_error=pos_err,
            goal_rotation_error=rot_err,
        )


@lru_cache(maxsize=1)
def default_verifier() -> Verifier:
    """The shared Franka `Verifier` (built on first use)."""
    return Verifier("franka")


def check_problem(problem: MBMProblem) -> ProblemValidity:
    """`default_verifier().check_problem(problem)`: feasibility of a problem's start and goal."""
    return default_verifier().check_problem(problem)


def verify_trajectory(problem_or_world: MBMProblem | dict | None, times: np.ndarray, positions: np.ndarray, **kwargs: Any) -> Verification:
    """`default_verifier().verify_trajectory(...)`; see `Verifier.verify_trajectory`."""
    return default_verifier().verify_trajectory(problem_or_world, times, positions, **kwargs)
