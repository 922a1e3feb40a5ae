"""Forward kinematics of the Franka: the ready configuration and a batch, at a few links.

    python examples/forward_kinematics.py
    python examples/forward_kinematics.py --batch 8 --links panda_link4 panda_hand panda_hand_tcp

Every pose is in the robot's base frame (panda_link0): position [m] and quaternion (w, x, y, z),
manip's order everywhere (ROS's (x, y, z, w) converts with `Pose.from_xyz_xyzw` / `to_xyz_xyzw`).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from manip import MotionGenerator, Pose


def fmt(pose: Pose) -> str:
    p = np.array2string(pose.position, precision=4, suppress_small=True, separator=", ")
    q = np.array2string(pose.quaternion, precision=4, suppress_small=True, separator=", ")
    return f"position {p} m, quaternion (w, x, y, z) {q}"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robot", default="franka",
                        help="A shipped robot's name or the folder of a robot.yaml (default franka).")
    parser.add_argument("--links", nargs="+", default=["panda_link4", "panda_hand", "panda_hand_tcp"],
                        help="Links (any frames of the URDF) whose poses are printed.")
    parser.add_argument("--batch", type=int, default=5,
                        help="Number of random configurations evaluated at once (default 5).")
    parser.add_argument("--seed", type=int, default=0, help="Seed of the random configurations (default 0).")
    args = parser.parse_args(argv)

    mg = MotionGenerator(args.robot)
    q = mg.default_joint_positions
    print(f"joints: {mg.joint_names}")
    print(f"ready configuration [rad]: {np.array2string(q, precision=3, separator=', ')}")
    for link in args.links:
        print(f"  {link:>16}: {fmt(mg.fk(q, link))}")
    print(f"  {'default link':>16}: {mg.ee_link} -> {fmt(mg.fk(q))}")

    # A batch: (N, 7) configurations give a batched Pose (positions (N, 3), quaternions (N, 4)).
    rng = np.random.default_rng(args.seed)
    Q = rng.uniform(mg.lower_limits, mg.upper_limits, (args.batch, len(mg.joint_names)))
    for link in args.links:
        poses = mg.fk(Q, link)
        print(f"\n{link}: batch of {len(poses)}, one [x, y, z, qw, qx, qy, qz] per row "
              "(position [m], quaternion (w, x, y, z)):")
        print(np.array2string(poses.to_xyz_wxyz(), precision=4, suppress_small=True, separator=", "))
        # the batch agrees with one-at-a-time evaluation
        for i in range(len(poses)):
            if not poses[i].isclose(mg.fk(Q[i], link), position_tol=1e-9, rotation_tol=1e-6):
                print(f"batched and single FK disagree at row {i}", file=sys.stderr)
                return 1

    n = 100_000
    Q = rng.uniform(mg.lower_limits, mg.upper_limits, (n, len(mg.joint_names)))
    t = time.perf_counter()
    mg.fk(Q)
    elapsed = time.perf_counter() - t
    print(f"\nbatched FK of {n:,} configurations to Poses: {elapsed * 1e3:.0f} ms ({n / elapsed:,.0f} /s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
