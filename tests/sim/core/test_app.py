"""SimulationApp: headless by default; the viewer needs a display."""

from __future__ import annotations

import logging
import os

import pytest

from manip.errors import InvalidInputError
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


def test_launch_config_refuses_a_non_bool_headless_and_warns_on_a_misspelt_key(caplog):
    # "false" is a true string: the app ran headless where the script asked for a window
    for bad in ({"headless": "false"}, {"headless": 0}, {"realtime": "no"}):
        with pytest.raises(InvalidInputError, match="must be True or False"):
            SimulationApp(bad)
    with caplog.at_level(logging.WARNING, logger="manip.sim.core.app"):
        app = SimulationApp({"headles": False, "renderer": "RayTracedLighting", "width": 640})
    assert app.headless  # the misspelt key is ignored, as Isaac ignores unknown keys, but said
    assert "'headles' is not one manip.sim reads; did you mean 'headless'?" in caplog.text
    assert "renderer" not in caplog.text and "width" not in caplog.text  # Isaac's own keys pass quietly
    app.close()
