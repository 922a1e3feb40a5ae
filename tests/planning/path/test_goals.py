"""The order in which a plan tries goal configurations (`manip.planning.path.goals`)."""

from __future__ import annotations

import numpy as np
import pytest

from manip import MotionGenerator
from manip.planning.path import goals
from manip.planning.path.goals import TIME_BAND, order_goals
from manip.timing.bounds import rest_to_rest_time


def _limits():
    mg = MotionGenerator("franka")
    return mg.default_joint_positions, mg.limits


def test_near_fastest_goals_go_shortest_first_and_slow_goals_last():
    start, limits = _limits()
    fast_short = start + np.array([0.8, 0, 0, 0, 0, 0, 0])
    fastest_long = start + np.array([0.79, 0.5, 0.5, -0.5, 0.5, 0.0, 0.0])  # a little faster, much longer
    slow = start + np.array([1.6, 0, 0, 0, 0, 0, 0])
    configs = np.stack([slow, fastest_long, fast_short])
    bounds = [rest_to_rest_time(start, q, limits) for q in configs]
    # the premise: the long goal is the fastest, the short one within the band, the slow one outside
    assert bounds[1] < bounds[2] <= bounds[1] * (1 + TIME_BAND) < bounds[0]
    order = order_goals(start, configs, limits)
    assert list(order) == [2, 1, 0]


def test_without_a_band_the_fastest_goal_comes_first(monkeypatch):
    start, limits = _limits()
    monkeypatch.setattr(goals, "TIME_BAND", 0.0)
    configs = np.stack([start + d for d in (np.array([0.8, 0, 0, 0, 0, 0, 0]),
                                            np.array([0.79, 0.5, 0.5, -0.5, 0.5, 0.0, 0.0]),
                                            np.array([1.6, 0, 0, 0, 0, 0, 0]))])
    bounds = np.array([rest_to_rest_time(start, q, limits) for q in configs])
    assert list(order_goals(start, configs, limits)) == list(np.argsort(bounds))


def test_single_joint_times_are_ruckigs_and_stand_in_where_ruckig_fails():
    """`single_joint_times` is the closed form of one joint's time-optimal S-curve (ruckig's to
    1e-12 over short, cruising and acceleration-limited moves); where ruckig fails on a motion
    of hours, `rest_to_rest_time` returns their maximum, a lower bound of the synchronised time."""
    import ruckig

    from manip.limits import JointLimits
    from manip.timing.bounds import single_joint_times

    start, limits = _limits()
    for d in (1e-6, 1e-3, 0.05, 0.4, 3.0):
        for k in range(start.size):
            otg, inp, traj = ruckig.Ruckig(1), ruckig.InputParameter(1), ruckig.Trajectory(1)
            inp.current_position, inp.target_position = [0.0], [d]
            inp.max_velocity = [limits.velocity[k]]
            inp.max_acceleration = [limits.acceleration[k]]
            inp.max_jerk = [limits.jerk[k]]
            otg.calculate(inp, traj)
            mine = single_joint_times(np.full(1, d), limits.velocity[[k]], limits.acceleration[[k]], limits.jerk[[k]])
            assert mine[0] == pytest.approx(traj.duration, rel=1e-12)
    goal = start + np.array([-0.9, 1.085, 0.0, 0.456, 0.0, 0.529, 0.015])
    assert rest_to_rest_time(start, goal, limits) >= single_joint_times(
        np.abs(goal - start), limits.velocity, limits.acceleration, limits.jerk).max() - 1e-12
    slow = JointLimits(limits.velocity * 1e-4, limits.acceleration, limits.jerk)
    bound = rest_to_rest_time(start, goal, slow)   # ruckig raises on this one
    assert bound == single_joint_times(np.abs(goal - start), slow.velocity, slow.acceleration, slow.jerk).max()
    assert bound > 3600.0
