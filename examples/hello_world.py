"""Hello World (Isaac Sim tutorial port): a cube dropped from 1 m falls and comes to rest.

    python examples/hello_world.py               # headless
    python examples/hello_world.py --viewer      # watch it in MuJoCo's viewer
    python examples/hello_world.py --video cube.mp4

Exit status 0 when the cube rests on the ground at z = half its edge length.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=500, help="World steps of 1/60 s each (default 500).")
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's interactive viewer (needs a display).")
    parser.add_argument("--video", metavar="PATH", help="Write an MP4 video (offscreen rendering, slower).")
    args = parser.parse_args(argv)

    from manip.sim import DynamicCuboid, SimulationApp, World

    app = SimulationApp({"headless": not args.viewer})
    world = World()
    world.scene.add_default_ground_plane()
    cube = world.scene.add(
        DynamicCuboid(
            prim_path="/World/random_cube",
            name="fancy_cube",
            position=np.array([0.0, 0.0, 1.0]),
            scale=np.array([0.5015, 0.5015, 0.5015]),
            size=1.0,
            color=np.array([0.0, 0.0, 1.0]),
        )
    )
    world.reset()
    world.set_camera_view(eye=[2.5, 2.5, 1.5], target=[0.0, 0.0, 0.3])
    if args.video:
        world.start_recording(args.video)
    for i in range(args.steps):
        if not app.is_running():
            break
        position, orientation = cube.get_world_pose()
        if i % 25 == 0:
            print(f"step {i:4d}  position {np.round(position, 4)}  orientation {np.round(orientation, 4)}  "
                  f"linear velocity {np.round(cube.get_linear_velocity(), 4)}")
        world.step(render=True)
    if args.video:
        print(f"video written to {world.stop_recording()}")
    z = cube.get_world_pose()[0][2]
    half = 0.5 * cube.get_size() * cube.get_local_scale()[2]
    app.close()
    ok = abs(z - half) < 2e-3 and np.linalg.norm(cube.get_linear_velocity()) < 1e-2
    print(f"cube rests at z = {z:.4f} m (half edge {half:.4f} m): {'ok' if ok else 'NOT at rest'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
