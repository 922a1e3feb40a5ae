#!/usr/bin/env python3
"""Where manip's planning time goes on MotionBenchMaker: per-stage and optimiser figures, and
A/B of trajectory-optimiser settings in one run.

    python benchmarks/plan_stages.py [--limit-per-scene 10] [--scenes cage_panda ...] [--goal both]
        [--set KEY=VALUE ...] [--json OUT] [--cprofile OUT]

Plans the first N valid problems of each scene (the verifier's problem check, as
`benchmarks/mbm.py`; goal kinds joint and pose, seed 0) and reports, per plan, the main thread's
CPU time (`time.thread_time`) and the wall time, each stage's share (`PlanResult.timings`, wall),
the optimiser's QPs (count and CPU time of `planning.trajopt.qp.solve`, PIQP included), the
clearance terms' CPU time and the collision checker's (`CollisionChecker._check`).

With `--set` (`TrajOptSettings` fields, e.g. `--set tolerance=0.01 first_iterations=1`, or a
module's constant as `module:NAME=VALUE`, e.g. `--set manip.planning.path.search:MAX_REPAIRS=4`),
every plan is made twice, with the defaults and with the settings given (alternating which goes
first; the world is loaded again for each, so constants read when the world's tables are built
count too, not those read when a checker is constructed), and the report gives the ratios: CPU,
wall, QPs, identical motions, motion time / lower bound and path length / straight line per goal
kind. QP counts and motions do not depend on the machine; CPU times do (take the bench lock, note
the load). The counting wraps a few functions of manip for the run's duration (measurement
only: plans are unchanged).
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import dataclasses
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from manip import MotionGenerator, WorldConfig
from manip.benchmarking.mbm_problems import goal_pose, load_mbm_problems
from manip.benchmarking.quality import (
    lower_bound_time,
    path_length,
    straight_line_length,
)
from manip.benchmarking.verify import Verifier
from manip.collision.checker import CollisionChecker
from manip.collision.clearance import ClearanceModel
from manip.errors import InvalidInputError
from manip.planning.trajopt import qp as qp_module
from manip.planning.trajopt import refine as refine_module
from manip.planning.trajopt.settings import TrajOptSettings

#: Counters of the plan being made: name -> [calls, main-thread CPU seconds].
_COUNTERS: dict[str, list] = collections.defaultdict(lambda: [0, 0.0])


def _counted(fn, name: str):
    """fn wrapped so that its calls and CPU time add to _COUNTERS[name] (outermost call only)."""
    depth = [0]

    def wrapper(*args, **kwargs):
        if depth[0]:
            return fn(*args, **kwargs)
        depth[0] += 1
        t = time.thread_time()
        try:
            return fn(*args, **kwargs)
        finally:
            depth[0] -= 1
            c = _COUNTERS[name]
            c[0] += 1
            c[1] += time.thread_time() - t

    return wrapper


#: What is counted: (owner, attribute, counter name).
_COUNTED = ((qp_module, "solve", "qp"), (refine_module, "optimize_trajectory", "trajopt"),
            (ClearanceModel, "terms", "terms"), (CollisionChecker, "_check", "check"))


@contextlib.contextmanager
def _instrumented():
    """manip's functions of `_COUNTED` counted (restored afterwards)."""
    originals = [(owner, attr, owner.__dict__[attr]) for owner, attr, _ in _COUNTED]
    try:
        for owner, attr, name in _COUNTED:
            setattr(owner, attr, _counted(getattr(owner, attr), name))
        yield
    finally:
        for owner, attr, fn in originals:
            setattr(owner, attr, fn)


@contextlib.contextmanager
def _settings(overrides: dict, constants: dict | None = None):
    """The optimiser's default settings replaced by TrajOptSettings(**overrides) (refine's default),
    and the module constants {(module, name): value} of `constants` set (restored afterwards)."""
    original = refine_module.TrajOptSettings
    saved = [(m, k, getattr(m, k)) for m, k in (constants or {})]
    if overrides:
        refine_module.TrajOptSettings = lambda: original(**overrides)
    for (m, k), v in (constants or {}).items():
        setattr(m, k, v)
    try:
        yield
    finally:
        refine_module.TrajOptSettings = original
        for m, k, v in saved:
            setattr(m, k, v)


def parse_constant(key: str, value) -> tuple[tuple, object]:
    """`module:NAME` and its value -> ((module, NAME), value); the constant must exist."""
    import importlib

    module_name, _, name = key.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as e:
        raise InvalidInputError(f"--set {key}: no module {module_name!r} ({e})") from None
    if not name or not hasattr(module, name):
        raise InvalidInputError(f"--set {key}: module {module_name} has no constant {name!r}")
    return (module, name), value


