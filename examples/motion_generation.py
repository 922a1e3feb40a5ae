"""Motion generation with the Franka: joint and pose goals around obstacles.

Plans in a small scene (a table, a wall and a shelf board), prints each plan's status,
per-stage timings and trajectory quality, and shows what a failure looks like.

    python examples/motion_generation.py [--seed 0] [--time-budget 5] [--plot joints.png] [--viewer web]

`--plot` writes the joint position/velocity/acceleration/jerk of the four motions with the
limits drawn; `--viewer web` shows the scene and the plans in the browser ("manip-robotics[viz]").
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from manip import MotionGenerator, Pose, WorldConfig

DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # (w, x, y, z): the hand's z axis points down

WORLD = {
    "cuboid": {
        "table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0.0, -0.02, 1, 0, 0, 0]},
        "wall": {"dims": [0.3, 0.04, 0.45], "pose": [0.5, 0.0, 0.225, 1, 0, 0, 0]},
        "board": {"dims": [0.25, 0.5, 0.02], "pose": [0.75, 0.0, 0.55, 1, 0, 0, 0]},
    }
}


def describe(label: str, result) -> None:
    """One line per plan: status, timings [ms], motion time, path length, peaks."""
    stages = " ".join(f"{k}={v * 1e3:.0f}ms" for k, v in result.timings.items())
    if not result.success:
        print(f"{label:<28} {result.status.name:<14} {stages}  ({result.message})")
        return
    t = result.trajectory
    print(
        f"{label:<28} {result.status.name:<14} {stages}  motion {t.duration:.2f} s, "
        f"path {t.path_length():.2f} rad, max |acc| {t.max_abs_acceleration().max():.1f} rad/s^2, "
        f"max |jerk| {t.max_abs_jerk().max():.0f} rad/s^3"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=0, help="Seed of the planning (default 0).")
    parser.add_argument("--time-budget", type=float, default=5.0, help="Time budget of each plan [s] (default 5).")
    parser.add_argument("--plot", type=Path, default=None, metavar="PNG",
                        help="Write joint plots with the limits drawn to this PNG file.")
    parser.add_argument("--viewer", choices=("web",), default=None,
                        help="Show the plans in the browser (pip install \"manip-robotics[viz]\"), served until "
                             "Ctrl-C.")
    parser.add_argument("--port", type=int, default=8080,
                        help="The port --viewer web serves (default 8080; the next free one if taken).")
    args = parser.parse_args(argv)

    mg = MotionGenerator("franka", WorldConfig.from_dict(WORLD), seed=args.seed, time_budget=args.time_budget)
    ready = mg.default_joint_positions
    print(f"world: {', '.join(mg.world.names)}")

    left = Pose([0.45, 0.3, 0.25], DOWN)
    right = Pose([0.45, -0.3, 0.25], DOWN)
    r1 = mg.plan_pose(ready, left)
    describe("ready -> left of the wall", r1)
    if not r1.success:
        return 1
    r2 = mg.plan_pose(r1.goal_q, right)
    describe("left -> right (over the wall)", r2)
    if not r2.success:
        return 1
    print(f"  reached within {r2.position_error * 1e3:.2f} mm, {np.degrees(r2.rotation_error):.3f} deg")
    down = Pose(mg.fk(r2.goal_q).position - [0.0, 0.0, 0.1], DOWN)
    r3 = mg.plan_pose(r2.goal_q, down, linear=True)
    describe("straight down 10 cm", r3)
    r4 = mg.plan_joints(r3.goal_q if r3.success else r2.goal_q, ready)
    describe("back to ready (joint goal)", r4)
    slow = mg.plan_joints(r3.goal_q if r3.success else r2.goal_q, ready, velocity_scale=0.3, acceleration_scale=0.3)
    describe("same at 30 % speed", slow)
    inside = mg.plan_pose(ready, Pose([0.5, 0.0, 0.2], DOWN))
    describe("goal inside the wall", inside)
    ok = all(r.success for r in (r1, r2, r3, r4, slow)) and not inside.success
    motions = [r.trajectory for r in (r1, r2, r3, r4) if r.success]
    if args.plot is not None:
        from manip.viz.plots import plot_joint_trajectory, robot_limits

        plot_joint_trajectory(motions, args.plot, limits=robot_limits(mg), title="ready -> left -> right -> down -> ready")
        print(f"plot written to {args.plot}")
    if args.viewer == "web":
        from manip.viz import Viewer

        viewer = Viewer(mg, port=args.port)
        viewer.show_plan(r2)  # over the wall; drag the gizmo to plan to another pose
        print(f"open {viewer.url} (over SSH: ssh -L {viewer.port}:localhost:{viewer.port} HOST); Ctrl-C to quit")
        viewer.wait()
        viewer.close()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
