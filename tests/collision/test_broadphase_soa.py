"""`collision.broadphase_soa.world_candidates`: the same candidates, depths and order as the
per-configuration `broadphase.world_candidates`, bit for bit (Panda; MotionBenchMaker worlds and a
world of every primitive kind, a rotated cylinder and capsule, a mesh and an attached box; random
configurations, configurations along segments near the obstacles, every block size)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.benchmarking.mbm_problems import load_mbm_problems
from manip.collision import broadphase, broadphase_soa
from manip.collision.checker import CollisionChecker
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Mesh, Sphere
from manip.collision.world import WorldConfig
from manip.pose import Pose


def _every_kind(config, kinematics) -> CollisionChecker:
    link3 = str(config.urdf_path.parent.parent / "meshes" / "collision" / "link3.stl")
    q = config.default_joint_positions
    held = Cuboid("held", [0.04, 0.09, 0.2], kinematics.fk(q, "panda_hand") @ Pose([0.0, 0.0, 0.2]))
    world = WorldConfig([
        held,
        Cuboid("table", [0.8, 1.2, 0.04], Pose([0.55, 0.0, -0.02])),
        Cuboid("shelf", [0.3, 0.6, 0.02], Pose([0.5, 0.0, 0.45], [0.96, 0.0, 0.28, 0.0])),
        Cylinder("can", 0.04, 0.3, Pose([0.45, -0.25, 0.15], [np.cos(0.4), np.sin(0.4), 0, 0])),
        Sphere("ball", 0.08, Pose([0.35, 0.3, 0.55])),
        Capsule("rod", 0.03, 0.4, Pose([0.3, 0.0, 0.7], [0.7071068, 0.7071068, 0.0, 0.0])),
        Mesh("mesh", file_path=link3, pose=Pose([-0.35, 0.35, 0.25])),
    ])
    cc = CollisionChecker(config, kinematics, world, padding=0.01, self_padding=0.002)
    cc.attach_object("held", q=q)
    return cc


def _configurations(kin, seed: int) -> np.ndarray:
    """3000 random configurations, then 2000 along 40 random segments (50 samples each: the
    spatially coherent batches of the segment checks)."""
    rng = np.random.default_rng(seed)
    Q = rng.uniform(kin.lower, kin.upper, (3000, kin.dof))
    a = rng.uniform(kin.lower, kin.upper, (40, kin.dof))
    b = np.clip(a + rng.normal(0.0, 0.4, a.shape), kin.lower, kin.upper)
    t = np.linspace(0.0, 1.0, 50)
    S = (a[:, None] + t[None, :, None] * (b - a)[:, None]).reshape(-1, kin.dof)
    return np.concatenate([Q, S])


def _assert_same(cc: CollisionChecker, Q: np.ndarray, lanes_list=(1, 7, 32, 1024)) -> int:
    """Both kernels on Q in batches of 1, 67 and 1024; returns the candidates found."""
    found = 0
    margin = cc._padding + 1e-9
    R, p = cc.kinematics.joint_transforms(Q[:0])   # an empty batch: empty answers
    assert all(x.size == 0 for x in broadphase_soa.world_candidates(R, p, margin, *cc._bp_world,
                                                                      *cc._bp_obstacles, 32))
    for size in (1, 67, 1024):
        for s in range(0, Q.shape[0], size if size > 1 else 97):
            R, p = cc.kinematics.joint_transforms(Q[s:s + size])
            old = broadphase.world_candidates(R, p, margin, *cc._bp_world, *cc._bp_obstacles)
            for lanes in lanes_list:
                new = broadphase_soa.world_candidates(R, p, margin, *cc._bp_world, *cc._bp_obstacles, lanes)
                for x, y in zip(old, new):
                    assert x.dtype == y.dtype and np.array_equal(x, y), (size, lanes)
            found += old[0].size
    return found


def test_every_obstacle_kind(franka_config, franka_kinematics):
    cc = _every_kind(franka_config, franka_kinematics).snapshot()
    assert _assert_same(cc, _configurations(cc.kinematics, 0)) > 1000   # the covers' levels were reached


@pytest.mark.parametrize("scene", ["bookshelf_small_panda", "cage_panda", "table_under_pick_panda"])
def test_mbm_worlds(franka_config, franka_kinematics, scene):
    problem = next(p for p in load_mbm_problems(limit_per_scene=1) if p.scene == scene)
    cc = CollisionChecker(franka_config, franka_kinematics, WorldConfig.from_dict(problem.world))
    Q = np.concatenate([_configurations(cc.kinematics, 1)[::2], np.asarray(problem.start)[None]])
    assert _assert_same(cc.snapshot(), Q, lanes_list=(32,)) > 100


def test_not_finite_lanes_are_not_skipped(franka_config, franka_kinematics):
    """A NaN or infinite configuration in a block: the block is not skipped on its bounding box
    (which would not hold those lanes); the answers stay those of the per-configuration kernel."""
    cc = _every_kind(franka_config, franka_kinematics).snapshot()
    Q = _configurations(cc.kinematics, 2)[:64].copy()
    Q[5, 1] = np.nan
    Q[9, 0] = np.inf
    R, p = cc.kinematics.joint_transforms(Q)
    margin = cc._padding + 1e-9
    old = broadphase.world_candidates(R, p, margin, *cc._bp_world, *cc._bp_obstacles)
    new = broadphase_soa.world_candidates(R, p, margin, *cc._bp_world, *cc._bp_obstacles, 32)
    assert old[0].size and not np.isin([5, 9], old[0]).any()
    for x, y in zip(old, new):
        np.testing.assert_array_equal(x, y)


def test_checker_answers_unchanged(franka_config, franka_kinematics, monkeypatch):
    """`_check` in each of its modes answers the same with either kernel."""
    cc = _every_kind(franka_config, franka_kinematics).snapshot()
    Q = _configurations(cc.kinematics, 3)[2000:4000]
    group = np.arange(Q.shape[0]) // 50
    modes = [{}, {"group": group}, {"group": group, "deepest_first": False}, {"stop_at_first": True}]
    new = [cc._check(Q, **m) for m in modes]
    monkeypatch.setattr(broadphase_soa, "world_candidates",
                        lambda R, p, margin, *tables: broadphase.world_candidates(R, p, margin, *tables[:-1]))
    old = [cc._check(Q, **m) for m in modes]
    for m, a, b in zip(modes, old, new):
        if "group" in m:
            for g in np.unique(group):
                assert a[group == g].any() == b[group == g].any()
        elif m.get("stop_at_first"):
            assert a.any() == b.any()
        else:
            np.testing.assert_array_equal(a, b)
    assert 0 < new[0].sum() < Q.shape[0]
