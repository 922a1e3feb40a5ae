"""`distance` / `distance_report` agree with `check_collision` where a part or an obstacle lies
wholly inside a closed mesh (no triangle touched: `collision.inside`, `Mesh(solid=True)`): such a
configuration's distance is <= 0, never a positive distance for a colliding configuration."""

from __future__ import annotations

import numpy as np
import pytest
from test_part_inside_part import FINGER_IN_LINK5, MISSED
from test_solid_meshes import box_mesh

from manip import MotionGenerator, WorldConfig
from manip.collision import Cuboid, Sphere
from manip.collision.solids import probe_points

READY = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])


@pytest.fixture(scope="module")
def mg():
    return MotionGenerator("franka")


def _frame(mg, q, part):
    """The base-frame placement (R (3, 3), p (3,)) of a part's geometry at q."""
    R, p = mg.checker.kinematics.joint_transforms(q[None])
    return R[0, part.joint] @ part.R, R[0, part.joint] @ part.p + p[0, part.joint]


def _part(mg, name):
    return next(p for p in mg.checker.state.parts if p.name == name)


def test_a_pebble_inside_a_link_has_a_negative_distance(mg):
    link5 = next(p for p in mg.checker.robot.parts if p.name == "panda_link5_0")
    V = np.asarray(link5.geometry.vertices()).reshape(-1, 3)
    frame = mg.fk(READY, "panda_link5")
    centre = frame.rotation @ (link5.R @ ((V.min(axis=0) + V.max(axis=0)) / 2) + link5.p) + frame.position
    inside = MotionGenerator("franka", WorldConfig([Sphere("pebble", 0.01, centre.tolist())]), padding=0.0)
    report = inside.checker.distance_report(READY)
    assert inside.check_collision(READY)
    assert report.distance == inside.distance(READY) == report.world_distance < -0.01   # deeper than its radius
    assert (report.closest.a, report.closest.b) == ("panda_link5", "pebble")
    assert [(c.a, c.b) for c in inside.checker.collision_report(READY).contacts] == [("panda_link5", "pebble")]
    assert inside.checker.collision_report(READY).contacts[0].distance == pytest.approx(report.distance, abs=1e-12)


def test_a_finger_inside_a_link_has_a_negative_self_distance(mg):
    for q in [FINGER_IN_LINK5, *MISSED]:
        report = mg.checker.distance_report(q)
        assert mg.check_collision(q) and report.self_distance < 0 and report.distance <= report.self_distance
        assert {report.closest.a, report.closest.b} & {"panda_leftfinger", "panda_rightfinger"}
        assert "panda_link5" in (report.closest.a, report.closest.b)


def test_a_link_inside_a_solid_mesh_box_is_as_deep_as_the_surface_is_far(mg):
    """A closed mesh box 5 mm around panda_link7 on every side: a solid, link7 collides and its
    distance is minus 5 mm (its distance to the surface); a surface, it touches no triangle and
    is free (only panda_link6 and the hand, which cross the box's faces, collide)."""
    link7 = _part(mg, "panda_link7")
    R, p = _frame(mg, READY, link7)
    X = np.asarray(link7.geometry.vertices()).reshape(-1, 3) @ R.T + p
    lo, hi = X.min(axis=0) - 0.005, X.max(axis=0) + 0.005
    for solid in (True, False):
        box = MotionGenerator("franka", WorldConfig([box_mesh("box", hi - lo, ((lo + hi) / 2).tolist(), solid)]),
                              padding=0.0)
        contacts = {c.a: c.distance for c in box.checker.collision_report(READY).contacts}
        assert box.check_collision(READY) and box.distance(READY) < 0
        assert ("panda_link7" in contacts) is solid and {"panda_link6", "panda_hand"} <= set(contacts)
        if solid:
            assert contacts["panda_link7"] == pytest.approx(-0.005, abs=1e-6)
            assert box.distance(READY) <= contacts["panda_link7"]
    cuboid = MotionGenerator("franka", WorldConfig([Cuboid("box", hi - lo, ((lo + hi) / 2).tolist())]), padding=0.0)
    assert cuboid.check_collision(READY) and cuboid.distance(READY) < -0.005


@pytest.mark.parametrize("robot", ["franka", "ur5"])
def test_no_colliding_configuration_has_a_positive_distance(robot):
    """Random configurations, each with a small obstacle (sphere, cuboid, closed mesh box as a
    surface and as a solid) or a 0.4 m solid mesh box at the centre of a random part: with no
    padding, every colliding one has a distance <= 0, the wholly-inside ones included."""
    mg = MotionGenerator(robot, padding=0.0)
    mg.checker.self_padding = 0.0
    rng = np.random.default_rng(7)
    colliding = inside = 0
    for trial in range(60):
        q = rng.uniform(mg.lower_limits, mg.upper_limits)
        parts = mg.checker.state.parts
        part = parts[rng.integers(len(parts))]
        R, p = _frame(mg, q, part)
        c = R @ probe_points(part.geometry).mean(axis=0) + p + rng.normal(scale=0.01, size=3)
        s = rng.uniform(0.004, 0.03)
        ob = [Sphere("o", s, c.tolist()), Cuboid("o", [s, s, s], c.tolist()), box_mesh("o", [s, s, s], c.tolist(), False),
              box_mesh("o", [s, s, s], c.tolist(), True), box_mesh("o", [0.4, 0.4, 0.4], c.tolist(), True)][trial % 5]
        mg.update_world(WorldConfig([ob]))
        if not mg.check_collision(q):
            continue
        colliding += 1
        found: list = []
        Rj, pj = mg.checker.kinematics.joint_transforms(q[None])
        mg.checker._parts_inside(Rj, pj, None, None, np.zeros(1, dtype=bool), found)
        inside += bool(found)
        assert mg.distance(q) <= 0.0, (trial, part.name, type(ob).__name__, mg.checker.collision_report(q))
    assert colliding > 30 and inside > 3
