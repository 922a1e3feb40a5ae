"""A new robot from a URDF and an SRDF alone ("new robot, no code"), and how the SRDF is read."""

from __future__ import annotations

import logging
from pathlib import Path

import mujoco
import numpy as np
import pytest

from manip.errors import InvalidInputError, RobotConfigError, UnknownNameError
from manip.motion_generator import MotionGenerator
from manip.pose import Pose
from manip.robot_config import config_from_urdf, load_robot_config
from manip.sim.scenes.mjcf_builder import build_mjcf
from manip.urdf import srdf_disabled_pairs

# A 3-link arm on a base: boxes and cylinders only, a continuous first joint, a tool frame.
URDF = """<?xml version="1.0"?>
<robot name="tri">
  <link name="base"><inertial><mass value="2"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="l1"><inertial><origin xyz="0 0 0.15"/><mass value="1.5"/><inertia ixx="0.01" iyy="0.01" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.04" length="0.3"/></geometry></collision></link>
  <link name="l2"><inertial><origin xyz="0.15 0 0"/><mass value="1.0"/><inertia ixx="0.002" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/><geometry><cylinder radius="0.035" length="0.3"/></geometry></collision></link>
  <link name="l3"><inertial><origin xyz="0.12 0 0"/><mass value="0.6"/><inertia ixx="0.001" iyy="0.005" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0.12 0 0"/><geometry><box size="0.24 0.05 0.05"/></geometry></collision></link>
  <link name="tool"/>
  <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit effort="50" velocity="2.0"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.3"/><axis xyz="0 -1 0"/>
    <limit lower="-1.6" upper="1.6" effort="50" velocity="2.0"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.3 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="-2.4" upper="2.4" effort="20" velocity="2.5"/></joint>
  <joint name="jt" type="fixed"><parent link="l3"/><child link="tool"/><origin xyz="0.24 0 0"/></joint>
</robot>
"""

SRDF = """<?xml version="1.0"?>
<robot name="tri">
  <group_state name="ready" group="arm">
    <joint name="j1" value="0"/><joint name="j2" value="0.5"/><joint name="j3" value="-1.0"/>
  </group_state>
  <disable_collisions link1="base" link2="l1" reason="Adjacent"/>
  <disable_collisions link1="l1" link2="l2" reason="Adjacent"/>
  <disable_collisions link1="l2" link2="l3" reason="Adjacent"/>
</robot>
"""


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> tuple[Path, Path]:
    d = tmp_path_factory.mktemp("tri")
    (d / "tri.urdf").write_text(URDF)
    (d / "tri.srdf").write_text(SRDF)
    return d / "tri.urdf", d / "tri.srdf"


def test_new_robot_plans_around_an_obstacle(files) -> None:
    urdf, srdf = files
    mg = MotionGenerator.from_urdf(urdf, srdf, ee_link="tool", seed=0)
    assert mg.joint_names == ["j1", "j2", "j3"]
    np.testing.assert_allclose(mg.default_joint_positions, [0.0, 0.5, -1.0])   # the SRDF's state
    np.testing.assert_allclose(mg.velocity_limits, [2.0, 2.0, 2.5])              # the URDF's
    np.testing.assert_allclose(mg.lower_limits, [-2 * np.pi, -1.6, -2.4])       # continuous: +-2 pi
    # a wall between a start on one side and a goal on the other
    world = {"cuboid": {"wall": {"dims": [0.05, 0.3, 0.6], "pose": [0.45, 0.0, 0.3, 1, 0, 0, 0]}}}
    mg.update_world(world)
    start, goal = np.array([0.8, 0.5, -1.0]), np.array([-0.8, 0.5, -1.0])
    assert not mg.check_collision(start) and not mg.check_collision(goal)
    r = mg.plan_joints(start, goal)
    assert r.success, r.status
    path = r.trajectory.positions
    np.testing.assert_allclose(path[0], start, atol=1e-6)
    np.testing.assert_allclose(path[-1], goal, atol=1e-6)
    assert not any(mg.check_collision(q) for q in path)
    # a pose goal for the tool, beside the wall
    q_target = np.array([1.2, 0.2, -0.6])
    assert not mg.check_collision(q_target)
    target = mg.fk(q_target)
    r = mg.plan_pose(start, target)
    assert r.success, r.status
    assert np.linalg.norm(mg.fk(r.trajectory.positions[-1]).position - target.position) < 1e-3


