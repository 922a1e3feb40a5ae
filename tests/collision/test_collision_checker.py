"""CollisionChecker: exact agreement with a plain Pinocchio/coal mesh check, covers, padding,
distances, motions, attached objects and errors, on the real Panda model."""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin
import pytest

from manip.collision import Capsule, CollisionChecker, Cuboid, Cylinder, Mesh, Sphere, WorldConfig
from manip.collision.robot_geometry import geometry_triangles
from manip.collision.spheres import subdivide
from manip.errors import InvalidInputError, UnknownNameError
from manip.pose import Pose


def clutter_world(config) -> WorldConfig:
    """A MotionBenchMaker-like scene: table, a two-board shelf with walls, cans, a ball,
    a capsule and a mesh obstacle (the Panda's own link3 mesh)."""
    link3 = str(config.urdf_path.parent.parent / "meshes" / "collision" / "link3.stl")
    rz = Pose([0, 0, 0], [np.cos(0.2), 0, 0, np.sin(0.2)])
    return WorldConfig([
        Cuboid("table", [0.8, 1.4, 0.04], Pose([0.65, 0.0, -0.03])),
        Cuboid("board_low", [0.35, 0.8, 0.02], Pose([0.7, 0.0, 0.3]) @ rz),
        Cuboid("board_high", [0.35, 0.8, 0.02], Pose([0.7, 0.0, 0.65]) @ rz),
        Cuboid("wall_left", [0.35, 0.02, 0.7], Pose([0.7, 0.4, 0.33]) @ rz),
        Cuboid("wall_right", [0.35, 0.02, 0.7], Pose([0.7, -0.4, 0.33]) @ rz),
        Cylinder("can1", 0.03, 0.14, [0.6, 0.15, 0.39]),
        Cylinder("can2", 0.04, 0.2, Pose([0.3, -0.5, 0.1], [np.cos(0.4), np.sin(0.4), 0, 0])),
        Sphere("ball", 0.06, [0.0, 0.55, 0.5]),
        Capsule("rod", 0.025, 0.5, Pose([-0.4, -0.3, 0.6], [np.cos(0.6), 0, np.sin(0.6), 0])),
        Mesh("mesh", file_path=link3, pose=Pose([-0.35, 0.35, 0.25])),
    ])


def _coal_shape(ob):
    """The reference's own coal geometry (built without manip's helpers)."""
    if isinstance(ob, Cuboid):
        return coal.Box(*ob.dims)
    if isinstance(ob, Sphere):
        return coal.Sphere(ob.radius)
    if isinstance(ob, Cylinder):
        return coal.Cylinder(ob.radius, ob.height)
    if isinstance(ob, Capsule):
        return coal.Capsule(ob.radius, ob.height)
    return coal.MeshLoader().load(ob.file_path, np.ones(3))


class Reference:
    """Plain Pinocchio computeCollisions over the URDF meshes, SRDF pairs removed, the world
    as geometry objects on the universe joint with a security margin."""

    def __init__(self, config, kin, world: WorldConfig, padding: float):
        model = kin.model
        gm = pin.buildGeomFromUrdf(model, str(config.urdf_path), pin.COLLISION, package_dirs=list(config.package_dirs))
        gm.addAllCollisionPairs()
        pin.removeCollisionPairs(model, gm, str(config.srdf_path))
        n_robot = len(gm.geometryObjects)
        for ob in world:
            go = pin.GeometryObject(ob.name, 0, 0, pin.SE3(ob.pose.rotation, ob.pose.position), _coal_shape(ob))
            oid = gm.addGeometryObject(go)
            for r in range(n_robot):
                gm.addCollisionPair(pin.CollisionPair(r, oid))
        self.model, self.data, self.gm, self.n_robot = model, model.createData(), gm, n_robot
        self.gd = pin.GeometryData(gm)
        for k, cp in enumerate(gm.collisionPairs):
            if cp.second >= n_robot:
                self.gd.collisionRequests[k].security_margin = padding

    def __call__(self, q: np.ndarray) -> bool:
        return bool(pin.computeCollisions(self.model, self.data, self.gm, self.gd, q, True))

    def part_inside_part(self, q: np.ndarray) -> tuple[str, str] | None:
        """A robot geometry with a vertex inside another's closed mesh (winding number) at q,
        among the checked self pairs, or None: coal tests surfaces, so it misses a part wholly
        inside a link's mesh (a finger inside panda_link5)."""
        import trimesh

        pin.updateGeometryPlacements(self.model, self.data, self.gm, self.gd, q)
        objs = self.gm.geometryObjects
        for cp in self.gm.collisionPairs:
            a, b = cp.first, cp.second
            if b >= self.n_robot:   # a world pair
                continue
            for x, y in ((a, b), (b, a)):
                if not objs[y].meshPath.lower().endswith((".stl", ".obj", ".dae")):
                    continue
                mesh = trimesh.load(objs[y].meshPath, force="mesh")
                mesh.apply_scale(np.asarray(objs[y].meshScale))
                g = objs[x].geometry
                V = (np.asarray(g.vertices()).reshape(-1, 3)[:1] if hasattr(g, "vertices")
                     else np.zeros((1, 3)))   # a primitive: its centre
                Mx, My = self.gd.oMg[x], self.gd.oMg[y]
                local = (V @ Mx.rotation.T + Mx.translation - My.translation) @ My.rotation
                if abs(_winding_number(mesh.vertices[mesh.faces], local[0])) > 0.5:
                    return objs[x].name, objs[y].name
        return None


