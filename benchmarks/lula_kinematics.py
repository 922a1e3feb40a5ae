"""Isaac's Lula kinematics interface on manip: IK success and time per call, and its cost over IKSolver.

Usage:
    python benchmarks/lula_kinematics.py [--n 500] [--seed 0]

Goals: the world poses of the Franka's `right_gripper` at uniformly random configurations
within the joint limits (reachable by construction), the robot's base placed off the origin
and turned. Three ways of asking, as scripts do: `cold` (no warm start: the default
configuration, then restarts), `tracking` (warm start 0.05 rad per joint from the answer, as a
robot following a target sends), `position` (position only, cold). Every claimed success is
checked here with manip's own FK (`Kinematics.fk` of panda_hand, 0.1 m along its z); the limits
too. `IKSolver` is the same goals given straight to `manip.ik.IKSolver` (panda_hand poses in
the base frame, the same tolerances): the ratio of the medians is the wrapper's cost.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from manip import quaternion as quat
from manip.ik import IKSolver
from manip.kinematics import Kinematics
from manip.pose import Pose
from manip.robot_config import load_robot_config
from manip.sim import LulaKinematicsSolver, interface_config_loader

HAND_TO_RIGHT_GRIPPER = Pose(np.array([0.0, 0.0, 0.1]))
T_WORLD_BASE = Pose(np.array([0.4, -0.3, 0.2]), quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), 0.8))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=500, help="Goals per mode (default 500).")
    parser.add_argument("--seed", type=int, default=0, help="Seed of the random configurations (default 0).")
    args = parser.parse_args(argv)

    cfg = load_robot_config("franka")
    kin = Kinematics(cfg)
    solver = LulaKinematicsSolver(**interface_config_loader.load_supported_lula_kinematics_solver_config("Franka"))
    solver.set_robot_base_pose(T_WORLD_BASE.position, T_WORLD_BASE.quaternion)
    ik = IKSolver(kin)
    rng = np.random.default_rng(args.seed)
    Q = rng.uniform(kin.lower, kin.upper, (args.n, 7))
    goals = [T_WORLD_BASE @ kin.fk(q, "panda_hand") @ HAND_TO_RIGHT_GRIPPER for q in Q]
    # warm up (compiled kernels, caches)
    solver.compute_inverse_kinematics("right_gripper", goals[0].position, goals[0].quaternion)
    ik.solve(kin.fk(Q[0], "panda_hand"))

    def check(q: np.ndarray, goal: Pose, position_only: bool) -> bool:
        reached = T_WORLD_BASE @ kin.fk(q, "panda_hand") @ HAND_TO_RIGHT_GRIPPER
        dp, dr = reached.distance(goal)
        inside = bool(np.all(q >= kin.lower - 1e-9) and np.all(q <= kin.upper + 1e-9))
        return inside and dp <= 1e-3 + 1e-9 and (position_only or dr <= 0.01 + 1e-9)

    rows = []
    for mode in ("cold", "tracking", "position", "IKSolver"):
        times, ok, wrong = [], 0, 0
        for q_true, goal in zip(Q, goals):
            t0 = time.perf_counter()
            if mode == "IKSolver":
                r = ik.solve(T_WORLD_BASE.inverse() @ goal @ HAND_TO_RIGHT_GRIPPER.inverse())
                q, success = np.asarray(r.q), bool(r.success)
            else:
                warm = q_true + rng.uniform(-0.05, 0.05, 7) if mode == "tracking" else None
                orientation = None if mode == "position" else goal.quaternion
                q, success = solver.compute_inverse_kinematics("right_gripper", goal.position, orientation, warm)
            times.append(time.perf_counter() - t0)
            if success:
                ok += 1
                if mode != "IKSolver":
                    wrong += not check(q, goal, mode == "position")
        t = np.array(times) * 1e3
        rows.append((mode, ok, wrong, float(np.median(t)), float(np.percentile(t, 99))))
    print(f"{'mode':10s} {'solved':>9s} {'wrong':>6s} {'median ms':>10s} {'p99 ms':>8s}")
    for mode, ok, wrong, med, p99 in rows:
        print(f"{mode:10s} {ok:4d}/{args.n:<4d} {wrong:6d} {med:10.3f} {p99:8.2f}")
    print(f"cold pose IK over IKSolver, median: {rows[0][3] / rows[3][3]:.2f} x")
    return 0 if all(r[2] == 0 for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
