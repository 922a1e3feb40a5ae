"""Isaac's RMPflow names (`RmpFlow`, `ArticulationMotionPolicy`, `MotionPolicyController`,
`load_supported_motion_policy_config`) on manip's QP controller: the loader's dict builds an
RmpFlow; compute_joint_targets reaches targets without a simulator; a simulated Franka
reaches a target and keeps clear of an obstacle it was given (and hits it when not given
it); obstacle bookkeeping as Lula's world; bad input raises naming what is valid."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import InvalidInputError, UnknownNameError
from manip.robot_config import load_robot_config

# The tutorial's imports, changed (README "Porting a tutorial"):
#   from omni.isaac.motion_generation import RmpFlow, ArticulationMotionPolicy, interface_config_loader
from manip.sim import (
    ArticulationMotionPolicy,
    DynamicSphere,
    FixedCuboid,
    Franka,
    LulaKinematicsSolver,
    MotionPolicyController,
    RmpFlow,
    SimulationError,
    VisualCapsule,
    VisualCone,
    VisualCuboid,
    World,
    get_extension_path_from_name,
    interface_config_loader,
)

DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # (w, x, y, z): right_gripper's z axis pointing down
BASE_POSITION = np.array([0.3, -0.2, 0.1])
BASE_ORIENTATION = quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), 0.6)
#: Hand down, turned with the base (world frame): the same problem as DOWN for an unturned base.
DOWN_TURNED = quat.multiply(BASE_ORIENTATION, DOWN)
#: A target in front of the robot, in its base frame [m].
TARGET_IN_BASE = np.array([0.5, 0.2, 0.4])
#: Simulated end effector to target under gravity [m]: the Franka's position drives have no
#: gravity compensation and settle 2.8-5.1 mm below their command (README, Lula kinematics;
#: measured here 4.8 mm), plus the controller's own residual (0.4 mm, the posture task).
REACH_TOLERANCE_GRAVITY = 0.006
#: The same without gravity: the controller's residual only.
REACH_TOLERANCE = 0.001
STEPS = 300  # 5 s at 60 Hz: a 0.3 m move from the ready pose, starting at rest (converged by ~4 s)


def _config(**changes) -> dict:
    return {**interface_config_loader.load_supported_motion_policy_config("Franka", "RMPflow"), **changes}


@pytest.fixture(scope="module")
def rmpflow() -> RmpFlow:
    return RmpFlow(**_config())


# ------------------------------------------------------------------ loader and construction
def test_the_loader_returns_the_dict_rmpflow_takes():
    assert interface_config_loader.get_supported_robot_policy_pairs() == {"Franka": ["RMPflow"]}
    config = _config()
    assert set(config) == {"robot_description_path", "urdf_path", "rmpflow_config_path", "end_effector_frame_name",
                           "maximum_substep_size", "ignore_robot_state_updates"}
    assert config["end_effector_frame_name"] == "right_gripper" and config["maximum_substep_size"] == 0.00334
    rmp_config_dir = Path(get_extension_path_from_name("omni.isaac.motion_generation")) / "motion_policy_configs"
    assert Path(config["rmpflow_config_path"]).resolve() == rmp_config_dir / "franka/rmpflow/franka_rmpflow_common.yaml"
    policy = RmpFlow(**config)
    assert policy.get_active_joints() == [f"panda_joint{i}" for i in range(1, 8)]
    assert policy.get_watched_joints() == []
    assert policy.controlled_frame == "panda_hand"  # right_gripper is 0.1 m beyond it, not in the MuJoCo model
    # The tutorial's direct construction from the extension's folder.
    direct = RmpFlow(robot_description_path=str(rmp_config_dir) + "/franka/rmpflow/robot_descriptor.yaml",
                     urdf_path=str(rmp_config_dir) + "/franka/lula_franka_gen.urdf",
                     rmpflow_config_path=str(rmp_config_dir) + "/franka/rmpflow/franka_rmpflow_common.yaml",
                     end_effector_frame_name="right_gripper", maximum_substep_size=0.00334)
    q = direct.get_default_cspace_position_target()
    assert np.allclose(q, [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
    # The end effector is the URDF's right_gripper: 0.1 m along panda_hand's z.
    solver = direct.get_kinematics_solver()
    assert isinstance(solver, LulaKinematicsSolver)
    p_hand, R_hand = solver.compute_forward_kinematics("panda_hand", q)
    p, R = direct.get_end_effector_pose(q)
    assert np.allclose(p, p_hand + 0.1 * R_hand[:, 2], atol=1e-9) and np.allclose(R, R_hand, atol=1e-9)


def test_unknown_robot_or_policy_names_the_supported_ones():
    with pytest.raises(UnknownNameError, match="Franka"):
        interface_config_loader.load_supported_motion_policy_config("UR10", "RMPflow")
    with pytest.raises(UnknownNameError, match="RMPflow"):
        interface_config_loader.load_supported_motion_policy_config("Franka", "RRT")


def test_a_policy_folder_of_ones_own_for_another_robot(tmp_path):
    """The UR5 (its URDF's root is a `world` link fixed to base_link; the end effector tool0 is a
    body of manip's model), loaded as Isaac loads a policy folder."""
    ur5 = load_robot_config("ur5")
    (tmp_path / "ur5").mkdir()
    (tmp_path / "ur5" / "ur5.yaml").write_text(
        "cspace: [shoulder_pan_joint, shoulder_lift_joint, elbow_joint, wrist_1_joint, wrist_2_joint, wrist_3_joint]\n"
        "default_q: [0.0, -1.2, 1.5, -1.9, -1.57, 0.0]\n")
    (tmp_path / "ur5" / "rmpflow.yaml").write_text("manip:\n    robot: ur5\n    safety_margin: 0.03\n")
    (tmp_path / "ur5" / "config.json").write_text(json.dumps({
        "relative_asset_paths": {"robot_description_path": "ur5.yaml", "urdf_path": str(ur5.urdf_path),
                                 "rmpflow_config_path": "rmpflow.yaml"},
        "end_effector_frame_name": "tool0", "maximum_substep_size": 1 / 300}))
    (tmp_path / "policy_map.json").write_text(json.dumps({"UR5": {"RMPflow": "./ur5/config.json"}}))
    assert interface_config_loader.get_supported_robot_policy_pairs(tmp_path) == {"UR5": ["RMPflow"]}
    policy = RmpFlow(**interface_config_loader.load_supported_motion_policy_config("UR5", "RMPflow", str(tmp_path)))
    assert policy.controlled_frame == "tool0" and policy.controller.safety_margin == 0.03
    q = policy.get_default_cspace_position_target()
    target = policy.get_end_effector_pose(q)[0] + np.array([0.1, 0.1, -0.1])
    policy.set_end_effector_target(target)
    q, _ = _run(policy, q, STEPS)
    assert np.linalg.norm(policy.get_end_effector_pose(q)[0] - target) < REACH_TOLERANCE


# ------------------------------------------------------------------ without the simulator
def _run(policy: RmpFlow, q: np.ndarray, steps: int) -> tuple[np.ndarray, np.ndarray]:
    v = np.zeros_like(q)
    for _ in range(steps):
        q, v = policy.compute_joint_targets(q, v, np.empty(0), np.empty(0), 1 / 60)
    return q, v


def test_compute_joint_targets_reaches_pose_position_and_orientation_targets(rmpflow):
    policy = rmpflow
    policy.reset()
    policy.set_robot_base_pose(BASE_POSITION, BASE_ORIENTATION)
    T_world_base = np.eye(4)
    T_world_base[:3, :3], T_world_base[:3, 3] = quat.to_matrix(BASE_ORIENTATION), BASE_POSITION
    target = (T_world_base @ np.append(TARGET_IN_BASE, 1.0))[:3]
    q0 = policy.get_default_cspace_position_target()
    lower, upper = load_robot_config("franka").lower_limits, load_robot_config("franka").upper_limits
    # Pose target (world frame).
    policy.set_end_effector_target(target, DOWN_TURNED)
    q, v = _run(policy, q0, STEPS)
    p, R = policy.get_end_effector_pose(q)
    assert np.linalg.norm(p - target) < REACH_TOLERANCE
    assert quat.angle_between(quat.from_matrix(R), DOWN_TURNED) < 0.01
    assert np.all(q >= lower) and np.all(q <= upper) and np.max(np.abs(v)) < 1e-3  # at rest there
    # Position only: the end effector (not the controlled panda_hand) reaches the point.
    moved = target + np.array([0.0, -0.3, 0.1])
    policy.set_end_effector_target(moved)
    q, _ = _run(policy, q, STEPS)
    assert np.linalg.norm(policy.get_end_effector_pose(q)[0] - moved) < REACH_TOLERANCE
    # Orientation only: the hand turns 90 deg about the world z; the position is free.
    turned = quat.multiply(quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), np.pi / 2), DOWN_TURNED)
    policy.set_end_effector_target(None, turned)
    q, _ = _run(policy, q, STEPS)
    assert quat.angle_between(quat.from_matrix(policy.get_end_effector_pose(q)[1]), turned) < 0.01
    # No target: to the cspace target.
    cspace_target = q0 + np.array([0.3, 0.2, 0.0, 0.1, 0.0, -0.2, 0.0])
    policy.set_cspace_target(cspace_target)
    policy.set_end_effector_target()
    q, _ = _run(policy, q, 2 * STEPS)
    assert np.max(np.abs(q - cspace_target)) < 1e-3
    assert policy.controller.weights.position == 1.0  # restored after the orientation-only target


