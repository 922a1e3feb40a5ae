"""Glue between the ported tutorial listings (tests/seeds/listings) and their tests.

The listings are the tutorials' code with only the imports changed (and headless=True).
What the tutorials do by hand in Isaac Sim's GUI, the glue does here, without touching the
listings: pressing Load / Reset / Play (`load`, `reset`, `play`), running snippets one after
another in the script editor's shared namespace (`Session`), Kit's event loop for async
snippets (`run_in_event_loop`), and watching the simulator after every render
(`Watcher`, a World observer: it reads state, and plays the user who drags a cube or
closes the window).
"""

from __future__ import annotations

import asyncio
import runpy
from pathlib import Path
from typing import Callable

from manip.sim import World

LISTINGS = Path(__file__).resolve().parent / "listings"


def listing_path(name: str) -> Path:
    return LISTINGS / name


def run_listing(name: str, run_name: str = "__main__") -> dict:
    """Run a listing file as a script (`python listing.py`); its globals afterwards."""
    return runpy.run_path(str(listing_path(name)), run_name=run_name)


class Session:
    """The script editor: snippets run one after another in one namespace."""

    def __init__(self) -> None:
        self.namespace: dict = {"__name__": "__main__"}

    def run(self, name: str) -> dict:
        path = listing_path(name)
        exec(compile(path.read_text(), str(path), "exec"), self.namespace)
        return self.namespace


def run_in_event_loop(fn: Callable[[], object]) -> object:
    """Call `fn()` inside a running asyncio loop (as Kit runs scripts) and wait for the tasks it scheduled."""

    async def kit() -> object:
        result = fn()
        pending = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
        await asyncio.gather(*pending)
        return result

    return asyncio.run(kit())


# ---------------------------------------------------------------------------- the GUI buttons
def load(sample) -> World:
    """The Load button of a BaseSample's panel; returns the World (paused, as Isaac leaves it)."""
    asyncio.run(sample.load_world_async())
    return sample.get_world()


def reset(sample) -> None:
    """The Reset button."""
    asyncio.run(sample.reset_async())


def play(world: World, steps: int) -> None:
    """The Play button, then `steps` rendered frames of Kit's update loop."""
    world.play()
    for _ in range(steps):
        world.step(render=True)


class Watcher:
    """A World observer calling `on_render(world)` after every render (and reset) while active."""

    def __init__(self, on_render: Callable[[World], None]):
        self.on_render = on_render

    def __enter__(self) -> Watcher:
        World.add_observer(self)
        return self

    def __exit__(self, *exc) -> None:
        World.remove_observer(self)

    def on_world_compiled(self, world) -> None:
        pass

    def on_world_rendered(self, world) -> None:
        if world.model is not None:
            self.on_render(world)

    def on_world_cleared(self, world) -> None:
        pass

    def on_camera_changed(self, world) -> None:
        pass
