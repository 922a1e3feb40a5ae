"""Inverse kinematics of the Franka: one goal, a batch, and an unreachable goal.

    python examples/inverse_kinematics.py
    python examples/inverse_kinematics.py --batch 500 --seed 3

Goals are poses of the end-effector link (panda_hand) in the base frame. A failure is a
result with `success=False` and a `status` saying why, never an exception; the exit status
is non-zero only if a reachable goal was not solved or the unreachable one was "solved".
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from manip import MotionGenerator, Pose


def show(name: str, r) -> None:
    q = np.array2string(r.q, precision=3, suppress_small=True, separator=", ")
    print(
        f"{name}: success={r.success} status={r.status.name} q={q}\n"
        f"    error {r.position_error * 1e3:.4f} mm / {np.degrees(r.rotation_error):.5f} deg, "
        f"{r.attempts} attempt(s), {r.iterations} iterations, {r.solve_time * 1e3:.2f} ms"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robot", default="franka",
                        help="A shipped robot's name or the folder of a robot.yaml (default franka).")
    parser.add_argument("--batch", type=int, default=200,
                        help="Number of random reachable goals solved as one batch (default 200).")
    parser.add_argument("--seed", type=int, default=0,
                        help="Seed of the random goals and of the IK restarts (default 0).")
    args = parser.parse_args(argv)

    mg = MotionGenerator(args.robot, seed=args.seed)
    ok = True

    # 1. One goal: 10 cm forward and 10 cm down from the ready pose, same orientation.
    ready = mg.fk(mg.default_joint_positions)
    goal = Pose(ready.position + np.array([0.10, 0.0, -0.10]), ready.quaternion)
    r = mg.ik(goal)  # seeded at the default configuration; the solution is the nearest found
    show("single goal", r)
    ok &= bool(r.success)

    # The same goal from a seed: the solution nearest the seed.
    r2 = mg.ik(goal, seed_q=r.q + 0.05)
    show("same goal, seeded near the first answer", r2)
    ok &= bool(r2.success) and bool(np.allclose(r2.q, r.q, atol=1e-2))

    # 2. A batch: the poses of random configurations within the limits (all reachable).
    rng = np.random.default_rng(args.seed)
    Q = rng.uniform(mg.lower_limits, mg.upper_limits, (args.batch, len(mg.joint_names)))
    goals = mg.fk(Q)
    b = mg.batch_ik(goals)
    print(
        f"\nbatch of {len(goals)}: {int(b.success.sum())} solved in {b.solve_time * 1e3:.0f} ms "
        f"({b.success.sum() / b.solve_time:,.0f} solutions/s); worst errors "
        f"{b.position_error.max() * 1e3:.4f} mm / {np.degrees(b.rotation_error.max()):.5f} deg"
    )
    ok &= bool(b.success.all())

    # 3. Unreachable: 2 m in front of the robot. Reported, not raised.
    far = Pose(np.array([2.0, 0.0, 0.5]), ready.quaternion)
    r3 = mg.ik(far)
    show("\nunreachable goal", r3)
    print(f"    why: {r3.status.hint}")
    ok &= not r3.success

    print("\nall as expected" if ok else "\nUNEXPECTED RESULT", file=sys.stdout if ok else sys.stderr)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
