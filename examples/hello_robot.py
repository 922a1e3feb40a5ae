"""Hello Robot (Isaac Sim tutorial port): the Jetbot with random wheel velocities sent
through its articulation controller from a physics callback.

    python examples/hello_robot.py [--steps 300] [--seed 0] [--viewer]

Exit status 0 when the robot moved.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=300, help="World steps of 1/60 s each (default 300).")
    parser.add_argument("--seed", type=int, default=0, help="Seed of the random wheel velocities (default 0).")
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's interactive viewer (needs a display).")
    args = parser.parse_args(argv)

    from manip.sim import ArticulationAction, Robot, SimulationApp, World, add_reference_to_stage, get_assets_root_path

    app = SimulationApp({"headless": not args.viewer})
    world = World()
    world.scene.add_default_ground_plane()
    add_reference_to_stage(usd_path=get_assets_root_path() + "/jetbot/jetbot.xml", prim_path="/World/Fancy_Robot")
    jetbot = world.scene.add(Robot(prim_path="/World/Fancy_Robot", name="fancy_robot"))
    print("num of DoF before the first reset:", jetbot.num_dof)  # None, as in Isaac
    world.reset()
    print("num of DoF after the first reset:", jetbot.num_dof)
    print("joint positions after the first reset:", jetbot.get_joint_positions())
    controller = jetbot.get_articulation_controller()
    controller.switch_control_mode("velocity")
    rng = np.random.default_rng(args.seed)

    def send_robot_actions(step_size: float) -> None:
        controller.apply_action(ArticulationAction(joint_positions=None, joint_efforts=None,
                                                   joint_velocities=5 * rng.random((2,))))

    world.add_physics_callback("sending_actions", callback_fn=send_robot_actions)
    world.set_camera_view(eye=[1.0, 1.0, 0.8], target=[0.2, 0.0, 0.0])
    start = jetbot.get_world_pose()[0]
    for i in range(args.steps):
        if not app.is_running():
            break
        world.step(render=True)
        if i % 50 == 0:
            print(f"step {i:4d}  base {np.round(jetbot.get_world_pose()[0], 3)}  "
                  f"wheel velocities {np.round(jetbot.get_joint_velocities(), 2)}")
    moved = float(np.linalg.norm(jetbot.get_world_pose()[0][:2] - start[:2]))
    app.close()
    print(f"the Jetbot moved {moved:.3f} m")
    return 0 if moved > 0.05 else 1


if __name__ == "__main__":
    sys.exit(main())