def _winding_number(T: np.ndarray, x: np.ndarray) -> float:
    """The winding number of the closed triangle surface T (F, 3, 3) about the point x (3,): the
    sum of its triangles' signed solid angles / 4 pi (A. Van Oosterom and J. Strackee, 1983);
    +-1 inside, 0 outside."""
    a, b, c = (T[:, k] - x for k in range(3))
    la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
    num = np.einsum("ij,ij->i", a, np.cross(b, c))
    den = la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", a, c) * lb \
        + np.einsum("ij,ij->i", b, c) * la
    return float(np.arctan2(num, den).sum() * 2.0 / (4.0 * np.pi))


@pytest.fixture(scope="module")
def world(franka_config) -> WorldConfig:
    return clutter_world(franka_config)


@pytest.fixture(scope="module")
def checker(franka_config, franka_kinematics, world) -> CollisionChecker:
    return CollisionChecker(franka_config, franka_kinematics, world, padding=0.0)


@pytest.fixture(scope="module")
def random_q(franka_kinematics) -> np.ndarray:
    rng = np.random.default_rng(7)
    return rng.uniform(franka_kinematics.lower, franka_kinematics.upper, (2000, 7))


def test_base_link_is_clear_of_the_table(checker):
    # the scene must not put every configuration in collision (that would test nothing)
    assert not checker.in_collision(checker.config.default_joint_positions)


def test_batch_agrees_exactly_with_plain_pinocchio_coal(franka_config, franka_kinematics, world, checker, random_q):
    ref = Reference(franka_config, franka_kinematics, world, padding=0.0)
    expected = np.array([ref(q) for q in random_q])
    got = checker.in_collision_batch(random_q)
    # a real mix of free and colliding configurations
    assert 0.2 < expected.mean() < 0.8
    false_free = np.nonzero(expected & ~got)[0]
    false_hit = np.nonzero(~expected & got)[0]
    assert false_free.size == 0, f"declared free but colliding: {random_q[false_free[:3]]}"
    # coal misses a part wholly inside another's mesh: each extra hit must be one (found by trimesh)
    inside = [ref.part_inside_part(random_q[k]) for k in false_hit]
    assert all(inside), f"declared colliding but free: {random_q[false_hit[[x is None for x in inside]]][:3]}"
    assert false_hit.size <= 0.005 * len(random_q)
    # single queries give the same answers
    for q, e in zip(random_q[:100], expected[:100] | np.isin(np.arange(100), false_hit)):
        assert checker.in_collision(q) == e


def test_padding_agrees_with_coal_security_margin(franka_config, franka_kinematics, world, random_q):
    pad = 0.03
    checker = CollisionChecker(franka_config, franka_kinematics, world, padding=pad)
    ref = Reference(franka_config, franka_kinematics, world, padding=pad)
    Q = random_q[:600]
    expected = np.array([ref(q) for q in Q])
    got = checker.in_collision_batch(Q)
    assert not (expected & ~got).any()
    # coal misses a part wholly inside another's mesh: each extra hit must be one (found by trimesh)
    assert all(ref.part_inside_part(Q[k]) for k in np.flatnonzero(got & ~expected))
    bare = CollisionChecker(franka_config, franka_kinematics, world, padding=0.0).in_collision_batch(Q)
    assert np.all(got >= bare) and got.sum() > bare.sum()


