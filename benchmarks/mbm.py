#!/usr/bin/env python3
"""MotionBenchMaker benchmark: manip and its peers, side by side, every trajectory verified.

    python benchmarks/mbm.py --dataset ../shared/data/mbm/panda_problems.tar.bz2 \\
        [--scenes box_panda cage_panda ...] [--limit-per-scene N] [--goal joint|pose|both] \\
        [--planners manip,roboplan,ompl] [--seeded N] [--timeout S] [--json OUT]

1. Loads the problems straight from the archive (no unpacking) and checks every start and
   goal with the independent verifier (`manip.benchmarking.verify`): problems that are
   infeasible for the example-robot-data Panda (limits, self or world collision) are
   counted, with their reasons, and not planned. Success rates are over the valid ones.
2. Runs each planner on each valid problem and goal kind (pose goal = FK of the goal
   configuration at `panda_hand`). Building a planner and loading a problem's obstacles
   are not timed; the planning time covers everything from (start, goal) to an executable
   trajectory (IK for pose goals, planning, smoothing, time parameterisation).
3. Verifies every returned trajectory with the same independent checker (dense exact-mesh
   collision check at 0.01 rad, position/velocity/acceleration limits, jerk limits for
   planners that claim them, start and goal at rest). A returned trajectory that fails
   counts as a failure AND as "invalid returned".
4. Reports per scene and overall: success rate, planning time mean/median/p75/p98 (over
   the verified successes), motion time, path length, max jerk, max acceleration, invalid
   returned, and, when manip ran with peers, the peers' median and p98 planning times as
   ratios to manip's.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import logging
import os
import platform
import re
import shlex
import subprocess
import sys
import time
from collections import Counter
from dataclasses import asdict, dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.report import cpu_model, replace_section  # noqa: E402

from manip.benchmarking.mbm import MBM_SCENES, default_dataset_path, goal_pose, load_mbm_problems  # noqa: E402
from manip.benchmarking.scenes import SCENE_KINDS, make_problems  # noqa: E402
from manip.benchmarking.verify import Verifier  # noqa: E402

log = logging.getLogger("benchmarks.mbm")

METRICS = ("plan_time_s", "motion_time_s", "path_length_rad", "max_jerk", "max_acceleration")


@dataclass
class Run:
    """One planner on one problem and goal kind."""

    planner: str
    goal: str
    scene: str
    index: int
    status: str
    claimed: bool
    verified: bool
    plan_time_s: float
    setup_time_s: float = float("nan")
    verify_time_s: float = float("nan")
    motion_time_s: float = float("nan")
    path_length_rad: float = float("nan")
    max_jerk: float = float("nan")
    max_acceleration: float = float("nan")
    max_velocity_ratio: float = float("nan")
    max_acceleration_ratio: float = float("nan")
    max_jerk_ratio: float = float("nan")
    claims_jerk_limits: bool = False
    reasons: list[str] = field(default_factory=list)


# ---------------------------------------------------------------------------- planners
def build_planner(name: str, timeout: float | None) -> Any:
    """A planner object with `.name` and `.plan(problem, goal_kind, seed)`."""
    if name == "manip":
        from benchmarks.planners.manip_planner import ManipPlanner

        return ManipPlanner(time_budget=timeout)
    from benchmarks.peers import get_peer

    if timeout is None:
        return get_peer(name)
    try:
        return get_peer(name, timeout_s=timeout)
    except TypeError:
        log.warning("peer %s takes no timeout_s option; using its default budget", name)
        return get_peer(name)


def run_one(planner: Any, problem: Any, goal: str, verifier: Verifier, seed: int) -> Run:
    """Plan one problem with one planner and verify the result."""
    try:
        out = planner.plan(problem, goal, seed=seed)
    except Exception as exc:  # a planner bug must not end the benchmark; it is reported
        log.exception("%s raised on %s/%d (%s goal)", planner.name, problem.scene, problem.index, goal)
        return Run(planner.name, goal, problem.scene, problem.index, f"ERROR: {type(exc).__name__}: {exc}",
                   False, False, float("nan"), reasons=[f"exception: {exc}"])
    run = Run(planner.name, goal, problem.scene, problem.index, str(out.status), bool(out.success), False,
              float(out.plan_time_s), setup_time_s=float(getattr(out, "setup_time_s", float("nan"))))
    run.claims_jerk_limits = bool(getattr(out, "claims_jerk_limits", False))
    if not out.success:
        return run
    if out.positions is None or out.times is None:
        run.reasons = ["claimed success without a trajectory"]
        return run
    t0 = time.perf_counter()
    kwargs: dict[str, Any] = {"check_jerk": bool(out.claims_jerk_limits)}
    if goal == "pose":
        kwargs["goal_pose"] = goal_pose(problem)
    v = verifier.verify_trajectory(problem, out.times, out.positions, out.velocities, out.accelerations, out.jerks, **kwargs)
    run.verify_time_s = time.perf_counter() - t0
    run.verified = v.valid
    run.reasons = list(v.reasons)
    run.motion_time_s = v.motion_time
    run.path_length_rad = v.path_length
    run.max_jerk = v.max_jerk
    run.max_acceleration = v.max_acceleration
    run.max_velocity_ratio = v.max_velocity_ratio
    run.max_acceleration_ratio = v.max_acceleration_ratio
    run.max_jerk_ratio = v.max_jerk_ratio
    return run


# ---------------------------------------------------------------------------- statistics
def stats(values: list[float]) -> dict[str, float]:
    """mean, median, p75, p98, max and n of the finite values (nan when there are none)."""
    a = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    if a.size == 0:
        return {"mean": float("nan"), "median": float("nan"), "p75": float("nan"), "p98": float("nan"),
                "max": float("nan"), "n": 0}
    return {
        "mean": float(a.mean()),
        "median": float(np.median(a)),
        "p75": float(np.percentile(a, 75)),
        "p98": float(np.percentile(a, 98)),
        "max": float(a.max()),
        "n": int(a.size),
    }


def summarize(runs: list[Run], n_valid: int) -> dict[str, Any]:
    """Success rate over `n_valid` problems and metric statistics over verified successes."""
    ok = [r for r in runs if r.verified]
    out: dict[str, Any] = {
        "valid_problems": n_valid,
        "planned": len(runs),
        "solved": len(ok),
        "success_rate": (len(ok) / n_valid) if n_valid else float("nan"),
        "claimed_success": sum(r.claimed for r in runs),
        "invalid_returned": sum(r.claimed and not r.verified for r in runs),
        "errors": sum(r.status.startswith("ERROR") for r in runs),
        "failure_statuses": dict(Counter(r.status for r in runs if not r.claimed)),
    }
    for m in METRICS:
        out[m] = stats([getattr(r, m) for r in ok])
    out["plan_time_all_s"] = stats([r.plan_time_s for r in runs])
    out["verify_time_s"] = stats([r.verify_time_s for r in runs if r.claimed])
    out["max_velocity_ratio"] = stats([r.max_velocity_ratio for r in runs if r.claimed])
    out["max_acceleration_ratio"] = stats([r.max_acceleration_ratio for r in runs if r.claimed])
    out["max_jerk_ratio"] = stats([r.max_jerk_ratio for r in runs if r.claimed])
    bad = Counter()
    for r in runs:
        if r.claimed and not r.verified:
            for reason in r.reasons:
                bad[re.sub(r" at t=.*", "", reason.split(":")[0])] += 1
    out["invalid_reasons"] = dict(bad)
    return out


def ratios_vs_manip(report: dict[str, Any]) -> dict[str, Any]:
    """peer / manip planning time, median and p98, per goal kind and overall."""
    planners = report["planners"]
    if "manip" not in planners or len(planners) < 2:
        return {}
    out: dict[str, Any] = {}
    for name, p in planners.items():
        if name == "manip":
            continue
        entry: dict[str, Any] = {}
        for label, a, b in [("all", p, planners["manip"])] + [
            (g, p["by_goal"][g], planners["manip"]["by_goal"][g]) for g in p["by_goal"] if g in planners["manip"]["by_goal"]
        ]:
            entry[label] = {
                q: (a["plan_time_s"][q] / b["plan_time_s"][q]) if b["plan_time_s"][q] > 0 else float("nan")
                for q in ("median", "p98")
            }
            entry[label]["motion_time_mean"] = (
                a["motion_time_s"]["mean"] / b["motion_time_s"]["mean"] if b["motion_time_s"]["mean"] > 0 else float("nan")
            )
        out[name] = entry
    return out


# ---------------------------------------------------------------------------- report
def machine_info() -> dict[str, Any]:
    cpu = cpu_model()
    versions = {}
    for pkg in ("manip", "pin", "coal", "ruckig", "numba", "numpy", "roboplan", "ompl", "toppra"):
        try:
            versions[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            pass
    try:
        commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=False).stdout.strip()
    except OSError:
        commit = ""
    try:
        load = [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover
        load = []
    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "load_average_at_start": load,
        "platform": platform.platform(),
        "python": platform.python_version(),
        "packages": versions,
        "commit": commit,
    }


def _fmt_ms(x: float) -> str:
    return "-" if not np.isfinite(x) else (f"{x * 1e3:.0f}" if x >= 0.1 else f"{x * 1e3:.1f}")


def _fmt(x: float, digits: int = 2) -> str:
    return "-" if not np.isfinite(x) else f"{x:.{digits}f}"


def markdown_tables(report: dict[str, Any]) -> str:
    """The report as Markdown tables (overall per planner and goal kind, then per scene)."""
    lines = []
    head = ("| planner | goal | solved / valid | success | invalid returned | plan time median / mean / p75 / p98 [ms] "
            "| motion time mean [s] | path length mean [rad] | max jerk mean [rad/s^3] | max acc mean [rad/s^2] |")
    lines += [head, "|" + "---|" * 10]
    for name, p in report["planners"].items():
        for g, s in list(p["by_goal"].items()) + ([("all", p)] if len(p["by_goal"]) > 1 else []):
            pt = s["plan_time_s"]
            lines.append(
                f"| {name} | {g} | {s['solved']}/{s['valid_problems']} | {100 * s['success_rate']:.1f} % | "
                f"{s['invalid_returned']} | {_fmt_ms(pt['median'])} / {_fmt_ms(pt['mean'])} / {_fmt_ms(pt['p75'])} / "
                f"{_fmt_ms(pt['p98'])} | {_fmt(s['motion_time_s']['mean'])} | {_fmt(s['path_length_rad']['mean'])} | "
                f"{_fmt(s['max_jerk']['mean'], 0)} | {_fmt(s['max_acceleration']['mean'], 1)} |"
            )
    if report.get("ratios_vs_manip"):
        lines += ["", "| peer | goal | plan time median / manip's | p98 / manip's | motion time mean / manip's |", "|---|---|---|---|---|"]
        for name, e in report["ratios_vs_manip"].items():
            for g, r in e.items():
                lines.append(f"| {name} | {g} | {_fmt(r['median'])}x | {_fmt(r['p98'])}x | {_fmt(r['motion_time_mean'])}x |")
    lines += ["", "| planner | goal | scene | solved / valid | invalid returned | plan time median / p98 [ms] "
              "| motion time mean [s] | path length mean [rad] | max jerk mean | max acc mean |", "|" + "---|" * 10]
    for name, p in report["planners"].items():
        for g, s in p["by_goal"].items():
            for scene, sc in s["by_scene"].items():
                pt = sc["plan_time_s"]
                lines.append(
                    f"| {name} | {g} | {scene} | {sc['solved']}/{sc['valid_problems']} | {sc['invalid_returned']} | "
                    f"{_fmt_ms(pt['median'])} / {_fmt_ms(pt['p98'])} | {_fmt(sc['motion_time_s']['mean'])} | "
                    f"{_fmt(sc['path_length_rad']['mean'])} | {_fmt(sc['max_jerk']['mean'], 0)} | "
                    f"{_fmt(sc['max_acceleration']['mean'], 1)} |"
                )
    inv = report["invalid_problems"]
    lines += ["", f"Problems infeasible for the example-robot-data Panda (not planned): {inv['count']} of "
              f"{report['problems']}: " + (", ".join(f"{k}: {v}" for k, v in inv["by_reason"].items()) or "none")]
    return "\n".join(lines)


SECTION = "## Motion generation (MotionBenchMaker)"

PUBLISHED = """Published figures on the same problem family (quoted, NOT measured here; from the
dataset's README and the papers):

| system (published) | hardware | success | planning time |
|---|---|---|---|
| cuRobo v0.7.6 motion generation (MBM, 800 problems) | RTX 6000 Ada GPU | 800/800 | median 31 ms, mean 42 ms, p98 161 ms |
| cuRobo v0.6 (paper), MBM + MpiNets (2600) | RTX 4090 GPU | 99.8 % | median 30 ms, mean 50 ms, p98 260 ms; motion time mean 1.59 s, path length mean 3.28 rad, max jerk mean 49 rad/s^3, max acc mean 6.8 rad/s^2 |
| Tesseract (OMPL RRTConnect + TrajOpt), same 2600 | Ryzen 9 7950X | 98.5 % | mean 2.95 s, p98 22 s |
| VAMP RRTConnect + simplification (geometric path only, no timing) | Ryzen 9 7950X, SIMD | 800/800 | median 109 us, mean 167 us |

VAMP cannot be installed here (published only as a source package whose build downloads its
dependencies) and mplib needs numpy < 2, so neither is measured; see benchmarks/peers/README.md.
cuRobo counts a pose goal reached within 5 mm and 5 %; the verifier here asks 1 mm and 0.01 rad.
"""

METHOD = """How to read it: problems whose start or goal is infeasible for the example-robot-data Panda
(fingers open at 0.04 m; limits, self or world collision, judged by the independent verifier)
are counted and not planned; success = the planner returned a trajectory AND it passed the
independent verification (`manip/benchmarking/verify.py`: exact meshes, every sample plus
linear interpolation to <= 0.01 rad L-inf, position/velocity/acceleration limits with 1e-3
relative slack for rounding, jerk limits for planners that claim them (manip), start within
1e-6 rad, joint goal within 1e-3 rad or pose goal within 1 mm / 0.01 rad at panda_hand, at
rest at both ends). "invalid returned" = trajectories a planner returned as successful that
failed verification (counted as failures). Planning time = wall time from (start, goal) to an
executable trajectory (IK for pose goals, path, smoothing, time parameterisation), over the
verified successes; loading a scene's obstacles is not timed. Max jerk and max acceleration
are the larger of the returned arrays and divided differences of the positions (TOP-RA's
piecewise-constant accelerations make the peers' jerk a sampling-dependent metric, not a
limit they claim). Ratios are peer / manip from the same run."""


def markdown_section(report: dict[str, Any]) -> str:
    """The BENCHMARKS.md section for a report."""
    m = report["machine"]
    pk = m.get("packages", {})
    unavailable = report.get("unavailable_planners") or {}
    lines = [
        SECTION,
        "",
        f"`{report['command']}`",
        "",
        f"Machine: {m['cpu']}, {m['cores']} cores, shared with other jobs (load average at start "
        f"{', '.join(str(x) for x in m.get('load_average_at_start', []))}); Python {m['python']}; "
        + ", ".join(f"{k} {v}" for k, v in pk.items())
        + f"; commit {m.get('commit', '?')}; {report['date']}; wall time {report['wall_time_s'] / 60:.0f} min.",
        "",
        f"Problems: {report['problems']} ({report['valid_problems']} valid), goal kinds: {', '.join(report['goal_kinds'])}.",
        "",
        markdown_tables(report),
        "",
    ]
    if unavailable:
        lines += ["Planners asked for but not run: " + "; ".join(f"{k}: {v}" for k, v in unavailable.items()), ""]
    lines += [METHOD, "", PUBLISHED]
    return "\n".join(lines)


def write_markdown(report: dict[str, Any], path: Path) -> None:
    """Replace (or append) this benchmark's section of BENCHMARKS.md; other sections are kept."""
    replace_section(path, SECTION, markdown_section(report))


# ---------------------------------------------------------------------------- main
def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dataset", type=Path, default=None,
                    help=f"panda_problems.tar.bz2 (default: $MANIP_MBM_DATASET or {default_dataset_path()}); "
                         "'none' to run only --seeded problems")
    ap.add_argument("--scenes", nargs="+", default=None, help=f"MBM scenes (default: all): {' '.join(MBM_SCENES)}")
    ap.add_argument("--limit-per-scene", type=int, default=None, help="first N problems of each scene")
    ap.add_argument("--goal", choices=("joint", "pose", "both"), default="both")
    ap.add_argument("--planners", default="manip,roboplan,ompl", help="comma-separated: manip,roboplan,ompl")
    ap.add_argument("--seeded", type=int, default=0, metavar="N",
                    help=f"also run N of manip's seeded problems of each kind ({', '.join(SCENE_KINDS)})")
    ap.add_argument("--seed", type=int, default=0, help="seed of the seeded scenes and of every planner")
    ap.add_argument("--timeout", type=float, default=None, help="planning budget per problem [s] (planners' default if unset)")
    ap.add_argument("--json", type=Path, default=None, help="write the full report (and every run) here")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    ap.add_argument("--write-md", action="store_true",
                    help="replace the 'Motion generation (MotionBenchMaker)' section of BENCHMARKS.md")
    ap.add_argument("--from-json", type=Path, default=None,
                    help="do not plan: print (and with --write-md write) the report saved by --json")
    return ap.parse_args(argv)


