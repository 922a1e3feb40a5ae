"""`occupancy_exact`: a part against a map's boxes, decided without coal where a cheap test is
conclusive, answers as coal on every box does."""

from __future__ import annotations

import coal
import numpy as np
import pytest

from manip import MotionGenerator
from manip.collision import OccupancyMap
from manip.collision.occupancy_exact import part_boxes, part_hull

RES = 0.02


def surface_map() -> OccupancyMap:
    """Thin measured slabs (as `fill="points"` gives) on a wavy surface, and a solid block."""
    rng = np.random.default_rng(3)
    cells, bounds = [], []
    for i in range(15, 35):
        for j in range(-12, 12):
            z = 0.25 + 0.05 * np.sin(i / 3.0) * np.cos(j / 4.0)
            k = int(np.floor(z / RES))
            lo = np.array([i * RES, j * RES, z - 0.002 * rng.random()])
            hi = np.array([(i + 1) * RES, (j + 1) * RES, z + 0.002 * rng.random()])
            cells.append([i, j, k])
            bounds.append(np.r_[lo, np.minimum(hi, (np.array([i, j, k]) + 1) * RES)])
    for i in range(20, 24):
        for j in range(14, 18):
            for k in range(0, 12):
                cells.append([i, j, k])
                bounds.append(np.r_[np.array([i, j, k]) * RES, (np.array([i, j, k]) + 1) * RES])
    return OccupancyMap.from_cells("camera", RES, np.array(cells), np.array(bounds))


@pytest.mark.parametrize("margin", [0.0, 0.004])
def test_answers_equal_coal_on_every_box(margin):
    mg = MotionGenerator("franka")
    geometry = surface_map().coal_geometry()
    boxes = [(coal.Box(*np.maximum(b[3:] - b[:3], 1e-9)), coal.Transform3s(np.eye(3), (b[:3] + b[3:]) / 2))
             for b in geometry.boxes]
    request = coal.CollisionRequest()
    request.security_margin = margin
    result = coal.CollisionResult()
    rng = np.random.default_rng(0)
    Q = rng.uniform(mg.lower_limits, mg.upper_limits, (250, 7))
    R, p = mg.checker.kinematics.joint_transforms(Q)
    parts = mg.checker.state.parts
    hits = decided = 0
    for n in range(Q.shape[0]):
        for part in parts:
            if part.joint == 0:
                continue
            Rg = R[n, part.joint] @ part.R
            tf = coal.Transform3s(Rg, p[n, part.joint] + R[n, part.joint] @ part.p)
            truth = False
            for box, btf in boxes:
                result.clear()
                if coal.collide(part.geometry, tf, box, btf, request, result):
                    truth = True
                    break
            assert geometry.collide(part.geometry, tf, request, result) == truth
            hull = part_hull(part.geometry)
            hit, left = part_boxes(*geometry._grid, geometry.solid, *geometry._points, tf.getRotation(),
                                   tf.getTranslation(), *hull, margin)
            hits += truth
            decided += bool(hit) or (not truth and left.size == 0)
            assert not hit or truth   # a vertex inside a box is a collision
    assert hits > 40
    assert decided > hits   # most answers come without coal


def hull_map() -> OccupancyMap:
    """The wavy surface measured as points every 2.5 mm (each cell the hull of its points), and
    the solid block as whole cells (no points: boxes)."""
    g = np.arange(15 * RES, 35 * RES, 0.0025)
    X, Y = np.meshgrid(g, np.arange(-12 * RES, 12 * RES, 0.0025))
    Z = 0.25 + 0.05 * np.sin(X / RES / 3.0) * np.cos(Y / RES / 4.0)
    P = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)
    cells, of_point = np.unique(np.floor(P / RES).astype(np.int64), axis=0, return_inverse=True)
    of_point = of_point.ravel()
    order = np.argsort(of_point, kind="stable")
    start = np.concatenate([[0], np.cumsum(np.bincount(of_point, minlength=len(cells)))])
    block = np.array([[i, j, k] for i in range(20, 24) for j in range(14, 18) for k in range(0, 12)])
    cells = np.vstack([cells, block])
    start = np.concatenate([start, np.full(len(block), start[-1])])
    return OccupancyMap.from_cells("camera", RES, cells, None, points=(start, P[order])), P


@pytest.mark.parametrize("margin", [0.0, 0.004])
def test_a_map_of_hulls_answers_as_coal_on_every_solid(margin):
    mg = MotionGenerator("franka")
    m, P = hull_map()
    assert m.num_hulls > 400 and m.num_boxes < m.num_cells   # the block's cells merged, each hull alone
    geometry = m.coal_geometry()
    solids = [geometry._solid(b)[:2] for b in range(geometry.boxes.shape[0])]
    # each hull holds its cell's points and lies in its cell's box (the broadphase's bound)
    assert m.contains_points(P[::7])
    for b in np.flatnonzero(~geometry.solid)[::25]:
        V = np.asarray(solids[b][0].points()).reshape(-1, 3)
        assert np.all(V >= geometry.boxes[b, :3] - 1e-12) and np.all(V <= geometry.boxes[b, 3:] + 1e-12)
    request = coal.CollisionRequest()
    request.security_margin = margin
    result = coal.CollisionResult()
    boxes_only = OccupancyMap.from_cells("boxes", RES, m.cells, m.bounds).coal_geometry()
    rng = np.random.default_rng(1)
    Q = rng.uniform(mg.lower_limits, mg.upper_limits, (150, 7))
    R, p = mg.checker.kinematics.joint_transforms(Q)
    hits = box_hits = 0
    for n in range(Q.shape[0]):
        for part in mg.checker.state.parts:
            if part.joint == 0:
                continue
            tf = coal.Transform3s(R[n, part.joint] @ part.R, p[n, part.joint] + R[n, part.joint] @ part.p)
            truth = False
            for solid, stf in solids:
                result.clear()
                if coal.collide(part.geometry, tf, solid, stf, request, result):
                    truth = True
                    break
            assert geometry.collide(part.geometry, tf, request, result) == truth
            box_hit = boxes_only.collide(part.geometry, tf, request, result)
            assert box_hit or not truth   # the hulls lie in the boxes
            hits += truth
            box_hits += box_hit
    assert hits > 20 and box_hits > hits   # a slanted surface's boxes stick out of it, its hulls do not
    # distances (the certificate's): the nearest solid's, as coal gives it against every one
    # (in contact: a penetration, not necessarily the deepest)
    hand = next(part for part in mg.checker.state.parts if part.joint == 7)
    for n in range(40):
        tf = coal.Transform3s(R[n, 7] @ hand.R, p[n, 7] + R[n, 7] @ hand.p)
        truth = min(coal.distance(hand.geometry, tf, solid, stf, coal.DistanceRequest(), coal.DistanceResult())
                    for solid, stf in solids)
        d, _ = geometry.distance(hand.geometry, tf, coal.DistanceRequest(), coal.DistanceResult())
        assert d == pytest.approx(truth, abs=1e-7) if truth > 0.0 else d <= 0.0
