"""Tests of manip.trajectory: the Trajectory type and its exact piecewise-jerk profile."""

from __future__ import annotations

import numpy as np
import pytest

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, UnknownNameError
from manip.timing import time_parameterize_for_robot
from manip.trajectory import CubicSplinePath, PathProfile, PiecewiseJerkProfile, Trajectory, sample_times


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


# ---------------------------------------------------------------------------- spline paths
def curved_points(k=12, dof=3, seed=0):
    """k points of a smooth curve with unevenly spaced samples."""
    rng = np.random.default_rng(seed)
    u = np.sort(np.concatenate([[0.0, 1.0], rng.uniform(0.0, 1.0, k - 2)]))
    c = rng.normal(size=(3, dof))
    return c[0] * u[:, None] + 0.3 * c[1] * np.sin(3 * u[:, None]) + 0.2 * c[2] * np.cos(5 * u[:, None])


def test_spline_passes_through_the_points_and_is_c2():
    pts = curved_points()
    sp = CubicSplinePath.fit(pts)
    assert sp.dof == 3 and sp.coeffs.shape == (4, len(pts) - 1, 3)
    np.testing.assert_allclose(sp.breaks[1:], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    q = sp.evaluate(sp.breaks)[0]
    np.testing.assert_allclose(q, pts, atol=1e-12)
    np.testing.assert_array_equal(q[[0, -1]], pts[[0, -1]])
    # left and right limits agree at the interior breaks for q, q', q''; q''' jumps except
    # at the second and second-to-last points (not-a-knot)
    eps = 1e-9
    left = sp.evaluate(sp.breaks[1:-1] - eps)
    right = sp.evaluate(sp.breaks[1:-1] + eps)
    for k, tol in ((0, 1e-7), (1, 1e-6), (2, 1e-5)):
        np.testing.assert_allclose(left[k], right[k], atol=tol)
    np.testing.assert_allclose(left[3][[0, -1]], right[3][[0, -1]], rtol=1e-9)
    assert np.abs(left[3][1:-1] - right[3][1:-1]).max() > 1e-3
    # clamped outside [0, L]
    np.testing.assert_array_equal(sp.evaluate([-1.0, sp.length + 1.0])[0], pts[[0, -1]])


def test_spline_special_cases_and_bounds():
    two = np.array([[0.0, 0.0], [3.0, 4.0]])
    line = CubicSplinePath.fit(two)
    q, d1, d2, d3 = line.evaluate(np.array([2.5]))
    np.testing.assert_allclose(q, [[1.5, 2.0]])
    np.testing.assert_allclose(d1, [[0.6, 0.8]])
    np.testing.assert_array_equal(d2, 0.0)
    three = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]])
    par = CubicSplinePath.fit(three)
    np.testing.assert_allclose(par.evaluate(par.breaks)[0], three, atol=1e-12)
    np.testing.assert_allclose(par.coeffs[3], 0.0, atol=1e-12)  # a parabola
    # per-piece bounds hold on dense samples and are attained
    sp = CubicSplinePath.fit(curved_points(seed=1))
    m1, m2, m3 = sp.piece_bounds()
    s = np.linspace(0.0, sp.length, 20001)
    q, d1, d2, d3 = sp.evaluate(s)
    for m, d in ((m1, d1), (m2, d2), (m3, d3)):
        assert np.all(m.max(axis=0) >= np.abs(d).max(axis=0) - 1e-12)
        np.testing.assert_allclose(m.max(axis=0), np.abs(d).max(axis=0), rtol=1e-3)
    lo, hi = sp.position_range()
    assert np.all(lo <= q.min(axis=0)) and np.all(hi >= q.max(axis=0))
    np.testing.assert_allclose(lo, q.min(axis=0), atol=1e-8)
    np.testing.assert_allclose(hi, q.max(axis=0), atol=1e-8)
    with pytest.raises(InvalidInputError, match="distinct"):
        CubicSplinePath.fit(np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0]]))
    with pytest.raises(InvalidInputError, match="K >= 2"):
        CubicSplinePath.fit(np.array([[0.0, 0.0]]))


