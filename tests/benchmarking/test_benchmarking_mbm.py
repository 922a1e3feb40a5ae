"""MotionBenchMaker loader: counts, frame conventions, cylinder dimensions, pose goals."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from manip.benchmarking.mbm_problems import (
    MBM_SCENES,
    default_dataset_path,
    goal_pose,
    load_mbm_problems,
    scene_to_world,
)
from manip.errors import UnknownNameError
from robot_constants import REPO_ROOT

DATASET = default_dataset_path()


def test_scene_to_world_converts_orientation_and_cylinder_dims():
    # A MoveIt PlanningScene fragment: ROS quaternions are (x, y, z, w); cylinders [height, radius].
    scene = yaml.safe_load(
        """
world:
  collision_objects:
    - id: can
      primitives: [{type: cylinder, dimensions: [0.14, 0.03]}]
      primitive_poses: [{position: [0.5, 0.1, 0.2], orientation: [0, 0, 0.7071067811865476, 0.7071067811865476]}]
    - id: shelf
      primitives: [{type: box, dimensions: [0.7, 0.4, 0.02]}]
      primitive_poses: [{position: [0.6, 0, 0.3], orientation: [0, 0, 0, 1]}]
"""
    )
    w = scene_to_world(scene)
    can = w["cylinder"]["can"]
    assert can["height"] == pytest.approx(0.14) and can["radius"] == pytest.approx(0.03)
    np.testing.assert_allclose(can["pose"], [0.5, 0.1, 0.2, 0.7071067811865476, 0, 0, 0.7071067811865476])
    np.testing.assert_allclose(w["cuboid"]["shelf"]["dims"], [0.7, 0.4, 0.02])
    np.testing.assert_allclose(w["cuboid"]["shelf"]["pose"], [0.6, 0, 0.3, 1, 0, 0, 0])


def test_loads_all_700_problems():
    problems = load_mbm_problems(DATASET)
    assert len(problems) == 700
    assert sorted({p.scene for p in problems}) == sorted(MBM_SCENES)
    for s in MBM_SCENES:
        idx = [p.index for p in problems if p.scene == s]
        assert idx == list(range(1, 101))
    for p in problems:
        assert p.start.shape == (7,) and p.goal.shape == (7,)
        assert p.joint_names == tuple(f"panda_joint{i}" for i in range(1, 8))
        for kind, objs in p.world.items():
            assert kind in ("cuboid", "cylinder")
            for o in objs.values():
                q = np.asarray(o["pose"][3:])
                assert np.linalg.norm(q) == pytest.approx(1.0)


def test_box_panda_1_matches_the_yaml():
    # Values read by hand from problems/box_panda/scene0001.yaml and request0001.yaml.
    (p,) = load_mbm_problems(DATASET, scenes=["box_panda"], limit_per_scene=1)
    assert p.name == "box_panda/1"
    np.testing.assert_allclose(p.start, [0, -0.785, 0, -2.356, 0, 1.571, 0.785])
    assert p.goal[1] == pytest.approx(1.7628)
    can = p.world["cylinder"]["Can1"]
    assert (can["height"], can["radius"]) == (pytest.approx(0.14), pytest.approx(0.03))
    # ROS (x, y, z, w) = (0, 0, 0.0741, 0.9973) -> (w, x, y, z)
    np.testing.assert_allclose(can["pose"][3:], [0.9972531602635496, 0, 0, 0.07406844364750122], atol=1e-12)
    np.testing.assert_allclose(p.world["cuboid"]["base"]["dims"], [0.7, 0.7, 0.04])


def test_scene_filter_limit_and_unknown_scene():
    ps = load_mbm_problems(DATASET, scenes=["cage_panda", "box_panda"], limit_per_scene=3)
    assert [p.name for p in ps] == [f"{s}/{i}" for s in ("box_panda", "cage_panda") for i in (1, 2, 3)]
    with pytest.raises(UnknownNameError, match="box_panda"):
        load_mbm_problems(DATASET, scenes=["boxes"])


def test_the_dataset_ships_with_the_repository(monkeypatch):
    # the planner regression tests and benchmarks/mbm.py run from a fresh clone, with nothing beside it
    monkeypatch.delenv("MANIP_MBM_DATASET", raising=False)
    shipped = default_dataset_path()
    assert shipped == REPO_ROOT / "benchmarks" / "data" / "mbm" / "panda_problems.tar.bz2"
    assert shipped.is_file() and (shipped.parent / "LICENSE-vamp-Apache-2.0.txt").is_file()
    assert len(load_mbm_problems(shipped, scenes=["box_panda"], limit_per_scene=2)) == 2


def test_missing_dataset_raises_with_the_path(tmp_path):
    with pytest.raises(FileNotFoundError, match="MANIP_MBM_DATASET"):
        load_mbm_problems(tmp_path / "nope.tar.bz2")


def test_goal_pose_is_fk_of_the_goal_at_the_hand():
    import pinocchio as pin

    from manip.robot_config import load_robot_config

    (p,) = load_mbm_problems(DATASET, scenes=["table_pick_panda"], limit_per_scene=1)
    cfg = load_robot_config("franka")
    model = pin.buildModelFromUrdf(str(cfg.urdf_path))
    data = model.createData()
    q = np.concatenate([p.goal, [0.04, 0.04]])
    pin.framesForwardKinematics(model, data, q)
    M = data.oMf[model.getFrameId("panda_hand")]
    g = goal_pose(p)
    np.testing.assert_allclose(g.position, M.translation, atol=1e-9)
    w, x, y, z = g.quaternion
    R = pin.Quaternion(w, x, y, z).matrix()
    np.testing.assert_allclose(R, M.rotation, atol=1e-9)
