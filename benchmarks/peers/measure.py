"""Quick check of the peers on a few MotionBenchMaker problems per scene.

Not the benchmark (that is `benchmarks/mbm.py`): this runs each peer on the first N problems
of each scene, verifies every returned trajectory with `manip.benchmarking.verify`, and
prints per-scene success, planning time and verification counts.

    .venv/bin/python -m benchmarks.peers.measure --peers roboplan,ompl --limit-per-scene 10 --goal joint
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):  # run as a file: make `benchmarks.peers` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.peers import available_peers, get_peer  # noqa: E402
from manip.benchmarking.mbm_problems import load_mbm_problems  # noqa: E402
from manip.benchmarking.verify import check_problem, verify_trajectory  # noqa: E402


def _stats(x: list[float]) -> str:
    if not x:
        return "-"
    a = np.asarray(x) * 1e3
    return f"med {np.median(a):7.1f} mean {a.mean():7.1f} p98 {np.percentile(a, 98):7.1f} ms"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dataset", default=None)
    ap.add_argument("--peers", default="roboplan,ompl")
    ap.add_argument("--scenes", default=None, help="comma-separated scene names (default all)")
    ap.add_argument("--limit-per-scene", type=int, default=10)
    ap.add_argument("--goal", choices=("joint", "pose"), default="joint")
    ap.add_argument("--timeout", type=float, default=10.0)
    ap.add_argument("--option", action="append", default=[], help="peer option name=value (python literal)")
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)

    import ast

    options = {}
    for o in args.option:
        k, v = o.split("=", 1)
        try:
            options[k] = ast.literal_eval(v)
        except (ValueError, SyntaxError):
            options[k] = v
    scenes = args.scenes.split(",") if args.scenes else None
    problems = load_mbm_problems(args.dataset, scenes=scenes, limit_per_scene=args.limit_per_scene)
    valid = [(p, check_problem(p)) for p in problems]
    problems = [p for p, v in valid if v.valid]
    print(f"{len(problems)} valid problems of {len(valid)}; invalid: "
          f"{[(p.scene, p.index, v.codes) for p, v in valid if not v.valid]}")
    avail = available_peers()
    report: dict = {}
    for name in args.peers.split(","):
        if avail.get(name) != "ok":
            print(f"{name}: {avail.get(name, 'unknown')}")
            continue
        t = time.perf_counter()
        peer = get_peer(name, timeout_s=args.timeout, **options)
        print(f"\n== {name} (built in {time.perf_counter() - t:.2f} s) goal={args.goal} options={options}")
        rows: dict[str, dict] = {}
        for p in problems:
            out = peer.plan(p, args.goal, seed=0)
            r = rows.setdefault(p.scene, {"n": 0, "ok": 0, "invalid": 0, "times": [], "motion": [], "reasons": []})
            r["n"] += 1
            r["times"].append(out.plan_time_s)
            if not out.success:
                r["reasons"].append(f"{p.index}:{out.status}")
                continue
            kw = {}
            if args.goal == "pose":
                from manip.benchmarking.mbm_problems import goal_pose

                kw["goal_pose"] = goal_pose(p)
            v = verify_trajectory(p, out.times, out.positions, velocities=out.velocities, accelerations=out.accelerations, jerks=out.jerks, **kw)
            if v.valid:
                r["ok"] += 1
                r["motion"].append(v.motion_time)
            else:
                r["invalid"] += 1
                r["reasons"].append(f"{p.index}:INVALID {'; '.join(v.reasons)[:160]}")
        tot = {"n": 0, "ok": 0, "invalid": 0, "times": [], "motion": []}
        for scene, r in rows.items():
            for k in ("n", "ok", "invalid"):
                tot[k] += r[k]
            tot["times"] += r["times"]
            tot["motion"] += r["motion"]
            print(f"{scene:24s} valid-solved {r['ok']:3d}/{r['n']:3d} invalid-returned {r['invalid']:2d}  "
                  f"plan {_stats(r['times'])}  motion med {np.median(r['motion']) if r['motion'] else float('nan'):.2f} s")
            for line in r["reasons"]:
                print(f"    {line}")
        print(f"{'ALL':24s} valid-solved {tot['ok']:3d}/{tot['n']:3d} invalid-returned {tot['invalid']:2d}  "
              f"plan {_stats(tot['times'])}  motion med {np.median(tot['motion']) if tot['motion'] else float('nan'):.2f} s")
        report[name] = {"rows": {s: {k: v for k, v in r.items()} for s, r in rows.items()}, "total": tot}
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=1, default=float))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
