"""`CollisionChecker.state`: one state of the checker's tables, read-only, unchanged by later edits."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from manip.collision import CollisionChecker, Cuboid, Sphere, WorldConfig
from robot_constants import FRANKA_READY

READY = np.array(FRANKA_READY)


def test_a_state_keeps_its_world_while_the_checker_is_edited(franka_config, franka_kinematics):
    ck = CollisionChecker(franka_config, franka_kinematics, WorldConfig())
    before = ck.state
    assert before.obstacles == () and not before.every_configuration_collides
    with pytest.raises(dataclasses.FrozenInstanceError):
        before.padding = 1.0  # type: ignore[misc]
    ck.add_obstacle(Sphere("ball", 0.05, [0.5, 0.0, 0.5]))
    after = ck.state
    assert [o.name for o in after.obstacles] == ["ball"] and before.obstacles == ()
    snap = ck.snapshot()
    assert snap.state is snap.state  # a snapshot builds its state once


def test_the_state_answers_the_questions_of_certify_clearance_and_validity(franka_config, franka_kinematics):
    ck = CollisionChecker(franka_config, franka_kinematics, WorldConfig())
    far = READY.copy()
    state = ck.state
    np.testing.assert_array_equal(state.collides(np.stack([READY, far])), ck.in_collision_batch(np.stack([READY, far])))
    R, p = state.joint_transforms(READY[None])
    assert R.shape == (1, franka_kinematics.model.njoints, 3, 3) and p.shape == (1, franka_kinematics.model.njoints, 3)
    q1 = READY + 0.3
    assert state.motion_free(READY, q1, 0.01) == ck.motion_valid(READY, q1, 0.01)
    np.testing.assert_array_equal(state.segments_free(READY[None], q1[None], 0.01),
                                  ck.motion_valid_batch(READY[None], q1[None], 0.01))
    t, steps = state.advance(READY, q1, 0.01)
    assert t == ck.first_collision(READY, q1, 0.01) and steps == ck.segment_steps(READY, q1, 0.01)


def test_an_obstacle_on_the_fixed_base_makes_every_configuration_collide(franka_config, franka_kinematics):
    ck = CollisionChecker(franka_config, franka_kinematics, WorldConfig())
    ck.add_obstacle(Cuboid("at_base", [0.1, 0.1, 0.1], [0.0, 0.0, 0.05]))
    state = ck.state
    assert state.every_configuration_collides
    g, o = state.always_colliding[0]
    assert state.obstacles[o].name == "at_base" and state.parts[g].joint == 0
    assert state.collides(np.stack([READY, READY + 0.5])).all()
    cert = ck.certify_path(np.stack([READY, READY + 0.1]))
    assert not cert.certified and cert.reason == "collision" and cert.pair[1] == "at_base"
