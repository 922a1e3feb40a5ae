"""examples/carry_upright.py: the cup is carried upright in the simulator, judged by what the
simulator measures (the cup's tilt at every physics step, the marbles left in the cup)."""

from __future__ import annotations

import numpy as np
import pytest

from robot_constants import REPO_ROOT, load_script

EXAMPLE = REPO_ROOT / "examples" / "carry_upright.py"


def _load():
    return load_script(EXAMPLE, "carry_upright_example")


cu = _load()
pytestmark = pytest.mark.usefixtures("fresh_world")  # tests/conftest.py


def test_the_cup_is_carried_upright_with_its_marbles():
    demo = cu.CarryUpright(tolerance=0.1, marbles=6, verbose=False)
    try:
        assert demo.run()
        bottom, R = demo.cup_pose()
        assert np.linalg.norm(bottom[:2] - cu.CUP_GOAL[:2]) < 0.03 and abs(bottom[2] - cu.CUP_GOAL[2]) < 0.01
        assert demo.marbles_in_cup() == 6
        # measured in the simulation at every physics step, from the first motion to the end:
        # the cup's own tilt (the plan holds it within 0.1 - GRIP_BUDGET; the grip's slip and the
        # arm's tracking stay within the budget)
        assert 0.0 < demo.max_tilt <= 0.1
        assert 0.0 < demo.max_hand_tilt <= 0.1
        assert np.all(demo.robot.gripper.get_joint_positions() > 0.035)  # released
    finally:
        demo.close()


def test_cli_reports_the_measured_tilt(capsys):
    assert cu.main(["--marbles", "2", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "marbles in the cup: 2/2" in out and "measured tilt of the cup" in out and "carried upright" in out
    assert "measured tilt of the hand's constrained axis" in out
