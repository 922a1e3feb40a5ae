"""Helpers shared by the peer adapters: world parsing, goal poses, trajectory sampling.

Nothing here plans; it only turns the benchmark's inputs (cuRobo-format worlds, MBM
problems) into plain NumPy data each peer can consume, and a peer's time-parameterised
trajectory into the `PlannerOutput` arrays.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np

from manip.errors import InvalidInputError
from manip.pose import Pose

log = logging.getLogger(__name__)

#: Sample period of every returned trajectory [s].
SAMPLE_DT = 0.01
#: Edge collision-check resolution used by every peer [rad] (joint-space L2 step).
EDGE_RESOLUTION = 0.01
#: Default planning budget per problem [s] (RRT-Connect only; IK has its own budget).
DEFAULT_TIMEOUT_S = 10.0
#: Pose-goal tolerances the peers' IK solves to: tighter than the verifier's 1 mm / 0.01 rad.
IK_POSITION_TOL = 1e-3  # [m]
IK_ROTATION_TOL = 1e-3  # [rad]
#: Finger opening assumed by every peer's collision model [m] (each finger, fully open).
FINGER_OPENING = 0.04


@dataclass(frozen=True)
class Obstacle:
    """One primitive obstacle in the robot base frame.

    Attributes:
        name: unique name within the world.
        kind: "box" or "cylinder".
        size: box: (3,) full edge lengths [m]; cylinder: (radius, height) [m] (axis along z).
        T: (4, 4) pose of the obstacle's centre in the base frame.
    """

    name: str
    kind: str
    size: tuple[float, ...]
    T: np.ndarray


def world_obstacles(world: dict[str, Any]) -> list[Obstacle]:
    """Parse a cuRobo-format world dict into obstacles.

    Args:
        world: {"cuboid": {name: {"dims": [x, y, z], "pose": [x, y, z, qw, qx, qy, qz]}},
            "cylinder": {name: {"radius": r, "height": h, "pose": [...]}}}.

    Returns:
        Obstacles in a deterministic order (cuboids then cylinders, by insertion order).

    Raises:
        InvalidInputError: an unsupported kind or a malformed entry.
    """
    if not isinstance(world, dict):
        raise InvalidInputError(f"world must be a dict in cuRobo's world format; got {type(world).__name__}")
    supported = {"cuboid", "cylinder"}
    out: list[Obstacle] = []
    for kind, objs in world.items():
        if kind not in supported:
            raise InvalidInputError(f"world kind '{kind}' is not supported by the peers; valid: {sorted(supported)}")
        for name, o in (objs or {}).items():
            try:
                pose = np.asarray(o["pose"], dtype=float).reshape(-1)
                if pose.shape != (7,) or not np.all(np.isfinite(pose)):
                    raise InvalidInputError(f"{kind} '{name}': pose must be 7 finite numbers [x, y, z, qw, qx, qy, qz]")
                T = Pose.from_xyz_wxyz(pose).as_matrix()
                if kind == "cuboid":
                    dims = tuple(float(v) for v in o["dims"])
                    if len(dims) != 3 or min(dims) <= 0:
                        raise InvalidInputError(f"cuboid '{name}': dims must be 3 positive lengths [m]; got {dims}")
                    out.append(Obstacle(str(name), "box", dims, T))
                else:
                    r, h = float(o["radius"]), float(o["height"])
                    if r <= 0 or h <= 0:
                        raise InvalidInputError(f"cylinder '{name}': radius and height must be > 0; got {r}, {h}")
                    out.append(Obstacle(str(name), "cylinder", (r, h), T))
            except (KeyError, TypeError, ValueError) as exc:
                if isinstance(exc, InvalidInputError):
                    raise
                raise InvalidInputError(f"{kind} '{name}': malformed entry {o!r} ({exc})") from None
    return out


def check_goal_kind(goal_kind: str) -> None:
    """Raise InvalidInputError unless `goal_kind` is "joint" or "pose"."""
    if goal_kind not in ("joint", "pose"):
        raise InvalidInputError(f"goal_kind must be 'joint' or 'pose'; got {goal_kind!r}")


def problem_arrays(problem: Any, joint_names: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Start and goal of an MBM problem as (7,) float arrays in `joint_names` order.

    Raises:
        InvalidInputError: wrong shapes, non-finite values or joint names that differ.
    """
    names = tuple(getattr(problem, "joint_names", joint_names))
    if names != tuple(joint_names):
        raise InvalidInputError(f"problem joint names {names} differ from the peer's {tuple(joint_names)}")
    start = np.asarray(problem.start, dtype=float).reshape(-1)
    goal = np.asarray(problem.goal, dtype=float).reshape(-1)
    for what, q in (("start", start), ("goal", goal)):
        if q.shape != (len(joint_names),) or not np.all(np.isfinite(q)):
            raise InvalidInputError(f"problem {what} must be ({len(joint_names)},) finite; got {q}")
    return start, goal


def goal_pose(problem: Any) -> Pose:
    """The pose goal of a problem at `panda_hand` (FK of its goal configuration, fingers open).

    Uses `manip.benchmarking.mbm_problems.goal_pose` when present (the driver's definition), else the
    same forward kinematics through `manip.kinematics`.
    """
    try:
        from manip.benchmarking.mbm_problems import goal_pose as _gp  # type: ignore[import-not-found]
    except ImportError:  # pragma: no cover - the driver's module not there yet
        from manip.kinematics import Kinematics
        from manip.robot_config import load_robot_config

        return Kinematics(load_robot_config("franka")).fk(np.asarray(problem.goal, dtype=float), "panda_hand")
    return _gp(problem)


def finite_difference_jerk(times: np.ndarray, accelerations: np.ndarray) -> np.ndarray:
    """Jerk [rad/s^3] of sampled accelerations by (non-uniform) central differences.

    Args:
        times: (T,) strictly increasing sample times [s].
        accelerations: (T, n) accelerations [rad/s^2].

    Returns:
        (T, n) jerks; zeros for fewer than 2 samples.
    """
    if len(times) < 2:
        return np.zeros_like(accelerations)
    return np.gradient(accelerations, times, axis=0)


def uniform_times(duration: float, dt: float = SAMPLE_DT) -> np.ndarray:
    """Sample times 0, dt, 2 dt, ..., with `duration` itself as the last sample [s]."""
    n = int(np.floor(duration / dt + 1e-9))
    t = np.arange(n + 1) * dt
    if duration - t[-1] > 1e-9:
        t = np.append(t, duration)
    return t
