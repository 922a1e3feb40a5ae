"""Control a robot (Isaac Sim tutorial port): the Franka tracks random joint targets within
its limits (seeded), opening and closing its gripper in turn.

    python examples/control_robot.py [--targets 5] [--seed 0] [--viewer] [--video franka.mp4]

Targets are drawn uniformly in [-0.5, 0.5] rad around the ready configuration, clipped to
the joint limits. Each is reached by a smooth (cosine) ramp of the position targets over
the first half of the hold time: a step of 0.5 rad would saturate the wrist drives (12 N m)
and swing. Exit status 0 when every target is tracked to < 0.02 rad.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--targets", type=int, default=5, help="Number of random joint targets (default 5).")
    parser.add_argument("--hold", type=float, default=2.0, help="Seconds spent on each target (default 2).")
    parser.add_argument("--seed", type=int, default=0, help="Seed of the random targets (default 0).")
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's interactive viewer (needs a display).")
    parser.add_argument("--video", metavar="PATH", help="Write an MP4 video (offscreen rendering, slower).")
    args = parser.parse_args(argv)

    from manip.sim import ArticulationAction, Franka, SimulationApp, World

    app = SimulationApp({"headless": not args.viewer})
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka(prim_path="/World/Fancy_Franka", name="fancy_franka"))
    world.reset()
    world.set_camera_view(eye=[1.6, 1.2, 1.0], target=[0.2, 0.0, 0.4])
    if args.video:
        world.start_recording(args.video)
    controller = franka.get_articulation_controller()
    limits = controller.get_joint_limits()[:7]
    home = franka.get_joints_default_state().positions[:7]
    rng = np.random.default_rng(args.seed)
    steps = int(round(args.hold / world.get_physics_dt()))
    worst = 0.0
    for k in range(args.targets):
        if not app.is_running():
            break
        target = np.clip(home + rng.uniform(-0.5, 0.5, 7), limits[:, 0], limits[:, 1])
        start = franka.get_joint_positions()[:7]
        if k % 2:
            franka.gripper.open()
        else:
            franka.gripper.close()
        ramp = steps // 2
        for i in range(steps):
            s = 0.5 - 0.5 * np.cos(np.pi * min(1.0, (i + 1) / ramp))
            # None entries keep the fingers' current targets.
            controller.apply_action(ArticulationAction(joint_positions=[*(start + s * (target - start)), None, None]))
            world.step(render=True)
        error = float(np.max(np.abs(franka.get_joint_positions()[:7] - target)))
        worst = max(worst, error)
        print(f"target {k}: {np.round(target, 3)}  max error {error:.4f} rad  fingers "
              f"{np.round(franka.gripper.get_joint_positions(), 4)}")
    if args.video:
        print(f"video written to {world.stop_recording()}")
    app.close()
    print(f"worst tracking error {worst:.4f} rad")
    return 0 if worst < 0.02 else 1


if __name__ == "__main__":
    sys.exit(main())
