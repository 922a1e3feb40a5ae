"""`LulaKinematicsSolver` against manip's own kinematics: FK agrees, IK reaches its targets
(pose and position only, any base pose), fails cleanly on unreachable targets, and rejects bad
input; any URDF + Lula YAML works (the UR5 with a YAML written here)."""

from __future__ import annotations

import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import InvalidInputError, UnknownNameError
from manip.kinematics import Kinematics
from manip.pose import Pose
from manip.robot_config import load_robot_config
from manip.sim import LulaKinematicsSolver, get_extension_path_from_name, interface_config_loader

READY = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
DOWN = np.array([0.0, 1.0, 0.0, 0.0])
HAND_TO_RIGHT_GRIPPER = Pose(np.array([0.0, 0.0, 0.1]))


@pytest.fixture(scope="module")
def solver() -> LulaKinematicsSolver:
    return LulaKinematicsSolver(**interface_config_loader.load_supported_lula_kinematics_solver_config("Franka"))


@pytest.fixture(scope="module")
def franka_kinematics() -> Kinematics:
    return Kinematics(load_robot_config("franka"))


@pytest.fixture
def fresh(solver):
    """The module's solver, back at the identity base pose and default settings after the test."""
    yield solver
    solver.set_robot_base_pose(np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]))
    solver.set_default_cspace_seeds(np.empty((0, 7)))
    solver.set_default_position_tolerance(1e-3)
    solver.set_default_orientation_tolerance(0.01)


def _pose(p, R) -> Pose:
    return Pose(p, quat.from_matrix(R))


def test_the_tutorials_file_paths_give_the_same_solver(solver):
    mg = get_extension_path_from_name("omni.isaac.motion_generation")
    assert get_extension_path_from_name("isaacsim.robot_motion.motion_generation") == mg
    other = LulaKinematicsSolver(robot_description_path=mg + "/motion_policy_configs/franka/rmpflow/robot_descriptor.yaml",
                                 urdf_path=mg + "/motion_policy_configs/franka/lula_franka_gen.urdf")
    assert other.get_joint_names() == [f"panda_joint{i}" for i in range(1, 8)]
    assert other.get_all_frame_names() == solver.get_all_frame_names()
    assert {"panda_link0", "panda_hand", "panda_hand_tcp", "right_gripper"} <= set(solver.get_all_frame_names())
    lower, upper = solver.get_cspace_position_limits()
    cfg = load_robot_config("franka")
    np.testing.assert_allclose(lower, cfg.lower_limits)
    np.testing.assert_allclose(upper, cfg.upper_limits)
    assert solver.supports_collision_avoidance() is False


def test_fk_agrees_with_manips_fk_and_right_gripper_is_01_m_beyond_the_hand(solver, franka_kinematics):
    rng = np.random.default_rng(3)
    for q in [READY, *rng.uniform(franka_kinematics.lower, franka_kinematics.upper, (20, 7))]:
        for frame in ("panda_link4", "panda_hand", "panda_hand_tcp"):
            p, R = solver.compute_forward_kinematics(frame, q)
            assert _pose(p, R).isclose(franka_kinematics.fk(q, frame), 1e-9, 1e-7), frame
        p, R = solver.compute_forward_kinematics("right_gripper", q)
        expected = franka_kinematics.fk(q, "panda_hand") @ HAND_TO_RIGHT_GRIPPER
        assert _pose(p, R).isclose(expected, 1e-9, 1e-7)
    # at the ready configuration the frame points down, 0.1 m below the hand
    p, R = solver.compute_forward_kinematics("right_gripper", READY, position_only=True)
    np.testing.assert_allclose(R[:, 2], [0.0, 0.0, -1.0], atol=1e-6)
    np.testing.assert_allclose(p, franka_kinematics.fk(READY, "panda_hand").position - [0.0, 0.0, 0.1], atol=1e-9)


def test_base_pose_moves_fk_and_ik_into_the_world_frame(fresh, franka_kinematics):
    solver = fresh
    T_world_base = Pose(np.array([0.3, -0.2, 0.1]), quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), 0.6))
    solver.set_robot_base_pose(T_world_base.position, T_world_base.quaternion)
    p, R = solver.compute_forward_kinematics("panda_hand", READY)
    assert _pose(p, R).isclose(T_world_base @ franka_kinematics.fk(READY, "panda_hand"), 1e-9, 1e-7)
    target = np.array([0.8, 0.1, 0.35])
    q, ok = solver.compute_inverse_kinematics("right_gripper", target, DOWN, warm_start=READY)
    assert ok
    p, R = solver.compute_forward_kinematics("right_gripper", q)
    assert np.linalg.norm(p - target) <= 1e-3
    assert quat.angle_between(quat.from_matrix(R), DOWN) <= 0.01
    # the same world target from the base frame, checked with manip's FK
    in_base = T_world_base.inverse() @ Pose(target, DOWN)
    assert (franka_kinematics.fk(q, "panda_hand") @ HAND_TO_RIGHT_GRIPPER).isclose(in_base, 1e-3, 0.01)


