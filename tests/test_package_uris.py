"""package:// mesh URIs resolved as ROS tools do, the same in manip.sim and MotionGenerator.from_urdf."""

from __future__ import annotations

import shutil
from importlib import metadata
from pathlib import Path

import mujoco
import numpy as np
import pytest

from manip import MotionGenerator, WorldConfig
from manip.errors import RobotConfigError
from manip.sim import SimulationError, World, add_reference_to_stage, create_new_stage

ERD = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share/example-robot-data")))
PANDA = ERD / "robots/panda_description/urdf/panda.urdf"
MESHES = "package://example-robot-data/robots/panda_description/meshes"
ARM = [f"panda_joint{i}" for i in range(1, 8)]
Q = np.array([0.3, -0.5, 0.2, -2.0, 0.1, 1.6, 0.5])


@pytest.fixture
def world(fresh_world):
    return fresh_world()


def sim_hand(urdf: Path) -> np.ndarray:
    """manip.sim: the URDF referenced on the stage, reset, a few steps; the hand's position at Q [m]."""
    world = World()
    add_reference_to_stage(str(urdf), "/World/R")
    world.reset()
    for _ in range(3):
        world.step(render=False)
    m, d = world.model, world.data
    assert sum(m.geom_type == mujoco.mjtGeom.mjGEOM_MESH) >= 9  # the collision meshes were loaded
    for name, q in zip(ARM, Q):
        d.qpos[m.joint(f"/World/R/{name}").qposadr[0]] = q
    mujoco.mj_kinematics(m, d)
    return d.body("/World/R/panda_hand").xpos.copy()


def planner_hand(urdf: Path) -> np.ndarray:
    """MotionGenerator.from_urdf: the hand's position at Q [m]; its collision meshes are there."""
    mg = MotionGenerator.from_urdf(urdf, ee_link="panda_hand", arm_joints=ARM)
    hand = mg.fk(Q).position
    box = WorldConfig.from_dict({"cuboid": {"b": {"dims": [0.05, 0.05, 0.05], "pose": [*hand, 1, 0, 0, 0]}}})
    mg.update_world(box)
    assert mg.check_collision(Q)  # the hand's mesh meets the box
    return hand


def package(folder: Path, name: str, manifest: bool = True) -> Path:
    """A ROS package `name` in `folder`: package.xml, the Panda's collision meshes and a URDF
    whose meshes are package://<name>/meshes/collision/*.stl (visual meshes left unresolvable)."""
    (folder / "meshes").mkdir(parents=True)
    shutil.copytree(ERD / "robots/panda_description/meshes/collision", folder / "meshes/collision")
    if manifest:
        (folder / "package.xml").write_text(f'<?xml version="1.0"?>\n<package format="3"><name>{name}</name>'
                                            "<version>0.0.1</version></package>\n")
    (folder / "urdf").mkdir()
    urdf = folder / "urdf/robot.urdf"
    urdf.write_text(PANDA.read_text().replace(MESHES, f"package://{name}/meshes"))
    return urdf


def test_example_robot_datas_own_panda_loads_in_the_simulator_and_the_planner(world):
    assert MESHES in PANDA.read_text()
    np.testing.assert_allclose(sim_hand(PANDA), planner_hand(PANDA), atol=1e-6)


def test_a_copy_outside_the_package_finds_it_in_the_python_environment(world, tmp_path):
    # example-robot-data installed by pip: its share/ folder is under cmeel.prefix, an ament prefix
    copy = tmp_path / "panda.urdf"
    copy.write_text(PANDA.read_text())
    np.testing.assert_allclose(sim_hand(copy), planner_hand(copy), atol=1e-6)


def test_ros_package_path(world, tmp_path, monkeypatch):
    package(tmp_path / "ws/src/arms/my_panda_description", "my_panda_description")
    urdf = tmp_path / "elsewhere/robot.urdf"
    urdf.parent.mkdir()
    shutil.copy(tmp_path / "ws/src/arms/my_panda_description/urdf/robot.urdf", urdf)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws/src"))
    np.testing.assert_allclose(sim_hand(urdf), planner_hand(urdf), atol=1e-6)