def test_sphere_covers_contain_every_surface_point(checker):
    for part in checker.robot.parts:
        V, F = geometry_triangles(part.geometry)
        pts, _ = subdivide(V, F, 0.005)
        X = pts @ part.R.T + part.p  # joint frame, like the centres
        d = np.linalg.norm(X[:, None, :] - part.centres[None], axis=-1) - part.radii[None]
        assert d.min(axis=1).max() <= 1e-12, part.name
        dc = np.linalg.norm(X[:, None, :] - part.coarse_centres[None], axis=-1) - part.coarse_radii[None]
        assert dc.min(axis=1).max() <= 1e-12, part.name
        if isinstance(part.geometry, coal.Box):  # solids: the inside counts too
            h = np.asarray(part.geometry.halfSide)
            inner = np.random.default_rng(0).uniform(-h, h, (500, 3)) @ part.R.T + part.p
            for Cs, rs in ((part.centres, part.radii), (part.coarse_centres, part.coarse_radii)):
                d = np.linalg.norm(inner[:, None, :] - Cs[None], axis=-1) - rs[None]
                assert d.min(axis=1).max() <= 1e-12, part.name
    # automatic, and not absurdly many
    assert 30 <= checker.num_spheres <= 400


def test_known_self_collision(checker):
    q = np.array([0.0, 1.7, 0.0, -3.0, 0.0, 0.0, 0.0])  # shoulder folded onto the base
    empty = CollisionChecker(checker.config, checker.kinematics)
    assert empty.in_collision(q)
    report = empty.collision_report(q)
    assert report.self_collision and not report.world_collision
    assert all(c.kind == "self" for c in report.contacts)
    assert empty.distance(q) < 0
    assert not empty.in_collision(checker.config.default_joint_positions)


def test_distance_sign_and_consistency(checker, random_q):
    hits = checker.in_collision_batch(random_q[:200])
    for q, hit in zip(random_q[:200], hits):
        rep = checker.distance_report(q)
        assert rep.distance == min(rep.world_distance, rep.self_distance)
        assert (rep.distance <= 0) if hit else (rep.distance > 0)
    rep = checker.distance_report(checker.config.default_joint_positions)
    assert rep.closest is not None and rep.closest.distance == pytest.approx(rep.distance)


def test_world_clearance_is_a_lower_bound_of_the_mesh_distance(franka_config, franka_kinematics, random_q):
    world = WorldConfig([ob for ob in clutter_world(franka_config) if not isinstance(ob, Mesh)])
    cc = CollisionChecker(franka_config, franka_kinematics, world)
    ref = Reference(franka_config, franka_kinematics, world, 0.0)
    # pairs of a moving robot geometry and an obstacle (the base link is left out by design)
    pairs = [k for k, cp in enumerate(ref.gm.collisionPairs)
             if ref.gm.geometryObjects[cp.second].name in world and ref.gm.geometryObjects[cp.first].parentJoint != 0]
    Q = random_q[:60]
    bound = cc.world_clearance_batch(Q)
    hit = cc.in_collision_batch(Q)
    for q, b, h in zip(Q, bound, hit):
        pin.computeDistances(ref.model, ref.data, ref.gm, ref.gd, q)
        true = min(ref.gd.distanceResults[k].min_distance for k in pairs)
        if true > 0:
            assert b <= true + 1e-9
        else:
            assert b <= 0
        if b > 0:
            assert not h or cc.collision_report(q).self_collision