def plan_once(mg: MotionGenerator, problem, kind: str, seed: int) -> dict:
    """One plan's row: CPU, wall, stages, counters and the motion's quality figures."""
    _COUNTERS.clear()
    c0, w0, p0 = time.thread_time(), time.perf_counter(), time.process_time()
    if kind == "joint":
        r = mg.plan_joints(problem.start, problem.goal, seed=seed)
    else:
        r = mg.plan_pose(problem.start, goal_pose(problem), link="panda_hand", seed=seed)
    row = dict(problem=f"{problem.scene}/{problem.index}", kind=kind, success=bool(r.success),
               cpu=time.thread_time() - c0, wall=time.perf_counter() - w0, process=time.process_time() - p0,
               stages=dict(r.timings),
               counters={k: list(v) for k, v in _COUNTERS.items()})
    if r.success:
        P = np.asarray(r.trajectory.positions)
        lim = mg.config.limits
        row.update(duration=float(r.trajectory.times[-1]), motion_hash=hash(P.tobytes()),
                   lower_bound=lower_bound_time(P[0], P[-1], lim.velocity, lim.acceleration, lim.jerk),
                   path=path_length(P), straight=straight_line_length(P[0], P[-1]))
    return row


def _pct(a, q) -> float:
    return float(np.percentile(a, q)) if len(a) else float("nan")


def report(rows: list[dict]) -> str:
    """The per-plan summary, the stage table and the optimiser's figures of one set of rows."""
    cpu = np.array([r["cpu"] for r in rows])
    wall = np.array([r["wall"] for r in rows])
    proc = np.array([r.get("process", np.nan) for r in rows])
    out = [f"plans {len(rows)}, solved {sum(r['success'] for r in rows)}; CPU median {np.median(cpu) * 1e3:.1f} ms, "
           f"mean {cpu.mean() * 1e3:.1f}, p98 {_pct(cpu, 98) * 1e3:.0f}; wall median {np.median(wall) * 1e3:.1f} ms, "
           f"mean {wall.mean() * 1e3:.1f}, p98 {_pct(wall, 98) * 1e3:.0f}; process CPU (all threads) median "
           f"{np.median(proc) * 1e3:.1f} ms, mean {proc.mean() * 1e3:.1f}", "",
           "| stage | share of stage time | median [ms] | p98 [ms] |", "|---|---|---|---|"]
    stages = collections.defaultdict(lambda: np.zeros(len(rows)))
    for i, r in enumerate(rows):
        for k, v in r["stages"].items():
            if k != "total":
                stages[k][i] = v
    total = sum(v.sum() for v in stages.values())
    for k, v in sorted(stages.items(), key=lambda kv: -kv[1].sum()):
        out.append(f"| {k} | {100 * v.sum() / total:.1f} % | {np.median(v) * 1e3:.2f} | {_pct(v, 98) * 1e3:.1f} |")
    qps = np.array([r["counters"].get("qp", [0, 0])[0] for r in rows])
    share = {k: sum(r["counters"].get(k, [0, 0])[1] for r in rows) / cpu.sum() for k in ("trajopt", "qp", "terms", "check")}
    qp_cpu = sum(r["counters"].get("qp", [0, 0])[1] for r in rows)
    out += ["", f"optimiser: {100 * share['trajopt']:.1f} % of the CPU time (QPs {100 * share['qp']:.1f} %, clearance "
            f"terms {100 * share['terms']:.1f} %); QPs per plan mean {qps.mean():.1f}, median {np.median(qps):.0f}, "
            f"p98 {_pct(qps, 98):.0f}; {qp_cpu / max(qps.sum(), 1) * 1e3:.2f} ms CPU per QP; collision checks "
            f"(`CollisionChecker._check`) {100 * share['check']:.1f} % of the CPU time"]
    return "\n".join(out)


def compare(a_rows: list[dict], b_rows: list[dict]) -> str:
    """B against A (the same plans): CPU, QPs, identical motions and the quality ratios."""
    both = [(a, b) for a, b in zip(a_rows, b_rows) if a["success"] and b["success"]]
    ca, cb = np.array([a["cpu"] for a in a_rows]), np.array([b["cpu"] for b in b_rows])
    wa, wb = np.array([a["wall"] for a in a_rows]), np.array([b["wall"] for b in b_rows])
    qa = sum(a["counters"].get("qp", [0, 0])[0] for a in a_rows)
    qb = sum(b["counters"].get("qp", [0, 0])[0] for b in b_rows)
    same = sum(a["motion_hash"] == b["motion_hash"] for a, b in both)
    out = [f"B / A: solved {sum(r['success'] for r in a_rows)} -> {sum(r['success'] for r in b_rows)}; identical "
           f"motions {same}/{len(both)}; CPU median {np.median(cb) / np.median(ca):.3f}, mean {cb.mean() / ca.mean():.3f}, "
           f"p98 {_pct(cb, 98) / _pct(ca, 98):.3f}; wall median {np.median(wb) / np.median(wa):.3f}, mean "
           f"{wb.mean() / wa.mean():.3f}; QPs {qb / max(qa, 1):.3f}"]
    for kind in ("joint", "pose"):
        pairs = [(a, b) for a, b in both if a["kind"] == kind]
        if not pairs:
            continue
        m = [np.mean([r["duration"] / r["lower_bound"] for r in side]) for side in zip(*pairs)]
        p = [np.mean([r["path"] / r["straight"] for r in side if r["straight"] > 1e-9]) for side in zip(*pairs)]
        out.append(f"  {kind} ({len(pairs)}): motion / lower bound {m[0]:.4f} -> {m[1]:.4f} ({m[1] / m[0] - 1:+.2%}), "
                   f"path / straight line {p[0]:.4f} -> {p[1]:.4f} ({p[1] / p[0] - 1:+.2%})")
    return "\n".join(out)