def test_defaults_are_logged_and_without_srdf_adjacent_links_are_skipped(files, caplog) -> None:
    urdf, _ = files
    with caplog.at_level(logging.INFO):
        c = config_from_urdf(urdf)
    text = caplog.text
    assert "no SRDF" in text and "acceleration_limits not given" in text and "ee_link not given" in text
    assert c.ee_link == "tool"   # the deepest link
    assert set(c.disabled_collision_pairs) == {("base", "l1"), ("l1", "l2"), ("l2", "l3")}
    np.testing.assert_allclose(c.acceleration_limits, 10.0)
    np.testing.assert_allclose(c.jerk_limits, 500.0)


def test_unknown_links_are_named(files) -> None:
    urdf, srdf = files
    with pytest.raises(UnknownNameError, match="l3"):
        config_from_urdf(urdf, srdf, ee_link="gripper")


def test_srdf_pairs_come_from_the_srdf_and_the_yaml_only_adds(tmp_path, files) -> None:
    urdf, srdf = files
    (tmp_path / "robot.yaml").write_text(f"""
name: tri
urdf: {urdf}
srdf: {srdf}
base_link: base
ee_link: tool
arm_joints: [j1, j2, j3]
default_joint_positions: [0.0, 0.5, -1.0]
lower_limits: [-3.0, -1.6, -2.4]
upper_limits: [3.0, 1.6, 2.4]
velocity_limits: [2.0, 2.0, 2.5]
acceleration_limits: [10.0, 10.0, 10.0]
jerk_limits: [500.0, 500.0, 500.0]
collision:
  disabled_pairs: [[base, l2]]
""")
    c = load_robot_config(tmp_path)
    assert set(srdf_disabled_pairs(srdf)) < set(c.disabled_collision_pairs)
    assert ("base", "l2") in c.disabled_collision_pairs
    assert len(c.disabled_collision_pairs) == 4


def test_mjcf_of_the_new_robot_matches_its_kinematics(files) -> None:
    urdf, srdf = files
    mg = MotionGenerator.from_urdf(urdf, srdf, ee_link="tool")
    text, assets = build_mjcf(mg.config)
    m = mujoco.MjModel.from_xml_string(text, assets)
    assert [m.actuator(i).name for i in range(m.nu)] == ["j1", "j2", "j3"]
    d = mujoco.MjData(m)
    for q in np.random.default_rng(0).uniform(mg.lower_limits, mg.upper_limits, size=(10, 3)):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        np.testing.assert_allclose(d.site("tool").xpos, mg.fk(q).position, atol=1e-9)


# Arms of example-robot-data that are not shipped in robots/, as a new user points at them.
def _erd(path: str) -> Path:
    from importlib import metadata

    root = metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share/example-robot-data/robots")
    return Path(str(root)) / path


def test_kinova_from_its_urdf_and_srdf_alone_plans(caplog) -> None:
    # kinova.srdf lists no disable_collisions pair (adjacent links touch at their joints), its
    # only state "arm_up" puts joint 3 at -pi/2, outside the URDF's [0.33, 5.95], and it names
    # the end effector: the robot plans from the two files with no other argument.
    with caplog.at_level(logging.WARNING):
        mg = MotionGenerator.from_urdf(_erd("kinova_description/robots/kinova.urdf"),
                                       _erd("kinova_description/srdf/kinova.srdf"), seed=0)
    assert mg.config.ee_link == "j2s6s200_end_effector"   # the SRDF's end_effector parent_link
    assert "lists no <disable_collisions> pair" in caplog.text and "turned by whole turns" in caplog.text
    # arm_up with joint 3 turned by 2 pi: the shipped robot's retract configuration
    np.testing.assert_allclose(mg.default_joint_positions, [1.5707, 2.618, -1.5707 + 2 * np.pi, 3.1415, 2.618, 0.0])
    np.testing.assert_allclose(mg.default_joint_positions, load_robot_config("kinova").default_joint_positions,
                               atol=1e-4)
    q0 = mg.default_joint_positions
    assert not mg.check_collision(q0)
    hand = mg.fk(q0)
    target = Pose(hand.position + np.array([0.0, 0.1, -0.1]), hand.quaternion)
    r = mg.plan_pose(q0, target)
    assert r.success, r.status
    assert np.linalg.norm(mg.fk(r.trajectory.positions[-1]).position - target.position) < 1e-3
    assert not any(mg.check_collision(q) for q in r.trajectory.positions)


