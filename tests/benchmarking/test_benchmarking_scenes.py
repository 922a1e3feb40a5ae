"""Seeded scenes: deterministic, valid starts and goals, goals inside the structures."""

from __future__ import annotations

import numpy as np
import pytest

from manip.benchmarking.scenes import SCENE_KINDS, make_problems
from manip.benchmarking.verify import default_verifier
from manip.errors import InvalidInputError


@pytest.mark.parametrize("kind", SCENE_KINDS)
def test_problems_are_valid_deterministic_and_prefix_stable(kind):
    a = make_problems(kind, 4, seed=7)
    b = make_problems(kind, 2, seed=7)
    v = default_verifier()
    for p in a:
        assert p.scene == f"seeded_{kind}"
        r = v.check_problem(p)
        assert r.valid, (p.name, r.reasons)
        assert np.abs(p.start - p.goal).max() >= 0.3
        assert set(p.world) <= {"cuboid", "cylinder"}  # what every peer can read
    for p, q in zip(a, b):
        assert p.world == q.world
        np.testing.assert_array_equal(p.start, q.start)
        np.testing.assert_array_equal(p.goal, q.goal)
    c = make_problems(kind, 2, seed=8)
    assert c[0].world != a[0].world


def test_most_problems_need_more_than_a_straight_line():
    v = default_verifier()
    obstructed = total = 0
    for kind in SCENE_KINDS:
        for p in make_problems(kind, 4, seed=0):
            Q = v.densify(np.array([0.0, 1.0]), np.stack([p.start, p.goal]))[1]
            obstructed += v.first_collision(Q, p.world) is not None
            total += 1
    assert obstructed >= total // 2


def test_shelf_goals_reach_into_the_shelf(franka_kinematics):
    # One end of every shelf problem has the fingertips behind the shelf's front face,
    # between two boards and between the side walls.
    for p in make_problems("shelf", 4, seed=1):
        b0 = p.world["cuboid"]["board0"]
        depth, width = b0["dims"][0], b0["dims"][1]
        w, _, _, z = b0["pose"][3:]
        yaw = 2 * np.arctan2(z, w)
        into = np.array([np.cos(yaw), np.sin(yaw)])
        side = np.array([-np.sin(yaw), np.cos(yaw)])
        centre = np.asarray(b0["pose"][:2])
        heights = sorted(o["pose"][2] for n, o in p.world["cuboid"].items() if n.startswith("board"))
        inside = []
        for q in (p.start, p.goal):
            tcp = franka_kinematics.fk(q, "panda_hand_tcp").position
            d = tcp[:2] - centre
            inside.append(
                abs(d @ into) < depth / 2 and abs(d @ side) < width / 2 and heights[0] < tcp[2] < heights[-1]
            )
        assert any(inside), p.name


def test_bad_arguments():
    with pytest.raises(InvalidInputError, match="table"):
        make_problems("kitchen", 1)
    with pytest.raises(InvalidInputError):
        make_problems("table", -1)
    assert make_problems("box", 0) == []
