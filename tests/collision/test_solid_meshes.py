"""Mesh obstacles are surfaces; `Mesh(solid=True)` makes a closed mesh the volume it bounds, in
the point checks, the plans and their continuous certificate; `Mesh.decimated` a coarser solid
that holds a mesh."""

from __future__ import annotations

import numpy as np
import pytest

from manip import MotionGenerator, Pose, WorldConfig
from manip.collision.shapes import Cuboid, Mesh
from manip.collision.solids import contains
from manip.errors import InvalidInputError

BOX_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])


def box_vertices(dims) -> np.ndarray:
    h = np.asarray(dims, dtype=float) / 2.0
    return np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * h


def box_mesh(name: str, dims, pose, solid: bool) -> Mesh:
    return Mesh(name, vertices=box_vertices(dims), faces=BOX_FACES, pose=pose, solid=solid)


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka", seed=0)


def test_a_robot_inside_a_closed_mesh_box_collides_only_as_a_solid(mg) -> None:
    q0 = mg.default_joint_positions
    q1 = q0 + np.array([0.6, 0.2, 0.0, 0.3, 0.0, 0.0, 0.0])
    room = dict(dims=[3.0, 3.0, 3.0], pose=[0.0, 0.0, 0.5])
    outcome = {}
    for kind, ob in (("surface", box_mesh("room", solid=False, **room)),
                     ("solid", box_mesh("room", solid=True, **room)),
                     ("cuboid", Cuboid("room", **room))):
        mg.update_world(WorldConfig([ob]))
        report = mg.checker.collision_report(q0)
        outcome[kind] = (mg.check_collision(q0), mg.plan_joints(q0, q1).status.name, mg.distance(q0) < 0,
                         mg.checker.certify_path(np.array([q0, q1])).reason, mg.checker.in_collision_exact(q0),
                         report.in_collision and report.contacts[0].b == "room" and report.contacts[0].distance < 0)
    assert outcome["surface"] == (False, "SUCCESS", False, "", False, False)   # a surface: free inside
    assert outcome["solid"] == outcome["cuboid"] == (True, "INVALID_START_WORLD_COLLISION", True, "collision", True,
                                                     True)
    mg.update_world({})


def test_a_plan_past_a_solid_mesh_keeps_out_of_its_volume(mg) -> None:
    q0 = np.array([-1.2, 0.3, 0.0, -1.8, 0.0, 2.1, 0.785])
    q1 = np.array([1.2, 0.3, 0.0, -1.8, 0.0, 2.1, 0.785])
    block = dict(dims=[0.3, 0.3, 0.5], pose=Pose([0.55, 0.0, 0.25], [np.cos(0.2), 0.0, 0.0, np.sin(0.2)]))
    cuboid = WorldConfig([Cuboid("block", **block)])
    mg.update_world(cuboid)
    assert mg.checker.motion_valid(q0, q1) is False   # the straight motion goes through the block
    mg.update_world(WorldConfig([box_mesh("block", solid=True, **block)]))
    assert not mg.check_collision(q0) and not mg.check_collision(q1)
    r = mg.plan_joints(q0, q1)
    assert r.success, r.status
    path = r.trajectory.positions
    # the same volume as a cuboid: the plan never enters it, sampled or continuous
    mg.update_world(cuboid)
    assert not mg.checker.in_collision_batch(path).any()
    assert mg.checker.certify_path(path).certified
    mg.update_world({})


def test_the_certificate_of_a_motion_inside_a_solid_fails_at_its_start(mg) -> None:
    q0 = mg.default_joint_positions
    path = np.array([q0, q0 + 0.2, q0 + 0.4])
    mg.update_world(WorldConfig([box_mesh("room", [3.0, 3.0, 3.0], [0.0, 0.0, 0.5], solid=False)]))
    assert mg.checker.certify_path(path).certified   # inside a surface: no triangle is ever touched
    mg.update_world(WorldConfig([box_mesh("room", [3.0, 3.0, 3.0], [0.0, 0.0, 0.5], solid=True)]))
    cert = mg.checker.certify_path(path)
    assert (cert.certified, cert.first_failed_segment, cert.reason, cert.pair[1]) == (False, 0, "collision", "room")
    mg.update_world({})