def test_z1_plans_from_a_named_srdf_state() -> None:
    urdf, srdf = _erd("z1_description/urdf/z1.urdf"), _erd("z1_description/srdf/z1.srdf")
    with pytest.raises(UnknownNameError, match="arm_up, home"):
        config_from_urdf(urdf, srdf, ee_link="link06", default_joint_positions="ready")
    mg = MotionGenerator.from_urdf(urdf, srdf, ee_link="link06", default_joint_positions="arm_up", seed=0)
    np.testing.assert_allclose(mg.default_joint_positions, [0.0, 0.26178, -0.26178, 0.0, 0.0, 0.0])
    assert ("link02", "link03") in mg.config.disabled_collision_pairs   # adjacent: z1.srdf lists no pair
    q0 = mg.default_joint_positions
    assert not mg.check_collision(q0)
    hand = mg.fk(q0)
    r = mg.plan_pose(q0, Pose(hand.position + np.array([0.0, 0.05, -0.05]), hand.quaternion))
    assert r.success, r.status


@pytest.mark.parametrize("kwargs, error, words", [
    ({"default_joint_positions": [np.nan, 0.5, -1.0]}, RobotConfigError, ["default_joint_positions", "finite"]),
    ({"default_joint_positions": "ready?"}, UnknownNameError, ["group_state", "ready"]),
    ({"arm_joints": ["j1", "jt"]}, RobotConfigError, ["['jt']", "not movable", "fixed"]),
    ({"arm_joints": ["j1", "j2", "j2"]}, RobotConfigError, ["distinct"]),
])
def test_bad_arguments_are_named(files, kwargs, error, words) -> None:
    urdf, srdf = files
    with pytest.raises(error) as info:
        config_from_urdf(urdf, srdf, ee_link="tool", **kwargs)
    for w in words:
        assert w in str(info.value)


def test_from_urdf_names_an_unknown_argument(files) -> None:
    urdf, srdf = files
    with pytest.raises(InvalidInputError) as info:
        MotionGenerator.from_urdf(urdf, srdf, ee_linc="tool")
    assert "ee_linc" in str(info.value) and "ee_link" in str(info.value) and "time_budget" in str(info.value)


def test_a_urdf_and_an_srdf_given_the_wrong_way_round_are_named(files) -> None:
    urdf, srdf = files
    with pytest.raises(RobotConfigError, match="not a URDF"):
        config_from_urdf(srdf)
    with pytest.raises(RobotConfigError, match="a URDF, not an SRDF"):
        config_from_urdf(urdf, urdf)


def test_srdf_state_outside_the_limits_is_turned_or_skipped(tmp_path, files) -> None:
    urdf, _ = files
    srdf = tmp_path / "states.srdf"
    # "far": j2 = 2.0 is outside [-1.6, 1.6] and j2 + k 2 pi never fits: skipped;
    # "turned": j3 = 4.0 is outside [-2.4, 2.4], 4.0 - 2 pi = -2.283 fits. No pair listed.
    srdf.write_text("""<robot name="tri">
  <group_state name="far" group="arm"><joint name="j1" value="0"/><joint name="j2" value="2.0"/><joint name="j3" value="0"/></group_state>
  <group_state name="turned" group="arm"><joint name="j1" value="0.1"/><joint name="j2" value="0.2"/><joint name="j3" value="4.0"/></group_state>
</robot>""")
    c = config_from_urdf(urdf, srdf, ee_link="tool")
    np.testing.assert_allclose(c.default_joint_positions, [0.1, 0.2, 4.0 - 2 * np.pi])
    assert set(c.disabled_collision_pairs) == {("base", "l1"), ("l1", "l2"), ("l2", "l3")}
    with pytest.raises(RobotConfigError, match="'far' is outside the joint limits"):
        config_from_urdf(urdf, srdf, ee_link="tool", default_joint_positions="far")


TRI_YAML = {
    "name": "tri", "base_link": "base", "ee_link": "tool", "arm_joints": ["j1", "j2", "j3"],
    "default_joint_positions": [0.0, 0.5, -1.0], "lower_limits": [-3.0, -1.6, -2.4], "upper_limits": [3.0, 1.6, 2.4],
    "velocity_limits": [2.0, 2.0, 2.5], "acceleration_limits": [10.0, 10.0, 10.0], "jerk_limits": [500.0, 500.0, 500.0],
}


