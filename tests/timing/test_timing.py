"""Tests of manip.timing: ruckig time-parameterisation of joint paths (Panda limits)."""

from __future__ import annotations

import numpy as np
import pytest
import ruckig

from manip.errors import InvalidInputError
from manip.timing import (
    TimingStatus,
    time_parameterize,
    time_parameterize_dense,
    time_parameterize_for_robot,
)
from manip.timing.segments import DEVIATION_STEP, SegmentSolver, segment_deviation
from manip.timing.shared import polyline_distances
from manip.trajectory import PathProfile, evaluate_pieces


def limits(cfg):
    return (
        np.asarray(cfg.velocity_limits),
        np.asarray(cfg.acceleration_limits),
        np.asarray(cfg.jerk_limits),
        np.asarray(cfg.lower_limits),
        np.asarray(cfg.upper_limits),
    )


def random_path(rng, cfg, k):
    """A random walk of k waypoints inside the position limits, steps of 0.3-1.2 rad."""
    lo, hi = np.asarray(cfg.lower_limits), np.asarray(cfg.upper_limits)
    q = [rng.uniform(lo, hi)]
    for _ in range(k - 1):
        step = rng.normal(size=7)
        step *= rng.uniform(0.3, 1.2) / np.linalg.norm(step)
        q.append(np.clip(q[-1] + step, lo, hi))
    return np.array(q)


def smooth_path(rng, cfg, k, length=3.0):
    """A smooth curve sampled at k points (like a trajectory optimiser's output)."""
    lo, hi = np.asarray(cfg.lower_limits), np.asarray(cfg.upper_limits)
    c = rng.uniform(lo * 0.5, hi * 0.5)
    a = rng.normal(size=(3, 7))
    s = np.linspace(0, 1, k)[:, None]
    q = c + a[0] * s + 0.3 * a[1] * np.sin(np.pi * s) + 0.2 * a[2] * np.sin(2 * np.pi * s)
    q = c + (q - c) * length / np.linalg.norm(np.diff(q, axis=0), axis=1).sum()
    return np.clip(q, lo, hi)


def polyline_distance(q, path):
    """Independent L-inf distance of each row of q (N, dof) to the polyline `path`:
    the exact L-inf distance to a segment is min over lambda in [0, 1] of a convex
    function; found here by dense search over lambda (upper bound, 501 values)."""
    lam = np.linspace(0.0, 1.0, 501)
    best = np.full(len(q), np.inf)
    for a, b in zip(path[:-1], path[1:]):
        pts = a[None, :] + lam[:, None] * (b - a)[None, :]  # (L, dof)
        for i0 in range(0, len(q), 200):
            chunk = q[i0 : i0 + 200]
            dist = np.abs(chunk[:, None, :] - pts[None, :, :]).max(axis=2).min(axis=1)
            best[i0 : i0 + 200] = np.minimum(best[i0 : i0 + 200], dist)
    return best


def grid_error(path):
    """Largest overestimate of `polyline_distance` (its lambda grid step / 2 on the longest segment)."""
    return float(np.linalg.norm(np.diff(path, axis=0), axis=1).max()) / 1000.0


def check_valid(result, path, cfg, vscale=1.0, ascale=1.0, jscale=1.0):
    """Every guarantee of a successful result, checked independently of the library."""
    vmax, amax, jmax, lo, hi = limits(cfg)
    assert result.success and result.status is TimingStatus.SUCCESS
    traj = result.trajectory
    # endpoints exact and at rest
    np.testing.assert_array_equal(traj.positions[0], path[0])
    np.testing.assert_array_equal(traj.positions[-1], path[-1])
    for arr in (traj.velocities, traj.accelerations):
        np.testing.assert_array_equal(arr[[0, -1]], 0.0)
    # uniform sampling, duration a multiple of dt
    assert traj.times[0] == 0.0
    np.testing.assert_allclose(np.diff(traj.times), traj.dt, rtol=1e-9)
    assert traj.duration == pytest.approx(round(traj.duration / traj.dt) * traj.dt, rel=1e-12)
    # limits on the samples and on a dense evaluation of the exact motion
    dense_t = np.linspace(0.0, traj.duration, max(2, int(traj.duration / 5e-4)))
    q, qd, qdd = traj.at_time(dense_t)
    for arr, lim in ((traj.velocities, vmax * vscale), (qd, vmax * vscale)):
        assert np.all(np.abs(arr) <= lim)
    for arr, lim in ((traj.accelerations, amax * ascale), (qdd, amax * ascale)):
        assert np.all(np.abs(arr) <= lim)
    assert np.all(np.abs(traj.jerks) <= jmax * jscale)
    # jerk consistent with the accelerations: mean jerk over each step within limits
    assert np.all(np.abs(np.diff(qdd, axis=0)) / np.diff(dense_t)[:, None] <= jmax * jscale * (1 + 1e-9))
    assert np.all(q >= lo - 1e-6) and np.all(q <= hi + 1e-6)
    assert np.all(traj.positions >= lo - 1e-6) and np.all(traj.positions <= hi + 1e-6)
    # analytic extrema agree
    assert np.all(traj.max_abs_velocity() <= vmax * vscale)
    assert np.all(traj.max_abs_acceleration() <= amax * ascale)
    assert np.all(traj.max_abs_jerk() <= jmax * jscale)
    pmin, pmax = traj.position_range()
    assert np.all(pmin >= lo - 1e-6) and np.all(pmax <= hi + 1e-6)
    return traj, dense_t, q


