"""Isaac's Lula kinematics tutorial, its imports changed, on a simulated Franka: IK actions
bring the end effector to the target in the World; FK of the robot's joints is where the
World puts the hand; bad input and a robot used before reset fail clearly; a second robot."""

from __future__ import annotations

import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import InvalidInputError, UnknownNameError

# The tutorial's imports, changed (README "Porting a tutorial"):
#   from omni.isaac.motion_generation import LulaKinematicsSolver, ArticulationKinematicsSolver, interface_config_loader
#   from omni.isaac.core.utils.extensions import get_extension_path_from_name
#   from omni.isaac.core.articulations import Articulation ... import carb
from manip.sim import (
    Articulation,
    ArticulationAction,
    ArticulationKinematicsSolver,
    LulaKinematicsSolver,
    RigidPrim,
    SimulationError,
    World,
    add_reference_to_stage,
    carb,
    get_assets_root_path,
    get_extension_path_from_name,
    interface_config_loader,
)

BASE_POSITION = np.array([0.3, -0.2, 0.1])
BASE_ORIENTATION = quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), 0.6)
DOWN = np.array([0.0, 1.0, 0.0, 0.0])


def _world_with_franka(gravity=(0.0, 0.0, -9.81)):
    world = World(stage_units_in_meters=1.0, gravity=gravity)
    world.scene.add_default_ground_plane()
    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", "/World/Franka")
    franka = world.scene.add(Articulation("/World/Franka", name="franka", position=BASE_POSITION,
                                          orientation=BASE_ORIENTATION))
    world.reset()
    return world, franka


def _settle(world, steps=300):
    for _ in range(steps):
        world.step(render=False)


def _tutorial_step(franka, art_kin, kin, target_position, target_orientation):
    """The tutorial's per-frame code, as written for Isaac."""
    robot_base_translation, robot_base_orientation = franka.get_world_pose()
    kin.set_robot_base_pose(robot_base_translation, robot_base_orientation)
    action, success = art_kin.compute_inverse_kinematics(target_position, target_orientation)
    if success:
        franka.apply_action(action)
    else:
        carb.log_warn("IK did not converge to a solution.  No action is being taken")
    return action, success


def test_the_tutorial_brings_right_gripper_to_each_target_in_the_world():
    world, franka = _world_with_franka()
    kinematics_config = interface_config_loader.load_supported_lula_kinematics_solver_config("Franka")
    kin = LulaKinematicsSolver(**kinematics_config)
    print(kin.get_all_frame_names())
    art_kin = ArticulationKinematicsSolver(franka, kin, "right_gripper")
    hand = RigidPrim("/World/Franka/panda_hand")
    for target in ([0.75, 0.0, 0.4], [0.55, 0.3, 0.25], [0.6, -0.35, 0.5]):
        target = np.array(target)
        action, success = _tutorial_step(franka, art_kin, kin, target, DOWN)
        assert success, target
        np.testing.assert_array_equal(action.joint_indices, np.arange(7))
        p_cmd, R_cmd = kin.compute_forward_kinematics("right_gripper", action.joint_positions)
        assert np.linalg.norm(p_cmd - target) <= 1e-3  # the commanded joints reach the target
        assert quat.angle_between(quat.from_matrix(R_cmd), DOWN) <= 0.01
        _settle(world)
        ee_position, ee_rot_mat = art_kin.compute_end_effector_pose()
        # the drives (PD, no gravity compensation) hold the arm a little below its command:
        # 4.4, 5.1 and 2.8 mm here (under 0.1 mm without gravity, the next test)
        assert np.linalg.norm(ee_position - target) < 6e-3, target
        assert quat.angle_between(quat.from_matrix(ee_rot_mat), DOWN) < 0.02
        # FK of the simulated joints is where the World has the hand (right_gripper 0.1 m along its z)
        p_hand, q_hand = hand.get_world_pose()
        np.testing.assert_allclose(ee_position, p_hand + 0.1 * quat.to_matrix(np.asarray(q_hand))[:, 2], atol=1e-6)
        np.testing.assert_allclose(ee_rot_mat, quat.to_matrix(np.asarray(q_hand)), atol=1e-6)


