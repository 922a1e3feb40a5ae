"""`RigidPrim.set_sleep_threshold` / `RigidPrimView.set_sleep_thresholds` (and the getters) raised
NotImplementedError: an Isaac script that disables sleeping (threshold 0, common before reading
contacts) stopped there. They are now checked against PhysX's range, kept for the getters
(PhysxRigidBodyAPI's default 5e-05 m^2/s^2 until set) and without effect, warned once: nothing
sleeps in manip.sim, so a resting cube still moves when pushed, whatever the threshold."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, RigidPrimView, World


def _cubes():
    world = World()
    cubes = [world.scene.add(DynamicCuboid(f"/World/Cube_{i}", name=f"cube{i}", position=[0.5, 0.2 * i, 0.05],
                                           size=0.1)) for i in range(2)]
    view = world.scene.add(RigidPrimView("/World/Cube_.*", name="cubes"))
    world.reset()
    return world, cubes, view


def test_rigid_prim_sleep_threshold_is_kept_warned_once_and_nothing_sleeps(caplog):
    world, cubes, _ = _cubes()
    assert cubes[0].get_sleep_threshold() == 5e-5
    with caplog.at_level(logging.WARNING, logger="manip.sim.prims.sleep"):
        cubes[0].set_sleep_threshold(0.0)          # what manip simulates: no warning
        cubes[0].set_sleep_threshold(10.0)         # would put the resting cube to sleep in PhysX
        cubes[0].set_sleep_threshold(20.0)         # warned once per prim
    assert [r.getMessage() for r in caplog.records if "nothing sleeps" in r.getMessage()] and len(caplog.records) == 1
    assert cubes[0].get_sleep_threshold() == 20.0 and cubes[1].get_sleep_threshold() == 5e-5
    for _ in range(60):                            # the cube settles on the ground (at rest)
        world.step(render=False)
    x0 = cubes[0].get_world_pose()[0][0]
    cubes[0].set_linear_velocity(np.array([0.5, 0.0, 0.0]))
    for _ in range(10):
        world.step(render=False)
    assert cubes[0].get_world_pose()[0][0] > x0 + 0.01    # awake: it moves


def test_rigid_prim_view_sleep_thresholds_per_index(caplog):
    _, _, view = _cubes()
    np.testing.assert_array_equal(view.get_sleep_thresholds(), [5e-5, 5e-5])
    with caplog.at_level(logging.WARNING, logger="manip.sim.prims.sleep"):
        view.set_sleep_thresholds(np.zeros(2))
        assert not caplog.records
        view.set_sleep_thresholds([0.5], indices=[1])
    assert len(caplog.records) == 1
    np.testing.assert_array_equal(view.get_sleep_thresholds(), [0.0, 0.5])
    np.testing.assert_array_equal(view.get_sleep_thresholds(indices=[1]), [0.5])


@pytest.mark.parametrize("call, value, match", [
    ("prim", -1.0, "threshold must be a finite number >= 0"),
    ("prim", float("nan"), "threshold must be a finite number >= 0"),
    ("prim", True, "threshold must be a finite number >= 0"),
    ("view", [0.1, -0.1], r"thresholds must be finite numbers >= 0 .*\[-0.1\]"),
    ("view", [0.1, 0.2, 0.3], "thresholds must be 2 values"),
])
def test_bad_sleep_thresholds_say_what_is_valid(call, value, match):
    _, cubes, view = _cubes()
    with pytest.raises(InvalidInputError, match=match):
        cubes[0].set_sleep_threshold(value) if call == "prim" else view.set_sleep_thresholds(value)
    assert cubes[0].get_sleep_threshold() == 5e-5 and view.get_sleep_thresholds().tolist() == [5e-5, 5e-5]