def test_ik_honours_the_tolerances_and_is_deterministic(fresh):
    solver = fresh
    target = np.array([0.45, 0.25, 0.3])
    q1, ok1 = solver.compute_inverse_kinematics("right_gripper", target, DOWN, warm_start=READY,
                                                position_tolerance=1e-5, orientation_tolerance=1e-4)
    q2, ok2 = solver.compute_inverse_kinematics("right_gripper", target, DOWN, warm_start=READY,
                                                position_tolerance=1e-5, orientation_tolerance=1e-4)
    assert ok1 and ok2
    np.testing.assert_array_equal(q1, q2)
    p, R = solver.compute_forward_kinematics("right_gripper", q1)
    assert np.linalg.norm(p - target) <= 1e-5
    assert quat.angle_between(quat.from_matrix(R), DOWN) <= 1e-4
    lower, upper = solver.get_cspace_position_limits()
    assert np.all(q1 >= lower) and np.all(q1 <= upper)


def test_position_only_ik_reaches_the_point_with_any_orientation(fresh):
    solver = fresh
    for target in ([0.5, -0.2, 0.4], [0.3, 0.4, 0.6], [-0.3, -0.3, 0.2]):
        q, ok = solver.compute_inverse_kinematics("right_gripper", np.array(target), warm_start=READY)
        assert ok, target
        p, _ = solver.compute_forward_kinematics("right_gripper", q)
        assert np.linalg.norm(p - target) <= 1e-3


def test_unreachable_targets_fail_with_joint_positions_within_the_limits(fresh):
    solver = fresh
    lower, upper = solver.get_cspace_position_limits()
    for orientation in (DOWN, None):
        q, ok = solver.compute_inverse_kinematics("right_gripper", np.array([1.5, 0.0, 0.5]), orientation,
                                                  warm_start=READY)
        assert ok is False
        assert q.shape == (7,) and np.all(q >= lower - 1e-12) and np.all(q <= upper + 1e-12)
    # a position reached only pointing up (1.15 m above the base, near full stretch): pointing
    # down, the wrist would have to be higher than the arm reaches
    high = np.array([0.0, 0.0, 1.15])
    assert solver.compute_inverse_kinematics("right_gripper", high, DOWN, warm_start=READY)[1] is False
    q, ok = solver.compute_inverse_kinematics("right_gripper", high, warm_start=READY)
    assert ok and np.linalg.norm(solver.compute_forward_kinematics("right_gripper", q)[0] - high) <= 1e-3


def test_default_cspace_seeds_are_tried_after_the_warm_start(fresh):
    solver = fresh
    seed = np.array([1.0, 0.3, -0.8, -1.8, 0.6, 2.2, -0.5])
    p, R = solver.compute_forward_kinematics("right_gripper", seed + 0.05)
    target = (p, quat.from_matrix(R))
    q_default, ok = solver.compute_inverse_kinematics("right_gripper", *target)  # from the default configuration
    assert ok and np.abs(q_default - seed).max() > 0.3
    solver.set_default_cspace_seeds(np.array([seed]))
    np.testing.assert_array_equal(solver.get_default_cspace_seeds()[0], seed)
    q, ok = solver.compute_inverse_kinematics("right_gripper", *target)
    assert ok and np.abs(q - seed).max() < 0.1  # solved from the seed
    q, ok = solver.compute_inverse_kinematics("right_gripper", *target, warm_start=READY)
    assert ok and np.abs(q - seed).max() > 0.3  # the warm start comes first and succeeds
    solver.set_default_position_tolerance(0.02)
    assert solver.get_default_position_tolerance() == 0.02
    solver.set_default_orientation_tolerance(0.2)
    assert solver.get_default_orientation_tolerance() == 0.2


def test_bad_input_raises_naming_the_argument(fresh):
    solver = fresh
    with pytest.raises(UnknownNameError, match="right_gripper"):
        solver.compute_forward_kinematics("gripper", READY)
    with pytest.raises(UnknownNameError, match="panda_hand"):
        solver.compute_inverse_kinematics("tool0", np.zeros(3))
    with pytest.raises(InvalidInputError, match=r"joint_positions must have shape \(7,\)"):
        solver.compute_forward_kinematics("panda_hand", READY[:6])
    with pytest.raises(InvalidInputError, match="joint_positions must be finite"):
        solver.compute_forward_kinematics("panda_hand", np.where(np.arange(7) == 2, np.nan, READY))
    with pytest.raises(InvalidInputError, match="target_position"):
        solver.compute_inverse_kinematics("panda_hand", np.array([0.4, np.nan, 0.3]), DOWN)
    with pytest.raises(InvalidInputError, match="target_orientation"):
        solver.compute_inverse_kinematics("panda_hand", np.array([0.4, 0.0, 0.3]), np.array([0.0, 2.0, 0.0, 0.0]))
    with pytest.raises(InvalidInputError, match="target_orientation"):
        solver.compute_inverse_kinematics("panda_hand", np.array([0.4, 0.0, 0.3]), np.array([0.0, 1.0, 0.0]))
    with pytest.raises(InvalidInputError, match="warm_start"):
        solver.compute_inverse_kinematics("panda_hand", np.array([0.4, 0.0, 0.3]), DOWN, warm_start=np.zeros(9))
    with pytest.raises(InvalidInputError, match="position_tolerance"):
        solver.compute_inverse_kinematics("panda_hand", np.array([0.4, 0.0, 0.3]), DOWN, position_tolerance=-1.0)
    with pytest.raises(InvalidInputError, match="robot_orientation"):
        solver.set_robot_base_pose(np.zeros(3), np.array([0.0, 0.0, 0.0, 0.0]))
    with pytest.raises(InvalidInputError, match="seeds"):
        solver.set_default_cspace_seeds(np.zeros((2, 6)))
    with pytest.raises(InvalidInputError, match="robot_description"):
        LulaKinematicsSolver("a.yaml", "b.urdf", robot_description=object())


