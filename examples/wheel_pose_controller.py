"""WheelBasePoseController (Isaac Sim tutorial port): the Jetbot drives itself to [0.8, 0.8].

    python examples/wheel_pose_controller.py [--steps 1200] [--viewer]

Exit status 0 when the Jetbot stops within position_tol (0.04 m) of the goal.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=1200,
                        help="Largest number of world steps of 1/60 s each (default 1200).")
    parser.add_argument("--goal", type=float, nargs=2, default=[0.8, 0.8], metavar=("X", "Y"),
                        help="The goal position of the Jetbot [m] (default 0.8 0.8).")
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's interactive viewer (needs a display).")
    args = parser.parse_args(argv)

    from manip.sim import (DifferentialController, SimulationApp, WheelBasePoseController, WheeledRobot, World,
                           get_assets_root_path)

    app = SimulationApp({"headless": not args.viewer})
    world = World()
    world.scene.add_default_ground_plane()
    jetbot = world.scene.add(
        WheeledRobot(prim_path="/World/Fancy_Robot", name="fancy_robot",
                     wheel_dof_names=["left_wheel_joint", "right_wheel_joint"], create_robot=True,
                     usd_path=get_assets_root_path() + "/jetbot/jetbot.xml")
    )
    world.reset()
    controller = WheelBasePoseController(
        name="cool_controller",
        open_loop_wheel_controller=DifferentialController(name="simple_control", wheel_radius=0.03, wheel_base=0.1125),
        is_holonomic=False,
    )
    goal = np.array(args.goal)
    position_tol = 0.04

    def send_robot_actions(step_size: float) -> None:
        position, orientation = jetbot.get_world_pose()
        jetbot.apply_wheel_actions(controller.forward(start_position=position, start_orientation=orientation,
                                                      goal_position=goal, position_tol=position_tol))

    world.add_physics_callback("sending_actions", send_robot_actions)
    world.set_camera_view(eye=[0.4, -1.0, 1.6], target=[0.4, 0.4, 0.0])
    for i in range(args.steps):
        if not app.is_running():
            break
        world.step(render=True)
        position = jetbot.get_world_pose()[0]
        if i % 60 == 0:
            print(f"t {world.current_time:5.2f} s  base {np.round(position[:2], 3)}  "
                  f"distance to goal {np.linalg.norm(position[:2] - goal):.3f} m")
        if np.linalg.norm(position[:2] - goal) < position_tol and np.all(np.abs(jetbot.get_wheel_velocities()) < 0.5):
            break
    distance = float(np.linalg.norm(jetbot.get_world_pose()[0][:2] - goal))
    t = world.current_time
    app.close()
    print(f"stopped {distance:.3f} m from the goal after {t:.2f} s")
    return 0 if distance < position_tol else 1


if __name__ == "__main__":
    sys.exit(main())
