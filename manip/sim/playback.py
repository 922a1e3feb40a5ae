"""Replay a planned trajectory on a simulated robot and read back what it did."""

from __future__ import annotations

import numpy as np

from manip.errors import InvalidInputError


def play_trajectory(world, robot, trajectory) -> np.ndarray:
    """Drive `robot` along `trajectory`, one ArticulationAction (position and velocity
    targets) per physics step, from wherever the robot stands (normally the start).

    Args:
        world: a reset `manip.sim.World`; its physics step must equal `trajectory.dt`.
        robot: a `manip.sim.Robot` / `Articulation` that has the trajectory's joints.
        trajectory: a `manip.Trajectory` (e.g. a `PlanResult.trajectory`).

    Returns:
        (T, dof) the simulated positions [rad] of the trajectory's joints: row 0 before
        the first step, row k after step k (compare with `trajectory.positions[k]`).

    Raises:
        InvalidInputError: the trajectory's dt differs from the world's physics step.
        UnknownNameError: a joint of the trajectory is not a DoF of the robot.
    """
    dt = world.get_physics_dt()
    if abs(trajectory.dt - dt) > 1e-9:
        raise InvalidInputError(f"trajectory.dt ({trajectory.dt} s) must equal the world's physics step ({dt} s); "
                                f"resample it with trajectory.resample({dt})")
    idx = trajectory.joint_indices_for(robot)
    out = [robot.get_joint_positions(idx)]
    for action in trajectory.to_articulation_actions(robot):
        robot.apply_action(action)
        world.step(render=False)
        out.append(robot.get_joint_positions(idx))
    return np.asarray(out)
