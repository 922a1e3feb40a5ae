"""The wheel: its name, the robot configurations and models, the prebuilt kernels; installed in a
new venv outside the repository, it plans and simulates without compiling."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import pytest
from robot_constants import REPO_ROOT

ROOT = REPO_ROOT


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    proc = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(out), str(ROOT)],
        capture_output=True, text=True, timeout=600,
    )
    if proc.returncode != 0:
        pytest.fail(f"building the wheel failed:\n{proc.stderr[-2000:]}")
    (whl,) = out.glob("manip_robotics-*.whl")
    return whl


def test_the_distribution_is_manip_robotics_and_imports_as_manip(wheel):
    meta = next(n for n in zipfile.ZipFile(wheel).namelist() if n.endswith(".dist-info/METADATA"))
    text = zipfile.ZipFile(wheel).read(meta).decode()
    assert "\nName: manip-robotics\n" in text
    assert wheel.name.startswith("manip_robotics-") and wheel.name.endswith("-py3-none-any.whl")


def test_wheel_carries_the_prebuilt_kernels_of_this_checkout(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    prebuilt = ROOT / "manip" / "_prebuilt"
    files = [p for p in prebuilt.rglob("*") if p.is_file()]
    assert files, "no prebuilt files in the checkout: run `python -m manip.prebuild` (make setup does)"
    for path in files:
        assert f"manip/_prebuilt/{path.relative_to(prebuilt).as_posix()}" in names
    assert "manip/_prebuilt/kernels/manifest.json" in names


def test_wheel_carries_every_robot_file(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for path in (ROOT / "robots").rglob("*"):
        if path.is_file() and "__pycache__" not in path.parts:
            rel = path.relative_to(ROOT / "robots").as_posix()
            assert f"manip/_robots/{rel}" in names, f"{rel} missing from the wheel"
    assert "manip/__init__.py" in names and "manip/sim/__init__.py" in names


def test_installed_layout_resolves_robots(wheel, tmp_path):
    """robots_root() finds manip/_robots in an unpacked wheel, away from the source tree."""
    zipfile.ZipFile(wheel).extractall(tmp_path)
    code = (
        "import manip.robot_config as rc, pathlib, sys;"
        "root = rc.robots_root(); assert root == pathlib.Path(sys.argv[1]) / 'manip' / '_robots', root;"
        "cfg = rc.load_robot_config('franka'); assert cfg.mjcf_path.is_file(), cfg.mjcf_path;"
        "print(cfg.folder)"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code, str(tmp_path)], capture_output=True, text=True, cwd=tmp_path,
        env={"PYTHONPATH": str(tmp_path), "PATH": "/usr/bin:/bin"}, timeout=120,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]


INSTALLED_USE = textwrap.dedent("""
    import json, os, pathlib, sys
    import manip
    from manip import MotionGenerator, Pose, jit
    from manip.sim import DynamicCuboid, Franka, World
    assert "site-packages" in manip.__file__, manip.__file__
    mg = MotionGenerator("franka")
    q0 = mg.default_joint_positions
    ok = [mg.plan_joints(q0, q0 + 0.3).success, mg.plan_pose(q0, Pose([0.5, 0.2, 0.3], [0, 1, 0, 0])).success]
    w = World()
    w.scene.add_default_ground_plane()
    w.scene.add(Franka("/World/Franka", name="franka"))
    cube = w.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.3], size=0.05))
    w.reset()
    for _ in range(30):
        w.step(render=False)
    print(json.dumps({"ok": [bool(x) for x in ok], "cube_z": float(cube.get_world_pose()[0][2]), "compiled": jit.compiled_names()}))
""")


def test_the_wheel_installed_in_a_new_venv_plans_and_simulates_from_another_folder(wheel, tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    python = str(venv / "bin" / "python")
    pip = subprocess.run([python, "-m", "pip", "install", "-q", str(wheel)], capture_output=True, text=True,
                         timeout=1800)
    assert pip.returncode == 0, pip.stderr[-3000:]
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "NUMBA_CACHE_DIR", "MANIP_CACHE_DIR")}
    env.update(MANIP_CACHE_DIR=str(tmp_path / "cache"), MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"))
    out = subprocess.run([python, "-c", INSTALLED_USE], capture_output=True, text=True, cwd=elsewhere, env=env,
                         timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["ok"] == [True, True]
    assert report["cube_z"] < 0.1  # it fell onto the ground
    assert report["compiled"] == []  # the wheel's prebuilt kernels were used
