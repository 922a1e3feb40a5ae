#!/usr/bin/env python3
"""Where manip's planning time goes on MotionBenchMaker: per-stage and optimiser figures, and
A/B of trajectory-optimiser settings in one run.

    python benchmarks/plan_stages.py [--limit-per-scene 10] [--scenes cage_panda ...] [--goal both]
        [--set KEY=VALUE ... | --tree OTHER_CHECKOUT] [--json OUT] [--cprofile OUT] [--trajopt-table]
        [--search-table]

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
kind. `--tree PATH` makes variant B the manip of another checkout instead (this script in a worker
process with that tree first on the path; the plans alternate between the two processes): an A/B of
code. QP counts and motions do not depend on the machine; CPU times do (take the bench lock, note
the load). The counting wraps a few functions of manip for the run's duration (measurement
only: plans are unchanged).

`--trajopt-table` accounts for all of the optimiser stage's CPU time (`refine.refine` but its
certified validation): each part's exclusive main-thread CPU time (PIQP's setup and solve, the
QP's assembly, the clearance terms' FK and nearest balls, the merit, the fit, ..., and the
Python glue of the SCO loops as the rest), and what each optimiser call of a plan came to.

`--search-table` gives the search's machine-independent counts per scene (RRT-Connect iterations of
the plan's searches and of its detour restarts, coarse and fine-repair, the restart searches that
found a path and the plans whose path they replaced, the checker's calls and configurations) and
the same per plan for the plans of the CPU p98 (the tail).
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import dataclasses
import hashlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

#: The checkout whose manip is measured: this one, or another for a `--tree` worker.
sys.path.insert(0, os.environ.get("PLAN_STAGES_TREE") or str(Path(__file__).resolve().parents[1]))

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
from manip.collision.state import CollisionState
from manip.errors import InvalidInputError
from manip.planning import pipeline as pipeline_module
from manip.planning.path import restarts as restarts_module
from manip.planning.path import search as search_module
from manip.planning.trajopt import bspline as bspline_module
from manip.planning.trajopt import optimizer as optimizer_module
from manip.planning.trajopt import qp as qp_module
from manip.planning.trajopt import refine as refine_module
from manip.planning.trajopt import sco as sco_module
from manip.planning.trajopt.settings import TrajOptSettings
from manip.trajectory import Trajectory

#: Counters of the plan being made: name -> [calls, main-thread CPU seconds].
_COUNTERS: dict[str, list] = collections.defaultdict(lambda: [0, 0.0])


def _counted(fn, name: str, amount=None):
    """fn wrapped so that its calls and CPU time add to _COUNTERS[name] (outermost call only);
    with `amount(args, kwargs, result) -> {counter: number}`, those numbers add to the counters too."""
    depth = [0]

    def wrapper(*args, **kwargs):
        if depth[0]:
            return fn(*args, **kwargs)
        depth[0] += 1
        t = time.thread_time()
        result = None
        try:
            result = fn(*args, **kwargs)
            return result
        finally:
            depth[0] -= 1
            c = _COUNTERS[name]
            c[0] += 1
            c[1] += time.thread_time() - t
            if amount is not None:
                for k, v in amount(args, kwargs, result).items():
                    _COUNTERS[k][0] += v

    return wrapper


def _rrt_phase(args, kwargs, result) -> dict:
    """RRT-Connect's iterations, by phase: the coarse search (its `motion_valid` is the search
    resolution's) or a fine repair; inside a detour restart's search, the restart's."""
    phase = "coarse" if getattr(args[4], "__name__", "") == "coarse_motion" else "repair"
    where = "restart" if _IN_RESTART[0] else "search"
    return {f"rrt_{where}_{phase}": result[1], f"rrt_{where}_{phase}_calls": 1}


_IN_RESTART = [False]  # True while a detour restart's search runs
_RESTARTS: list[str] = []  # the outcomes of the plan's restart searches, in order


