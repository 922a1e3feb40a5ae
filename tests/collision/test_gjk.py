"""`collision.gjk.within` against coal (the oracle) on the Panda's link hulls and the primitive
shapes, at thousands of random placements and three margins; `compiled_narrowphase.concavity`."""

from __future__ import annotations

import coal
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from manip.collision import gjk
from manip.collision.checker import CollisionChecker
from manip.planning.path.compiled_narrowphase import CONVEX_TOLERANCE, concavity

BAND = 1e-6   # [m] answers may differ from coal's only this close to the margin


@pytest.fixture(scope="module")
def links(franka_config):
    """The Panda's link meshes and their hulls (coal), and the hulls' vertices in one array."""
    checker = CollisionChecker(franka_config)
    meshes = [(p.geometry, p.hull) for p in checker.state.parts if p.hull is not p.geometry]
    points = [np.asarray(h.points(), dtype=float) for _, h in meshes]
    count = np.array([len(P) for P in points])
    return meshes, np.ascontiguousarray(np.concatenate(points)), np.cumsum(count) - count, count


def _shape(kind: str, rng, links):
    """(gjk kind, h, rho, vertex start, count, coal geometry, mesh or None) of a random shape."""
    meshes, _, start, count = links
    if kind == "box":
        h = rng.uniform(0.01, 0.3, 3)
        return gjk.ROUNDED_BOX, h, 0.0, 0, 0, coal.Box(*(2 * h)), None
    if kind == "sphere":
        r = rng.uniform(0.01, 0.2)
        return gjk.ROUNDED_BOX, np.zeros(3), r, 0, 0, coal.Sphere(r), None
    if kind == "capsule":
        r, hh = rng.uniform(0.01, 0.1), rng.uniform(0.01, 0.3)
        return gjk.ROUNDED_BOX, np.array([0, 0, hh]), r, 0, 0, coal.Capsule(r, 2 * hh), None
    if kind == "cylinder":
        r, hh = rng.uniform(0.01, 0.2), rng.uniform(0.01, 0.3)
        return gjk.CYLINDER, np.array([r, r, hh]), 0.0, 0, 0, coal.Cylinder(r, 2 * hh), None
    g = int(rng.integers(len(meshes)))
    return gjk.VERTICES, np.zeros(3), 0.0, start[g], count[g], meshes[g][1], meshes[g][0]


KINDS = ["box", "sphere", "capsule", "cylinder", "hull"]


@pytest.mark.parametrize("other", KINDS)
def test_within_agrees_with_coal(links, other):
    rng = np.random.default_rng(KINDS.index(other))
    V = links[1]
    n, unsure, wrong, free_meshes = 2000, 0, [], 0
    for _ in range(n):
        a = _shape("hull", rng, links)
        b = _shape(other, rng, links)
        Ra, Rb = Rotation.random(2, random_state=rng).as_matrix()
        ca, cb = rng.normal(scale=0.15, size=(2, 3))
        margin = float(rng.choice([0.0, 0.01, 0.03]))
        r = gjk.within(a[0], Ra, ca, a[1], a[2], b[0], Rb, cb, b[1], b[2], V, a[3], a[4], b[3], b[4], margin)
        req = coal.CollisionRequest()
        req.security_margin = margin
        ta, tb = coal.Transform3s(Ra, ca), coal.Transform3s(Rb, cb)
        hit = coal.collide(a[5], ta, b[5], tb, req, coal.CollisionResult())
        if r == gjk.UNSURE:
            unsure += 1
            continue
        if (r == gjk.WITHIN) != hit:
            d = coal.distance(a[5], ta, b[5], tb, coal.DistanceRequest(), coal.DistanceResult())
            wrong.append(d - margin)
        if r == gjk.APART:   # the hull holds the mesh: the mesh keeps clear too
            free_meshes += 1
            assert not coal.collide(a[6], ta, b[6] if b[6] is not None else b[5], tb, req, coal.CollisionResult())
    assert unsure == 0
    assert all(abs(w) < BAND for w in wrong), wrong
    assert free_meshes > n // 10   # both answers met often
    assert n - free_meshes - unsure > n // 10


def test_within_overlap_and_touching():
    """Unit boxes: overlapping, apart by 1 cm against margins 0.5 and 1.5 cm, and a sphere
    inside a cylinder."""
    R, z, V = np.eye(3), np.zeros(3), np.zeros((0, 3))
    h = np.full(3, 0.5)
    box = (gjk.ROUNDED_BOX, R)
    assert gjk.within(*box, z, h, 0.0, *box, np.array([0.9, 0, 0]), h, 0.0, V, 0, 0, 0, 0, 0.0) == gjk.WITHIN
    far = np.array([1.01, 0.0, 0.0])
    assert gjk.within(*box, z, h, 0.0, *box, far, h, 0.0, V, 0, 0, 0, 0, 0.005) == gjk.APART
    assert gjk.within(*box, z, h, 0.0, *box, far, h, 0.0, V, 0, 0, 0, 0, 0.015) == gjk.WITHIN
    cyl = np.array([0.3, 0.3, 0.2])
    assert gjk.within(gjk.ROUNDED_BOX, R, z, z, 0.05, gjk.CYLINDER, R, z, cyl, 0.0, V, 0, 0, 0, 0, 0.0) == gjk.WITHIN
    assert gjk.within(gjk.ROUNDED_BOX, R, np.array([0, 0, 0.26]), z, 0.05, gjk.CYLINDER, R, z, cyl, 0.0, V,
                      0, 0, 0, 0, 0.0) == gjk.APART


def test_concavity(links):
    """The Panda's meshes are their hulls (within the tolerance); a box with a dent is not."""
    for mesh, hull in links[0]:
        assert concavity(mesh, np.asarray(hull.points())) < 0.3e-3   # 0.03-0.23 mm
    X = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * 0.1
    top = np.array([0.0, 0.0, 0.1 - 0.02])   # the top face's centre, pushed 2 cm in
    V = np.vstack([X, top])
    hull_faces = [(0, 1, 3), (0, 3, 2), (0, 4, 5), (0, 5, 1), (0, 2, 6), (0, 6, 4), (4, 6, 7), (4, 7, 5),
                  (2, 3, 7), (2, 7, 6)]
    top_faces = [(1, 5, 8), (5, 7, 8), (7, 3, 8), (3, 1, 8)]   # the top face (1, 3, 5, 7) as a dent
    mesh = coal.BVHModelOBBRSS()
    mesh.beginModel(len(hull_faces) + len(top_faces), len(V))
    mesh.addVertices(V)
    mesh.addTriangles(np.array(hull_faces + top_faces))
    mesh.endModel()
    assert concavity(mesh, X) == pytest.approx(0.02, abs=1e-9)
    assert concavity(mesh, X) > CONVEX_TOLERANCE
