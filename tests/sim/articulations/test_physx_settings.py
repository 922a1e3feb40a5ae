"""PhysX's per-articulation solver settings (`set_solver_position_iteration_count`, the velocity
count, `set_sleep_threshold`, `set_stabilization_threshold`) raised NotImplementedError: an
Isaac script that tunes them stopped there. They are now checked, kept for their getters and
without effect (MuJoCo's iteration cap is the World's, nothing sleeps), with a warning saying so."""

from __future__ import annotations

import logging

import mujoco
import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import ArticulationAction, Franka, World


def _run(world: World, franka: Franka, steps: int = 40) -> np.ndarray:
    world.reset()
    target = franka.get_joint_positions() + np.array([0.3, -0.2, 0.1, -0.3, 0.2, 0.3, -0.2, 0.0, 0.0])
    franka.get_articulation_controller().apply_action(ArticulationAction(joint_positions=target))
    out = []
    for _ in range(steps):
        world.step(render=False)
        out.append(franka.get_joint_positions())
    return np.array(out)


def test_articulation_solver_settings_are_kept_and_change_nothing(caplog):
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    assert franka.get_solver_position_iteration_count() == 32 and franka.get_solver_velocity_iteration_count() == 1
    assert franka.get_sleep_threshold() == 0.005 and franka.get_stabilization_threshold() == 0.001
    before = _run(world, franka)
    iterations = world.model.opt.iterations
    with caplog.at_level(logging.WARNING, logger="manip.sim.articulations.physx_settings"):
        franka.set_solver_position_iteration_count(64)
        franka.set_solver_position_iteration_count(4)   # warned once per setting
        franka.set_solver_velocity_iteration_count(8)
        franka.set_sleep_threshold(0.0)           # what manip simulates (nothing sleeps): no warning
        franka.set_sleep_threshold(0.02)
        franka.set_stabilization_threshold(0.01)
    warned = [r.getMessage() for r in caplog.records]
    assert len(warned) == 4 and "World.model.opt.iterations" in warned[0] and "nothing sleeps" in warned[2]
    franka.set_sleep_threshold(0.0)
    assert franka.get_solver_position_iteration_count() == 4 and franka.get_solver_velocity_iteration_count() == 8
    assert franka.get_sleep_threshold() == 0.0 and franka.get_stabilization_threshold() == 0.01
    after = _run(world, franka)   # the same motion, step for step: nothing changed in MuJoCo
    np.testing.assert_array_equal(after, before)
    assert world.model.opt.iterations == iterations
    assert not world.model.opt.enableflags & mujoco.mjtEnableBit.mjENBL_SLEEP   # nothing sleeps
    assert float(np.abs(after[-1] - after[0]).max()) > 0.05   # the arm moved (a motion, not a rest)


@pytest.mark.parametrize("call, value, match", [
    ("set_solver_position_iteration_count", 0, r"count must be a whole number in \[1, 255\]"),
    ("set_solver_position_iteration_count", 2.5, r"\[1, 255\]"),
    ("set_solver_velocity_iteration_count", 256, r"\[0, 255\]"),
    ("set_sleep_threshold", -1.0, "threshold must be a finite number >= 0"),
    ("set_stabilization_threshold", float("nan"), "threshold must be a finite number >= 0"),
])
def test_bad_solver_settings_raise_saying_what_is_valid(call, value, match):
    franka = World().scene.add(Franka("/World/Franka", name="franka"))
    with pytest.raises(InvalidInputError, match=match):
        getattr(franka, call)(value)
