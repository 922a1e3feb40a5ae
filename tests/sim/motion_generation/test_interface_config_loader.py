"""`interface_config_loader` and `get_extension_path_from_name`: manip's Franka files, a
configuration folder of one's own, and clear errors for what is not there."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from manip.errors import UnknownNameError
from manip.sim import LulaKinematicsSolver, get_extension_path_from_name, interface_config_loader
from manip.sim.motion_generation import robot_description


def test_import_forms_of_the_module():
    from manip.sim import interface_config_loader as a
    from manip.sim.motion_generation import interface_config_loader as b

    assert a is b
    assert callable(a.load_supported_lula_kinematics_solver_config)


def test_the_franka_is_supported_and_its_files_are_manips():
    assert interface_config_loader.get_supported_robots_with_lula_kinematics() == ["Franka"]
    assert interface_config_loader.get_supported_robot_policy_pairs() == {"Franka": ["RMPflow"]}
    config = interface_config_loader.load_supported_lula_kinematics_solver_config("Franka")
    assert set(config) == {"robot_description_path", "urdf_path"}
    mg = Path(get_extension_path_from_name("isaacsim.robot_motion.motion_generation"))
    assert Path(config["robot_description_path"]).resolve() == \
        mg / "motion_policy_configs/franka/rmpflow/robot_descriptor.yaml"
    assert Path(config["urdf_path"]).name == "lula_franka_gen.urdf"
    desc = robot_description.load_robot_description(config["robot_description_path"])
    assert desc.cspace == tuple(f"panda_joint{i}" for i in range(1, 8))
    assert desc.root_link == "panda_link0"
    assert desc.fixed_joints == {"panda_finger_joint1": 0.04, "panda_finger_joint2": 0.04}


def test_unknown_robot_raises_listing_the_supported_ones():
    with pytest.raises(UnknownNameError, match="Franka"):
        interface_config_loader.load_supported_lula_kinematics_solver_config("UR10")


def test_a_policy_folder_of_ones_own(tmp_path):
    from manip.robot_config import load_robot_config

    (tmp_path / "ur5").mkdir()
    (tmp_path / "ur5" / "ur5.yaml").write_text("cspace: [shoulder_pan_joint, shoulder_lift_joint, elbow_joint, "
                                                "wrist_1_joint, wrist_2_joint, wrist_3_joint]\n")
    (tmp_path / "ur5" / "config.json").write_text(json.dumps({"relative_asset_paths": {
        "robot_description_path": "ur5.yaml", "urdf_path": str(load_robot_config("ur5").urdf_path)}}))
    (tmp_path / "policy_map.json").write_text(json.dumps({"UR5": {"RMPflow": "./ur5/config.json"},
                                                          "Jetbot": {"Other": "x.json"}}))
    assert interface_config_loader.get_supported_robots_with_lula_kinematics(tmp_path) == ["UR5"]
    config = interface_config_loader.load_supported_lula_kinematics_solver_config("UR5", str(tmp_path))
    assert LulaKinematicsSolver(**config).get_joint_names()[0] == "shoulder_pan_joint"
    with pytest.raises(UnknownNameError, match="UR5"):
        interface_config_loader.load_supported_lula_kinematics_solver_config("Jetbot", tmp_path)
    with pytest.raises(FileNotFoundError, match="policy_map.json"):
        interface_config_loader.load_supported_lula_kinematics_solver_config("UR5", tmp_path / "ur5")
