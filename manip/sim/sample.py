"""`BaseSample`: the lifecycle of Isaac Sim's example extensions, as plain methods.

Subclasses override `setup_scene()` (add objects/tasks to `self.get_world()`),
`setup_post_load()`, `setup_pre_reset()`, `setup_post_reset()`, `world_cleanup()`.
Isaac's methods are async because of its GUI; here they are plain, with `*_async` aliases.
"""

from __future__ import annotations

from manip.sim.stage import create_new_stage
from manip.sim.world import World


class BaseSample:
    """Base of a sample: `load_world()`, `reset()`, `clear()`.

    Args:
        world_settings: World arguments (default physics_dt = rendering_dt = 1/60,
            stage_units_in_meters = 1).
    """

    def __init__(self, world_settings: dict | None = None):
        self._world: World | None = None
        self._current_tasks = None
        self._world_settings = {"physics_dt": 1.0 / 60.0, "stage_units_in_meters": 1.0, "rendering_dt": 1.0 / 60.0}
        if world_settings:
            self._world_settings.update(world_settings)

    def get_world(self) -> World | None:
        return self._world

    def set_world_settings(self, physics_dt: float | None = None, stage_units_in_meters: float | None = None,
                           rendering_dt: float | None = None) -> None:
        for k, v in (("physics_dt", physics_dt), ("stage_units_in_meters", stage_units_in_meters),
                     ("rendering_dt", rendering_dt)):
            if v is not None:
                self._world_settings[k] = v

    def load_world(self) -> None:
        """Create the World on a new stage, `setup_scene()`, reset, `setup_post_load()`;
        if there are tasks, register the "tasks_step" physics callback that runs their pre_step."""
        World.clear_instance()
        create_new_stage()
        self._world = World(**self._world_settings)
        self.setup_scene()
        self._world_cleanup()
        self._world.reset()
        self._world.pause()
        self.setup_post_load()
        self._world.play()
        if self._world.get_current_tasks():
            self._world.add_physics_callback("tasks_step", self._world.step_async)

    def reset(self) -> None:
        """`setup_pre_reset()`, World reset, `setup_post_reset()`."""
        self.setup_pre_reset()
        self._world.reset()
        self.setup_post_reset()

    def clear(self) -> None:
        """Stop, remove callbacks, `world_cleanup()`, forget the World and empty the stage."""
        if self._world is not None:
            self._world_cleanup()
            World.clear_instance()
            self._world = None
        create_new_stage()

    def _world_cleanup(self) -> None:
        self._world.stop()
        self._world.clear_all_callbacks()
        self._current_tasks = None
        self.world_cleanup()

    async def load_world_async(self) -> None:
        self.load_world()

    async def reset_async(self) -> None:
        self.reset()

    async def clear_async(self) -> None:
        self.clear()

    # hooks
    def setup_scene(self) -> None:
        """Add the sample's objects and tasks (the World exists)."""

    def setup_post_load(self) -> None:
        """After the first reset: find objects, add callbacks."""

    def setup_pre_reset(self) -> None:
        """Before a reset."""

    def setup_post_reset(self) -> None:
        """After a reset."""

    def world_cleanup(self) -> None:
        """Drop references to scene objects (called on load and clear)."""
