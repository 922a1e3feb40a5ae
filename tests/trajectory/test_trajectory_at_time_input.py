"""Trajectory.at_time: bad times raise an InvalidInputError naming the argument."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.robot_config import load_robot_config
from manip.timing import time_parameterize_for_robot


@pytest.fixture(scope="module")
def traj():
    cfg = load_robot_config("franka")
    a = np.array(cfg.default_joint_positions)
    r = time_parameterize_for_robot(np.array([a, a + 0.3]), cfg, dt=1 / 60)
    assert r.success
    return r.trajectory


@pytest.mark.parametrize("t, words", [
    ("0.5", ["at_time: t", "a time [s] or an (N,) array of times", "'0.5'", "str"]),
    (["0.1", "0.2"], ["at_time: t", "'0.1'", "list"]),
    (1j, ["at_time: t", "1j", "complex"]),
    (True, ["at_time: t", "True", "bool"]),
    (None, ["at_time: t", "None"]),
    ([[0.1, 0.2], [0.3]], ["at_time: t", "[[0.1, 0.2], [0.3]]"]),
    (np.zeros((2, 3)), ["at_time: t", "(N,) array", "shape (2, 3)"]),
    ([[0.1], [0.2]], ["at_time: t", "shape (2, 1)"]),
    (np.nan, ["at_time: t", "finite"]),
    ([0.1, np.inf], ["at_time: t", "finite"]),
])
def test_bad_times_name_the_argument(traj, t, words):
    with pytest.raises(InvalidInputError) as info:
        traj.at_time(t)
    for w in words:
        assert w in str(info.value)


@pytest.mark.parametrize("sampled", [False, True])
def test_good_times_still_work(traj, sampled):
    if sampled:  # no profile: the sampled interpolation
        from manip.trajectory import Trajectory

        traj = Trajectory(traj.times, traj.positions, traj.velocities, traj.accelerations, traj.jerks, traj.dt,
                          traj.joint_names)
        assert traj.profile is None
    q, qd, qdd = traj.at_time(0.1)
    assert q.shape == qd.shape == qdd.shape == (7,)
    q, _, _ = traj.at_time([0.0, traj.duration])
    np.testing.assert_allclose(q, traj.positions[[0, -1]], atol=1e-9)
    q, _, _ = traj.at_time(np.int64(0))
    np.testing.assert_allclose(q, traj.positions[0], atol=1e-12)
