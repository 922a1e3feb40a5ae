"""The BaseSample lifecycle (Isaac Sim extension-sample port): load, step, reset, clear.

A sample with the Franka pick-and-place task's scene: `setup_scene` adds the task,
`setup_post_load` finds its objects and adds a physics callback, `reset` restores the
default state, `clear` empties the World. The hooks are `async def`, as in Isaac's samples;
after loading, the World is paused (Isaac waits for the Play button): `world.play()`.

    python examples/sample_lifecycle.py [--steps 120] [--viewer]

Exit status 0 when the reset restored the cube and the callback ran once per physics step.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=120,
                        help="World steps of 1/60 s each before the reset (default 120).")
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's interactive viewer (needs a display).")
    args = parser.parse_args(argv)

    from manip.sim import BaseSample, PickPlace, SimulationApp, World

    class HelloSample(BaseSample):
        def __init__(self) -> None:
            super().__init__()
            self.calls = 0
            self.events: list[str] = []

        def setup_scene(self) -> None:
            self.events.append("setup_scene")
            self.get_world().add_task(PickPlace(name="pick_place"))

        async def setup_post_load(self) -> None:
            self.events.append("setup_post_load")
            world = self.get_world()
            params = world.get_task("pick_place").get_params()
            self._cube = world.scene.get_object(params["cube_name"]["value"])
            self._franka = world.scene.get_object(params["robot_name"]["value"])
            world.add_physics_callback("count_steps", self.on_physics_step)

        def on_physics_step(self, step_size: float) -> None:
            self.calls += 1
            if self.calls == 1:
                print(f"physics callback: step_size = {step_size:.5f} s")

        async def setup_pre_reset(self) -> None:
            self.events.append("setup_pre_reset")

        async def setup_post_reset(self) -> None:
            self.events.append("setup_post_reset")

        def world_cleanup(self) -> None:
            self.events.append("world_cleanup")
            self._cube = None
            self._franka = None

    app = SimulationApp({"headless": not args.viewer})
    sample = HelloSample()
    sample.load_world()
    world = sample.get_world()
    world.play()  # the Play button
    start = sample._cube.get_world_pose()[0]
    # Push the cube, then step.
    sample._cube.set_world_pose(position=start + np.array([0.0, 0.0, 0.2]))
    for _ in range(args.steps):
        if not app.is_running():
            break
        world.step(render=True)
    moved = sample._cube.get_world_pose()[0]
    print(f"after {world.current_time:.2f} s the cube is at {np.round(moved, 4)}; observations:")
    for k, v in world.get_observations().items():
        print(f"  {k}: " + ", ".join(f"{kk}={np.round(vv, 3)}" for kk, vv in v.items()))
    steps_done = world.current_time_step_index - 1  # the reset's warm-up step runs no callback
    calls = sample.calls
    sample.reset()
    restored = np.allclose(sample._cube.get_world_pose()[0], start, atol=1e-9)
    print(f"after reset: cube at {np.round(sample._cube.get_world_pose()[0], 4)}, time {world.current_time:.2f} s")
    sample.clear()
    print("lifecycle:", " -> ".join(sample.events))
    print("World after clear:", World.instance())
    app.close()
    ok = restored and calls == steps_done and World.instance() is None
    print(f"callback calls {calls} for {steps_done} physics steps; reset restored the cube: {restored}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
