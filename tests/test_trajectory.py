"""Tests of manip.trajectory: the Trajectory type and its exact piecewise-jerk profile."""

from __future__ import annotations

import numpy as np
import pytest

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, UnknownNameError
from manip.robot_config import load_robot_config
from manip.timing import time_parameterize_for_robot
from manip.trajectory import PiecewiseJerkProfile, Trajectory, sample_times


@pytest.fixture(scope="module")
def cfg():
    return load_robot_config("franka")


@pytest.fixture(scope="module")
def traj(cfg):
    a = np.array(cfg.default_joint_positions)
    path = np.array(
        [a, a + [0.5, 0.3, -0.2, 0.4, 0.1, -0.3, 0.6], a + [0.9, -0.1, 0.3, 0.6, -0.4, 0.2, 1.2], a + [0.2, 0, 0, 0, 0, 0, 0]]
    )
    r = time_parameterize_for_robot(path, cfg, dt=1 / 60)
    assert r.success
    return r.trajectory


class DofNamesRobot:
    """Like Isaac's Articulation / manip.sim robots: fingers after the arm, arm joints in a shuffled order."""

    def __init__(self, arm):
        self.dof_names = [arm[2], arm[0], arm[1], *arm[3:], "panda_finger_joint1", "panda_finger_joint2"]


class IndexOnlyRobot:
    def __init__(self, names):
        self._names = list(names)

    def get_dof_index(self, name):
        return self._names.index(name) if name in self._names else -1


def test_samples_come_from_the_exact_profile(traj):
    q, qd, qdd = traj.at_time(traj.times)
    np.testing.assert_array_equal(q, traj.positions)
    np.testing.assert_array_equal(qd, traj.velocities)
    np.testing.assert_array_equal(qdd, traj.accelerations)
    assert traj.positions.shape == (traj.num_samples, 7)
    assert traj.duration == traj.times[-1]


def test_profile_is_consistent_with_its_own_derivatives(traj):
    """Finite differences of positions match velocities etc. (the pieces are integrated right)."""
    h = 1e-6
    t = np.linspace(0.01, traj.duration - 0.01, 301)
    q0, v0, a0 = traj.at_time(t)
    q1, v1, a1 = traj.at_time(t + h)
    qm, vm, am = traj.at_time(t - h)
    np.testing.assert_allclose((q1 - qm) / (2 * h), v0, atol=1e-6)
    np.testing.assert_allclose((v1 - vm) / (2 * h), a0, atol=1e-3)
    # continuity: no jumps in position, velocity or acceleration anywhere
    tt = np.linspace(0, traj.duration, 20001)
    q, v, a = traj.at_time(tt)
    dt = tt[1] - tt[0]
    jmax = traj.max_abs_jerk().max()
    assert np.abs(np.diff(a, axis=0)).max() <= jmax * dt * (1 + 1e-9)


def test_analytic_extrema_bound_dense_samples(traj):
    e = traj.profile.extrema()
    t = np.linspace(0, traj.duration, 50001)
    q, qd, qdd, qddd = traj.profile.evaluate(t)
    assert np.all(e["max_abs_velocity"] >= np.abs(qd).max(axis=0))
    assert np.all(e["max_abs_acceleration"] >= np.abs(qdd).max(axis=0))
    assert np.all(e["position_max"] >= q.max(axis=0)) and np.all(e["position_min"] <= q.min(axis=0))
    # and are attained (up to the sampling step)
    step = t[1] - t[0]
    np.testing.assert_allclose(e["max_abs_velocity"], np.abs(qd).max(axis=0), atol=500 * step**2)
    np.testing.assert_allclose(e["position_max"], q.max(axis=0), atol=3 * step**2)
    np.testing.assert_allclose(e["max_abs_jerk"], np.abs(qddd).max(axis=0))


