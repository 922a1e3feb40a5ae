"""Constrained planning: an upright orientation held over the whole motion, manip against OMPL.

    python benchmarks/constrained.py [--per-kind 80] [--seed 0] [--ompl-timeout 3] [--write-md]

Problems: the seeded table, shelf and cage scenes of `manip.benchmarking.scenes`, made
"upright": the hand axis (of +-x, +-y, +-z of `panda_hand`) nearest the world's up at the goal
must stay within TOLERANCE (0.1 rad) of up (`OrientationConstraint(axis, (0, 0, 1), 0.1)`:
a cup held in a top or a side grasp). The start and the goal are projected onto the
constraint (`manip.constraints.project`); a problem whose projected start or goal is in
collision or outside the limits (checked by the independent verifier) is left out, so every
problem kept has a valid upright start and goal.

Per problem, in one process: manip with the constraint (`plan_joints(..., constraints=...)`),
manip without it (the motion-time reference), and OMPL 2.0's `ProjectedStateSpace` with
RRT-Connect (`benchmarks/peers/ompl_constrained.py`). Every trajectory is checked by the
verifier (exact meshes, limits, endpoints) and its tilt is sampled at 1 kHz (manip's
trajectories through their exact profiles or Hermite interpolation, OMPL's through
TOPP-RA's). Planning time is wall and CPU (process) time of the planning call.
`--write-md` replaces the "## Constrained planning" section of BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import datetime as dt
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
from manip import MotionGenerator, OrientationConstraint  # noqa: E402
from manip.benchmarking.scenes import make_problems  # noqa: E402
from manip.benchmarking.verify import default_verifier  # noqa: E402
from manip.constraints import project  # noqa: E402

KINDS = ("table", "shelf", "cage")
TOLERANCE = 0.1  # [rad]
LINK = "panda_hand"
UP = np.array([0.0, 0.0, 1.0])
AXES = np.concatenate([np.eye(3), -np.eye(3)])


class Upright:
    """A seeded problem made upright: world, start, goal, the constraint."""

    def __init__(self, name, world, start, goal, constraint):
        self.name, self.world, self.start, self.goal, self.constraint = name, world, start, goal, constraint
        self.joint_names = tuple(f"panda_joint{i}" for i in range(1, 8))


def upright_problems(per_kind: int, seed: int, mg: MotionGenerator) -> tuple[list[Upright], int]:
    """The upright problems (see the module doc) and how many seeded problems were tried."""
    verifier = default_verifier()
    kin = mg.kinematics
    out, tried = [], 0
    for kind in KINDS:
        for p in make_problems(kind, per_kind, seed):
            tried += 1
            R = kin.fk(np.asarray(p.goal), LINK).rotation
            axis = AXES[int(np.argmax((R @ AXES.T).T @ UP))]
            c = OrientationConstraint(axis=axis, direction=UP, tolerance=TOLERANCE, link=LINK)
            ends = [project([c], kin, np.asarray(q, dtype=float)) for q in (p.start, p.goal)]
            if any(q is None for q in ends):
                continue
            if any(verifier.check_configuration(q, p.world, "q")[0] for q in ends):
                continue
            out.append(Upright(f"{p.scene}/{p.index}", p.world, ends[0], ends[1], c))
    return out, tried


def tilt_1khz(c: OrientationConstraint, kin, times: np.ndarray, positions: np.ndarray, at_time=None) -> float:
    """Largest tilt [rad] of a trajectory sampled every 1 ms (`at_time` when given, else linear between samples)."""
    t = np.arange(0.0, times[-1], 1e-3)
    if at_time is not None:
        Q = at_time(t)[0]
    else:
        Q = np.stack([np.interp(t, times, positions[:, j]) for j in range(positions.shape[1])], axis=1)
    return float(c.tilt(kin, np.vstack([Q, positions[-1:]])).max())


def run(args) -> dict:
    mg = MotionGenerator("franka")
    kin = mg.kinematics
    verifier = default_verifier()
    problems, tried = upright_problems(args.per_kind, args.seed, mg)
    ompl = None
    if args.ompl_timeout > 0:
        from benchmarks.peers.ompl_constrained import OMPLConstrainedPeer

        ompl = OMPLConstrainedPeer(timeout_s=args.ompl_timeout, seed=args.seed)
    rows = []
    for i, p in enumerate(problems):
        mg.update_world(p.world)
        row = {"name": p.name}
        for label, opts in (("manip", {"constraints": (p.constraint,)}), ("free", {})):
            c0, t0 = time.process_time(), time.perf_counter()
            r = mg.plan_joints(p.start, p.goal, seed=args.seed + i, **opts)
            row[f"{label}_wall"], row[f"{label}_cpu"] = time.perf_counter() - t0, time.process_time() - c0
            row[f"{label}_ok"], row[f"{label}_status"] = bool(r.success), r.status.name
            if r.success:
                tr = r.trajectory
                v = verifier.verify_trajectory(p.world, tr.times, tr.positions, tr.velocities, tr.accelerations,
                                               start_q=p.start, goal_q=p.goal)
                row[f"{label}_valid"] = v.valid
                row[f"{label}_motion"] = tr.duration
                row[f"{label}_tilt"] = tilt_1khz(p.constraint, kin, tr.times, tr.positions, tr.at_time)
        if ompl is not None:
            c0 = time.process_time()
            o = ompl.plan_upright(p, p.constraint.axis, UP, TOLERANCE, LINK, seed=args.seed + i)
            row["ompl_cpu"] = time.process_time() - c0
            row["ompl_wall"], row["ompl_ok"], row["ompl_status"] = o.plan_time_s, o.success, o.status
            if o.success:
                v = verifier.verify_trajectory(p.world, o.times, o.positions, o.velocities, o.accelerations,
                                               start_q=p.start, goal_q=p.goal)
                row["ompl_valid"], row["ompl_motion"] = v.valid, float(o.times[-1])
                row["ompl_tilt"] = tilt_1khz(p.constraint, kin, o.times, o.positions)
        rows.append(row)
        if not args.quiet:
            bits = [f"{k}: {'ok' if row.get(f'{k}_ok') else row.get(f'{k}_status', '-')}" for k in ("manip", "free", "ompl")]
            print(f"{i:4d} {p.name:<18} " + ", ".join(bits) + f"  manip {row['manip_wall'] * 1e3:7.1f} ms, "
                  f"tilt {row.get('manip_tilt', float('nan')):.4f}", flush=True)
    return {"rows": rows, "tried": tried}


def summary(res: dict, args) -> str:
    rows = res["rows"]
    n = len(rows)

    def stats(key: str) -> str:
        ok = [r for r in rows if r.get(f"{key}_ok")]
        wall = np.array([r[f"{key}_wall"] for r in rows])
        cpu = np.array([r[f"{key}_cpu"] for r in rows])
        invalid = sum(1 for r in ok if not r.get(f"{key}_valid", True))
        tilts = np.array([r[f"{key}_tilt"] for r in ok]) if ok else np.zeros(0)
        over = int(np.sum(tilts > TOLERANCE)) if key != "free" else 0
        ratio = np.array([r[f"{key}_motion"] / r["free_motion"] for r in ok if r.get("free_ok")])
        return (f"| {key} | {len(ok)}/{n} ({100 * len(ok) / max(n, 1):.1f} %) | {invalid} | "
                f"{tilts.max() if tilts.size else float('nan'):.4f} | {over} | "
                f"{np.median(wall) * 1e3:.0f} / {np.percentile(wall, 98) * 1e3:.0f} | "
                f"{np.median(cpu) * 1e3:.0f} / {np.percentile(cpu, 98) * 1e3:.0f} | "
                + (f"{np.median(ratio):.2f} / {np.percentile(ratio, 90):.2f} / {ratio.max():.2f} |" if ratio.size
                   else "- |"))

    head = ("| planner | solved | invalid | max tilt at 1 kHz [rad] | tilt > 0.1 | planning wall median / p98 [ms] "
            "| CPU median / p98 [ms] | motion time / unconstrained: median / p90 / max |\n|---|---|---|---|---|---|---|---|")
    lines = [head, stats("manip"), stats("free")]
    if any("ompl_ok" in r for r in rows):
        lines.append(stats("ompl"))
    per_kind = []
    for kind in KINDS:
        sub = [r for r in rows if r["name"].startswith(f"seeded_{kind}")]
        if sub:
            per_kind.append(f"{kind} {sum(r['manip_ok'] for r in sub)}/{len(sub)}"
                            + (f" (OMPL {sum(r.get('ompl_ok', False) for r in sub)})" if "ompl_ok" in sub[0] else ""))
    failed = [f"{r['name']} ({r['manip_status']})" for r in rows if not r["manip_ok"]]
    neither = sum(1 for r in rows if not r["manip_ok"] and not r.get("ompl_ok", False))
    text = "\n".join(lines)
    text += (f"\n\n{n} upright problems kept of {res['tried']} seeded ones ({args.per_kind} per kind, seed {args.seed}); "
             f"manip solved per kind: {', '.join(per_kind)}. manip failures: {', '.join(failed) or 'none'}"
             f" ({neither} solved by neither planner).")
    return text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--per-kind", type=int, default=80, help="seeded problems per scene kind (before filtering)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--ompl-timeout", type=float, default=3.0, help="OMPL's planning budget [s]; 0 = no OMPL")
    parser.add_argument("--quiet", action="store_true")
    parser.add_argument("--write-md", action="store_true", help="replace the section of BENCHMARKS.md")
    args = parser.parse_args(argv)
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    res = run(args)
    text = summary(res, args)
    load1 = os.getloadavg()[0]
    machine = (f"{cpu_model()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
               f"{dt.datetime.now().strftime('%Y-%m-%d %H:%M')}; load average {load0:.2f} at the start, {load1:.2f} at "
               f"the end; {time.perf_counter() - t0:.0f} s in all")
    print(text)
    print(machine)
    if args.write_md:
        cmd = "python benchmarks/constrained.py " + " ".join(argv if argv is not None else sys.argv[1:])
        section = (f"## Constrained planning\n\n`{cmd.strip()}` ({machine}).\n\n{text}\n")
        replace_section(ROOT / "BENCHMARKS.md", "## Constrained planning", section)
    rows = res["rows"]
    ok = sum(r["manip_ok"] for r in rows)
    bad = sum(1 for r in rows if r["manip_ok"] and (not r.get("manip_valid", True) or r["manip_tilt"] > TOLERANCE))
    return 0 if rows and ok >= 0.98 * len(rows) and bad == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
