"""The motion-generation examples run as scripts and print what they promise."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from robot_constants import REPO_ROOT

EXAMPLES = REPO_ROOT / "examples"


@pytest.mark.parametrize(
    "script, expected",
    [
        (
            "motion_generation.py",
            ["left -> right (over the wall) SUCCESS", "straight down 10 cm", "goal inside the wall         IK_FAIL"],
        ),
        ("collision_avoidance.py", ["carrying the bar: SUCCESS", "bar released at"]),
    ],
)
def test_example_runs(script: str, expected: list[str], tmp_path: Path):
    proc = subprocess.run(
        [sys.executable, str(EXAMPLES / script)], cwd=tmp_path, capture_output=True, text=True, timeout=300,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for text in expected:
        assert text in proc.stdout, proc.stdout
