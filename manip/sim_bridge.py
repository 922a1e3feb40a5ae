"""The planner's seam with the simulator, duck-typed over `manip.sim` (never imported).

* `world_config_from_sim`: a simulated World's collision shapes as a planner `WorldConfig`
  (it calls `world.scene.get_collision_objects()` and `robot.get_world_pose()`).
* `joint_indices_for`, `trajectory_to_actions`: a timed `Trajectory` as the robot's DoF
  indices and one `ArticulationAction` per step (the robot has `dof_names` and/or
  `get_dof_index(name)`; the trajectory is read through its attributes only, so this
  module does not import `manip.trajectory`, which delegates to it).
* `robot_columns`: which joints of a multi-arm robot's trajectory (`left_panda_joint1`, ...)
  drive one simulated robot (`panda_joint1`, ...): Isaac's multi-robot pattern, one prim and
  one controller per arm, each given its own ArticulationActions.
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
    return any(name.startswith(p) or prim_path.startswith(p) for p in ignore)


def _check_ignore(world, ignore) -> tuple[str, ...]:
    """`ignore` as a tuple of non-empty strings (one string is one entry), each the start of the
    name or prim path of something in the World (a scene object or a prim on its stage).

    Raises:
        InvalidInputError: an entry that is not a non-empty string (a string that is not in a
            list would otherwise be read letter by letter: "/World/cube" ignored everything).
        UnknownNameError: an entry that names nothing in the World (a typo would leave the
            object to pick as an obstacle, or, as a prefix, drop other objects silently).
    """
    entries = (ignore,) if isinstance(ignore, str) else tuple(ignore or ())
    for p in entries:
        if not isinstance(p, str) or not p:
            raise InvalidInputError(f"ignore: each entry must be a non-empty name or prim path (str); got {p!r} "
                                    f"in {ignore!r}")
    known = set()
    scene = getattr(world, "scene", None)
    for n in (scene.get_object_names() if hasattr(scene, "get_object_names") else []):
        known.add(n)
        known.add(getattr(scene.get_object(n), "prim_path", n))
    stage = getattr(scene, "stage", None)
    known.update(getattr(prim, "prim_path", "") for prim in (stage.prims() if hasattr(stage, "prims") else []))
    known.update(o.name for o in scene.get_collision_objects())
    known.update(o.prim_path for o in scene.get_collision_objects())
    for p in entries:
        if not any(k.startswith(p) for k in known if k):
            raise UnknownNameError("ignore: object name or prim path", p,
                                   sorted(k for k in known if k and not k.startswith("__")))
    return entries


def world_config_from_sim(world, robot, ignore: Sequence[str] = (), *, base_in_robot: Pose | None = None) -> WorldConfig:
    """Every collision object of `world`, in `robot`'s base frame, as a WorldConfig.

    Args:
        world: a `manip.sim.World` after `reset()`.
        robot: the planned robot (its own geoms are skipped; other robots are obstacles), or a
            list of the simulated robots that are its arms (a multi-arm robot, `manip.robot_arms`:
            all are skipped; the frame is the first one's, moved by `base_in_robot`).
        ignore: names or prim-path prefixes to leave out (e.g. the object to pick); one
            string or a sequence of them, each naming something in the World.
        base_in_robot: the planner's base frame in the (first) robot's frame (default: the same).

    Ellipsoids become their bounding sphere (conservative); cones and meshes become meshes;
    planes become large boxes under their surface. The ground the robot stands on need not
    be ignored: an obstacle wholly below the robot's base frame is not checked against the
    links fixed to the base (`ObstacleTables.below_base`), only against the moving ones.

    Raises:
        InvalidInputError: before the world's first `reset()` (the robot's pose is unknown); a
            `robot` that is not an articulation; an `ignore` entry that is not a non-empty string.
        UnknownNameError: an `ignore` entry that starts no name or prim path in the World.
    """
    robots = list(robot) if isinstance(robot, (list, tuple)) else [robot]
    for r in robots:
        if not hasattr(r, "dof_names") or not callable(getattr(r, "get_world_pose", None)):
            raise InvalidInputError(f"robot must be the simulated robot the planner plans for (an Articulation / "
                                    f"Robot with joints), or a list of them; got {type(r).__name__} "
                                    f"{getattr(r, 'name', r)!r}")
    robot = robots[0]
    robot_pose = robot.get_world_pose()
    if robot_pose is None or getattr(world, "model", True) is None:  # a robot's pose is known before, the world not
        raise InvalidInputError(
            f"robot {getattr(robot, 'name', robot)!r}: its pose is not known before the world's first reset(); "
            "call world.reset() before reading the world (update_world_from_sim)")
    position, orientation = robot_pose
    T_world_robot = Pose(np.asarray(position, dtype=float), np.asarray(orientation, dtype=float))
    T_base_world = (T_world_robot if base_in_robot is None else T_world_robot @ base_in_robot).inverse()
    ignore = _check_ignore(world, ignore)
    robot_paths = {getattr(r, "prim_path", None) for r in robots}
    cfg = WorldConfig()
    used: set[str] = set()
    for obj in world.scene.get_collision_objects():
        if obj.is_robot and obj.robot_prim_path in robot_paths:
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


def _identities(robot: Any) -> list[str]:
    """The robot's name and the last segment of its prim path, lower case (what names its arm)."""
    out = [str(getattr(robot, "name", "") or ""), str(getattr(robot, "prim_path", "") or "").rsplit("/", 1)[-1]]
    return [i.lower() for i in out if i]


