"""Two arms, one plan: seeded `dual_franka` problems where the hands must pass each other.

Each problem (seeded by its index): a table and 3-6 boxes in the space the two arms share
(x 0.35-0.75 m, |y| <= 0.35 m, up to 0.45 m high); a start with each hand on its own side
(hand down, a random yaw), and a goal with the hands swapped to the other side, one low and
one high, so the arms must pass each other. Start and goal are collision-free configurations
of the combined robot (found by IK of each hand, the other arm held).

Planned three ways:

- together: `MotionGenerator("dual_franka").plan_joints(start, goal)`, one motion of both arms;
- one arm at a time (the naive baseline): the left arm to its goal with the right arm held,
  then the right arm with the left held (`plan_joints` with the other arm's joints unchanged);
  it fails when the first arm's goal or path blocks the second;
- `plan_many` on the same problems (the batch API, its default budgets), to check it gives
  the same success on the multi-arm robot.

Every returned trajectory is checked by the independent verifier (`manip.benchmarking.verify`:
its own Pinocchio + coal model, every pair of the two arms included). Reported: success,
invalid returned, planning time (wall and CPU) median / p98, and motion time against the
per-problem lower bound (the time-optimal rest-to-rest motion along the straight line, which
ignores obstacles: `manip.timing.bounds.rest_to_rest_time`).

Usage::

    .venv/bin/python benchmarks/multi_arm.py                  # 200 problems, all three
    .venv/bin/python benchmarks/multi_arm.py --problems 20 --skip-batch
    .venv/bin/python benchmarks/multi_arm.py --problems 0 --skip-baseline --skip-batch --relative 50

`--relative N` also plans N seeded carries (both hands on a bar, the bar moved 10-30 cm and
turned) with `RelativePoseConstraint(5 mm, 0.02 rad)` and samples each trajectory at 1 kHz.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time

import numpy as np

from manip import MotionGenerator, Pose
from manip import quaternion as quat
from manip.batch import Problem, plan_many
from manip.benchmarking.verify import Verifier
from manip.timing.bounds import rest_to_rest_time

ROBOT = "dual_franka"
SHARED_X, SHARED_Y, SHARED_Z = (0.35, 0.75), (-0.35, 0.35), (0.05, 0.45)   # [m] where the clutter goes
HAND_X = (0.3, 0.65)                                                          # [m] where the hands go
LOW_Z, HIGH_Z = (0.12, 0.25), (0.38, 0.55)                                   # [m] the crossing hands' heights
OWN_SIDE, OTHER_SIDE = (0.12, 0.40), (-0.35, -0.05)                           # [m] |y| of the left hand (mirrored)
TRIES = 200                                                                   # draws per problem before giving up


def hand_down(yaw: float) -> np.ndarray:
    return quat.multiply(quat.from_axis_angle([0.0, 0.0, 1.0], yaw), np.array([0.0, 1.0, 0.0, 0.0]))


def clutter(rng: np.random.Generator) -> dict:
    """A cuRobo-style world dict: the table and 3-6 boxes in the shared space."""
    cuboids = {"table": {"dims": [1.0, 1.6, 0.04], "pose": [0.55, 0.0, -0.02, 1, 0, 0, 0]}}
    for k in range(int(rng.integers(3, 7))):
        dims = rng.uniform(0.04, 0.12, 3)
        c = [rng.uniform(*SHARED_X), rng.uniform(*SHARED_Y), rng.uniform(*SHARED_Z)]
        q = quat.from_axis_angle([0.0, 0.0, 1.0], rng.uniform(-np.pi, np.pi))
        cuboids[f"box{k}"] = {"dims": dims.tolist(), "pose": [*c, *q.tolist()]}
    return {"cuboid": cuboids}


def _hands(mg: MotionGenerator, rng: np.random.Generator, seed_q: np.ndarray, cross: bool) -> np.ndarray | None:
    """A collision-free configuration with the hands on their own sides (or crossed), or None."""
    q = seed_q.copy()
    low_left = rng.random() < 0.5
    for arm, sign in ((mg.config.arms[0], 1.0), (mg.config.arms[1], -1.0)):
        y_range = OTHER_SIDE if cross else OWN_SIDE
        y = sign * rng.uniform(*y_range)
        if cross:
            z = rng.uniform(*(LOW_Z if (arm is mg.config.arms[0]) == low_left else HIGH_Z))
        else:
            z = rng.uniform(LOW_Z[0], HIGH_Z[1])
        goal = Pose([rng.uniform(*HAND_X), y, z], hand_down(rng.uniform(-0.6, 0.6)))
        r = mg.ik(goal, link=arm.ee_link, seed_q=q, collision_free=True, seed=int(rng.integers(2**31)))
        if not r.success:
            return None
        q = r.q.copy()
    return q if not mg.check_collision(q) else None


def make_problems(n: int, seed: int = 0) -> list[tuple[dict, np.ndarray, np.ndarray]]:
    """`n` seeded problems (world dict, start (14,), goal (14,)); problem i depends only on (seed, i)."""
    mg = MotionGenerator(ROBOT, seed=seed)
    home = mg.default_joint_positions
    out = []
    for i in range(n):
        rng = np.random.default_rng([seed, i])
        for _ in range(TRIES):
            world = clutter(rng)
            mg.update_world(world)
            if mg.check_collision(home):
                continue
            start = _hands(mg, rng, home, cross=False)
            goal = None if start is None else _hands(mg, rng, start, cross=True)
            if goal is not None:
                out.append((world, start, goal))
                break
        else:
            raise RuntimeError(f"problem {i}: no start and goal found in {TRIES} draws")
    return out


def _stats(values) -> str:
    v = np.asarray(values, dtype=float)
    return f"{1e3 * np.median(v):.0f} / {1e3 * np.percentile(v, 98):.0f}" if v.size else "-"


def plan_together(mg: MotionGenerator, verifier: Verifier, problems) -> dict:
    out = {"solved": 0, "invalid": 0, "wall": [], "cpu": [], "ratio": [], "motion": []}
    for i, (world, start, goal) in enumerate(problems):
        mg.update_world(world)
        w, c = time.perf_counter(), time.process_time()
        r = mg.plan_joints(start, goal, seed=i)
        out["wall"].append(time.perf_counter() - w)
        out["cpu"].append(time.process_time() - c)
        if not r.success:
            continue
        t = r.trajectory
        ok = verifier.verify_trajectory(world, t.times, t.positions, t.velocities, t.accelerations, start_q=start,
                                        goal_q=goal).valid
        out["solved"] += 1
        out["invalid"] += not ok
        out["motion"].append(t.duration)
        out["ratio"].append(t.duration / rest_to_rest_time(start, goal, mg.limits))
    return out


def plan_one_arm_at_a_time(mg: MotionGenerator, verifier: Verifier, problems) -> dict:
    """The naive baseline: the left arm first (the right held), then the right (the left held)."""
    out = {"solved": 0, "invalid": 0, "wall": [], "cpu": [], "ratio": [], "motion": []}
    left = slice(*mg.config.arms[0].columns)
    for i, (world, start, goal) in enumerate(problems):
        mg.update_world(world)
        mid = start.copy()
        mid[left] = goal[left]
        w, c = time.perf_counter(), time.process_time()
        first = mg.plan_joints(start, mid, seed=i)
        second = mg.plan_joints(mid, goal, seed=i) if first.success else None
        out["wall"].append(time.perf_counter() - w)
        out["cpu"].append(time.process_time() - c)
        if second is None or not second.success:
            continue
        ok = True
        for r, a, b in ((first, start, mid), (second, mid, goal)):
            t = r.trajectory
            ok &= verifier.verify_trajectory(world, t.times, t.positions, t.velocities, t.accelerations, start_q=a,
                                             goal_q=b).valid
        duration = first.trajectory.duration + second.trajectory.duration
        out["solved"] += 1
        out["invalid"] += not ok
        out["motion"].append(duration)
        out["ratio"].append(duration / rest_to_rest_time(start, goal, mg.limits))
    return out


def plan_batch(problems, workers: int | None) -> dict:
    batch = [Problem(world, start, goal, robot=ROBOT, id=i) for i, (world, start, goal) in enumerate(problems)]
    w = time.perf_counter()
    results = plan_many(batch, workers=workers, seed=0)
    wall = time.perf_counter() - w
    return {"solved": sum(bool(r.success) for r in results), "wall": wall, "results": results}


def relative_pose_problems(mg: MotionGenerator, n: int, seed: int) -> list[tuple[np.ndarray, dict]]:
    """`n` seeded carries: both hands on a bar 20-40 cm long (hand down, across it) at a random
    place on the table, and goals that move the bar (its centre 10-30 cm away, turned up to
    0.5 rad about z): (start (14,), goals {hand: Pose})."""
    mg.update_world({"cuboid": {"table": {"dims": [1.0, 1.6, 0.04], "pose": [0.55, 0.0, -0.02, 1, 0, 0, 0]}}})
    hands = [a.ee_link for a in mg.config.arms]
    out = []
    for i in range(n):
        rng = np.random.default_rng([seed, 1_000_003, i])
        for _ in range(TRIES):
            half = rng.uniform(0.10, 0.20)
            centre = np.array([rng.uniform(0.4, 0.6), rng.uniform(-0.08, 0.08), rng.uniform(0.15, 0.3)])
            bar = Pose(centre, quat.from_axis_angle([0, 0, 1], rng.uniform(-0.3, 0.3)))
            grips = {h: bar @ Pose([0.0, s * half, 0.0], hand_down(np.pi / 2)) for h, s in zip(hands, (1.0, -1.0))}
            grasp = mg.plan_poses(mg.default_joint_positions, grips, seed=i)
            if not grasp.success:
                continue
            step = rng.normal(size=3)
            step *= rng.uniform(0.10, 0.30) / np.linalg.norm(step)
            moved = Pose(bar.position + step, quat.multiply(quat.from_axis_angle([0, 0, 1], rng.uniform(-0.5, 0.5)),
                                                            bar.quaternion))
            if moved.position[2] < 0.12:
                continue
            T = moved @ bar.inverse()
            out.append((grasp.goal_q, {h: T @ mg.fk(grasp.goal_q, h) for h in hands}))
            break
    return out


def plan_relative(mg: MotionGenerator, problems, tolerance=(0.005, 0.02)) -> dict:
    """Carries planned with `RelativePoseConstraint` of the two hands; every solved trajectory
    sampled at 1 kHz (`Trajectory.resample(0.001)`): how many leave the tolerances."""
    from manip import RelativePoseConstraint

    hands = [a.ee_link for a in mg.config.arms]
    hold = RelativePoseConstraint(*hands, position_tolerance=tolerance[0], rotation_tolerance=tolerance[1])
    out = {"solved": 0, "beyond": 0, "worst": -1.0, "cpu": [], "ratio": [], "straight": 0, "failed": []}
    for i, (start, goals) in enumerate(problems):
        c = time.process_time()
        r = mg.plan_poses(start, goals, constraints=(hold,), seed=i)
        out["cpu"].append(time.process_time() - c)
        if not r.success:
            out["failed"].append(f"{i}: {r.status.name}")
            continue
        out["solved"] += 1
        out["straight"] += r.source == "linear"  # the straight carry (`planning.arms`), not a searched path
        worst = float(hold.at_start(mg.kinematics, start).violation(mg.kinematics,
                                                                     r.trajectory.resample(0.001).positions).max())
        out["worst"] = max(out["worst"], worst)
        out["beyond"] += worst > 0.0
        out["ratio"].append(r.trajectory.duration / rest_to_rest_time(start, r.goal_q, mg.limits))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--problems", type=int, default=200, help="Seeded problems (default 200).")
    ap.add_argument("--seed", type=int, default=0, help="Seed of the problems (default 0).")
    ap.add_argument("--workers", type=int, default=None, help="plan_many's workers (default: all cores).")
    ap.add_argument("--skip-baseline", action="store_true", help="Do not plan one arm at a time.")
    ap.add_argument("--skip-batch", action="store_true", help="Do not run plan_many.")
    ap.add_argument("--relative", type=int, default=0, help="Also plan this many carries with RelativePoseConstraint.")
    args = ap.parse_args(argv)
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.2f}", flush=True)
    t = time.perf_counter()
    problems = make_problems(args.problems, args.seed)
    print(f"{len(problems)} problems made in {time.perf_counter() - t:.1f} s", flush=True)
    mg = MotionGenerator(ROBOT, seed=0)
    verifier = Verifier(mg.config)
    rows = [("both arms together (plan_joints)", plan_together(mg, verifier, problems))] if problems else []
    if problems and not args.skip_baseline:
        rows.append(("one arm at a time (the other held)", plan_one_arm_at_a_time(mg, verifier, problems)))
    n = len(problems)
    print("\n| planner | solved | invalid | planning wall median / p98 (ms) | CPU median / p98 (ms) | "
          "motion time median (s) | motion / lower bound: median, mean, p90 |")
    print("|---|---|---|---|---|---|---|")
    for name, r in rows:
        ratio = np.asarray(r["ratio"])
        print(f"| {name} | {r['solved']}/{n} ({100 * r['solved'] / n:.1f} %) | {r['invalid']} | {_stats(r['wall'])} | "
              f"{_stats(r['cpu'])} | {np.median(r['motion']):.2f} | {np.median(ratio):.2f}, {ratio.mean():.2f}, "
              f"{np.percentile(ratio, 90):.2f} |")
    print(f"load after: {os.getloadavg()[0]:.2f}", flush=True)
    together = rows[0][1] if rows else {"solved": 0, "invalid": 0}
    if not args.skip_batch and n:
        b = plan_batch(problems, args.workers)
        print(f"\nplan_many ({args.workers or os.cpu_count()} workers, its default budgets): {b['solved']}/{n} solved in "
              f"{b['wall']:.1f} s ({n / b['wall']:.1f} problems/s); load {os.getloadavg()[0]:.2f}")
    good = together["solved"] >= 0.99 * n and together["invalid"] == 0
    if args.relative:
        carries = relative_pose_problems(mg, args.relative, args.seed)
        rel = plan_relative(mg, carries)
        print(f"\nRelativePoseConstraint (5 mm, 0.02 rad), {len(carries)} carries: {rel['solved']} solved "
              f"({rel['straight']} by the straight carry; failed: {', '.join(rel['failed']) or 'none'}), "
              f"{rel['beyond']} beyond the tolerances at 1 kHz (largest residual {rel['worst']:+.3f}: the "
              f"fraction of a tolerance used, minus 1), "
              f"CPU median / p98 {_stats(rel['cpu'])} ms, motion / lower bound median "
              f"{np.median(rel['ratio']) if rel['ratio'] else float('nan'):.2f}; load {os.getloadavg()[0]:.2f}")
        good &= rel["beyond"] == 0
    return 0 if good else 1


if __name__ == "__main__":
    sys.exit(main())