@pytest.mark.parametrize("mode", ["exact", "blend"])
def test_random_paths_within_all_limits(cfg, mode):
    rng = np.random.default_rng(1)
    for k in (2, 3, 5, 8):
        for _ in range(4):
            path = random_path(rng, cfg, k)
            r = time_parameterize_for_robot(path, cfg, mode=mode)
            traj, _, q = check_valid(r, path, cfg)
            assert traj.joint_names == tuple(cfg.arm_joints)
            # the motion passes through every waypoint it keeps
            assert r.max_deviation <= (1e-9 if mode == "exact" else 0.05)


def test_exact_mode_stays_on_the_straight_segments(cfg):
    rng = np.random.default_rng(2)
    for _ in range(3):
        path = random_path(rng, cfg, 5)
        r = time_parameterize_for_robot(path, cfg, mode="exact")
        traj, t, q = check_valid(r, path, cfg)
        # deviation measured independently: on the polyline up to the lambda search step
        step = np.abs(np.diff(path, axis=0)).max() / 500
        assert polyline_distance(q[::20], path).max() <= step
        assert r.max_deviation < 1e-9
        # stops (v = 0) at every waypoint: each waypoint is reached at rest
        for w in path[1:-1]:
            i = np.argmin(np.abs(q - w).max(axis=1))
            assert np.abs(q[i] - w).max() < 1e-3
            assert np.abs(traj.at_time(t[i])[1]).max() < 0.5  # near the stop



def test_a_path_of_the_wrong_width_names_the_path(cfg):
    # a path of full robot states (7 arm joints + 2 fingers) blamed the robot's limits:
    # "velocity_limits must have shape (9,) (one per joint); got (7,)"
    a = np.r_[cfg.default_joint_positions, 0.04, 0.04]
    with pytest.raises(InvalidInputError, match=r"path must have shape \(K, 7\): the arm joints \['panda_joint1'.*"
                                                r"got 9 columns \(a full robot state, the gripper's last\? pass path\[:, :7\]\)"):
        time_parameterize_for_robot([a, a + 0.1], cfg)
    with pytest.raises(InvalidInputError, match=r"path must have shape \(K, 7\).*got 6 columns$"):
        time_parameterize_for_robot(np.zeros((2, 6)), cfg)
    assert time_parameterize_for_robot([a[:7], a[:7] + 0.1], cfg).success

def test_exact_segments_are_time_optimal_lines(cfg):
    """A rest-to-rest straight move takes as long as its slowest joint alone needs (ruckig)."""
    vmax, amax, jmax, lo, hi = limits(cfg)
    a = np.array(cfg.default_joint_positions)
    b = a + np.array([0.8, -0.3, 0.5, -0.6, 0.2, 0.9, -1.0])
    r = time_parameterize_for_robot([a, b], cfg, mode="exact", dt=1e-3)
    # ruckig on the single slowest joint's 1-D problem is a lower bound; the line can't beat it
    otg, inp, out = ruckig.Ruckig(1), ruckig.InputParameter(1), ruckig.Trajectory(1)
    lower_bound = 0.0
    for d in range(7):
        inp.current_position, inp.target_position = [a[d]], [b[d]]
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = [vmax[d]], [amax[d]], [jmax[d]]
        otg.calculate(inp, out)
        lower_bound = max(lower_bound, out.duration)
    assert r.minimum_duration >= lower_bound - 1e-9
    assert r.minimum_duration <= 1.5 * lower_bound
    check_valid(r, np.array([a, b]), cfg)