def _no_dataset(args: argparse.Namespace) -> bool:
    return args.dataset is not None and str(args.dataset).lower() == "none"


def load_problems(args: argparse.Namespace) -> list[Any]:
    problems: list[Any] = []
    if not _no_dataset(args):
        problems += load_mbm_problems(args.dataset, scenes=args.scenes, limit_per_scene=args.limit_per_scene)
    for kind in SCENE_KINDS if args.seeded > 0 else ():
        problems += make_problems(kind, args.seeded, seed=args.seed)
    return problems


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    if args.from_json is not None:
        with open(args.from_json) as f:
            saved = json.load(f)
        print(markdown_tables(saved))
        if args.write_md:
            write_markdown(saved, ROOT / "BENCHMARKS.md")
        return 0
    machine = machine_info()  # before planning: the load average at start
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        tqdm = None

    problems = load_problems(args)
    if not problems:
        print("no problems selected", file=sys.stderr)
        return 2
    verifier = Verifier("franka")
    validity = {(p.scene, p.index): verifier.check_problem(p) for p in problems}
    valid = [p for p in problems if validity[(p.scene, p.index)].valid]
    invalid = [p for p in problems if not validity[(p.scene, p.index)].valid]
    goals = ["joint", "pose"] if args.goal == "both" else [args.goal]
    names = [n.strip() for n in args.planners.split(",") if n.strip()]

    planners, unavailable = {}, {}
    for n in names:
        try:
            planners[n] = build_planner(n, args.timeout)
        except Exception as exc:  # PeerUnavailableError, ImportError, ...
            unavailable[n] = f"{type(exc).__name__}: {exc}"
            print(f"planner {n} not run: {unavailable[n]}", file=sys.stderr)
    if not planners:
        return 2

    total = len(planners) * len(goals) * len(valid)
    bar = tqdm(total=total, unit="plan", disable=args.no_progress or tqdm is None, dynamic_ncols=True) if tqdm else None
    runs: list[Run] = []
    t_start = time.time()
    for name, planner in planners.items():
        for g in goals:
            for p in valid:
                r = run_one(planner, p, g, verifier, args.seed)
                runs.append(r)
                if bar is not None:
                    bar.set_postfix_str(f"{name} {g} {p.scene}/{p.index}", refresh=False)
                    bar.update(1)
    if bar is not None:
        bar.close()

    scenes = list(dict.fromkeys(p.scene for p in problems))
    valid_by_scene = Counter(p.scene for p in valid)
    report: dict[str, Any] = {
        "date": _dt.datetime.now().astimezone().isoformat(timespec="seconds"),
        "command": shlex.join(["python", "benchmarks/mbm.py"] + (sys.argv[1:] if argv is None else list(argv))),
        "machine": machine,
        "dataset": None if _no_dataset(args) else str(args.dataset or default_dataset_path()),
        "goal_kinds": goals,
        "problems": len(problems),
        "valid_problems": len(valid),
        "wall_time_s": time.time() - t_start,
        "invalid_problems": {
            "count": len(invalid),
            "by_scene": dict(Counter(p.scene for p in invalid)),
            "by_reason": dict(Counter(c for p in invalid for c in validity[(p.scene, p.index)].codes)),
            "problems": [{"problem": f"{p.scene}/{p.index}", "reasons": list(validity[(p.scene, p.index)].reasons)} for p in invalid],
        },
        "unavailable_planners": unavailable,
        "planners": {},
    }
    for name in planners:
        mine = [r for r in runs if r.planner == name]
        entry = summarize(mine, len(valid) * len(goals))
        entry["claims_jerk_limits"] = any(r.claims_jerk_limits for r in mine)
        entry["by_scene"] = {s: summarize([r for r in mine if r.scene == s], valid_by_scene[s] * len(goals)) for s in scenes}
        entry["by_goal"] = {}
        for g in goals:
            rg = [r for r in mine if r.goal == g]
            eg = summarize(rg, len(valid))
            eg["by_scene"] = {s: summarize([r for r in rg if r.scene == s], valid_by_scene[s]) for s in scenes}
            entry["by_goal"][g] = eg
        report["planners"][name] = entry
    report["ratios_vs_manip"] = ratios_vs_manip(report)

    print(markdown_tables(report))
    if args.json is not None:
        report["runs"] = [asdict(r) for r in runs]
        args.json.parent.mkdir(parents=True, exist_ok=True)
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1, default=float)
        print(f"\nwrote {args.json}")
    if args.write_md:
        write_markdown(report, ROOT / "BENCHMARKS.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
