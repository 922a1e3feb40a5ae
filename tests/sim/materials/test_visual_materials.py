"""Visual materials (issue 32, item 2): a shape's colour is its material's, read and changed
through Isaac's API, and drawn by MuJoCo (the compiled model's geom colour)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import (DynamicCuboid, FixedSphere, OmniGlass, OmniPBR, PreviewSurface, VisualCuboid, VisualMaterial,
                       World)


def _rgba(world, obj) -> np.ndarray:
    return world.physics_sim_view.model.geom_rgba[obj.geom_id].copy()


def test_a_cube_made_with_a_color_carries_a_preview_surface_of_that_color():
    world = World()
    cube = world.scene.add(DynamicCuboid(prim_path="/World/cube", name="cube", position=[0, 0, 1.0], size=0.05,
                                         color=np.array([0, 0, 1.0])))
    material = cube.get_applied_visual_material()  # was AttributeError
    assert isinstance(material, PreviewSurface) and isinstance(material, VisualMaterial)
    assert material.prim_path.startswith("/World/Looks/visual_material")
    np.testing.assert_array_equal(material.get_color(), [0, 0, 1.0])
    world.reset()
    np.testing.assert_array_equal(_rgba(world, cube), [0, 0, 1.0, 1.0])
    material.set_color([1.0, 0.0, 0.0])  # after the reset: the drawn colour changes at once
    np.testing.assert_array_equal(_rgba(world, cube)[:3], [1.0, 0.0, 0.0])
    np.testing.assert_array_equal(cube.get_color(), [1.0, 0.0, 0.0])


def test_a_shape_without_a_color_is_grey_and_every_shape_has_its_own_material():
    a = VisualCuboid("/World/a", name="a")
    b = VisualCuboid("/World/b", name="b")
    np.testing.assert_array_equal(a.get_applied_visual_material().get_color(), [0.5, 0.5, 0.5])
    assert a.get_applied_visual_material() is not b.get_applied_visual_material()


def test_one_material_applied_to_two_objects_recolours_both():
    world = World()
    red = PreviewSurface(prim_path="/World/Looks/red", color=np.array([1.0, 0.0, 0.0]), roughness=0.3, metallic=0.9)
    a = world.scene.add(FixedSphere("/World/a", name="a", radius=0.05, position=[0.5, 0, 0.05]))
    b = world.scene.add(DynamicCuboid("/World/b", name="b", size=0.05, position=[0.5, 0.2, 0.025],
                                      visual_material=red))
    a.apply_visual_material(red)
    assert a.get_applied_visual_material() is red and a.is_visual_material_applied()
    world.reset()
    for obj in (a, b):
        np.testing.assert_array_equal(_rgba(world, obj)[:3], [1.0, 0.0, 0.0])
    red.set_color([0.0, 1.0, 0.0])
    for obj in (a, b):
        np.testing.assert_array_equal(_rgba(world, obj)[:3], [0.0, 1.0, 0.0])
    assert red.get_roughness() == 0.3 and red.get_metallic() == 0.9
    b.set_color([0.2, 0.2, 0.2])  # through the object: its material changes, so both do
    np.testing.assert_allclose(_rgba(world, a)[:3], [0.2, 0.2, 0.2], rtol=1e-6)  # float32 in MuJoCo


def test_omni_pbr_and_glass_keep_their_parameters_and_draw_their_colour():
    world = World()
    pbr = OmniPBR(prim_path="/World/Looks/pbr", color=[0.1, 0.2, 0.3], texture_path="wood.png",
                  texture_scale=[2.0, 2.0])
    glass = OmniGlass(prim_path="/World/Looks/glass", color=[0.8, 0.9, 1.0], ior=1.5)
    a = world.scene.add(VisualCuboid("/World/a", name="a", visual_material=pbr))
    b = world.scene.add(VisualCuboid("/World/b", name="b", visual_material=glass))
    world.reset()
    np.testing.assert_allclose(_rgba(world, a), [0.1, 0.2, 0.3, 1.0])
    np.testing.assert_allclose(_rgba(world, b), [0.8, 0.9, 1.0, 0.3])  # glass: see-through
    assert pbr.get_texture() == "wood.png" and list(pbr.get_texture_scale()) == [2.0, 2.0]
    pbr.set_reflection_roughness(0.1)
    pbr.set_metallic_constant(0.7)
    assert (pbr.get_reflection_roughness(), pbr.get_metallic_constant()) == (0.1, 0.7)
    assert glass.get_ior() == 1.5
    b.set_visibility(False)
    assert _rgba(world, b)[3] == 0.0


@pytest.mark.parametrize("make", [
    lambda: PreviewSurface("/World/Looks/x", color=[-0.1, 0, 0]),   # (above 1 is USD's HDR colour: allowed)
    lambda: PreviewSurface("/World/Looks/x", roughness=1.5),
    lambda: VisualCuboid("/World/c", name="c", visual_material="red"),
    lambda: VisualCuboid("/World/c", name="c").apply_visual_material([1, 0, 0]),
])
def test_bad_materials_raise_naming_the_argument(make):
    with pytest.raises(InvalidInputError):
        make()
