"""The reactive controller reports a local minimum (StepStatus.STALLED) instead of wandering silently."""

from __future__ import annotations

import numpy as np

from manip.control import ReactiveController, StepStatus
from manip.pose import Pose

DT = 1 / 60


def _run(ctrl, target, seconds):
    q = ctrl.rest_configuration
    out = []
    for _ in range(int(seconds / DT)):
        r = ctrl.step(q, target, DT)
        out.append(r)
        q = r.q
    return q, out


def test_ur10_behind_itself_is_reported_stalled():
    """A UR10 target behind the base (a 150 deg turn; benchmarks/reactive_reach.py seed 6100, target 5, the
    class of the round-four UR10 pick): the steps stay solved but the arm gets stuck over 1 m away."""
    c = ReactiveController("ur10")
    target = Pose([-1.0348, -0.5222, 0.4202], [0.2229, -0.5734, 0.1007, 0.7819])
    _, rs = _run(c, target, 5.0)
    first = next(k for k, r in enumerate(rs) if r.status is StepStatus.STALLED)
    assert 2.0 <= first * DT <= 4.5
    assert rs[first].solved and rs[first].stalled and rs[first].position_error > 0.5
    assert all(r.status is StepStatus.SOLVED for r in rs[:first])


def test_reached_and_moving_targets_do_not_stall():
    c = ReactiveController("franka")
    q_goal = c.rest_configuration + np.array([0.5, 0.3, -0.2, 0.4, 0.1, -0.3, 0.2])
    goal = c.frame_pose(q_goal)
    _, rs = _run(c, goal, 4.0)
    assert rs[-1].position_error < 1e-3
    assert not any(r.stalled for r in rs)
    # a target that keeps moving (a circle) never stalls, even where the arm lags behind it
    c.reset()
    q = c.rest_configuration
    p0 = c.frame_pose(q).position
    for k in range(240):
        r = c.step(q, p0 + 0.1 * np.array([np.cos(k / 20) - 1, np.sin(k / 20), 0.0]), DT)
        assert not r.stalled
        q = r.q


def test_out_of_reach_stalls_then_recovers_and_stall_time_none_disables():
    c = ReactiveController("franka", stall_time=0.5)
    far = Pose([2.5, 0.0, 0.5])
    q, rs = _run(c, far.position, 3.0)
    assert rs[-1].stalled and rs[-1].position_error > 1.0
    assert all(r.stalled for r in rs[-60:])  # stays stalled while the arm oscillates at full stretch
    near = c.frame_pose(c.rest_configuration).position
    rs = []
    for _ in range(180):  # a reachable target again: the arm approaches it, the steps are SOLVED again
        rs.append(c.step(q, near, DT))
        q = rs[-1].q
    k = next(k for k, r in enumerate(rs) if r.status is StepStatus.SOLVED)
    assert k * DT < 0.5 and rs[-1].position_error < 1e-3 and not any(r.stalled for r in rs[k:])
    off = ReactiveController("franka", stall_time=None)
    _, rs = _run(off, far.position, 3.0)
    assert not any(r.stalled for r in rs)


def test_frame_pose_is_where_step_measures_the_error():
    c = ReactiveController("ur5")
    q = c.rest_configuration + 0.2
    pose = c.frame_pose(q)
    r = c.step(q, pose, DT)
    assert r.position_error < 1e-12 and r.orientation_error < 1e-6