def test_blend_within_deviation_tolerance_and_faster(cfg):
    rng = np.random.default_rng(3)
    for tol in (0.02, 0.1):
        for _ in range(3):
            path = random_path(rng, cfg, 6)
            rb = time_parameterize_for_robot(path, cfg, mode="blend", deviation_tolerance=tol)
            re = time_parameterize_for_robot(path, cfg, mode="exact")
            _, _, q = check_valid(rb, path, cfg)
            assert polyline_distance(q[::20], path).max() <= tol
            assert rb.max_deviation <= tol
            assert rb.minimum_duration <= re.minimum_duration


def test_blend_much_faster_on_dense_smooth_path(cfg):
    rng = np.random.default_rng(4)
    for _ in range(3):
        path = smooth_path(rng, cfg, 30)
        rb = time_parameterize_for_robot(path, cfg)
        re = time_parameterize_for_robot(path, cfg, mode="exact")
        _, _, q = check_valid(rb, path, cfg)
        assert rb.trajectory.duration < 0.5 * re.trajectory.duration
        assert rb.max_deviation <= 0.05
        assert polyline_distance(q[::20], path).max() <= 0.05
        assert len(rb.waypoints) < len(path)  # dense waypoints were thinned within tolerance


def test_gentle_corner_is_blended(cfg):
    a = np.array(cfg.default_joint_positions)
    path = np.array([a, a + [0.6, 0.3, 0, 0, 0, 0, 0], a + [1.2, 0.4, 0, 0, 0, 0, 0]])
    rb = time_parameterize_for_robot(path, cfg)
    re = time_parameterize_for_robot(path, cfg, mode="exact")
    check_valid(rb, path, cfg)
    assert np.linalg.norm(rb.waypoint_velocities[1]) > 0.5
    assert rb.trajectory.duration < 0.85 * re.trajectory.duration


def test_blend_never_overshoots_a_position_limit(cfg):
    """Waypoints on joint 4's upper limit with a corner there: a bisector velocity would push
    past the limit; the result must stay within it."""
    hi = np.asarray(cfg.upper_limits)
    a = np.array(cfg.default_joint_positions)
    w0 = a.copy()
    w1 = a.copy()
    w1[3] = hi[3]
    w1[0] += 0.5
    w2 = w1.copy()
    w2[0] += 0.8
    path = np.array([w0, w1, w2])
    r = time_parameterize_for_robot(path, cfg, position_tolerance=0.0)
    check_valid(r, path, cfg)
    pmin, pmax = r.trajectory.position_range()
    assert pmax[3] <= hi[3] + 1e-12  # round-off only


def test_collinear_and_repeated_waypoints_are_merged(cfg):
    a = np.array(cfg.default_joint_positions)
    b = a + 0.6
    b[3] = a[3] - 0.6
    path = np.array([a, a, a + 0.25 * (b - a), a + 0.5 * (b - a), b, b])
    r = time_parameterize_for_robot(path, cfg, mode="exact")
    r2 = time_parameterize_for_robot([a, b], cfg, mode="exact")
    check_valid(r, path, cfg)
    assert len(r.waypoints) == 2
    assert r.minimum_duration == pytest.approx(r2.minimum_duration, rel=1e-12)


def test_single_waypoint_gives_a_still_trajectory(cfg):
    a = np.array(cfg.default_joint_positions)
    for path in ([a], [a, a, a]):
        r = time_parameterize_for_robot(path, cfg)
        assert r.success and r.trajectory.duration == 0.0 and r.trajectory.num_samples == 1
        np.testing.assert_array_equal(r.trajectory.positions[0], a)


def test_points_apart_by_rounding_only_give_a_still_trajectory_at_the_start(cfg):
    """A planning start 1e-18 to 1e-15 rad from its goal (a simulated arm parked at its wait
    pose) is a move ruckig times at 0 s: a still trajectory at the start, not a failed
    verification (before: LIMIT_VIOLATION "endpoints differ from the path's")."""
    a = np.array(cfg.default_joint_positions)
    for eps in (1e-18, 1e-15):
        b = a.copy()
        b[4] += eps
        for mode in ("blend", "exact"):
            r = time_parameterize_for_robot([b, a], cfg, mode=mode)
            assert r.success, r.message
            assert r.trajectory.num_samples == 1
            np.testing.assert_array_equal(r.trajectory.positions[0], b)


