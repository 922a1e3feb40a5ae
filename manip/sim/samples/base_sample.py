"""`BaseSample`: the lifecycle of Isaac Sim's example extensions (`omni.isaac.examples.base_sample`).

Subclasses override `setup_scene()` (add objects/tasks to `self.get_world()`),
`setup_post_load()`, `setup_pre_reset()`, `setup_post_reset()`, `setup_post_clear()`,
`world_cleanup()`. Isaac's samples write the `setup_*` hooks as `async def`; here a hook may
be `async def` (it is awaited) or a plain method (it is called), in Isaac's order:

- `load_world_async()`: if no World exists: a new stage, `World(**world_settings)`,
  `initialize_simulation_context_async()`, `setup_scene()`; else the existing World is used
  and `setup_scene()` is not called (as Isaac; a warning says so). Then `reset_async()`,
  `pause_async()`, `setup_post_load()`, and if there are tasks the "tasks_step" physics
  callback (`world.step_async`, the tasks' pre_step).
- `reset_async()`: remove "tasks_step", play, `setup_pre_reset()`, World `reset_async()`,
  pause, `setup_post_reset()`, add "tasks_step" back.
- `clear_async()`: a new stage; stop the World, remove its callbacks, `world_cleanup()`,
  forget the World; `setup_post_clear()`.

After loading or resetting, the World is paused, as in Isaac (where the user then presses
Play): call `world.play()` before stepping. The synchronous `load_world()`, `reset()` and
`clear()` run the async versions to completion (`asyncio.run`); inside a running event
loop, await the `*_async` methods instead.
"""

from __future__ import annotations

import asyncio
import gc
import inspect
import logging
from typing import Any, Awaitable, Callable

from manip.sim.scenes.stage import SimulationError, create_new_stage_async, update_stage_async
from manip.sim.core.world import World

logger = logging.getLogger(__name__)


async def run_hook(hook: Callable[[], Any]) -> Any:
    """Call `hook()` and await its result if it is awaitable (an `async def` hook)."""
    result = hook()
    if inspect.isawaitable(result):
        result = await result
    return result


def run_sync(coro: Awaitable, what: str) -> Any:
    """Run `coro` to completion with `asyncio.run`.

    Raises:
        SimulationError: an event loop is running in this thread (await `what` instead).
    """
    try:
        asyncio.get_running_loop()
    except RuntimeError:
        return asyncio.run(coro)
    if inspect.iscoroutine(coro):
        coro.close()
    raise SimulationError(f"an asyncio event loop is running: use `await {what}` instead")


class BaseSample:
    """Base of a sample: `load_world_async()`, `reset_async()`, `clear_async()` (and their
    synchronous forms `load_world()`, `reset()`, `clear()`).

    Args:
        world_settings: World arguments (default physics_dt = rendering_dt = 1/60 s,
            stage_units_in_meters = 1); Isaac's BaseSample takes none (use
            `set_world_settings`).
    """

    def __init__(self, world_settings: dict | None = None) -> None:
        self._world: World | None = None
        self._current_tasks = None
        self._world_settings = {"physics_dt": 1.0 / 60.0, "stage_units_in_meters": 1.0, "rendering_dt": 1.0 / 60.0}
        if world_settings:
            self._world_settings.update(world_settings)

    def get_world(self) -> World | None:
        return self._world

    def set_world_settings(self, physics_dt: float | None = None, stage_units_in_meters: float | None = None,
                           rendering_dt: float | None = None) -> None:
        """World arguments used by the next `load_world_async()` that creates the World."""
        for k, v in (("physics_dt", physics_dt), ("stage_units_in_meters", stage_units_in_meters),
                     ("rendering_dt", rendering_dt)):
            if v is not None:
                self._world_settings[k] = v

    # ------------------------------------------------------------------ the buttons
    async def load_world_async(self) -> None:
        """The Load button (see the module docstring for the order of the calls)."""
        if World.instance() is None:
            await create_new_stage_async()
            self._world = World(**self._world_settings)
            await self._world.initialize_simulation_context_async()
            await run_hook(self.setup_scene)
        else:
            self._world = World.instance()
            logger.warning("load_world: a World exists already; it is used as is and setup_scene() is not called "
                           "(as in Isaac). Call World.clear_instance() first for a fresh world.")
        self._current_tasks = self._world.get_current_tasks()
        await self._world.reset_async()
        await self._world.pause_async()
        await run_hook(self.setup_post_load)
        if len(self._current_tasks) > 0:
            self._world.add_physics_callback("tasks_step", self._world.step_async)

    async def reset_async(self) -> None:
        """The Reset button: `setup_pre_reset()`, World reset, `setup_post_reset()`; paused after.

        Raises:
            SimulationError: the world is not loaded.
        """
        world = self._need_world("reset")
        has_tasks = world.is_tasks_scene_built() and len(self._current_tasks or {}) > 0
        if has_tasks:
            world.remove_physics_callback("tasks_step")
        await world.play_async()
        await update_stage_async()
        await run_hook(self.setup_pre_reset)
        await world.reset_async()
        await world.pause_async()
        await run_hook(self.setup_post_reset)
        if has_tasks:
            world.add_physics_callback("tasks_step", world.step_async)

    async def clear_async(self) -> None:
        """The Clear button: a new stage, the World cleaned up and forgotten, `setup_post_clear()`."""
        await create_new_stage_async()
        if self._world is not None:
            self.release_world()
            self._world.clear_instance()
            self._world = None
            gc.collect()
        await run_hook(self.setup_post_clear)

    def load_world(self) -> None:
        """`load_world_async()`, run to completion."""
        run_sync(self.load_world_async(), "sample.load_world_async()")

    def reset(self) -> None:
        """`reset_async()`, run to completion."""
        run_sync(self.reset_async(), "sample.reset_async()")

    def clear(self) -> None:
        """`clear_async()`, run to completion."""
        run_sync(self.clear_async(), "sample.clear_async()")

    def _need_world(self, what: str) -> World:
        if self._world is None:
            raise SimulationError(f"{what}: the sample's world is not loaded; call load_world() (the Load button) first")
        return self._world

    def release_world(self) -> None:
        """Stop the World, drop its callbacks and tasks, then run the `world_cleanup` hook
        (the extension calls this on shutdown and when the stage is cleared)."""
        self._world.stop()
        self._world.clear_all_callbacks()
        self._current_tasks = None
        self.world_cleanup()

    _world_cleanup = release_world  # Isaac's name (its extension calls it)

    # ------------------------------------------------------------------ hooks (sync or async)
    def setup_scene(self) -> None:
        """Add the sample's objects and tasks (the World exists)."""

    def setup_post_load(self) -> None:
        """After the first reset: find objects, add callbacks."""

    def setup_pre_reset(self) -> None:
        """Before a reset (remove a physics callback, reset a controller...)."""

    def setup_post_reset(self) -> None:
        """After a reset (which includes one warm-up step)."""

    def setup_post_clear(self) -> None:
        """After the Clear button (or a new stage) dropped the World and its callbacks."""

    def world_cleanup(self) -> None:
        """Drop references to scene objects (called on clear and on extension shutdown)."""
