"""Isaac's `create_prim` (it raised NotImplementedError): lights and Xforms are transforms, bare
USD geometry is a visual shape of USD's default size, `usd_path` references a model."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import (DynamicCuboid, Robot, VisualCuboid, World, XFormPrim, create_prim, get_assets_root_path,
                       get_prim_at_path, is_prim_path_valid)


def test_lights_and_xforms_are_transforms_and_the_world_runs_with_them():
    world = World()
    light = create_prim("/World/Light", "SphereLight", position=np.array([1.0, 1.0, 3.0]),
                        attributes={"inputs:radius": 0.1, "inputs:intensity": 5000})
    group = create_prim("/World/Objects", "Xform")
    assert isinstance(light, XFormPrim) and get_prim_at_path("/World/Light") is light
    assert is_prim_path_valid("/World/Objects") and isinstance(group, XFormPrim)
    world.reset()
    np.testing.assert_allclose(light.get_world_pose()[0], [1.0, 1.0, 3.0])
    with pytest.raises(InvalidInputError, match="already exists"):
        create_prim("/World/Light", "DistantLight")


def test_a_bare_cube_is_visual_of_the_given_size_and_lets_a_dynamic_cube_fall_through():
    world = World()
    world.scene.add_default_ground_plane()
    cube = create_prim("/World/Cube", prim_type="Cube", position=np.array([0.0, 0.0, 0.3]), attributes={"size": 0.2})
    default = create_prim("/World/Unit", prim_type="Cube", position=[3.0, 0.0, 1.0])
    assert isinstance(cube, VisualCuboid) and cube.get_size() == pytest.approx(0.2)
    assert default.get_size() == pytest.approx(2.0)  # USD's default
    falling = world.scene.add(DynamicCuboid("/World/falling", name="falling", position=[0.0, 0.0, 0.8], size=0.05))
    world.scene.add(cube)
    world.reset()
    np.testing.assert_allclose(world.scene.compute_object_AABB(cube.name), [[-0.1, -0.1, 0.2], [0.1, 0.1, 0.4]])
    for _ in range(60):
        world.step(render=False)
    assert falling.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)  # through it, onto the ground
    with pytest.raises(InvalidInputError, match="radius"):
        create_prim("/World/Ball", "Sphere", attributes={"size": 1.0})


def test_a_usd_path_references_the_model_and_other_types_raise():
    world = World()
    create_prim("/World/Franka", "Xform", usd_path=get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd")
    robot = world.scene.add(Robot("/World/Franka", name="franka"))
    world.reset()
    assert robot.num_dof == 9
    with pytest.raises(NotImplementedError, match="Camera"):
        create_prim("/World/Mesh", "Mesh")
