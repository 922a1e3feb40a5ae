"""`simulation_app.update()` is one frame of Kit's loop: physics advances while the World
plays (issue 32, item 5)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.sim import BaseTask, DynamicCuboid, SimulationApp, World


def test_update_steps_physics_and_callbacks_while_playing():
    app = SimulationApp({"headless": True})
    world = World(physics_dt=1 / 60, rendering_dt=1 / 60)
    cube = world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 1.0], size=0.1))
    calls = []
    world.add_physics_callback("count", lambda dt: calls.append(dt))
    pre_steps = []

    class Watch(BaseTask):
        def pre_step(self, time_step_index, simulation_time):
            pre_steps.append(time_step_index)

    world.add_task(Watch("watch"))
    world.reset()
    t0 = world.current_time
    for _ in range(30):
        app.update()
    assert world.current_time - t0 == pytest.approx(0.5)
    assert len(calls) == 30 and calls[0] == pytest.approx(1 / 60)
    assert not pre_steps  # Kit's update runs physics, not the tasks' pre_step (world.step() does)
    assert cube.get_world_pose()[0][2] < 1.0 - 0.5 * 9.81 * 0.4**2  # it fell
    world.pause()
    t1 = world.current_time
    app.update()
    assert world.current_time == t1  # paused: render only
    app.close()


def test_update_takes_rendering_dt_worth_of_physics_steps():
    app = SimulationApp()
    world = World(physics_dt=1 / 120, rendering_dt=1 / 30)
    world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 1.0], size=0.1))
    world.reset()
    i0 = world.current_time_step_index
    app.update()
    assert world.current_time_step_index - i0 == 4
    np.testing.assert_allclose(world.get_physics_dt(), 1 / 120)
    app.close()
