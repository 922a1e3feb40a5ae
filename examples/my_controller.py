"""A custom controller (Isaac Sim tutorial port): a unicycle BaseController drives the
Jetbot at [0.5 m/s, pi/4 rad/s].

    python examples/my_controller.py [--steps 300] [--viewer]

Exit status 0 when the Jetbot turned counter-clockwise while driving forward.
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=300, help="World steps of 1/60 s each (default 300).")
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's interactive viewer (needs a display).")
    args = parser.parse_args(argv)

    from manip.sim import (ArticulationAction, BaseController, SimulationApp, WheeledRobot, World,
                           get_assets_root_path, quat_to_euler_angles)

    class CoolController(BaseController):
        """Open-loop unicycle model: [v, w] -> wheel velocities of a differential drive."""

        def __init__(self) -> None:
            super().__init__(name="my_cool_controller")
            self._wheel_radius = 0.03
            self._wheel_base = 0.1125

        def forward(self, command) -> ArticulationAction:
            v, w = command
            left = (2 * v - w * self._wheel_base) / (2 * self._wheel_radius)
            right = (2 * v + w * self._wheel_base) / (2 * self._wheel_radius)
            return ArticulationAction(joint_velocities=[left, right])

    app = SimulationApp({"headless": not args.viewer})
    world = World()
    world.scene.add_default_ground_plane()
    jetbot = world.scene.add(
        WheeledRobot(prim_path="/World/Fancy_Robot", name="fancy_robot",
                     wheel_dof_names=["left_wheel_joint", "right_wheel_joint"], create_robot=True,
                     usd_path=get_assets_root_path() + "/jetbot/jetbot.xml")
    )
    world.reset()
    controller = CoolController()
    world.add_physics_callback(
        "sending_actions", lambda step_size: jetbot.apply_wheel_actions(controller.forward([0.5, math.pi / 4]))
    )
    world.set_camera_view(eye=[0.0, -1.5, 2.0], target=[0.0, 0.5, 0.0])
    yaw_unwrapped, last_yaw = 0.0, 0.0
    for i in range(args.steps):
        if not app.is_running():
            break
        world.step(render=True)
        yaw = quat_to_euler_angles(jetbot.get_world_pose()[1])[2]
        yaw_unwrapped += (yaw - last_yaw + math.pi) % (2 * math.pi) - math.pi
        last_yaw = yaw
        if i % 50 == 0:
            print(f"step {i:4d}  base {np.round(jetbot.get_world_pose()[0][:2], 3)}  yaw {yaw:+.3f} rad")
    t = world.current_time
    app.close()
    print(f"after {t:.2f} s: turned {yaw_unwrapped:.3f} rad (commanded {math.pi / 4 * t:.3f})")
    return 0 if yaw_unwrapped > 0.5 * math.pi / 4 * t else 1


if __name__ == "__main__":
    sys.exit(main())