def test_at_time_clamps_and_shapes(traj):
    q, qd, qdd = traj.at_time(-1.0)
    assert q.shape == (7,)
    np.testing.assert_array_equal(q, traj.positions[0])
    np.testing.assert_array_equal(qd, 0.0)
    q, qd, qdd = traj.at_time(traj.duration + 5.0)
    np.testing.assert_array_equal(q, traj.positions[-1])
    np.testing.assert_array_equal(qd, 0.0)
    np.testing.assert_array_equal(qdd, 0.0)
    q, _, _ = traj.at_time(np.array([0.1, 0.2]))
    assert q.shape == (2, 7)
    with pytest.raises(InvalidInputError):
        traj.at_time(np.nan)


def test_resample_is_exact_and_keeps_duration(traj):
    r = traj.resample(0.004)
    assert r.duration == traj.duration
    assert r.dt == 0.004
    q, qd, qdd = traj.at_time(r.times)
    np.testing.assert_array_equal(r.positions, q)
    np.testing.assert_array_equal(r.velocities, qd)
    steps = np.diff(r.times)
    np.testing.assert_allclose(steps[:-1], 0.004, rtol=1e-9)
    assert 0 < steps[-1] <= 0.004 + 1e-12
    back = r.resample(traj.dt)
    np.testing.assert_allclose(back.positions, traj.positions, atol=1e-12)


def test_samples_only_trajectory_interpolates(traj):
    fine = traj.resample(0.002)
    plain = Trajectory(fine.times, fine.positions, fine.velocities, fine.accelerations, fine.jerks, fine.dt, fine.joint_names)
    assert plain.profile is None
    # at the samples: the samples
    q, qd, qdd = plain.at_time(fine.times[5])
    np.testing.assert_array_equal(q, fine.positions[5])
    # between samples: cubic Hermite, close to the exact motion
    t = np.linspace(0, traj.duration, 777)
    np.testing.assert_allclose(plain.at_time(t)[0], traj.at_time(t)[0], atol=1e-6)
    np.testing.assert_allclose(plain.at_time(t)[1], traj.at_time(t)[1], atol=0.01)
    coarse = plain.resample(0.01)
    assert coarse.duration == pytest.approx(traj.duration)
    np.testing.assert_allclose(coarse.positions, traj.at_time(coarse.times)[0], atol=1e-6)


def test_path_length_and_helpers(traj, cfg):
    t = np.linspace(0, traj.duration, 100001)
    q = traj.at_time(t)[0]
    exact = np.linalg.norm(np.diff(q, axis=0), axis=1).sum()
    assert traj.path_length() <= exact + 1e-9
    assert traj.path_length() == pytest.approx(exact, rel=0.02)
    assert np.all(traj.max_abs_velocity() <= cfg.velocity_limits)
    assert np.all(traj.max_abs_acceleration() <= cfg.acceleration_limits)
    assert np.all(traj.max_abs_jerk() <= cfg.jerk_limits)
    line = Trajectory([0.0, 1.0], [[0.0, 0.0], [3.0, 4.0]], np.zeros((2, 2)), np.zeros((2, 2)), np.zeros((2, 2)), 1.0, ["a", "b"])
    assert line.path_length() == 5.0


def test_arrays_are_read_only(traj):
    with pytest.raises(ValueError):
        traj.positions[0, 0] = 1.0
    with pytest.raises(Exception):
        traj.dt = 0.1


def test_to_articulation_actions_indexes_robot_dofs(traj, cfg):
    robot = DofNamesRobot(list(cfg.arm_joints))
    actions = traj.to_articulation_actions(robot)
    assert len(actions) == traj.num_samples - 1
    assert all(isinstance(a, ArticulationAction) for a in actions)
    idx = actions[0].joint_indices
    for k, name in enumerate(traj.joint_names):
        assert robot.dof_names[idx[k]] == name
    np.testing.assert_array_equal(actions[0].joint_positions, traj.positions[1])
    np.testing.assert_array_equal(actions[-1].joint_positions, traj.positions[-1])
    np.testing.assert_array_equal(actions[-1].joint_velocities, 0.0)
    assert actions[0].joint_efforts is None
    # per physics step
    per_step = traj.to_articulation_actions(robot, physics_dt=1 / 240)
    assert len(per_step) == int(np.ceil(traj.duration * 240 - 1e-9))
    np.testing.assert_array_equal(per_step[-1].joint_positions, traj.positions[-1])
    # get_dof_index-only robot
    other = traj.to_articulation_actions(IndexOnlyRobot(robot.dof_names))
    np.testing.assert_array_equal(other[0].joint_indices, idx)


