"""`collision.convex_parts`: the one table of parts and obstacles as `gjk` shapes that the exact
checker's screen (`hull_screen`) and the coarse search's narrowphase (`compiled_narrowphase`)
share, the hull planes `inside`, `occupancy_exact` and `compiled_narrowphase` share, and the
screen's tables built only when the screen runs (not at each world edit)."""

from __future__ import annotations

import dataclasses

import coal
import numpy as np
import pytest
from scipy.spatial import ConvexHull

from manip.collision import convex_parts, gjk, hull_screen
from manip.collision.checker import CollisionChecker
from manip.collision.inside import inside_table
from manip.collision.occupancy_exact import part_hull
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Mesh, Sphere
from manip.collision.world import WorldConfig
from manip.planning.path import compiled_narrowphase
from manip.planning.path.compiled_narrowphase import CONVEX_TOLERANCE, NarrowTables, concavity
from manip.pose import Pose


@pytest.fixture(scope="module")
def checker(franka_config, franka_kinematics):
    """The Franka holding a box, a sphere, a capsule and a cylinder, among each kind of obstacle."""
    q = franka_config.default_joint_positions
    hand = franka_kinematics.fk(q, "panda_hand")
    held = [Cuboid("box", [0.04, 0.06, 0.1], hand @ Pose([0.0, 0.0, 0.15])),
            Sphere("ball", 0.03, hand @ Pose([0.0, 0.1, 0.15])),
            Capsule("rod", 0.02, 0.1, hand @ Pose([0.0, -0.1, 0.15])),
            Cylinder("can", 0.03, 0.1, hand @ Pose([0.1, 0.0, 0.15]))]
    world = WorldConfig(held + [
        Cuboid("table", [0.8, 1.2, 0.04], Pose([0.55, 0.0, -0.02])),
        Sphere("pebble", 0.05, Pose([0.4, 0.3, 0.5])),
        Capsule("pole", 0.03, 0.4, Pose([0.3, -0.4, 0.5])),
        Cylinder("tin", 0.04, 0.3, Pose([0.45, -0.25, 0.15])),
        Mesh("cube", vertices=np.array([[x, y, z] for x in (0, 0.1) for y in (0, 0.1) for z in (0, 0.1)]),
             faces=ConvexHull(np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)])).simplices,
             pose=Pose([0.6, 0.4, 0.3])),
    ])
    cc = CollisionChecker(franka_config, franka_kinematics, world, padding=0.01)
    for ob in held:
        cc.attach_object(ob.name, q=q)
    return cc


def test_each_part_and_obstacle_is_its_gjk_shape(checker):
    kind, h, rho, start, count, V = convex_parts.part_tables(checker.state.parts)
    by_name = {p.name: g for g, p in enumerate(checker.state.parts)}
    for g, part in enumerate(checker.state.parts):
        if hasattr(part.geometry, "num_tris"):   # a link mesh: its hull's vertices
            assert kind[g] == gjk.VERTICES, part.name
            assert np.array_equal(V[start[g]:start[g] + count[g]], np.asarray(part.hull.points()))
    assert kind[by_name["box"]] == gjk.ROUNDED_BOX and np.allclose(h[by_name["box"]], [0.02, 0.03, 0.05])
    assert kind[by_name["ball"]] == gjk.ROUNDED_BOX and rho[by_name["ball"]] == 0.03
    assert kind[by_name["rod"]] == gjk.ROUNDED_BOX and np.allclose(h[by_name["rod"]], [0, 0, 0.05])
    assert kind[by_name["can"]] == gjk.CYLINDER and np.allclose(h[by_name["can"]], [0.03, 0.03, 0.05])
    assert convex_parts.obstacle_kinds(checker.state.obstacles).tolist() == [
        gjk.ROUNDED_BOX, gjk.ROUNDED_BOX, gjk.ROUNDED_BOX, gjk.CYLINDER, gjk.NO]


def test_the_screen_and_the_coarse_narrowphase_read_one_table(checker):
    cc = checker.snapshot()
    nt = NarrowTables(cc.state)
    for mine, theirs in zip((nt.kind, nt.h, nt.rho, nt.start, nt.count, nt.V), cc._hull_parts):
        assert np.array_equal(mine, theirs)
    assert np.array_equal(nt.okind, cc._hull_okind)
    # the convex flags: the primitives, and the Panda's link meshes (0.03-0.23 mm under their hulls)
    assert nt.convex.all()


def _convex(P: np.ndarray):
    """A coal.Convex of points P (K, 3)."""
    points = coal.StdVec_Vec3s()
    for x in P:
        points.append(x)
    return coal.ConvexBase.convexHull(points, False, "Qt")


class _Points:
    """A hull of given points (a flat one: qhull builds none)."""

    def __init__(self, P: np.ndarray):
        self._P = P

    def points(self) -> np.ndarray:
        return self._P


