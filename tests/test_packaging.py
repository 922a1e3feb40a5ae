"""The wheel carries the robot configurations and models (a non-editable install can load them)."""

from __future__ import annotations

import subprocess
import sys
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
    (whl,) = out.glob("manip-*.whl")
    return whl


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