def test_speed_scales_and_duration(cfg):
    vmax, amax, jmax, lo, hi = limits(cfg)
    rng = np.random.default_rng(5)
    path = random_path(rng, cfg, 4)
    fast = time_parameterize_for_robot(path, cfg)
    slow = time_parameterize_for_robot(path, cfg, velocity_scale=0.3, acceleration_scale=0.5, jerk_scale=0.5)
    check_valid(slow, path, cfg, vscale=0.3, ascale=0.5, jscale=0.5)
    assert slow.trajectory.duration > fast.trajectory.duration
    # a chosen duration (rounded up to dt): same geometric path, just slower
    target = fast.minimum_duration * 2.0 + 0.01
    r = time_parameterize_for_robot(path, cfg, duration=target, dt=0.01)
    check_valid(r, path, cfg)
    assert r.trajectory.duration == pytest.approx(np.ceil(target / 0.01 - 1e-9) * 0.01, rel=1e-12)
    assert r.max_deviation == pytest.approx(fast.max_deviation, abs=1e-3)
    # too short: a result saying what is feasible
    short = time_parameterize_for_robot(path, cfg, duration=0.5 * fast.minimum_duration)
    assert not short.success and short.status is TimingStatus.DURATION_TOO_SHORT
    assert short.trajectory is None
    assert short.minimum_duration == pytest.approx(fast.minimum_duration)


def test_profile_matches_ruckig_at_time(cfg):
    """The extracted constant-jerk pieces reproduce ruckig's own evaluation."""
    vmax, amax, jmax, lo, hi = limits(cfg)
    from manip.trajectory import evaluate_pieces

    solver = SegmentSolver(cfg.limits)
    a = np.array(cfg.default_joint_positions)
    b = a + np.array([0.4, -0.2, 0.3, 0.1, -0.5, 0.2, 0.6])
    v0 = np.array([0.5, 0.1, 0.0, -0.2, 0.3, 0.0, 0.4])
    v1 = np.array([0.2, -0.3, 0.1, 0.0, -0.6, 0.5, 0.1])
    seg = solver.solve(a, v0, b, v1)
    ts = np.linspace(0, seg.duration, 57)
    q, qd, qdd, _ = evaluate_pieces(seg.knots, seg.p, seg.v, seg.a, seg.j, ts)
    for k, t in enumerate(ts):
        rp, rv, ra = solver.traj.at_time(float(t))
        np.testing.assert_allclose(q[k], rp, atol=1e-10)
        np.testing.assert_allclose(qd[k], rv, atol=1e-9)
        np.testing.assert_allclose(qdd[k], ra, atol=1e-7)


def test_limits_without_config(cfg):
    path = np.array([[0.0, 0.0], [1.0, 0.5], [1.5, -0.5]])
    r = time_parameterize(path, [1.0, 2.0], 5.0, 100.0, dt=0.01)
    assert r.success
    assert r.trajectory.joint_names == ("joint_0", "joint_1")
    assert np.all(r.trajectory.max_abs_velocity() <= [1.0, 2.0])
    assert np.all(r.trajectory.max_abs_acceleration() <= 5.0)


def test_bad_inputs_raise(cfg):
    a = np.array(cfg.default_joint_positions)
    good = np.array([a, a + 0.1])
    bad_nan = good.copy()
    bad_nan[1, 2] = np.nan
    with pytest.raises(InvalidInputError, match="non-finite"):
        time_parameterize_for_robot(bad_nan, cfg)
    with pytest.raises(InvalidInputError, match="shape"):
        time_parameterize_for_robot(good[:, :6], cfg)
    with pytest.raises(InvalidInputError, match="shape"):
        time_parameterize_for_robot(a, cfg)
    outside = good.copy()
    outside[1, 3] = 0.5  # joint 4 upper limit is -0.0698
    with pytest.raises(InvalidInputError, match="outside the position limits"):
        time_parameterize_for_robot(outside, cfg)
    # a hair outside is accepted
    hair = good.copy()
    hair[0, 3] = cfg.upper_limits[3] + 5e-7
    assert time_parameterize_for_robot(hair, cfg).success
    with pytest.raises(InvalidInputError, match="mode"):
        time_parameterize_for_robot(good, cfg, mode="fast")
    for kw in ({"velocity_scale": 0.0}, {"acceleration_scale": 1.5}, {"jerk_scale": np.nan}):
        with pytest.raises(InvalidInputError, match="scale"):
            time_parameterize_for_robot(good, cfg, **kw)
    with pytest.raises(InvalidInputError, match="dt"):
        time_parameterize_for_robot(good, cfg, dt=0.0)
    with pytest.raises(InvalidInputError, match="velocity_limits"):
        time_parameterize(good, [1.0] * 6, 1.0, 1.0)
    with pytest.raises(InvalidInputError, match="jerk_limits"):
        time_parameterize(good, 1.0, 1.0, -1.0)
    with pytest.raises(InvalidInputError, match="both"):
        time_parameterize(good, 1.0, 1.0, 1.0, lower_limits=cfg.lower_limits)
    with pytest.raises(InvalidInputError, match="joint_names"):
        time_parameterize(good, 1.0, 1.0, 1.0, joint_names=["a"])


