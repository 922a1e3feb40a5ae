"""Pick-and-place success rate and speed: randomised episodes of examples/pick_and_place.py.

    python benchmarks/pick_and_place.py [--episodes 100] [--seed 0] [--write-md]
    python benchmarks/pick_and_place.py --episodes 20 --configs obstacles

Each configuration ("plain": cube, robot, ground; "obstacles": plus the example's fixed
boxes; "perceive": the obstacles, the planner seeing them only through two depth cameras) runs `--episodes` episodes with a random cube position and yaw each (the example's
`--seed` stream), headless, in one process. An episode counts as placed when, at its end,
the cube's centre rests within 1 cm of the place position, read from the simulator.
Real-time factor = simulated time / wall time of whole episodes (planning, physics and
everything the example does). `--write-md` replaces the `## Pick and place` section of
BENCHMARKS.md. Exit status 1 when a target is missed (>= 99 % placed, >= 10x real time).
"""

from __future__ import annotations

import argparse
import datetime as dt
import importlib.util
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.report import cpu_model, replace_section  # noqa: E402
TARGET_SUCCESS = 0.99
TARGET_RTF = 10.0
#: Configurations: "perceive" is "obstacles" with the planner's obstacles from two depth
#: cameras only (`--perceive`); each with its targets (placed fraction, real-time factor).
CONFIGS = ("plain", "obstacles", "perceive")
TARGET = {"plain": (TARGET_SUCCESS, TARGET_RTF), "obstacles": (TARGET_SUCCESS, TARGET_RTF), "perceive": (0.95, 0.0)}


