"""Build manip's prebuilt files: the compiled kernels and the shipped robots' geometry.

    python -m manip.prebuild            # into manip/_prebuilt/ (about 1-2 min of CPU)

Run once where manip is installed from source (`make setup` does) and before building a
wheel (the wheel carries `manip/_prebuilt/`). It starts one child process that

- compiles every kernel for the generic CPU of this architecture (`manip.jit`) by running
  a workload that meets every one of them: plans of each kind (one with a constraint), IK,
  clearance and the reactive controller on the Panda, the arm-arm clearance of the two-arm Panda robot, a joint plan and an
  IK call on every shipped arm;
- computes the shipped robots' sphere covers and self-pair proofs (`manip.disk_cache`),

then writes `_prebuilt/kernels/manifest.json` (numba, Python, architecture and the digest of
every kernel module: the kernels are used only where all of these match). A first plan in a
fresh environment then loads kernels instead of compiling them (`benchmarks/cold_start.py`).

    python -m manip.prebuild --add      # run by another Python: its kernels beside the others

keeps what is there and adds this interpreter's kernels and environment (numba names its files
by Python version, so one folder, and one wheel, serves each Python that ran it); the kernels'
source must be the one the folder was built from (`make wheel` runs it for Python 3.11-3.13).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from manip import jit
from manip.disk_cache import PREBUILT_GEOMETRY
from manip.robot_config import available_robots

logger = logging.getLogger(__name__)


def workload(robots: list[str]) -> list[str]:
    """Meet every kernel, and build the geometry of `robots`: returns the names of the kernels
    compiled (in this process). Raises RuntimeError when a plan of the workload fails."""
    from manip import MotionGenerator, Pose, WorldConfig

    world = WorldConfig.from_dict({
        "cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]},
                   "post": {"dims": [0.06, 0.06, 0.5], "pose": [0.45, 0.0, 0.25, 1, 0, 0, 0]}},
        "sphere": {"ball": {"radius": 0.05, "position": [-0.4, 0.4, 0.6]}},
        "capsule": {"rod": {"radius": 0.02, "base": [0, 0, 0], "tip": [0, 0, 0.2],
                            "pose": [-0.4, -0.4, 0.3, 1, 0, 0, 0]}},
        "cylinder": {"can": {"radius": 0.03, "height": 0.12, "pose": [0.6, 0.3, 0.06, 1, 0, 0, 0]}},
    })
    mg = MotionGenerator("franka", world)
    q0 = mg.default_joint_positions
    goal = Pose([0.45, 0.3, 0.35], [0, 1, 0, 0])
    q1 = mg.ik(goal, seed_q=q0).q
    goals = Pose(np.array([[0.45, -0.3, 0.35], [0.5, 0.3, 0.3]]), np.array([[0, 1, 0, 0]] * 2))
    slow = {"seed": 0, "time_budget": 900.0}  # the first plans compile kernels for tens of seconds
    results = [
        mg.plan_joints(q0, q1, **slow),
        mg.plan_pose(q0, goal, **slow),
        mg.plan_pose(q0, goal, smoothness="smooth", optimize_clearance=True, **slow),
        mg.plan_pose(q1, Pose(goal.position + [0, 0, 0.1], goal.quaternion), linear=True, **slow),
        mg.plan_goalset(q0, goals, **slow),
        *mg.plan_batch(np.array([q0, q1]), np.array([q1, q0]), **slow),
    ]
    failed = [r.status.name for r in results if not r.success]
    if failed:
        raise RuntimeError(f"the prebuild workload's plans failed: {failed}")
    _constrained(mg, q0, q1)
    mg.batch_ik(goals)
    mg.distance(q0)
    mg.check_collision(q0)
    _blended_timing(mg, q0)
    _reactive_control()
    _two_arms()
    _perception(mg, q0)
    for name in robots:
        if name != "franka":
            MotionGenerator(name)
    return sorted(jit.compiled_names())


def _blended_timing(mg, q0: np.ndarray) -> None:
    """A path timed with its corners blended at speed (`timing.time_path(mode="blend")`): the
    blend planner's deviation kernel, with its segments' own arrays (the plans above end in
    optimised motions, which never need it; a plan whose optimised motion fails does)."""
    from manip.timing import time_path

    path = q0 + np.array([[0.0] * 7, [0.6, 0.2, 0, 0, 0, 0, 0], [1.2, 0.2, 0.1, 0, 0, 0, 0]])
    if not time_path(path, mg.config.limits, mode="blend").success:
        raise RuntimeError("the prebuild workload's blended timing failed")


def _constrained(mg, q0: np.ndarray, q1: np.ndarray) -> None:
    """A plan keeping the hand pointing down and a projection onto that cone (the compiled
    certificate and projection of `OrientationConstraint`, `constraints.tilt_kernels`)."""
    from manip import OrientationConstraint
    from manip.constraints import project

    down = OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=0.1)
    if project([down], mg.kinematics, q0 + 0.2) is None:
        raise RuntimeError("the prebuild workload's projection onto a constraint failed")
    r = mg.plan_joints(q0, q1, constraints=(down,), seed=0, time_budget=900.0)
    if not r.success:
        raise RuntimeError(f"the prebuild workload's constrained plan failed: {r.status.name}")


def _two_arms() -> None:
    """The optimiser's arm-arm clearance terms of a two-arm robot (`collision.arm_clearance`'s kernel)."""
    from manip import MotionGenerator

    mg = MotionGenerator("dual_franka")
    reaching = np.array([[-1.57, 0.3, 0.0, -1.6, 0.0, 1.8, 0.785, 1.57, 0.0, 0.0, -2.2, 0.0, 1.8, 0.785]])
    if not len(mg.clearance.terms(reaching, 0.05).distance):
        raise RuntimeError("the prebuild workload's two arms have no clearance term")


def _reactive_control() -> None:
    """One step of the reactive controller with an obstacle (its collision kernel)."""
    from manip import Pose, WorldConfig
    from manip.control import ReactiveController

    world = WorldConfig.from_dict({"cuboid": {"box": {"dims": [0.1, 0.1, 0.1], "pose": [0.45, 0.0, 0.45, 1, 0, 0, 0]}}})
    ctl = ReactiveController("franka", world)
    q = ctl.rest_configuration
    for _ in range(3):
        q = ctl.step(q, Pose([0.45, 0.0, 0.3], [0, 1, 0, 0]), 1 / 60).q


def _perception(mg, q0) -> None:
    """Depth images and a cloud into an occupancy map, then a plan on it (the map's kernels)."""
    from manip import Pose, Sphere

    mg.update_world({})
    K = np.array([[40.0, 0.0, 31.5], [0.0, 40.0, 23.5], [0.0, 0.0, 1.0]])
    down = Pose([0.6, 0.0, 1.0], [np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0])   # +X forward turned to -Z
    depth = np.full((48, 64), 1.0, dtype=np.float32)
    mg.update_world_from_depth(depth, K, down, q=q0)
    mg.update_world_from_depth((depth * 1.2).astype(np.float64), K, down, q=q0)   # seen through: freed (float64 depth)
    mg.update_world_from_depth(depth, K, down, name="bounded", unknown="occupied", bounds=[[0.3, -0.3, -0.3], [0.9, 0.3, 0.1]])
    m = mg.update_world_from_pointcloud(np.array([[0.6, 0.0, -0.2], [0.7, 0.1, -0.2]]), origin=[0.6, 0.0, 1.0], q=q0)
    m.contains_points(np.array([[0.6, 0.0, -0.19]]))
    whole = mg.update_world_from_depth(depth, K, down, name="cells", fill="cells", q=q0)   # boxes, merged
    whole.contains_points(np.array([[0.6, 0.0, -0.19]]))
    mg.remove_obstacle("cells")
    mg.distance(q0)
    Q = np.random.default_rng(0).uniform(mg.lower_limits, mg.upper_limits, (64, mg.lower_limits.size))
    if not mg.checker.in_collision_batch(Q).any():   # parts against the maps' boxes (`occupancy_exact`)
        raise RuntimeError("the prebuild workload's configurations met no occupancy map")
    hand = mg.fk(q0)   # a held sphere: shapes `occupancy_exact` leaves to coal (`boxes_near_balls`)
    mg.attach_object(Sphere("held", 0.04, Pose(hand.position, [1.0, 0.0, 0.0, 0.0])), q=q0)
    mg.checker.in_collision_batch(Q)
    low = mg.ik(Pose([0.55, 0.0, 0.035], [np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0]), seed_q=q0)   # the hand level, 3.5 cm up
    if not low.success or "held" not in {c.a for c in mg.checker.collision_report(low.q).contacts}:
        raise RuntimeError("the prebuild workload's held sphere met no occupancy map")
    mg.detach_object(q0)
    mg.remove_obstacle("held")
    r = mg.plan_pose(q0, Pose([0.45, 0.3, 0.35], [0, 1, 0, 0]), seed=0, time_budget=900.0)
    if not r.success:
        raise RuntimeError(f"the prebuild workload's plan on an occupancy map failed: {r.status.name}")


def merged_manifest(existing: dict | None, built: dict) -> dict:
    """The manifest of a folder holding `existing`'s kernels and those just `built` (by another
    Python, `--add`): the environments of both, the kernels of either. Raises RuntimeError when
    there is nothing to add to or the kernels' source differs (the folder must be rebuilt)."""
    if existing is None:
        raise RuntimeError("--add: no prebuilt kernels to add to; run `python -m manip.prebuild` first")
    if existing.get("sources") != built["sources"]:
        raise RuntimeError("--add: the prebuilt kernels were built from another source of the kernel modules; "
                           "rebuild them with `python -m manip.prebuild` (without --add) first")
    envs = jit.manifest_environments(existing)
    envs += [e for e in built["environments"] if e not in envs]
    return dict(built, environment=envs[0], environments=envs,
                kernels=sorted(set(existing.get("kernels", [])) | set(built["kernels"])))


def _kernel_modules() -> list[Path]:
    """The modules of manip that define kernels, found by their text (nothing imported)."""
    root = Path(jit.__file__).resolve().parent
    return [f for f in root.rglob("*.py") if "\n@kernel" in f.read_text()]


def _child(out: Path, robots: list[str], add: bool) -> None:
    started = time.process_time()
    names = workload(robots)
    env = jit.environment()
    manifest = {"environment": env, "environments": [env], "sources": jit.source_digest(jit.kernel_files()),
                "kernels": names, "built": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
                "cpu_seconds": round(time.process_time() - started, 1)}
    if add:
        manifest = merged_manifest(jit.read_manifest(out), manifest)
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1))


