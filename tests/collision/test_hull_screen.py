"""`collision.hull_screen`: every candidate pair it drops is free for coal, and every check of
the checker answers the same with and without it (Panda, primitives of each kind, an attached
box, a padding, random configurations and segments near the obstacles)."""

from __future__ import annotations

import coal
import numpy as np
import pytest
from scipy.spatial import ConvexHull

from manip.collision import broadphase, hull_screen
from manip.collision.checker import CollisionChecker
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Sphere
from manip.collision.solids import mesh_arrays
from manip.collision.world import WorldConfig
from manip.pose import Pose


@pytest.fixture(scope="module")
def checker(franka_config, franka_kinematics):
    q = franka_config.default_joint_positions
    held = Cuboid("held", [0.04, 0.09, 0.2], franka_kinematics.fk(q, "panda_hand") @ Pose([0.0, 0.0, 0.2]))
    world = WorldConfig([
        held,
        Cuboid("table", [0.8, 1.2, 0.04], Pose([0.55, 0.0, -0.02])),
        Cuboid("shelf", [0.3, 0.6, 0.02], Pose([0.5, 0.0, 0.45], [0.96, 0.0, 0.28, 0.0])),
        Cylinder("can", 0.04, 0.3, Pose([0.45, -0.25, 0.15])),
        Sphere("ball", 0.08, Pose([0.35, 0.3, 0.55])),
        Capsule("rod", 0.03, 0.4, Pose([0.3, 0.0, 0.7], [0.7071068, 0.7071068, 0.0, 0.0])),
    ])
    cc = CollisionChecker(franka_config, franka_kinematics, world, padding=0.01, self_padding=0.002)
    cc.attach_object("held", q=q)
    return cc


def _near_configurations(cc, n: int, seed: int) -> np.ndarray:
    """n random configurations, most of them with broadphase candidates (near the obstacles)."""
    rng = np.random.default_rng(seed)
    kin = cc.kinematics
    Q = rng.uniform(kin.lower, kin.upper, (20 * n, kin.dof))
    R, p = kin.joint_transforms(Q)
    nn = cc._candidates(Q, R, p)[0]
    near = np.unique(nn)
    return Q[near[:n]] if near.size >= n else Q[:n]


def test_hulls_hold_the_meshes(checker):
    for part in checker.state.parts:
        if hasattr(part.geometry, "num_tris") and part.hull is not part.geometry:
            V = mesh_arrays(part.geometry)[0]
            eq = ConvexHull(np.asarray(part.hull.points())).equations
            assert (V @ eq[:, :3].T + eq[:, 3]).max() < 1e-9, part.name


def test_dropped_pairs_are_free_for_coal(checker):
    cc = checker.snapshot()
    Q = _near_configurations(cc, 400, 0)
    R, p = cc.kinematics.joint_transforms(Q)
    n, kind, i, j = cc._candidates(Q, R, p)
    RA, pA = broadphase.part_placements(R, p, n, i, cc._pj, cc._gR, cc._gp)
    RB, pB = broadphase.part_placements(R, p, n, np.where(kind == 1, j, 0), cc._pj, cc._gR, cc._gp)
    drop = hull_screen.apart(kind, i, j, RA, pA, RB, pB, *cc._hull_parts, cc._hull_okind, *cc._bp_obstacles[:4],
                             cc._padding + hull_screen.SLACK, cc._self_padding + hull_screen.SLACK)
    assert drop.sum() > len(drop) // 10 and (~drop).sum() > 20   # both met often
    parts, res = cc.state.parts, coal.CollisionResult()
    kinds = set()
    for t in np.flatnonzero(drop):
        a = parts[i[t]]
        ta = coal.Transform3s(RA[t], pA[t])
        if kind[t] == 0:
            geom, tb, req = cc._ogeom[j[t]], cc._otf[j[t]], cc._req_world
            kinds.add(type(cc.state.obstacles[j[t]]).__name__)
        else:
            geom, tb, req = parts[j[t]].geometry, coal.Transform3s(RB[t], pB[t]), cc._req_self
            kinds.add("self")
        res.clear()
        assert not coal.collide(a.geometry, ta, geom, tb, req, res), (a.name, kind[t], j[t])
    assert kinds == {"Cuboid", "Cylinder", "Sphere", "Capsule", "self"}


def _with_and_without(monkeypatch, f):
    """f() with the screen on, then off."""
    monkeypatch.setattr(hull_screen, "ENABLED", True)
    out = f()
    monkeypatch.setattr(hull_screen, "ENABLED", False)
    return out, f()


def test_checks_answer_the_same(checker, monkeypatch):
    cc = checker.snapshot()
    Q = _near_configurations(cc, 600, 1)
    for kwargs in ({}, {"inside": True}, {"stop_at_first": True, "deepest_first": False}):
        on, off = _with_and_without(monkeypatch, lambda: cc._check(Q, **kwargs))  # noqa: B023
        if "stop_at_first" in kwargs:
            assert on.any() == off.any() and np.argmax(on) == np.argmax(off)
        else:
            assert np.array_equal(on, off)
            assert 50 < on.sum() < len(Q) - 50
    rng = np.random.default_rng(2)
    Q0 = _near_configurations(cc, 150, 3)
    Q1 = Q0 + rng.normal(scale=0.3, size=Q0.shape)
    Q1 = np.clip(Q1, cc.kinematics.lower, cc.kinematics.upper)
    on, off = _with_and_without(monkeypatch, lambda: cc.motion_valid_batch(Q0, Q1, 0.02))
    assert np.array_equal(on, off) and 10 < on.sum() < len(Q0) - 10
    hits = _with_and_without(monkeypatch, lambda: [cc.first_collision(a, b, 0.02) for a, b in zip(Q0[:40], Q1[:40])])
    assert hits[0] == hits[1]
