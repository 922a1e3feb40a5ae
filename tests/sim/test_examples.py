"""Every simulation example runs headless and succeeds (exit status 0)."""

from __future__ import annotations

import subprocess
import sys

import pytest
from robot_constants import REPO_ROOT

EXAMPLES = REPO_ROOT / "examples"

CASES = {
    "hello_world.py": ["--steps", "150"],
    "hello_robot.py": ["--steps", "120"],
    "my_controller.py": ["--steps", "120"],
    "wheel_pose_controller.py": [],
    "control_robot.py": ["--targets", "2", "--hold", "1.5"],
    "robot_info.py": [],
    "sample_lifecycle.py": ["--steps", "30"],
    "tutorial_pick_and_place.py": ["--steps", "1400"],
    "bimanual_handover.py": ["--episodes", "1", "--quiet"],
    "bimanual_carry.py": ["--episodes", "1", "--quiet"],
    "lula_kinematics.py": ["--steps", "240"],
    "rmpflow_follow_target.py": ["--steps", "1200"],
}


@pytest.mark.parametrize("script", sorted(CASES))
def test_example_runs_headless(script):
    proc = subprocess.run([sys.executable, str(EXAMPLES / script), *CASES[script]], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, f"{script} failed:\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}"
    assert proc.stdout.strip()