def _restart_search(fn):
    """`restarts.search_path` counted ("restart_searches", "restart_found": those that found a
    path) and flagged (the RRT iterations inside count as the restarts')."""

    def wrapper(*args, **kwargs):
        _COUNTERS["restart_searches"][0] += 1
        _IN_RESTART[0] = True
        try:
            result = fn(*args, **kwargs)
        finally:
            _IN_RESTART[0] = False
        _COUNTERS["restart_found"][0] += result[0] is not None
        _RESTARTS.append("found" if result[0] is not None else "none")
        return result

    return wrapper


#: What is counted: (owner, attribute, counter name, amount or None).
_COUNTED = ((qp_module, "solve", "qp", None), (refine_module, "optimize_trajectory", "trajopt", None),
            (ClearanceModel, "terms", "terms", None),
            (CollisionChecker, "_check", "check", lambda a, k, r: {"configs": len(a[1])}),
            (search_module, "rrt_connect", "rrt", _rrt_phase))
if hasattr(CollisionChecker, "_collides_given"):  # the compiled search's exact checks (one configuration each)
    _COUNTED += ((CollisionChecker, "_collides_given", "check", lambda a, k, r: {"configs": 1}),)


def _restarts_kept(fn):
    """`pipeline.shorter_way_round` counted: "restart_kept" when it returns a new path."""

    def wrapper(path, *args, **kwargs):
        out = fn(path, *args, **kwargs)
        _COUNTERS["restart_kept"][0] += out is not path
        return out

    return wrapper


@contextlib.contextmanager
def _instrumented():
    """manip's functions of `_COUNTED` counted, the restarts' searches flagged (restored afterwards)."""
    originals = [(owner, attr, owner.__dict__[attr]) for owner, attr, _, _ in _COUNTED]
    originals.append((restarts_module, "search_path", restarts_module.search_path))
    originals.append((pipeline_module, "shorter_way_round", pipeline_module.shorter_way_round))
    try:
        for owner, attr, name, amount in _COUNTED:
            setattr(owner, attr, _counted(getattr(owner, attr), name, amount))
        restarts_module.search_path = _restart_search(restarts_module.search_path)
        pipeline_module.shorter_way_round = _restarts_kept(pipeline_module.shorter_way_round)
        yield
    finally:
        for owner, attr, fn in originals:
            setattr(owner, attr, fn)


#: The optimiser stage's parts (`--trajopt-table`): (owner, attribute, part). The root is
#: `refine.refine`; a part's time excludes the parts called inside it; "glue" is what is left of
#: the root and of the SCO loops themselves.
_TRAJOPT_PARTS = (
    (pipeline_module, "refine", "glue (refine, SCO loops)"),
    (refine_module, "validate_trajectory", "validate (certificate; not the trajopt stage)"),
    (optimizer_module, "sco_fixed_step", "glue (refine, SCO loops)"),
    (optimizer_module, "sco_free_step", "glue (refine, SCO loops)"),
    (qp_module, "inequality_rows", "QP assembly: inequality rows"),
    (qp_module, "csc_of_transpose", "QP assembly: inequality rows"),  # before issue 33's round three
    (qp_module, "solve", "QP: PIQP's solver object, settings, result"),
    (qp_module, "regularised", "QP assembly"),
    (qp_module, "with_columns", "QP assembly"),
    (sco_module, "_solve_qp", "QP assembly"),
    (sco_module.SplineProblem, "ray_rows", "QP assembly"),
    (sco_module, "_collision_rows", "QP rows: clearance, limits, objective"),
    (sco_module, "_csc", "QP rows: clearance, limits, objective"),
    (sco_module, "_limit_rows", "QP rows: clearance, limits, objective"),  # before issue 33's round three
    (sco_module, "_row_limits", "QP rows: clearance, limits, objective"),
    (sco_module, "_objective", "QP rows: clearance, limits, objective"),
    (ClearanceModel, "terms", "clearance terms: nearest balls, gradients"),
    (CollisionState, "joint_transforms", "clearance terms: FK of the samples"),
    (sco_module, "_merit", "merit and clearance floor"),
    (sco_module, "_polygon_step", "merit and clearance floor"),
    (sco_module, "_violation", "merit and clearance floor"),
    (sco_module, "_min_distance", "merit and clearance floor"),
    (bspline_module, "control_from_samples", "fit of the seed"),
    (optimizer_module, "_end_directions", "end rays (directions, projection)"),
    (sco_module.SplineProblem, "project_rays", "end rays (directions, projection)"),
    (sco_module.SplineProblem, "__init__", "problem setup (SplineProblem)"),
    (optimizer_module, "_check_seed", "problem setup (SplineProblem)"),
    (bspline_module, "limit_step", "re-time and sample the result"),
    (bspline_module, "to_profile", "re-time and sample the result"),
    (Trajectory, "from_profile", "re-time and sample the result"),
)
_PARTS_CPU: dict[str, float] = collections.defaultdict(float)
_PARTS_CALLS: dict[str, int] = collections.defaultdict(int)
_STACK: list = []  # [part, start CPU, CPU of the parts called inside]