def test_moving_a_solid_keeps_it_solid_and_its_rotation(mg) -> None:
    q0 = mg.default_joint_positions
    quarter = [np.cos(np.pi / 8), 0.0, 0.0, np.sin(np.pi / 8)]
    mg.update_world(WorldConfig([box_mesh("room", [3.0, 3.0, 3.0], Pose([5.0, 0.0, 0.5], quarter), solid=True)]))
    assert not mg.check_collision(q0)
    mg.update_obstacle_pose("room", [0.0, 0.0, 0.5])
    moved = mg.world.get("room")
    assert moved.solid and np.allclose(moved.pose.quaternion, quarter)
    assert mg.check_collision(q0)
    mg.update_world({})


def test_solid_needs_a_closed_consistently_oriented_mesh() -> None:
    V = box_vertices([0.2, 0.2, 0.2])
    with pytest.raises(InvalidInputError, match=r"mesh 'lid' \(solid=True\): not a closed surface: 4 edge\(s\) belong to 1 triangle"):
        Mesh("lid", vertices=V, faces=BOX_FACES[:-2], solid=True)   # a side removed: an open box
    Mesh("lid", vertices=V, faces=BOX_FACES[:-2])                   # as a surface, fine
    flipped = BOX_FACES.copy()
    flipped[3] = flipped[3, ::-1]
    with pytest.raises(InvalidInputError, match="not consistently oriented"):
        Mesh("flip", vertices=V, faces=flipped, solid=True)
    with pytest.raises(InvalidInputError, match="solid must be True or False"):
        Mesh("box", vertices=V, faces=BOX_FACES, solid="yes")
    with pytest.raises(InvalidInputError, match="solid must be True or False"):
        WorldConfig.from_dict({"mesh": {"box": {"vertices": V.tolist(), "faces": BOX_FACES.tolist(), "solid": 1}}})
    # inside out (every triangle clockwise): turned outward, the same solid
    inverted = Mesh("inv", vertices=V, faces=BOX_FACES[:, ::-1], solid=True)
    assert inverted.solid_data.volume == pytest.approx(0.008)
    assert contains(inverted.solid_data, _bvh(inverted), np.zeros((1, 3)))


def _bvh(mesh: Mesh):
    from manip.collision.shapes import coal_geometry

    return coal_geometry(mesh)


def test_the_world_format_carries_solid_and_stl_files_load_welded(tmp_path) -> None:
    V = box_vertices([0.2, 0.3, 0.4])
    d = {"mesh": {"box": {"vertices": V.tolist(), "faces": BOX_FACES.tolist(), "solid": True, "pose": [1, 0, 0, 1, 0, 0, 0]}}}
    w = WorldConfig.from_dict(d)
    assert w.get("box").solid and w.to_dict()["mesh"]["box"]["solid"] is True
    assert WorldConfig.from_dict(w.to_dict()).get("box").solid
    assert "solid" not in WorldConfig.from_dict({"mesh": {"b": {"vertices": V.tolist(),
                                                                  "faces": BOX_FACES.tolist()}}}).to_dict()["mesh"]["b"]
    # a binary STL repeats each vertex per triangle: read and welded into a closed solid
    rec = np.zeros(len(BOX_FACES), dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    rec["v"] = V[BOX_FACES]
    path = tmp_path / "box.stl"
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + np.uint32(len(BOX_FACES)).tobytes())
        rec.tofile(f)
    m = Mesh("box", file_path=path, solid=True)
    assert m.vertices.shape == (8, 3) and m.faces.shape == (12, 3)
    assert m.solid_data.volume == pytest.approx(0.024, rel=1e-6)
    # sent to another process (manip.batch): pickled without coal's tree, still a solid
    import pickle

    _bvh(m)
    copied = pickle.loads(pickle.dumps(m.with_pose([0.0, 0.0, 0.5])))
    assert copied.solid and contains(copied.solid_data, _bvh(copied), np.zeros((1, 3)))


