#!/usr/bin/env python3
"""Cold start: the CPU and wall seconds of manip's first calls in a fresh environment.

    python benchmarks/cold_start.py [--runs 3] [--write-md]      # this interpreter, fresh processes
    python benchmarks/cold_start.py --wheel dist/manip_robotics-*.whl   # also: a new venv with the wheel

Each run is a new process whose numba and manip caches are empty folders (NUMBA_CACHE_DIR,
MANIP_CACHE_DIR): what a user meets after `pip install`. It times, one after the other and
cumulatively (CPU = the process's user + system time): `import manip`, the first
MotionGenerator("franka") and FK, the first IK, the first `plan_joints`, the first
`plan_pose`, the first simulation step (World, Franka, cube, reset, step); then, in another
fresh process, the first pick-and-place episode (`examples/pick_and_place.py --episodes 1`,
the whole process). Two rows per call: with the prebuilt kernels and geometry (`manip.jit`,
`python -m manip.prebuild`) and without them (`MANIP_PREBUILT=off`: numba compiles every
kernel the call meets, as before 0.2.0). `--wheel` adds a third: a new venv outside the
repository with the wheel and its dependencies installed from the registry, run from another
folder. Counts of compiled kernels are printed beside the seconds.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from datetime import datetime, timezone
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from report import cpu_model, replace_section  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
STEPS = ["import manip", "first FK", "first IK", "first plan_joints", "first plan_pose", "first sim step"]

PROBE = textwrap.dedent("""
    import json, os, time
    def now():
        t = os.times()
        return t.user + t.system, time.perf_counter()
    cpu0, wall0 = now()
    out = {}
    def mark(name):
        cpu, wall = now()
        out[name] = (cpu - cpu0, wall - wall0)
    import manip
    from manip import MotionGenerator, Pose, WorldConfig
    mark("import manip")
    world = WorldConfig.from_dict({"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]}}})
    mg = MotionGenerator("franka", world)
    q0 = mg.default_joint_positions
    mg.fk(q0)
    mark("first FK")
    mg.ik(Pose([0.45, 0.1, 0.35], [0, 1, 0, 0]), seed_q=q0)
    mark("first IK")
    assert mg.plan_joints(q0, q0 + 0.3).success
    mark("first plan_joints")
    assert mg.plan_pose(q0, Pose([0.5, 0.2, 0.3], [0, 1, 0, 0])).success
    mark("first plan_pose")
    from manip.sim import DynamicCuboid, Franka, World
    w = World()
    w.scene.add_default_ground_plane()
    w.scene.add(Franka("/World/Franka", name="franka"))
    w.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.03], size=0.05))
    w.reset()
    w.step(render=False)
    mark("first sim step")
    from manip import jit
    out["compiled"] = len(jit.compiled_names())
    print("COLD_START " + json.dumps(out))
""")


def _env(tmp: Path, prebuilt: bool) -> dict:
    return dict(os.environ, NUMBA_CACHE_DIR=str(tmp / "numba"), MANIP_CACHE_DIR=str(tmp / "manip"),
                MANIP_PREBUILT="on" if prebuilt else "off")


def _child_cpu(cmd: list[str], env: dict, cwd: Path) -> tuple[float, float, str]:
    """(CPU [s] of the finished child, wall [s], its stdout) of one command."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    proc = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True, timeout=1800)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd[:3])}... failed:\n{proc.stderr[-3000:]}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), wall, proc.stdout


def run_once(python: str, prebuilt: bool, cwd: Path) -> dict:
    """One fresh process of PROBE and one of the pick-and-place example; returns the figures."""
    with tempfile.TemporaryDirectory(prefix="manip-cold-") as tmp:
        env = _env(Path(tmp), prebuilt)
        _, _, out = _child_cpu([python, "-c", PROBE], env, cwd)
        line = next(ln for ln in out.splitlines() if ln.startswith("COLD_START "))
        probe = json.loads(line[len("COLD_START "):])
    with tempfile.TemporaryDirectory(prefix="manip-cold-") as tmp:
        env = _env(Path(tmp), prebuilt)
        cpu, wall, out = _child_cpu([python, str(ROOT / "examples" / "pick_and_place.py"), "--episodes", "1",
                                     "--quiet"], env, cwd)
        if "placed 1/1" not in out:
            raise RuntimeError(f"the pick-and-place episode failed:\n{out[-2000:]}")
    probe["first pick-and-place episode"] = (cpu, wall)
    return probe


