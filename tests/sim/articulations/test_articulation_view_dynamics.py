"""ArticulationView dynamics (issue 32, item 4): Jacobians, mass matrix, gravity forces,
efforts, root pose and velocity, checked against finite differences and the simulation."""

from __future__ import annotations

import numpy as np
import pytest

from manip.sim import ArticulationView, Franka, World


@pytest.fixture
def franka():
    world = World()
    world.scene.add_default_ground_plane()
    robot = world.scene.add(Franka("/World/Franka", name="franka", position=[0.2, -0.1, 0.0]))
    view = world.scene.add(ArticulationView(prim_paths_expr="/World/Franka", name="franka_view"))
    world.reset()
    return world, robot, view


def test_jacobians_match_finite_differences_of_the_hand_pose(franka):
    world, robot, view = franka
    q = np.array([0.3, -0.5, 0.2, -2.0, 0.1, 1.6, 0.7, 0.03, 0.03])
    robot.set_joint_positions(q)
    J = view.get_jacobians()
    assert J.shape == (1, robot.num_bodies - 1, 6, 9) == (1, *view.get_jacobian_shape())
    hand = robot.body_names.index("panda_hand") - 1  # the root link has no Jacobian row (fixed base)
    sim = world.physics_sim_view
    bid = sim.model.body("/World/Franka/panda_hand").id

    def hand_pos(qq):
        robot.set_joint_positions(qq)
        sim.ensure_kinematics()
        return sim.data.xpos[bid].copy()

    eps = 1e-6
    fd = np.stack([(hand_pos(q + eps * e) - hand_pos(q - eps * e)) / (2 * eps) for e in np.eye(9)], axis=1)
    np.testing.assert_allclose(J[0, hand, :3], fd, atol=1e-6)


def test_mass_matrix_is_symmetric_positive_and_gravity_forces_hold_the_arm(franka):
    world, robot, view = franka
    M = view.get_mass_matrices()
    assert M.shape == (1, 9, 9) == (1, *view.get_mass_matrix_shape())
    np.testing.assert_allclose(M[0], M[0].T, atol=1e-12)
    assert np.all(np.linalg.eigvalsh(M[0]) > 0)
    g = view.get_generalized_gravity_forces()
    assert g.shape == (1, 9) and abs(g[0, 1]) > 1.0  # the shoulder carries the arm
    # effort mode, efforts = gravity forces: the arm neither falls nor rises
    view.switch_control_mode("effort")
    q0 = robot.get_joint_positions()
    view.set_joint_efforts(view.get_generalized_gravity_forces())
    for _ in range(3):
        world.step(render=False)
        view.set_joint_efforts(view.get_generalized_gravity_forces())
    assert np.max(np.abs(robot.get_joint_positions()[:7] - q0[:7])) < 2e-3
    np.testing.assert_allclose(view.get_applied_joint_efforts()[0, :7], g[0, :7], rtol=0.05, atol=0.05)


def test_root_pose_velocity_and_joints_state(franka):
    world, robot, view = franka
    p, q = view.get_world_poses()
    np.testing.assert_allclose(p, [[0.2, -0.1, 0.0]], atol=1e-12)
    np.testing.assert_allclose(q, [[1, 0, 0, 0]], atol=1e-12)
    np.testing.assert_array_equal(view.get_velocities(), np.zeros((1, 6)))  # a fixed base
    state = view.get_joints_state()
    np.testing.assert_array_equal(state.positions, robot.get_joint_positions()[None])
    assert state.velocities.shape == (1, 9) and state.efforts.shape == (1, 9)
    assert view.get_measured_joint_efforts().shape == (1, 9)


def test_velocity_mode_tracks_a_velocity_target(franka):
    world, robot, view = franka
    view.switch_control_mode("velocity", joint_indices=[0])
    view.set_joint_velocity_targets([0.5], joint_indices=[0])
    for _ in range(60):
        world.step(render=False)
    assert robot.get_joint_velocities()[0] == pytest.approx(0.5, abs=0.05)


def test_disable_gravity_keeps_a_limp_arm_up(franka):
    world, robot, view = franka
    view.switch_control_mode("effort")  # no drive holds the arm
    q0 = robot.get_joint_positions()
    robot.disable_gravity()
    for _ in range(60):
        world.step(render=False)
    assert np.max(np.abs(robot.get_joint_positions()[:7] - q0[:7])) < 1e-3
    robot.enable_gravity()
    for _ in range(30):
        world.step(render=False)
    assert np.max(np.abs(robot.get_joint_positions()[:7] - q0[:7])) > 0.05  # it falls
