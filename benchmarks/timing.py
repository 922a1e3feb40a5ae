"""Benchmark of manip.timing.time_parameterize on MotionBenchMaker-like Panda paths.

Paths (no planner involved, so only the timing is measured):
  line    start -> goal of each MBM problem (2 waypoints)
  via     start -> 1-3 random via points around the straight line -> goal (like a
          shortcut RRT-Connect path)
  dense   the `via` path smoothed and resampled at 30 points (like a trajectory
          optimiser's output)
For each mode (exact, blend with several tolerances): mean motion time [s], path length
[rad], max |jerk| [rad/s^3], max |acceleration| [rad/s^2], max deviation from the path
[rad], compute time median / p98 [ms]. cuRobo's means on MBM for comparison: 1.59 s,
3.28 rad, 49 rad/s^3, 6.8 rad/s^2.

    .venv/bin/python benchmarks/timing.py [--per-scene 20] [--seed 0]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from manip.benchmarking.mbm_problems import dataset_available, load_mbm_problems
from manip.robot_config import load_robot_config
from manip.timing import time_parameterize_for_robot


def make_paths(problems, cfg, rng):
    lo, hi = np.asarray(cfg.lower_limits), np.asarray(cfg.upper_limits)
    out = {"line": [], "via": [], "dense": []}
    for p in problems:
        s, g = np.asarray(p.start), np.asarray(p.goal)
        if np.any(s < lo) or np.any(s > hi) or np.any(g < lo) or np.any(g > hi):
            continue
        out["line"].append(np.array([s, g]))
        n_via = int(rng.integers(1, 4))
        lam = np.sort(rng.uniform(0.2, 0.8, n_via))
        vias = [s + t * (g - s) + rng.normal(scale=0.25, size=7) for t in lam]
        via = np.clip(np.array([s, *vias, g]), lo, hi)
        out["via"].append(via)
        # smooth: Chaikin corner cutting twice, then resample by arc length at 30 points
        q = via
        for _ in range(3):
            new = [q[0]]
            for a, b in zip(q[:-1], q[1:]):
                new += [0.75 * a + 0.25 * b, 0.25 * a + 0.75 * b]
            new.append(q[-1])
            q = np.array(new)
        s_arc = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(q, axis=0), axis=1))])
        t = np.linspace(0, s_arc[-1], 30)
        dense = np.stack([np.interp(t, s_arc, q[:, d]) for d in range(7)], axis=1)
        out["dense"].append(np.clip(dense, lo, hi))
    return out


def run(paths, cfg, **kw):
    rows = []
    for path in paths:
        r = time_parameterize_for_robot(path, cfg, **kw)
        if not r.success:
            rows.append(None)
            continue
        tr = r.trajectory
        rows.append(
            (tr.duration, tr.path_length(), tr.max_abs_jerk().max(), tr.max_abs_acceleration().max(),
             r.max_deviation, r.compute_time * 1e3)
        )
    ok = np.array([x for x in rows if x is not None])
    fails = sum(x is None for x in rows)
    return ok, fails


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--per-scene", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    if not dataset_available():
        print("MotionBenchMaker dataset not found (see manip.benchmarking.mbm_problems)", file=sys.stderr)
        return 1
    cfg = load_robot_config("franka")
    problems = load_mbm_problems(limit_per_scene=args.per_scene)
    sets = make_paths(problems, cfg, np.random.default_rng(args.seed))
    configs = [
        ("exact", dict(mode="exact")),
        ("blend 0.02", dict(mode="blend", deviation_tolerance=0.02)),
        ("blend 0.05", dict(mode="blend", deviation_tolerance=0.05)),
        ("blend 0.10", dict(mode="blend", deviation_tolerance=0.10)),
    ]
    print(f"{len(problems)} problems, dt = 1/60 s, Panda limits from robots/franka/robot.yaml")
    print(f"{'paths':6s} {'mode':11s} {'n':>4s} {'fail':>4s} {'time s':>7s} {'len rad':>7s} {'jerk':>6s} "
          f"{'acc':>5s} {'dev rad':>7s} {'ms med':>6s} {'ms p98':>6s}")
    failed = 0
    for name, paths in sets.items():
        for label, kw in configs:
            if name == "line" and label != "exact" and label != "blend 0.05":
                continue
            ok, fails = run(paths, cfg, **kw)
            failed += fails
            m = ok.mean(axis=0)
            print(f"{name:6s} {label:11s} {len(ok):4d} {fails:4d} {m[0]:7.3f} {m[1]:7.2f} {m[2]:6.0f} {m[3]:5.1f} "
                  f"{ok[:, 4].max():7.4f} {np.median(ok[:, 5]):6.2f} {np.percentile(ok[:, 5], 98):6.2f}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