def test_internal_state_and_restarts(rmpflow):
    policy = rmpflow
    policy.reset()
    q0 = policy.get_default_cspace_position_target()
    policy.set_end_effector_target(TARGET_IN_BASE, DOWN)
    q1, v1 = policy.compute_joint_targets(q0, np.zeros(7), [], [], 1 / 60)
    assert np.array_equal(policy.get_internal_robot_joint_states()[0], q1)
    # A state within RESYNC_TOLERANCE of the command: the command goes on (drive sag ignored).
    q2, _ = policy.compute_joint_targets(q1 - 0.05, np.zeros(7), [], [], 1 / 60)
    policy.set_internal_robot_joint_states(q1, v1, [], [])
    q2_again, _ = policy.compute_joint_targets(q1, v1, [], [], 1 / 60)
    assert np.allclose(q2, q2_again, atol=1e-12)
    # A state far from it (the robot was moved): the step starts from the given state.
    far = q1 + 0.5
    q3, _ = policy.compute_joint_targets(far, np.zeros(7), [], [], 1 / 60)
    assert np.max(np.abs(q3 - far)) < 0.1
    # ignore_robot_state_updates: the given state is used once only.
    policy.ignore_robot_state_updates = True  # Isaac's attribute, or set_ignore_state_updates(True)
    policy.reset()
    a, _ = policy.compute_joint_targets(q0, np.zeros(7), [], [], 1 / 60)
    b, _ = policy.compute_joint_targets(q0 + 0.5, np.zeros(7), [], [], 1 / 60)
    assert np.max(np.abs(b - a)) < 0.1
    policy.set_ignore_state_updates(False)


