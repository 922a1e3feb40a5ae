"""`get_prim_at_path` of a robot's link returns a prim, as Isaac's does (a `Usd.Prim`): before,
"/World/Franka/panda_hand" gave None although `is_prim_path_valid` said True. The link's prim
is an XFormPrim reading the body's pose from MuJoCo, and every prim answers USD's reading
methods (`IsValid`, `GetPath`, `GetName`, `GetTypeName`, `GetChildren`, `GetParent`)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from manip.sim import (
    DynamicCuboid,
    Franka,
    World,
    XFormPrim,
    get_prim_at_path,
    get_relative_transform,
    is_prim_path_valid,
)


def test_a_robots_link_is_a_prim_whose_pose_follows_the_simulation():
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.05], size=0.05))
    world.reset()
    hand = get_prim_at_path("/World/Franka/panda_hand")
    assert isinstance(hand, XFormPrim) and is_prim_path_valid("/World/Franka/panda_hand")
    assert hand.IsValid() and hand.GetPath() == "/World/Franka/panda_hand" and hand.GetName() == "panda_hand"
    assert hand.GetTypeName() == "Xform" and get_prim_at_path("/World/Franka/panda_hand") is hand  # one per path
    franka.set_joint_positions(np.array([0.6, -0.4, -1.8]), joint_indices=[0, 1, 3])
    for _ in range(5):
        world.step(render=False)
    body = mujoco.mj_name2id(world.model, mujoco.mjtObj.mjOBJ_BODY, "/World/Franka/panda_hand")
    mujoco.mj_kinematics(world.model, world.data)
    p, q = hand.get_world_pose()
    np.testing.assert_allclose(p, world.data.xpos[body], atol=1e-12)
    np.testing.assert_allclose(q, world.data.xquat[body], atol=1e-12)
    # the transformation utilities take it as they take any prim
    rel = get_relative_transform(hand, get_prim_at_path("/World/Franka"))
    np.testing.assert_allclose(rel[:3, 3], p - franka.get_world_pose()[0], atol=1e-9)
    # the tree: the model's links are its children (flat, as Isaac's robot USD), the link's parent the model
    robot = get_prim_at_path("/World/Franka")
    names = [c.GetName() for c in robot.GetChildren()]
    assert {"panda_link0", "panda_link7", "panda_hand", "panda_leftfinger"} <= set(names)
    assert hand.GetParent() is robot and robot.IsValid() and robot.GetTypeName() == "Xform"
    assert franka.prim is robot   # Isaac's Articulation.prim (an AttributeError before)
    assert cube.GetTypeName() == "Cube" and get_prim_at_path("/World/cube") is cube and cube.GetChildren() == []
    # what is not there is None (as Isaac's invalid prim tests False), a link of no model too
    assert get_prim_at_path("/World/Franka/no_such_link") is None and get_prim_at_path("/World/nothing") is None
    world.scene.remove_object("franka")
    assert not hand.IsValid() and get_prim_at_path("/World/Franka/panda_hand") is None


def test_prim_and_prims_are_the_objects_answering_usds_reading_methods():
    """`cube.prim` / `view.prims` raised NotImplementedError; Isaac scripts pass them to the prim
    utilities or read their path and validity."""
    from manip.sim import RigidPrimView, get_prim_children, get_prim_path

    world = World()
    cube = world.scene.add(DynamicCuboid("/World/Cube_0", name="c0", position=[0.0, 0.0, 0.05], size=0.05))
    world.scene.add(DynamicCuboid("/World/Cube_1", name="c1", position=[0.2, 0.0, 0.05], size=0.05))
    view = world.scene.add(RigidPrimView("/World/Cube_.*", name="cubes"))
    world.reset()
    assert cube.prim is cube and cube.prim.IsValid() and get_prim_path(cube.prim) == "/World/Cube_0"
    assert [p.GetPath() for p in view.prims] == ["/World/Cube_0", "/World/Cube_1"] and view.prims[0] is cube
    assert get_prim_children(cube.prim) == []
    with pytest.raises(NotImplementedError, match="GetAttribute\\('size'\\): manip has no USD attributes"):
        cube.prim.GetAttribute("size")
