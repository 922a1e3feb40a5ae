"""`CollisionChecker.allowing` (a view where given contacts are allowed, and only those) and
`CollisionChecker.fork` (an editable copy that leaves the original alone)."""

from __future__ import annotations

import numpy as np
import pytest

from manip import Cuboid, MotionGenerator, Pose, UnknownNameError

FINGERS = ("panda_leftfinger", "panda_rightfinger")


@pytest.fixture(scope="module")
def setup():
    mg = MotionGenerator("franka")
    q = mg.default_joint_positions
    tcp = mg.fk(q, "panda_hand_tcp")
    # a 1 cm block at one fingertip (the fingers are open 4 cm each side of the TCP)
    mg.add_obstacle(Cuboid("block", [0.01, 0.01, 0.01], Pose(tcp.position + 0.04 * tcp.rotation[:, 1])))
    return mg, q


def test_only_the_allowed_pairs_are_skipped(setup):
    mg, q = setup
    checker = mg.checker
    assert checker.in_collision(q)
    assert {c.a for c in checker.collision_report(q).contacts} <= set(FINGERS)
    view = checker.allowing([(f, "block") for f in FINGERS])
    assert not view.in_collision(q)
    assert checker.in_collision(q)  # the checker itself is unchanged
    # a contact of another link with the block still counts
    palm = mg.fk(q, "panda_hand").position
    mg.add_obstacle(Cuboid("palm_block", [0.03, 0.03, 0.03], Pose(palm)))  # the palm in a second block
    try:
        view = mg.checker.allowing([(f, "block") for f in FINGERS])
        assert view.in_collision(q)
        assert any(c.b == "palm_block" for c in view.collision_report(q).contacts)
    finally:
        mg.remove_obstacle("palm_block")


def test_the_certificate_of_a_view_skips_the_allowed_pairs(setup):
    mg, q = setup
    q1 = q.copy()
    q1[6] += 0.3  # turn the hand about its axis: the finger stays at the block
    path = np.stack([q, q1])
    assert not mg.checker.certify_path(path).certified
    view = mg.checker.allowing([(f, "block") for f in FINGERS])
    assert view.certify_path(path).certified


def test_unknown_names_are_refused(setup):
    mg, _ = setup
    with pytest.raises(UnknownNameError, match="panda_thumb"):
        mg.checker.allowing([("panda_thumb", "block")])
    with pytest.raises(UnknownNameError, match="brick"):
        mg.checker.allowing([("panda_leftfinger", "brick")])


def test_a_fork_is_edited_alone(setup):
    mg, q = setup
    fork = mg.checker.fork()
    fork.remove_obstacle("block")
    fork.attach_object(Cuboid("parcel", [0.05, 0.05, 0.05], Pose([0.5, 0.0, 0.3])), q=q)
    assert "block" in mg.world and "block" not in fork.world
    assert not mg.checker.attached_objects and "parcel" in fork.attached_objects
    assert not fork.in_collision(q) or fork.collision_report(q).contacts[0].b != "block"