# ------------------------------------------------------------------ in the simulator
def _world_with_franka(gravity=(0.0, 0.0, -9.81), obstacle_position=None):
    World.clear_instance()
    world = World(stage_units_in_meters=1.0, gravity=gravity)
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka", position=BASE_POSITION,
                                    orientation=BASE_ORIENTATION))
    cube = None
    if obstacle_position is not None:
        cube = world.scene.add(FixedCuboid("/World/obstacle", name="obstacle", position=obstacle_position, size=0.08,
                                           color=np.array([0.0, 0.0, 1.0])))
    world.reset()
    return world, franka, cube


def _in_world(p_base: np.ndarray) -> np.ndarray:
    return BASE_POSITION + quat.to_matrix(BASE_ORIENTATION) @ p_base


def _contacts(world, franka, geom_id: int) -> int:
    d, m = world.data, world.model
    robot = {b for b in range(m.nbody) if m.body(b).name.startswith(franka.prim_path + "/")}
    return sum(1 for c in d.contact[: d.ncon]
               if (c.geom1 == geom_id and m.geom_bodyid[c.geom2] in robot)
               or (c.geom2 == geom_id and m.geom_bodyid[c.geom1] in robot))


@pytest.mark.parametrize("gravity, tolerance", [((0.0, 0.0, -9.81), REACH_TOLERANCE_GRAVITY),
                                                ((0.0, 0.0, 0.0), REACH_TOLERANCE)], ids=["gravity", "no_gravity"])
