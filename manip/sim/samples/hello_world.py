"""`HelloWorld`: Isaac Sim's "Hello World" example sample (`omni.isaac.examples.hello_world`).

The starting point of the Isaac tutorials: a `BaseSample` whose scene is the default ground
plane and whose hooks do nothing. Extension code that imports it
(`from omni.isaac.examples.hello_world import HelloWorld`) ports with
`from manip.sim import HelloWorld`; `HelloWorldExtension` is the extension around it (what
the example package's `__init__.py` imports).
"""

from __future__ import annotations

from manip.sim.samples.base_sample import BaseSample
from manip.sim.samples.extension import BaseSampleExtension


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


class HelloWorldExtension(BaseSampleExtension):
    """Isaac's Hello World extension (`omni.isaac.examples.hello_world.HelloWorldExtension`):
    a `BaseSampleExtension` around a `HelloWorld` sample, headless (its buttons are methods,
    see `manip.sim.samples.extension`)."""

    def on_startup(self, ext_id: str) -> None:
        super().on_startup(ext_id)
        super().start_extension(
            menu_name="",
            submenu_name="",
            name="Hello World",
            title="Hello World Example",
            doc_link="https://docs.omniverse.nvidia.com/isaacsim/latest/core_api_tutorials/tutorial_core_hello_world.html",
            overview="This Example introduces the user on how to do cool stuff with Isaac Sim through scripting in "
                     "asynchronous mode.",
            file_path=__file__,
            sample=HelloWorld(),
        )
