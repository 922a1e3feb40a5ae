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
from manip.sim import ArticulationAction, ArticulationView, Franka, World


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
    # PhysxArticulationAPI's schema defaults (round six had 0.005 and 0.001 for the thresholds)
    assert franka.get_sleep_threshold() == 5e-5 and franka.get_stabilization_threshold() == 1e-5
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


def _self_contacts(world: World) -> list[tuple[str, str]]:
    """Pairs of the Franka's bodies in contact in the current state (MuJoCo's collision pass)."""
    m, d = world.model, world.data
    mujoco.mj_forward(m, d)
    out = []
    for c in d.contact[:d.ncon]:
        a, b = m.body(m.geom_bodyid[c.geom1]).name, m.body(m.geom_bodyid[c.geom2]).name
        if a.startswith("/World/Franka/") and b.startswith("/World/Franka/"):
            out.append((a, b))
    return out


def test_self_collisions_turn_off_and_on_at_the_next_reset():
    """`set_enabled_self_collisions` raised NotImplementedError; False now excludes every pair of the
    robot's links from contact (from the next reset, as PhysX reads the flag at creation)."""
    folded = np.array([0.794, -0.812, -2.66, -3.022, 1.815, 3.424, 0.618, 0.04, 0.04])  # the hand in the base
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    assert franka.get_enabled_self_collisions() is True
    world.reset()
    franka.set_joint_positions(folded)
    hits = _self_contacts(world)
    assert ("/World/Franka/panda_link0", "/World/Franka/panda_hand") in hits   # the model's own filter
    franka.set_enabled_self_collisions(False)
    assert franka.get_enabled_self_collisions() is False and _self_contacts(world)   # not before the reset
    world.reset()
    franka.set_joint_positions(folded)
    assert _self_contacts(world) == []
    ground = world.scene.add_default_ground_plane()   # the links still collide with the rest of the world
    world.reset()
    franka.set_joint_positions(folded)
    assert ground is not None and _self_contacts(world) == []
    m, d = world.model, world.data
    robot = [(m.body(m.geom_bodyid[c.geom1]).name.startswith("/World/Franka"),
              m.body(m.geom_bodyid[c.geom2]).name.startswith("/World/Franka")) for c in d.contact[:d.ncon]]
    assert (True, False) in robot or (False, True) in robot   # a link on the ground
    view = ArticulationView("/World/Franka", name="franka_view")
    assert view.get_enabled_self_collisions().tolist() == [False]   # the view reads the robot's flag
    franka.set_enabled_self_collisions(True)
    world.reset()
    franka.set_joint_positions(folded)
    assert ("/World/Franka/panda_link0", "/World/Franka/panda_hand") in _self_contacts(world)
    assert view.get_enabled_self_collisions().tolist() == [True]
    with pytest.raises(InvalidInputError, match="flag must be a bool"):
        franka.set_enabled_self_collisions("no")
