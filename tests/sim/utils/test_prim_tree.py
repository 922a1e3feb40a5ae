"""Isaac's prim-tree helpers (`omni.isaac.core.utils.prims.get_prim_children`, ...) and
`omni.isaac.core.utils.xforms.get_world_pose` / `get_local_pose`: an ImportError before."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.sim import (
    DynamicCuboid,
    Franka,
    World,
    XFormPrim,
    define_prim,
    get_all_matching_child_prims,
    get_first_matching_child_prim,
    get_local_pose,
    get_prim_at_path,
    get_prim_children,
    get_prim_object_type,
    get_prim_parent,
    get_prim_path,
    get_prim_type_name,
    get_world_pose,
)


def test_the_prim_tree_of_a_robot_and_objects():
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka", position=[0.2, -0.1, 0.0]))
    world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.05], size=0.05))
    tool = world.scene.add(XFormPrim("/World/Franka/panda_hand/tool", name="tool", translation=[0, 0, 0.1]))
    world.reset()
    robot = get_prim_at_path("/World/Franka")
    links = [get_prim_path(p) for p in get_prim_children(robot)]
    assert "/World/Franka/panda_hand" in links and "/World/Franka/panda_link3" in links
    assert [get_prim_path(p) for p in get_prim_children("/World/Franka/panda_hand")] == ["/World/Franka/panda_hand/tool"]
    assert get_prim_parent(tool) is get_prim_at_path("/World/Franka/panda_hand")
    assert get_prim_parent("/World/Franka/panda_hand") is robot
    assert get_prim_type_name("/World/cube") == "Cube" and get_prim_type_name("/World/Franka") == "Xform"
    assert get_prim_object_type("/World/Franka") == "articulation"
    assert get_prim_object_type("/World/Franka/panda_hand") == "rigid_body"
    assert get_prim_object_type("/World/cube") == "rigid_body" and get_prim_object_type("/World/Franka/panda_hand/tool") == "xform"
    assert get_prim_object_type("/World/nothing") is None
    fingers = get_all_matching_child_prims("/World/Franka", lambda path: path.endswith("finger"))
    assert [get_prim_path(p) for p in fingers] == ["/World/Franka/panda_leftfinger", "/World/Franka/panda_rightfinger"]
    assert get_all_matching_child_prims("/World/Franka", depth=0) == [robot]
    assert get_prim_path(get_first_matching_child_prim("/World/Franka", lambda p: "tool" in p)) == \
        "/World/Franka/panda_hand/tool"   # breadth first: below a link, found after the links
    assert get_first_matching_child_prim("/World/Franka", lambda p: "wheel" in p) is None
    # poses: the link's from MuJoCo, in the world and in the robot's frame
    franka.set_joint_positions(np.array([0.5, -0.6, -1.9]), joint_indices=[0, 1, 3])
    world.step(render=False)
    body = mujoco.mj_name2id(world.model, mujoco.mjtObj.mjOBJ_BODY, "/World/Franka/panda_hand")
    mujoco.mj_kinematics(world.model, world.data)
    p, q = get_world_pose("/World/Franka/panda_hand")
    np.testing.assert_allclose(p, world.data.xpos[body], atol=1e-12)
    np.testing.assert_allclose(abs(quat.multiply(quat.conjugate(q), world.data.xquat[body])[0]), 1.0, atol=1e-12)
    np.testing.assert_allclose(get_world_pose("/World/Franka")[0], [0.2, -0.1, 0.0], atol=1e-9)
    np.testing.assert_allclose(get_local_pose("/World/Franka/panda_hand")[0], p - [0.2, -0.1, 0.0], atol=1e-9)
    np.testing.assert_allclose(get_local_pose("/World/Franka/panda_hand/tool")[0], [0, 0, 0.1], atol=1e-12)


def test_define_prim_and_bad_calls():
    World()
    light = define_prim("/World/Light", "SphereLight")
    assert define_prim("/World/Light", "SphereLight") is light  # already there: returned, as USD's Define
    define_prim("/World/box", "Cube")
    with pytest.raises(InvalidInputError, match=r"a Cube is there already"):
        define_prim("/World/box", "Sphere")
    with pytest.raises(InvalidInputError, match="no prim at '/World/nothing'"):
        get_prim_type_name("/World/nothing")
    with pytest.raises(InvalidInputError, match="no prim at"):
        get_world_pose("/World/nothing")
    with pytest.raises(InvalidInputError, match="depth must be None or a whole number"):
        get_all_matching_child_prims("/World/box", depth=-1)
    with pytest.raises(InvalidInputError, match="prim must be a prim"):
        get_prim_children(3)


def test_isaacs_bounds_utilities_bound_objects_robots_and_links():
    """`omni.isaac.core.utils.bounds` (ImportError before): a table's top to place a cube on, a robot
    and its hand, tight in the current state."""
    from manip.sim import FixedCuboid, compute_aabb, compute_combined_aabb, create_bbox_cache

    world = World()
    table = world.scene.add(FixedCuboid("/World/table", name="table", position=[0.6, 0.0, 0.2],
                                        scale=[0.4, 0.6, 0.4], size=1.0))
    world.scene.add(Franka("/World/Franka", name="franka"))
    cache = create_bbox_cache()
    box = compute_aabb(cache, "/World/table")   # before the reset: from the pose and size
    np.testing.assert_allclose(box, [0.4, -0.3, 0.0, 0.8, 0.3, 0.4], atol=1e-9)
    world.reset()
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", size=0.05,
                                         position=[0.6, 0.0, compute_aabb(cache, "/World/table")[5] + 0.025]))
    world.reset()
    for _ in range(30):
        world.step(render=False)
    assert cube.get_world_pose()[0][2] == pytest.approx(0.425, abs=1e-3)   # it rests on the table's top
    robot = compute_aabb(cache, "/World/Franka")
    hand = compute_aabb(cache, "/World/Franka/panda_hand", include_children=True)
    assert np.all(robot[:3] <= hand[:3] + 1e-12) and np.all(hand[3:] <= robot[3:] + 1e-12)
    p, _ = get_world_pose("/World/Franka/panda_hand")
    assert np.all(hand[:3] < p) and np.all(p < hand[3:])
    assert robot[2] == pytest.approx(0.0, abs=5e-3)   # tight: the base stands on the floor
    both = compute_combined_aabb(cache, ["/World/table", "/World/cube"])
    np.testing.assert_allclose(both[[0, 1, 3, 4]], [0.4, -0.3, 0.8, 0.3], atol=1e-6)
    assert both[5] == pytest.approx(0.45, abs=1e-3) and table.get_world_pose()[0][2] == pytest.approx(0.2)
    with pytest.raises(InvalidInputError, match="no prim at '/World/nothing'"):
        compute_aabb(cache, "/World/nothing")
    with pytest.raises(InvalidInputError, match="non-empty list"):
        compute_combined_aabb(cache, [])