def test_to_articulation_actions_unknown_joint(traj, cfg):
    robot = DofNamesRobot(list(cfg.arm_joints))
    robot.dof_names.remove("panda_joint4")
    with pytest.raises(UnknownNameError) as e:
        traj.to_articulation_actions(robot)
    assert "panda_joint4" in str(e.value) and "panda_finger_joint1" in str(e.value)
    with pytest.raises(UnknownNameError):
        traj.to_articulation_actions(IndexOnlyRobot(robot.dof_names))
    with pytest.raises(InvalidInputError, match="dof_names"):
        traj.to_articulation_actions(object())


def test_time_scaled_profile(traj):
    p = traj.profile
    s = p.time_scaled(2.0)
    assert s.duration == pytest.approx(2 * p.duration)
    t = np.linspace(0, p.duration, 101)
    q, qd, qdd, j = p.evaluate(t)
    q2, qd2, qdd2, j2 = s.evaluate(2 * t)
    np.testing.assert_allclose(q2, q, atol=1e-12)
    np.testing.assert_allclose(qd2, qd / 2, atol=1e-12)
    np.testing.assert_allclose(qdd2, qdd / 4, atol=1e-10)
    with pytest.raises(InvalidInputError):
        p.time_scaled(0.0)


def test_construction_validates():
    t = np.array([0.0, 0.1, 0.2])
    z = np.zeros((3, 2))
    Trajectory(t, z, z, z, z, 0.1, ["a", "b"])  # fine
    with pytest.raises(InvalidInputError, match="positions"):
        Trajectory(t, np.zeros((2, 2)), z, z, z, 0.1, ["a", "b"])
    with pytest.raises(InvalidInputError, match="velocities"):
        Trajectory(t, z, np.zeros((3, 3)), z, z, 0.1, ["a", "b"])
    with pytest.raises(InvalidInputError, match="joint_names"):
        Trajectory(t, z, z, z, z, 0.1, ["a"])
    with pytest.raises(InvalidInputError, match="duplicates"):
        Trajectory(t, z, z, z, z, 0.1, ["a", "a"])
    with pytest.raises(InvalidInputError, match="start at 0"):
        Trajectory(t + 0.1, z, z, z, z, 0.1, ["a", "b"])
    with pytest.raises(InvalidInputError, match="spaced"):
        Trajectory(np.array([0.0, 0.1, 0.3]), z, z, z, z, 0.1, ["a", "b"])
    with pytest.raises(InvalidInputError, match="increasing"):
        Trajectory(np.array([0.0, 0.1, 0.1]), z, z, z, z, 0.1, ["a", "b"])
    bad = z.copy()
    bad[1, 1] = np.inf
    with pytest.raises(InvalidInputError, match="non-finite"):
        Trajectory(t, bad, z, z, z, 0.1, ["a", "b"])
    with pytest.raises(InvalidInputError, match="dt"):
        Trajectory(t, z, z, z, z, 0.0, ["a", "b"])
    with pytest.raises(InvalidInputError):
        PiecewiseJerkProfile(np.array([[0.0, 1.0, 0.5]]), *(np.zeros((1, 2)),) * 4)


def test_sample_times():
    np.testing.assert_allclose(sample_times(0.3, 0.1), [0, 0.1, 0.2, 0.3])
    assert sample_times(0.3, 0.1)[-1] == 0.3
    np.testing.assert_allclose(sample_times(0.25, 0.1), [0, 0.1, 0.2, 0.25])
    np.testing.assert_array_equal(sample_times(0.0, 0.1), [0.0])
