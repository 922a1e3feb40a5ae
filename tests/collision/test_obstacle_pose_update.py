"""`update_obstacle_pose(name, [x, y, z])`: a position alone moves an obstacle and keeps its rotation."""

from __future__ import annotations

import numpy as np

from manip import MotionGenerator, Pose
from manip.collision.shapes import Cuboid


def test_a_position_alone_keeps_the_rotation() -> None:
    mg = MotionGenerator("franka")
    q0 = mg.default_joint_positions
    hand = mg.fk(q0).position
    # a thin wall turned 90 degrees about z: 0.6 m long along x, 2 cm thick along y
    quarter = np.array([np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)])
    mg.add_obstacle(Cuboid("wall", [0.02, 0.6, 0.6], Pose([2.0, 2.0, 2.0], quarter)))
    assert not mg.check_collision(q0)
    target = hand + np.array([0.25, 0.0, 0.0])   # turned, the wall reaches back through the hand
    mg.update_obstacle_pose("wall", list(target))
    moved = mg.world.get("wall").pose
    np.testing.assert_allclose(moved.position, target)
    np.testing.assert_allclose(abs(moved.quaternion @ quarter), 1.0, atol=1e-12)
    assert mg.check_collision(q0)
    # a full pose still sets the rotation: unturned, the wall is 0.25 m in front of the hand
    mg.update_obstacle_pose("wall", [*target, 1.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(mg.world.get("wall").pose.quaternion, [1.0, 0.0, 0.0, 0.0])
    assert not mg.check_collision(q0)
    # and so does a Pose
    mg.update_obstacle_pose("wall", Pose(target, quarter))
    assert mg.check_collision(q0)
