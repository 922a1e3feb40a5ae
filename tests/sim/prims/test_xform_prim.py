"""XFormPrim's Isaac methods that are not poses."""

from __future__ import annotations

from manip.sim import DynamicCuboid, Franka, RigidPrim, World, XFormPrim


def test_is_valid_is_a_method_saying_whether_the_prim_is_on_the_stage():
    # Isaac: prim.is_valid() -> bool. It was a property here: the call raised TypeError.
    world = World()
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", size=0.1))
    world.scene.add(Franka("/World/Franka", name="franka"))
    hand = RigidPrim("/World/Franka/panda_hand", name="hand")
    frame = XFormPrim("/World/frame", name="frame")
    assert cube.is_valid() and hand.is_valid() and frame.is_valid()  # before the first reset too
    assert not cube.simulated
    world.reset()
    assert cube.is_valid() and cube.simulated and hand.simulated
    world.scene.remove_object("cube")
    assert not cube.is_valid()
    world.scene.remove_object("franka")
    assert not hand.is_valid()
