"""The planner's seam with the simulator, duck-typed over `manip.sim` (never imported).

* `world_config_from_sim`: a simulated World's collision shapes as a planner `WorldConfig`
  (it calls `world.scene.get_collision_objects()` and `robot.get_world_pose()`).
* `joint_indices_for`, `trajectory_to_actions`: a timed `Trajectory` as the robot's DoF
  indices and one `ArticulationAction` per step (the robot has `dof_names` and/or
  `get_dof_index(name)`; the trajectory is read through its attributes only, so this
  module does not import `manip.trajectory`, which delegates to it).
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.collision import Capsule, Cuboid, Cylinder, Mesh, Sphere, WorldConfig
from manip.errors import InvalidInputError, UnknownNameError
from manip.pose import Pose

logger = logging.getLogger(__name__)

#: Planes become boxes this large [m] (x, y) and thick (z), their top face on the plane.
PLANE_SIZE = 20.0
PLANE_THICKNESS = 0.1


def _ignored(name: str, prim_path: str, ignore: Sequence[str]) -> bool:
    return any(name.startswith(p) or prim_path.startswith(p) for p in ignore if p)


def world_config_from_sim(world, robot, ignore: Sequence[str] = ()) -> WorldConfig:
    """Every collision object of `world`, in `robot`'s base frame, as a WorldConfig.

    Args:
        world: a `manip.sim.World` after `reset()`.
        robot: the planned robot (its own geoms are skipped; other robots are obstacles).
        ignore: names or prim-path prefixes to leave out (e.g. the object to pick).

    Ellipsoids become their bounding sphere (conservative); cones and meshes become meshes;
    planes become large boxes under their surface. The ground the robot stands on need not
    be ignored: an obstacle wholly below the robot's base frame is not checked against the
    links fixed to the base (`ObstacleTables.below_base`), only against the moving ones.

    Raises:
        InvalidInputError: before the world's first `reset()` (the robot's pose is unknown).
    """
    robot_pose = robot.get_world_pose()
    if robot_pose is None or getattr(world, "model", True) is None:  # a robot's pose is known before, the world not
        raise InvalidInputError(
            f"robot {getattr(robot, 'name', robot)!r}: its pose is not known before the world's first reset(); "
            "call world.reset() before reading the world (update_world_from_sim)")
    position, orientation = robot_pose
    T_base_world = Pose(np.asarray(position, dtype=float), np.asarray(orientation, dtype=float)).inverse()
    robot_path = getattr(robot, "prim_path", None)
    cfg = WorldConfig()
    used: set[str] = set()
    for obj in world.scene.get_collision_objects():
        if obj.is_robot and obj.robot_prim_path == robot_path:
            continue
        if _ignored(obj.name, obj.prim_path, ignore):
            continue
        pose = T_base_world @ obj.pose
        name = obj.name
        k = 1
        while name in used:  # one scene object may own several geoms
            k += 1
            name = f"{obj.name}#{k}"
        used.add(name)
        dims = np.asarray(obj.dimensions, dtype=float)
        if obj.shape == "cuboid":
            cfg.add(Cuboid(name, dims, pose))
        elif obj.shape == "sphere":
            cfg.add(Sphere(name, float(dims[0]), pose))
        elif obj.shape == "cylinder":
            cfg.add(Cylinder(name, float(dims[0]), float(dims[1]), pose))
        elif obj.shape == "capsule":
            cfg.add(Capsule(name, float(dims[0]), float(dims[1]), pose))
        elif obj.shape == "ellipsoid":
            cfg.add(Sphere(name, float(np.max(dims)), pose))
        elif obj.shape in ("mesh", "cone"):
            if obj.vertices is None or obj.faces is None:
                logger.warning("skipping %s: mesh without vertices", name)
                continue
            cfg.add(Mesh(name, pose=pose, vertices=obj.vertices, faces=obj.faces))
        elif obj.shape == "plane":
            box = Pose(np.array([0.0, 0.0, -PLANE_THICKNESS / 2]))
            cfg.add(Cuboid(name, [PLANE_SIZE, PLANE_SIZE, PLANE_THICKNESS], pose @ box))
        else:
            logger.warning("skipping %s: unsupported shape %r", name, obj.shape)
    return cfg


def joint_indices_for(trajectory: Any, robot: Any) -> np.ndarray:
    """(dof,) indices of `trajectory.joint_names` among a robot's degrees of freedom.

    Args:
        trajectory: a `manip.Trajectory` (only `joint_names` is read).
        robot: duck-typed: a `dof_names` sequence (Isaac's `Articulation` and `manip.sim`
            robots have one) and/or a `get_dof_index(name)` method.

    Raises:
        UnknownNameError: a joint of the trajectory is not a DoF of the robot (the
            message lists the robot's DoFs).
        InvalidInputError: `robot` has neither `dof_names` nor `get_dof_index`.
    """
    dof_names = getattr(robot, "dof_names", None)
    if dof_names is not None and not callable(dof_names):
        names = [str(n) for n in dof_names]
        out = []
        for n in trajectory.joint_names:
            if n not in names:
                raise UnknownNameError("joint", n, names)
            out.append(names.index(n))
        return np.asarray(out, dtype=int)
    getter = getattr(robot, "get_dof_index", None)
    if getter is None:
        raise InvalidInputError(
            f"robot must have a `dof_names` list or a `get_dof_index(name)` method; got {type(robot).__name__}"
        )
    out = []
    for n in trajectory.joint_names:
        try:
            i = getter(n)
        except (KeyError, ValueError, IndexError):
            i = None
        if i is None or int(i) < 0:
            raise UnknownNameError("joint", n, [])
        out.append(int(i))
    return np.asarray(out, dtype=int)


def trajectory_to_actions(trajectory: Any, robot: Any, physics_dt: float | None = None) -> list[ArticulationAction]:
    """One `ArticulationAction` per step of `trajectory`, for a simulated robot.

    The actions are for the samples after t = 0 (the robot is assumed to be at the start
    already), so applying one action per step of period `trajectory.dt` replays the
    trajectory. With `physics_dt` given, the trajectory is first resampled at the
    simulator's step, giving one action per physics step.

    Args:
        trajectory: a `manip.Trajectory` (`joint_names`, `positions`, `velocities`,
            `num_samples`, `resample(dt)` are used).
        robot: duck-typed articulation with `dof_names` and/or `get_dof_index(name)`.
        physics_dt: the simulator's step [s]; None uses the trajectory's `dt`.

    Returns:
        T - 1 actions with `joint_positions` [rad], `joint_velocities` [rad/s] and
        `joint_indices` (the robot's indices of `joint_names`).

    Raises:
        UnknownNameError: a joint of the trajectory is not a DoF of the robot.
    """
    traj = trajectory if physics_dt is None else trajectory.resample(physics_dt)
    idx = joint_indices_for(trajectory, robot)
    return [
        ArticulationAction(joint_positions=traj.positions[k], joint_velocities=traj.velocities[k], joint_indices=idx)
        for k in range(1, traj.num_samples)
    ]


def solution_arrays(solution: dict) -> tuple[list[str], np.ndarray, np.ndarray]:
    """(joint_names, positions (T, dof), velocities (T, dof)) of a tutorial solution dict.

    Args:
        solution: {"joint_names", "positions", "velocities", ...} (per-step lists), as
            `TutorialMotionGen.motion_generate` returns.

    Raises:
        InvalidInputError: the solution is None (a failed `motion_generate`) or not a
            dict, lacks a key, or its arrays disagree in shape.
    """
    if solution is None:
        raise InvalidInputError(
            "solution is None: motion_generate returns None when planning fails (the log says why); "
            "check `if solution is not None` before converting it to actions")
    if not isinstance(solution, Mapping):
        raise InvalidInputError(
            f"solution must be the dict motion_generate returns; got {type(solution).__name__}")
    missing = [k for k in ("joint_names", "positions", "velocities") if k not in solution]
    if missing:
        raise InvalidInputError(f"solution lacks {missing}; it needs joint_names, positions, velocities")
    names = list(solution["joint_names"])
    positions = np.asarray(solution["positions"], dtype=float)
    velocities = np.asarray(solution["velocities"], dtype=float)
    if positions.ndim != 2 or positions.shape[1] != len(names) or velocities.shape != positions.shape:
        raise InvalidInputError(
            f"solution positions and velocities must both have shape (T, {len(names)}); "
            f"got {positions.shape} and {velocities.shape}"
        )
    return names, positions, velocities