def test_a_simulated_franka_follows_the_target(gravity, tolerance):
    world, franka, _ = _world_with_franka(gravity)
    rmpflow = RmpFlow(**_config())
    rmpflow.set_robot_base_pose(*franka.get_world_pose())
    policy = ArticulationMotionPolicy(franka, rmpflow, default_physics_dt=1 / 60)
    target = _in_world(TARGET_IN_BASE)
    rmpflow.set_end_effector_target(target, DOWN_TURNED)
    fingers = franka.get_joint_positions()[7:]
    for _ in range(STEPS):
        rmpflow.update_world()
        action = policy.get_next_articulation_action(world.get_physics_dt())
        assert list(action.joint_indices) == list(range(7))  # the arm only; the fingers are left alone
        franka.apply_action(action)
        world.step(render=False)
    # Measured in the simulation: the URDF's right_gripper at the robot's joints, and the hand's body.
    q = franka.get_joint_positions()
    p, R = rmpflow.get_end_effector_pose(q[:7])
    assert np.linalg.norm(p - target) < tolerance
    assert quat.angle_between(quat.from_matrix(R), DOWN_TURNED) < 0.02
    hand = franka.end_effector.get_world_pose()[0]  # panda_hand_tcp, 3.4 mm beyond right_gripper
    assert abs(np.linalg.norm(hand - target) - 0.0034) < tolerance
    assert np.allclose(q[7:], fingers, atol=1e-3)


@pytest.mark.parametrize("given, restart_every_frame", [(True, False), (False, False), (True, True)],
                         ids=["obstacle_given", "obstacle_not_given", "given_but_restarting_every_frame"])
def test_the_arm_keeps_clear_of_an_obstacle_it_was_given(given, restart_every_frame):
    # The cube stands on the straight way from the ready pose to the first target, below the arm
    # between the second and the third.
    obstacle = _in_world(np.array([0.4, 0.0, 0.37]))
    world, franka, cube = _world_with_franka(obstacle_position=obstacle)
    rmpflow = RmpFlow(**_config())
    rmpflow.set_robot_base_pose(*franka.get_world_pose())
    if restart_every_frame:  # from the measured joints every frame, as Isaac's RMPflow
        rmpflow.resync_tolerance = 1e-9
    controller = MotionPolicyController("follow", ArticulationMotionPolicy(franka, rmpflow))
    if given:
        controller.add_obstacle(cube)
    contacts = 0
    clearance = []
    for target in (np.array([0.5, 0.0, 0.2]), np.array([0.4, 0.3, 0.4]), np.array([0.4, -0.3, 0.4])):
        for _ in range(240):
            franka.apply_action(controller.forward(_in_world(target), DOWN_TURNED))
            world.step(render=False)
            contacts += _contacts(world, franka, cube.geom_id)
            clearance.append(rmpflow.last_result.obstacle_clearance)
    if given and not restart_every_frame:
        assert contacts == 0
        assert min(clearance) > 0.01  # the 2 cm margin of manip's rmpflow YAML, less the linearisation's creep
    else:  # the same motions hit the cube: without it, or when the command follows the drives' sag onto it
        assert contacts > 0