# ---------------------------------------------------------------------------- dense paths
DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # hand z axis pointing down


@pytest.fixture(scope="module")
def line_path():
    """30 IK solutions of the Franka's TCP on a 15 cm vertical line (a dense, curved joint path).

    Returns (path (30, 7), kinematics, line start (3,), line end (3,)).
    """
    from manip import MotionGenerator, Pose

    mg = MotionGenerator("franka")
    start = mg.ik(Pose([0.45, -0.3, 0.3], DOWN), seed_q=np.asarray(mg.default_joint_positions))
    assert start.success
    p0 = mg.fk(start.q, "panda_hand_tcp")
    pts = [start.q]
    for z in np.linspace(0.0, -0.15, 30)[1:]:
        r = mg.ik(Pose(p0.position + [0.0, 0.0, z], p0.quaternion), "panda_hand_tcp", seed_q=pts[-1])
        assert r.success
        pts.append(r.q)
    return np.array(pts), mg.kinematics, p0.position, p0.position + [0.0, 0.0, -0.15]


def dense(path, cfg, **options):
    vmax, amax, jmax, lo, hi = limits(cfg)
    return time_parameterize_dense(
        path, vmax, amax, jmax, joint_names=list(cfg.arm_joints), lower_limits=lo, upper_limits=hi, **options
    )


def keeps_moving(traj, fraction=0.3):
    """True iff the joint-space speed stays above `fraction` of its peak from 20 % to 80 % of the duration."""
    t = np.linspace(0.0, traj.duration, 2001)
    speed = np.linalg.norm(traj.at_time(t)[1], axis=1)
    middle = (t >= 0.2 * traj.duration) & (t <= 0.8 * traj.duration)
    return bool(speed[middle].min() > fraction * speed.max())


def test_dense_line_path_flows_without_stopping(cfg, line_path):
    path, kin, a, b = line_path
    r = dense(path, cfg)
    traj, dense_t, q = check_valid(r, path, cfg)
    assert r.mode == "along_path"
    assert isinstance(traj.profile, PathProfile)
    assert keeps_moving(traj)
    # the blend timing of the same path nearly stops at every point, and is much slower
    rb = time_parameterize_for_robot(path, cfg, deviation_tolerance=1e-3)
    assert rb.success and not keeps_moving(rb.trajectory)
    assert traj.duration < 0.5 * rb.trajectory.duration
    # the curve passes through the points and stays close to the polyline between them
    assert r.max_deviation <= 1e-3
    assert polyline_distance(q[::40], path).max() <= r.max_deviation + grid_error(path)
    # ... and keeps the TCP on the line (much closer than the polyline would)
    tcp = kin.fk(q[::5], "panda_hand_tcp").position
    u = (b - a) / np.linalg.norm(b - a)
    d = tcp - a
    assert np.linalg.norm(d - (d @ u)[:, None] * u, axis=1).max() < 1e-5  # [m]
    # waypoint bookkeeping
    assert len(r.waypoints) == len(path) and len(r.segment_durations) == len(path) - 1
    assert np.all(r.segment_durations > 0)
    assert r.segment_durations.sum() == pytest.approx(traj.duration, rel=1e-9)
    t_points = np.concatenate([[0.0], np.cumsum(r.segment_durations)])
    qp, qdp, _ = traj.at_time(t_points)
    np.testing.assert_allclose(qp, path, atol=1e-7)
    np.testing.assert_allclose(qdp, r.waypoint_velocities, atol=1e-5)
    np.testing.assert_array_equal(r.waypoint_velocities[[0, -1]], 0.0)


