"""The Franka's ready-made `KinematicsSolver` (Isaac's franka extension; its "follow target with
IK" example imports it, and `from manip.sim import KinematicsSolver` raised ImportError)."""

from __future__ import annotations

import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import UnknownNameError
from manip.sim import FollowTarget, KinematicsSolver, World


def test_isaacs_follow_target_with_ik_example_reaches_the_target():
    world = World(stage_units_in_meters=1.0)
    world.add_task(FollowTarget(name="follow_target_task", target_position=np.array([0.5, 0.2, 0.4])))
    world.reset()
    params = world.get_task("follow_target_task").get_params()
    franka = world.scene.get_object(params["robot_name"]["value"])
    target_name = params["target_name"]["value"]
    controller = KinematicsSolver(franka)
    assert controller.get_end_effector_frame() == "right_gripper"
    articulation_controller = franka.get_articulation_controller()
    for _ in range(120):
        world.step(render=True)
        obs = world.get_observations()
        actions, success = controller.compute_inverse_kinematics(
            target_position=obs[target_name]["position"], target_orientation=obs[target_name]["orientation"])
        assert success
        articulation_controller.apply_action(actions)
    position, rotation = controller.compute_end_effector_pose()
    assert np.linalg.norm(position - [0.5, 0.2, 0.4]) < 6e-3  # the drives' gravity sag, as Isaac's
    assert quat.angle_between(quat.from_matrix(rotation), obs[target_name]["orientation"]) < 0.02
    with pytest.raises(UnknownNameError, match="right_gripper"):
        KinematicsSolver(franka, end_effector_frame_name="no_such_frame")