def test_world_distance_matches_mesh_distance(franka_config, franka_kinematics):
    # one box in front of the ready pose: the hull distance equals coal's mesh distance
    q = franka_config.default_joint_positions
    box = Cuboid("box", [0.1, 0.1, 0.1], [0.55, 0.0, 0.3])
    cc = CollisionChecker(franka_config, franka_kinematics, WorldConfig([box]))
    ref = Reference(franka_config, franka_kinematics, WorldConfig([box]), 0.0)
    pin.computeDistances(ref.model, ref.data, ref.gm, ref.gd, q)
    world_pairs = [k for k, cp in enumerate(ref.gm.collisionPairs) if ref.gm.geometryObjects[cp.second].name == "box"]
    expected = min(ref.gd.distanceResults[k].min_distance for k in world_pairs)
    got = cc.distance_report(q).world_distance
    assert 0 < got <= expected + 1e-9
    assert got == pytest.approx(expected, abs=2e-3)


def test_motion_and_path_checks(franka_config, franka_kinematics):
    wall = Cuboid("wall", [0.02, 1.0, 1.0], [0.5, 0.0, 0.5])
    cc = CollisionChecker(franka_config, franka_kinematics, WorldConfig([wall]))
    q0 = np.array([1.2, 0.0, 0.0, -1.8, 0.0, 1.8, 0.8])
    q1 = q0.copy()
    q1[0] = -1.2  # swings the arm through the wall
    assert not cc.in_collision(q0) and not cc.in_collision(q1)
    assert not cc.motion_valid(q0, q1)
    q_back = q0.copy()
    q_back[0] = 2.4
    assert cc.motion_valid(q0, q_back)
    ok = cc.path_valid(np.stack([q_back, q0, q1]))
    assert ok.valid is False and ok.first_invalid_segment == 1
    assert cc.path_valid(np.stack([q_back, q0])) == (True, None)
    # the resolution bound: every sample of a valid motion is free
    steps = int(np.ceil(np.abs(q_back - q0).max() / 0.01))
    Q = q0 + np.linspace(0, 1, steps + 1)[:, None] * (q_back - q0)
    assert not cc.in_collision_batch(Q).any()


def test_attach_and_detach(franka_config, franka_kinematics):
    kin = franka_kinematics
    q = franka_config.default_joint_positions
    T_hand = kin.fk(q, "panda_hand")
    # a 20 cm box held below the hand flange, wider than the open fingers (they overlap it)
    held = Cuboid("held", [0.04, 0.09, 0.2], T_hand @ Pose([0.0, 0.0, 0.2]))
    cc = CollisionChecker(franka_config, kin, WorldConfig([held]))
    # in the world the box is just an obstacle overlapping the fingers
    assert cc.in_collision(q)
    cc.attach_object("held", q=q)
    assert "held" not in cc.world and "held" in cc.attached_objects
    assert not cc.in_collision(q)  # held between the fingers: allowed
    # a plate crossing the box's lower end, 15 cm beyond the fingertips: the bare hand misses it
    plate = Cuboid("plate", [0.2, 0.2, 0.01], T_hand @ Pose([0.0, 0.0, 0.27]))
    bare = CollisionChecker(franka_config, kin, WorldConfig([plate]))
    assert not bare.in_collision(q)
    cc.add_obstacle(plate)
    assert cc.in_collision(q)
    rep = cc.collision_report(q)
    assert [(c.kind, c.a, c.b) for c in rep.contacts] == [("attached_world", "held", "plate")]
    assert cc.distance(q) < 0
    cc.remove_obstacle("plate")
    # the attached box moves with the hand, and is checked against the other links
    q_side = q.copy()
    q_side[0] += 0.8
    assert not cc.in_collision(q_side)
    (placed,) = cc.detach_object(q_side)
    expected = kin.fk(q_side, "panda_hand") @ Pose([0.0, 0.0, 0.2])
    assert placed.pose.isclose(expected, 1e-9, 1e-9)
    assert cc.world.get("held").pose.isclose(expected, 1e-9, 1e-9)
    assert cc.attached_objects == {}
    assert cc.in_collision(q_side)  # back in the world, overlapping the fingers again


