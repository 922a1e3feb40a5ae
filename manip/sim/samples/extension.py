"""`BaseSampleExtension`: a headless stand-in for Isaac's example extension (its UI panel).

Isaac's `BaseSampleExtension` is an `omni.ext.IExt` that builds a window with Load and
Reset buttons around a `BaseSample`. manip has no Kit UI: the window is not drawn, and the
buttons are methods: `load_world()` (= clicking Load, Isaac's `_on_load_world`),
`reset()` (= Reset, `_on_reset`) and `clear()`. Each runs the sample's coroutine to
completion (or schedules it with `asyncio.ensure_future` inside a running event loop, as
Isaac does) and then calls the `post_*_button_event()` hook. The button states are kept in
`get_buttons()` ("Load World" enabled until loaded, then "Reset").

Typical headless use of an Isaac extension class written against this base::

    ext = HelloWorldExtension()
    ext.on_startup("my.ext.id")       # Kit calls this when the extension is enabled
    ext.load_world()                  # the Load button
    world = ext.get_world(); world.play()
    for _ in range(100):
        world.step(render=False)
    ext.reset()                       # the Reset button
    ext.on_shutdown()
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any, Awaitable, Callable

from manip.errors import InvalidInputError
from manip.sim.core.callbacks import TimelineEvent
from manip.sim.samples.base_sample import BaseSample, run_sync
from manip.sim.scenes.stage import SimulationError, StageEvent
from manip.sim.core.world import World

logger = logging.getLogger(__name__)


class Button:
    """A UI button's state: `enabled`, `text`, `tooltip`; `click()` calls its function if enabled."""

    def __init__(self, text: str, on_clicked_fn: Callable[[], Any], enabled: bool = True, tooltip: str = ""):
        self.text = text
        self.enabled = enabled
        self.tooltip = tooltip
        self._fn = on_clicked_fn

    def set_tooltip(self, tooltip: str) -> None:
        self.tooltip = tooltip

    def click(self) -> Any:
        """Press the button: call its function (nothing happens, with a warning, if disabled)."""
        if not self.enabled:
            logger.warning("button %r is disabled", self.text)
            return None
        return self._fn()

    def __repr__(self) -> str:
        return f"Button({self.text!r}, enabled={self.enabled})"


class Frame:
    """An extra UI frame of the panel (not drawn here): a `title`, `visible`, `collapsed`."""

    def __init__(self) -> None:
        self.title = ""
        self.visible = False
        self.collapsed = False


def _run(coro: Awaitable, what: str) -> Any:
    """Run `coro` to completion; inside a running loop, schedule it (Isaac's ensure_future)."""
    try:
        asyncio.get_running_loop()
    except RuntimeError:
        return run_sync(coro, what)
    return asyncio.ensure_future(coro)