def _part(fn, name: str, root: bool):
    """fn wrapped so that its exclusive CPU time adds to _PARTS_CPU[name] (inside the root only)."""

    def wrapper(*args, **kwargs):
        if (not _STACK and not root) or (_STACK and _STACK[-1][0].startswith("validate")):
            return fn(*args, **kwargs)  # outside the stage, or inside the certificate (its own part)
        frame = [name, time.thread_time(), 0.0]
        _STACK.append(frame)
        try:
            return fn(*args, **kwargs)
        finally:
            _STACK.pop()
            elapsed = time.thread_time() - frame[1]
            _PARTS_CPU[name] += elapsed - frame[2]
            _PARTS_CALLS[name] += 1
            if _STACK:
                _STACK[-1][2] += elapsed

    return wrapper


class _TimedSolver:
    """A PIQP SparseSolver whose setup and solve are timed as parts."""

    def __init__(self, solver):
        self._solver = solver
        self.settings = solver.settings
        self.setup = _part(solver.setup, "PIQP setup", False)
        self.solve = _part(solver.solve, "PIQP solve", False)

    @property
    def result(self):
        return self._solver.result


class _TimedPiqp:
    """`piqp` as `qp.solve` uses it, its SparseSolver's setup and solve timed as parts."""

    def __init__(self, piqp):
        self.PIQP_SOLVED = piqp.PIQP_SOLVED
        self._piqp = piqp

    def SparseSolver(self):  # noqa: N802 (piqp's name)
        return _TimedSolver(self._piqp.SparseSolver())


@contextlib.contextmanager
def _trajopt_parts():
    """The parts of `_TRAJOPT_PARTS` and PIQP's calls timed (restored afterwards)."""
    parts = [(owner, attr, name) for owner, attr, name in _TRAJOPT_PARTS if attr in owner.__dict__]  # (older trees)
    originals = [(owner, attr, owner.__dict__[attr]) for owner, attr, _ in parts]
    piqp = qp_module.piqp
    try:
        for i, (owner, attr, name) in enumerate(parts):
            fn = owner.__dict__[attr]
            if isinstance(fn, classmethod):
                setattr(owner, attr, classmethod(_part(fn.__func__, name, False)))
            else:
                setattr(owner, attr, _part(fn, name, i == 0))
        qp_module.piqp = _TimedPiqp(piqp)
        yield
    finally:
        qp_module.piqp = piqp
        for owner, attr, fn in originals:
            setattr(owner, attr, fn)


