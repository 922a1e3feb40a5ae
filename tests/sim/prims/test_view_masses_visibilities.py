"""Domain randomisation through Isaac's views (NotImplementedError before): `RigidPrimView.set_masses`
changes how the same push moves each cube (real MuJoCo physics), a robot link's mass too;
`get_densities`; `XFormPrimView.set_visibilities` hides objects without changing collisions."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, Franka, RigidPrimView, World
from manip.sim.scenes.stage import SimulationError


def cubes_and_a_franka():
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka", position=[0.0, -1.0, 0.0]))
    cubes = [world.scene.add(DynamicCuboid(f"/World/Cube_{i}", name=f"cube{i}", position=[0.5, 0.2 * i, 0.5],
                                           size=0.1)) for i in range(3)]
    view = world.scene.add(RigidPrimView("/World/Cube_.*", name="cubes"))
    world.reset()
    return world, franka, cubes, view


def test_set_masses_changes_how_a_push_moves_each_cube_and_persists():
    world, _, cubes, view = cubes_and_a_franka()
    masses = np.array([0.5, 1.0, 2.0])
    view.set_masses(masses)
    np.testing.assert_allclose(view.get_masses(), masses)
    assert [c.get_mass() for c in cubes] == pytest.approx(masses.tolist())
    np.testing.assert_allclose(view.get_densities(), masses / 0.1 ** 3)
    world.get_physics_context().set_gravity(0.0)
    start = view.get_world_poses()[0]
    for _ in range(30):                                   # 2 N along x for 0.5 s (free fall off: no gravity)
        view.apply_forces(np.tile([2.0, 0.0, 0.0], (3, 1)))
        world.step(render=False)
    moved = view.get_world_poses()[0][:, 0] - start[:, 0]
    np.testing.assert_allclose(moved, 0.5 * (2.0 / masses) * 0.5 ** 2, rtol=0.05)   # x = F t^2 / 2m
    view.set_masses([3.0], indices=[1])
    world.reset()                                         # kept across a reset
    np.testing.assert_allclose(view.get_masses(), [0.5, 3.0, 2.0])
    # a robot link's mass, through a view of it
    hand = world.scene.add(RigidPrimView("/World/Franka/panda_hand", name="hand"))
    world.reset()
    hand.set_masses([1.5])
    np.testing.assert_allclose(hand.get_masses(), [1.5])
    with pytest.raises(SimulationError, match="link of a referenced robot"):
        hand.get_densities()
    with pytest.raises(InvalidInputError, match="masses"):
        view.set_masses([1.0, 2.0])
    with pytest.raises(InvalidInputError, match="mass"):
        view.set_masses([1.0, -2.0, 1.0])


def test_set_visibilities_hides_objects_they_still_collide():
    world, _, cubes, view = cubes_and_a_franka()
    assert view.get_visibilities().tolist() == [True, True, True]
    view.set_visibilities(np.array([True, False, True]))
    assert view.get_visibilities().tolist() == [True, False, True] and not cubes[1].get_visibility()
    view.set_visibilities([True], indices=[1])
    assert cubes[1].get_visibility()
    with pytest.raises(InvalidInputError, match="visibilities must be 3 bools"):
        view.set_visibilities([1, 0])
    view.set_visibilities([False, False, False])
    world.scene.add_default_ground_plane()
    world.reset()
    for _ in range(90):
        world.step(render=False)
    np.testing.assert_allclose(view.get_world_poses()[0][:, 2], 0.05, atol=2e-3)   # resting on the ground
