"""Quality metrics of the benchmark: lower bound on motion time, path lengths, max jerk."""

from __future__ import annotations

import math

import numpy as np
import pytest
import ruckig

from manip.benchmarking.quality import lower_bound_time, max_jerk, path_length, safe_ratio, straight_line_length
from manip.errors import InvalidInputError


def _ruckig_duration(q0, q1, v, a, j) -> float:
    dof = len(q0)
    otg = ruckig.Ruckig(dof)
    inp = ruckig.InputParameter(dof)
    inp.current_position = list(q0)
    inp.target_position = list(q1)
    inp.current_velocity = [0.0] * dof
    inp.current_acceleration = [0.0] * dof
    inp.target_velocity = [0.0] * dof
    inp.target_acceleration = [0.0] * dof
    inp.max_velocity = list(v)
    inp.max_acceleration = list(a)
    inp.max_jerk = list(j)
    tr = ruckig.Trajectory(dof)
    assert otg.calculate(inp, tr) == ruckig.Result.Working
    return tr.duration


def test_lower_bound_equals_a_direct_ruckig_call(franka_config):
    rng = np.random.default_rng(3)
    c = franka_config
    for _ in range(5):
        q0 = rng.uniform(c.lower_limits, c.upper_limits)
        q1 = rng.uniform(c.lower_limits, c.upper_limits)
        lb = lower_bound_time(q0, q1, c.velocity_limits, c.acceleration_limits, c.jerk_limits)
        assert lb == pytest.approx(_ruckig_duration(q0, q1, c.velocity_limits, c.acceleration_limits, c.jerk_limits),
                                   rel=1e-12)
        # every joint alone needs at least distance / vmax
        assert lb >= float(np.max(np.abs(q1 - q0) / c.velocity_limits)) - 1e-12


def test_lower_bound_edge_cases():
    q = np.zeros(3)
    assert lower_bound_time(q, q, 1.0, 1.0, 1.0) == 0.0
    # one joint, 1 rad, v=2, a=15, infinite jerk: trapezoid 1/2 + 2/15 s
    assert lower_bound_time([0.0], [1.0], 2.0, 15.0, math.inf) == pytest.approx(0.5 + 2.0 / 15.0)
    finite = lower_bound_time([0.0, 0.0], [1.0, -0.5], 2.0, 15.0, 500.0)
    assert finite > lower_bound_time([0.0, 0.0], [1.0, -0.5], 2.0, 15.0, math.inf)
    with pytest.raises(InvalidInputError):
        lower_bound_time([0.0, 0.0], [1.0], 1.0, 1.0, 1.0)
    with pytest.raises(InvalidInputError):
        lower_bound_time([0.0], [1.0], 1.0, 0.0, 1.0)
    with pytest.raises(InvalidInputError):
        lower_bound_time([0.0], [math.nan], 1.0, 1.0, 1.0)


def test_lower_bound_is_below_manips_planned_duration():
    from manip import MotionGenerator

    mg = MotionGenerator("franka")
    q0 = mg.default_joint_positions
    goals = [q0 + np.array([0.8, -0.3, 0.4, 0.5, -0.6, 0.3, 1.0]), q0 + np.array([-1.2, 0.4, 0.0, 0.3, 0.0, -0.4, 0.0])]
    c = mg.config
    for q1 in goals:
        r = mg.plan_joints(q0, q1)
        assert r.success, r.status
        t = np.asarray(r.trajectory.times)
        lb = lower_bound_time(q0, q1, c.velocity_limits, c.acceleration_limits, c.jerk_limits)
        assert 0.0 < lb <= (t[-1] - t[0]) + 1e-9
        assert path_length(np.asarray(r.trajectory.positions)) >= straight_line_length(q0, q1) - 1e-9


def test_path_length_of_a_straight_line_is_its_l2_norm():
    q0 = np.array([0.1, -0.2, 0.3, -1.5, 0.0, 1.2, 0.4])
    q1 = np.array([0.9, 0.4, -0.3, -2.0, 1.0, 2.0, -0.4])
    s = np.linspace(0.0, 1.0, 37) ** 2  # uneven, monotone samples of the segment
    P = q0 + s[:, None] * (q1 - q0)
    assert path_length(P) == pytest.approx(np.linalg.norm(q1 - q0), rel=1e-12)
    assert straight_line_length(q0, q1) == pytest.approx(np.linalg.norm(q1 - q0), rel=1e-12)
    # there and back again: twice the distance
    assert path_length(np.stack([q0, q1, q0])) == pytest.approx(2 * np.linalg.norm(q1 - q0))
    assert path_length(q0[None, :]) == 0.0
    with pytest.raises(InvalidInputError):
        path_length(q0)


def test_max_jerk_is_the_largest_absolute_jerk_over_time_and_joints():
    J = np.array([[0.0, 1.0, -2.0], [3.0, -7.5, 0.5], [0.0, 0.0, 0.0]])
    assert max_jerk(J) == 7.5

    class T:
        jerks = J

    assert max_jerk(T()) == 7.5
    assert math.isnan(max_jerk(np.zeros((0, 3))))


def test_safe_ratio():
    assert safe_ratio(3.0, 2.0) == 1.5
    assert math.isnan(safe_ratio(1.0, 0.0))
    assert math.isnan(safe_ratio(math.nan, 1.0))
