"""`OccupancyMap`: voxel cells as solid boxes in checks, distances and certificates."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from manip import MotionGenerator, Pose, WorldConfig
from manip.collision import Cuboid, OccupancyMap
from manip.collision.clearance import ClearanceModel
from manip.errors import InvalidInputError

RES = 0.02


def block(lo, hi) -> np.ndarray:
    """(C, 3) the cells of the box [lo, hi) of cell indices."""
    axes = [np.arange(a, b) for a, b in zip(lo, hi)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


# a wall and a table top, as cells and as the cuboids they fill exactly
CELLS = np.vstack([block((25, -10, 0), (28, 10, 20)), block((10, -25, -1), (45, 25, 0))])
BOXES = [Cuboid("wall", [0.06, 0.4, 0.4], [0.53, 0.0, 0.2]), Cuboid("table", [0.7, 1.0, 0.02], [0.55, 0.0, -0.01])]


@pytest.fixture(scope="module")
def pair():
    m = MotionGenerator("franka")
    m.add_obstacle(OccupancyMap.from_cells("camera", RES, CELLS))
    return m, MotionGenerator("franka", WorldConfig(BOXES))


def test_checks_equal_those_of_the_same_boxes(pair):
    on_map, on_boxes = pair
    Q = np.random.default_rng(0).uniform(on_map.lower_limits, on_map.upper_limits, (600, 7))
    a = on_map.checker.in_collision_batch(Q)
    b = on_boxes.checker.in_collision_batch(Q)
    assert 20 < a.sum() < 580
    np.testing.assert_array_equal(a, b)
    for q in Q[~b][:40]:   # clearances are exact (penetration depths of a mesh of boxes are not compared)
        assert on_map.distance(q) == pytest.approx(on_boxes.distance(q), abs=1e-5)


def test_clearance_terms_are_those_of_the_same_boxes_and_only_active_ones(pair):
    on_map, on_boxes = pair
    Q = np.random.default_rng(1).uniform(on_map.lower_limits, on_map.upper_limits, (300, 7))
    activation = 0.03
    a = ClearanceModel(on_map.checker).terms(Q, activation)
    b = ClearanceModel(on_boxes.checker).terms(Q, activation)
    assert np.all(a.distance < activation - 1e-9)   # no term for a body without a cell nearer than that
    assert 30 < a.config.size <= b.config.size
    for n in np.unique(b.config):   # the map is one obstacle: its nearest term is the boxes' nearest
        nearest = b.distance[b.config == n].min()
        if nearest >= 0.0:   # (inside a box, the map gives the ball's centre depth, the boxes a signed distance)
            assert a.distance[a.config == n].min() == pytest.approx(nearest, abs=1e-9)
    assert set(a.config.tolist()) == set(b.config.tolist())


def test_the_certificate_proves_motions_around_the_cells_and_refuses_motions_through_them(pair):
    on_map, on_boxes = pair
    q0 = on_map.default_joint_positions
    ik = lambda p: on_boxes.ik(Pose(p, [0, 1, 0, 0]), seed_q=q0, collision_free=True).q  # noqa: E731
    left, right = ik([0.4, 0.35, 0.25]), ik([0.4, -0.35, 0.25])
    front, beside = ik([0.35, 0.0, 0.15]), ik([0.7, 0.3, 0.15])   # in front of the wall; beside it, behind
    through = np.array([front, beside])   # the straight joint motion sweeps the arm through the wall
    assert not on_boxes.checker.certify_path(through).certified
    assert not on_map.checker.certify_path(through).certified
    r = on_map.plan_joints(left, right, seed=0)
    assert r.success
    assert on_map.checker.certify_path(r.trajectory.positions).certified
    assert on_boxes.checker.certify_path(r.trajectory.positions).certified


def test_a_part_inside_a_block_of_cells_collides_without_touching_a_face():
    mg = MotionGenerator("franka")
    q = mg.default_joint_positions
    hand = mg.fk(q, "panda_hand").position
    c = np.floor(hand / RES).astype(int)
    mg.add_obstacle(OccupancyMap.from_cells("camera", RES, block(c - 8, c + 9)))   # a 34 cm cube of cells
    assert mg.check_collision(q)
    assert not mg.checker.certify_path(np.array([q, q + 0.01])).certified
    assert mg.checker.collision_report(q).contacts


def test_cells_under_the_base_are_never_checked_against_its_fixed_links():
    mg = MotionGenerator("franka")
    q = mg.default_joint_positions
    floor = block((-20, -20, -1), (20, 20, 0))          # the floor the base stands on
    into_base = block((-3, -3, 0), (3, 3, 2))           # even cells inside panda_link0
    mg.add_obstacle(OccupancyMap.from_cells("camera", RES, np.vstack([floor, into_base])))
    assert not mg.check_collision(q)
    assert mg.checker.certify_path(np.array([q, q + 0.05])).certified


def test_a_map_round_trips_through_the_world_dict_and_pickle():
    m = OccupancyMap.from_cells("camera", RES, CELLS)
    w = WorldConfig.from_dict(WorldConfig([m]).to_dict())
    back = w.get("camera")
    assert isinstance(back, OccupancyMap)
    np.testing.assert_array_equal(back.cells, m.cells)
    again = pickle.loads(pickle.dumps(m))
    np.testing.assert_array_equal(again.cells, m.cells)
    assert again.num_boxes == m.num_boxes and again.contains_points(np.array([[0.53, 0.0, 0.2]]))


def test_bad_input_names_the_argument():
    with pytest.raises(InvalidInputError, match="cells"):
        OccupancyMap.from_cells("camera", RES, np.zeros((4, 2), dtype=int))
    with pytest.raises(InvalidInputError, match="cells"):
        OccupancyMap.from_cells("camera", RES, np.zeros((4, 3)))
    with pytest.raises(InvalidInputError, match="resolution"):
        OccupancyMap.from_cells("camera", -1.0, CELLS)
    m = OccupancyMap.from_cells("camera", RES, CELLS)
    with pytest.raises(InvalidInputError, match="base frame"):
        m.with_pose([0.1, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="from_cells"):
        OccupancyMap("camera")


def _slanted_points():
    """(cells, (start, points)): a plane rising 30 deg along x measured every 2 mm."""
    g = np.arange(0.40, 0.48, 0.002)
    X, Y = np.meshgrid(g, np.arange(-0.04, 0.04, 0.002))
    P = np.stack([X.ravel(), Y.ravel(), 0.2 + math.tan(math.radians(30)) * (X.ravel() - 0.4)], axis=1)
    cells, of_point = np.unique(np.floor(P / RES).astype(np.int64), axis=0, return_inverse=True)
    of_point = of_point.ravel()
    start = np.concatenate([[0], np.cumsum(np.bincount(of_point, minlength=len(cells)))])
    return cells, (start, P[np.argsort(of_point, kind="stable")])


def test_a_map_of_points_is_the_hulls_of_its_cells_and_round_trips():
    cells, points = _slanted_points()
    m = OccupancyMap.from_cells("camera", RES, cells, None, points)
    boxes = OccupancyMap.from_cells("boxes", RES, cells, m.bounds)
    assert m.num_hulls == m.num_cells > 10
    assert m.contains_points(points[1])   # every measured point
    above = np.array([[0.442, 0.005, 0.2 + math.tan(math.radians(30)) * 0.042 + 0.003]])   # 3 mm above the plane
    assert boxes.contains_points(above) and not m.contains_points(above)
    w = WorldConfig.from_dict(WorldConfig([m]).to_dict())
    back = w.get("camera")
    assert back.num_hulls == m.num_hulls and not back.contains_points(above) and back.contains_points(points[1])
    again = pickle.loads(pickle.dumps(m))
    assert again.num_hulls == m.num_hulls and not again.contains_points(above)


def _signed_volume(V: np.ndarray, F: np.ndarray) -> float:
    """The volume [m^3] a closed triangle mesh encloses (> 0 when its faces point outward)."""
    return float(np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6.0)


def test_the_solids_mesh_is_the_boxes_and_hulls_the_checks_use():
    from scipy.spatial import ConvexHull

    from manip.collision.occupancy_hulls import GROW, hull_points

    cells, points = _slanted_points()
    m = OccupancyMap.from_cells("camera", RES, cells, None, points)
    V, F = m.solids_mesh()
    g = m.coal_geometry()
    start, P, box_cell = g.hulls
    hulls = np.flatnonzero(~g.solid)
    assert hulls.size == m.num_hulls > 10
    # each hull cell's convex hull, faces outward: the mesh encloses the sum of their volumes (each
    # hull also holds three points GROW from one of its points, a volume of at most a cell's face times GROW)
    volume = sum(ConvexHull(hull_points(P[start[box_cell[k]]:start[box_cell[k] + 1]], g.boxes[k], RES)).volume
                 for k in hulls)
    assert _signed_volume(V, F) == pytest.approx(volume, abs=hulls.size * 6 * RES ** 2 * GROW)
    assert volume < 0.5 * np.prod(g.boxes[hulls, 3:] - g.boxes[hulls, :3], axis=1).sum()   # much less than the boxes
    # a map of cells alone: the mesh is its merged boxes
    boxes = OccupancyMap.from_cells("boxes", RES, cells)
    Vb, Fb = boxes.solids_mesh()
    np.testing.assert_array_equal(Vb, boxes.vertices)
    np.testing.assert_array_equal(Fb, boxes.faces)
    assert _signed_volume(Vb, Fb) == pytest.approx(len(cells) * RES ** 3, rel=1e-9)


def test_a_hull_from_qhulls_triangles_answers_as_coals_own_hull():
    import coal

    from manip.collision.occupancy_hulls import cell_hull, hull_triangles

    cells, (start, P) = _slanted_points()
    m = OccupancyMap.from_cells("camera", RES, cells, None, (start, P))
    g = m.coal_geometry()
    rng = np.random.default_rng(0)
    checked = 0
    for k in np.flatnonzero(~g.solid):
        pts = P[start[g.hulls[2][k]]:start[g.hulls[2][k] + 1]]
        ours, _ = cell_hull(pts, g.boxes[k], RES)
        V, _ = hull_triangles(pts, g.boxes[k], RES)
        vertices = coal.StdVec_Vec3s()
        for x in V:
            vertices.append(x)
        coals = coal.ConvexBase.convexHull(vertices, False, "Qt")
        centre = (g.boxes[k, :3] + g.boxes[k, 3:]) / 2
        for _ in range(10):
            tf = coal.Transform3s(np.eye(3), centre + rng.normal(0.0, 0.01, 3))
            ball = coal.Sphere(0.003)
            d = [coal.distance(h, coal.Transform3s(), ball, tf, coal.DistanceRequest(), coal.DistanceResult())
                 for h in (ours, coals)]
            hit = [coal.collide(h, coal.Transform3s(), ball, tf, coal.CollisionRequest(), coal.CollisionResult())
                   for h in (ours, coals)]
            # equal to GJK's tolerance (its iterations walk the two vertex sets by other paths)
            assert d[0] == pytest.approx(d[1], abs=coal.DistanceRequest().gjk_tolerance) and hit[0] == hit[1]
            checked += 1
    assert checked >= 100


def test_hulls_are_remembered_for_a_bounded_number_of_cells(monkeypatch):
    from manip.collision import occupancy_hulls

    monkeypatch.setattr(occupancy_hulls, "HULL_CACHE", 4)
    monkeypatch.setattr(occupancy_hulls, "_HULLS", {})
    cells, points = _slanted_points()
    m = OccupancyMap.from_cells("camera", RES, cells, None, points)
    V, F = m.solids_mesh()
    assert len(occupancy_hulls._HULLS) == 4   # the last 4 of the map's hull cells
    again = OccupancyMap.from_cells("camera", RES, cells, None, points)   # an update that changed nothing
    np.testing.assert_array_equal(again.solids_mesh()[0], V)
    np.testing.assert_array_equal(again.solids_mesh()[1], F)
    assert again.contains_points(points[1]) and len(occupancy_hulls._HULLS) == 4


def test_bad_points_name_the_argument():
    cells, (start, P) = _slanted_points()
    for bad in ((start[:-1], P), (start, P[:-1]), (start[::-1], P), (start.astype(float), P), "abc", (start, P[:, :2])):
        with pytest.raises(InvalidInputError, match="points"):
            OccupancyMap.from_cells("camera", RES, cells, None, bad)
    Q = P.copy()
    Q[3, 1] = np.nan
    with pytest.raises(InvalidInputError, match="points"):
        OccupancyMap.from_cells("camera", RES, cells, None, (start, Q))
    with pytest.raises(InvalidInputError, match="distinct"):
        OccupancyMap.from_cells("camera", RES, np.vstack([cells, cells[:1]]), None,
                                (np.append(start, start[-1]), P))


def test_bad_bounds_name_the_argument():
    with pytest.raises(InvalidInputError, match="bounds"):
        OccupancyMap.from_cells("camera", RES, CELLS, np.zeros((3, 6)))
    b = np.hstack([CELLS * RES, (CELLS + 1) * RES])
    b[0, 3] = b[0, 0] - 0.001   # hi < lo
    with pytest.raises(InvalidInputError, match="bounds"):
        OccupancyMap.from_cells("camera", RES, CELLS, b)


# a table top measured as points at z = 0.013 m (in the middle of the cells of layer 0)
TOP = 0.013
SLAB_CELLS = block((15, -10, 0), (35, 10, 1))
SLAB = np.hstack([SLAB_CELLS * RES, (SLAB_CELLS + 1) * RES])
SLAB[:, 2] = SLAB[:, 5] = TOP


def test_a_cell_holds_its_bounds_and_meets_its_occupied_neighbours():
    m = OccupancyMap.from_cells("camera", RES, SLAB_CELLS, SLAB)
    assert m.num_boxes == 1   # one flat sheet: the cells' boxes meet and merge
    cb = m.cell_boxes()
    np.testing.assert_allclose(cb[:, 2], TOP, atol=1e-4)
    np.testing.assert_allclose(cb[:, 5], TOP, atol=1e-4)
    assert m.contains_points(np.array([[0.5, 0.0, TOP]]))
    assert not m.contains_points(np.array([[0.5, 0.0, TOP + 0.002]]))   # in the cell, above the surface
    assert m.lower_bounds(np.array([[0.5, 0.0, TOP + 0.005]]), exact_within=0.05)[0] == pytest.approx(0.005, abs=2e-4)
    # a lone cell keeps its bounds on every side
    lone = OccupancyMap.from_cells("lone", RES, [[25, 0, 5]], [[0.505, 0.004, 0.101, 0.507, 0.016, 0.103]])
    np.testing.assert_allclose(lone.cell_boxes()[0], [0.505, 0.004, 0.101, 0.507, 0.016, 0.103], atol=1.5e-4)
    back = WorldConfig.from_dict(WorldConfig([m]).to_dict()).get("camera")
    np.testing.assert_array_equal(back.cell_boxes(), m.cell_boxes())


def sheet(z: float, res: float) -> OccupancyMap:
    """A horizontal surface at height z [m] under the hand, measured in cells of edge res [m]."""
    lo, hi = np.floor(np.array([0.21, -0.1]) / res).astype(int), np.ceil(np.array([0.41, 0.1]) / res).astype(int)
    k = math.floor(z / res)
    cells = block((lo[0], lo[1], k), (hi[0], hi[1], k + 1))
    bounds = np.hstack([cells * res, (cells + 1) * res])
    bounds[:, 2] = bounds[:, 5] = z
    return OccupancyMap.from_cells("camera", res, cells, bounds)


def test_the_hand_5_mm_above_a_measured_surface_is_free_and_certified_along_it():
    mg = MotionGenerator("franka")
    q = mg.default_joint_positions
    z = 0.3
    for _ in range(3):   # raise the surface until it is 5 mm below the robot
        mg.add_obstacle(sheet(z, RES))
        z += mg.checker.distance_report(q).world_distance - 0.005
        mg.remove_obstacle("camera")
    res = z / (math.floor(z / RES) + 0.3)   # about 2 cm, the surface 30 % up its cells
    mg.add_obstacle(sheet(z, res))
    assert not mg.check_collision(q)
    assert mg.checker.distance_report(q).world_distance == pytest.approx(0.005, abs=2e-4)
    whole = MotionGenerator("franka")
    whole.add_obstacle(OccupancyMap.from_cells("camera", res, mg.world.get("camera").cells))
    assert whole.check_collision(q)   # whole cells reach 14 mm above the surface
    # along the sheet: certified; down into it: a collision
    q2 = q.copy()
    q2[0] += 0.1
    assert mg.checker.certify_path(np.array([q, q2])).certified
    deeper = q.copy()
    deeper[3] -= 0.05   # the elbow bends: the hand goes 2.4 cm down, into the surface
    assert mg.check_collision(deeper)
    assert not mg.checker.certify_path(np.array([q, deeper])).certified