def test_attaching_an_attached_object_again_says_it_is_attached(franka_config, franka_kinematics):
    q = franka_config.default_joint_positions
    held = Cuboid("held", [0.04, 0.04, 0.04], franka_kinematics.fk(q, "panda_hand") @ Pose([0.0, 0.0, 0.1]))
    cc = CollisionChecker(franka_config, franka_kinematics, WorldConfig([held]))
    cc.attach_object("held", q=q)
    # not "obstacle 'held' not found": it left the world because it is held
    with pytest.raises(InvalidInputError, match="'held' is already attached .*panda_hand.*detach"):
        cc.attach_object("held", q=q)
    assert list(cc.attached_objects) == ["held"] and "held" not in cc.world
    # moving or removing it as an obstacle said "obstacle 'held' not found; available: ..."
    for edit in (lambda: cc.update_obstacle_pose("held", [0.3, 0.3, 0.3]), lambda: cc.remove_obstacle("held")):
        with pytest.raises(InvalidInputError, match=r"\('held'\): 'held' is attached to the robot \(to panda_hand\), "
                                                    r"not in the world; detach_object\(q\) it first"):
            edit()
    assert list(cc.attached_objects) == ["held"]


def test_attached_object_hits_the_arm(franka_config, franka_kinematics):
    kin = franka_kinematics
    q = franka_config.default_joint_positions
    # a long bar along the hand's y axis (across the fingers), held at the fingertips
    bar = Cuboid("bar", [0.03, 0.9, 0.03], kin.fk(q, "panda_hand") @ Pose([0.0, 0.0, 0.11]))
    cc = CollisionChecker(franka_config, kin)
    cc.attach_object(bar, q=q)
    assert not cc.in_collision(q)
    # turn the flange: the bar sweeps into the upper arm
    Q = q + np.outer(np.linspace(0, 1.5, 16), [0, 0, 0, 0, 0, 0, 1.0])
    hits = cc.in_collision_batch(Q)
    assert hits.any() and not hits[0]
    q_hit = Q[np.argmax(hits)]
    kinds = {c.kind for c in cc.collision_report(q_hit).contacts}
    assert "attached_self" in kinds


def test_world_updates(franka_config, franka_kinematics):
    cc = CollisionChecker(franka_config, franka_kinematics)
    q = franka_config.default_joint_positions
    hand = franka_kinematics.fk(q, "panda_hand").position
    assert not cc.in_collision(q)
    cc.add_obstacle(Sphere("s", 0.05, hand))
    assert cc.in_collision(q)
    cc.update_obstacle_pose("s", hand + [0, 0, 0.5])
    assert not cc.in_collision(q)
    cc.remove_obstacle("s")
    cc.set_world({"cuboid": {"b": {"dims": [0.1, 0.1, 0.1], "pose": list(hand) + [1, 0, 0, 0]}}})
    assert cc.in_collision(q) and cc.world.names == ["b"]
    with pytest.raises(UnknownNameError, match="available: b"):
        cc.remove_obstacle("s")


def test_invalid_inputs(franka_config, franka_kinematics, checker):
    with pytest.raises(InvalidInputError, match=r"\(7,\)"):
        checker.in_collision(np.zeros(6))
    with pytest.raises(InvalidInputError, match="non-finite"):
        checker.in_collision_batch(np.full((2, 7), np.nan))
    with pytest.raises(InvalidInputError, match=">= 0"):
        CollisionChecker(franka_config, franka_kinematics, padding=-0.01)
    with pytest.raises(InvalidInputError, match="resolution"):
        checker.motion_valid(np.zeros(7), np.ones(7), resolution=0.0)
    with pytest.raises(InvalidInputError, match="in_collision_batch"):
        checker.in_collision(np.zeros((2, 7)))
    with pytest.raises(InvalidInputError, match="self_padding"):
        checker.self_padding = -0.01
    q0, q1 = np.zeros(7), np.full(7, 0.1)
    for bad in (0.0, -0.01, float("nan"), "fine"):
        for check in (
            lambda: checker.motion_valid(q0, q1, resolution=bad),
            lambda: checker.first_collision(q0, q1, resolution=bad),
            lambda: checker.motion_valid_batch(q0[None], q1[None], resolution=bad),
            lambda: checker.path_valid(np.stack([q0, q1]), resolution=bad),
            lambda: CollisionChecker.segment_steps(q0, q1, resolution=bad),
        ):
            with pytest.raises(InvalidInputError, match="resolution must be a positive"):
                check()
    with pytest.raises(InvalidInputError, match="q \\(the grasp configuration\\) or pose_in_link"):
        checker.attach_object(Sphere("x", 0.01))
    with pytest.raises(UnknownNameError):
        checker.attach_object("no_such_obstacle", q=np.zeros(7))


