"""Isaac's `utils.transformations` and `utils.distance_metrics` (ImportError before) on a
simulated scene: a Franka turned about z and a cube resting on the ground, read in each
other's frames; a camera's frame is USD's (-z forward)."""

from __future__ import annotations

import numpy as np
import pytest

from manip import Kinematics, load_robot_config
from manip.errors import InvalidInputError
from manip.sim import (
    Camera,
    DynamicCuboid,
    Franka,
    World,
    euler_angles_to_quat,
    get_prim_at_path,
    get_relative_transform,
    get_transform_with_normalized_rotation,
    get_translation_from_target,
    get_world_pose_from_relative,
    pose_from_tf_matrix,
    quat_to_rot_matrix,
    rotational_distance_angle,
    rotational_distance_identity_matrix_deviation,
    rotational_distance_single_axis,
    tf_matrices_from_poses,
    tf_matrix_from_pose,
    weighted_translational_distance,
)

TURNED = euler_angles_to_quat([0, 0, 90], degrees=True)


def test_poses_and_matrices_round_trip():
    q = euler_angles_to_quat([10, -20, 30], degrees=True)
    T = tf_matrix_from_pose([0.1, 0.2, 0.3], q)
    np.testing.assert_allclose(T[:3, :3], quat_to_rot_matrix(q), atol=1e-12)
    np.testing.assert_allclose(T[3], [0, 0, 0, 1])
    t, back = pose_from_tf_matrix(T)
    np.testing.assert_allclose(t, [0.1, 0.2, 0.3])
    np.testing.assert_allclose(back * np.sign(back[0]), q * np.sign(q[0]), atol=1e-12)
    many = tf_matrices_from_poses(np.array([[0, 0, 0], [0.1, 0.2, 0.3]]), np.array([[1, 0, 0, 0], q]))
    assert many.shape == (2, 4, 4)
    np.testing.assert_allclose(many[1], T, atol=1e-12)
    scaled = T.copy()
    scaled[:3, :3] *= [2.0, 3.0, 0.5]
    np.testing.assert_allclose(get_transform_with_normalized_rotation(scaled), T, atol=1e-12)
    with pytest.raises(InvalidInputError, match="unit quaternion"):
        tf_matrix_from_pose([0, 0, 0], [1, 1, 0, 0])
    with pytest.raises(InvalidInputError, match=r"\(4, 4\)"):
        pose_from_tf_matrix(np.eye(3))


def test_relative_transforms_between_a_robot_its_link_a_cube_and_a_camera():
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka", position=[0.5, 0.2, 0.0], orientation=TURNED))
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.9, 0.4, 0.1], size=0.05))
    camera = Camera("/World/camera", position=[0.9, 0.4, 1.0], resolution=(64, 48),
                    orientation=euler_angles_to_quat([0, 90, 0], degrees=True))   # looking down
    world.reset()
    for _ in range(60):                                   # the cube falls onto the ground
        world.step(render=False)
    # the hand in the robot's frame is the robot's forward kinematics (the base turned and moved)
    kin = Kinematics(load_robot_config("franka"))
    q = franka.get_joint_positions()[:7]
    hand = get_relative_transform("/World/Franka/panda_hand", get_prim_at_path("/World/Franka"))
    np.testing.assert_allclose(hand[:3, 3], kin.fk(q, "panda_hand").position, atol=1e-3)
    position, orientation = get_world_pose_from_relative(franka, hand[:3, 3], pose_from_tf_matrix(hand)[1])
    np.testing.assert_allclose(position, [0.5, 0.2, 0.0] + quat_to_rot_matrix(TURNED) @ hand[:3, 3], atol=1e-9)
    assert rotational_distance_angle(quat_to_rot_matrix(orientation), quat_to_rot_matrix(TURNED) @ hand[:3, :3]) < 1e-6
    # the resting cube, seen from the robot: (0.4, 0.2) ahead in the world is (0.2, -0.4) in the turned base
    in_robot = get_translation_from_target([0, 0, 0], cube, franka)
    np.testing.assert_allclose(in_robot, [0.2, -0.4, 0.025], atol=2e-3)
    # the camera (USD axes: -z forward) sees the cube 0.975 m in front, on its axis
    np.testing.assert_allclose(get_translation_from_target([0, 0, 0], "/World/cube", camera), [0, 0, -0.975],
                               atol=2e-3)
    # distance metrics between the hand and the cube frames
    cube_T = get_relative_transform(cube, "/World/defaultGroundPlane")
    assert weighted_translational_distance(cube_T, [0.9, 0.4, 0.025]) < 2e-3
    assert weighted_translational_distance([0, 0, 0], [1, 2, 2], np.diag([1.0, 0.0, 0.0])) == pytest.approx(1.0)
    hand_world = get_relative_transform("/World/Franka/panda_hand", "/World/defaultGroundPlane")
    down = quat_to_rot_matrix([0, 1, 0, 0])                   # the hand pointing down
    assert rotational_distance_single_axis(hand_world, down, [0, 0, 1]) < 0.05   # Franka's ready pose
    assert rotational_distance_angle(down, np.eye(3)) == pytest.approx(np.pi)
    assert rotational_distance_identity_matrix_deviation(np.eye(4), np.eye(3)) == 0.0
    with pytest.raises(InvalidInputError, match="no prim at '/World/nothing'"):
        get_relative_transform("/World/nothing", cube)
    with pytest.raises(InvalidInputError, match="get_prim_at_path found nothing"):
        get_relative_transform(get_prim_at_path("/World/nothing"), cube)
