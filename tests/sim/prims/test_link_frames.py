"""An XFormPrim made below a robot's link ("/World/Franka/panda_hand/tool_frame") is a frame
fixed to that link, as the Xform Isaac creates there: before, it was taken for a body of the
model that does not exist, and every `world.reset()` raised."""

from __future__ import annotations

import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.sim import Franka, RigidPrim, RigidPrimView, World, XFormPrim


def test_a_frame_below_a_link_rides_on_it():
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    tool = world.scene.add(XFormPrim("/World/Franka/panda_hand/tool_frame", name="tool", translation=[0.0, 0.0, 0.2]))
    assert tool.mount_link == "/World/Franka/panda_hand"
    hand = XFormPrim("/World/Franka/panda_hand")   # the model's own body: wrapped, as before
    assert hand.mount_link is None

    def expected():
        p, q = hand.get_world_pose()
        return p + quat.to_matrix(q) @ [0.0, 0.0, 0.2]

    np.testing.assert_allclose(tool.get_world_pose()[0], expected(), atol=1e-9)  # before the first reset
    world.reset()
    np.testing.assert_allclose(tool.get_world_pose()[0], expected(), atol=1e-9)
    franka.set_joint_positions(np.array([0.7, -0.3]), joint_indices=[0, 1])
    world.step(render=False)
    np.testing.assert_allclose(tool.get_world_pose()[0], expected(), atol=1e-9)
    np.testing.assert_allclose(tool.get_world_pose()[1], hand.get_world_pose()[1], atol=1e-9)
    np.testing.assert_allclose(tool.get_local_pose()[0], [0.0, 0.0, 0.2])
    tool.set_local_pose(translation=[0.0, 0.05, 0.1])
    np.testing.assert_allclose(tool.get_world_pose()[0], hand.get_world_pose()[0]
                               + quat.to_matrix(hand.get_world_pose()[1]) @ [0.0, 0.05, 0.1], atol=1e-9)
    world.reset()  # a scene object: back to its default pose in the link's frame
    np.testing.assert_allclose(tool.get_local_pose()[0], [0.0, 0.0, 0.2])


def test_what_cannot_ride_on_a_link_says_so():
    world = World()
    world.scene.add(Franka("/World/Franka", name="franka"))
    with pytest.raises(InvalidInputError, match="below none of its links"):
        XFormPrim("/World/Franka/frame")
    # a rigid body is a link of the model, never a new frame: a wrong name fails here (it made
    # every later world.reset() raise)
    with pytest.raises(InvalidInputError, match="has no body or site of that name"):
        RigidPrim("/World/Franka/panda_hand/not_a_link")
    world.reset()
    assert RigidPrim("/World/Franka/panda_hand").get_mass() > 0


def test_a_links_local_pose_is_in_the_robots_frame_its_parent_prim():
    # Isaac's robot USDs put the links under the robot's prim ("/World/Franka/panda_hand"):
    # a link's local pose is in the robot's frame (it was the world pose).
    world = World()
    yaw = np.array([np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)])  # 90 deg about z
    franka = world.scene.add(Franka("/World/Franka", name="franka", position=[0.5, 0.2, 0.1], orientation=yaw))
    hand = RigidPrim("/World/Franka/panda_hand", name="hand")
    link0 = XFormPrim("/World/Franka/panda_link0")
    view = world.scene.add(RigidPrimView("/World/Franka/panda_(hand|link0)", name="links"))

    def check():
        p_r, q_r = franka.get_world_pose()
        p_h, q_h = hand.get_world_pose()
        lp, lq = hand.get_local_pose()
        np.testing.assert_allclose(p_r + quat.to_matrix(q_r) @ lp, p_h, atol=1e-9)
        assert quat.angle_between(quat.multiply(q_r, lq), q_h) < 1e-6
        np.testing.assert_allclose(link0.get_local_pose()[0], 0.0, atol=1e-9)
        return lp

    before_reset = check()
    world.reset()
    at_reset = check()
    np.testing.assert_allclose(at_reset, before_reset, atol=1e-9)
    franka.set_world_pose(position=[-1.0, 0.0, 0.0])   # teleported: the local pose stays
    world.step(render=False)
    np.testing.assert_allclose(check(), at_reset, atol=2e-3)
    assert np.linalg.norm(hand.get_local_pose()[0] - hand.get_world_pose()[0]) > 0.5
    positions, orientations = view.get_local_poses()   # the view agrees, link by link
    assert view.prim_paths == ["/World/Franka/panda_link0", "/World/Franka/panda_hand"]
    np.testing.assert_allclose(positions, [link0.get_local_pose()[0], hand.get_local_pose()[0]], atol=1e-9)
    np.testing.assert_allclose(orientations[1], hand.get_local_pose()[1], atol=1e-9)
