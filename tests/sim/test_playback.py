"""play_trajectory: a planned motion replayed on a simulated robot, and the mistakes it names."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from manip import MotionGenerator
from manip.sim import Franka, SimulationError, World
from manip.sim.playback import START_TOLERANCE, play_trajectory


@pytest.fixture(scope="module")
def mg():
    return MotionGenerator("franka")


def test_a_paused_world_raises_instead_of_returning_a_motionless_replay(mg):
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    q0 = franka.get_joint_positions()
    plan = mg.plan_joints(q0, mg.default_joint_positions + 0.2)
    assert plan.success
    world.pause()
    # it returned (T, 7) rows all equal to the start: the robot had not moved
    with pytest.raises(SimulationError, match="not playing .*world.play"):
        play_trajectory(world, franka, plan.trajectory)
    world.play()
    played = play_trajectory(world, franka, plan.trajectory)
    assert played.shape == plan.trajectory.positions.shape
    assert np.abs(played[-1] - plan.trajectory.positions[-1]).max() < 0.02


def test_a_robot_away_from_the_start_is_warned_about(mg, caplog):
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    start = mg.default_joint_positions
    plan = mg.plan_joints(start, start + 0.2)
    with caplog.at_level(logging.WARNING, logger="manip.sim.playback"):
        play_trajectory(world, franka, plan.trajectory)  # from its start: no warning
    assert "start" not in caplog.text
    # now at the goal, the same plan again: every drive jumps 0.2 rad back to the first sample
    assert np.abs(franka.get_joint_positions()[:7] - plan.trajectory.positions[0]).max() > START_TOLERANCE
    with caplog.at_level(logging.WARNING, logger="manip.sim.playback"):
        play_trajectory(world, franka, plan.trajectory)
    assert "the robot is 0.2" in caplog.text and "from the trajectory's start at panda_joint" in caplog.text


def test_the_trajectory_of_a_failed_plan_is_refused_by_name(mg):
    """A failed plan's `trajectory` is None: before, AttributeError "'NoneType' object has no
    attribute 'dt'"."""
    from manip.errors import InvalidInputError

    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    failed = mg.plan_joints(mg.default_joint_positions, np.full(7, 10.0))
    assert not failed.success and failed.trajectory is None
    with pytest.raises(InvalidInputError, match=r"trajectory must be a manip.Trajectory .*got NoneType \(a failed "
                                                r"plan's result.trajectory is None: check result.success\)"):
        play_trajectory(world, franka, failed.trajectory)
