"""The FK and IK examples run as scripts (headless) and exit 0."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from robot_constants import REPO_ROOT

EXAMPLES = REPO_ROOT / "examples"


@pytest.mark.parametrize(
    "script, args, expected",
    [
        ("forward_kinematics.py", ["--batch", "3"], ["panda_hand_tcp", "batch of 3", "quaternion (w, x, y, z)"]),
        ("inverse_kinematics.py", ["--batch", "50"], ["status=SUCCESS", "status=OUT_OF_REACH", "all as expected"]),
    ],
)
def test_example_runs(script: str, args: list[str], expected: list[str], tmp_path: Path):
    proc = subprocess.run(
        [sys.executable, str(EXAMPLES / script), *args],
        cwd=tmp_path,  # not the repository: the installed package is what runs
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for text in expected:
        assert text in proc.stdout, proc.stdout
