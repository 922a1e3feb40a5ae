"""The reactive controller on random reachable targets: how often it gets there, and how it fails.

    python benchmarks/reactive_reach.py --n 30 --seed 6100 [--robots franka ur5 ur10 kinova xarm7]

Each target is the controlled frame's pose (position and orientation) at a random configuration
within the joint limits whose frame is 5 cm or more above the ground plane and whose links are
safety_margin (1 cm) or more apart (a pose the arm can take); the arm starts at its
default joint positions, with no obstacles (self-collision avoidance on). One run is up to 10 s of
60 Hz steps (it goes on after a STALLED report, to count false alarms); reached = position error
< 5 mm and orientation error < 0.02 rad. Prints per arm: reached (and of those, reached after a
STALLED report), not reached (and of those, reported STALLED, and when), mean step time.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

ROBOTS = ("franka", "ur5", "ur10", "kinova", "xarm7")


def targets(robot: str, n: int, seed: int):
    """n (position, wxyz) targets of `robot`'s controlled frame at random configurations."""
    from manip.control import ReactiveController
    from manip.robot_config import load_robot_config
    cfg = load_robot_config(robot)
    ctrl = ReactiveController(robot)
    rng = np.random.default_rng([seed, ROBOTS.index(robot)])
    out = []
    while len(out) < n:
        q = rng.uniform(cfg.limits.lower, cfg.limits.upper)
        pose = ctrl.frame_pose(q)
        # a reachable target: the configuration keeps safety_margin between the robot's links
        if pose.position[2] >= 0.05 and ctrl.step(q, pose, 1 / 60).self_clearance >= ctrl.safety_margin:
            out.append(pose)
    return out


def run(robot: str, target, steps: int = 600, dt: float = 1 / 60, self_collision: bool = True, **weights) -> dict:
    from manip.control import ReactiveController, StepStatus
    ctrl = ReactiveController(robot, self_collision=self_collision)
    if weights:
        ctrl.set_weights(**weights)
    q = ctrl.rest_configuration
    pose = target
    t = 0.0
    status, stalled_at = "moving", None
    for k in range(steps):
        r = ctrl.step(q, pose, dt)
        t += r.solve_time
        if r.position_error < 5e-3 and r.orientation_error < 0.02:
            status = "reached"
            break
        if stalled_at is None and r.status is getattr(StepStatus, "STALLED", None):
            stalled_at = k * dt
        q = r.q
    return {"status": status, "steps": k + 1, "step_ms": 1e3 * t / (k + 1), "error": r.position_error,
            "stalled_at": stalled_at}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=30)
    ap.add_argument("--seed", type=int, default=6100)
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS), choices=ROBOTS)
    ap.add_argument("--posture", type=float, default=None, help="posture weight (default: the controller's)")
    ap.add_argument("--no-self-collision", action="store_true", help="the controller without self-collision avoidance")
    a = ap.parse_args(argv)
    w = {} if a.posture is None else {"posture": a.posture}
    for robot in a.robots:
        rows = [run(robot, tg, self_collision=not a.no_self_collision, **w) for tg in targets(robot, a.n, a.seed)]
        ok = [r for r in rows if r["status"] == "reached"]
        bad = [r for r in rows if r["status"] != "reached"]
        ms = np.mean([r["step_ms"] for r in rows])
        print(f"{robot:7s} reached {len(ok)}/{len(rows)} (after a STALLED report: "
              f"{sum(r['stalled_at'] is not None for r in ok)}); not reached at 10 s {len(bad)}, of which reported "
              f"STALLED {sum(r['stalled_at'] is not None for r in bad)} (first at "
              f"{[round(r['stalled_at'], 2) for r in bad if r['stalled_at'] is not None]} s); step {ms:.3f} ms; "
              f"errors of those not reached [m] {[round(r['error'], 3) for r in bad]}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
