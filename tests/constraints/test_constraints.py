"""Constraint math (tilt, box distance and their Jacobians vs finite differences), the
constraint certificate between samples, projection, and bad input."""

from __future__ import annotations

import numpy as np
import pytest

from manip import InvalidInputError, OrientationConstraint, PositionConstraint, UnknownNameError
from manip.constraints import certify_constraints, project, satisfied, segments_hold

EPS = 1e-6


def _fd(c, kin, q):
    """(m, dof) central differences of c.residual at q."""
    with np.errstate(invalid="ignore"):  # inf - inf on the unbounded rows
        cols = [(c.residual(kin, (q + EPS * e)[None])[0] - c.residual(kin, (q - EPS * e)[None])[0]) / (2 * EPS)
                for e in np.eye(kin.dof)]
    return np.array(cols).T


@pytest.fixture(scope="module")
def configs(franka_kinematics):
    rng = np.random.default_rng(3)
    return rng.uniform(franka_kinematics.lower, franka_kinematics.upper, (12, franka_kinematics.dof))


def test_tilt_is_the_angle_between_the_link_axis_and_the_direction(franka_kinematics, configs):
    kin = franka_kinematics
    c = OrientationConstraint(axis=(1, 0, 0), direction=(0, 0.6, 0.8), tolerance=0.2, link="panda_link7")
    R = np.array([kin.fk(q, "panda_link7").rotation for q in configs])
    expected = np.arccos(np.clip((R @ [1, 0, 0]) @ [0, 0.6, 0.8], -1, 1))
    np.testing.assert_allclose(c.tilt(kin, configs), expected, atol=1e-9)
    np.testing.assert_allclose(c.residual(kin, configs)[:, 0], expected - 0.2, atol=1e-9)


@pytest.mark.parametrize("link", [None, "panda_link5", "panda_hand_tcp"])
def test_tilt_gradient_matches_finite_differences(franka_kinematics, configs, link):
    kin = franka_kinematics
    c = OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=0.1, link=link)
    J = c.jacobian(kin, configs)
    for q, Jq in zip(configs, J):
        np.testing.assert_allclose(Jq, _fd(c, kin, q), atol=1e-6)


@pytest.mark.parametrize("direction,tolerance", [((0, 0, 1), 0.1), ((0, 0.6, 0.8), 0.4)])
def test_optimizer_rows_lie_inside_the_cone_and_their_gradient_matches(franka_kinematics, configs, direction,
                                                                       tolerance):
    kin = franka_kinematics
    c = OrientationConstraint(axis=(0, 1, 0), direction=direction, tolerance=tolerance, link="panda_hand")
    r, J = c.optimizer_rows(kin, configs)
    fd = np.stack([(c.optimizer_rows(kin, configs + EPS * e)[0] - c.optimizer_rows(kin, configs - EPS * e)[0])
                   / (2 * EPS) for e in np.eye(kin.dof)], axis=-1)
    np.testing.assert_allclose(J, fd, atol=1e-6)
    # an inner approximation: wherever every row holds, the tilt is within the tolerance (the
    # polygon's corners touch the cone), and most of the cone is covered
    Q = np.random.default_rng(5).uniform(kin.lower, kin.upper, (40000, kin.dof))
    inside = np.all(c.optimizer_rows(kin, Q)[0] <= 0.0, axis=1)
    tilt = c.tilt(kin, Q)
    assert inside.sum() > 50 and tilt[inside].max() <= tolerance + 1e-12
    assert inside.sum() >= 0.95 * np.sum(tilt <= tolerance)


def test_optimizer_rows_of_a_wide_cone_are_the_angle(franka_kinematics, configs):
    kin = franka_kinematics
    c = OrientationConstraint(axis=(0, 1, 0), direction=(0, 0, 1), tolerance=1.2, link="panda_hand")
    r, J = c.optimizer_rows(kin, configs)
    np.testing.assert_allclose(r, c.residual(kin, configs), atol=1e-12)


def test_box_distance_and_its_gradient(franka_kinematics, configs):
    kin = franka_kinematics
    lo, hi = np.array([0.2, -0.4, 0.1]), np.array([0.7, 0.4, np.inf])
    c = PositionConstraint(lower=lo, upper=hi, link="panda_hand_tcp")
    p = np.array([kin.fk(q, "panda_hand_tcp").position for q in configs])
    v = c.violation(kin, configs)
    inside = np.all((p >= lo) & (p <= hi), axis=1)
    np.testing.assert_array_equal(v <= 0, inside)
    # the violation is the L-inf signed distance to the box
    np.testing.assert_allclose(v, np.max(np.concatenate([p - hi, lo - p], axis=1), axis=1), atol=1e-12)
    J = c.jacobian(kin, configs)
    for q, Jq in zip(configs, J):
        fd = _fd(c, kin, q)
        finite = np.isfinite(c.residual(kin, q[None])[0])
        np.testing.assert_allclose(Jq[finite], fd[finite], atol=1e-6)


