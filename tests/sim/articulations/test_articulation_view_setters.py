"""ArticulationView's setters Isaac scripts call on views (they raised NotImplementedError):
`set_max_efforts`, `switch_dof_control_mode`, `get_applied_actions`, `set_world_poses` and the
view's own joint default state, applied by its `post_reset` after the robot's, as Isaac's."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import Articulation, ArticulationAction, ArticulationView, DynamicCuboid, Franka, World

HOME = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8, 0.04, 0.04])


@pytest.fixture
def franka():
    world = World()
    world.scene.add_default_ground_plane()
    robot = world.scene.add(Franka("/World/Franka", name="franka"))
    view = world.scene.add(ArticulationView(prim_paths_expr="/World/Franka", name="franka_view"))
    world.reset()
    return world, robot, view


def test_set_max_efforts_limits_the_drive_that_holds_the_arm(franka):
    world, robot, view = franka
    hold = view.get_generalized_gravity_forces()[0, 1]  # shoulder torque holding the arm [N m]
    assert abs(hold) > 2.0
    view.set_max_efforts(np.array([[0.2 * abs(hold)]]), joint_indices=[1])
    np.testing.assert_allclose(view.get_max_efforts()[0, :3], [87.0, 0.2 * abs(hold), 87.0])
    q0 = robot.get_joint_positions()[1]
    for _ in range(60):
        world.step(render=False)
    assert abs(robot.get_joint_positions()[1] - q0) > 0.2  # too weak to hold the arm: it sags
    with pytest.raises(InvalidInputError, match="max efforts"):
        view.set_max_efforts([-1.0], joint_indices=[0])


def test_switch_dof_control_mode_and_applied_actions(franka):
    world, robot, view = franka
    view.switch_dof_control_mode("velocity", 0)
    kps, kds = view.get_gains()
    assert kps[0, 0] == 0 and kds[0, 0] > 0 and kps[0, 1] > 0
    robot.apply_action(ArticulationAction(joint_velocities=[0.4], joint_indices=[0]))
    for _ in range(60):
        world.step(render=False)
    assert robot.get_joint_velocities()[0] == pytest.approx(0.4, abs=0.02)
    actions = view.get_applied_actions()
    assert actions.joint_positions.shape == actions.joint_velocities.shape == actions.joint_efforts.shape == (1, 9)
    assert actions.joint_velocities[0, 0] == pytest.approx(0.4)
    np.testing.assert_allclose(actions.joint_positions[0], robot.get_applied_action().joint_positions)


def test_set_world_poses_moves_the_fixed_base_until_the_reset(franka):
    world, robot, view = franka
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[1.0, 0, 0.05], size=0.1))
    world.reset()
    view.set_world_poses(positions=np.array([[1.5, 0.0, 0.0]]), orientations=np.array([[0.0, 0.0, 0.0, 1.0]]))
    np.testing.assert_allclose(robot.get_world_pose()[0], [1.5, 0, 0], atol=1e-9)
    hand = robot.end_effector.get_world_pose()[0]
    assert hand[0] < 1.5  # turned half a turn: the hand is on the cube's side
    for _ in range(10):
        world.step(render=False)
    np.testing.assert_allclose(view.get_world_poses()[0], [[1.5, 0, 0]], atol=1e-9)
    world.reset()
    np.testing.assert_allclose(view.get_world_poses()[0], [[0, 0, 0]], atol=1e-9)
    with pytest.raises(InvalidInputError):
        view.set_world_poses(orientations=[[0.0, 0.0, 0.0, 0.0]])


def test_the_views_joint_default_state_applies_at_every_reset(franka):
    world, robot, view = franka
    np.testing.assert_allclose(view.get_joints_default_state().positions[0], robot.get_joints_default_state().positions)
    view.set_joints_default_state(positions=HOME[None, :])
    assert view.get_joints_default_state().positions.shape == (1, 9)
    robot.set_joint_positions(np.zeros(9))
    world.reset()
    np.testing.assert_allclose(robot.get_joint_positions(), HOME, atol=1e-9)
    for _ in range(60):
        world.step(render=False)
    np.testing.assert_allclose(robot.get_joint_positions(), HOME, atol=0.02)  # the targets too
    with pytest.raises(InvalidInputError):
        view.set_joints_default_state(positions=np.zeros(5))


def test_a_view_made_before_its_robot_still_applies_its_default_state_last():
    world = World()
    world.scene.add_default_ground_plane()
    from manip.sim import add_reference_to_stage, get_assets_root_path

    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", "/World/Franka")
    view = world.scene.add(Articulation(prim_paths_expr="/World/Franka", name="view"))  # Isaac 5's name
    robot = world.scene.add(Articulation("/World/Franka", name="robot"))
    world.reset()
    view.set_joints_default_state(positions=HOME)
    robot.set_joints_default_state(positions=np.zeros(9))
    world.reset()
    np.testing.assert_allclose(robot.get_joint_positions(), HOME, atol=1e-9)


def test_a_view_applies_isaacs_batched_articulation_actions(franka):
    """`from omni.isaac.core.utils.types import ArticulationActions` (an ImportError from manip.sim
    before): a (1, K) batch of targets drives the view's robot."""
    from manip.sim import ArticulationActions

    world, robot, view = franka
    target = np.array([[0.3, -0.5]])
    view.apply_action(ArticulationActions(joint_positions=target, joint_indices=np.array([0, 1])))
    for _ in range(120):
        world.step(render=False)
    np.testing.assert_allclose(robot.get_joint_positions()[:2], target[0], atol=0.02)
    np.testing.assert_allclose(view.get_applied_actions().joint_positions[0, :2], target[0])
