"""The first plan in a fresh environment: prebuilt kernels and geometry instead of compiling.

Counted, not timed: a fresh process with empty numba and manip caches compiles no kernel and
computes no collision geometry for the Panda (planning, simulating, planning on a depth
camera's map) when the prebuilt files are there (`make setup`, `make demo` and `make test`
build them; the wheel carries them). `benchmarks/cold_start.py`
measures the seconds.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from manip import MotionGenerator, Pose, WorldConfig, jit
from manip.disk_cache import PREBUILT_GEOMETRY, DiskCache

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = jit.PREBUILT_KERNELS / "manifest.json"

FIRST_USE = textwrap.dedent("""
    import json, logging, sys
    import numpy as np
    logging.basicConfig(level=logging.WARNING)
    from manip import MotionGenerator, Pose, WorldConfig, jit
    from manip.sim import DynamicCuboid, Franka, World
    world = WorldConfig.from_dict({"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]}}})
    mg = MotionGenerator("franka", world)
    q0 = mg.default_joint_positions
    ok = [mg.plan_joints(q0, q0 + 0.3).success, mg.plan_pose(q0, Pose([0.5, 0.2, 0.3], [0, 1, 0, 0])).success,
          mg.plan_pose(q0, Pose([0.5, 0.2, 0.3], [0, 1, 0, 0]), linear=True).success]
    # a path timed with its corners blended at speed (what a plan falls back to when its optimised
    # motion fails the certificate): the blend planner's own kernel signature
    from manip.timing import time_path
    ok.append(time_path(q0 + np.array([[0.0] * 7, [0.5, 0.1, 0.2, 0, 0, 0, 0], [1.0, 0.3, 0.2, 0.1, 0, 0, 0]]),
                        mg.config.limits, mode="blend").success)
    w = World()
    w.scene.add_default_ground_plane()
    franka = w.scene.add(Franka("/World/Franka", name="franka"))
    w.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.03], size=0.05))
    w.reset()
    for _ in range(10):
        w.step(render=False)
    # what a depth camera sees, as the README's perception example: a map, then a plan on it
    from manip.sim import Camera, euler_angles_to_quat
    cam = Camera("/World/depth", position=[-0.5, -0.7, 1.4], resolution=(640, 480),
                 orientation=euler_angles_to_quat([0, 49, 35], degrees=True))
    cam.set_focal_length(1.2)
    w.reset()
    position, orientation = cam.get_world_pose()
    seen = MotionGenerator("franka")
    seen.update_world_from_depth(cam.get_depth(), cam.get_intrinsics_matrix(), Pose(position, orientation),
                                 q=franka.get_joint_positions())
    ok.append(seen.plan_pose(q0, Pose([0.4, -0.2, 0.3], [0, 1, 0, 0])).success)
    print(json.dumps({"ok": [bool(x) for x in ok], "compiled": jit.compiled_names()}))
