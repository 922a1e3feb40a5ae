"""Unseen problems, round three: the flagship pick-and-place in manip.sim with random cubes.

    python benchmarks/unseen_sim.py --n 40 --seed 4000 [--sizes 0.03,0.08] [--out results.json]

Episode i (seeded by seed + i): a cube of edge uniform in `--sizes` [m] at a random reachable
pose and yaw (examples/pick_and_place.py's pick area), the example's obstacles on every other
episode (every episode with `--perceive`: the planner sees them only through two depth cameras), a perturbation (the cube moved away after the place, picked again) on every third
(every episode with `--perturb-all`).
Each episode builds its own World (`PickAndPlace(cube_size=...)`), so sizes differ. Prints one
line per episode and a summary: placed, why the others failed (the example's reason:
planning status, grasp check, controller), largest slip of the cube in the hand, obstacle
contacts. Wall times are of niced runs beside other jobs: indicative only.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.pick_and_place import load_example


def random_boxes(ex, seed: int) -> list[tuple[str, np.ndarray, np.ndarray, float]]:
    """2-5 random boxes on the ground instead of the example's layout (`--random-obstacles`): edges
    4-15 cm, heights 5-35 cm, random yaw, 0.25-0.8 m from the base within +-110 deg of its x axis,
    their footprint at least 12 cm from the place position (cubes keep 10 cm from them: the
    example's `random_cube_pose`)."""
    rng = np.random.default_rng([seed, 7919])
    out = []
    while len(out) < int(rng.integers(2, 6)):
        r, a = rng.uniform(0.25, 0.8), rng.uniform(-np.radians(110), np.radians(110))
        dims = np.array([rng.uniform(0.04, 0.15), rng.uniform(0.04, 0.15), rng.uniform(0.05, 0.35)])
        c = np.array([r * np.cos(a), r * np.sin(a), dims[2] / 2])
        if np.linalg.norm(c[:2] - ex.PLACE_POSITION[:2]) - np.linalg.norm(dims[:2]) / 2 < 0.12:
            continue
        out.append((f"box{len(out)}", c, dims, float(rng.uniform(-np.pi, np.pi))))
    return out


def run(n: int, seed: int, sizes: tuple[float, float], perceive: bool = False,
        random_obstacles: bool = False, perturb_all: bool = False) -> list[dict]:
    ex = load_example()
    if random_obstacles:
        ex.obstacle_boxes = lambda s: random_boxes(ex, s)
    rows = []
    for i in range(n):
        rng = np.random.default_rng([seed, i])
        size = float(rng.uniform(*sizes))
        obstacles, perturb = i % 2 == 1 or perceive or random_obstacles, perturb_all or i % 3 == 2
        t0 = time.perf_counter()
        try:
            demo = ex.PickAndPlace(seed=seed + i, obstacles=obstacles, verbose=False, cube_size=size,
                                   perceive=perceive)
        except ValueError as exc:
            rows.append({"i": i, "size": size, "placed": False, "reason": f"refused: {exc}", "obstacles": obstacles,
                         "perturb": perturb})
            print(f"episode {i:3d} size {size * 100:4.1f} cm: refused ({exc})", flush=True)
            continue
        try:
            r = demo.run_episode(0, perturb=perturb)
        finally:
            demo.close()
        row = {"i": i, "size": size, "obstacles": obstacles, "perturb": perturb, "placed": r.placed,
               "error_mm": r.error * 1e3, "slip_mm": r.slip * 1e3, "picks": r.picks, "plans": r.plans,
               "failed_plans": r.failed_plans, "contacts": r.obstacle_contact_steps, "reason": r.reason,
               "wall": time.perf_counter() - t0, "sim": r.sim_time, "log": r.log}
        rows.append(row)
        print(f"episode {i:3d} size {size * 100:4.1f} cm{' obst' if obstacles else '     '}"
              f"{' perturb' if perturb else '        '}: {'placed' if r.placed else 'FAILED'} error "
              f"{r.error * 1e3:6.1f} mm, slip {r.slip * 1e3:4.1f} mm, picks {r.picks}, plans {r.plans}"
              f"/{r.plans + r.failed_plans}, contacts {r.obstacle_contact_steps}, wall {row['wall']:5.1f} s"
              + ("" if r.placed else f"\n    reason: {r.reason}"), flush=True)
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--seed", type=int, default=4000)
    ap.add_argument("--sizes", default="0.03,0.08", help="cube edge range [m], lo,hi")
    ap.add_argument("--perceive", action="store_true",
                    help="the planner sees the obstacles only through two depth cameras (obstacles in every episode)")
    ap.add_argument("--random-obstacles", action="store_true",
                    help="2-5 random boxes in every episode instead of the example's layout")
    ap.add_argument("--perturb-all", action="store_true",
                    help="every episode moves the cube away after the place (to a random pose) and picks it again")
    ap.add_argument("--out", help="write the rows (with each episode's log) as JSON")
    a = ap.parse_args(argv)
    lo, hi = (float(v) for v in a.sizes.split(","))
    rows = run(a.n, a.seed, (lo, hi), a.perceive, a.random_obstacles, a.perturb_all)
    ok = [r for r in rows if r["placed"]]
    print(f"\nplaced {len(ok)}/{len(rows)}; slip max {max([r.get('slip_mm', 0) for r in rows] or [0]):.1f} mm; "
          f"obstacle contact steps {sum(r.get('contacts', 0) for r in rows)}")
    for r in rows:
        if not r["placed"]:
            print(f"  {r['i']} ({r['size'] * 100:.1f} cm): {r['reason']}")
    if a.out:
        Path(a.out).write_text(json.dumps(rows, indent=1))
    return 0 if len(ok) == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main())
