"""`WorldObserver`: what follows every World (`SimulationContext.add_observer`); the
SimulationApp's viewer is one. The simulation imports no viewer: observers are told."""

from __future__ import annotations

from typing import Any, Protocol


class WorldObserver(Protocol):
    """Follows every World (`World.add_observer`); the SimulationApp's viewer is one.

    Each method receives the World: after it compiled a model, after it rendered (or
    reset), when it is cleared (`clear_instance`), when its camera view changed.
    """

    def on_world_compiled(self, world: Any) -> None: ...

    def on_world_rendered(self, world: Any) -> None: ...

    def on_world_cleared(self, world: Any) -> None: ...

    def on_camera_changed(self, world: Any) -> None: ...