def build(robots: list[str], out_kernels: Path = jit.PREBUILT_KERNELS, out_geometry: Path = PREBUILT_GEOMETRY,
          add: bool = False) -> dict:
    """Rebuild the prebuilt kernels and the geometry of `robots` (in a child process); returns
    the manifest. With `add`, keep what is there and add this Python's kernels (module docstring)."""
    if add:   # checked before the workload's minutes of CPU
        merged_manifest(jit.read_manifest(out_kernels), {"sources": jit.source_digest(_kernel_modules()),
                                                      "environments": [], "kernels": []})
    for folder in (out_kernels, out_geometry):
        if not add:
            shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="manip-prebuild-") as numba_cache:
        env = dict(os.environ, NUMBA_CPU_NAME=jit.PORTABLE_CPU, NUMBA_CPU_FEATURES="", NUMBA_CACHE_DIR=numba_cache,
                   MANIP_CACHE_DIR=str(out_geometry), **{jit.BUILD_ENV: str(out_kernels)})
        subprocess.run([sys.executable, "-m", "manip.prebuild", "--child", str(out_kernels), "--robots", *robots,
                        *(["--add"] if add else [])], env=env, check=True)
    return json.loads((out_kernels / "manifest.json").read_text())


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", default=["all"], metavar="NAME",
                        help="shipped robots whose collision geometry is prebuilt (default: all of them; the "
                             "kernels are built either way)")
    parser.add_argument("--add", action="store_true",
                        help="keep the prebuilt kernels there and add this Python's (for a wheel serving several "
                             "Pythons; the kernels' source must be the one they were built from)")
    parser.add_argument("--child", metavar="DIR", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(message)s")
    robots = available_robots() if args.robots == ["all"] else args.robots
    unknown = sorted(set(robots) - set(available_robots()))
    if unknown:
        parser.error(f"unknown robots {unknown}; shipped: {available_robots()}")
    if args.child:
        _child(Path(args.child), robots, args.add)
        return 0
    t = time.perf_counter()
    try:
        manifest = build(robots, add=args.add)
    except RuntimeError as e:
        parser.error(str(e))
    print(f"prebuilt {len(manifest['kernels'])} kernels and the geometry of {', '.join(robots)} "
          f"({manifest['cpu_seconds']} s of CPU) for {jit.environment()} into {jit.PREBUILT_KERNELS.parent} "
          f"in {time.perf_counter() - t:.0f} s; the folder serves {jit.manifest_environments(manifest)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