@pytest.mark.parametrize("change, error, words", [
    ({"ee_link": "tool1"}, UnknownNameError, ["link (ee_link) 'tool1'", "tool"]),
    ({"tcp_link": "tcp"}, UnknownNameError, ["link (tcp_link) 'tcp'"]),
    ({"base_link": "l2", "ee_link": "l1"}, RobotConfigError, ["'l1' is not below 'l2'"]),
    ({"base_link": None}, RobotConfigError, ["'base_link' must name a link"]),
    ({"arm_joints": "j1"}, RobotConfigError, ["'arm_joints' must be a list of joint names"]),
    ({"arm_joints": ["j1", "j1", "j3"]}, RobotConfigError, ["'arm_joints' must be distinct"]),
    ({"default_joint_positions": [float("nan"), 0.5, -1.0]}, RobotConfigError, ["'default_joint_positions'", "finite"]),
    ({"velocity_limits": [0.0, 2.0, 2.5]}, RobotConfigError, ["'velocity_limits'", "positive"]),
    ({"jerk_limits": ["fast", 500, 500]}, RobotConfigError, ["'jerk_limits' must be 3 numbers"]),
    ({"collision": {"padding": "thin"}}, RobotConfigError, ["'padding' must be a number"]),
    ({"gripper": {"joints": ["finger"], "open_positions": [0.04], "closed_positions": [0.0]}}, UnknownNameError,
     ["joint (gripper: joints) 'finger'"]),
])
def test_mistakes_in_a_robot_yaml_are_named_when_it_loads(tmp_path, files, change, error, words) -> None:
    import yaml

    urdf, srdf = files
    d = {**TRI_YAML, "urdf": str(urdf), "srdf": str(srdf), **change}
    (tmp_path / "robot.yaml").write_text(yaml.safe_dump({k: v for k, v in d.items() if v is not None}))
    with pytest.raises(error) as info:
        load_robot_config(tmp_path)
    for w in words:
        assert w in str(info.value)


def test_unknown_robot_yaml_keys_raise_and_bad_yaml_is_named(tmp_path, files) -> None:
    import yaml

    urdf, srdf = files
    (tmp_path / "robot.yaml").write_text(yaml.safe_dump({**TRI_YAML, "urdf": str(urdf), "sdrf": str(srdf)}))
    with pytest.raises(RobotConfigError, match=r"unknown key\(s\) \['sdrf'\] \('sdrf': did you mean 'srdf'\?\)"):
        load_robot_config(tmp_path)   # more cases: tests/test_config_mistakes.py
    (tmp_path / "robot.yaml").write_text("urdf: [unclosed\n")
    with pytest.raises(RobotConfigError, match="not a readable YAML file"):
        load_robot_config(tmp_path)


def test_make_mjcf_builds_a_users_robot_folder_and_names_what_is_missing(tmp_path, files) -> None:
    import subprocess
    import sys

    import yaml

    from manip.robot_config import robots_root

    tool = robots_root() / "tools" / "make_mjcf.py"
    urdf, srdf = files
    folder = tmp_path / "tri"
    folder.mkdir()
    d = {**TRI_YAML, "urdf": str(urdf), "srdf": str(srdf)}
    (folder / "robot.yaml").write_text(yaml.safe_dump(d))
    out = subprocess.run([sys.executable, str(tool), str(folder)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 2 and "has no 'mjcf:' entry" in out.stderr
    out = subprocess.run([sys.executable, str(tool), "no_such_robot"], capture_output=True, text=True, timeout=300)
    assert out.returncode == 2 and "robot 'no_such_robot' not found" in out.stderr
    (folder / "robot.yaml").write_text(yaml.safe_dump({**d, "mjcf": "tri.xml"}))
    out = subprocess.run([sys.executable, str(tool), str(folder)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    m = mujoco.MjModel.from_xml_path(str(folder / "tri.xml"))
    assert [m.actuator(i).name for i in range(m.nu)] == ["j1", "j2", "j3"]
    mg = MotionGenerator(str(folder))
    data = mujoco.MjData(m)
    data.qpos[:] = [0.3, 0.5, -1.0]
    mujoco.mj_kinematics(m, data)
    np.testing.assert_allclose(data.site("tool").xpos, mg.fk(np.array([0.3, 0.5, -1.0])).position, atol=1e-9)


def test_a_urdf_copied_out_of_its_package_names_its_missing_meshes(tmp_path) -> None:
    # package:// mesh URIs resolve as ROS tools do (manip.package_uri; tests/test_package_uris.py):
    # a copy elsewhere still finds the installed example-robot-data, but not a package found nowhere
    copy = tmp_path / "z1.urdf"
    copy.write_text(_erd("z1_description/urdf/z1.urdf").read_text())
    MotionGenerator.from_urdf(copy, ee_link="link06")
    copy.write_text(_erd("z1_description/urdf/z1.urdf").read_text().replace("package://example-robot-data/",
                                                                             "package://my_z1/"))
    with pytest.raises(RobotConfigError, match=r"collision mesh package://my_z1/.*: package 'my_z1' not found"):
        MotionGenerator.from_urdf(copy, ee_link="link06")
