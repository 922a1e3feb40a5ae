"""`RMPFlowController.get_motion_policy()`: RmpFlow's world interface bound to the controller
(Isaac scripts add obstacles and set the base pose through it)."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from manip.errors import InvalidInputError, UnknownNameError
from manip.sim import FixedCuboid, FollowTarget, GroundPlane, RMPFlowController, VisualSphere, World


def contacts_between(world: World, robot_prefix: str, geom_id: int) -> int:
    m, d = world.model, world.data
    bodies = [m.geom_bodyid[g] for c in d.contact[: d.ncon] for g in (c.geom1, c.geom2) if geom_id in (c.geom1, c.geom2)
              and g != geom_id]
    return sum(m.body(b).name.startswith(robot_prefix) for b in bodies)


def _scene():
    world = World()
    task = FollowTarget(target_position=[0.45, 0.0, 0.45])
    world.add_task(task)
    wall = world.scene.add(FixedCuboid("/World/Wall", name="wall", position=[0.55, 0.0, 0.4], size=1.0,
                                       scale=[0.04, 0.6, 0.6]))
    world.reset()
    return world, task.robot, wall


def test_an_obstacle_added_through_the_motion_policy_is_the_controllers():
    world, franka, wall = _scene()
    controller = RMPFlowController("follow", franka)
    policy = controller.get_motion_policy()
    assert policy is controller.get_motion_policy()
    assert policy.get_active_joints() == [f"panda_joint{i}" for i in range(1, 8)] and policy.get_watched_joints() == []
    policy.set_robot_base_pose(*franka.get_world_pose())  # Isaac's call: the same pose, nothing said
    assert policy.add_cuboid(wall) is True
    assert policy.add_obstacle(wall) is False  # Isaac: added once, False
    assert controller.controller.world.names == [wall.prim_path]
    behind = np.array([0.7, 0.0, 0.45])
    contacts = 0
    for _ in range(200):
        franka.apply_action(controller.forward(behind, [0.0, 1.0, 0.0, 0.0]))
        world.step(render=False)
        contacts += contacts_between(world, franka.prim_path + "/", wall.geom_id)
    assert contacts == 0 and controller.last_result.position_error > 0.1  # held in front of the wall
    # The end effector's pose as the policy computes it is the simulated hand's.
    q = franka.get_joint_positions()[:7]
    p, R = policy.get_end_effector_pose(q)
    assert np.linalg.norm(p - franka.end_effector.get_world_pose()[0]) < 1e-6 and np.allclose(R @ R.T, np.eye(3))
    # Shared both ways: the controller removes what the policy added.
    controller.remove_obstacle(wall)
    with pytest.raises(UnknownNameError, match="Wall. not found"):
        policy.remove_obstacle(wall)
    with pytest.raises(InvalidInputError, match="add_sphere"):
        policy.add_sphere(wall)


def test_the_policys_reset_forgets_obstacles_and_a_wrong_base_pose_is_reported(caplog):
    world, franka, wall = _scene()
    ground = world.scene.add_default_ground_plane()
    controller = RMPFlowController("follow", franka)
    policy = controller.get_motion_policy()
    assert policy.add_obstacle(ground) and policy.add_cuboid(wall, static=True)
    assert isinstance(ground, GroundPlane) and len(controller.controller.world.names) == 2
    policy.disable_obstacle(wall)
    assert controller.controller.world.names == [ground.prim_path]
    policy.enable_obstacle(wall)
    policy.update_world([wall])
    with pytest.raises(UnknownNameError):
        policy.update_world([world.scene.add(VisualSphere("/World/s", name="s", radius=0.05))])
    policy.reset()
    assert controller.controller.world.names == []
    with caplog.at_level(logging.WARNING):
        policy.set_robot_base_pose([1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0])
    assert "follows the articulation's pose" in caplog.text
    with pytest.raises(InvalidInputError, match="robot_orientation"):
        policy.set_robot_base_pose([0.0, 0.0, 0.0], [1.0, 1.0, 0.0, 0.0])
