"""The Lula robot description reader: the keys read, the keys ignored, and malformed files
raising errors that name the file and the key."""

from __future__ import annotations

import pytest

from manip.errors import InvalidInputError, UnknownNameError
from manip.sim import LulaKinematicsSolver, get_extension_path_from_name
from manip.sim.motion_generation.robot_description import load_robot_description

URDF = "/motion_policy_configs/franka/lula_franka_gen.urdf"
CSPACE = "cspace: [panda_joint1, panda_joint2, panda_joint3, panda_joint4, panda_joint5, panda_joint6, panda_joint7]\n"


def _write(tmp_path, text: str):
    p = tmp_path / "robot.yaml"
    p.write_text(text)
    return p


def test_lulas_other_keys_are_ignored(tmp_path):
    desc = load_robot_description(_write(tmp_path, "api_version: 1.0\n" + CSPACE + (
        "acceleration_limits: [1, 1, 1, 1, 1, 1, 1]\ncomposite_task_spaces: []\n"
        "collision_spheres:\n  - panda_link0:\n    - center: [0, 0, 0.05]\n      radius: 0.08\n")))
    assert len(desc.cspace) == 7 and desc.root_link is None and desc.default_q is None and desc.fixed_joints == {}


@pytest.mark.parametrize("text, match", [
    ("cspace: []\n", "cspace"),
    ("cspace: panda_joint1\n", "cspace"),
    ("cspace: [panda_joint1, panda_joint1]\n", "twice"),
    (CSPACE + "default_q: [0, 0, 0]\n", "default_q must be 7"),
    (CSPACE + "default_q: [0, 0, 0, .nan, 0, 0, 0]\n", "default_q"),
    (CSPACE + "root_link: 3\n", "root_link"),
    (CSPACE + "cspace_to_urdf_rules:\n  - {name: panda_finger_joint1, rule: zero}\n", "only 'fixed'"),
    (CSPACE + "cspace_to_urdf_rules:\n  - {name: panda_finger_joint1, rule: fixed}\n", "finite number"),
    (CSPACE + "cspace_to_urdf_rules:\n  - {name: panda_joint1, rule: fixed, value: 0}\n", "is a cspace joint"),
    ("- a\n- b\n", "mapping"),
    ("cspace: [a\n", "not valid YAML"),
])
def test_malformed_descriptions_raise_naming_the_key(tmp_path, text, match):
    with pytest.raises(InvalidInputError, match=match):
        load_robot_description(_write(tmp_path, text))


def test_names_the_urdf_does_not_have_raise_listing_the_valid_ones(tmp_path):
    urdf = get_extension_path_from_name("omni.isaac.motion_generation") + URDF
    with pytest.raises(UnknownNameError, match="panda_joint7"):
        LulaKinematicsSolver(str(_write(tmp_path, "cspace: [panda_joint1, joint2]\n")), urdf)
    with pytest.raises(UnknownNameError, match="panda_finger_joint1"):
        LulaKinematicsSolver(str(_write(tmp_path, CSPACE + "cspace_to_urdf_rules:\n"
                                        "  - {name: finger, rule: fixed, value: 0}\n")), urdf)
    with pytest.raises(UnknownNameError, match="root_link"):
        LulaKinematicsSolver(str(_write(tmp_path, CSPACE + "root_link: base\n")), urdf)
    with pytest.raises(InvalidInputError, match="root_link panda_link3 moves with cspace joints"):
        LulaKinematicsSolver(str(_write(tmp_path, CSPACE + "root_link: panda_link3\n")), urdf)
