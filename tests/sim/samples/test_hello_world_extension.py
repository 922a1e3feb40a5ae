"""The Hello World sample package's names, and coroutines scheduled outside a running loop
(issue 32, item 9)."""

from __future__ import annotations

import asyncio
import warnings


from manip.sim import DynamicCuboid, HelloWorld, HelloWorldExtension, SimulationApp, World


def test_the_hello_world_extension_loads_and_resets_its_sample():
    ext = HelloWorldExtension()
    ext.on_startup("omni.isaac.examples.hello_world")
    assert isinstance(ext.sample, HelloWorld)
    assert ext.get_buttons()["Load World"].enabled and not ext.get_buttons()["Reset"].enabled
    ext.load_world()
    world = ext.get_world()
    assert world.scene.get_object("default_ground_plane") is not None
    assert ext.get_buttons()["Reset"].enabled
    world.play()
    for _ in range(10):
        world.step(render=False)
    ext.reset()
    assert world.current_time_step_index == 1
    ext.on_shutdown()


def _new_idle_loop() -> asyncio.AbstractEventLoop:
    loop = asyncio.new_event_loop()
    asyncio.set_event_loop(loop)
    return loop


def test_ensure_future_at_top_level_runs_at_the_next_world_step():
    loop = _new_idle_loop()
    try:
        world = World()
        cube = world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 1.0], size=0.1))
        world.reset()
        world.pause()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            asyncio.ensure_future(world.play_async())  # Kit would run it at its next frame
        assert not world.is_playing()
        world.step(render=False)  # the frame: the coroutine runs, then physics (now playing)
        assert world.is_playing()
        z0 = cube.get_world_pose()[0][2]
        world.step(render=False)
        assert cube.get_world_pose()[0][2] < z0
    finally:
        asyncio.set_event_loop(None)
        loop.close()


def test_ensure_future_runs_at_the_next_app_update():
    loop = _new_idle_loop()
    try:
        app = SimulationApp()
        world = World()
        world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 1.0], size=0.1))
        world.reset()
        done = []

        async def user_coroutine():
            await world.pause_async()
            done.append(world.current_time)

        asyncio.ensure_future(user_coroutine())
        app.update()
        assert done and not world.is_playing()
        app.close()
    finally:
        asyncio.set_event_loop(None)
        loop.close()


def test_inside_a_running_loop_the_loop_runs_its_tasks_itself():
    async def kit():
        world = World()
        world.scene.add(DynamicCuboid("/World/c", name="c", size=0.1))
        world.reset()
        task = asyncio.ensure_future(world.pause_async())
        world.step(render=False)  # must not try to run the running loop
        await task
        return world.is_playing()

    assert asyncio.run(kit()) is False