def test_missing_files_raise_file_not_found_listing_the_mapped_names(tmp_path):
    mg = get_extension_path_from_name("omni.isaac.motion_generation")
    yaml_path = mg + "/motion_policy_configs/franka/rmpflow/robot_descriptor.yaml"
    with pytest.raises(FileNotFoundError, match="lula_franka_gen.urdf"):
        LulaKinematicsSolver(yaml_path, str(tmp_path / "ur10_gen.urdf"))
    with pytest.raises(FileNotFoundError, match="robot_description_path"):
        LulaKinematicsSolver(str(tmp_path / "missing.yaml"), mg + "/motion_policy_configs/franka/lula_franka_gen.urdf")
    with pytest.raises(UnknownNameError, match="extension"):
        get_extension_path_from_name("omni.isaac.franka")


UR5_YAML = """
api_version: 1.0
cspace: [wrist_3_joint, shoulder_pan_joint, shoulder_lift_joint, elbow_joint, wrist_1_joint, wrist_2_joint]
root_link: base_link
default_q: [0.0, 0.0, -2.2, 1.9, -1.383, -1.57]
acceleration_limits: [15, 15, 15, 15, 15, 15]
collision_spheres: []
"""
UR5_ORDER = [5, 0, 1, 2, 3, 4]  # cspace index -> manip's joint index (URDF tree order)


def test_a_second_robot_from_its_urdf_and_a_yaml_with_joints_out_of_tree_order(tmp_path):
    cfg = load_robot_config("ur5")
    (tmp_path / "ur5.yaml").write_text(UR5_YAML)
    solver = LulaKinematicsSolver(str(tmp_path / "ur5.yaml"), str(cfg.urdf_path))
    assert solver.get_joint_names()[0] == "wrist_3_joint"
    assert {"world", "base_link", "tool0", "ee_link"} <= set(solver.get_all_frame_names())
    assert "right_gripper" not in solver.get_all_frame_names()
    kin = Kinematics(cfg)
    T_world_base = Pose(np.array([1.0, 0.5, 0.2]), quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), -2.0))
    solver.set_robot_base_pose(T_world_base.position, T_world_base.quaternion)
    T_model_base = kin.fk(cfg.default_joint_positions, "base_link")
    rng = np.random.default_rng(0)
    for q_manip in rng.uniform(-3.0, 3.0, (10, 6)):
        q_lula = q_manip[[5, 0, 1, 2, 3, 4]]
        p, R = solver.compute_forward_kinematics("tool0", q_lula)
        expected = T_world_base @ T_model_base.inverse() @ kin.fk(q_manip, "tool0")
        assert _pose(p, R).isclose(expected, 1e-9, 1e-7)
    target = T_world_base @ T_model_base.inverse() @ kin.fk(cfg.default_joint_positions + 0.3, "tool0")
    q, ok = solver.compute_inverse_kinematics("tool0", target.position, target.quaternion,
                                              warm_start=np.array([0.0, 0.0, -2.2, 1.9, -1.383, -1.57]))
    assert ok
    p, R = solver.compute_forward_kinematics("tool0", q)
    assert _pose(p, R).isclose(target, 1e-3, 0.01)


def test_fixed_rules_hold_joints_outside_the_cspace(tmp_path):
    """The fingers held where cspace_to_urdf_rules says: their links move with the value."""
    base = """
cspace: [panda_joint1, panda_joint2, panda_joint3, panda_joint4, panda_joint5, panda_joint6, panda_joint7]
cspace_to_urdf_rules:
  - {name: panda_finger_joint1, rule: fixed, value: %s}
"""
    urdf = get_extension_path_from_name("omni.isaac.motion_generation") + "/motion_policy_configs/franka/lula_franka_gen.urdf"
    y = []
    for value in (0.0, 0.03):
        path = tmp_path / f"f{value}.yaml"
        path.write_text(base % value)
        p, R = LulaKinematicsSolver(str(path), urdf).compute_forward_kinematics("panda_leftfinger", READY)
        y.append(R.T @ (p - LulaKinematicsSolver(str(path), urdf).compute_forward_kinematics("panda_hand", READY)[0]))
    np.testing.assert_allclose(y[1] - y[0], [0.0, 0.03, 0.0], atol=1e-9)  # the finger slides along the hand's y