def make_wheel_venv(wheel: Path, folder: Path) -> str:
    """A new venv in `folder` with `wheel` and its dependencies; returns its python."""
    subprocess.run([sys.executable, "-m", "venv", str(folder)], check=True)
    python = str(folder / "bin" / "python")
    subprocess.run([python, "-m", "pip", "install", "--quiet", str(wheel)], check=True)
    return python


def table(rows: dict[str, list[dict]]) -> str:
    names = STEPS + ["first pick-and-place episode"]
    head = "| step (cumulative from process start) | " + " | ".join(f"{k}: CPU / wall [s]" for k in rows) + " |"
    lines = [head, "|---|" + "---|" * len(rows)]
    for name in names:
        cells = []
        for runs in rows.values():
            cpu = statistics.median(r[name][0] for r in runs)
            wall = statistics.median(r[name][1] for r in runs)
            cells.append(f"{cpu:.2f} / {wall:.2f}")
        label = name + (" (its own fresh process, whole run)" if name.startswith("first pick") else "")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append("| kernels compiled by the probe | " + " | ".join(
        "/".join(str(r["compiled"]) for r in runs) for runs in rows.values()) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="fresh processes per row (medians are shown)")
    parser.add_argument("--wheel", type=Path, help="also measure a new venv with this wheel installed")
    parser.add_argument("--no-before", action="store_true", help="skip the MANIP_PREBUILT=off row (it compiles: slow)")
    parser.add_argument("--write-md", action="store_true", help="replace the Cold start section of BENCHMARKS.md")
    args = parser.parse_args(argv)
    rows: dict[str, list[dict]] = {}
    venv = None
    try:
        if args.wheel is not None:
            venv = Path(tempfile.mkdtemp(prefix="manip-wheel-venv-"))
            t = time.perf_counter()
            python = make_wheel_venv(args.wheel.resolve(), venv)
            print(f"venv with {args.wheel.name} installed in {time.perf_counter() - t:.0f} s", flush=True)
            outside = Path(tempfile.mkdtemp(prefix="manip-elsewhere-"))
            rows[f"wheel in a new venv ({args.wheel.name})"] = [run_once(python, True, outside)
                                                                for _ in range(args.runs)]
        rows["checkout, prebuilt"] = [run_once(sys.executable, True, ROOT) for _ in range(args.runs)]
        if not args.no_before:
            rows["checkout, MANIP_PREBUILT=off (compiles)"] = [run_once(sys.executable, False, ROOT)
                                                             for _ in range(args.runs)]
    finally:
        if venv is not None:
            shutil.rmtree(venv, ignore_errors=True)
    text = table(rows)
    print(text)
    if args.write_md:
        stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        load = os.getloadavg()[0]
        section = (f"## Cold start (the first calls in a fresh environment)\n\n"
                   f"`python benchmarks/cold_start.py --runs {args.runs}"
                   f"{' --wheel ' + args.wheel.name if args.wheel else ''}` on {stamp}, {cpu_model()}, "
                   f"{os.cpu_count()} cores, load {load:.1f} at the end, Python {sys.version.split()[0]}. Each column "
                   f"is the median of {args.runs} fresh processes with empty numba and manip cache folders; each "
                   f"figure is cumulative from the process's start (CPU = user + system). The pick-and-place row is "
                   f"a separate fresh process running `examples/pick_and_place.py --episodes 1` whole.\n\n{text}\n")
        replace_section(ROOT / "BENCHMARKS.md", "## Cold start (the first calls in a fresh environment)", section)
    return 0


if __name__ == "__main__":
    sys.exit(main())
