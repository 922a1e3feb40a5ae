"""Joint positions past a limit are set as Isaac sets them, then the limit pushes the joint
back (issue 32, item 6); NaN, inf and absurd magnitudes still raise."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import Franka, World


@pytest.fixture
def franka():
    world = World()
    world.scene.add_default_ground_plane()
    robot = world.scene.add(Franka(prim_path="/World/Franka", name="franka"))
    world.reset()
    return world, robot


def test_zeros_are_set_with_a_warning_then_joint4_returns_inside_its_limit(franka, caplog):
    world, robot = franka
    with caplog.at_level(logging.WARNING):
        robot.set_joint_positions(np.zeros(9))  # was InvalidInputError: panda_joint4=0 not in [-3.07, -0.07]
    assert "panda_joint4=0.0000 not in" in caplog.text and "back on their limits" in caplog.text
    np.testing.assert_array_equal(robot.get_joint_positions(), np.zeros(9))  # as set, until physics runs
    world.step(render=False)
    lo, hi = robot.get_dof_limits().T
    q = robot.get_joint_positions()
    assert np.all(q >= lo) and np.all(q <= hi)
    assert hi[3] - 0.05 < q[3] <= hi[3]  # pushed back inside, next to the limit
    for _ in range(60):
        world.step(render=False)
    q = robot.get_joint_positions()
    assert np.all(q >= lo - 1e-9) and np.all(q <= hi + 1e-9)


@pytest.mark.parametrize("bad, match", [(np.nan, "finite"), (np.inf, "finite"), (1e7, "largest accepted magnitude")])
def test_non_finite_and_absurd_positions_still_raise_and_change_nothing(franka, bad, match):
    world, robot = franka
    q = robot.get_joint_positions()
    with pytest.raises(InvalidInputError, match=match):
        robot.set_joint_positions(np.r_[q[:3], bad, q[4:]])
    np.testing.assert_array_equal(robot.get_joint_positions(), q)