def test_without_gravity_the_world_reaches_the_ik_target_exactly():
    """The few mm above are the drives' gravity sag: without gravity the frame settles on the target."""
    world, franka = _world_with_franka(gravity=(0.0, 0.0, 0.0))
    mg_path = get_extension_path_from_name("omni.isaac.motion_generation")
    kin = LulaKinematicsSolver(
        robot_description_path=mg_path + "/motion_policy_configs/franka/rmpflow/robot_descriptor.yaml",
        urdf_path=mg_path + "/motion_policy_configs/franka/lula_franka_gen.urdf")
    art_kin = ArticulationKinematicsSolver(franka, kin, "right_gripper")
    target = np.array([0.7, 0.0, 0.4])
    _, success = _tutorial_step(franka, art_kin, kin, target, DOWN)
    assert success
    _settle(world)
    ee_position, _ = art_kin.compute_end_effector_pose()
    assert np.linalg.norm(ee_position - target) < 1e-4


def test_position_only_and_a_failure_take_no_action(caplog):
    world, franka = _world_with_franka()
    kin = LulaKinematicsSolver(**interface_config_loader.load_supported_lula_kinematics_solver_config("Franka"))
    art_kin = ArticulationKinematicsSolver(franka, kin, "right_gripper")
    target = np.array([0.5, 0.2, 0.45])
    _, success = _tutorial_step(franka, art_kin, kin, target, None)
    assert success
    _settle(world)
    assert np.linalg.norm(art_kin.compute_end_effector_pose(position_only=True)[0] - target) < 5e-3
    q_before = franka.get_joint_positions()
    with caplog.at_level("WARNING", logger="manip.sim.carb"):
        action, success = _tutorial_step(franka, art_kin, kin, np.array([2.0, 0.0, 0.5]), DOWN)
    assert success is False and "IK did not converge" in caplog.text
    assert action.joint_positions.shape == (7,)
    _settle(world, 50)
    np.testing.assert_allclose(franka.get_joint_positions(), q_before, atol=1e-3)


def test_end_effector_frame_setters_and_bad_input():
    world, franka = _world_with_franka()
    kin = LulaKinematicsSolver(**interface_config_loader.load_supported_lula_kinematics_solver_config("Franka"))
    with pytest.raises(UnknownNameError, match="right_gripper"):
        ArticulationKinematicsSolver(franka, kin, "panda_gripper")
    with pytest.raises(InvalidInputError, match="kinematics_solver"):
        ArticulationKinematicsSolver(franka, object(), "right_gripper")
    art_kin = ArticulationKinematicsSolver(franka, kin, "right_gripper")
    assert art_kin.get_kinematics_solver() is kin
    assert art_kin.get_joints_subset().joint_names == kin.get_joint_names()
    np.testing.assert_array_equal(art_kin.get_joints_subset().joint_indices, np.arange(7))
    art_kin.set_end_effector_frame("panda_hand")
    assert art_kin.get_end_effector_frame() == "panda_hand"
    kin.set_robot_base_pose(*franka.get_world_pose())
    p_hand, _ = RigidPrim("/World/Franka/panda_hand").get_world_pose()
    np.testing.assert_allclose(art_kin.compute_end_effector_pose()[0], p_hand, atol=1e-6)
    with pytest.raises(UnknownNameError):
        art_kin.set_end_effector_frame("hand")
    with pytest.raises(InvalidInputError, match="target_position"):
        art_kin.compute_inverse_kinematics(np.array([0.5, 0.0]))
    with pytest.raises(InvalidInputError, match="target_orientation"):
        art_kin.compute_inverse_kinematics(np.array([0.5, 0.0, 0.3]), np.array([1.0, 1.0, 0.0, 0.0]))