def load_example(name: str = "pick_and_place"):
    """The module examples/<name>.py (examples/ is not a package)."""
    spec = importlib.util.spec_from_file_location(f"{name}_example", ROOT / "examples" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # dataclasses look their module up while the class is built
    spec.loader.exec_module(mod)
    return mod


def machine() -> dict:
    import mujoco

    cpu = cpu_model()
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(), "mujoco": mujoco.__version__,
            "date": dt.datetime.now().strftime("%Y-%m-%d %H:%M"),
            "load": os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")}


def run_config(ex, name: str, episodes: int, seed: int, perturb: bool) -> dict:
    demo = ex.PickAndPlace(seed=seed, obstacles=(name in ("obstacles", "perceive")), verbose=False,
                           perceive=(name == "perceive"))
    results = []
    t0 = time.perf_counter()
    try:
        for i in range(episodes):
            r = demo.run_episode(i, perturb=perturb)
            results.append(r)
            mark = "ok" if r.placed else f"FAILED ({r.reason})"
            print(f"  {name} episode {i:3d}: {mark}, error {r.error * 1e3:5.2f} mm, plan {r.plan_time:5.2f} s, "
                  f"sim {r.sim_time:5.2f} s, wall {r.wall_time:5.2f} s, slip {r.slip * 1e3:4.1f} mm"
                  + (f", {r.obstacle_contact_steps} obstacle contact steps" if r.obstacle_contact_steps else ""),
                  flush=True)
    finally:
        demo.close()
    wall = time.perf_counter() - t0
    err = np.array([r.error for r in results])
    sim = np.array([r.sim_time for r in results])
    walls = np.array([r.wall_time for r in results])
    plan = np.array([r.plan_time for r in results])
    return {
        "name": name,
        "episodes": len(results),
        "placed": int(sum(r.placed for r in results)),
        "err_median": float(np.median(err)) if len(err) else float("nan"),
        "err_p95": float(np.percentile(err, 95)) if len(err) else float("nan"),
        "err_max": float(np.max(err)) if len(err) else float("nan"),
        "picks": int(sum(r.picks for r in results)),
        "failed_plans": int(sum(r.failed_plans for r in results)),
        "plans": int(sum(r.plans for r in results)),
        "contact_steps": int(sum(r.obstacle_contact_steps for r in results)),
        "slip_max": float(max(r.slip for r in results)) if results else float("nan"),
        "plan_median": float(np.median(plan)),
        "plan_p95": float(np.percentile(plan, 95)),
        "sim_total": float(sim.sum()),
        "wall_total": float(walls.sum()),
        "rtf": float(sim.sum() / walls.sum()),
        "rtf_min": float(np.min(sim / walls)),
        "sim_median": float(np.median(sim)),
        "wall_median": float(np.median(walls)),
        "process_wall": wall,
        "failures": [(r.index, r.reason) for r in results if not r.placed],
    }


def table(rows: list[dict], m: dict) -> str:
    head = ("| configuration | placed within 1 cm | final error median / p95 / max | picks | plans (failed) | "
            "cube slip in hand (max) | obstacle contacts | planning per episode median / p95 | "
            "episode sim / wall median | real-time factor (all episodes / worst) |")
    lines = [
        f"Machine: {m['cpu']}, {m['cores']} cores; Python {m['python']}, MuJoCo {m['mujoco']}; {m['date']}; "
        f"load average at start {m['load']:.1f}",
        "",
        head,
        "|" + "|".join("---" for _ in range(head.count("|") - 1)) + "|",
    ]
    for r in rows:
        lines.append(
            f"| {r['name']} | {r['placed']}/{r['episodes']} ({100 * r['placed'] / max(r['episodes'], 1):.0f} %) | "
            f"{r['err_median'] * 1e3:.1f} / {r['err_p95'] * 1e3:.1f} / {r['err_max'] * 1e3:.1f} mm | {r['picks']} | "
            f"{r['plans']} ({r['failed_plans']}) | {r['slip_max'] * 1e3:.1f} mm | {r['contact_steps']} steps | "
            f"{r['plan_median']:.2f} / {r['plan_p95']:.2f} s | {r['sim_median']:.2f} / {r['wall_median']:.2f} s | "
            f"{r['rtf']:.1f}x / {r['rtf_min']:.1f}x |"
        )
    fails = [(r["name"], i, why) for r in rows for i, why in r["failures"]]
    if fails:
        lines.append("")
        lines.append("Failed episodes: " + "; ".join(f"{n} #{i}: {why}" for n, i, why in fails))
    return "\n".join(lines) + "\n"


def write_markdown(text: str, args: argparse.Namespace, path: Path) -> None:
    cmd = f"python benchmarks/pick_and_place.py --episodes {args.episodes} --seed {args.seed}"
    if args.configs != "plain,obstacles":
        cmd += f" --configs {args.configs}"
    if args.perturb:
        cmd += " --perturb"
    # the perceiving episodes have a section of their own (the others' stays as it is)
    heading = "## Pick and place, perceiving" if args.configs == "perceive" else "## Pick and place"
    targets = ("Targets: >= 95 % placed, 0 obstacle contacts (the planner sees the obstacles only through two "
               "640x480 depth cameras, examples/perception_rig.py)." if args.configs == "perceive" else
               f"Targets: >= {TARGET_SUCCESS * 100:.0f} % placed, >= {TARGET_RTF:g}x real time.")
    section = (
        f"{heading}\n\n"
        f"`{cmd} --write-md` (examples/pick_and_place.py headless: a 5 cm, 0.05 kg cube at a random position "
        "(x 0.35-0.65 m, y -0.35-0.35 m, >= 15 cm from the place position) and yaw per episode, held by friction "
        "only; placed = the cube's centre rests within 1 cm of the place position, read from the simulator; "
        "'cube slip' = largest shift of the cube in the hand between the lift and the release; "
        "'obstacle contacts' = physics steps in which anything touched an obstacle box; wall time includes "
        f"planning and physics, on a machine shared with other jobs). {targets}\n\n" + text + "\n"
    )
    replace_section(path, heading, section)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--configs", default="plain,obstacles", help="comma-separated: plain, obstacles, perceive")
    parser.add_argument("--perturb", action="store_true", help="each episode also re-picks after a perturbation")
    parser.add_argument("--write-md", action="store_true", help="update the Pick and place section of BENCHMARKS.md")
    args = parser.parse_args(argv)
    configs = [c.strip() for c in args.configs.split(",") if c.strip()]
    bad = [c for c in configs if c not in CONFIGS]
    if bad or not configs:
        parser.error(f"unknown configuration(s) {bad}; valid: {', '.join(CONFIGS)}")
    ex = load_example()
    m = machine()
    rows = [run_config(ex, c, args.episodes, args.seed, args.perturb) for c in configs]
    text = table(rows, m)
    print()
    print(text)
    if args.write_md:
        write_markdown(text, args, ROOT / "BENCHMARKS.md")
    ok = all(r["placed"] >= TARGET[r["name"]][0] * r["episodes"] and r["rtf"] >= TARGET[r["name"]][1] for r in rows)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
