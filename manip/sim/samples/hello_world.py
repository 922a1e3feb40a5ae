"""`HelloWorld`: Isaac Sim's "Hello World" example sample (`omni.isaac.examples.hello_world`).

The starting point of the Isaac tutorials: a `BaseSample` whose scene is the default ground
plane and whose hooks do nothing. Extension code that imports it
(`from omni.isaac.examples.hello_world import HelloWorld`) ports with
`from manip.sim import HelloWorld`.
"""

from __future__ import annotations

from manip.sim.samples.base_sample import BaseSample


class HelloWorld(BaseSample):
    """A sample with the default ground plane only (hooks are async and empty, as Isaac's)."""

    def setup_scene(self) -> None:
        self.get_world().scene.add_default_ground_plane()

    async def setup_post_load(self) -> None:
        return

    async def setup_pre_reset(self) -> None:
        return

    async def setup_post_reset(self) -> None:
        return

    def world_cleanup(self) -> None:
        return