def test_a_robot_used_before_reset_raises():
    world = World()
    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", "/World/Franka")
    franka = world.scene.add(Articulation("/World/Franka", name="franka"))
    kin = LulaKinematicsSolver(**interface_config_loader.load_supported_lula_kinematics_solver_config("Franka"))
    art_kin = ArticulationKinematicsSolver(franka, kin, "right_gripper")
    with pytest.raises(SimulationError, match="reset"):
        art_kin.compute_inverse_kinematics(np.array([0.5, 0.0, 0.4]), DOWN)
    with pytest.raises(SimulationError, match="reset"):
        art_kin.compute_end_effector_pose()
    world.reset()
    assert art_kin.compute_inverse_kinematics(np.array([0.5, 0.0, 0.4]), DOWN)[1]


UR5_YAML = """
cspace: [shoulder_pan_joint, shoulder_lift_joint, elbow_joint, wrist_1_joint, wrist_2_joint, wrist_3_joint]
root_link: base_link
default_q: [0.0, -2.2, 1.9, -1.383, -1.57, 0.0]
"""


def test_a_second_robot_from_urdf_and_yaml_in_the_world(tmp_path):
    from manip.robot_config import load_robot_config

    cfg = load_robot_config("ur5")
    (tmp_path / "ur5.yaml").write_text(UR5_YAML)
    world = World(stage_units_in_meters=1.0)
    add_reference_to_stage(str(cfg.mjcf_path), "/World/UR5")
    ur5 = world.scene.add(Articulation("/World/UR5", name="ur5", position=np.array([-0.2, 0.4, 0.05]),
                                       orientation=quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), 2.5)))
    world.reset()
    ur5.set_joint_positions(cfg.default_joint_positions)
    ur5.apply_action(ArticulationAction(joint_positions=cfg.default_joint_positions))
    _settle(world, 50)
    kin = LulaKinematicsSolver(str(tmp_path / "ur5.yaml"), str(cfg.urdf_path))
    art_kin = ArticulationKinematicsSolver(ur5, kin, "tool0")
    kin.set_robot_base_pose(*ur5.get_world_pose())
    p0, _ = art_kin.compute_end_effector_pose()
    target = p0 + np.array([0.05, -0.1, 0.1])
    action, success = art_kin.compute_inverse_kinematics(target, DOWN)
    assert success
    ur5.apply_action(action)
    _settle(world)
    p, R = art_kin.compute_end_effector_pose()
    assert np.linalg.norm(p - target) < 5e-3
    assert quat.angle_between(quat.from_matrix(R), DOWN) < 0.02


def test_articulation_subset_reads_and_drives_its_joints_by_name():
    from manip.sim import ArticulationSubset

    world, franka = _world_with_franka(gravity=(0.0, 0.0, 0.0))
    subset = ArticulationSubset(franka, ["panda_joint7", "panda_joint1"])
    np.testing.assert_array_equal(subset.joint_indices, [6, 0])
    assert subset.num_joints == 2 and subset.joint_names == ["panda_joint7", "panda_joint1"]
    np.testing.assert_allclose(subset.get_joint_positions(), franka.get_joint_positions()[[6, 0]])
    subset.apply_action([0.5, 0.3])
    _settle(world, 200)
    np.testing.assert_allclose(subset.get_joint_positions(), [0.5, 0.3], atol=1e-3)
    np.testing.assert_allclose(subset.get_joint_velocities(), [0.0, 0.0], atol=1e-2)
    # a solver whose joints the robot does not have: the first use names them
    with pytest.raises(UnknownNameError, match="shoulder_pan_joint"):
        ArticulationSubset(franka, ["shoulder_pan_joint"]).get_joint_positions()
    with pytest.raises(InvalidInputError, match="articulation"):
        ArticulationSubset(object(), ["panda_joint1"])
