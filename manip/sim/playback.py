"""Replay a planned trajectory on a simulated robot and read back what it did."""

from __future__ import annotations

import logging

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.scenes.stage import SimulationError
from manip.sim_bridge import robot_columns

logger = logging.getLogger(__name__)

#: A robot farther than this from the trajectory's start (any joint) [rad or m] gets a
#: warning: its drives jump to the first sample instead of following a planned motion.
START_TOLERANCE = 0.05


def play_trajectory(world, robot, trajectory) -> np.ndarray:
    """Drive `robot` along `trajectory`, one ArticulationAction (position and velocity
    targets) per physics step, from wherever the robot stands (normally the start).

    Args:
        world: a reset `manip.sim.World`; its physics step must equal `trajectory.dt`.
        robot: a `manip.sim.Robot` / `Articulation` that has the trajectory's joints, or a
            list of robots, one per arm of a multi-arm robot's trajectory, each driven by its
            own arm's joints (`Trajectory.to_articulation_actions`).
        trajectory: a `manip.Trajectory` (e.g. a `PlanResult.trajectory`).

    Returns:
        (T, dof) the simulated positions [rad] of the trajectory's joints: row 0 before
        the first step, row k after step k (compare with `trajectory.positions[k]`).

    A robot more than `START_TOLERANCE` from the trajectory's start logs a warning (its
    drives jump to the first sample).

    Raises:
        InvalidInputError: not a Trajectory (e.g. None, a failed plan's); its dt differs from
            the world's physics step.
        SimulationError: the world is not playing (paused or stopped: no step would move
            the robot, and every row would be the same).
        UnknownNameError: a joint of the trajectory is not a DoF of the robot.
    """
    if not callable(getattr(trajectory, "to_articulation_actions", None)):
        hint = " (a failed plan's result.trajectory is None: check result.success)" if trajectory is None else ""
        raise InvalidInputError(f"trajectory must be a manip.Trajectory (e.g. PlanResult.trajectory); got "
                                f"{type(trajectory).__name__}{hint}")
    dt = world.get_physics_dt()
    if abs(trajectory.dt - dt) > 1e-9:
        raise InvalidInputError(f"trajectory.dt ({trajectory.dt} s) must equal the world's physics step ({dt} s); "
                                f"resample it with trajectory.resample({dt})")
    robots = list(robot) if isinstance(robot, (list, tuple)) else [robot]
    columns = [robot_columns(trajectory, r) for r in robots]
    actions = [trajectory.to_articulation_actions(r) for r in robots]

    def read() -> np.ndarray:
        q = np.full(len(trajectory.joint_names), np.nan)
        for r, (cols, idx) in zip(robots, columns):
            q[cols] = r.get_joint_positions(idx)
        return q

    if not world.is_playing():
        raise SimulationError("play_trajectory: the World is not playing (paused or stopped), so no step would move "
                              "the robot; call world.play() (or world.reset()) first")
    out = [read()]
    gap = np.abs(out[0] - trajectory.positions[0])
    if np.nanmax(gap) > START_TOLERANCE:
        j = int(np.nanargmax(gap))
        logger.warning("play_trajectory: the robot is %.3g from the trajectory's start at %s (%.4g, planned %.4g); "
                       "its drives jump to the first sample. Plan from robot.get_joint_positions(), or move the robot "
                       "to trajectory.positions[0] first", gap[j], trajectory.joint_names[j], out[0][j],
                       trajectory.positions[0][j])
    for step in zip(*actions):
        for r, action in zip(robots, step):
            r.apply_action(action)
        world.step(render=False)
        out.append(read())
    return np.asarray(out)