@pytest.mark.parametrize("make", [
    lambda: OrientationConstraint((0, 0, 1), (0, 0, 1), 0.3, link="panda_hand"),
    lambda: OrientationConstraint((1, 0, 0), (0, 0, 1), 0.3, link="panda_hand"),
    lambda: OrientationConstraint((0, 0.6, 0.8), (0.6, 0, 0.8), 0.3, link="panda_hand_tcp"),
    lambda: OrientationConstraint((0, 0, -1), (0, 0, 1), 0.3, link="panda_link5"),
    lambda: PositionConstraint((-0.5, -0.5, 0.0), (0.8, 0.5, 1.0), link="panda_hand_tcp"),
])
def test_segment_bound_holds_on_random_segments(franka_kinematics, make):
    """|r(t) - r(s)| <= L |t - s| on densely sampled random segments."""
    kin, c = franka_kinematics, make()
    rng = np.random.default_rng(5)
    for _ in range(20):
        q0 = rng.uniform(kin.lower, kin.upper)
        q1 = np.clip(q0 + rng.normal(0, 0.4, kin.dof), kin.lower, kin.upper)
        t = np.linspace(0, 1, 401)
        r = c.residual(kin, q0 + t[:, None] * (q1 - q0))
        L = c.segment_bound(kin, q0[None], q1[None])[0]
        rate = np.max(np.abs(np.diff(r, axis=0)), axis=1) / (t[1] - t[0])
        assert np.all(rate <= L * (1 + 1e-9)), (rate.max(), L)


def test_tilt_bound_skips_turns_that_cannot_tilt(franka_kinematics):
    """An upright constraint: the vertical first joint's turn and, for the axis along the last
    joint, the last joint's turn leave the tilt unchanged, and the bound says so (0)."""
    kin = franka_kinematics
    rng = np.random.default_rng(2)
    top = OrientationConstraint((0, 0, 1), (0, 0, 1), 0.3, link="panda_hand")
    side = OrientationConstraint((1, 0, 0), (0, 0, 1), 0.3, link="panda_hand")
    for _ in range(5):
        q0 = rng.uniform(kin.lower, kin.upper)
        for joint, constraint in ((0, top), (0, side), (6, top)):
            q1 = q0.copy()
            q1[joint] = np.clip(q0[joint] + 1.0, kin.lower[joint], kin.upper[joint])
            tilt = constraint.tilt(kin, q0 + np.linspace(0, 1, 50)[:, None] * (q1 - q0))
            assert np.ptp(tilt) < 1e-9
            assert constraint.segment_bound(kin, q0[None], q1[None])[0] == 0.0
        q1 = q0.copy()
        q1[6] = np.clip(q0[6] + 1.0, kin.lower[6], kin.upper[6])
        assert side.segment_bound(kin, q0[None], q1[None])[0] == pytest.approx(abs(q1[6] - q0[6]))


def test_certificate_refuses_a_violation_between_samples(franka_kinematics):
    """Both ends within 0.4 rad of the direction; joint 7 sweeps the hand's x axis through
    the opposite side in between: two samples, the certificate must refuse."""
    kin = franka_kinematics
    q0 = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, -2.8])
    q1 = q0.copy()
    q1[6] = 2.8
    qpi = q0.copy()
    qpi[6] = np.pi  # outside the limits: only to read the direction
    direction = kin.fk(qpi, "panda_hand").rotation[:, 0]
    c = OrientationConstraint(axis=(1, 0, 0), direction=direction, tolerance=0.4, link="panda_hand")
    assert satisfied([c], kin, np.stack([q0, q1])).all()
    cert = certify_constraints([c], kin, np.stack([q0, q1]))
    assert not cert.certified and cert.first_failed_segment == 0 and cert.reason == "constraint"
    assert "tilt" in cert.pair[0] and "tolerance 0.4" in cert.pair[0]
    # sampled densely, the samples themselves show the violation the certificate found
    dense = q0 + np.linspace(0, 1, 101)[:, None] * (q1 - q0)
    assert not satisfied([c], kin, dense).all()


def test_certificate_refuses_a_position_leaving_the_box_between_samples(franka_kinematics):
    """Joint 1 from -2.5 to 2.5 rad: the hand starts and ends behind the robot (x < -0.2 m)
    and passes in front of it in between."""
    kin = franka_kinematics
    q0 = np.array([-2.5, -0.3, 0.0, -2.0, 0.0, 1.8, 0.785])
    q1 = q0.copy()
    q1[0] = 2.5
    c = PositionConstraint((-2, -2, -2), (-0.2, 2, 2), link="panda_hand")
    assert satisfied([c], kin, np.stack([q0, q1])).all()
    cert = certify_constraints([c], kin, np.stack([q0, q1]))
    assert not cert.certified and cert.reason == "constraint" and "outside the box" in cert.pair[0]
    ok, bad, _ = segments_hold([c], kin, q0[None], q1[None])
    assert not ok[0] and bad[0]


