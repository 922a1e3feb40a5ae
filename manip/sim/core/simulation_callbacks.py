"""`SimulationCallbacks`: Isaac's named-callback methods of `SimulationContext` (add, remove,
`*_exists` and `clear_*` for physics, timeline, stage and render callbacks), over one
`CallbackTable` per kind (`manip.sim.core.callbacks`).

Names follow Isaac Sim 4.x: adding a name that is taken, or removing one that does not exist,
logs an error (`carb.log_error`) and changes nothing. The stage callbacks are the stage's own
table (`Stage.callbacks`): the stage calls them when a prim is added, removed or changed.
"""

from __future__ import annotations

from collections.abc import Callable

from manip.sim.core.callbacks import CallbackTable, TimelineEvent
from manip.sim.scenes.stage import Stage, StageEvent


class SimulationCallbacks:
    """Physics, timeline, stage and render callbacks by name (a part of `SimulationContext`).

    `_init_callbacks()` creates the physics, timeline and render tables; the stage callbacks
    are `self._stage.callbacks`. The simulation calls the tables (`CallbackTable.call`).
    """

    _stage: Stage
    _physics_callbacks: CallbackTable
    _timeline_callbacks: CallbackTable
    _render_callbacks: CallbackTable

    def _init_callbacks(self) -> None:
        self._physics_callbacks = CallbackTable("physics")
        self._timeline_callbacks = CallbackTable("timeline")
        self._render_callbacks = CallbackTable("render")

    def add_physics_callback(self, callback_name: str, callback_fn: Callable[[float], None]) -> None:
        """Call `callback_fn(step_size)` before every physics step (step_size = physics_dt [s]).

        A name that is taken logs an error (`carb.log_error`, as Isaac) and keeps the
        existing callback.

        Raises:
            InvalidInputError: `callback_fn` is not callable.
        """
        self._physics_callbacks.add(callback_name, callback_fn)

    def remove_physics_callback(self, callback_name: str) -> None:
        """Remove a physics callback; an unknown name logs an error (as Isaac)."""
        self._physics_callbacks.remove(callback_name)

    def physics_callback_exists(self, callback_name: str) -> bool:
        return callback_name in self._physics_callbacks

    def clear_physics_callbacks(self) -> None:
        """Remove every physics callback."""
        self._physics_callbacks.clear()

    def add_timeline_callback(self, callback_name: str, callback_fn: Callable[[TimelineEvent], None]) -> None:
        """Call `callback_fn(event)` on play/pause/stop (`event.type`: "PLAY", "PAUSE", "STOP")."""
        self._timeline_callbacks.add(callback_name, callback_fn)

    def remove_timeline_callback(self, callback_name: str) -> None:
        self._timeline_callbacks.remove(callback_name)

    def timeline_callback_exists(self, callback_name: str) -> bool:
        return callback_name in self._timeline_callbacks

    def clear_timeline_callbacks(self) -> None:
        """Remove every timeline callback."""
        self._timeline_callbacks.clear()

    def add_stage_callback(self, callback_name: str, callback_fn: Callable[[StageEvent], None]) -> None:
        """Call `callback_fn(event)` when the stage changes (`event.type`: "PRIM_ADDED",
        "PRIM_REMOVED", "PRIM_CHANGED", "CLEARED", "COMPILED"; `event.path`)."""
        self._stage.callbacks.add(callback_name, callback_fn)

    def remove_stage_callback(self, callback_name: str) -> None:
        self._stage.callbacks.remove(callback_name)

    def stage_callback_exists(self, callback_name: str) -> bool:
        return callback_name in self._stage.callbacks

    def clear_stage_callbacks(self) -> None:
        """Remove every stage callback."""
        self._stage.callbacks.clear()

    def add_render_callback(self, callback_name: str, callback_fn: Callable[[TimelineEvent], None]) -> None:
        """Call `callback_fn(event)` after every render (`event.payload`: {"dt": rendering_dt [s]})."""
        self._render_callbacks.add(callback_name, callback_fn)

    def remove_render_callback(self, callback_name: str) -> None:
        self._render_callbacks.remove(callback_name)

    def render_callback_exists(self, callback_name: str) -> bool:
        return callback_name in self._render_callbacks

    def clear_render_callbacks(self) -> None:
        """Remove every render callback."""
        self._render_callbacks.clear()

    def clear_all_callbacks(self) -> None:
        """Remove every physics, timeline, stage and render callback."""
        for clear in (self.clear_physics_callbacks, self.clear_timeline_callbacks, self.clear_stage_callbacks,
                      self.clear_render_callbacks):
            clear()
