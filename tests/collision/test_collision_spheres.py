"""Automatic sphere covers: every surface point is inside a ball, for closed and open meshes."""

from __future__ import annotations

import numpy as np
import pytest

from manip.collision.spheres import cover_with_spheres, inside_mesh, is_closed, protrusion, subdivide


def _box(h):
    V = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float) * h
    F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return V, F


def _covered(V, F, C, R):
    pts, _ = subdivide(V, F, 0.002)
    d = np.linalg.norm(pts[:, None, :] - C[None], axis=-1) - R[None]
    return d.min(axis=1).max() <= 1e-12


@pytest.mark.parametrize("h, tol", [([0.01, 0.02, 0.005], 0.01), ([0.2, 0.05, 0.05], 0.02), ([0.15, 0.1, 0.01], 0.02)])
def test_box_covers(h, tol):
    V, F = _box(np.array(h))
    assert is_closed(F)
    C, R = cover_with_spheres(V, F, tolerance=tol, max_spheres=32)
    assert len(R) <= 32
    assert _covered(V, F, C, R)


def test_cover_sticks_out_by_about_the_tolerance_when_enough_balls():
    V, F = _box(np.array([0.1, 0.03, 0.03]))
    C, R = cover_with_spheres(V, F, tolerance=0.02, max_spheres=48)
    pts, _ = subdivide(V, F, 0.004)
    # the protrusion bound holds up to the coarse sampling of the final assignment
    assert protrusion(C, R, V, F, pts, True) <= 0.02 + 0.006


def test_open_mesh_is_covered():
    V = np.array([[0, 0, 0], [0.3, 0, 0], [0.3, 0.2, 0], [0, 0.2, 0]], dtype=float)
    F = np.array([[0, 1, 2], [0, 2, 3]])
    assert not is_closed(F)
    C, R = cover_with_spheres(V, F, tolerance=0.02, max_spheres=16)
    assert _covered(V, F, C, R)


def test_inside_mesh():
    V, F = _box(np.array([0.1, 0.2, 0.3]))
    pts = np.array([[0, 0, 0], [0.09, 0.19, 0.29], [0.11, 0, 0], [0, 0, 0.31]])
    np.testing.assert_array_equal(inside_mesh(pts, V, F), [True, True, False, False])


def test_cover_is_deterministic():
    V, F = _box(np.array([0.2, 0.05, 0.05]))
    a = cover_with_spheres(V, F)
    b = cover_with_spheres(V, F)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def test_solid_cover_holds_the_volume():
    h = np.array([0.1, 0.04, 0.03])
    V, F = _box(h)
    C, R = cover_with_spheres(V, F, tolerance=0.01, max_spheres=32, solid=True)
    pts = np.random.default_rng(0).uniform(-h, h, (5000, 3))
    d = np.linalg.norm(pts[:, None, :] - C[None], axis=-1) - R[None]
    assert d.min(axis=1).max() <= 1e-12
    assert _covered(V, F, C, R)
