"""A grasped 5 cm cube is held by friction alone at the World's default time step (1/60 s,
9 substeps): pick from the PickPlace task scene, lift 25 cm, hold 2 s."""

from __future__ import annotations

import numpy as np
import pytest

from manip import Kinematics, Pose, load_robot_config
from manip.ik import IKSolver
from manip.sim import ArticulationAction, PickPlace, World

DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # hand z axis pointing down
HOME = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])


def test_grasped_cube_is_held_while_lifting_and_holding():
    ik = IKSolver(Kinematics(load_robot_config("franka")))

    def solve(p, seed):
        r = ik.solve(Pose(np.asarray(p, dtype=float), DOWN), link="panda_hand_tcp", seed_q=seed)
        assert r.success
        return r.q

    cube_p = np.array([0.5, 0.0, 0.025])
    q_pre = solve(cube_p + [0, 0, 0.12], HOME)
    q_grasp = solve(cube_p, q_pre)
    q_lift = solve(cube_p + [0, 0, 0.25], q_grasp)

    world = World()
    task = PickPlace(cube_initial_position=cube_p, cube_mass=0.05)
    world.add_task(task)
    world.reset()
    franka, cube = task.robot, task.cube

    def ramp(q0, q1, seconds):
        n = int(seconds * 60)
        for i in range(n):
            s = 0.5 - 0.5 * np.cos(np.pi * (i + 1) / n)
            franka.apply_action(ArticulationAction(joint_positions=[*(q0 + s * (q1 - q0)), None, None]))
            world.step(render=False)

    franka.set_joint_positions(q_pre, joint_indices=np.arange(7))
    for _ in range(30):
        world.step(render=False)
    ramp(q_pre, q_grasp, 1.0)
    franka.gripper.close()
    for _ in range(40):
        world.step(render=False)
    fingers = franka.gripper.get_joint_positions()
    assert np.allclose(fingers, 0.025, atol=0.002)  # stopped by the 5 cm cube
    rel_closed = cube.get_world_pose()[0] - franka.end_effector.get_world_pose()[0]
    ramp(q_grasp, q_lift, 1.5)
    for _ in range(120):
        world.step(render=False)
    rel_held = cube.get_world_pose()[0] - franka.end_effector.get_world_pose()[0]
    assert cube.get_world_pose()[0][2] > 0.25
    assert np.linalg.norm(rel_held - rel_closed) < 0.005
    assert np.linalg.norm(cube.get_linear_velocity()) < 0.01
    assert cube.get_world_pose()[0][2] == pytest.approx(franka.end_effector.get_world_pose()[0][2], abs=0.01)
