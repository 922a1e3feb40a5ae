"""Two robots placed inside each other: a clear error at reset naming them, instead of NaN
physics at the first steps (exactly overlapping Frankas raised SimulationInstabilityError at
t = 0.05 s; 0.1 m apart they tangled silently)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.sim import Franka, World
from manip.sim.scenes.robot_overlaps import RobotsOverlapError


def two_frankas(second_position):
    world = World()
    world.scene.add_default_ground_plane()
    a = world.scene.add(Franka("/World/Franka1", name="franka1", position=[0.0, 0.0, 0.0]))
    b = world.scene.add(Franka("/World/Franka2", name="franka2", position=second_position))
    return world, a, b


@pytest.mark.parametrize("x", [0.0, 0.1])
def test_overlapping_frankas_raise_at_reset_naming_both(x):
    world, _, _ = two_frankas([x, 0.0, 0.0])
    with pytest.raises(RobotsOverlapError, match=r"/World/Franka1 \(base at \[0.0, 0.0, 0.0\] m\) and "
                                                 rf"/World/Franka2 \(base at \[{x}, 0.0, 0.0\] m\): "
                                                 r"/World/Franka1's panda_\w+ is \d+ mm inside /World/Franka2's"):
        world.reset()


def test_frankas_apart_simulate_and_a_moved_one_is_checked_again():
    world, _, b = two_frankas([0.0, 1.0, 0.0])
    world.reset()
    for _ in range(30):
        world.step(render=False)
    assert np.all(np.isfinite(b.get_joint_positions()))
    np.testing.assert_allclose(b.get_world_pose()[0], [0.0, 1.0, 0.0], atol=1e-9)
    b.set_default_state(position=[0.05, 0.0, 0.0])
    with pytest.raises(RobotsOverlapError, match="Franka2"):
        world.reset()


def test_a_robot_moved_into_another_after_the_reset_raises_and_stays():
    """A `set_world_pose` after the reset into another robot raised nothing (the arms tangled or
    MuJoCo reported NaN accelerations at the next steps): it raises, and the robot stays put."""
    from manip.sim import ArticulationView

    world, _, b = two_frankas([0.0, 1.0, 0.0])
    world.reset()
    with pytest.raises(RobotsOverlapError, match=r"moving /World/Franka2 puts it inside another robot .*"
                                                 r"/World/Franka2 was left where it was"):
        b.set_world_pose(position=[0.1, 0.0, 0.0])
    np.testing.assert_allclose(b.get_world_pose()[0], [0.0, 1.0, 0.0], atol=1e-9)
    view = ArticulationView("/World/Franka2", name="franka2_view")
    world.scene.add(view)
    world.reset()
    with pytest.raises(RobotsOverlapError, match="Franka2"):
        view.set_world_poses(positions=np.array([[0.0, 0.05, 0.0]]))
    b.set_world_pose(position=[0.0, 0.6, 0.0])       # clear of the other: moves
    for _ in range(30):
        world.step(render=False)
    np.testing.assert_allclose(b.get_world_pose()[0], [0.0, 0.6, 0.0], atol=1e-9)
    assert np.all(np.isfinite(b.get_joint_positions()))
