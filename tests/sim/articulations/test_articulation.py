"""Articulations and drives: tracking, teleporting, action semantics, gains, modes, errors."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from manip.errors import InvalidInputError, UnknownNameError
from manip.sim import (
    ArticulationAction,
    Franka,
    ParallelGripper,
    RigidPrim,
    Robot,
    SimulationError,
    SingleManipulator,
    World,
    XFormPrim,
    add_reference_to_stage,
    get_assets_root_path,
)

ARM_TARGET = np.array([0.3, -0.4, 0.2, -2.0, 0.3, 1.9, 0.5])


@pytest.fixture
def franka_world():
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    return world, franka


def _ramp(world, franka, target, seconds=1.0):
    """Smooth position targets from the current positions to `target` (7,), then hold."""
    start = franka.get_joint_positions()[:7]
    n = int(seconds * 60)
    for i in range(n):
        s = 0.5 - 0.5 * np.cos(np.pi * (i + 1) / n)
        franka.apply_action(ArticulationAction(joint_positions=[*(start + s * (target - start)), None, None]))
        world.step(render=False)


def test_franka_tracks_a_reachable_joint_target(franka_world):
    world, franka = franka_world
    _ramp(world, franka, ARM_TARGET)
    for _ in range(60):
        world.step(render=False)
    err = np.abs(franka.get_joint_positions()[:7] - ARM_TARGET)
    assert err.max() < 0.02
    assert np.abs(franka.get_joint_velocities()).max() < 0.01


def test_set_joint_positions_teleports_and_holds(franka_world):
    world, franka = franka_world
    q = np.r_[ARM_TARGET, 0.02, 0.02]
    franka.set_joint_positions(q)
    assert np.array_equal(franka.get_joint_positions(), q)
    assert np.allclose(franka.get_applied_action().joint_positions, q)  # targets follow
    ee = franka.end_effector.get_world_pose()[0]
    for _ in range(120):
        world.step(render=False)
    assert np.abs(franka.get_joint_positions() - q).max() < 0.01
    assert np.linalg.norm(franka.end_effector.get_world_pose()[0] - ee) < 0.01
    # Subsets by index.
    franka.set_joint_positions([0.01, 0.01], joint_indices=[7, 8])
    assert np.allclose(franka.gripper.get_joint_positions(), 0.01)


def test_action_none_entries_keep_targets_and_efforts_default_to_zero(franka_world):
    world, franka = franka_world
    before = franka.get_applied_action()
    franka.apply_action(ArticulationAction(joint_positions=[None] * 7 + [0.01, None]))
    after = franka.get_applied_action()
    assert after.joint_positions[7] == 0.01
    assert np.array_equal(np.delete(after.joint_positions, 7), np.delete(before.joint_positions, 7))
    # A field left None is untouched.
    franka.apply_action(ArticulationAction(joint_velocities=np.full(9, 0.1)))
    assert np.allclose(franka.get_applied_action().joint_positions, after.joint_positions)
    assert np.allclose(franka.get_applied_action().joint_velocities, 0.1)
    # Efforts: NaN -> 0.
    franka.apply_action(ArticulationAction(joint_efforts=[1.0] + [None] * 8))
    assert np.array_equal(franka.get_applied_action().joint_efforts, np.r_[1.0, np.zeros(8)])
    # joint_indices address a subset.
    franka.apply_action(ArticulationAction(joint_positions=[0.1, 0.2], joint_indices=[0, 6]))
    t = franka.get_applied_action().joint_positions
    assert t[0] == 0.1 and t[6] == 0.2 and t[7] == 0.01


def test_gripper_forward_is_full_length_and_moves_the_fingers(franka_world):
    world, franka = franka_world
    a = franka.gripper.forward("close")
    assert a.get_length() == 9
    assert np.all(np.isnan(a.joint_positions[:7])) and np.array_equal(a.joint_positions[7:], [0.0, 0.0])
    franka.gripper.close()
    for _ in range(30):
        world.step(render=False)
    assert np.all(franka.gripper.get_joint_positions() < 0.002)
    franka.gripper.open()
    for _ in range(30):
        world.step(render=False)
    assert np.allclose(franka.gripper.get_joint_positions(), 0.04, atol=0.002)
    with pytest.raises(InvalidInputError):
        franka.gripper.forward("squeeze")
    # Isaac's gripper.apply_action takes the fingers' two entries; the whole robot's action of
    # forward() is for robot.apply_action, and the message says so.
    with pytest.raises(InvalidInputError, match=r"needs 2 entries .*got 9: gripper.forward\(\) returns the whole"):
        franka.gripper.apply_action(franka.gripper.forward("open"))
    franka.gripper.apply_action(ArticulationAction(joint_positions=[0.02, 0.02]))
    for _ in range(30):
        world.step(render=False)
    assert np.allclose(franka.gripper.get_joint_positions(), 0.02, atol=0.002)


def test_gripper_action_deltas_set_after_construction_step_the_fingers(franka_world):
    """Isaac's ParallelGripper.set_action_deltas / get_action_deltas (they raised
    NotImplementedError): with deltas, close() moves each finger by its delta from where it is."""
    world, franka = franka_world
    assert franka.gripper.get_action_deltas() is None
    franka.gripper.set_action_deltas(np.array([0.01, 0.01]))
    np.testing.assert_allclose(franka.gripper.get_action_deltas(), [0.01, 0.01])
    franka.gripper.close()
    for _ in range(30):
        world.step(render=False)
    np.testing.assert_allclose(franka.gripper.get_joint_positions(), 0.03, atol=0.002)
    franka.gripper.set_action_deltas(None)
    franka.gripper.close()
    for _ in range(30):
        world.step(render=False)
    assert np.all(franka.gripper.get_joint_positions() < 0.002)
    with pytest.raises(InvalidInputError, match="action_deltas"):
        franka.gripper.set_action_deltas([0.01, np.nan])


def test_bad_actions_raise_and_leave_the_state_unchanged(franka_world):
    world, franka = franka_world
    ctrl = franka.get_articulation_controller()
    before = ctrl.get_applied_action()
    q = franka.get_joint_positions()
    with pytest.raises(InvalidInputError, match="9 DoF"):
        ctrl.apply_action(ArticulationAction(joint_positions=np.zeros(7)))
    with pytest.raises(InvalidInputError, match="out of range"):
        ctrl.apply_action(ArticulationAction(joint_positions=[0.0], joint_indices=[9]))
    with pytest.raises(InvalidInputError):
        ArticulationAction(joint_positions=[np.inf] * 9)
    with pytest.raises(InvalidInputError, match="finite"):
        franka.set_joint_positions(np.r_[np.nan, q[1:]])
    with pytest.raises(InvalidInputError, match="exceeds the largest accepted magnitude"):
        franka.set_joint_positions(np.r_[5e6, q[1:]])
    with pytest.raises(InvalidInputError, match="entries"):
        franka.set_joint_positions(q[:3])
    with pytest.raises(InvalidInputError):
        ctrl.apply_action({"joint_positions": q})
    after = ctrl.get_applied_action()
    for f in ("joint_positions", "joint_velocities", "joint_efforts"):
        assert np.array_equal(getattr(before, f), getattr(after, f))
    assert np.array_equal(franka.get_joint_positions(), q)


def test_getters_before_the_first_reset_return_none_with_a_warning(caplog):
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    with caplog.at_level(logging.WARNING):
        assert franka.num_dof is None
        assert franka.dof_names is None
        assert franka.get_joint_positions() is None
        assert franka.dof_properties is None
    assert "before the first World.reset()" in caplog.text
    with pytest.raises(SimulationError, match="reset"):
        franka.set_joint_positions(np.zeros(9))
    with pytest.raises(SimulationError):
        franka.get_articulation_controller().apply_action(ArticulationAction(joint_positions=np.zeros(9)))
    world.reset()
    assert franka.num_dof == 9


def test_dof_names_index_and_properties(franka_world):
    world, franka = franka_world
    assert franka.dof_names == [f"panda_joint{i}" for i in range(1, 8)] + ["panda_finger_joint1", "panda_finger_joint2"]
    assert franka.get_dof_index("panda_finger_joint2") == 8
    with pytest.raises(UnknownNameError, match="panda_joint1"):
        franka.get_dof_index("joint_x")
    props = franka.dof_properties
    assert props.dtype.names == ("type", "hasLimits", "lower", "upper", "driveMode", "maxVelocity", "maxEffort",
                                 "stiffness", "damping")
    assert list(props["type"]) == [1] * 7 + [2, 2]
    assert np.all(props["hasLimits"]) and np.all(props["driveMode"] == 1)
    assert props["lower"][3] == pytest.approx(-3.0718) and props["upper"][7] == pytest.approx(0.04)
    assert props["maxEffort"][0] == pytest.approx(87) and props["maxEffort"][6] == pytest.approx(12)
    assert props["maxVelocity"][0] == pytest.approx(2.175)
    kps, kds = franka.get_articulation_controller().get_gains()
    assert np.allclose(props["stiffness"], kps) and np.allclose(props["damping"], kds) and np.all(kps > 0)


def test_gains_and_modes_change_the_physics(franka_world):
    world, franka = franka_world
    ctrl = franka.get_articulation_controller()
    kps, kds = ctrl.get_gains()
    ctrl.switch_control_mode("effort")
    assert np.all(franka.dof_properties["driveMode"] == 0)
    q0 = franka.get_joint_positions()
    for _ in range(30):
        world.step(render=False)
    assert np.abs(franka.get_joint_positions() - q0)[:7].max() > 0.05  # the arm sags without drives
    ctrl.switch_control_mode("position")
    assert np.allclose(ctrl.get_gains()[0], kps)
    ctrl.set_gains(kps=kps * 2, kds=kds)
    assert np.allclose(franka.dof_properties["stiffness"], kps * 2)
    ctrl.set_max_efforts([50.0], joint_indices=[0])
    assert ctrl.get_max_efforts()[0] == 50.0
    with pytest.raises(InvalidInputError):
        ctrl.set_gains(kps=-kps)
    with pytest.raises(InvalidInputError):
        ctrl.switch_control_mode("torque")
    world.reset()  # post_reset restores the default gains and limits
    assert np.allclose(ctrl.get_gains()[0], kps) and ctrl.get_max_efforts()[0] == pytest.approx(87)
    assert np.allclose(franka.get_joint_positions(), q0)


def test_effort_and_velocity_modes_on_a_slider(slider_file):
    world = World(gravity=(0.0, 0.0, 0.0))
    add_reference_to_stage(slider_file, "/World/Slider")
    robot = world.scene.add(Robot("/World/Slider", name="slider"))
    world.reset()
    ctrl = robot.get_articulation_controller()
    assert robot.dof_properties["driveMode"][0] == 0  # no actuator in the file: no drive gains
    # Effort: F = 2 N on 1 kg for 0.5 s -> v = 1 m/s, x = 0.25 m.
    ctrl.apply_action(ArticulationAction(joint_efforts=[2.0]))
    for _ in range(30):
        world.step(render=False)
    assert robot.get_joint_velocities()[0] == pytest.approx(1.0, rel=1e-6)
    # Semi-implicit Euler over 270 substeps of 1/540 s: x = a dt^2 n (n + 1) / 2.
    n, dt = 30 * world.physics_substeps, world.model.opt.timestep
    assert robot.get_joint_positions()[0] == pytest.approx(2.0 * dt * dt * n * (n + 1) / 2, rel=1e-9)
    # Velocity drive: kd = 50 N s/m, target 0.3 m/s -> converges with time constant m/kd = 0.02 s.
    ctrl.apply_action(ArticulationAction(joint_efforts=[0.0], joint_velocities=[0.3]))
    ctrl.set_gains(kps=[0.0], kds=[50.0])
    assert robot.dof_properties["driveMode"][0] == 2
    for _ in range(30):
        world.step(render=False)
    assert robot.get_joint_velocities()[0] == pytest.approx(0.3, abs=1e-6)
    # Position drive: kp = 100 N/m, kd = 20 N s/m (critically damped) settles at the target.
    ctrl.set_gains(kps=[100.0], kds=[20.0])
    ctrl.apply_action(ArticulationAction(joint_positions=[0.5], joint_velocities=[0.0]))
    for _ in range(120):
        world.step(render=False)
    assert robot.get_joint_positions()[0] == pytest.approx(0.5, abs=1e-3)
    assert robot.get_applied_joint_efforts()[0] == pytest.approx(0.0, abs=0.1)


def test_robot_pose_and_unknown_prim():
    world = World()
    with pytest.raises(SimulationError, match="add_reference_to_stage"):
        Robot("/World/Nothing")
    with pytest.raises(FileNotFoundError):
        add_reference_to_stage("/no/such/file.xml", "/World/X")
    path = get_assets_root_path() + "/franka/franka.xml"
    add_reference_to_stage(path, "/World/Franka")
    robot = world.scene.add(Robot("/World/Franka", name="franka", position=[1.0, 0.5, 0.0]))
    world.reset()
    p, q = robot.get_world_pose()
    assert np.allclose(p, [1.0, 0.5, 0.0]) and np.allclose(q, [1, 0, 0, 0])
    robot.set_world_pose(position=[0.0, 0.0, 0.1])
    assert np.allclose(robot.get_world_pose()[0], [0.0, 0.0, 0.1])
    world.reset()
    assert np.allclose(robot.get_world_pose()[0], [1.0, 0.5, 0.0])
    assert robot.num_bodies == 11


def test_a_rigid_prim_on_a_link_reads_its_velocity_and_survives_resets():
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    hand = world.scene.add(RigidPrim("/World/Franka/panda_hand", name="hand"))  # Isaac: a link's rigid body
    assert np.all(hand.get_linear_velocity() == 0)  # authored at rest before the first reset
    world.reset()  # was AttributeError: the link had no default velocities
    franka.set_joint_velocities(np.r_[1.0, np.zeros(8)])  # 1 rad/s about the base's vertical axis
    sim = world.physics_sim_view
    com = sim.data.xipos[sim.model.body("/World/Franka/panda_hand").id]  # PhysX reports the COM's velocity
    np.testing.assert_allclose(hand.get_angular_velocity(), [0, 0, 1.0], atol=1e-9)
    np.testing.assert_allclose(hand.get_linear_velocity(), np.cross([0, 0, 1.0], com), atol=1e-9)
    with pytest.raises(SimulationError, match="follows the joints"):
        hand.set_linear_velocity([0, 0, 1.0])
    assert hand.get_mass() > 0
    world.step(render=False)
    world.reset()
    np.testing.assert_allclose(hand.get_linear_velocity(), 0.0, atol=1e-9)


TWO_LINK_URDF = """<robot name="two_link">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
    </inertial></link>
  <link name="l1"><inertial><origin xyz="0 0 0.25"/><mass value="1"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.25"/><geometry><box size="0.05 0.05 0.4"/></geometry></collision></link>
  <link name="l2"><inertial><origin xyz="0 0 0.25"/><mass value="1"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.25"/><geometry><box size="0.05 0.05 0.4"/></geometry></collision></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="40" velocity="2"/></joint>
  <joint name="elbow" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.5"/>
    <axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="20" velocity="2"/></joint>
