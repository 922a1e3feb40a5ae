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
            hit, left = part_boxes(*geometry._grid, tf.getRotation(), tf.getTranslation(), *hull, margin)
            hits += truth
            decided += bool(hit) or (not truth and left.size == 0)
            assert not hit or truth   # a vertex inside a box is a collision
    assert hits > 40
    assert decided > hits   # most answers come without coal