def trajopt_table(rows: list[dict]) -> str:
    """The optimiser stage's CPU by part, over the plans of `rows` (their "parts" counters)."""
    cpu = collections.defaultdict(float)
    calls = collections.defaultdict(int)
    for r in rows:
        for k, (n, t) in r.get("parts", {}).items():
            cpu[k] += t
            calls[k] += n
    total_plans = sum(r["cpu"] for r in rows)
    stage = sum(v for k, v in cpu.items() if not k.startswith("validate"))
    n = max(len(rows), 1)
    out = [f"optimiser stage (refine but its validation): {stage * 1e3 / n:.2f} ms CPU per plan, "
           f"{100 * stage / total_plans:.1f} % of the plans' CPU", "",
           "| part | share of the stage | per plan [ms] | calls per plan |", "|---|---|---|---|"]
    for k, v in sorted(cpu.items(), key=lambda kv: -kv[1]):
        share = "" if k.startswith("validate") else f"{100 * v / stage:.1f} %"
        out.append(f"| {k} | {share} | {v * 1e3 / n:.2f} | {calls[k] / n:.1f} |")
    runs = [r["counters"].get("trajopt", [0, 0]) for r in rows]
    qps = [r["counters"].get("qp", [0, 0])[0] for r in rows]
    used = [r.get("source") == "trajopt" for r in rows]
    out += ["", f"optimiser calls per plan {np.mean([c[0] for c in runs]):.2f} (plans with 2+: "
            f"{sum(c[0] > 1 for c in runs)}/{len(rows)}); the optimiser's motion returned in {sum(used)}/{len(rows)} "
            f"plans; QPs of plans whose motion is not the optimiser's: {sum(q for q, u in zip(qps, used) if not u)} "
            f"of {sum(qps)}"]
    return "\n".join(out)


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
    _RESTARTS.clear()
    _PARTS_CPU.clear()
    _PARTS_CALLS.clear()
    c0, w0, p0 = time.thread_time(), time.perf_counter(), time.process_time()
    if kind == "joint":
        r = mg.plan_joints(problem.start, problem.goal, seed=seed)
    else:
        r = mg.plan_pose(problem.start, goal_pose(problem), link="panda_hand", seed=seed)
    row = dict(problem=f"{problem.scene}/{problem.index}", kind=kind, success=bool(r.success),
               cpu=time.thread_time() - c0, wall=time.perf_counter() - w0, process=time.process_time() - p0,
               stages=dict(r.timings),
               counters={k: list(v) for k, v in _COUNTERS.items()}, restarts=list(_RESTARTS),
               parts={k: [_PARTS_CALLS[k], v] for k, v in _PARTS_CPU.items()})
    if r.success:
        P = np.asarray(r.trajectory.positions)
        lim = mg.config.limits
        row.update(source=r.source, duration=float(r.trajectory.times[-1]),
                   motion_hash=hashlib.sha1(P.tobytes()).hexdigest(),  # the same in any process
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


def _count(row: dict, *names: str) -> int:
    return sum(row["counters"].get(k, [0, 0])[0] for k in names)


_SEARCH = ("rrt_search_coarse", "rrt_search_repair")
_RESTART = ("rrt_restart_coarse", "rrt_restart_repair")


def search_table(rows: list[dict], tail: float = 98.0) -> str:
    """Per scene: CPU median / p98, the search's machine-independent counts per plan (RRT
    iterations of the searches and of the detour restarts, restart searches, checker calls and
    configurations checked, QPs), and the plans at or above the `tail` percentile of CPU."""
    out = ["| scene | plans | CPU median / p98 [ms] | RRT its search (coarse + repair) mean / p98 | restart searches "
           "(found, path kept) | restart its mean / p98 | checker calls mean | configs checked mean | QPs mean |",
           "|---|---|---|---|---|---|---|---|---|"]
    by_scene = collections.defaultdict(list)
    for r in rows:
        by_scene[r["problem"].split("/")[0]].append(r)
    for scene, rs in sorted(by_scene.items()):
        cpu = np.array([r["cpu"] for r in rs]) * 1e3
        its = np.array([_count(r, *_SEARCH) for r in rs])
        rit = np.array([_count(r, *_RESTART) for r in rs])
        out.append(f"| {scene} | {len(rs)} | {np.median(cpu):.0f} / {_pct(cpu, 98):.0f} | {its.mean():.0f} / "
                   f"{_pct(its, 98):.0f} | {sum(_count(r, 'restart_searches') for r in rs)} ({sum(_count(r, 'restart_found') for r in rs)}, "
                   f"{sum(_count(r, 'restart_kept') for r in rs)}) | {rit.mean():.0f} / "
                   f"{_pct(rit, 98):.0f} | {np.mean([_count(r, 'check') for r in rs]):.0f} | "
                   f"{np.mean([_count(r, 'configs') for r in rs]):.0f} | {np.mean([_count(r, 'qp') for r in rs]):.1f} |")
    cut = _pct([r["cpu"] for r in rows], tail)
    top = sorted((r for r in rows if r["cpu"] >= cut), key=lambda r: -r["cpu"])
    out += ["", f"plans at or above the CPU p{tail:g} ({cut * 1e3:.0f} ms): {len(top)}", "",
            "| plan | goal | CPU [ms] | search / restarts / trajopt [ms] | RRT its search coarse + repair | restart "
            "searches (found, kept): its coarse + repair | QPs | configs checked |", "|---|---|---|---|---|---|---|---|"]
    for r in top:
        st = r["stages"]
        out.append(f"| {r['problem']} | {r['kind']} | {r['cpu'] * 1e3:.0f} | {st.get('plan', 0) * 1e3:.0f} / "
                   f"{st.get('restarts', 0) * 1e3:.0f} / {st.get('trajopt', 0) * 1e3:.0f} | "
                   f"{_count(r, 'rrt_search_coarse')} + {_count(r, 'rrt_search_repair')} | "
                   f"{_count(r, 'restart_searches')} ({_count(r, 'restart_found')}, {_count(r, 'restart_kept')}): "
                   f"{_count(r, 'rrt_restart_coarse')} + "
                   f"{_count(r, 'rrt_restart_repair')} | {_count(r, 'qp')} | {_count(r, 'configs')} |")
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


class _TreeWorker:
    """Variant B planned by another checkout's manip: this script in a worker process (`--worker`)
    with that tree first on the path, asked for one plan at a time."""

    def __init__(self, tree: str, args: argparse.Namespace):
        cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "--limit-per-scene",
               str(args.limit_per_scene), "--seed", str(args.seed)] + (["--scenes", *args.scenes] if args.scenes else [])
        env = dict(os.environ, PLAN_STAGES_TREE=str(Path(tree).resolve()), PYTHONPATH=str(Path(tree).resolve()))
        self.proc = subprocess.Popen(cmd + (["--trajopt-table"] if args.trajopt_table else []), env=env,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        self.problems = json.loads(self.proc.stdout.readline())  # after its warm-up plans

    def plan(self, index: int, kind: str) -> dict:
        self.proc.stdin.write(f"{index} {kind}\n")
        self.proc.stdin.flush()
        return json.loads(self.proc.stdout.readline())

    def close(self) -> None:
        self.proc.stdin.close()
        self.proc.wait()


def _serve(mg: MotionGenerator, problems: list, args: argparse.Namespace) -> int:
    """`--worker`: plans the problems asked for on stdin ("index kind" lines), one JSON row per line."""
    mg.update_world(WorldConfig.from_dict(problems[0].world))
    for kind in ("joint", "pose"):
        plan_once(mg, problems[0], kind, args.seed)
    print(json.dumps(len(problems)), flush=True)
    current = None
    with _instrumented(), (_trajopt_parts() if args.trajopt_table else contextlib.nullcontext()):
        for line in sys.stdin:
            index, kind = line.split()
            if current != index:
                mg.update_world(WorldConfig.from_dict(problems[int(index)].world))
                current = index
            print(json.dumps(plan_once(mg, problems[int(index)], kind, args.seed), default=str), flush=True)
    return 0


def _run(mg: MotionGenerator, problems: list, kinds: list[str], overrides: dict, seed: int, profiler,
         constants: dict | None = None, worker: _TreeWorker | None = None) -> dict:
    """{"A": rows with the default settings, "B": rows with `overrides` and `constants`, or of
    `worker`'s tree (empty without)}; one untimed warm-up plan per goal kind (and variant) first."""
    variants = ("A", "B") if overrides or constants or worker else ("A",)
    for variant in variants[: 1 if worker else 2]:
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
                if worker is not None and variant == "B":
                    rows["B"].append(worker.plan(i, kind))
                    continue
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
    ap.add_argument("--tree", default=None, help="variant B: the manip of this other checkout (an A/B of code)")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)  # `--tree`'s worker process
    ap.add_argument("--trajopt-table", action="store_true",
                    help="account for the optimiser stage's CPU by part (PIQP, assembly, clearance terms, ...)")
    ap.add_argument("--search-table", action="store_true",
                    help="per scene: the search's counts (RRT iterations, restarts, checker calls, configurations) "
                         "and the plans of the CPU p98")
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
    if args.tree and (overrides or constants):
        raise InvalidInputError("--tree and --set: one B variant at a time")
    if args.tree and not (Path(args.tree) / "manip" / "__init__.py").is_file():
        raise InvalidInputError(f"--tree {args.tree!r}: not a checkout of manip (no manip/__init__.py there)")
    mg = MotionGenerator("franka")
    verifier = Verifier(mg.config)
    problems = [p for p in load_mbm_problems(limit_per_scene=args.limit_per_scene)
                if (args.scenes is None or p.scene in args.scenes) and verifier.check_problem(p).valid]
    kinds = ["joint", "pose"] if args.goal == "both" else [args.goal]
    if not problems:
        print("no valid problems selected", file=sys.stderr)
        return 2
    if args.worker:
        return _serve(mg, problems, args)
    worker = _TreeWorker(args.tree, args) if args.tree else None
    profiler = None
    if args.cprofile:
        import cProfile

        profiler = cProfile.Profile()
    load = os.getloadavg()
    try:
        with _instrumented(), (_trajopt_parts() if args.trajopt_table else contextlib.nullcontext()):
            rows = _run(mg, problems, kinds, overrides, args.seed, profiler, constants, worker)
    finally:
        if worker is not None:
            worker.close()
    print(f"load average at start {load[0]:.2f}, at end {os.getloadavg()[0]:.2f}; {len(problems)} valid problems, "
          f"goals {', '.join(kinds)}")
    print(report(rows["A"]))
    if args.search_table:
        print("\n" + search_table(rows["A"]))
    if args.trajopt_table:
        print("\n" + trajopt_table(rows["A"]))
    if overrides or constants or worker:
        print(f"\nB = the manip of {Path(args.tree).resolve()}" if worker else
              f"\nB = TrajOptSettings({', '.join(f'{k}={v!r}' for k, v in overrides.items())})"
              + "".join(f", {m.__name__}.{k} = {v!r}" for (m, k), v in constants.items()))
        print(report(rows["B"]))
        if args.search_table:
            print("\n" + search_table(rows["B"]))
        if args.trajopt_table:
            print("\n" + trajopt_table(rows["B"]))
        print()
        print(compare(rows["A"], rows["B"]))
    if args.json:
        Path(args.json).write_text(json.dumps(dict(load=load, overrides=overrides, tree=args.tree, rows=rows,
                                                   constants={f"{m.__name__}:{k}": v for (m, k), v in constants.items()}),
                                              default=str))
    if profiler is not None:
        profiler.dump_stats(args.cprofile)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
