#!/usr/bin/env python3
"""MotionBenchMaker benchmark: manip and its peers, side by side, every trajectory verified.

    python benchmarks/mbm.py [--dataset benchmarks/data/mbm/panda_problems.tar.bz2] \\
        [--scenes box_panda cage_panda ...] [--limit-per-scene N] [--goal joint|pose|both] \\
        [--planners manip,roboplan,ompl] [--seeded N] [--timeout S] [--json OUT] \\
        [--curobo-limits] [--smoothness time_optimal|smooth] [--no-trajopt] [--label NAME] [--write-md]
    python benchmarks/mbm.py --from-json before.json after.json [--write-md]

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
4. Measures the quality of every returned trajectory (`manip.benchmarking.quality`): motion
   time, the problem's lower bound (ruckig's time-optimal rest-to-rest motion from the start
   to the goal configuration, for pose goals to the configuration the trajectory reached,
   under the limits the planner was given; infinite jerk for planners that do not limit
   jerk), motion time / lower bound, path length, path length / straight-line length, max
   jerk, max acceleration.
5. Reports per planner, per goal kind and per scene: success rate, invalid returned,
   planning time (median, mean, p75, p98 over the verified successes), mean motion time,
   mean lower bound, their ratio of means and the mean of the per-problem ratios, the same
   for path length against the straight line, mean max jerk and max acceleration; and,
   when manip ran with peers, the peers' median and p98 planning times as ratios to manip's.

Options for before/after and like-for-like rows: `--label NAME` names a run's rows
"manip (NAME)"; `--from-json A.json B.json ...` merges saved reports into one set of
tables (and with `--write-md` writes them to BENCHMARKS.md); `--curobo-limits` gives every
planner cuRobo's franka.yml limits (acceleration 15 rad/s^2 and jerk 500 rad/s^3 on every
joint, URDF velocities) and verifies and bounds with them; `--smoothness` is passed to
manip's plan calls as `smoothness=...` (only when given).
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime as _dt
import json
import logging
import math
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

from manip.benchmarking.mbm_problems import MBM_SCENES, default_dataset_path, goal_pose, load_mbm_problems  # noqa: E402
from manip.benchmarking.quality import (  # noqa: E402
    lower_bound_time,
    max_jerk,
    safe_ratio,
    straight_line_length,
)
from manip.benchmarking.scenes import SCENE_KINDS, make_problems  # noqa: E402
from manip.benchmarking.verify import Verifier  # noqa: E402
from manip.errors import InvalidInputError  # noqa: E402
from manip.limits import JointLimits  # noqa: E402
from manip.robot_config import RobotConfig, load_robot_config  # noqa: E402

log = logging.getLogger("benchmarks.mbm")

#: Metrics summarised (mean, median, p75, p98, max) over the verified successes.
METRICS = (
    "plan_time_s",
    "motion_time_s",
    "lower_bound_s",
    "motion_time_ratio",
    "path_length_rad",
    "straight_line_rad",
    "path_length_ratio",
    "max_jerk",
    "max_jerk_returned",
    "max_acceleration",
)

#: cuRobo's franka.yml limits (`--curobo-limits`): every joint [rad/s^2], [rad/s^3].
CUROBO_ACCELERATION = 15.0
CUROBO_JERK = 500.0
#: Default row label of a `--curobo-limits` run without `--label`.
CUROBO_LABEL = "cuRobo limits"


@dataclass
class Run:
    """One planner on one problem and goal kind.

    Quality fields are nan when there is no trajectory (and, except the joint-goal lower
    bound, when there is none to measure). Units: seconds, radians, rad/s^2, rad/s^3.
    """

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
    #: ruckig's time-optimal rest-to-rest duration from the start to the goal configuration
    #: (pose goals: to the trajectory's last position) under the planner's limits [s].
    lower_bound_s: float = float("nan")
    #: motion_time_s / lower_bound_s (nan when the bound is 0).
    motion_time_ratio: float = float("nan")
    path_length_rad: float = float("nan")
    #: joint-space L2 distance from the start to the same goal configuration [rad].
    straight_line_rad: float = float("nan")
    #: path_length_rad / straight_line_rad.
    path_length_ratio: float = float("nan")
    #: max |jerk| over samples and joints, the larger of the returned jerks and third divided
    #: differences of the positions (the verifier's figure; the one in the tables).
    max_jerk: float = float("nan")
    #: max |jerk| of the returned jerk samples alone (`quality.max_jerk`).
    max_jerk_returned: float = float("nan")
    max_acceleration: float = float("nan")
    max_velocity_ratio: float = float("nan")
    max_acceleration_ratio: float = float("nan")
    max_jerk_ratio: float = float("nan")
    claims_jerk_limits: bool = False
    reasons: list[str] = field(default_factory=list)
    #: the planner's own per-stage wall times [s] (e.g. manip's `PlanResult.timings`).
    stage_times_s: dict[str, float] = field(default_factory=dict)


# ---------------------------------------------------------------------------- limits
# A planner's limits (what it is verified and bounded with) are a `manip.JointLimits`.
def same_limits(a: JointLimits, b: JointLimits) -> bool:
    """Whether two planners were given the same velocity, acceleration and jerk limits."""
    return all(np.allclose(x, y) for x, y in ((a.velocity, b.velocity), (a.acceleration, b.acceleration),
                                              (a.jerk, b.jerk)))


def limits_dict(limits: JointLimits) -> dict[str, list[float]]:
    """The velocity, acceleration and jerk limits as lists (for the JSON report)."""
    return {"velocity": limits.velocity.tolist(), "acceleration": limits.acceleration.tolist(),
            "jerk": limits.jerk.tolist()}


def benchmark_config(curobo_limits: bool = False, robot: str = "franka") -> RobotConfig:
    """The robot configuration every planner gets: robot.yaml's, or with cuRobo's limits.

    With `curobo_limits` the acceleration limit is `CUROBO_ACCELERATION` and the jerk limit
    `CUROBO_JERK` on every joint (cuRobo's franka.yml); velocities stay the URDF's.
    """
    cfg = load_robot_config(robot)
    if curobo_limits:
        cfg = dataclasses.replace(
            cfg,
            acceleration_limits=np.full(cfg.dof, CUROBO_ACCELERATION),
            jerk_limits=np.full(cfg.dof, CUROBO_JERK),
        )
    return cfg


# ---------------------------------------------------------------------------- planners
def build_planner(name: str, timeout: float | None, config: RobotConfig | None = None,
                  plan_options: dict[str, Any] | None = None) -> Any:
    """A planner object with `.name` and `.plan(problem, goal_kind, seed)`.

    Args:
        name: "manip" or a peer name (`benchmarks.peers.PEER_NAMES`).
        timeout: planning budget per problem [s] (None: the planner's default).
        config: robot configuration (its limits) to plan with; None: robot.yaml's. A peer
            that takes no `config` is built without it (the driver marks its rows).
        plan_options: options of manip's plan calls (e.g. {"smoothness": "smooth"}); manip
            tries them when built, so an unknown option raises InvalidInputError here.
    """
    if name == "manip":
        from benchmarks.planners.manip_planner import ManipPlanner

        return ManipPlanner(time_budget=timeout, robot=config if config is not None else "franka",
                            plan_options=plan_options)
    from benchmarks.peers import get_peer

    opts: dict[str, Any] = {}
    if config is not None:
        opts["config"] = config
    if timeout is not None:
        opts["timeout_s"] = timeout
    while True:
        try:
            return get_peer(name, **opts)
        except TypeError:
            if not opts:
                raise
            dropped = "config" if "config" in opts else "timeout_s"
            log.warning("peer %s takes no %s option; built without it", name, dropped)
            opts.pop(dropped)


def planner_limits(planner: Any, default: JointLimits) -> JointLimits:
    """The limits a built planner actually plans with (its `config`), else `default`."""
    cfg = getattr(planner, "config", None)
    return cfg.limits if isinstance(cfg, RobotConfig) else default


def _quality(run: Run, start: np.ndarray, target: np.ndarray | None, limits: JointLimits, jerk_limited: bool) -> None:
    """Fill the lower bound, straight-line length and their ratios of `run` (in place)."""
    if target is None:
        return
    jmax = limits.jerk if jerk_limited else math.inf
    try:
        run.lower_bound_s = lower_bound_time(start, target, limits.velocity, limits.acceleration, jmax)
    except Exception as exc:  # never end the benchmark over a metric
        log.warning("lower bound failed on %s/%d: %s", run.scene, run.index, exc)
    run.straight_line_rad = straight_line_length(start, target)
    run.motion_time_ratio = safe_ratio(run.motion_time_s, run.lower_bound_s)
    run.path_length_ratio = safe_ratio(run.path_length_rad, run.straight_line_rad)


def run_one(planner: Any, problem: Any, goal: str, verifier: Verifier, seed: int, limits: JointLimits | None = None) -> Run:
    """Plan one problem with one planner, verify the result and measure its quality.

    Args:
        limits: the limits the planner was given (default: the verifier's robot config's);
            the trajectory is verified against them and the lower bound computed with them
            (jerk only for planners that claim jerk limits, infinite otherwise).
    """
    if limits is None:
        limits = verifier.config.limits
    start = np.asarray(problem.start, dtype=float)
    try:
        out = planner.plan(problem, goal, seed=seed)
    except Exception as exc:  # a planner bug must not end the benchmark; it is reported
        log.exception("%s raised on %s/%d (%s goal)", planner.name, problem.scene, problem.index, goal)
        return Run(planner.name, goal, problem.scene, problem.index, f"ERROR: {type(exc).__name__}: {exc}",
                   False, False, float("nan"), reasons=[f"exception: {exc}"])
    run = Run(planner.name, goal, problem.scene, problem.index, str(out.status), bool(out.success), False,
              float(out.plan_time_s), setup_time_s=float(getattr(out, "setup_time_s", float("nan"))))
    run.claims_jerk_limits = bool(getattr(out, "claims_jerk_limits", False))
    run.stage_times_s = {k: float(v) for k, v in (getattr(out, "stage_times_s", None) or {}).items()}
    if not out.success or out.positions is None or out.times is None:
        if out.success:
            run.reasons = ["claimed success without a trajectory"]
        if goal == "joint":  # the bound is defined without a trajectory
            _quality(run, start, np.asarray(problem.goal, dtype=float), limits, run.claims_jerk_limits)
        return run
    t0 = time.perf_counter()
    kwargs: dict[str, Any] = {"check_jerk": bool(out.claims_jerk_limits), "velocity_limits": limits.velocity,
                              "acceleration_limits": limits.acceleration, "jerk_limits": limits.jerk}
    if goal == "pose":
        kwargs["goal_pose"] = goal_pose(problem)
    v = verifier.verify_trajectory(problem, out.times, out.positions, out.velocities, out.accelerations, out.jerks, **kwargs)
    run.verify_time_s = time.perf_counter() - t0
    run.verified = v.valid
    run.reasons = list(v.reasons)
    run.motion_time_s = v.motion_time
    run.path_length_rad = v.path_length
    run.max_jerk = v.max_jerk
    run.max_jerk_returned = max_jerk(out.jerks) if out.jerks is not None else float("nan")
    run.max_acceleration = v.max_acceleration
    run.max_velocity_ratio = v.max_velocity_ratio
    run.max_acceleration_ratio = v.max_acceleration_ratio
    run.max_jerk_ratio = v.max_jerk_ratio
    P = np.asarray(out.positions, dtype=float)
    target = np.asarray(problem.goal, dtype=float) if goal == "joint" else P[-1]
    _quality(run, start, target, limits, run.claims_jerk_limits)
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


def ratio_of_means(runs: list[Any], num: str, den: str) -> float:
    """mean(num) / mean(den) over the runs where both are finite and den > 0 (nan if none)."""
    pairs = [(getattr(r, num), getattr(r, den)) for r in runs]
    pairs = [(a, b) for a, b in pairs if np.isfinite(a) and np.isfinite(b) and b > 0]
    if not pairs:
        return float("nan")
    a, b = np.asarray(pairs).T
    return float(a.mean() / b.mean())


def summarize(runs: list[Run], n_valid: int) -> dict[str, Any]:
    """Success rate over `n_valid` problems and metric statistics over verified successes.

    Besides `stats` of every metric in `METRICS` (the mean of `motion_time_ratio` is the mean
    of the per-problem ratios), it gives `motion_time_ratio_of_means` = mean motion time /
    mean lower bound and `path_length_ratio_of_means` = mean path length / mean straight-line
    length, both over the verified successes whose denominator is positive.
    """
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
    out["motion_time_ratio_of_means"] = ratio_of_means(ok, "motion_time_s", "lower_bound_s")
    out["path_length_ratio_of_means"] = ratio_of_means(ok, "path_length_rad", "straight_line_rad")
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


def summarize_planner(runs: list[Run], goals: list[str], scenes: list[str], valid_by_scene: dict[str, int]) -> dict[str, Any]:
    """One planner's summary: overall, `by_scene`, and `by_goal[g]` with its own `by_scene`."""
    n_valid = sum(valid_by_scene.get(s, 0) for s in scenes)
    entry = summarize(runs, n_valid * len(goals))
    entry["claims_jerk_limits"] = any(r.claims_jerk_limits for r in runs)
    entry["by_scene"] = {s: summarize([r for r in runs if r.scene == s], valid_by_scene.get(s, 0) * len(goals))
                         for s in scenes}
    entry["by_goal"] = {}
    for g in goals:
        rg = [r for r in runs if r.goal == g]
        eg = summarize(rg, n_valid)
        eg["by_scene"] = {s: summarize([r for r in rg if r.scene == s], valid_by_scene.get(s, 0)) for s in scenes}
        entry["by_goal"][g] = eg
    return entry


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


def _get(s: dict[str, Any], key: str, q: str | None = "mean") -> float:
    """s[key][q] (or s[key] for q=None), nan when a saved report lacks it (older reports)."""
    v = s.get(key, float("nan"))
    if q is not None:
        v = v.get(q, float("nan")) if isinstance(v, dict) else float("nan")
    return float("nan") if v is None else float(v)


def display_name(name: str, entry: dict[str, Any], label: str | None = None) -> str:
    """A row's planner name: the entry's `display_name`, else "name (label)", else name."""
    if entry.get("display_name"):
        return str(entry["display_name"])
    return f"{name} ({label})" if label else name


def _quality_cells(s: dict[str, Any]) -> str:
    """motion time | lower bound | ratios | path length | path ratios | max jerk | max acc."""
    return (
        f"{_fmt(_get(s, 'motion_time_s'))} | {_fmt(_get(s, 'lower_bound_s'))} | "
        f"{_fmt(_get(s, 'motion_time_ratio_of_means', None))} / {_fmt(_get(s, 'motion_time_ratio'))} | "
        f"{_fmt(_get(s, 'path_length_rad'))} | "
        f"{_fmt(_get(s, 'path_length_ratio_of_means', None))} / {_fmt(_get(s, 'path_length_ratio'))} | "
        f"{_fmt(_get(s, 'max_jerk'), 0)} | {_fmt(_get(s, 'max_acceleration'), 1)}"
    )


QUALITY_HEAD = ("motion time mean [s] | lower bound mean [s] | motion time / lower bound: ratio of means / mean ratio "
                "| path length mean [rad] | path / straight line: ratio of means / mean ratio "
                "| max jerk mean [rad/s^3] | max acc mean [rad/s^2]")


def markdown_tables(report: dict[str, Any]) -> str:
    """The report as Markdown tables (overall per planner and goal kind, then per scene)."""
    label = report.get("label")
    lines = []
    head = ("| planner | goal | solved / valid | success | invalid returned | plan time median / mean / p75 / p98 [ms] | "
            + QUALITY_HEAD + " |")
    lines += [head, "|" + "---|" * 13]
    for name, p in report["planners"].items():
        dn = display_name(name, p, label)
        for g, s in list(p["by_goal"].items()) + ([("all", p)] if len(p["by_goal"]) > 1 else []):
            pt = s["plan_time_s"]
            lines.append(
                f"| {dn} | {g} | {s['solved']}/{s['valid_problems']} | {100 * s['success_rate']:.1f} % | "
                f"{s['invalid_returned']} | {_fmt_ms(pt['median'])} / {_fmt_ms(pt['mean'])} / {_fmt_ms(pt['p75'])} / "
                f"{_fmt_ms(pt['p98'])} | {_quality_cells(s)} |"
            )
    if report.get("ratios_vs_manip"):
        lines += ["", "| peer | goal | plan time median / manip's | p98 / manip's | motion time mean / manip's |", "|---|---|---|---|---|"]
        for name, e in report["ratios_vs_manip"].items():
            dn = display_name(name, report["planners"].get(name, {}), label)
            for g, r in e.items():
                lines.append(f"| {dn} | {g} | {_fmt(r['median'])}x | {_fmt(r['p98'])}x | {_fmt(r['motion_time_mean'])}x |")
    lines += ["", "| planner | goal | scene | solved / valid | invalid returned | plan time median / p98 [ms] | "
              + QUALITY_HEAD + " |", "|" + "---|" * 13]
    for name, p in report["planners"].items():
        dn = display_name(name, p, label)
        for g, s in p["by_goal"].items():
            for scene, sc in s["by_scene"].items():
                pt = sc["plan_time_s"]
                lines.append(
                    f"| {dn} | {g} | {scene} | {sc['solved']}/{sc['valid_problems']} | {sc['invalid_returned']} | "
                    f"{_fmt_ms(pt['median'])} / {_fmt_ms(pt['p98'])} | {_quality_cells(sc)} |"
                )
    inv = report["invalid_problems"]
    lines += ["", f"Problems infeasible for the example-robot-data Panda (not planned): {inv['count']} of "
              f"{report['problems']}: " + (", ".join(f"{k}: {v}" for k, v in inv["by_reason"].items()) or "none")]
    notes = report.get("planner_limits") or {}
    marked = {k: v for k, v in notes.items() if v != "as benchmark"}
    if marked:
        lines += ["", "Planners NOT given the benchmark's limits: "
                  + "; ".join(f"{display_name(k, report['planners'].get(k, {}), label)}: {v}" for k, v in marked.items())]
    return "\n".join(lines)


def merge_reports(reports: list[dict[str, Any]], names: list[str] | None = None) -> dict[str, Any]:
    """Several saved reports as one, for side-by-side tables (e.g. "manip (before)", "manip (after)").

    Each report's planners are renamed to their display names ("name (label)" when the run
    had `--label`; else the name, or "name (file stem)" when two reports share a name); the
    ratios to manip stay those of each run. One report is returned unchanged.

    Args:
        reports: reports as saved by `--json`.
        names: one name per report (e.g. the file stems), for disambiguation.
    """
    if len(reports) == 1:
        return reports[0]
    names = names or [f"run {i + 1}" for i in range(len(reports))]
    first = reports[0]
    merged: dict[str, Any] = {k: v for k, v in first.items() if k not in ("planners", "ratios_vs_manip", "runs", "label")}
    merged["planners"], merged["ratios_vs_manip"], merged["planner_limits"] = {}, {}, {}
    merged["goal_kinds"] = list(dict.fromkeys(g for r in reports for g in r.get("goal_kinds", [])))
    merged["wall_time_s"] = sum(float(r.get("wall_time_s", 0.0)) for r in reports)
    merged["sources"] = []
    for rep, src in zip(reports, names):
        label = rep.get("label")
        renamed: dict[str, str] = {}
        for name, p in rep["planners"].items():
            dn = display_name(name, p, label)
            if dn in merged["planners"]:
                dn = f"{dn} ({src})"
            renamed[name] = dn
            merged["planners"][dn] = dict(p, display_name=dn)
        for name, e in (rep.get("ratios_vs_manip") or {}).items():
            if name in renamed:
                merged["ratios_vs_manip"][renamed[name]] = e
        for name, note in (rep.get("planner_limits") or {}).items():
            if name in renamed:
                merged["planner_limits"][renamed[name]] = note
        merged["sources"].append({
            "file": src, "label": label, "command": rep.get("command"), "date": rep.get("date"),
            "commit": rep.get("machine", {}).get("commit"),
            "load_average_at_start": rep.get("machine", {}).get("load_average_at_start", []),
            "problems": rep.get("problems"), "valid_problems": rep.get("valid_problems"),
            "limits": rep.get("limits"), "plan_options": rep.get("plan_options"),
            "planners": list(renamed.values()),
        })
    return merged


SECTION = "## Motion generation (MotionBenchMaker)"

PUBLISHED = """Published figures on the same problem family (quoted, NOT measured here; from the
dataset's README and the papers):

| system (published) | hardware | success | planning time |
|---|---|---|---|
| cuRobo v0.7.6 motion generation (MBM, 800 problems) | RTX 6000 Ada GPU | 800/800 | median 31 ms, mean 42 ms, p98 161 ms; motion time mean 1.36 s, path length mean 3.82 rad, max jerk mean 119 rad/s^3 |
| cuRoboV2 (Apache-2.0), MBM + MpiNets (2600) | GPU | 99.73 % | median 35 ms, p98 81 ms; motion time mean 1.25 s, path length mean 3.13 rad, max jerk mean 227 rad/s^3 |
| Tesseract (OMPL RRTConnect + TrajOpt), MBM + MpiNets (2600) | Ryzen 9 7950X | 98.5 % | mean 2.95 s, p98 22 s |
| VAMP RRTConnect + simplification (geometric path only, no timing) | Ryzen 9 7950X, SIMD | 800/800 | median 109 us, mean 167 us |

cuRobo's limits are acceleration 15 rad/s^2 and jerk 500 rad/s^3 on every joint (its
franka.yml; `--curobo-limits` runs manip and the peers with them); it counts a pose goal
reached within 5 mm and 5 %, widens the joint limits by 0.2 rad and checks collisions with
spheres; the verifier here asks 1 mm / 0.01 rad and exact meshes. VAMP cannot be installed
here (published only as a source package whose build downloads its dependencies) and mplib
needs numpy < 2, so neither is measured; see benchmarks/peers/README.md.
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
verified successes; loading a scene's obstacles is not timed. Quality columns are means over
the verified successes (`manip/benchmarking/quality.py`). Lower bound = ruckig's
time-optimal rest-to-rest motion from the start to the goal configuration (for pose goals:
to the configuration the trajectory reached) under the limits the planner was given, with
infinite jerk for the planners that do not limit jerk (the peers): no valid motion between
the two configurations is shorter. "ratio of means" = mean motion time / mean lower bound;
"mean ratio" = mean over problems of motion time / lower bound (1.00 = time-optimal
straight line); the same for path length against the joint-space straight line (L2, the
shortest path). Max jerk and max acceleration are the larger of the returned arrays and
divided differences of the positions (TOP-RA's piecewise-constant accelerations make the
peers' jerk a sampling-dependent metric, not a limit they claim). Ratios to manip's are
peer / manip from the same run."""


def _limits_line(limits: dict[str, Any] | None, plan_options: dict[str, Any] | None) -> str:
    if not limits:
        return ""
    acc = ", ".join(f"{a:g}" for a in limits.get("acceleration", []))
    jerk = ", ".join(f"{a:g}" for a in limits.get("jerk", []))
    opts = ", ".join(f"{k}={v}" for k, v in (plan_options or {}).items()) or "defaults"
    return (f"limits: {limits.get('source', '?')} (acceleration [{acc}] rad/s^2, jerk [{jerk}] rad/s^3, "
            f"URDF velocities); manip plan options: {opts}")


def markdown_section(report: dict[str, Any]) -> str:
    """The BENCHMARKS.md section for a report (or a `merge_reports` of several)."""
    m = report["machine"]
    pk = m.get("packages", {})
    unavailable = report.get("unavailable_planners") or {}
    sources = report.get("sources")
    if sources:
        runs = ["Runs merged into these tables (`python benchmarks/mbm.py --from-json ...`):", ""]
        for s in sources:
            runs.append(
                f"- {', '.join(s['planners'])}: `{s.get('command')}` ({s.get('date')}, commit {s.get('commit') or '?'}, "
                f"load average at start {', '.join(str(x) for x in s.get('load_average_at_start') or [])}; "
                f"{s.get('problems')} problems, {s.get('valid_problems')} valid"
                + (f"; {_limits_line(s.get('limits'), s.get('plan_options'))}" if s.get("limits") else "") + ")"
            )
        lines = [SECTION, ""] + runs + [
            "",
            f"Machine: {m['cpu']}, {m['cores']} cores, shared with other jobs; Python {m['python']}; "
            + ", ".join(f"{k} {v}" for k, v in pk.items()) + f"; total wall time {report['wall_time_s'] / 60:.0f} min.",
            "",
        ]
    else:
        lim = _limits_line(report.get("limits"), report.get("plan_options"))
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
        ] + ([lim[0].upper() + lim[1:] + ".", ""] if lim else [])
    lines += [
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
    ap.add_argument("--curobo-limits", action="store_true",
                    help=f"give every planner cuRobo's franka.yml limits: acceleration {CUROBO_ACCELERATION:g} rad/s^2 and "
                         f"jerk {CUROBO_JERK:g} rad/s^3 on every joint (URDF velocities); verification and lower "
                         f"bounds use them too; rows are labelled '{CUROBO_LABEL}' unless --label is given")
    ap.add_argument("--smoothness", choices=("time_optimal", "smooth"), default=None,
                    help="pass smoothness=... to manip's plan calls (not passed when omitted)")
    ap.add_argument("--no-trajopt", action="store_true",
                    help="pass trajopt=False to manip's plan calls (the shortcut pipeline alone: a 'before' row)")
    ap.add_argument("--label", default=None, help="label this run's rows, e.g. 'before' -> 'manip (before)'")
    ap.add_argument("--json", type=Path, default=None, help="write the full report (and every run) here")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    ap.add_argument("--plot", type=Path, default=None, help="write planning/motion-time distributions (PNG) here")
    ap.add_argument("--write-md", action="store_true",
                    help="replace the 'Motion generation (MotionBenchMaker)' section of BENCHMARKS.md")
    ap.add_argument("--from-json", type=Path, nargs="+", default=None, metavar="REPORT",
                    help="do not plan: print (and with --write-md write) the report(s) saved by --json; "
                         "several are merged into one set of tables (label runs with --label)")
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


def _from_json(args: argparse.Namespace) -> int:
    reports = []
    for path in args.from_json:
        with open(path) as f:
            reports.append(json.load(f))
    report = merge_reports(reports, [Path(p).stem for p in args.from_json])
    print(markdown_tables(report))
    if args.json is not None and len(reports) > 1:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1, default=float)
        print(f"\nwrote {args.json}")
    if args.plot is not None:
        from benchmarks.plots import plot_mbm
        plot_mbm([r for rep in reports for r in rep.get("runs", [])], args.plot)
    if args.write_md:
        write_markdown(report, ROOT / "BENCHMARKS.md")
    return 0


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    if args.from_json is not None:
        return _from_json(args)
    machine = machine_info()  # before planning: the load average at start
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        tqdm = None

    problems = load_problems(args)
    if not problems:
        print("no problems selected", file=sys.stderr)
        return 2
    config = benchmark_config(args.curobo_limits)
    bench_limits = config.limits
    label = args.label if args.label is not None else (CUROBO_LABEL if args.curobo_limits else None)
    plan_options = {"smoothness": args.smoothness} if args.smoothness is not None else {}
    if args.no_trajopt:
        plan_options["trajopt"] = False
    verifier = Verifier(config)
    validity = {(p.scene, p.index): verifier.check_problem(p) for p in problems}
    valid = [p for p in problems if validity[(p.scene, p.index)].valid]
    invalid = [p for p in problems if not validity[(p.scene, p.index)].valid]
    goals = ["joint", "pose"] if args.goal == "both" else [args.goal]
    names = [n.strip() for n in args.planners.split(",") if n.strip()]

    planners, unavailable, limits_of, limits_note = {}, {}, {}, {}
    for n in names:
        try:
            planners[n] = build_planner(n, args.timeout, config=config if args.curobo_limits else None,
                                        plan_options=plan_options if n == "manip" else None)
        except InvalidInputError as exc:  # an option the planner rejects (e.g. --smoothness): fail, do not hide it
            print(f"planner {n} rejected the benchmark's options: {exc}", file=sys.stderr)
            return 2
        except Exception as exc:  # PeerUnavailableError, ImportError, ...
            unavailable[n] = f"{type(exc).__name__}: {exc}"
            print(f"planner {n} not run: {unavailable[n]}", file=sys.stderr)
            continue
        limits_of[n] = planner_limits(planners[n], bench_limits)
        limits_note[n] = "as benchmark" if same_limits(limits_of[n], bench_limits) else (
            "plans with its own limits " + json.dumps(limits_dict(limits_of[n])) + " (verified and bounded with those)")
        if limits_note[n] != "as benchmark":
            print(f"planner {n}: {limits_note[n]}", file=sys.stderr)
    if not planners:
        return 2

    total = len(planners) * len(goals) * len(valid)
    bar = tqdm(total=total, unit="plan", disable=args.no_progress or tqdm is None, dynamic_ncols=True) if tqdm else None
    runs: list[Run] = []
    t_start = time.time()
    for name, planner in planners.items():
        for g in goals:
            if valid:  # one untimed plan first: kernels compiled or loaded on first use stay out of the times
                try:
                    planner.plan(valid[0], g, seed=args.seed)
                except Exception:  # reported by its timed run below
                    log.warning("%s: the untimed warm-up plan raised", name)
            for p in valid:
                r = run_one(planner, p, g, verifier, args.seed, limits=limits_of[name])
                runs.append(r)
                if bar is not None:
                    bar.set_postfix_str(f"{name} {g} {p.scene}/{p.index}", refresh=False)
                    bar.update(1)
    if bar is not None:
        bar.close()

    scenes = list(dict.fromkeys(p.scene for p in problems))
    valid_by_scene = dict(Counter(p.scene for p in valid))
    report: dict[str, Any] = {
        "date": _dt.datetime.now().astimezone().isoformat(timespec="seconds"),
        "command": shlex.join(["python", "benchmarks/mbm.py"] + (sys.argv[1:] if argv is None else list(argv))),
        "machine": machine,
        "dataset": None if _no_dataset(args) else str(args.dataset or default_dataset_path()),
        "label": label,
        "limits": dict(limits_dict(bench_limits),
                       source="cuRobo's franka.yml (--curobo-limits)" if args.curobo_limits else "robots/franka/robot.yaml"),
        "plan_options": plan_options,
        "planner_limits": limits_note,
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
        entry = summarize_planner([r for r in runs if r.planner == name], goals, scenes, valid_by_scene)
        if label:
            entry["display_name"] = display_name(name, {}, label)
        report["planners"][name] = entry
    report["ratios_vs_manip"] = ratios_vs_manip(report)

    print(markdown_tables(report))
    if args.json is not None:
        report["runs"] = [dict(asdict(r), label=label) for r in runs]
        args.json.parent.mkdir(parents=True, exist_ok=True)
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1, default=float)
        print(f"\nwrote {args.json}")
    if args.plot is not None:
        from benchmarks.plots import plot_mbm
        plot_mbm([dict(asdict(r), label=label) for r in runs], args.plot)
    if args.write_md:
        write_markdown(report, ROOT / "BENCHMARKS.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
