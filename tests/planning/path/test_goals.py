"""The order in which a plan tries goal configurations (`manip.planning.path.goals`)."""

from __future__ import annotations

import numpy as np

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
