"""Isaac's GeometryPrimView (4.x `omni.isaac.core.prims`; it did not exist): poses of the shapes,
their collisions switched in batch (a cube with its collision off falls through the ground),
collision approximation tokens, physics materials, and PhysX-only members that say why not."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, Franka, GeometryPrim, GeometryPrimView, PhysicsMaterial, VisualCuboid, World
from manip.sim.scenes.stage import SimulationError


def cubes(world, n=3, collisions=None):
    for i in range(n):
        world.scene.add(DynamicCuboid(f"/World/Cube_{i}", name=f"cube_{i}", position=[0.3 * i, 0.0, 0.2], size=0.05))
    return world.scene.add(GeometryPrimView("/World/Cube_.*", name="cubes", collisions=collisions))


def test_poses_and_collisions_in_batch_decide_which_cubes_land():
    world = World()
    world.scene.add_default_ground_plane()
    view = cubes(world)
    world.reset()
    np.testing.assert_allclose(view.get_world_poses()[0], [[0.0, 0, 0.2], [0.3, 0, 0.2], [0.6, 0, 0.2]], atol=1e-6)
    assert view.is_collision_enabled().tolist() == [True, True, True]
    view.disable_collision(indices=[1])
    assert view.is_collision_enabled().tolist() == [True, False, True]
    for _ in range(60):
        world.step(render=False)
    z = view.get_world_poses()[0][:, 2]
    assert z[0] == pytest.approx(0.025, abs=2e-3) and z[2] == pytest.approx(0.025, abs=2e-3)  # landed
    assert z[1] < -0.5                                              # fell through the ground
    view.enable_collision(indices=[1])
    assert view.is_collision_enabled(indices=[1]).tolist() == [True]


def test_collisions_argument_approximations_and_materials():
    world = World()
    for i in range(2):
        world.scene.add(VisualCuboid(f"/World/Mark_{i}", name=f"mark_{i}", position=[0.3 * i, 1.0, 0.1], size=0.05))
    view = world.scene.add(GeometryPrimView("/World/Mark_.*", name="marks", collisions=[True, False]))
    world.reset()
    assert view.is_collision_enabled().tolist() == [True, False]    # visual shapes collide only when asked
    assert view.get_collision_approximations() == ["none", "none"]
    view.set_collision_approximations(["convexHull", "boundingCube"])
    assert view.get_collision_approximations() == ["convexHull", "boundingCube"]
    assert GeometryPrim("/World/Mark_0").get_collision_approximation() == "convexHull"
    with pytest.raises(InvalidInputError, match="one of .*'convexHull'"):
        view.set_collision_approximations("convex")
    rubber = PhysicsMaterial("/World/Physics_Materials/rubber", dynamic_friction=1.0, static_friction=1.0)
    view.apply_physics_materials(rubber, indices=[1])
    assert view.get_applied_physics_materials() == [None, rubber]
    with pytest.raises(InvalidInputError, match="physics_materials: 1 values for 2 prims"):
        view.apply_physics_materials([rubber])
    with pytest.raises(NotImplementedError, match="set_contact_offsets is not available in manip.sim"):
        view.set_contact_offsets(np.full(2, 0.01))


def test_a_robots_links_have_no_shape_settings():
    world = World()
    world.scene.add(Franka("/World/Franka", name="franka"))
    view = world.scene.add(GeometryPrimView("/World/Franka/panda_link[0-9]", name="links"))
    world.reset()
    assert view.count == 8 and view.get_world_poses()[0].shape == (8, 3)
    with pytest.raises(SimulationError, match="is not a shape"):
        view.is_collision_enabled()