@pytest.fixture(scope="module")
def path_traj(cfg):
    from manip.timing import time_parameterize_dense

    a = np.array(cfg.default_joint_positions)
    u = np.linspace(0.0, 1.0, 20)[:, None]
    pts = a + u * [0.6, -0.3, 0.2, 0.5, 0.1, 0.2, -0.4] + 0.1 * np.sin(np.pi * u) * [1, 1, 0, -1, 0, 1, 0]
    r = time_parameterize_dense(pts, cfg.velocity_limits, cfg.acceleration_limits, cfg.jerk_limits,
                                joint_names=cfg.arm_joints)
    assert r.success
    return r.trajectory


def test_path_profile_is_exact_and_consistent(path_traj):
    traj = path_traj
    assert isinstance(traj.profile, PathProfile) and traj.profile.dof == 7
    q, qd, qdd = traj.at_time(traj.times)
    np.testing.assert_array_equal(q, traj.positions)
    np.testing.assert_array_equal(qd, traj.velocities)
    np.testing.assert_array_equal(qdd, traj.accelerations)
    # the chain rule: finite differences of the exact motion match its derivatives
    h = 1e-6
    t = np.linspace(0.01, traj.duration - 0.01, 301)
    q0, v0, a0, j0 = traj.profile.evaluate(t)
    q1, v1, a1, _ = traj.profile.evaluate(t + h)
    qm, vm, am, _ = traj.profile.evaluate(t - h)
    np.testing.assert_allclose((q1 - qm) / (2 * h), v0, atol=1e-6)
    np.testing.assert_allclose((v1 - vm) / (2 * h), a0, atol=1e-3)
    smooth = np.all(np.abs(j0) < 1e9, axis=1)  # away from jerk switches, central differences
    np.testing.assert_allclose(((a1 - am) / (2 * h))[smooth], j0[smooth], atol=0.5)
    # resampling evaluates the same motion
    r = traj.resample(1e-3)
    assert r.duration == traj.duration and r.profile is traj.profile
    np.testing.assert_array_equal(r.positions[-1], traj.positions[-1])
    # extrema: dense maxima, attained and not exceeded by a finer evaluation
    e = traj.profile.extrema()
    tt = np.linspace(0.0, traj.duration, 40001)
    _, qd, qdd, qddd = traj.profile.evaluate(tt)
    # sampled every h: velocity within J h^2 / 8 and acceleration within J h / 2 of the maximum
    h, jerk = 2.5e-4, np.abs(qddd).max(axis=0)
    vmax, amax = np.abs(qd).max(axis=0), np.abs(qdd).max(axis=0)
    # (the finer grid here is also sampled: both are within these bounds of the true maxima)
    assert np.all(np.abs(e["max_abs_velocity"] - vmax) <= jerk * h**2 / 8)
    assert np.all(np.abs(e["max_abs_acceleration"] - amax) <= jerk * h / 2)
    np.testing.assert_allclose(e["max_abs_jerk"], jerk, rtol=1e-2)
    np.testing.assert_array_equal(traj.max_abs_velocity(), e["max_abs_velocity"])


def test_path_profile_time_scaled_and_validation(path_traj):
    p = path_traj.profile
    s = p.time_scaled(2.0)
    assert s.duration == pytest.approx(2 * p.duration)
    t = np.linspace(0, p.duration, 101)
    q, qd, qdd, j = p.evaluate(t)
    q2, qd2, qdd2, j2 = s.evaluate(2 * t)
    np.testing.assert_allclose(q2, q, atol=1e-12)
    np.testing.assert_allclose(qd2, qd / 2, atol=1e-12)
    np.testing.assert_allclose(qdd2, qdd / 4, atol=1e-10)
    np.testing.assert_allclose(j2, j / 8, atol=1e-8)
    with pytest.raises(InvalidInputError, match="one degree of freedom"):
        PathProfile(p.path, PiecewiseJerkProfile(np.zeros((2, 2)), *(np.zeros((2, 1)),) * 4))
    with pytest.raises(InvalidInputError, match="PathProfile with 3 joints"):
        Trajectory(path_traj.times, path_traj.positions[:, :3], path_traj.velocities[:, :3],
                   path_traj.accelerations[:, :3], path_traj.jerks[:, :3], path_traj.dt, ["a", "b", "c"], p)