def test_dense_smooth_curves_within_limits_and_faster_than_blend(cfg):
    rng = np.random.default_rng(5)
    for _ in range(3):
        path = smooth_path(rng, cfg, 30, length=1.5)
        r = dense(path, cfg)
        traj, _, q = check_valid(r, path, cfg)
        assert keeps_moving(traj)
        rb = time_parameterize_for_robot(path, cfg, deviation_tolerance=1e-3)
        assert traj.duration < 0.6 * rb.trajectory.duration
        assert polyline_distance(q[::40], path).max() <= r.max_deviation + grid_error(path)


def test_dense_straight_line_is_the_time_optimal_line(cfg):
    a = np.array(cfg.default_joint_positions)
    path = np.array([a, a + [0.4, -0.3, 0.2, 0.5, 0.0, 0.1, -0.6]])
    r = dense(path, cfg)
    re = time_parameterize_for_robot(path, cfg, mode="exact")
    traj, _, q = check_valid(r, path, cfg)
    assert r.minimum_duration == pytest.approx(re.minimum_duration, rel=1e-9)
    assert traj.num_samples == re.trajectory.num_samples
    np.testing.assert_allclose(traj.positions, re.trajectory.positions, atol=1e-9)
    assert r.max_deviation < 1e-12
    u = (path[1] - path[0]) / np.linalg.norm(path[1] - path[0])
    d = q - path[0]
    assert np.linalg.norm(d - (d @ u)[:, None] * u, axis=1).max() < 1e-9


def test_dense_scales_and_duration(cfg, line_path):
    path = line_path[0]
    fast = dense(path, cfg)
    slow = dense(path, cfg, velocity_scale=0.5, acceleration_scale=0.5, jerk_scale=0.5)
    check_valid(slow, path, cfg, 0.5, 0.5, 0.5)
    assert slow.minimum_duration > fast.minimum_duration
    stretched = dense(path, cfg, duration=2.0)
    traj, _, _ = check_valid(stretched, path, cfg)
    assert traj.duration == pytest.approx(2.0, abs=traj.dt)
    assert traj.duration >= 2.0
    np.testing.assert_array_less(traj.max_abs_velocity(), 0.5 * fast.trajectory.max_abs_velocity())
    short = dense(path, cfg, duration=0.5 * fast.minimum_duration)
    assert not short.success and short.status is TimingStatus.DURATION_TOO_SHORT
    assert short.minimum_duration == pytest.approx(fast.minimum_duration)


def test_dense_fails_with_a_status_when_the_curve_cannot_be_used(cfg):
    vmax, amax, jmax, lo, hi = limits(cfg)
    a = np.array(cfg.default_joint_positions)
    # a zig-zag: the spline strays from the polyline between the points
    zig = np.array([a + [0.05 * i, 0.03 * (i % 2), 0, 0, 0, 0, 0] for i in range(10)])
    r = dense(zig, cfg, deviation_tolerance=1e-4)
    assert not r.success and r.status is TimingStatus.DEVIATION_TOO_LARGE and r.trajectory is None
    assert r.max_deviation > 1e-4
    assert dense(zig, cfg).success  # without a tolerance it is timed (slowly)
    # a path that reaches joint 0's upper limit at a point while still rising: the curve overshoots
    top = hi[0]
    j0 = np.array([top - 0.3, top - 0.15, top - 0.05, top, top - 0.2, top - 0.5])
    path = np.tile(a, (6, 1))
    path[:, 0] = j0
    path[:, 1] += np.linspace(0.0, 0.3, 6)
    r = dense(path, cfg)
    assert not r.success and r.status is TimingStatus.POSITION_LIMIT
    assert "panda_joint1" in r.message
    # without position limits it succeeds
    r = time_parameterize_dense(path, vmax, amax, jmax)
    assert r.success and r.trajectory.position_range()[1][0] > top


def test_dense_repeated_points(cfg):
    a = np.array(cfg.default_joint_positions)
    b = a + [0.2, 0.1, 0, 0, 0, 0, 0]
    c = b + [0.2, 0.0, 0.1, 0, 0, 0, 0]
    r = dense(np.array([a, a, b, b, b, c, c]), cfg)
    check_valid(r, np.array([a, c]), cfg)
    np.testing.assert_array_equal(r.waypoints, [a, b, c])
    still = dense(np.array([a, a, a]), cfg)
    assert still.success and still.mode == "along_path"
    assert still.trajectory.num_samples == 1
    np.testing.assert_array_equal(still.trajectory.positions[0], a)