def test_motion_valid_batch_matches_single_edges(checker, random_q):
    free = random_q[:300][~checker.in_collision_batch(random_q[:300])][:40]
    rng = np.random.default_rng(3)
    Q0 = free
    d = rng.uniform(-1, 1, Q0.shape)
    Q1 = np.clip(Q0 + 0.8 * d / np.abs(d).max(axis=1, keepdims=True), checker.kinematics.lower, checker.kinematics.upper)
    batch = checker.motion_valid_batch(Q0, Q1)
    single = np.array([checker.motion_valid(a, b) for a, b in zip(Q0, Q1)])
    np.testing.assert_array_equal(batch, single)
    assert 0 < batch.sum() < batch.size  # both kinds present
    # the definition: every configuration at <= 0.01 rad spacing is free
    for a, b, ok in zip(Q0[:15], Q1[:15], batch[:15]):
        steps = int(np.ceil(np.abs(b - a).max() / 0.01))
        dense = a + np.linspace(0, 1, steps + 1)[:, None] * (b - a)
        assert ok == (not checker.in_collision_batch(dense).any())


def test_motion_valid_catches_a_short_contact(franka_config, franka_kinematics):
    kin = franka_kinematics
    q0 = franka_config.default_joint_positions.copy()
    q1 = q0.copy()
    q1[1] += 0.6  # the shoulder swings the fingertips fast (about 0.8 m/rad)
    q_mid = (q0 + q1) / 2
    # a 4 mm pebble just beyond the left fingertip at the mid configuration: touched over a
    # few 0.01 rad steps only
    tip = (kin.fk(q_mid, "panda_hand") @ Pose([0.0, 0.0476, 0.124])).position
    cc = CollisionChecker(franka_config, kin, WorldConfig([Sphere("pebble", 0.004, tip)]))
    assert not cc.in_collision(q0) and not cc.in_collision(q1)
    steps = 60
    Q = q0 + np.linspace(0, 1, steps + 1)[:, None] * (q1 - q0)
    hits = cc.in_collision_batch(Q)
    assert 0 < hits.sum() <= 8  # the contact spans a few samples only
    assert not cc.motion_valid(q0, q1, resolution=0.01)
    assert not cc.motion_valid_batch(q0[None], q1[None])[0]


def test_first_collision_is_the_first_colliding_sample(checker, random_q):
    free = random_q[:200][~checker.in_collision_batch(random_q[:200])]
    found = 0
    for q0, q1 in zip(free[:20], free[20:40]):
        t = checker.first_collision(q0, q1)
        steps = checker.segment_steps(q0, q1)
        dense = q0 + (np.arange(steps + 1) / steps)[:, None] * (q1 - q0)
        hits = checker.in_collision_batch(dense)
        if t is None:
            assert not hits.any() and checker.motion_valid(q0, q1)
        else:
            found += 1
            k = int(round(t * steps))
            assert hits[k] and not hits[:k].any()
    assert found > 0


def test_obstacle_inside_an_attached_box_collides(franka_config, franka_kinematics):
    # coal treats primitives as solids: a pebble inside a held box touches it
    kin = franka_kinematics
    q = franka_config.default_joint_positions
    T_box = kin.fk(q, "panda_hand") @ Pose([0.0, 0.0, 0.25])
    cc = CollisionChecker(franka_config, kin)
    cc.attach_object(Cuboid("crate", [0.16, 0.16, 0.16], T_box), q=q)
    cc.add_obstacle(Sphere("pebble", 0.005, T_box.position))
    assert cc.in_collision(q) and cc.in_collision_exact(q)
    cc.remove_obstacle("pebble")
    assert not cc.in_collision(q)


def test_gripper_positions(franka_config, franka_kinematics):
    kin = franka_kinematics
    q = franka_config.default_joint_positions
    # a 4 cm wide block between the open fingertips (8 cm apart): clear when open, hit when closed
    block = Cuboid("block", [0.02, 0.04, 0.02], kin.fk(q, "panda_hand") @ Pose([0.0, 0.0, 0.1034]))
    cc = CollisionChecker(franka_config, kin, WorldConfig([block]))
    assert not cc.in_collision(q)
    cc.set_gripper_positions([0.0, 0.0])
    assert cc.in_collision(q)
    assert {c.a for c in cc.collision_report(q).contacts} <= {"panda_leftfinger", "panda_rightfinger"}
    cc.set_gripper_positions(None)
    assert not cc.in_collision(q)
    with pytest.raises(InvalidInputError, match="outside its limits"):
        cc.set_gripper_positions([0.5, 0.5])


