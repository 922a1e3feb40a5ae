"""A camera placed below a robot's link ("/World/Franka/panda_hand/wrist_cam") rides on it,
as in Isaac: before, `world.reset()` raised "the referenced model has no body or site of that
name"."""

from __future__ import annotations

import math

import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.sim import Camera, FixedCuboid, Franka, World, XFormPrim

# Isaac's "world" camera axes look along +X; turned -90 deg about y they look along the link's +z
ALONG_Z = quat.from_axis_angle(np.array([0.0, 1.0, 0.0]), -math.pi / 2)


def _scene(**camera_pose):
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    # a 2 m slab whose top is at z = 0.2, under the hand (the hand's z points down at home)
    world.scene.add(FixedCuboid("/World/slab", name="slab", position=[0.3, 0.0, 0.1], scale=[2.0, 2.0, 0.2], size=1.0))
    cam = world.scene.add(Camera("/World/Franka/panda_hand/wrist_cam", name="wrist_cam", resolution=(64, 48), **camera_pose))
    world.reset()
    return world, franka, cam


def test_a_wrist_camera_sees_along_the_hand_and_moves_with_it():
    world, franka, cam = _scene(translation=[0.0, 0.0, 0.1], orientation=ALONG_Z)
    assert cam.mount_link == "/World/Franka/panda_hand"
    hand = XFormPrim("/World/Franka/panda_hand")
    p_hand, q_hand = hand.get_world_pose()
    p_cam, _ = cam.get_world_pose()
    np.testing.assert_allclose(p_cam, p_hand + quat.to_matrix(q_hand) @ [0.0, 0.0, 0.1], atol=1e-9)
    # looking straight down from 0.1 m below the flange at the slab's top (z = 0.2)
    assert cam.get_depth()[23:25, 31:33] == pytest.approx(p_cam[2] - 0.2, abs=1e-3)
    np.testing.assert_allclose(cam.get_local_pose()[0], [0.0, 0.0, 0.1], atol=1e-12)
    # turn the first joint: the camera goes with the hand
    franka.set_joint_positions(np.array([0.8]), joint_indices=[0])
    world.step(render=False)
    p_hand, q_hand = hand.get_world_pose()
    p_cam, q_cam = cam.get_world_pose(camera_axes="usd")
    np.testing.assert_allclose(p_cam, p_hand + quat.to_matrix(q_hand) @ [0.0, 0.0, 0.1], atol=1e-6)
    assert np.linalg.norm(p_cam[:2]) > 0.2 and abs(math.atan2(p_cam[1], p_cam[0]) - 0.8) < 1e-3
    assert cam.get_depth()[24, 32] == pytest.approx(p_cam[2] - 0.2, abs=1e-3)
    points = cam.get_pointcloud()
    assert np.abs(points[np.isfinite(points).all(axis=1), 2] - 0.2).max() < 1e-3  # on the slab's top


def test_a_world_position_is_kept_in_the_links_frame_and_reset_restores_it():
    # given in the world (the robot at its authored pose): 5 cm beside the flange
    world, franka, cam = _scene(translation=[0.05, 0.0, 0.0])
    p_world, _ = cam.get_world_pose()
    World.clear_instance()
    world, franka, cam2 = _scene(position=p_world)
    np.testing.assert_allclose(cam2.get_local_pose()[0], [0.05, 0.0, 0.0], atol=1e-9)
    cam2.set_local_pose(translation=[0.0, 0.1, 0.0])
    np.testing.assert_allclose(cam2.get_local_pose()[0], [0.0, 0.1, 0.0])
    world.reset()
    np.testing.assert_allclose(cam2.get_local_pose()[0], [0.05, 0.0, 0.0], atol=1e-9)
    # set_world_pose keeps the camera on the link, at the pose it gives in the link's frame
    target = cam2.get_world_pose()[0] + [0.0, 0.0, 0.02]
    cam2.set_world_pose(position=target)
    np.testing.assert_allclose(cam2.get_world_pose()[0], target, atol=1e-9)
    franka.set_joint_positions(np.array([0.5]), joint_indices=[0])
    world.step(render=False)
    assert np.linalg.norm(cam2.get_world_pose()[0] - target) > 0.05


def test_a_camera_inside_a_robot_but_below_no_link_says_where_to_put_it():
    world = World()
    world.scene.add(Franka("/World/Franka", name="franka"))
    cam = Camera("/World/Franka/panda_hand/mount/deeper/cam", resolution=(32, 24))  # nearest link: the hand
    assert cam.mount_link == "/World/Franka/panda_hand"
    with pytest.raises(InvalidInputError, match="below none of its links"):
        Camera("/World/Franka/cam", resolution=(32, 24))
