"""`SimulationApp`: headless by default, MuJoCo's interactive viewer, or the browser.

`SimulationApp({"headless": False})` opens `mujoco.viewer.launch_passive` on the World's
model when it is compiled (and reopens it when a reset recompiles a changed stage); every
render of the World (`world.step(render=True)`, `world.render()`, `app.update()`) syncs
it, paced to real time. Headless runs need no display.

`SimulationApp({"headless": False, "viewer": "web"})` serves the World in the browser
instead (viser, `pip install "manip-robotics[viz]"`; no display needed): the bodies' poses are
streamed at each render, at most `web_rate` (30) times per second of wall time, to
http://localhost:`web_port` (8080; the next free port if taken, see `viewer_url`). The
web viewer is created lazily: importing `manip.sim` never imports viser.

The app observes the World (`World.add_observer`, see `WorldObserver`); the World never
imports the app.
"""

from __future__ import annotations

import atexit
import difflib
import logging
import threading
import time
from typing import Any

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.core.event_loop import run_pending_coroutines
from manip.sim.core.gl_backend import has_display
from manip.sim.core.simulation_context import SimulationContext
from manip.sim.scenes.stage import SimulationError
from manip.sim.core.world import World
from manip.sim.utils.not_supported import declare as declare_not_supported

logger = logging.getLogger(__name__)

_APP: SimulationApp | None = None

DEFAULT_CONFIG = {"headless": True, "width": 1280, "height": 720, "realtime": True, "viewer": "native",
                  "web_host": "127.0.0.1", "web_port": 8080, "web_rate": 30.0}
VIEWERS = ("native", "web")
#: How long closing the app waits for MuJoCo's viewer thread to end [s].
VIEWER_JOIN_TIMEOUT = 10.0
_EXIT_HOOK_REGISTERED = False


def _close_viewers_at_exit() -> None:
    """Close the app's viewer (joining its thread) at interpreter exit, before glfw's own
    atexit `terminate` (registered earlier, when mujoco.viewer imported glfw; atexit runs
    handlers last-in first-out). A script that never calls `simulation_app.close()` then
    exits cleanly too."""
    global _EXIT_HOOK_REGISTERED
    if not _EXIT_HOOK_REGISTERED:
        atexit.register(_close_at_exit)
        _EXIT_HOOK_REGISTERED = True


def _close_at_exit() -> None:
    if _APP is not None:
        _APP.close()


