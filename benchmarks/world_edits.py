"""World edits at scale: `add_obstacle`, `remove_obstacle` and `update_obstacle_pose` with
hundreds to thousands of obstacles (camera-rate updates), and a full `update_world` for
comparison. Prints a markdown table (median and p95 per edit [ms]).

The edits are incremental: the checker's obstacle tables are copied with one row added,
removed or replaced (no coal geometry rebuilt, no other obstacle touched), and installed
atomically, so a plan running in another thread keeps the world it started with.

Usage:
    .venv/bin/python benchmarks/world_edits.py [--sizes 100 1000 2000] [--edits 300]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from manip import MotionGenerator
from manip.collision import Cuboid, Cylinder, Sphere, WorldConfig


def random_obstacles(n: int, rng: np.random.Generator, prefix: str = "ob") -> list:
    """n boxes, spheres and cylinders scattered around the robot (0.3-1.5 m away)."""
    out = []
    for i in range(n):
        r, a, z = rng.uniform(0.3, 1.5), rng.uniform(-np.pi, np.pi), rng.uniform(-0.2, 1.2)
        p = [r * np.cos(a), r * np.sin(a), z]
        kind = i % 3
        if kind == 0:
            out.append(Cuboid(f"{prefix}{i}", rng.uniform(0.01, 0.05, 3), p + [1.0, 0.0, 0.0, 0.0]))
        elif kind == 1:
            out.append(Sphere(f"{prefix}{i}", rng.uniform(0.005, 0.03), p))
        else:
            out.append(Cylinder(f"{prefix}{i}", rng.uniform(0.005, 0.02), rng.uniform(0.02, 0.1), p + [1.0, 0, 0, 0]))
    return out


def _stats(samples: list[float]) -> tuple[float, float]:
    a = np.asarray(samples) * 1e3
    return float(np.median(a)), float(np.percentile(a, 95))


def measure(n: int, edits: int, seed: int = 0) -> dict[str, tuple[float, float]]:
    """Per-edit times [ms] (median, p95) at a world of n obstacles."""
    rng = np.random.default_rng(seed)
    mg = MotionGenerator("franka", WorldConfig(random_obstacles(n, rng)))
    extra = random_obstacles(edits, rng, prefix="new")
    out: dict[str, list[float]] = {"add_obstacle": [], "remove_obstacle": [], "update_obstacle_pose": [],
                                   "update_world (full rebuild)": []}
    for ob in extra:  # add one, then remove it: the world stays at n obstacles
        t = time.perf_counter()
        mg.add_obstacle(ob)
        out["add_obstacle"].append(time.perf_counter() - t)
        t = time.perf_counter()
        mg.remove_obstacle(ob.name)
        out["remove_obstacle"].append(time.perf_counter() - t)
    names = mg.world.names
    for k in range(edits):
        name = names[k % len(names)]
        pose = list(rng.uniform(-1.0, 1.0, 3)) + [1.0, 0.0, 0.0, 0.0]
        t = time.perf_counter()
        mg.checker.update_obstacle_pose(name, pose)
        out["update_obstacle_pose"].append(time.perf_counter() - t)
    world = mg.world
    for _ in range(max(3, edits // 50)):
        t = time.perf_counter()
        mg.update_world(world)
        out["update_world (full rebuild)"].append(time.perf_counter() - t)
    return {k: _stats(v) for k, v in out.items()}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100, 1000, 2000], help="obstacle counts")
    ap.add_argument("--edits", type=int, default=300, help="edits of each kind per size")
    args = ap.parse_args()
    results = {n: measure(n, args.edits) for n in args.sizes}
    kinds = list(next(iter(results.values())))
    print(f"World edits, {platform.processor() or platform.machine()}, {args.edits} edits of each kind; "
          "median / p95 per edit [ms]\n")
    print("| edit | " + " | ".join(f"{n} obstacles" for n in args.sizes) + " |")
    print("|---|" + "---|" * len(args.sizes))
    for k in kinds:
        print(f"| `{k}` | " + " | ".join(f"{results[n][k][0]:.3f} / {results[n][k][1]:.3f}" for n in args.sizes) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