""")


def _fresh(tmp_path: Path, code: str = FIRST_USE, **env) -> subprocess.CompletedProcess:
    """`code` (FIRST_USE) in a new process whose numba and manip caches are empty folders."""
    full = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"), MANIP_CACHE_DIR=str(tmp_path / "manip"),
                MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"), **env)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=full, cwd=tmp_path,
                          timeout=900)


def test_the_prebuilt_files_are_there_and_match_this_source():
    assert MANIFEST.is_file(), "no prebuilt kernels: run `python -m manip.prebuild` (make setup/test/demo do)"
    manifest = json.loads(MANIFEST.read_text())
    assert jit.environment() in jit.manifest_environments(manifest)
    assert manifest["sources"] == jit.source_digest(ROOT / "manip" / name for name in manifest["sources"])
    # every module that defines a kernel is in the digest
    defining = {str(p.relative_to(ROOT / "manip")) for p in (ROOT / "manip").rglob("*.py")
                if "\n@kernel" in p.read_text()}
    assert defining == set(manifest["sources"])
    assert any(PREBUILT_GEOMETRY.glob("spheres-*.npz")) and any(PREBUILT_GEOMETRY.glob("selfpair-*.json"))


def test_a_fresh_process_plans_and_simulates_without_compiling(tmp_path):
    out = _fresh(tmp_path)
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["ok"] == [True, True, True, True, True]
    assert report["compiled"] == [], f"kernels compiled in a fresh process: {report['compiled']} " \
                                     "(the prebuild workload in manip/prebuild.py does not meet them)"
    assert "compiling" not in out.stderr and "computing the collision geometry" not in out.stderr, out.stderr
    # nothing was computed for the Panda: its geometry came from the prebuilt folder
    assert not list((tmp_path / "manip").glob("spheres-*"))


CONSTRAINED_USE = textwrap.dedent("""
    import json
    import numpy as np
    from manip import Cuboid, MotionGenerator, OrientationConstraint, Pose, jit
    from manip import quaternion as quat
    mg = MotionGenerator("franka", {"cuboid": {"table": {"dims": [1.0, 1.2, 0.04], "pose": [0.5, 0, -0.02, 1, 0, 0, 0]}}})
    q0 = mg.default_joint_positions
    upright = OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=0.1)
    first = mg.plan_pose(q0, Pose([0.45, -0.3, 0.25], [0, 1, 0, 0]))
    # a start read from a returned trajectory (its arrays are read-only), then a straight line
    ok = [mg.plan_pose(first.trajectory.positions[-1], Pose([0.4, -0.1, 0.35], [0, 1, 0, 0]), linear=True,
                       constraints=(upright,)).success]
    ok.append(not mg.checker.in_collision_batch(first.trajectory.positions).any())  # read-only and column-major
    mg.add_obstacle(Cuboid("cube", [0.05, 0.05, 0.05], Pose([0.5, -0.3, 0.025])))
    grasps = Pose.stack([Pose([0.5, -0.3, 0.028], quat.multiply(quat.from_axis_angle([0, 0, 1], a), [0, 1, 0, 0]))
                         for a in (0.0, np.pi / 2)])
    grasp = mg.plan_grasp(q0, grasps, "cube", link="panda_hand_tcp")
    mg.attach_object("cube", q=grasp.segment("approach").goal_q, link="panda_hand_tcp")
    place = mg.plan_place(grasp.segment("lift").goal_q, Pose.stack([Pose([0.4, 0.3, 0.025])]), constraints=(upright,))
    ok += [grasp.success, place.success]
    print(json.dumps({"ok": [bool(x) for x in ok], "compiled": jit.compiled_names()}))