class BaseSampleExtension:
    """The example extension around a `BaseSample`, headless (see the module docstring)."""

    def __init__(self) -> None:
        self._ext_id: str | None = None
        self._sample: BaseSample | None = None
        self._buttons: dict[str, Button] | None = None
        self._menu_items = None
        self._extra_frames: list[Frame] = []
        self._window = None

    # ------------------------------------------------------------------ Kit lifecycle
    def on_startup(self, ext_id: str) -> None:
        """Called when the extension starts (Kit passes its id)."""
        self._menu_items = None
        self._buttons = None
        self._ext_id = ext_id
        self._sample = None
        self._extra_frames = []

    def start_extension(self, menu_name: str, submenu_name: str, name: str, title: str, doc_link: str,
                        overview: str, file_path: str, sample: BaseSample | None = None,
                        number_of_extra_frames: int = 1, window_width: int = 350,
                        keep_window_open: bool = False) -> None:
        """Set up the panel around `sample` (a new `BaseSample()` if None): the Load World
        button enabled, Reset disabled, `number_of_extra_frames` extra frames. The menu
        entry and window are not drawn (headless)."""
        if sample is not None and not isinstance(sample, BaseSample):
            raise InvalidInputError(f"sample must be a BaseSample; got {type(sample).__name__}")
        self._sample = sample if sample is not None else BaseSample()
        self._name = name
        self._title = title
        self._doc_link = doc_link
        self._overview = overview
        self._file_path = file_path
        self._menu_items = [menu_name, submenu_name, name]
        self._extra_frames = [Frame() for _ in range(int(number_of_extra_frames))]
        self._buttons = {
            "Load World": Button("Load", self._on_load_world, enabled=True, tooltip="Load World and Task"),
            "Reset": Button("Reset", self._on_reset, enabled=False, tooltip="Reset robot and environment"),
        }

    def on_shutdown(self) -> None:
        """Called when the extension stops: the sample's world is cleaned up (not cleared)."""
        self._extra_frames = []
        if self._sample is not None and self._sample.get_world() is not None:
            self._sample.release_world()
        self._menu_items = None
        if self._buttons is not None:
            self._buttons["Load World"].enabled = True
            self._enable_all_buttons(False)
        self._buttons = None
        self.shutdown_cleanup()

    # ------------------------------------------------------------------ accessors
    @property
    def sample(self) -> BaseSample | None:
        return self._sample

    def get_world(self) -> World | None:
        return World.instance()

    def get_buttons(self) -> dict[str, Button]:
        return self._buttons if self._buttons is not None else {}

    def get_frame(self, index: int) -> Frame:
        if index >= len(self._extra_frames):
            raise InvalidInputError(f"there were {len(self._extra_frames)} extra frames created only")
        return self._extra_frames[index]

    # ------------------------------------------------------------------ the buttons, as methods
    def load_world(self) -> Any:
        """Click Load World."""
        return self._on_load_world()

    def reset(self) -> Any:
        """Click Reset."""
        return self._on_reset()

    def clear(self) -> Any:
        """Clear the sample's world (Isaac's Clear: a new stage)."""
        return self._on_clear()

    def _need_started(self) -> BaseSample:
        if self._sample is None or self._buttons is None:
            raise SimulationError("the extension is not started: call on_startup(ext_id) (which calls start_extension)")
        return self._sample

    def _on_load_world(self) -> Any:
        sample = self._need_started()

        async def _on_load_world_async() -> None:
            await sample.load_world_async()
            sample.get_world().add_stage_callback("stage_event_1", self.on_stage_event)
            self._enable_all_buttons(True)
            self._buttons["Load World"].enabled = False
            self.post_load_button_event()
            sample.get_world().add_timeline_callback("stop_reset_event", self._reset_on_stop_event)

        return _run(_on_load_world_async(), "the Load button's coroutine")

    def _on_reset(self) -> Any:
        sample = self._need_started()

        async def _on_reset_async() -> None:
            await sample.reset_async()
            self.post_reset_button_event()

        return _run(_on_reset_async(), "the Reset button's coroutine")

    def _on_clear(self) -> Any:
        sample = self._need_started()

        async def _on_clear_async() -> None:
            await sample.clear_async()
            if self._buttons is not None:
                self._enable_all_buttons(False)
                self._buttons["Load World"].enabled = True
            self.post_clear_button_event()

        return _run(_on_clear_async(), "the Clear button's coroutine")

    def _enable_all_buttons(self, flag: bool) -> None:
        for button in (self._buttons or {}).values():
            button.enabled = flag

    def _set_button_tooltip(self, button_name: str, tool_tip: str) -> None:
        self._buttons[button_name].set_tooltip(tool_tip)

    # ------------------------------------------------------------------ events
    def on_stage_event(self, event: StageEvent) -> None:
        """A cleared stage (Isaac: closed) ends the World: clean it up, Load enabled again."""
        if event.type == "CLEARED" and World.instance() is not None and self._sample is not None \
                and self._sample.get_world() is not None:
            self._sample.release_world()
            self._sample.get_world().clear_instance()
            if self._buttons is not None:
                self._enable_all_buttons(False)
                self._buttons["Load World"].enabled = True

    def _reset_on_stop_event(self, e: TimelineEvent) -> None:
        if e.type == "STOP" and self._buttons is not None:
            self._buttons["Load World"].enabled = False
            self._buttons["Reset"].enabled = True
            self.post_clear_button_event()

    # ------------------------------------------------------------------ hooks
    def post_reset_button_event(self) -> None:
        """After the Reset button's work."""

    def post_load_button_event(self) -> None:
        """After the Load button's work."""

    def post_clear_button_event(self) -> None:
        """After a Clear (or a stop of the timeline)."""

    def shutdown_cleanup(self) -> None:
        """Extra cleanup at shutdown."""
