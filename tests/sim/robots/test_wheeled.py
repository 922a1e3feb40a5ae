"""Differential drive: controller formulas, the pose controller's decisions, the Jetbot."""

from __future__ import annotations

import math

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import (
    ArticulationAction,
    DifferentialController,
    WheelBasePoseController,
    Robot,
    WheeledRobot,
    World,
    add_reference_to_stage,
    euler_angles_to_quat,
    get_assets_root_path,
    jetbot_model_path,
)

R, B = 0.03, 0.1125


def test_differential_controller_formula_and_clipping():
    c = DifferentialController("d", wheel_radius=R, wheel_base=B)
    v, w = 0.5, math.pi / 4
    a = c.forward([v, w])
    assert np.allclose(a.joint_velocities, [(2 * v - w * B) / (2 * R), (2 * v + w * B) / (2 * R)])
    clipped = DifferentialController("d", R, B, max_linear_speed=0.1, max_angular_speed=0.5, max_wheel_speed=4.0)
    a = clipped.forward([1.0, 0.0])
    assert np.allclose(a.joint_velocities, [0.1 / R, 0.1 / R])  # linear clip first: 3.33 rad/s
    a = clipped.forward([0.0, 10.0])
    assert np.allclose(a.joint_velocities, [-0.5 * B / (2 * R), 0.5 * B / (2 * R)])
    a = DifferentialController("d", R, B, max_wheel_speed=3.0).forward([1.0, 0.0])
    assert np.allclose(a.joint_velocities, [3.0, 3.0])
    with pytest.raises(InvalidInputError):
        c.forward([np.nan, 0.0])
    with pytest.raises(InvalidInputError):
        DifferentialController("d", wheel_radius=0.0, wheel_base=B)


def _pose_cmd(start, yaw, goal, **kw):
    ctrl = WheelBasePoseController("p", DifferentialController("d", R, B))
    return ctrl.forward(np.array([*start, 0.0]), euler_angles_to_quat([0, 0, yaw]), np.array(goal), **kw).joint_velocities


def test_wheel_base_pose_controller_decisions():
    # Inside position_tol: stop.
    assert np.allclose(_pose_cmd([0.79, 0.8], 0.0, [0.8, 0.8]), 0.0)
    # Facing the goal: drive straight at lateral_velocity.
    assert np.allclose(_pose_cmd([0, 0], math.pi / 4, [1, 1]), [0.2 / R, 0.2 / R])
    # Goal to the left: turn in place counter-clockwise (left wheel back).
    left, right = _pose_cmd([0, 0], 0.0, [0, 1])
    assert left < 0 < right and right == pytest.approx(0.5 * B / (2 * R))
    # Across the +-pi seam: heading 170 deg, goal at -170 deg -> wrapped error +20 deg -> CCW.
    goal = [math.cos(math.radians(-170)), math.sin(math.radians(-170))]
    left, right = _pose_cmd([0, 0], math.radians(170), goal)
    assert left < 0 < right


@pytest.fixture
def jetbot_world():
    world = World()
    world.scene.add_default_ground_plane()
    jetbot = world.scene.add(WheeledRobot("/World/Jetbot", name="jetbot",
                                          wheel_dof_names=["left_wheel_joint", "right_wheel_joint"],
                                          create_robot=True, usd_path=str(jetbot_model_path())))
    world.reset()
    return world, jetbot


def test_jetbot_reaches_the_goal_within_position_tol(jetbot_world):
    world, jetbot = jetbot_world
    assert list(jetbot.dof_properties["driveMode"]) == [2, 2]  # wheels in velocity mode after reset
    ctrl = WheelBasePoseController("p", DifferentialController("d", R, B))
    goal, tol = np.array([0.8, 0.8]), 0.04
    for _ in range(900):
        p, q = jetbot.get_world_pose()
        action = ctrl.forward(p, q, goal, position_tol=tol)
        jetbot.apply_wheel_actions(action)
        world.step(render=False)
        if np.allclose(action.joint_velocities, 0.0):
            break
    for _ in range(30):
        world.step(render=False)
    assert np.linalg.norm(jetbot.get_world_pose()[0][:2] - goal) < tol
    assert np.abs(jetbot.get_wheel_velocities()).max() < 0.1


def test_jetbot_drives_at_the_commanded_speed(jetbot_world):
    world, jetbot = jetbot_world
    jetbot.apply_wheel_actions(DifferentialController("d", R, B).forward([0.2, 0.0]))
    for _ in range(60):
        world.step(render=False)
    x0 = jetbot.get_world_pose()[0][0]
    for _ in range(60):
        world.step(render=False)
    assert jetbot.get_world_pose()[0][0] - x0 == pytest.approx(0.2, rel=0.1)  # 1 s at 0.2 m/s
    assert np.allclose(jetbot.get_wheel_velocities(), 0.2 / R, rtol=0.05)
    with pytest.raises(InvalidInputError, match="2 wheels"):
        jetbot.apply_wheel_actions(ArticulationAction(joint_velocities=[1.0, 1.0, 1.0]))


def test_jetbot_as_a_plain_robot_has_velocity_drives_and_drives_on_velocity_targets():
    """Isaac's "Hello Robot": the Jetbot wrapped as a Robot, driven through its controller."""
    world = World()
    world.scene.add_default_ground_plane()
    add_reference_to_stage(usd_path=get_assets_root_path() + "/Isaac/Robots/Jetbot/jetbot.usd",
                           prim_path="/World/Fancy_Robot")
    jetbot = world.scene.add(Robot(prim_path="/World/Fancy_Robot", name="fancy_robot"))
    world.reset()
    kps, kds = jetbot.get_articulation_controller().get_gains()
    assert np.all(kps == 0.0) and not np.any(np.signbit(kps)) and np.all(kds > 0)  # 0, not -0 (printed "-0.")
    jetbot.get_articulation_controller().apply_action(ArticulationAction(joint_velocities=np.array([5.0, 5.0])))
    for _ in range(120):
        world.step(render=False)
    assert jetbot.get_world_pose()[0][0] > 0.2  # about 0.15 m/s for 2 s