def test_certificate_accepts_a_dense_path_that_keeps_the_constraint(franka_kinematics):
    kin = franka_kinematics
    c = OrientationConstraint((0, 0, 1), (0, 0, -1), 0.1)
    q0 = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
    q1 = q0.copy()
    q1[0] = 1.5  # joint 1 turns the hand about the vertical: the tilt does not change
    path = q0 + np.linspace(0, 1, 5)[:, None] * (q1 - q0)
    assert certify_constraints([c], kin, path).certified


def test_projection_lands_inside_with_margin(franka_kinematics, configs):
    kin = franka_kinematics
    c = OrientationConstraint((0, 0, 1), (0, 0, -1), 0.1)
    start = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
    rng = np.random.default_rng(0)
    for _ in range(10):
        q = project([c], kin, np.clip(start + rng.normal(0, 0.3, 7), kin.lower, kin.upper))
        assert q is not None
        assert c.violation(kin, q[None])[0] <= -0.5 * c.margin + 1e-9
        assert kin.within_limits(q)


@pytest.mark.parametrize("kwargs, words", [
    ({"axis": (0, 0, 0)}, "axis"),
    ({"axis": (0, 0, 2)}, "axis"),
    ({"direction": (np.nan, 0, 1)}, "direction"),
    ({"direction": (0, 1)}, "direction"),
    ({"tolerance": -0.1}, "tolerance"),
    ({"tolerance": 0.0}, "tolerance"),
    ({"tolerance": 4.0}, "tolerance"),
    ({"tolerance": True}, "tolerance"),
    ({"link": ""}, "link"),
])
def test_orientation_bad_input(kwargs, words):
    with pytest.raises(InvalidInputError, match=words):
        OrientationConstraint(**kwargs)


@pytest.mark.parametrize("kwargs, words", [
    ({"lower": (0, 0, 0), "upper": (1, 1, 0)}, "upper must be > lower"),
    ({"lower": (0, 0), "upper": (1, 1, 1)}, "lower"),
    ({"lower": (0, 0, np.nan), "upper": (1, 1, 1)}, "lower"),
    ({"lower": (0, 0, 0), "upper": "abc"}, "upper"),
])
def test_position_bad_input(kwargs, words):
    with pytest.raises(InvalidInputError, match=words):
        PositionConstraint(**kwargs)


def test_unknown_link_is_named(franka_kinematics):
    with pytest.raises(UnknownNameError, match="OrientationConstraint link.*panda_hnd"):
        OrientationConstraint(link="panda_hnd").check(franka_kinematics)


def test_the_certificate_of_a_timed_motion_allows_for_its_deviation_from_the_chords(franka_kinematics):
    """Joint 1 turns a hand that points down: its tilt from a direction 0.0999 rad off the
    vertical stays 0.0999 along the segment. Certified for the straight segment (tolerance
    0.1), refused for a motion that may stray 1 mrad per joint from it (the bound of that
    displacement, 7 mrad, is more than the 0.1 mrad left)."""
    from manip.constraints import trajectory_deviation

    kin = franka_kinematics
    q0 = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
    u = kin.fk(q0, "panda_hand").rotation[:, 2]
    a = 0.0999
    e = np.array([1.0, 0.0, 0.0]) - u[0] * u
    c = OrientationConstraint((0, 0, 1), np.cos(a) * u + np.sin(a) * e / np.linalg.norm(e), 0.1)
    q1 = q0.copy()
    q1[0] += 1.0
    path = q0 + np.linspace(0, 1, 6)[:, None] * (q1 - q0)
    np.testing.assert_allclose(c.tilt(kin, path), a, atol=1e-6)
    assert certify_constraints([c], kin, path).certified
    refused = certify_constraints([c], kin, path, deviation=np.full((5, 7), 1e-3))
    assert not refused.certified and refused.first_failed_segment == 0
    # an allowance beyond half the constraint's margin (0.015 rad) is not applied (the polyline only)
    assert certify_constraints([c], kin, path, deviation=np.full((5, 7), 3e-3)).certified
    # the deviation of a sampled motion: |a| dt^2 / 8 with |a| bounded by the samples and the jerk
    dev = trajectory_deviation(np.array([[1.0, -2.0], [3.0, 0.5]]), 0.1, np.array([10.0, 10.0]))
    np.testing.assert_allclose(dev, [[(3.0 + 0.5) * 0.01 / 8, (2.0 + 0.5) * 0.01 / 8]])