def test_names_import_from_the_checker_module_as_before():
    """The result types live in manip.collision.results; the old import path still works."""
    import manip.collision
    from manip.collision import checker as checker_module
    from manip.collision import results

    for name in ("AttachedObject", "CollisionReport", "Contact", "DistanceReport", "PathCheck"):
        assert getattr(checker_module, name) is getattr(results, name) is getattr(manip.collision, name)
    assert checker_module.CollisionChecker is manip.collision.CollisionChecker


def test_incremental_edits_answer_like_a_rebuilt_world(franka_config, franka_kinematics, world, random_q):
    """add / remove / update_obstacle_pose change one row of the tables; the answers are
    those of a checker built from scratch with the same world, including obstacles that
    touch the fixed base (checked once per world)."""
    ck = CollisionChecker(franka_config, franka_kinematics, world)
    rng = np.random.default_rng(3)
    base_touch = Cuboid("at_base", [0.1, 0.1, 0.1], [0.0, 0.0, 0.05])
    for step in range(12):
        names = ck.world.names
        op = step % 3
        if op == 0:
            ob = base_touch if step == 3 else Sphere(f"s{step}", 0.05, rng.uniform(-0.6, 0.6, 3) + [0.3, 0, 0.3])
            ck.add_obstacle(ob)
        elif op == 1:
            ck.remove_obstacle(names[int(rng.integers(len(names)))])
        else:
            ck.update_obstacle_pose(names[int(rng.integers(len(names)))], list(rng.uniform(-0.5, 0.5, 3) + [0.4, 0, 0.4]))
        fresh = CollisionChecker(franka_config, franka_kinematics, ck.world)
        assert ck.state.always_colliding == fresh.state.always_colliding
        assert np.array_equal(ck.in_collision_batch(random_q[:200]), fresh.in_collision_batch(random_q[:200]))
    # the obstacle at the base makes every configuration collide until it is removed
    if "at_base" in ck.world:
        assert ck.in_collision_batch(random_q[:5]).all()
        ck.remove_obstacle("at_base")
    assert not ck.state.every_configuration_collides


def test_edits_keep_snapshots_unchanged(franka_config, franka_kinematics, world, random_q):
    ck = CollisionChecker(franka_config, franka_kinematics, world)
    before = ck.in_collision_batch(random_q[:100])
    snap = ck.snapshot()
    ck.remove_obstacle("table")
    ck.add_obstacle(Sphere("big", 0.3, [0.4, 0.0, 0.4]))
    ck.update_obstacle_pose("ball", [0.3, 0.0, 0.6])
    assert np.array_equal(snap.in_collision_batch(random_q[:100]), before)
    assert snap.world.names == world.names
    assert not np.array_equal(ck.in_collision_batch(random_q[:100]), before)


def test_exact_reference_leaves_the_base_on_its_floor_as_in_collision_does():
    """`in_collision_exact` is `in_collision` without the broadphase: a floor the base stands on
    (its top within 1 mm below z = 0) is not checked against the links fixed to the base in
    either (the UR5's base_link mesh reaches below z = 0), and a moving link in it collides in both."""
    from manip.kinematics import Kinematics
    from manip.robot_config import load_robot_config

    ur5 = load_robot_config("ur5")
    kin = Kinematics(ur5)
    floor = Cuboid("floor", [3.0, 3.0, 0.02], [0.0, 0.0, -0.011])
    cc = CollisionChecker(ur5, kin, WorldConfig([floor]))
    q = ur5.default_joint_positions
    assert not cc.in_collision(q)
    assert not cc.in_collision_exact(q)
    rng = np.random.default_rng(0)
    Q = rng.uniform(kin.lower, kin.upper, (60, kin.dof))
    fast = cc.in_collision_batch(Q)
    assert fast.any() and not fast.all()
    assert [cc.in_collision_exact(x) for x in Q] == fast.tolist()