def test_a_ground_plane_is_a_slab_below_it():
    world, franka, _ = _world_with_franka()
    ground = world.scene.get_object("default_ground_plane")
    rmpflow = RmpFlow(**_config())
    rmpflow.set_robot_base_pose(*franka.get_world_pose())
    assert rmpflow.add_obstacle(ground) and rmpflow.add_ground_plane(ground) is False
    slab = rmpflow.controller.world.get(ground.prim_path)
    assert np.allclose(slab.dims, [50.0, 50.0, 0.001]) and np.isclose(slab.pose.position[2], -0.0005 - BASE_POSITION[2])
    rmpflow.set_end_effector_target(_in_world(np.array([0.5, 0.0, -0.2])), DOWN_TURNED)  # 0.1 m below the ground
    q, _ = _run(rmpflow, rmpflow.get_default_cspace_position_target(), STEPS)
    assert rmpflow.last_result.obstacle_clearance > 0.015  # the 2 cm margin, less the creep
    assert rmpflow.get_end_effector_pose(q)[0][2] > 0.0  # the ground is z = 0 (the base stands 0.1 m above it)


def test_obstacles_are_tracked_as_in_lulas_world():
    world, franka, _ = _world_with_franka()
    cube = world.scene.add(VisualCuboid("/World/box", name="box", position=[0.5, 0.0, 0.3], size=0.1))
    ball = world.scene.add(DynamicSphere("/World/ball", name="ball", position=[0.5, 0.4, 0.5], radius=0.05))
    rod = world.scene.add(VisualCapsule("/World/rod", name="rod", position=[0.5, -0.4, 0.5], radius=0.02, height=0.2))
    cone = world.scene.add(VisualCone("/World/cone", name="cone", position=[0.2, 0.5, 0.3], radius=0.05, height=0.1))
    rmpflow = RmpFlow(**_config())
    rmpflow.set_robot_base_pose(*franka.get_world_pose())
    assert rmpflow.add_obstacle(cube) and rmpflow.add_sphere(ball, static=True) and rmpflow.add_capsule(rod)
    assert rmpflow.add_cone(cone)
    assert rmpflow.add_obstacle(cube) is False  # twice: kept once, as Isaac
    with pytest.raises(InvalidInputError, match="VisualCuboid"):
        rmpflow.add_cuboid(ball)

    def pose_in_base(name):
        return rmpflow.controller.world.get(name).pose.position

    T_base_world_R = quat.to_matrix(BASE_ORIENTATION).T
    rmpflow.update_world()  # the base was placed since the obstacles were added: every one re-read
    cube.set_world_pose(position=np.array([0.6, 0.1, 0.35]))
    ball.set_world_pose(position=np.array([0.6, 0.5, 0.55]))
    rmpflow.update_world()  # the dynamic ones only
    assert np.allclose(pose_in_base("/World/box"), T_base_world_R @ (np.array([0.6, 0.1, 0.35]) - BASE_POSITION))
    assert np.allclose(pose_in_base("/World/ball"), T_base_world_R @ (np.array([0.5, 0.4, 0.5]) - BASE_POSITION))
    rmpflow.set_robot_base_pose(*franka.get_world_pose())  # unchanged: not a move
    rmpflow.update_world([cube])
    assert np.allclose(pose_in_base("/World/ball"), T_base_world_R @ (np.array([0.5, 0.4, 0.5]) - BASE_POSITION))
    rmpflow.set_robot_base_pose(np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]))  # the base moved: static ones too
    rmpflow.update_world([cube])
    assert np.allclose(pose_in_base("/World/ball"), [0.6, 0.5, 0.55])
    # Disable / enable / remove; unknown ones raise listing the added ones.
    n = rmpflow.controller.collision_pair_counts[0]
    assert rmpflow.disable_obstacle(rod) and rmpflow.controller.collision_pair_counts[0] < n
    assert rmpflow.enable_obstacle(rod) and rmpflow.controller.collision_pair_counts[0] == n
    assert rmpflow.remove_obstacle(rod)
    with pytest.raises(UnknownNameError, match="/World/box"):
        rmpflow.remove_obstacle(rod)
    with pytest.raises(UnknownNameError, match="/World/ball"):
        rmpflow.update_world([rod])
    rmpflow.reset()  # as Isaac's: the world is cleared
    assert len(rmpflow.controller.world) == 0


