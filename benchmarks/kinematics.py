"""Kinematics benchmark: FK throughput, IK success rate, time per solve and batch throughput.

Usage:
    python benchmarks/kinematics.py                     # 1000 poses, seed 0, prints a table
    python benchmarks/kinematics.py --n 1000 --seed 0 --json out.json --write-md

The IK goals are the `panda_hand` poses of uniformly random configurations within the joint
limits (reachable by construction). Every claimed success is checked again here with
`Kinematics.fk`: a "wrong" success would be a solution outside the limits or farther than
the tolerances from its goal. `--write-md` replaces the `## Kinematics` section of
BENCHMARKS.md (and leaves the other sections alone).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from manip import Pose
from manip.ik import IKSolver
from manip.kinematics import Kinematics
from manip.robot_config import load_robot_config

LINK = "panda_hand"
ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.report import cpu_model, replace_section  # noqa: E402


def machine() -> dict:
    cpu = cpu_model()
    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "pinocchio": pin.__version__,
        "date": dt.datetime.now().strftime("%Y-%m-%d %H:%M"),
        "load_average_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
    }


def best_rate(fn, count: int, repeats: int = 3) -> float:
    """Items per second of fn() (which processes `count` items), best of `repeats`."""
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return count / best


def bench_fk(k: Kinematics, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    fid = k.frame_id(LINK)
    model, data = k.model, k.data
    Q1 = rng.uniform(k.lower, k.upper, (5000, k.dof))

    def pin_single():
        for q in Q1:
            pin.forwardKinematics(model, data, q)
            pin.updateFramePlacement(model, data, fid)

    def fk_single():
        for q in Q1[:2000]:
            k.fk(q, LINK)

    out = {
        "fk_pinocchio_single_per_s": best_rate(pin_single, len(Q1)),
        "fk_manip_single_per_s": best_rate(fk_single, 2000),
    }
    for n in (10_000, 100_000):
        Q = rng.uniform(k.lower, k.upper, (n, k.dof))
        out[f"fk_batched_{n}_per_s"] = best_rate(lambda: k.frame_transforms(Q, [fid]), n)
        out[f"fk_batched_pose_{n}_per_s"] = best_rate(lambda: k.fk(Q, LINK), n)
    Q = rng.uniform(k.lower, k.upper, (10_000, k.dof))
    out["jacobian_batched_10000_per_s"] = best_rate(lambda: k.frame_jacobians(Q, fid), 10_000)
    return out


def wrong_claims(k: Kinematics, q: np.ndarray, success: np.ndarray, goals: Pose, solver: IKSolver) -> int:
    dp, dr = k.fk(q, LINK).distance(goals)
    bad = ~k.within_limits(q) | (dp > solver.position_tolerance) | (dr > solver.rotation_tolerance)
    return int(np.sum(success & bad))


def bench_ik(k: Kinematics, n: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    Q = rng.uniform(k.lower, k.upper, (n, k.dof))
    goals = k.fk(Q, LINK)
    solver = IKSolver(k, seed=seed)
    solver.solve(goals[0], LINK)  # warm-up
    times, q_sol, success, attempts = [], np.empty((n, k.dof)), np.zeros(n, dtype=bool), []
    for i, goal in enumerate(goals):
        r = solver.solve(goal, LINK)
        times.append(r.solve_time)
        q_sol[i], success[i] = r.q, bool(r.success)
        attempts.append(r.attempts)
    times = np.array(times)
    out = {
        "ik_poses": n,
        "ik_single_success_rate": float(success.mean()),
        "ik_single_wrong_claims": wrong_claims(k, q_sol, success, goals, solver),
        "ik_single_median_ms": float(np.median(times) * 1e3),
        "ik_single_p98_ms": float(np.percentile(times, 98) * 1e3),
        "ik_single_mean_ms": float(times.mean() * 1e3),
        "ik_single_mean_attempts": float(np.mean(attempts)),
    }
    best, result = np.inf, None
    for rep in range(3):
        t = time.perf_counter()
        b = solver.solve_batch(goals, LINK)
        elapsed = time.perf_counter() - t
        if elapsed < best:
            best, result = elapsed, b
    out.update(
        {
            "ik_batch_success_rate": float(result.success.mean()),
            "ik_batch_wrong_claims": wrong_claims(k, result.q, result.solved, goals, solver),  # (N,) mask
            "ik_batch_solutions_per_s": float(result.success.sum() / best),
            "ik_batch_time_s": float(best),
        }
    )
    return out


def bench_mink(k: Kinematics, n: int, seed: int) -> dict:
    """mink's differential IK (QP per step, daqp) on the MuJoCo model, for comparison."""
    import mink
    import mujoco

    config = k.config
    model = mujoco.MjModel.from_xml_path(str(config.mjcf_path))
    configuration = mink.Configuration(model)
    arm_qpos = [model.jnt_qposadr[model.joint(j).id] for j in config.arm_joints]
    # mink frame for the hand: a body named like the link
    task = mink.FrameTask(LINK, "body", position_cost=1.0, orientation_cost=1.0)
    limits = [mink.ConfigurationLimit(model)]
    rng = np.random.default_rng(seed)
    Q = rng.uniform(k.lower, k.upper, (n, k.dof))
    goals = k.fk(Q, LINK)
    q_home = model.qpos0.copy()
    q_home[arm_qpos] = config.default_joint_positions
    dt_step, max_iters, restarts = 0.1, 200, 10
    times, success = [], []
    for goal in goals:
        task.set_target(mink.SE3.from_rotation_and_translation(mink.SO3(goal.quaternion), goal.position))
        t = time.perf_counter()
        ok = False
        for attempt in range(restarts):
            q0 = q_home.copy()
            if attempt:
                q0[arm_qpos] = rng.uniform(k.lower, k.upper)
            configuration.update(q0)
            for _ in range(max_iters):
                err = task.compute_error(configuration)
                if np.linalg.norm(err[:3]) < 1e-4 and np.linalg.norm(err[3:]) < 1e-4:
                    ok = True
                    break
                vel = mink.solve_ik(configuration, [task], dt_step, "daqp", damping=1e-3, limits=limits)
                configuration.integrate_inplace(vel, dt_step)
            if ok:
                break
        times.append(time.perf_counter() - t)
        if ok:
            q = configuration.q[arm_qpos]
            dp, dr = k.fk(q, LINK).distance(goal)
            ok = bool(dp <= 1e-3 and dr <= 0.01 and k.within_limits(q, 1e-6))
        success.append(ok)
    times = np.array(times)
    return {
        "mink_poses": n,
        "mink_success_rate": float(np.mean(success)),
        "mink_median_ms": float(np.median(times) * 1e3),
        "mink_p98_ms": float(np.percentile(times, 98) * 1e3),
    }