def test_a_flat_hull_or_a_hull_beside_another_geometry_is_left_to_coal(checker):
    """The two degenerate rows the two copies once answered differently: both leave the part's
    pairs to coal now (gjk.NO, not convex): a flat hull (fewer than 4 points) and a convex
    geometry that is not a mesh given with a separate hull (not known to hold it)."""
    link = next(p for p in checker.state.parts if p.name == "panda_link5")
    tri = _Points(np.array([[0.0, 0, 0], [0.1, 0, 0], [0, 0.1, 0]]))   # qhull makes no coal.Convex of these
    tetra = _convex(np.array([[0.0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]]))
    flat = dataclasses.replace(link, hull=tri)
    beside = dataclasses.replace(link, geometry=tetra, hull=_convex(2 * np.asarray(tetra.points())))
    for part in (flat, beside):
        assert convex_parts.part_row(part)[0] == gjk.NO
    compiled_narrowphase._LAST_PARTS = (None, None)
    arrays = compiled_narrowphase._part_arrays([flat, beside, link])
    assert arrays[0].tolist() == [gjk.NO, gjk.NO, gjk.VERTICES] and arrays[-1].tolist() == [False, False, True]
    compiled_narrowphase._LAST_PARTS = (None, None)


def test_one_hull_per_mesh_for_inside_occupancy_and_concavity(checker):
    cc = checker.snapshot()
    tab = inside_table(cc._parts, cc._pairs, cc._pj, cc._gR, cc._gp)
    closed = set(tab.closed.tolist())
    assert closed   # the Panda's links are closed meshes
    for g, part in enumerate(cc._parts):
        if not hasattr(part.geometry, "num_tris"):
            continue
        eq, area = convex_parts.hull_planes(part.geometry)
        assert convex_parts.hull_planes(part.geometry)[0] is eq   # cached: qhull once per mesh
        V = np.asarray(part.geometry.vertices()).reshape(-1, 3)
        assert np.array_equal(eq, ConvexHull(V).equations) and area == ConvexHull(V).area
        data = part_hull(part.geometry)
        assert np.array_equal(data[3], eq[:, :3]) and np.array_equal(data[4], -eq[:, 3])
        if g in closed:
            assert np.array_equal(tab.hulls[g, :len(eq)], eq) and np.all(tab.hulls[g, len(eq):, 3] == -np.inf)
        # the mesh's hull and its coal hull's points' hull: one polytope, the same depth
        depth = concavity(part.geometry)
        assert depth == pytest.approx(concavity(part.geometry, np.asarray(part.hull.points())), abs=1e-12)
        assert depth < CONVEX_TOLERANCE


def test_edits_build_no_screen_table_until_the_screen_runs(franka_config, franka_kinematics, monkeypatch):
    world = WorldConfig([Cuboid("a", [0.1, 0.1, 0.1], Pose([0.5, 0.0, 0.5])), Sphere("b", 0.05, Pose([0.4, 0.3, 0.5]))])
    cc = CollisionChecker(franka_config, franka_kinematics, world)
    built = []
    monkeypatch.setattr(convex_parts, "obstacle_kinds", lambda obs: built.append(len(obs)) or np.array(
        [gjk.ROUNDED_BOX if type(ob) in (Cuboid, Sphere, Capsule) else gjk.CYLINDER if type(ob) is Cylinder else gjk.NO
         for ob in obs], dtype=np.int64))
    q = franka_config.default_joint_positions
    for k in range(5):
        cc.update_obstacle_pose("a", Pose([0.5, 0.02 * k, 0.5]))
    cc.add_obstacle(Cylinder("c", 0.03, 0.2, Pose([0.3, -0.3, 0.3])))
    assert not hull_screen.ENABLED and not cc.in_collision(q)
    assert built == [] and cc.__dict__["_hull_okind_lazy"] == [] and cc.__dict__["_hull_parts_lazy"] == []
    Q = np.random.default_rng(0).uniform(franka_kinematics.lower, franka_kinematics.upper, (300, 7))
    off = cc.in_collision_batch(Q)
    monkeypatch.setattr(hull_screen, "ENABLED", True)   # switched on later: built for the world of now
    assert np.array_equal(cc.in_collision_batch(Q), off) and built == [3]
    assert cc._hull_okind.tolist() == [gjk.ROUNDED_BOX, gjk.ROUNDED_BOX, gjk.CYLINDER] and built == [3]
    cc.remove_obstacle("b")   # a new world: new kinds at its first check
    assert cc._hull_okind.tolist() == [gjk.ROUNDED_BOX, gjk.CYLINDER] and built == [3, 2]
    assert cc._hull_parts[0].size == len(cc.state.parts)