def test_dense_bad_inputs_raise(cfg):
    vmax, amax, jmax, lo, hi = limits(cfg)
    a = np.array(cfg.default_joint_positions)
    path = np.array([a, a + 0.1])
    with pytest.raises(InvalidInputError, match="deviation_tolerance"):
        time_parameterize_dense(path, vmax, amax, jmax, deviation_tolerance=-1.0)
    with pytest.raises(InvalidInputError, match="shape"):
        time_parameterize_dense(a, vmax, amax, jmax)
    with pytest.raises(InvalidInputError, match="velocity_limits"):
        time_parameterize_dense(path, vmax[:3], amax, jmax)
    with pytest.raises(InvalidInputError, match="velocity_scale"):
        time_parameterize_dense(path, vmax, amax, jmax, velocity_scale=1.5)
    outside = path.copy()
    outside[1, 2] = hi[2] + 0.1
    with pytest.raises(InvalidInputError, match="outside the position limits"):
        time_parameterize_dense(outside, vmax, amax, jmax, lower_limits=lo, upper_limits=hi)


def test_along_path_mode_of_time_parameterize(cfg, line_path):
    path = line_path[0]
    r = time_parameterize_for_robot(path, cfg, mode="along_path", deviation_tolerance=1e-3)
    direct = dense(path, cfg, deviation_tolerance=1e-3)
    check_valid(r, path, cfg)
    assert r.mode == "along_path" and r.minimum_duration == direct.minimum_duration
    np.testing.assert_array_equal(r.trajectory.positions, direct.trajectory.positions)
    tight = time_parameterize_for_robot(path, cfg, mode="along_path", deviation_tolerance=1e-6)
    assert tight.status is TimingStatus.DEVIATION_TOO_LARGE


def test_segment_deviation_is_the_largest_sampled_distance_from_the_path(cfg):
    # the compiled deviation against the profile evaluated and measured with numpy, on
    # blended segments (ends in motion) of the Franka's limits
    solver = SegmentSolver(cfg.limits)
    rng = np.random.default_rng(3)
    for k in range(40):
        p0, p1 = rng.uniform(-1.0, 1.0, (2, 7))
        v0, v1 = rng.uniform(-0.5, 0.5, (2, 7))
        seg = solver.solve(p0, v0, p1, v1)
        sub_path = np.vstack([p0, rng.uniform(-1.0, 1.0, (k % 3, 7)), p1])
        ts = np.linspace(0.0, seg.duration, max(8, int(np.ceil(seg.duration / DEVIATION_STEP)) + 1))
        q = evaluate_pieces(seg.knots, seg.p, seg.v, seg.a, seg.j, ts)[0]
        expected = float(polyline_distances(q, sub_path).max())
        assert segment_deviation(seg, sub_path) == pytest.approx(expected, rel=1e-12, abs=1e-12)
        assert expected > 0.0


def test_dense_timing_of_a_motion_of_hours_checks_a_bounded_grid(cfg, line_path):
    """A straight-line path at 1e-5 of the velocity limits lasts hours: its verification grid is at
    most MAX_DENSE_TIMES times plus the timing's knots (every 0.25 ms it was 53 M times, 20 GB of
    arrays: a linear `plan_pose(..., velocity_scale=1e-5)` was killed for memory), and the
    returned samples still keep the scaled limits."""
    from manip.trajectory.spline import MAX_DENSE_TIMES

    path = line_path[0]
    r = dense(path, cfg, velocity_scale=1e-5, dt=1.0)
    assert r.success, r.message
    profile = r.trajectory.profile
    assert isinstance(profile, PathProfile) and profile.duration > 3600.0
    grid = profile.dense_times()
    assert grid.size <= MAX_DENSE_TIMES + 1 + profile.timing.knots[0].size
    vmax = np.asarray(cfg.velocity_limits) * 1e-5
    assert np.all(np.abs(r.trajectory.velocities) <= vmax)
    assert np.all(np.abs(profile.evaluate(grid)[1]) <= vmax)
    np.testing.assert_allclose(r.trajectory.positions[[0, -1]], path[[0, -1]], atol=1e-9)
