"""The simulation in the browser: `SimulationApp({"headless": False, "viewer": "web"})`."""

from __future__ import annotations

import subprocess
import sys
import time

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, Franka, SimulationApp, World


pytestmark = pytest.mark.usefixtures("fresh_world")  # tests/conftest.py


def test_importing_manip_sim_does_not_import_viser():
    code = "import sys, manip.sim; assert 'viser' not in sys.modules and 'manip.viz' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)


def test_bad_viewer_settings_are_refused():
    with pytest.raises(InvalidInputError, match="native, web"):
        SimulationApp({"headless": False, "viewer": "browser"})
    with pytest.raises(InvalidInputError, match="headless"):
        SimulationApp({"viewer": "web"})  # headless by default


def test_world_bodies_stream_to_the_browser(port, monkeypatch):
    pytest.importorskip("viser", reason="the web viewer needs the viz extra: pip install 'manip-robotics[viz]'")
    rate = 50.0
    app = SimulationApp({"headless": False, "viewer": "web", "web_port": port, "web_rate": rate, "realtime": False})
    try:
        world = World()
        world.scene.add_default_ground_plane()
        world.scene.add(Franka("/World/Franka", name="franka"))
        cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.3], size=0.05))
        assert app.viewer_url is None  # nothing served before the World is compiled
        world.reset()
        assert app.viewer_url is not None and app.is_running()
        scene = app._web_server.scene
        cube_frame = scene.get_handle_by_name("/sim/_World_cube")
        hand = scene.get_handle_by_name("/sim/_World_Franka_panda_hand")
        assert cube_frame is not None and hand is not None
        # the moving links' meshes (link1-7 and the hand), children of their body frames (the
        # base, welded to the world, is drawn once under /sim/static)
        mesh_nodes = [n for n in app._viewer.node_names
                      if ("_panda_link" in n or "_panda_hand/" in n) and n.count("/") == 3]
        assert len(mesh_nodes) >= 8
        for _ in range(30):  # the cube falls 0.3 m
            world.step(render=True)
        time.sleep(1.0 / rate)  # the next render is due
        world.render()
        p, _ = cube.get_world_pose()
        assert p[2] < 0.1
        # the stream re-sends a body only once it moved more than SEND_TOLERANCE since its last
        # frame (the settling cube's last micrometres may not be sent)
        from manip.viz.sim_stream import SEND_TOLERANCE

        np.testing.assert_allclose(cube_frame.position, p, rtol=0.0, atol=SEND_TOLERANCE)
        pushes = app._viewer.pushes
        from manip.viz import sim_stream

        frozen = sim_stream.clock()  # 20 steps within one 1/50 s of the stream's clock, however loaded the machine
        monkeypatch.setattr(sim_stream, "clock", lambda: frozen)
        for _ in range(20):  # faster than 50 Hz: the stream is rate-limited
            world.step(render=True)
        assert app._viewer.pushes - pushes <= 1
    finally:
        app.close()
    assert not app.is_running() and app.viewer_url is None