def robot_columns(trajectory: Any, robot: Any, prefix: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(columns, indices): the trajectory's joints that drive `robot`, and the robot's DoF index of each.

    A trajectory whose joints are all the robot's DoFs drives it whole. A multi-arm robot's
    trajectory (`manip.robot_arms`: `left_panda_joint1`, ..., `right_panda_joint1`, ...) drives
    one simulated robot per arm: the joints `prefix + <DoF name>`. Without `prefix`, the arm
    is the one whose prefix names the robot: its `name` or its prim path's last segment is the
    prefix or starts with it ("left", "left_franka", "/World/left_franka" for "left_").

    Raises:
        UnknownNameError: a joint matches no DoF of the robot, or `prefix` is no arm's.
        InvalidInputError: several arms' joints fit the robot and its name names none of them
            (pass `prefix=`); `robot` has neither `dof_names` nor `get_dof_index`.
    """
    names = [str(n) for n in trajectory.joint_names]
    dof_names = getattr(robot, "dof_names", None)
    dof_names = None if dof_names is None or callable(dof_names) else [str(n) for n in dof_names]
    if prefix is None and (dof_names is None or all(n in dof_names for n in names)):
        return np.arange(len(names)), joint_indices_for(trajectory, robot)
    if dof_names is None:
        raise InvalidInputError(f"robot must have a `dof_names` list to take one arm's joints; got {type(robot).__name__}")
    groups: dict[str, list[int]] = {}
    for c, n in enumerate(names):
        for d in dof_names:
            if n.endswith(d) and len(n) > len(d):
                groups.setdefault(n[: -len(d)], []).append(c)
    if prefix is None:
        if not groups:
            raise UnknownNameError("joint", next(n for n in names if n not in dof_names), dof_names)
        ids = _identities(robot)
        match = [p for p in groups if any(i == p.rstrip("_").lower() or i.startswith(p.lower()) for i in ids)]
        if len(groups) > 1 and len(match) != 1:
            raise InvalidInputError(
                f"robot {getattr(robot, 'name', robot)!r}: the trajectory holds the joints of the arms "
                f"{sorted(groups)}; name the robot after its arm (name='left_franka' for 'left_') or pass prefix=")
        prefix = match[0] if match else next(iter(groups))
    if prefix not in groups:
        raise UnknownNameError("prefix (an arm of the trajectory)", prefix, groups)
    cols = [c for c in range(len(names)) if names[c].startswith(prefix) and names[c][len(prefix):] in dof_names]
    return np.asarray(cols, dtype=int), np.asarray([dof_names.index(names[c][len(prefix):]) for c in cols], dtype=int)


def trajectory_to_actions(trajectory: Any, robot: Any, physics_dt: float | None = None, *,
                          prefix: str | None = None) -> list[ArticulationAction]:
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
        prefix: the arm of a multi-arm robot's trajectory that drives `robot` (default: the
            one its name names; `robot_columns`).

    Returns:
        T - 1 actions with `joint_positions` [rad], `joint_velocities` [rad/s] and
        `joint_indices` (the robot's indices of `joint_names`).

    Raises:
        UnknownNameError: a joint of the trajectory is not a DoF of the robot.
    """
    traj = trajectory if physics_dt is None else trajectory.resample(physics_dt)
    cols, idx = robot_columns(trajectory, robot, prefix)
    return [
        ArticulationAction(joint_positions=traj.positions[k, cols], joint_velocities=traj.velocities[k, cols],
                           joint_indices=idx)
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
