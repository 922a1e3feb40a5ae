"""Configuration mistakes a new user makes: a typo in robot.yaml or in an SRDF raises, naming
the key, link, state or joint and what is valid; it never silently drops a safety margin."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest
import yaml

from manip.errors import RobotConfigError, UnknownNameError
from manip.robot_config import available_robots, config_from_urdf, load_robot_config, robots_root

FRANKA_YAML = robots_root() / "franka" / "robot.yaml"


def _erd(rel: str) -> Path:
    root = metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share/example-robot-data/robots")
    return Path(str(root)) / rel


PANDA_URDF = _erd("panda_description/urdf/panda.urdf")
PANDA_SRDF = _erd("panda_description/srdf/panda.srdf")


def _franka_yaml(tmp_path: Path, edit) -> Path:
    """A copy of the shipped Franka's robot.yaml in tmp_path, changed by `edit(d)`."""
    d = yaml.safe_load(FRANKA_YAML.read_text())
    edit(d)
    path = tmp_path / "robot.yaml"
    path.write_text(yaml.safe_dump(d, sort_keys=False))
    return path


def _set(path: tuple[str, ...], key: str, value=0.01):
    def edit(d):
        for p in path:
            d = d[p]
        d[key] = value
    return edit


@pytest.mark.parametrize("section, key, valid", [
    ((), "tcp_lnik", "tcp_link"),
    ((), "colision", "collision"),
    ((), "griper", "gripper"),
    ((), "simm", "sim"),
    (("collision",), "paddign", "padding"),
    (("gripper",), "open_position", "open_positions"),
    (("sim",), "kpp", "kp"),
    (("sim", "finger_contact"), "fricton", "friction"),
    (("srdf",), "pakage", "package"),
])
def test_an_unknown_key_raises_naming_it_the_file_and_the_valid_keys(tmp_path, section, key, valid) -> None:
    path = _franka_yaml(tmp_path, _set(section, key))
    with pytest.raises(RobotConfigError) as info:
        load_robot_config(path)
    msg = str(info.value)
    assert f"unknown key(s) ['{key}']" in msg and f"did you mean '{valid}'" in msg
    assert str(path) in msg
    assert re.search(rf"valid: .*\b{valid}\b", msg), msg


def test_a_misspelt_padding_never_becomes_zero(tmp_path) -> None:
    def padded(key):
        def edit(d):
            d["collision"] = {key: 0.02}
        return edit
    assert load_robot_config(_franka_yaml(tmp_path, padded("padding"))).collision_padding == 0.02
    with pytest.raises(RobotConfigError, match=r"collision: unknown key\(s\) \['paddign'\]"):
        load_robot_config(_franka_yaml(tmp_path, padded("paddign")))


def test_extension_keys_are_kept_and_ignored(tmp_path) -> None:
    def edit(d):
        d["x_vendor"] = {"cell": "A3"}
        d["collision"]["x_note"] = "measured 2026"
        d["sim"]["x_tuned_by"] = "me"
    c = load_robot_config(_franka_yaml(tmp_path, edit))
    assert c.raw["x_vendor"] == {"cell": "A3"} and c.collision_padding == 0.0
    ref = load_robot_config("franka")
    np.testing.assert_array_equal(c.default_joint_positions, ref.default_joint_positions)
    assert c.disabled_collision_pairs == ref.disabled_collision_pairs


def test_a_section_that_is_not_a_mapping_is_named(tmp_path) -> None:
    with pytest.raises(RobotConfigError, match="'sim' must be a mapping of kp, kv"):
        load_robot_config(_franka_yaml(tmp_path, _set((), "sim", [1, 2])))


def test_every_shipped_robot_loads() -> None:
    assert {"franka", "kinova", "ur10", "ur5", "xarm7"} <= set(available_robots())
    for name in available_robots():
        assert load_robot_config(name).dof >= 6


def _srdf_with(tmp_path: Path, old: str, new: str) -> Path:
    text = PANDA_SRDF.read_text()
    assert old in text
    path = tmp_path / "panda.srdf"
    path.write_text(text.replace(old, new, 1))
    return path


def test_an_srdf_pair_naming_an_unknown_link_raises_listing_the_links(tmp_path) -> None:
    bad = _srdf_with(tmp_path, 'link2="panda_link4" reason="Never"', 'link2="panda_lnik4" reason="Never"')
    with pytest.raises(UnknownNameError) as info:
        config_from_urdf(PANDA_URDF, bad)
    msg = str(info.value)
    assert "'panda_lnik4' not found" in msg and "disable_collisions" in msg and str(bad) in msg
    assert "panda_link4" in msg and "panda_hand" in msg   # the valid links are listed
    # the same SRDF named by a robot.yaml
    with pytest.raises(UnknownNameError, match="panda_lnik4"):
        load_robot_config(_franka_yaml(tmp_path, _set((), "srdf", str(bad))))


def test_a_misspelt_joint_in_the_default_group_state_raises_naming_it(tmp_path) -> None:
    assert np.allclose(config_from_urdf(PANDA_URDF, PANDA_SRDF).default_joint_positions,
                       [0, -0.785398, 0, -2.35619, 0, 1.5707, 0.785398])   # the state "default"
    bad = _srdf_with(tmp_path, '<joint name="panda_joint4" value="-2.35619"/>',
                     '<joint name="panda_jiont4" value="-2.35619"/>')
    with pytest.raises(RobotConfigError) as info:
        config_from_urdf(PANDA_URDF, bad)
    msg = str(info.value)
    assert "group_state 'default'" in msg and "['panda_joint4']" in msg and "['panda_jiont4']" in msg
    assert "panda_joint1, panda_joint2" in msg   # the arm joints
    # an explicit default configuration does not read the states
    q = [0.0, -0.5, 0.0, -2.0, 0.0, 1.5, 0.7]
    np.testing.assert_allclose(config_from_urdf(PANDA_URDF, bad, default_joint_positions=q).default_joint_positions, q)


def test_a_misspelt_value_in_the_default_group_state_raises_naming_the_joint(tmp_path) -> None:
    bad = _srdf_with(tmp_path, '<joint name="panda_joint4" value="-2.35619"/>',
                     '<joint name="panda_joint4" value="-23.5619"/>')
    with pytest.raises(RobotConfigError, match=r"group_state 'default': panda_joint4 = -23.5619 outside \[-3.0718"):
        config_from_urdf(PANDA_URDF, bad)


def test_example_robot_data_srdfs_load_with_their_urdfs() -> None:
    root = _erd("")
    loaded = []
    for srdf in sorted(root.rglob("*.srdf")):
        urdfs = sorted(srdf.parent.parent.rglob("*.urdf"))
        if not urdfs:
            continue
        links = {a for el in ET.parse(srdf).getroot().iter("disable_collisions") for a in (el.get("link1"), el.get("link2"))}
        ok = []
        for urdf in urdfs:
            if links - {el.get("name") for el in ET.parse(urdf).getroot().iter("link")}:
                continue  # the SRDF of another URDF of the package
            try:
                config_from_urdf(urdf, srdf)
            except RobotConfigError as exc:
                # only the SRDF of another variant (alex's hands): its state names the other hands' joints
                assert "names joint(s)" in str(exc), (srdf, urdf, exc)
                continue
            ok.append(urdf.name)
        assert ok, f"{srdf} loads with none of {[u.name for u in urdfs]}"
        loaded.append(srdf.name)
    assert {"panda.srdf", "ur5.srdf", "xarm7.srdf", "kinova.srdf", "talos.srdf", "go1.srdf"} <= set(loaded)