def _run(mg: MotionGenerator, problems: list, kinds: list[str], overrides: dict, seed: int, profiler,
         constants: dict | None = None) -> dict:
    """{"A": rows with the default settings, "B": rows with `overrides` and `constants` (empty
    without)}; one untimed warm-up plan per goal kind (and variant) first."""
    variants = ("A", "B") if overrides or constants else ("A",)
    for variant in variants:
        with _settings(overrides if variant == "B" else {}, constants if variant == "B" else None):
            mg.update_world(WorldConfig.from_dict(problems[0].world))
            for kind in kinds:
                plan_once(mg, problems[0], kind, seed)
    rows = {"A": [], "B": []}
    for i, p in enumerate(problems):
        if not constants:
            mg.update_world(WorldConfig.from_dict(p.world))
        for kind in kinds:
            order = variants if i % 2 == 0 else variants[::-1]
            for variant in order:
                with _settings(overrides if variant == "B" else {}, constants if variant == "B" else None):
                    if constants:  # the tables are built with the variant's constants
                        mg.update_world(WorldConfig.from_dict(p.world))
                    if profiler is not None and variant == "A":
                        profiler.enable()
                    rows[variant].append(plan_once(mg, p, kind, seed))
                    if profiler is not None:
                        profiler.disable()
    return rows


def parse_args(argv=None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit-per-scene", type=int, default=10, help="first N problems of each scene (before the check)")
    ap.add_argument("--scenes", nargs="*", default=None, help="MBM scenes (default: all)")
    ap.add_argument("--goal", choices=("joint", "pose", "both"), default="both")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                    help="TrajOptSettings fields or module:CONSTANT values of variant B (Python literals); every "
                         "plan is made with both")
    ap.add_argument("--json", default=None, help="write every row here")
    ap.add_argument("--cprofile", default=None, help="write a cProfile of the planning here (default settings only)")
    return ap.parse_args(argv)


def main(argv=None) -> int:
    import ast

    args = parse_args(argv)
    overrides, constants = {}, {}
    names = [f.name for f in dataclasses.fields(TrajOptSettings)]
    for kv in args.set:
        key, _, value = kv.partition("=")
        if ":" in key:
            k, v = parse_constant(key, ast.literal_eval(value))
            constants[k] = v
            continue
        if key not in names:
            raise InvalidInputError(f"--set {kv!r}: {key!r} is not a TrajOptSettings field ({', '.join(names)})")
        overrides[key] = ast.literal_eval(value)
    TrajOptSettings(**overrides)  # a bad field or value fails here, with its own message
    mg = MotionGenerator("franka")
    verifier = Verifier(mg.config)
    problems = [p for p in load_mbm_problems(limit_per_scene=args.limit_per_scene)
                if (args.scenes is None or p.scene in args.scenes) and verifier.check_problem(p).valid]
    kinds = ["joint", "pose"] if args.goal == "both" else [args.goal]
    if not problems:
        print("no valid problems selected", file=sys.stderr)
        return 2
    profiler = None
    if args.cprofile:
        import cProfile

        profiler = cProfile.Profile()
    load = os.getloadavg()
    with _instrumented():
        rows = _run(mg, problems, kinds, overrides, args.seed, profiler, constants)
    print(f"load average at start {load[0]:.2f}, at end {os.getloadavg()[0]:.2f}; {len(problems)} valid problems, "
          f"goals {', '.join(kinds)}")
    print(report(rows["A"]))
    if overrides or constants:
        print(f"\nB = TrajOptSettings({', '.join(f'{k}={v!r}' for k, v in overrides.items())})"
              + "".join(f", {m.__name__}.{k} = {v!r}" for (m, k), v in constants.items()))
        print(report(rows["B"]))
        print()
        print(compare(rows["A"], rows["B"]))
    if args.json:
        Path(args.json).write_text(json.dumps(dict(load=load, overrides=overrides, rows=rows,
                                                   constants={f"{m.__name__}:{k}": v for (m, k), v in constants.items()}),
                                              default=str))
    if profiler is not None:
        profiler.dump_stats(args.cprofile)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
