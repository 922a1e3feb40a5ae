"""The cuRobo wrapper's other attributes (issue 32, item 10): what is meaningful is provided,
anything cuRobo-specific raises an error naming it."""

from __future__ import annotations

import numpy as np
import pytest

from manip import TutorialMotionGen as CuroboMotionGenerator
from manip.compat.tutorial_attributes import TutorialAttributeError


@pytest.fixture(scope="module")
def wrapper():
    return CuroboMotionGenerator(robot_config_file_name="my_franka_robot_config.yml",
                                 world_config_file_name="collision_base.yml",
                                 user_config_file_name="isaac_sim_user_config.toml")


def test_user_and_robot_config(wrapper):
    assert wrapper.user_config["interpolation_dt"] == 0.004
    kin = wrapper.robot_config["kinematics"]
    assert kin["base_link"] == "panda_link0" and kin["ee_link"] == "ee_link"
    assert kin["cspace"]["joint_names"] == wrapper.joint_names and len(kin["cspace"]["retract_config"]) == 9
    assert kin["lock_joints"] == {"panda_finger_joint1": 0.04, "panda_finger_joint2": 0.04}


def test_kinematics_model_matches_fk(wrapper):
    q = wrapper.default_joint_positions
    state = wrapper.kinematics_model.get_state(q)
    xyzw = wrapper.fk(q)
    np.testing.assert_allclose(state.ee_position, xyzw[:3], atol=1e-12)
    np.testing.assert_allclose(np.abs(state.ee_quaternion @ wrapper.xyzw_to_wxyz(xyzw[3:])), 1.0, atol=1e-12)
    assert wrapper.kinematics_model.get_joint_limits().shape == (7, 2)


def test_plan_config_and_tensor_args(wrapper):
    cfg = wrapper.motion_gen_plan_config
    assert cfg.timeout == 10.0 and cfg.enable_graph is False
    with pytest.raises(TutorialAttributeError, match="read-only"):
        cfg.max_attempts = 10
    assert wrapper.tensor_args.device == "cpu"
    np.testing.assert_array_equal(wrapper.tensor_args.to_device([1, 2]), [1.0, 2.0])


def test_cuda_only_things_raise_naming_the_attribute(wrapper):
    with pytest.raises(TutorialAttributeError, match="kinematics_model.get_link_poses"):
        wrapper.kinematics_model.get_link_poses
    with pytest.raises(AttributeError, match="'world_coll_checker'"):
        wrapper.world_coll_checker