""")


def test_a_returned_trajectorys_arrays_passed_on_compile_nothing(tmp_path):
    # a trajectory's arrays are read-only (and its positions column-major): passed on to a kernel
    # as they are, each compiled a second version of it (8 s of CPU for the tilt certificate's,
    # 6 s for the self-collision broadphase's) in a fresh environment
    out = _fresh(tmp_path, code=CONSTRAINED_USE)
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["ok"] == [True, True, True, True]
    assert report["compiled"] == [], f"kernels compiled in a fresh process: {report['compiled']}"
    assert "compiling" not in out.stderr, out.stderr


def test_without_the_prebuilt_files_one_line_says_what_is_compiled_and_that_it_happens_once(tmp_path):
    code = textwrap.dedent("""
        import numpy as np
        from manip import jit
        from manip.kinematics import _joint_frames
        from manip.robot_config import load_robot_config
        from manip.kinematics import Kinematics
        kin = Kinematics(load_robot_config("franka"))
        kin.joint_transforms(np.zeros((2, kin.dof)))
        kin.joint_transforms(np.ones((3, kin.dof)))
        print(jit.compiled_names())
    """)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"), MANIP_CACHE_DIR=str(tmp_path / "manip"),
               MANIP_PREBUILT="off")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)
    assert out.returncode == 0, out.stderr
    assert "manip.kinematics._joint_frames" in out.stdout
    assert out.stderr.count("compiling manip's kernels for this machine") == 1, out.stderr
    assert "once" in out.stderr


def test_a_manifest_of_another_source_is_not_used(tmp_path, monkeypatch):
    manifest = json.loads(MANIFEST.read_text())
    manifest["sources"]["kinematics.py"] = "0" * 64  # as if kinematics.py had been edited since
    (tmp_path / "manifest.json").write_text(json.dumps(manifest))
    monkeypatch.setattr(jit, "PREBUILT_KERNELS", tmp_path)
    monkeypatch.setattr(jit, "_prebuilt_valid", None)
    assert jit._manifest_matches() is False
    monkeypatch.setattr(jit, "_prebuilt_valid", None)
    monkeypatch.setattr(jit, "PREBUILT_KERNELS", MANIFEST.parent)
    assert jit._manifest_matches() is True


def _elsewhere(env: dict, python: str) -> dict:
    """`env` of another Python version (`python` never this one: the test runs on any Python)."""
    assert python != env["python"]
    return dict(env, python=python)


def test_a_folder_built_for_several_pythons_serves_each_and_no_other(tmp_path, monkeypatch):
    manifest = json.loads(MANIFEST.read_text())
    here = jit.environment()
    monkeypatch.setattr(jit, "PREBUILT_KERNELS", tmp_path)
    for envs, used in (([_elsewhere(here, "2.7"), here, _elsewhere(here, "4.0")], True),
                       ([_elsewhere(here, "2.7"), _elsewhere(here, "4.0")], False),
                       ([dict(here, numba="0.0.1")], False)):
        (tmp_path / "manifest.json").write_text(json.dumps(dict(manifest, environment=envs[0], environments=envs)))
        monkeypatch.setattr(jit, "_prebuilt_valid", None)
        assert jit._manifest_matches() is used, envs
    # a manifest of one environment only (as manip 0.2.0 wrote them)
    (tmp_path / "manifest.json").write_text(json.dumps({"environment": here, "sources": manifest["sources"]}))
    monkeypatch.setattr(jit, "_prebuilt_valid", None)
    assert jit._manifest_matches() is True


def test_adding_another_pythons_kernels_keeps_every_environment_and_refuses_another_source():
    from manip.prebuild import merged_manifest

    manifest = json.loads(MANIFEST.read_text())
    here = jit.environment()
    other = _elsewhere(here, "4.0")
    built = {"environment": other, "environments": [other], "sources": manifest["sources"], "kernels": ["k.new"]}
    merged = merged_manifest(manifest, built)
    assert merged["environments"] == jit.manifest_environments(manifest) + [other]
    assert set(merged["kernels"]) == set(manifest["kernels"]) | {"k.new"}
    assert merged_manifest(merged, built)["environments"] == merged["environments"]  # added twice: once
    with pytest.raises(RuntimeError, match="another source"):
        merged_manifest(manifest, dict(built, sources=dict(manifest["sources"], **{"kinematics.py": "0" * 64})))
    with pytest.raises(RuntimeError, match="first"):
        merged_manifest(None, built)


def test_the_disk_cache_reads_the_users_folder_then_the_prebuilt_one_and_writes_only_the_users(tmp_path):
    user, prebuilt = tmp_path / "user", tmp_path / "prebuilt"
    prebuilt.mkdir()
    (prebuilt / "a.json").write_text("prebuilt")
    cache = DiskCache(user, prebuilt)
    assert cache.find("a.json") == prebuilt / "a.json"
    cache.write("a.json", lambda p: p.write_text("user"))
    assert cache.find("a.json") == user / "a.json" and (prebuilt / "a.json").read_text() == "prebuilt"
    assert cache.find("b.json") is None
    assert not list(user.glob("*.tmp*"))
    DiskCache(None, prebuilt).write("c.json", lambda p: p.write_text("x"))  # no user folder: nothing written
    assert not (prebuilt / "c.json").exists()


@pytest.mark.parametrize("kind", ["joints", "pose", "linear"])
def test_timings_account_for_the_whole_plan(kind):
    world = WorldConfig.from_dict({"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]}}})
    mg = MotionGenerator("franka", world)
    q0 = mg.default_joint_positions
    goal = Pose([0.5, 0.2, 0.3], [0, 1, 0, 0])
    r = {"joints": lambda: mg.plan_joints(q0, np.clip(q0 + 0.3, mg.lower_limits, mg.upper_limits)),
         "pose": lambda: mg.plan_pose(q0, goal),
         "linear": lambda: mg.plan_pose(q0, goal, linear=True)}[kind]()
    assert r.success
    stages = {k: v for k, v in r.timings.items() if k != "total"}
    assert "other" in stages and all(v >= 0.0 for v in stages.values())
    assert sum(stages.values()) == pytest.approx(r.timings["total"], rel=1e-9, abs=1e-9)
