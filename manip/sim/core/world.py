"""`World`: Isaac Sim's `World` on MuJoCo: the simulation (`SimulationContext`) plus the
scene and the tasks.

One per process, as Isaac's: a second `World(...)` returns the existing instance. See
`manip.sim.core.simulation_context` for time stepping, solver options and callbacks.
"""

from __future__ import annotations

import logging

from manip.sim.core.callbacks import TimelineEvent  # noqa: F401 (re-exported)
from manip.errors import InvalidInputError
from manip.sim.core.data_logger import DataLogger
from manip.sim.core.event_loop import run_pending_coroutines
from manip.sim.scenes.scene import Scene
from manip.sim.core.simulation_context import (  # noqa: F401 (re-exported)
    DEFAULT_DT,
    SimulationContext,
    SimulationInstabilityError,
    SimulationWarning,
    WorldObserver,
)
from manip.sim.scenes.stage import get_current_stage
from manip.sim.tasks.task_registry import TaskRegistry
from manip.sim.utils.not_supported import declare as declare_not_supported

logger = logging.getLogger(__name__)


class World(SimulationContext):
    """The simulation with its scene and tasks (Isaac's `World`).

    A second `World(...)` returns the existing instance; differing arguments are ignored
    with a warning (use `set_simulation_dt`, or `World.clear_instance()` first).

    Args:
        physics_dt, rendering_dt, stage_units_in_meters, ..., substep_dt, gravity: as
            `SimulationContext` (physics_dt [s] default 1/60; substep_dt, gravity keyword-only).
    """

    def _init_components(self) -> None:
        self._scene = Scene(self)
        self._task_registry = TaskRegistry()
        self._last_pre_step_index = -1  # step index whose task pre_steps ran
        self._data_logger = DataLogger()

    def get_data_logger(self) -> DataLogger:
        """The World's `DataLogger`: started, it records one frame per `step()` (after its physics)."""
        return self._data_logger

    def _clear_components(self) -> None:
        """At `clear_instance()`: clean up the tasks."""
        self._task_registry.cleanup()

    @property
    def scene(self) -> Scene:
        return self._scene

    # ------------------------------------------------------------------ timeline and stepping
    def reset(self, soft: bool = False) -> None:
        """Isaac's `World.reset`: build task scenes (once per task), call each task's
        `cleanup()` (it removes what the task added during the episode, such as
        FollowTarget's obstacles), stop, compile the stage if it changed, play and take one
        warm-up step (see `SimulationContext.reset`), then restore every scene object's
        default state and call each task's `post_reset()`.

        Objects, referenced models and wrappers (Robot, views) may be added at any time;
        the next reset compiles and initialises them. After a reset the world is playing
        and `current_time_step_index` is 1 (with rendering_dt = physics_dt), as in Isaac.
        Physics callbacks are kept. `soft=True` (after a first reset) only restores the
        default states and calls the tasks' `post_reset()`, without restarting physics.
        """
        self._task_registry.set_up_scenes(self._scene)
        self._task_registry.cleanup()
        if soft and self._sim is None:
            logger.warning("reset(soft=True) before the first reset: doing a full reset")
        if not (soft and self._sim is not None):
            self.initialize_physics()
        self._scene.post_reset()
        self._forward()
        self._task_registry.post_reset()
        self._last_pre_step_index = -1
        self._notify("on_world_rendered")

    def initialize_physics(self) -> None:
        """Stop, compile if needed, play and take the warm-up step (no default states restored)."""
        self._task_registry.set_up_scenes(self._scene)
        super().initialize_physics()

    def stop(self) -> None:
        """Stop: time and step index go back to 0, objects and robots to the compiled initial
        state (Isaac's Stop); the next `play()` starts from there."""
        self._last_pre_step_index = -1
        super().stop()

    def step(self, render: bool = True, step_sim: bool = True, update_fabric: bool = False) -> None:
        """Run the tasks' `pre_step`, then physics (if playing): max(1, rendering_dt /
        physics_dt) physics steps with render=True, one with render=False; then render.
        `update_fabric` (Isaac 5) is accepted: poses are always read from MuJoCo.

        Physics callbacks run before each physics step with `step_size = physics_dt`.
        Coroutines a script scheduled with `asyncio.ensure_future` outside a running loop
        run first, as Kit's loop runs them each frame (`manip.sim.core.event_loop`).
        """
        run_pending_coroutines()
        self.step_async()
        super().step(render, step_sim)
        self._data_logger.log_step(self.get_current_tasks(), self._scene, self.current_time_step_index,
                                   self.current_time)

    async def reset_async_set_up_scene(self, soft: bool = False) -> None:
        """Build the task scenes that are not built yet (Isaac's first half of `reset_async`)."""
        self._task_registry.set_up_scenes(self._scene)

    async def reset_async_no_set_up_scene(self, soft: bool = False) -> None:
        """`reset()` without building task scenes first (they are built already)."""
        self.reset(soft)

    def step_async(self, step_size: float | None = None) -> None:
        """Run each task's `pre_step(step_index, time)` once for the current physics step
        (Isaac's name; what the BaseSample's "tasks_step" physics callback calls)."""
        if self._last_pre_step_index == self._index:
            return
        self._last_pre_step_index = self._index
        self._task_registry.pre_step(self._index, self._time)

    # ------------------------------------------------------------------ tasks
    def add_task(self, task) -> None:
        """Register a task; its scene is set up at the next `reset()`.

        Raises:
            InvalidInputError: a task of that name exists.
        """
        self._task_registry.add(task)

    def get_task(self, name: str):
        """The task named `name`.

        Raises:
            UnknownNameError: no such task (the message lists them).
        """
        return self._task_registry.get(name)

    def get_current_tasks(self) -> dict:
        return self._task_registry.as_dict()

    def is_tasks_scene_built(self) -> bool:
        return self._task_registry.scenes_built()

    def get_observations(self, task_name: str | None = None) -> dict:
        """One task's observations, or all tasks' merged into one dict."""
        return self._task_registry.observations(task_name)

    def calculate_metrics(self, task_name: str | None = None) -> dict:
        return self._task_registry.metrics(task_name)

    def is_done(self, task_name: str | None = None) -> bool:
        """Whether the task (or every task) is done."""
        return self._task_registry.is_done(task_name)

    def clear(self) -> None:
        """Remove every scene object (and its prim) and every task; the stage is emptied."""
        self.stop_recording()
        self._task_registry.cleanup()
        self._task_registry.clear()
        self._scene.clear(registry_only=True)
        self._unbind_all()
        self._stage.clear()
        self._compiled_version = -1
        self._data_logger = DataLogger()  # as Isaac's clear()
        self.stop()


def clear_stage(predicate=None) -> None:
    """Delete every prim of the stage (Isaac's `omni.isaac.core.utils.stage.clear_stage`).

    With a World, its scene and tasks are emptied too (`World.clear()`): their objects lived
    on the stage. Isaac leaves stale wrappers registered in that case; here they are dropped.

    Raises:
        InvalidInputError: a `predicate` (Isaac's filter of the prims to delete; delete single
            prims with `delete_prim` here).
    """
    if predicate is not None:
        raise InvalidInputError("clear_stage(predicate=...) is not supported: it clears the whole stage; delete "
                                "single prims with delete_prim(prim_path)")
    world = World.instance()
    if world is not None:
        world.clear()
    else:
        get_current_stage().clear()


declare_not_supported(SimulationContext)