def table(res: dict) -> str:
    m = res["machine"]
    rows = [
        ("FK single call, Pinocchio C++ (from Python)", f"{res['fk_pinocchio_single_per_s']:,.0f} /s"),
        ("FK single call, `Kinematics.fk` -> Pose", f"{res['fk_manip_single_per_s']:,.0f} /s"),
        ("FK batched (R, p), N = 10,000", f"{res['fk_batched_10000_per_s']:,.0f} /s"),
        ("FK batched (R, p), N = 100,000", f"{res['fk_batched_100000_per_s']:,.0f} /s"),
        ("FK batched -> Pose (with quaternions), N = 10,000", f"{res['fk_batched_pose_10000_per_s']:,.0f} /s"),
        ("FK batched -> Pose (with quaternions), N = 100,000", f"{res['fk_batched_pose_100000_per_s']:,.0f} /s"),
        ("Jacobians batched, N = 10,000", f"{res['jacobian_batched_10000_per_s']:,.0f} /s"),
        (f"IK single: success on {res['ik_poses']} reachable poses", f"{100 * res['ik_single_success_rate']:.1f} %"),
        ("IK single: wrong claimed successes", f"{res['ik_single_wrong_claims']}"),
        ("IK single: median / p98 / mean time per solve",
         f"{res['ik_single_median_ms']:.2f} / {res['ik_single_p98_ms']:.2f} / {res['ik_single_mean_ms']:.2f} ms"),
        ("IK single: mean attempts (restarts + 1)", f"{res['ik_single_mean_attempts']:.2f}"),
        (f"IK batch of {res['ik_poses']}: success", f"{100 * res['ik_batch_success_rate']:.1f} %"),
        ("IK batch: wrong claimed successes", f"{res['ik_batch_wrong_claims']}"),
        ("IK batch: throughput", f"{res['ik_batch_solutions_per_s']:,.0f} solutions/s ({res['ik_batch_time_s'] * 1e3:.0f} ms)"),
    ]
    if "mink_success_rate" in res:
        rows += [
            (f"mink IK (QP per step, daqp), {res['mink_poses']} poses: success", f"{100 * res['mink_success_rate']:.1f} %"),
            ("mink IK: median / p98 time per solve", f"{res['mink_median_ms']:.2f} / {res['mink_p98_ms']:.2f} ms"),
        ]
    w = max(len(r[0]) for r in rows)
    lines = [
        f"Machine: {m['cpu']}, {m['cores']} cores; Python {m['python']}, NumPy {m['numpy']}, "
        f"Pinocchio {m['pinocchio']}; {m['date']}; load average at start {m['load_average_1min']:.1f}",
        "",
        f"| {'measure'.ljust(w)} | result |",
        f"|{'-' * (w + 2)}|--------|",
    ]
    lines += [f"| {a.ljust(w)} | {b} |" for a, b in rows]
    return "\n".join(lines)


def write_markdown(res: dict, args: argparse.Namespace, path: Path) -> None:
    section = (
        "## Kinematics\n\n"
        f"`python benchmarks/kinematics.py --n {args.n} --seed {args.seed}{' --mink' if args.mink else ''} --write-md` "
        "(Franka Panda, link `panda_hand`; IK goals are the poses of uniformly random configurations "
        "within the joint limits; success = within 1 mm and 0.01 rad and the joint limits, checked "
        "again by the benchmark). Timings are wall time on a machine shared with other jobs.\n\n"
        + table(res)
        + "\n"
    )
    replace_section(path, "## Kinematics", section)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1000, help="number of IK goals")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, default=None, help="write the results here")
    parser.add_argument("--mink", action="store_true", help="also measure mink's IK (slow)")
    parser.add_argument("--mink-n", type=int, default=100, help="goals for the mink comparison")
    parser.add_argument("--write-md", action="store_true", help="update the Kinematics section of BENCHMARKS.md")
    args = parser.parse_args(argv)

    k = Kinematics(load_robot_config("franka"))
    res: dict = {"machine": machine(), "n": args.n, "seed": args.seed}
    res.update(bench_fk(k, args.seed))
    res.update(bench_ik(k, args.n, args.seed))
    if args.mink:
        res.update(bench_mink(k, args.mink_n, args.seed))
    print(table(res))
    if args.json:
        args.json.write_text(json.dumps(res, indent=2))
    if args.write_md:
        write_markdown(res, args, ROOT / "BENCHMARKS.md")
    failed = res["ik_single_wrong_claims"] + res["ik_batch_wrong_claims"]
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
