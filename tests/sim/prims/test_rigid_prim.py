"""RigidPrim's constructor takes Isaac's mass, density and velocities (it raised TypeError),
and what a wrapper sets reaches the wrapped body and survives the World's compiles."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, Franka, RigidPrim, SimulationError, VisualCuboid, World


def test_a_wrapper_made_with_mass_and_velocity_sets_the_object_for_every_reset():
    world = World()
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.0, 0.0, 1.0], size=0.1))
    wrapper = RigidPrim("/World/cube", name="cube_body", mass=0.5, linear_velocity=[1.0, 0.0, 0.0])
    world.reset()
    assert cube.get_mass() == pytest.approx(0.5) and wrapper.get_mass() == pytest.approx(0.5)
    np.testing.assert_allclose(cube.get_linear_velocity(), [1.0, 0.0, 0.0])
    world.step(render=False)
    assert cube.get_world_pose()[0][0] == pytest.approx(1.0 / 60.0, rel=1e-3)
    wrapper.set_mass(0.2)  # kept when the World recompiles (it was the wrapper's only)
    world.scene.add(VisualCuboid("/World/mark", name="mark", position=[2.0, 2.0, 2.0], size=0.1))
    world.reset()
    assert cube.get_mass() == pytest.approx(0.2)
    RigidPrim("/World/cube", name="cube_body_2", density=1000.0)
    assert cube.get_mass() == pytest.approx(1.0)  # 1000 kg/m^3 x (0.1 m)^3


def test_a_links_mass_is_kept_and_what_a_link_cannot_take_says_so():
    world = World()
    world.scene.add(Franka("/World/Franka", name="franka"))
    hand = RigidPrim("/World/Franka/panda_hand", name="hand", mass=2.0)  # before the first reset
    world.reset()
    assert hand.get_mass() == pytest.approx(2.0)
    world.scene.add(VisualCuboid("/World/mark", name="mark", position=[2.0, 2.0, 2.0], size=0.1))
    world.reset()
    assert hand.get_mass() == pytest.approx(2.0)
    with pytest.raises(SimulationError, match="follows the joints"):
        RigidPrim("/World/Franka/panda_link3", name="l3", linear_velocity=[0.0, 0.0, 1.0])
    with pytest.raises(SimulationError, match="set its mass"):
        RigidPrim("/World/Franka/panda_link4", name="l4", density=500.0)
    with pytest.raises(InvalidInputError, match="either mass or density"):
        RigidPrim("/World/Franka/panda_link5", name="l5", mass=1.0, density=500.0)