class SimulationApp:
    """The application (Isaac's `SimulationApp`).

    Args:
        launch_config: {"headless": bool (default True), "realtime": bool (default True,
            pace the viewer to real time), "viewer": "native" (MuJoCo's window, default) or
            "web" (the browser; with "web_host" (default "127.0.0.1"), "web_port" (8080)
            and "web_rate" [Hz] (30), the most poses streamed per second)}; other Isaac
            keys (width, height, renderer, ...) are accepted and ignored.

    Raises:
        InvalidInputError: launch_config is not a dict, "headless" or "realtime" is not a
            bool, "viewer" is not one of VIEWERS, or it is "web" with "headless" True. A key
            close to one manip reads ("headles") logs a warning.
        experience: ignored (Isaac's .kit file).
    """

    def __init__(self, launch_config: dict | None = None, experience: str = ""):
        global _APP
        cfg = dict(DEFAULT_CONFIG)
        if launch_config is not None:
            if not isinstance(launch_config, dict):
                raise InvalidInputError(f"launch_config must be a dict; got {type(launch_config).__name__}")
            for key in launch_config:
                near = difflib.get_close_matches(str(key), [k for k in DEFAULT_CONFIG if k != key], n=1, cutoff=0.8)
                if key not in DEFAULT_CONFIG and near:
                    logger.warning("launch_config key %r is not one manip.sim reads; did you mean %r? (ignored, "
                                   "as Isaac ignores keys it does not know)", key, near[0])
            cfg.update(launch_config)
        for key in ("headless", "realtime"):
            if not isinstance(cfg[key], (bool, np.bool_)):
                raise InvalidInputError(f"launch_config[{key!r}] must be True or False; got {cfg[key]!r}")
        if cfg["viewer"] not in VIEWERS:
            raise InvalidInputError(f"launch_config['viewer'] must be one of {', '.join(VIEWERS)}; got {cfg['viewer']!r}")
        self.config = cfg
        self.headless = bool(cfg["headless"])
        self.web = cfg["viewer"] == "web"
        if self.web and self.headless:
            raise InvalidInputError('launch_config: viewer "web" shows the World in a browser; set "headless": False with it')
        self._viewer: Any = None
        self._viewer_threads: list[threading.Thread] = []
        self._web_server: Any = None  # viser server, created with the first web view
        self._viewer_model = None
        self._closed = False
        self._last_sync = None
        if _APP is not None:
            World.remove_observer(_APP)  # only the latest app follows the World
        _APP = self
        World.add_observer(self)
        w = World.instance()
        if w is not None and w.model is not None:
            self._open_viewer(w)

    @property
    def app(self) -> SimulationApp:
        return self

    @property
    def viewer_url(self) -> str | None:
        """The web viewer's address on this machine (None until it is serving)."""
        if self._web_server is None:
            return None
        return f"http://localhost:{self._web_server.get_port()}"

    def is_running(self) -> bool:
        """False once closed, or once the viewer window was closed by the user."""
        if self._closed:
            return False
        if self._viewer is not None and not self.web:
            return bool(self._viewer.is_running())
        return True

    def is_exiting(self) -> bool:
        return not self.is_running()

    def update(self) -> None:
        """One frame of Kit's update loop: while the World is playing, the physics of one
        rendered frame (max(1, rendering_dt / physics_dt) physics steps, each after the
        physics callbacks; the tasks' `pre_step` is not run, as in Isaac, where only
        `world.step()` runs it); then the render (viewer sync). Paused or stopped: render only.
        Coroutines scheduled with `asyncio.ensure_future` outside a running loop run here
        (`manip.sim.core.event_loop`), as Kit's loop runs them each frame."""
        run_pending_coroutines()
        w = World.instance()
        if w is not None and w.model is not None:
            SimulationContext.step(w, render=True)

    def close(self, wait_for_replicator: bool = True) -> None:
        """Close the viewer (if any; waits for its thread to end, at most
        VIEWER_JOIN_TIMEOUT) and the World's recording."""
        global _APP
        w = World.instance()
        if w is not None:
            w.stop_recording()
        self._close_viewer()
        if self._web_server is not None:
            self._web_server.stop()
            self._web_server = None
        self._closed = True
        World.remove_observer(self)
        if _APP is self:
            _APP = None

    def set_setting(self, setting: str, value) -> None:
        self.config[setting] = value

    # ------------------------------------------------------------------ World events (WorldObserver)
    def on_world_compiled(self, world: SimulationContext) -> None:
        """Open (or reopen, on the new model) the viewer unless headless."""
        if not self.headless:
            self._open_viewer(world)

    def on_world_rendered(self, world: SimulationContext) -> None:
        if self._viewer is not None:
            self._sync(world)

    def on_world_cleared(self, world: SimulationContext) -> None:
        self._close_viewer()

    def on_camera_changed(self, world: SimulationContext) -> None:
        if self._viewer is not None and not self.web:
            world.get_camera_view().apply(self._viewer.cam)

    # ------------------------------------------------------------------ viewer
    def _open_viewer(self, world: SimulationContext) -> None:
        if self.headless or self._closed:
            return
        self._close_viewer()
        if self.web:
            self._open_web_viewer(world)
            return
        if not has_display():
            # MuJoCo's viewer aborts the process when GLFW cannot open a window: check first.
            raise SimulationError(
                "cannot open the MuJoCo viewer: no display (DISPLAY/WAYLAND_DISPLAY unset). Watch it in the browser "
                "instead: SimulationApp({'headless': False, 'viewer': 'web'}) (needs pip install \"manip-robotics[viz]\"; "
                "in examples/pick_and_place.py, follow_target.py and motion_generation.py: `--viewer web`), or run "
                "headless (the default) or record a video."
            )
        try:
            import mujoco.viewer

            before = set(threading.enumerate())
            self._viewer = mujoco.viewer.launch_passive(world.model, world.data,
                                                        show_left_ui=False, show_right_ui=False)
            # The viewer's thread (MuJoCo keeps no handle on it): joined when the viewer closes.
            self._viewer_threads = [t for t in threading.enumerate() if t not in before]
            _close_viewers_at_exit()
        except Exception as exc:
            raise SimulationError(
                f"cannot open the MuJoCo viewer ({exc}); it needs a display (DISPLAY/WAYLAND_DISPLAY). On machines "
                "without one, watch it in the browser: SimulationApp({'headless': False, 'viewer': 'web'}) (in the "
                "examples: `--viewer web`), or run headless (SimulationApp({'headless': True}), the default)."
            ) from exc
        self._viewer_model = world.model
        world.get_camera_view().apply(self._viewer.cam)

    def _open_web_viewer(self, world: SimulationContext) -> None:
        """Stream the World to the browser (viser imported here, on first use only)."""
        try:
            from manip.viz.server import start_server
            from manip.viz.sim_stream import SimStream
        except ImportError as exc:
            raise SimulationError(
                f"the web viewer needs viser ({exc}): pip install \"manip-robotics[viz]\"; or run headless"
            ) from exc
        if self._web_server is None:
            self._web_server = start_server(self.config["web_host"], self.config["web_port"], grid=False)
        self._viewer = SimStream(self._web_server, world.model, max_rate=self.config["web_rate"])
        self._viewer_model = world.model
        world.physics_sim_view.ensure_kinematics()
        self._viewer.push(world.data, force=True)

    def _close_viewer(self) -> None:
        if self._viewer is not None and self.web:
            self._viewer.remove()
        elif self._viewer is not None:
            try:
                self._viewer.close()
            except Exception:  # already closed by the user
                pass
            # Wait for the viewer's thread to leave its render loop: glfw's atexit `terminate`
            # running while that thread still draws crashes the process (SIGSEGV, or a
            # GLXBadDrawable hang) after the script's results.
            for t in self._viewer_threads:
                if t is not threading.current_thread():
                    t.join(timeout=VIEWER_JOIN_TIMEOUT)
                    if t.is_alive():
                        logger.warning("the MuJoCo viewer's thread did not end within %.0f s", VIEWER_JOIN_TIMEOUT)
            self._viewer_threads = []
        self._viewer = None
        self._viewer_model = None

    def _sync(self, world: SimulationContext) -> None:
        if self._viewer is None:
            return
        if world.model is not self._viewer_model:
            self._open_viewer(world)
        if self.web:
            if self._viewer.due():  # the stream's rate limit: no kinematics between frames
                world.physics_sim_view.ensure_kinematics()
                self._viewer.push(world.data)
        elif not self._viewer.is_running():
            return
        else:
            world.physics_sim_view.ensure_kinematics()
            self._viewer.sync()
        if self.config.get("realtime", True):
            now = time.perf_counter()
            if self._last_sync is not None:
                wait = world.get_rendering_dt() - (now - self._last_sync)
                if wait > 0:
                    time.sleep(wait)
            self._last_sync = time.perf_counter()


def get_app() -> SimulationApp | None:
    """The running SimulationApp, if any."""
    return _APP


declare_not_supported(SimulationApp)
