"""SimulationApp: headless by default; the viewer needs a display."""

from __future__ import annotations

import os

import pytest

from manip.sim import DynamicCuboid, SimulationApp, SimulationError, World


def test_headless_app_runs_and_closes():
    app = SimulationApp()
    assert app.headless and app.is_running()
    world = World()
    world.scene.add(DynamicCuboid("/World/c", name="c", size=0.1))
    world.reset()
    app.update()  # one frame of Kit's loop: the world plays after a reset, so physics advances
    assert world.current_time_step_index == 2  # the reset's warm-up step, then the frame's
    app.close()
    assert not app.is_running()


@pytest.mark.skipif(bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")), reason="has a display")
def test_viewer_without_display_says_so():
    app = SimulationApp({"headless": False})
    world = World()
    world.scene.add(DynamicCuboid("/World/c", name="c", size=0.1))
    try:
        with pytest.raises(SimulationError, match="display"):
            world.reset()
    finally:
        app.close()