def star_prism(points: int = 5, r_out: float = 0.3, r_in: float = 0.12, height: float = 0.2):
    """A closed, non-convex star prism centred on the origin, and its inside test."""
    a = np.pi * np.arange(2 * points) / points
    r = np.where(np.arange(2 * points) % 2 == 0, r_out, r_in)
    ring = np.c_[r * np.cos(a), r * np.sin(a)]
    n = len(ring)
    V = np.r_[np.c_[ring, np.full(n, -height / 2)], np.c_[ring, np.full(n, height / 2)],
              [[0.0, 0.0, -height / 2], [0.0, 0.0, height / 2]]]
    F = []
    for i in range(n):
        j = (i + 1) % n
        F += [[i, j, n + j], [i, n + j, n + i], [2 * n, j, i], [2 * n + 1, n + i, n + j]]

    def inside(P: np.ndarray) -> np.ndarray:
        x, y = P[:, 0], P[:, 1]
        odd = np.zeros(len(P), dtype=bool)
        for i in range(n):   # ray casting along +x
            (x1, y1), (x2, y2) = ring[i], ring[(i + 1) % n]
            crosses = (y1 > y) != (y2 > y)
            xc = x1 + (y - y1) * (x2 - x1) / np.where(y2 != y1, y2 - y1, 1.0)
            odd ^= crosses & (x < xc)
        return odd & (np.abs(P[:, 2]) < height / 2)

    return V, np.array(F), inside


def test_the_inside_test_is_exact_on_a_non_convex_solid() -> None:
    V, F, inside = star_prism()
    mesh = Mesh("star", vertices=V, faces=F, solid=True)
    bvh = _bvh(mesh)
    rng = np.random.default_rng(0)
    P = rng.uniform([-0.35, -0.35, -0.15], [0.35, 0.35, 0.15], size=(3000, 3))
    # also points just off the notches' edges and corners, where the closest feature is not a face
    notch = V[1:10:2, :2] * 1.02
    P = np.r_[P, np.c_[notch, np.full(len(notch), 0.05)], np.c_[V[0:10:2, :2] * 0.98, np.full(5, 0.099)]]
    truth = inside(P)
    got = np.array([contains(mesh.solid_data, bvh, p[None]) for p in P])
    assert truth.sum() > 300 and np.array_equal(got, truth)


def test_decimated_meshes_are_solids_that_hold_the_original(mg) -> None:
    # a fine surface: a 2 m x 2 m height field of 80,000 triangles in the arm's reach
    n = 200
    x, y = np.meshgrid(np.linspace(-1, 1, n + 1), np.linspace(-1, 1, n + 1))
    V = np.c_[x.ravel() + 0.5, y.ravel(), 0.05 * np.sin(5 * x.ravel()) * np.cos(5 * y.ravel()) + 0.1]
    i = np.arange(n)[:, None] * (n + 1) + np.arange(n)[None]
    F = np.r_[np.c_[i.ravel(), i.ravel() + 1, i.ravel() + n + 2], np.c_[i.ravel(), i.ravel() + n + 2, i.ravel() + n + 1]]
    scan = Mesh("scan", vertices=V, faces=F)
    coarse = scan.decimated(0.04)
    assert coarse.solid and len(coarse.faces) < len(F) / 4 and coarse.name == "scan"
    # it holds every vertex and triangle centre of the original, and is at most a cell diagonal larger
    P = np.r_[V, V[F].mean(axis=1)]
    bvh = _bvh(coarse)
    assert all(contains(coarse.solid_data, bvh, p[None]) for p in P[::11])
    lo, hi = coarse.solid_data.lower, coarse.solid_data.upper
    assert np.all(lo <= V.min(axis=0)) and np.all(hi >= V.max(axis=0))
    assert np.all(V.min(axis=0) - lo <= 0.04 * np.sqrt(3)) and np.all(hi - V.max(axis=0) <= 0.04 * np.sqrt(3))
    # as an obstacle: whatever the original touches, the decimated solid does too
    rng = np.random.default_rng(1)
    Q = rng.uniform(mg.lower_limits, mg.upper_limits, size=(200, 7))
    mg.update_world(WorldConfig([scan]))
    fine = mg.checker.in_collision_batch(Q)
    mg.update_world(WorldConfig([coarse]))
    assert fine.any() and not np.any(fine & ~mg.checker.in_collision_batch(Q))
    with pytest.raises(InvalidInputError, match="cell"):
        scan.decimated(0.0)
    with pytest.raises(InvalidInputError, match=r"use a cell of at least"):
        scan.decimated(1e-4)
    mg.update_world({})