def test_the_debug_drawings_do_nothing_and_say_so_once(caplog):
    policy = RmpFlow(**_config())
    with caplog.at_level(logging.WARNING, logger="manip.sim.motion_generation.rmpflow"):
        for _ in range(2):
            policy.visualize_collision_spheres()
            policy.delete_collision_sphere_prims()
            assert policy.get_collision_spheres_as_prims() == []
    said = [r.getMessage() for r in caplog.records]
    assert len(said) == 3 and all("does nothing in manip" in m and "collision spheres" in m for m in said)


# ------------------------------------------------------------------ bad input
def test_bad_input_raises_naming_what_is_valid(rmpflow, tmp_path):
    q = rmpflow.get_default_cspace_position_target()
    with pytest.raises(UnknownNameError, match="right_gripper"):
        RmpFlow(**_config(end_effector_frame_name="gripper"))
    with pytest.raises(InvalidInputError, match="maximum_substep_size"):
        RmpFlow(**_config(maximum_substep_size=0.0))
    with pytest.raises(InvalidInputError, match="ignore_robot_state_updates"):
        RmpFlow(**_config(ignore_robot_state_updates="no"))
    with pytest.raises(FileNotFoundError, match="rmpflow_config_path"):
        RmpFlow(**_config(rmpflow_config_path=str(tmp_path / "missing.yaml")))
    bad = tmp_path / "bad.yaml"
    bad.write_text("manip:\n    safety_margn: 0.02\n")
    with pytest.raises(InvalidInputError, match="safety_margin"):
        RmpFlow(**_config(rmpflow_config_path=str(bad)))
    lula_only = tmp_path / "lula.yaml"  # an Isaac file: Lula's keys ignored, the controller's defaults
    lula_only.write_text("joint_limit_buffers: [.01, .03, .01, .01, .01, .01, .01]\nrmp_params: {}\n")
    assert RmpFlow(**_config(rmpflow_config_path=str(lula_only))).controller.safety_margin == 0.01
    franka_urdf = str(load_robot_config("franka").urdf_path)  # a file: no alias says which robot it is
    with pytest.raises(InvalidInputError, match="franka"):
        RmpFlow(**_config(rmpflow_config_path=str(lula_only), urdf_path=franka_urdf, end_effector_frame_name="panda_hand"))
    with pytest.raises(InvalidInputError, match="active_joint_positions.*panda_joint1"):
        rmpflow.compute_joint_targets(q[:6], np.zeros(7), [], [], 1 / 60)
    with pytest.raises(InvalidInputError, match="active_joint_velocities"):
        rmpflow.compute_joint_targets(q, np.full(7, np.nan), [], [], 1 / 60)
    with pytest.raises(InvalidInputError, match="watched_joint_positions"):
        rmpflow.compute_joint_targets(q, np.zeros(7), [0.0], [], 1 / 60)
    with pytest.raises(InvalidInputError, match="frame_duration"):
        rmpflow.compute_joint_targets(q, np.zeros(7), [], [], 0.0)
    with pytest.raises(InvalidInputError, match="target_orientation"):
        rmpflow.set_end_effector_target([0.4, 0.0, 0.4], [1.0, 0.2, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="target_position"):
        rmpflow.set_end_effector_target([0.4, np.nan, 0.4])
    with pytest.raises(InvalidInputError, match="robot_position"):
        rmpflow.set_robot_base_pose([0.0, 0.0], [1.0, 0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="active_joint_targets"):
        rmpflow.set_cspace_target(np.zeros(9))
    with pytest.raises(InvalidInputError, match="shape object"):
        rmpflow.add_obstacle("a cube")
    with pytest.raises(InvalidInputError, match="motion_policy"):
        ArticulationMotionPolicy(object(), object())
    with pytest.raises(InvalidInputError, match="ArticulationMotionPolicy"):
        MotionPolicyController("c", rmpflow)


def test_a_robot_used_before_reset_raises():
    World.clear_instance()
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    policy = ArticulationMotionPolicy(franka, RmpFlow(**_config()))
    with pytest.raises(SimulationError, match="world.reset"):
        policy.get_next_articulation_action()
    with pytest.raises(InvalidInputError, match="physics_dt"):
        policy.get_next_articulation_action(-1.0)