</robot>"""


def test_a_referenced_urdf_gets_isaacs_urdf_importer_drives_and_follows_actions(tmp_path):
    path = tmp_path / "two_link.urdf"
    path.write_text(TWO_LINK_URDF)
    world = World()
    add_reference_to_stage(usd_path=str(path), prim_path="/World/arm")
    arm = world.scene.add(Robot(prim_path="/World/arm", name="arm"))
    world.reset()
    props = arm.dof_properties
    assert arm.dof_names == ["shoulder", "elbow"]
    np.testing.assert_allclose(props["stiffness"], 1e3)  # was 0: a limp arm that ignored position actions
    np.testing.assert_allclose(props["damping"], 1e2)
    np.testing.assert_allclose(props["maxEffort"], [40.0, 20.0])  # the URDF's effort limits (was inf)
    target = np.array([0.5, -0.5])
    arm.apply_action(ArticulationAction(joint_positions=target))
    for _ in range(120):
        world.step(render=False)
    np.testing.assert_allclose(arm.get_joint_positions(), target, atol=0.02)  # against gravity


def test_single_manipulator_with_the_tutorials_gripper_opened_past_the_finger_limits(caplog):
    """Isaac's "Adding a New Manipulator": opened positions 0.05 m on the Panda's 0.04 m fingers."""
    world = World()
    world.scene.add_default_ground_plane()
    add_reference_to_stage(usd_path=get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", prim_path="/World/Franka")
    gripper = ParallelGripper(end_effector_prim_path="/World/Franka/panda_rightfinger",
                              joint_prim_names=["panda_finger_joint1", "panda_finger_joint2"],
                              joint_opened_positions=np.array([0.05, 0.05]),
                              joint_closed_positions=np.array([0.02, 0.02]), action_deltas=np.array([0.01, 0.01]))
    robot = world.scene.add(SingleManipulator(prim_path="/World/Franka", name="my_franka",
                                              end_effector_prim_name="panda_rightfinger", gripper=gripper))
    q0 = np.r_[ARM_TARGET, 0.05, 0.05]
    robot.set_joints_default_state(positions=q0)
    with caplog.at_level(logging.WARNING):
        world.reset()  # was InvalidInputError: the gripper's reset teleported the fingers to 0.05 m
    assert "panda_finger_joint1=0.0500 not in [0.0000, 0.0400]" in caplog.text
    np.testing.assert_allclose(robot.get_joint_positions(), np.r_[ARM_TARGET, 0.04, 0.04], atol=1e-9)
    assert robot.gripper is gripper
    np.testing.assert_allclose(robot.end_effector.get_world_pose()[0],
                               XFormPrim("/World/Franka/panda_rightfinger").get_world_pose()[0])
    close = robot.gripper.forward("close")  # with deltas: 0.01 m in from where the fingers are
    np.testing.assert_allclose(close.joint_positions[7:], 0.03, atol=1e-9)
    assert np.all(np.isnan(close.joint_positions[:7]))
    robot.apply_action(close)
    for _ in range(30):
        world.step(render=False)
    np.testing.assert_allclose(robot.gripper.get_joint_positions(), 0.03, atol=2e-3)
    robot.gripper.open()  # target 0.05: the fingers stop on their 0.04 m limit
    for _ in range(30):
        world.step(render=False)
    np.testing.assert_allclose(robot.gripper.get_joint_positions(), 0.04, atol=1e-4)
    with pytest.raises(InvalidInputError, match="exactly one"):
        SingleManipulator(prim_path="/World/Franka", name="other")


def test_switching_back_from_velocity_mode_keeps_the_targets_as_isaac(franka_world):
    """Isaac's switch_control_mode changes the gains only: after moving in velocity mode, the old
    position target and the velocity target still drive the joints (Franka joints 2 and 4 saturate
    at 87 N m); applying the current positions and zero velocities before switching holds the arm."""
    world, franka = franka_world
    ctrl = franka.get_articulation_controller()
    kps, kds = ctrl.get_gains()
    q_home = franka.get_joint_positions()
    vel = np.array([0, 0.3, 0, 0.3, 0, 0, 0, 0, 0.0])

    def move_in_velocity_mode():
        ctrl.switch_control_mode("velocity", joint_indices=np.arange(7))
        assert np.all(ctrl.get_gains()[0][:7] == 0)
        ctrl.apply_action(ArticulationAction(joint_velocities=vel))
        for _ in range(30):
            world.step(render=False)
        return franka.get_joint_positions()

    q = move_in_velocity_mode()
    assert q[1] - q_home[1] > 0.1
    ctrl.switch_control_mode("position", joint_indices=np.arange(7))
    assert np.allclose(ctrl.get_gains()[0], kps) and np.allclose(ctrl.get_gains()[1], kds)
    applied = ctrl.get_applied_action()
    assert np.allclose(applied.joint_positions, q_home) and np.allclose(applied.joint_velocities, vel)
    world.step(render=False)
    assert abs(franka.get_measured_joint_efforts()[1]) == pytest.approx(87.0)  # the drive's effort limit

    world.reset()
    q = move_in_velocity_mode()
    ctrl.apply_action(ArticulationAction(joint_positions=q, joint_velocities=np.zeros(9)))
    ctrl.switch_control_mode("position", joint_indices=np.arange(7))
    peak = 0.0
    for _ in range(30):
        world.step(render=False)
        peak = max(peak, float(np.abs(franka.get_measured_joint_efforts()[:7]).max()))
    assert peak < 60.0 and np.abs(franka.get_joint_positions() - q)[:7].max() < 0.02