def test_ament_prefix_path(world, tmp_path, monkeypatch):
    package(tmp_path / "install/share/my_panda_description", "my_panda_description")
    urdf = tmp_path / "robot.urdf"
    shutil.copy(tmp_path / "install/share/my_panda_description/urdf/robot.urdf", urdf)
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "install"))
    np.testing.assert_allclose(sim_hand(urdf), planner_hand(urdf), atol=1e-6)


def test_the_urdfs_own_package_is_found_by_walking_up(world, tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    # by its folder's name, without package.xml; and a package beside it in the same workspace
    own = package(tmp_path / "src/my_panda_description", "my_panda_description", manifest=False)
    np.testing.assert_allclose(sim_hand(own), planner_hand(own), atol=1e-6)
    World.clear_instance()
    create_new_stage()
    (tmp_path / "src/robot_bringup/urdf").mkdir(parents=True)
    beside = tmp_path / "src/robot_bringup/urdf/robot.urdf"
    shutil.copy(own, beside)
    np.testing.assert_allclose(sim_hand(beside), planner_hand(beside), atol=1e-6)


def test_a_package_xml_naming_another_folder(world, tmp_path, monkeypatch):
    # ROS finds a package by its package.xml; the simulator does too. Pinocchio, which builds the
    # planner's collision model, looks for a folder of the package's name: a clear error says so
    urdf = package(tmp_path / "src/panda_pkg", "my_panda_description")
    sim_hand(urdf)
    with pytest.raises(RobotConfigError) as info:
        MotionGenerator.from_urdf(urdf, ee_link="panda_hand", arm_joints=ARM)
    assert "package://my_panda_description/meshes/collision/link0.stl" in str(info.value)
    assert "rename or link" in str(info.value) and "panda_pkg" in str(info.value)


def test_an_unknown_package_names_the_uri_and_the_folders_searched(world, tmp_path, monkeypatch):
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws"))
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "install"))
    urdf = tmp_path / "robots/robot.urdf"
    urdf.parent.mkdir()
    urdf.write_text(PANDA.read_text().replace(MESHES, "package://no_such_description/meshes"))
    uri = "package://no_such_description/meshes/collision/link0.stl"
    words = [uri, "package 'no_such_description' not found", f"{tmp_path / 'robots'} and its parent folders",
             f"{tmp_path / 'ws'} (ROS_PACKAGE_PATH)", str(tmp_path / "install/share"), "ROS_PACKAGE_PATH",
             "AMENT_PREFIX_PATH"]
    with pytest.raises(RobotConfigError) as info:
        MotionGenerator.from_urdf(urdf, ee_link="panda_hand", arm_joints=ARM)
    for w in words:
        assert w in str(info.value)
    World()
    add_reference_to_stage(str(urdf), "/World/R")
    with pytest.raises(SimulationError) as info:
        World.instance().reset()
    for w in [*words, "/World/R"]:
        assert w in str(info.value)


def test_a_package_without_the_file_says_where_it_looked(world, tmp_path, monkeypatch):
    urdf = package(tmp_path / "src/my_panda_description", "my_panda_description")
    (tmp_path / "src/my_panda_description/meshes/collision/link3.stl").unlink()
    with pytest.raises(RobotConfigError, match=r"collision/link3.stl: package 'my_panda_description' is .*"
                                               r"my_panda_description, which has no meshes/collision/link3.stl"):
        MotionGenerator.from_urdf(urdf, ee_link="panda_hand", arm_joints=ARM)
    World()
    add_reference_to_stage(str(urdf), "/World/R")
    with pytest.raises(SimulationError, match="which has no meshes/collision/link3.stl"):
        World.instance().reset()
