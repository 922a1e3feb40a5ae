"""Contacts as PhysX makes them (issue 32, item 7): friction averaged by default, combine
modes honoured, stiff contacts (a dropped object penetrates at most ~2 mm)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, DynamicSphere, FixedCuboid, PhysicsMaterial, World, euler_angles_to_quat
from manip.sim.scenes.contact_model import combine

SLOPE = np.deg2rad(20.0)


def _slide_on_ramp(box_material=None, ramp_material=None, seconds=1.0) -> float:
    """How far a 10 cm box slides down a 20 deg ramp in `seconds` [m]."""
    world = World()
    q = euler_angles_to_quat([0.0, SLOPE, 0.0])
    world.scene.add(FixedCuboid("/World/ramp", name="ramp", position=[0, 0, 0.5], orientation=q,
                                scale=[2.0, 1.0, 0.05], size=1.0, physics_material=ramp_material))
    R = np.array([[np.cos(SLOPE), 0, np.sin(SLOPE)], [0, 1, 0], [-np.sin(SLOPE), 0, np.cos(SLOPE)]])
    box = world.scene.add(DynamicCuboid("/World/box", name="box", position=np.array([0, 0, 0.5]) + R @ [0, 0, 0.075],
                                        orientation=q, size=0.1, physics_material=box_material))
    world.reset()
    p0 = box.get_world_pose()[0]
    for _ in range(int(round(seconds * 60))):
        world.step(render=False)
    return float(np.linalg.norm(box.get_world_pose()[0] - p0))


def _expected_slide(mu: float, seconds: float = 1.0) -> float:
    a = 9.81 * (np.sin(SLOPE) - mu * np.cos(SLOPE))
    return max(a, 0.0) * seconds**2 / 2


def test_a_slippery_box_on_a_default_ramp_slides_with_the_average_friction():
    ice = PhysicsMaterial("/World/Physics_Materials/ice", static_friction=0.05, dynamic_friction=0.05)
    d = _slide_on_ramp(box_material=ice)  # the ramp: no material, PhysX's default 0.5
    assert d == pytest.approx(_expected_slide(0.275), rel=0.05)  # (0.05 + 0.5) / 2; was 1 mm with max


@pytest.mark.parametrize("mode, mu", [("min", 0.05), ("multiply", 0.025), ("max", 0.5), ("average", 0.275)])
def test_combine_modes_are_honoured(mode, mu):
    ice = PhysicsMaterial("/World/Physics_Materials/ice", static_friction=0.05, dynamic_friction=0.05,
                          friction_combine_mode=mode)
    d = _slide_on_ramp(box_material=ice)
    expected = _expected_slide(mu)
    if expected == 0.0:
        assert d < 0.002
    else:
        assert d == pytest.approx(expected, rel=0.05)


def test_the_later_mode_in_physx_precedence_wins():
    assert combine(0.2, "average", 0.6, "min") == 0.2
    assert combine(0.2, "max", 0.6, "multiply") == 0.6
    assert combine(0.2, "multiply", 0.6, "average") == pytest.approx(0.12)
    ramp = PhysicsMaterial("/World/Physics_Materials/ramp", dynamic_friction=0.5, friction_combine_mode="min")
    ice = PhysicsMaterial("/World/Physics_Materials/ice", dynamic_friction=0.05)  # average
    assert _slide_on_ramp(box_material=ice, ramp_material=ramp) == pytest.approx(_expected_slide(0.05), rel=0.05)


def test_a_bad_combine_mode_raises_naming_the_valid_ones():
    with pytest.raises(InvalidInputError, match="average, min, multiply, max"):
        PhysicsMaterial(friction_combine_mode="mean")
    with pytest.raises(InvalidInputError, match="friction_combine_mode"):
        PhysicsMaterial().set_friction_combine_mode("maximum")


@pytest.mark.parametrize("shape", ["ball", "cube", "hello_world_cube"])
def test_a_dropped_object_penetrates_the_ground_at_most_2mm(shape):
    """Dropped from heights 0.8-1.5 m (every phase of the step at impact): a 5 cm ball, a
    5.15 cm cube and the Hello World tutorial's 0.5 m cube (size 1 scaled by 0.5015)."""
    worst = 0.0
    for h in np.linspace(0.8, 1.5, 17):
        World.clear_instance()
        world = World()
        world.scene.add_default_ground_plane()
        if shape == "ball":
            obj = world.scene.add(DynamicSphere("/World/o", name="o", position=[0, 0, h], radius=0.025))
            rest = 0.025
        elif shape == "cube":
            obj = world.scene.add(DynamicCuboid("/World/o", name="o", position=[0, 0, h], size=0.0515))
            rest = 0.0515 / 2
        else:
            obj = world.scene.add(DynamicCuboid(prim_path="/World/random_cube", name="fancy_cube", position=[0, 0, h],
                                                scale=np.array([0.5015] * 3), color=np.array([0, 0, 1.0])))
            rest = 0.5015 / 2
        world.reset()
        zs = []
        for _ in range(120):
            world.step(render=False)
            zs.append(obj.get_world_pose()[0][2])
        worst = max(worst, rest - min(zs))
        assert zs[-1] == pytest.approx(rest, abs=2e-4)  # at rest on the surface, not sunk into it
    assert worst < 0.002  # was 29 mm (ball), 34 mm (the Hello World cube) with MuJoCo's defaults


def test_the_franka_fingers_keep_their_authored_grip():
    """Geoms of higher priority (the Franka's finger pads) keep deciding alone, as in MuJoCo."""
    from manip.sim import Franka

    world = World()
    world.scene.add_default_ground_plane()
    world.scene.add(Franka("/World/Franka", name="franka"))
    world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0, 0.025], size=0.05))
    world.reset()
    m = world.model
    pads = [g for g in range(m.ngeom) if m.geom_priority[g] == 1 and "finger" in m.body(m.geom_bodyid[g]).name]
    cube = m.geom("/World/cube/geom").id
    pair_geoms = {frozenset((int(a), int(b))) for a, b in zip(m.pair_geom1, m.pair_geom2)}
    for p in pads:
        if frozenset((p, cube)) in pair_geoms:
            k = [i for i in range(m.npair) if {int(m.pair_geom1[i]), int(m.pair_geom2[i])} == {p, cube}][0]
            assert m.pair_friction[k, 0] == pytest.approx(m.geom_friction[p, 0])  # the pad's 1.2
