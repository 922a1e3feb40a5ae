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


@pytest.mark.parametrize("robot", ["ur5", "xarm7"])
def test_pose_goals_end_at_the_ik_solution_turned_nearest_the_start(robot):
    """Joints that turn +-2 pi: an IK solution a whole turn further than needed is the same pose
    (the same contacts) by a longer motion. Before, 7 of 21 random UR5 plan_pose calls (seed 5001)
    ended turning a joint 3.2-5.7 rad where a turn the other way needed under pi."""
    mg = MotionGenerator(robot)
    lo, hi = mg.lower_limits, mg.upper_limits
    rng = np.random.default_rng(5001)
    ends = []
    while len(ends) < 12:
        a, b = rng.uniform(lo, hi), rng.uniform(lo, hi)
        if mg.check_collision(a) or mg.check_collision(b):
            continue
        r = mg.plan_pose(a, mg.fk(b))
        assert r.success, r.message
        g = r.trajectory.positions[-1]
        d = g - a
        other_way = g - 2 * np.pi * np.sign(d)
        assert np.allclose(mg.fk(g).position, mg.fk(b).position, atol=1e-3)
        ends.append(np.any((np.abs(d) > np.pi) & (other_way >= lo) & (other_way <= hi)))
    assert not any(ends), f"{sum(ends)} of 12 plans turned a joint more than pi where less would do"


def test_whole_turns_move_revolute_joints_only():
    """A prismatic joint's "2 pi" is 6.28 m of travel, not the same placement: a rail with long
    limits keeps its IK value; revolute joints of the same arm turn to the value nearest the start."""
    from types import SimpleNamespace

    from manip.planning.goal_configurations import nearest_turn

    ur5 = MotionGenerator("ur5").kinematics
    rail = SimpleNamespace(dof=ur5.dof + 1, lower=np.r_[-10.0, ur5.lower], upper=np.r_[10.0, ur5.upper],
                           joint_revolute=np.r_[False, ur5.joint_revolute],
                           fk_tables=lambda: (np.arange(ur5.dof + 1), None, None))
    start = np.r_[-3.0, np.zeros(ur5.dof)]
    q = np.r_[3.0, 5.0, np.zeros(ur5.dof - 1)]
    near = nearest_turn(q, start, rail)
    assert near[0] == 3.0                                    # the rail: 6 m away, but not a turn
    assert np.isclose(near[1], 5.0 - 2 * np.pi)              # the UR5's base: the same placement nearer
    assert np.array_equal(nearest_turn(q[1:], start[1:], ur5), near[1:])
