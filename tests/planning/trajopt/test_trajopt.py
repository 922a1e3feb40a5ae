"""The trajectory optimiser: B-spline limits, small problems, the planner's use of it."""

from __future__ import annotations

import time

import numpy as np
import pytest

from manip import MotionGenerator, WorldConfig
from manip.collision.clearance import ClearanceModel
from manip.errors import InvalidInputError
from manip.limits import JointLimits
from manip.planning.trajopt import bspline
from manip.planning.trajopt.optimizer import TrajOptSettings, optimize_trajectory
from manip.timing.bounds import rest_to_rest_time
from robot_constants import FRANKA_READY

READY = np.array(FRANKA_READY)
#: A wall between two configurations on either side of it.
WALL = {"cuboid": {"wall": {"dims": [0.3, 0.04, 0.5], "pose": [0.5, 0.0, 0.25, 1, 0, 0, 0]}}}
LEFT = np.array([0.6, 0.4, 0.0, -1.9, 0.0, 2.3, 0.785])
RIGHT = np.array([-0.6, 0.4, 0.0, -1.9, 0.0, 2.3, 0.785])


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka", WALL)


def dense_extrema(profile, step: float = 5e-4) -> tuple[np.ndarray, ...]:
    t = np.arange(0.0, profile.duration + step, step)
    _, v, a, j = profile.evaluate(np.minimum(t, profile.duration))
    return np.abs(v).max(axis=0), np.abs(a).max(axis=0), np.abs(j).max(axis=0)


def test_bspline_limits_hold_for_the_continuous_motion():
    rng = np.random.default_rng(0)
    c = np.cumsum(rng.normal(0, 0.2, (19, 3)), axis=0)
    c[:3], c[-3:] = c[0], c[-1]
    vmax, amax, jmax = np.array([2.0, 1.5, 1.0]), np.array([10.0, 8.0, 6.0]), np.array([500.0, 300.0, 200.0])
    h = bspline.limit_step(c, JointLimits(vmax, amax, jmax))
    prof = bspline.to_profile(c, h)
    v, a, j = dense_extrema(prof)
    assert np.all(v <= vmax * (1 + 1e-9)) and np.all(a <= amax * (1 + 1e-9)) and np.all(j <= jmax * (1 + 1e-9))
    # a limit is active: the same shape any faster would break it
    assert max(np.max(v / vmax), np.max(a / amax), np.max(j / jmax)) > 0.999
    q0, v0, a0, _ = prof.evaluate(np.array([0.0, prof.duration]))
    np.testing.assert_array_equal(q0[0], c[0])
    np.testing.assert_array_equal(q0[1], c[-1])
    assert np.all(v0 == 0) and np.all(np.abs(a0) < 1e-9)


@pytest.mark.parametrize("solver", ["piqp", "daqp"])
def test_optimiser_in_free_space_comes_close_to_the_time_optimal_line(mg, solver):
    """With PIQP's sparse interface (the default) and through qpsolvers (DAQP, a dense solver)."""
    free = MotionGenerator("franka")
    start, goal = READY, READY + np.array([0.8, 0.3, -0.5, 0.4, 0.6, -0.3, 0.9])
    detour = np.stack([start, (start + goal) / 2 + 0.4, goal])  # a seed with a corner
    seed = free.plan_joints(start, goal, trajopt=False)  # straight line: the time-optimal seed
    cfg = free.config
    timed = np.linspace(0, 1, 61)[:, None]
    positions = np.concatenate([detour[0] + timed[:31] * 2 * (detour[1] - detour[0]),
                                detour[1] + (timed[31:] - 0.5) * 2 * (detour[2] - detour[1])])
    times = np.linspace(0.0, 3.0, 61)
    bound = rest_to_rest_time(start, goal, cfg.limits)
    res = optimize_trajectory(positions, times, limits=cfg.limits, clearance=free.clearance, padding=0.0,
                              deadline=time.perf_counter() + 60.0, min_duration=bound,
                              settings=TrajOptSettings(solver=solver))
    assert res.success, res.message
    assert res.duration < 1.25 * bound < times[-1]
    v, a, j = dense_extrema(res.profile)
    assert np.all(v <= cfg.velocity_limits * (1 + 1e-9)) and np.all(a <= cfg.acceleration_limits * (1 + 1e-9))
    assert np.all(j <= cfg.jerk_limits * (1 + 1e-9))
    path = res.profile.evaluate(np.linspace(0, res.duration, 400))[0]
    length = np.linalg.norm(np.diff(path, axis=0), axis=1).sum()
    assert length < 1.05 * np.linalg.norm(goal - start)  # the corner was straightened
    assert seed.source == "straight_line"


def test_planner_uses_the_optimiser_around_a_wall_and_stays_valid(mg):
    base = mg.plan_joints(LEFT, RIGHT, trajopt=False, seed=3)
    opt = mg.plan_joints(LEFT, RIGHT, seed=3)
    assert base.success and opt.success and base.source == "shortcut"
    assert opt.source in ("trajopt", "shortcut")
    assert "trajopt" in opt.timings
    assert opt.motion_time <= base.motion_time
    if opt.source == "trajopt":
        assert opt.motion_time < base.motion_time
    traj = opt.trajectory
    assert mg.checker.path_valid(traj.positions, resolution=0.005).valid
    assert np.all(np.abs(traj.velocities) <= mg.velocity_limits * (1 + 1e-9))
    assert np.all(np.abs(traj.accelerations) <= mg.acceleration_limits * (1 + 1e-9))
    assert np.all(np.abs(traj.jerks) <= mg.jerk_limits * (1 + 1e-9))
    np.testing.assert_array_equal(traj.positions[0], LEFT)
    np.testing.assert_allclose(traj.positions[-1], RIGHT, atol=1e-12)


def test_same_seed_same_trajectory(mg):
    a = mg.plan_joints(LEFT, RIGHT, seed=5)
    b = mg.plan_joints(LEFT, RIGHT, seed=5)
    np.testing.assert_array_equal(a.trajectory.positions, b.trajectory.positions)


def test_a_failing_optimiser_falls_back_to_the_shortcut_trajectory(mg, monkeypatch):
    import manip.planning.trajopt.refine as refine

    def broken(*args, **kwargs):
        raise AssertionError("must not be reached")

    def failing(*args, **kwargs):
        from manip.planning.trajopt.optimizer import TrajOptResult
        return TrajOptResult(False, None, None, float("nan"), 0, "test: no solution")

    monkeypatch.setattr(refine, "optimize_trajectory", failing)
    r = mg.plan_joints(LEFT, RIGHT, seed=3)
    assert r.success and r.source == "shortcut"
    monkeypatch.setattr(refine, "optimize_trajectory", broken)
    assert mg.plan_joints(LEFT, RIGHT, seed=3, trajopt=False).source == "shortcut"
    assert mg.plan_joints(LEFT, RIGHT, seed=3, duration=6.0).source == "shortcut"  # a fixed duration keeps the seed


def test_a_failed_first_round_gets_a_second_chance_from_the_fitted_seed(mg, monkeypatch):
    """Bisection over durations: when the round at the seed's duration gives nothing usable,
    the search starts once more from the seed's spline at a duration where it is within the limits."""
    import manip.planning.trajopt.optimizer as trajopt

    cfg = mg.config
    seed = mg.plan_joints(LEFT, RIGHT, trajopt=False, seed=3).trajectory  # round the wall
    args = (seed.positions, seed.times)
    kw = dict(limits=cfg.limits, clearance=mg.clearance, padding=0.0)
    real = trajopt.sco_fixed_step
    targets = []

    def first_round_fails(prob, c0, h, radius, **rest):
        targets.append(h * prob.n)
        if len(targets) == 1:
            return False, c0, 1, "test: the first round fails", radius
        return real(prob, c0, h, radius, **rest)

    monkeypatch.setattr(trajopt, "sco_fixed_step", first_round_fails)
    bisection = TrajOptSettings(free_duration=False)
    res = optimize_trajectory(*args, **kw, deadline=time.perf_counter() + 60.0, max_duration=seed.duration,
                              settings=bisection)
    assert res.success and res.duration < seed.duration
    fit = bspline.control_from_samples(seed.positions, seed.times, seed.duration, TrajOptSettings().intervals)
    second = max(seed.duration, TrajOptSettings().intervals * bspline.limit_step(fit, cfg.limits))
    assert targets[0] == pytest.approx(seed.duration) and targets[1] == pytest.approx(second)
    targets.clear()
    res = optimize_trajectory(*args, **kw, deadline=time.perf_counter() + 60.0,
                              settings=TrajOptSettings(free_duration=False, second_chance=False))
    assert not res.success and targets == [pytest.approx(seed.duration)]


def test_free_duration_sco_steps_keep_the_clearance_and_never_slow_the_motion(mg):
    """Every prefix of the free-duration SCO (the same steps, cut after k QPs) keeps its start's
    sampled clearance (less 1 mm) and ends no slower than it started; the bisection over
    durations is the other setting and must give a valid motion too."""
    from manip.planning.trajopt.sco import SplineProblem, sco_free_step

    cfg = mg.config
    seed = mg.plan_joints(LEFT, RIGHT, trajopt=False, seed=3).trajectory  # round the wall
    s = TrajOptSettings()
    n = s.intervals
    prob = SplineProblem(n, 7, s, LEFT, RIGHT)
    c0 = bspline.control_from_samples(seed.positions, seed.times, seed.duration, n)
    limits = cfg.limits
    margin, activation = s.margin, s.margin + s.activation

    def nearest(c: np.ndarray) -> float:
        d = mg.clearance.terms(prob.B @ c, activation).distance
        return float(d.min()) if d.size else activation

    start = nearest(c0)
    seen = [start]
    durations = [n * bspline.limit_step(c0, limits)]
    for k in range(1, 7):
        c, solves = sco_free_step(prob, c0, limits=limits, clearance=mg.clearance, margin=margin, settings=s,
                                  deadline=time.perf_counter() + 60.0, h_floor=0.0, max_solves=k)
        assert solves <= k
        assert np.all(c[:3] == LEFT) and np.all(c[n:] == RIGHT)
        seen.append(nearest(c))
        assert seen[-1] >= min(margin, start) - 1e-3
        durations.append(n * bspline.limit_step(c, limits))
    assert durations[-1] < durations[0]
    assert min(seen) < activation  # the motion comes near the wall: the clearance terms were active
    for settings in (s, TrajOptSettings(free_duration=False)):
        res = optimize_trajectory(seed.positions, seed.times, limits=limits, clearance=mg.clearance, padding=0.0,
                                  deadline=time.perf_counter() + 60.0, settings=settings,
                                  max_duration=seed.duration)
        assert res.success and res.duration < seed.duration
        v, a, j = dense_extrema(res.profile)
        assert np.all(v <= cfg.velocity_limits * (1 + 1e-9)) and np.all(a <= cfg.acceleration_limits * (1 + 1e-9))


def _spy_on_refine(monkeypatch, failures: int, ends_tied: int):
    """Record refine's optimiser calls (seed positions, settings) and validated motions; the
    first `failures` validations fail, and every result reports `ends_tied`."""
    import dataclasses

    import manip.planning.trajopt.refine as refine

    real_optimize, real_validate = refine.optimize_trajectory, refine.validate_trajectory
    calls, validations = [], []

    def optimize(*args, settings, **kwargs):
        calls.append((args[0], settings))
        return dataclasses.replace(real_optimize(*args, settings=settings, **kwargs), ends_tied=ends_tied)

    def validate(*args):
        validations.append(args[0])
        return "test: collides" if len(validations) <= failures else real_validate(*args)

    monkeypatch.setattr(refine, "optimize_trajectory", optimize)
    monkeypatch.setattr(refine, "validate_trajectory", validate)
    return refine, calls, validations


def test_an_optimised_motion_that_fails_validation_is_repaired_from_itself(mg, monkeypatch):
    """The optimisation goes on from the invalid motion with denser clearance samples."""
    refine, calls, validations = _spy_on_refine(monkeypatch, failures=1, ends_tied=0)
    r = mg.plan_joints(LEFT, RIGHT, seed=3)
    assert r.success and r.source == "trajopt"
    assert [s.samples_per_interval for _, s in calls] == [TrajOptSettings().samples_per_interval,
                                                         refine.REPAIR_SAMPLES]
    np.testing.assert_array_equal(calls[1][0], validations[0].positions)  # seeded by the invalid motion
    assert r.trajectory is validations[1]


@pytest.mark.parametrize("ends_tied", [0, 1])
def test_a_motion_whose_repair_fails_too_is_retried_with_more_of_the_seed_ends(mg, monkeypatch, ends_tied):
    """Retries from the seed keep more control points on its end segments, only when an end was tied."""
    refine, calls, validations = _spy_on_refine(monkeypatch, failures=2, ends_tied=ends_tied)
    r = mg.plan_joints(LEFT, RIGHT, seed=3)
    assert r.success
    ray_points = [s.ray_points for _, s in calls]
    if ends_tied:
        assert ray_points == [1, 1, refine.RETRY_RAY_POINTS[0]] and r.source == "trajopt"
        np.testing.assert_array_equal(calls[2][0], calls[0][0])  # from the seed again
        assert r.trajectory is validations[2]
    else:
        assert ray_points == [1, 1] and r.source == "shortcut"


def test_a_motion_whose_every_try_fails_takes_one_retry_and_falls_back_to_the_path(mg, monkeypatch):
    """After the repair and one retry per `RETRY_RAY_POINTS` entry fail, the path's timing is returned."""
    refine, calls, _ = _spy_on_refine(monkeypatch, failures=10, ends_tied=1)
    r = mg.plan_joints(LEFT, RIGHT, seed=3)
    assert r.success and r.source == "shortcut"
    assert [s.ray_points for _, s in calls] == [1, 1, *refine.RETRY_RAY_POINTS] == [1, 1, 2]


def test_the_optimiser_keeps_to_its_qp_budget(mg):
    """`max_solves` bounds the QPs (a count: the result does not depend on the machine's speed)."""
    cfg = mg.config
    seed = mg.plan_joints(LEFT, RIGHT, trajopt=False, seed=3).trajectory
    args = (seed.positions, seed.times)
    kw = dict(limits=cfg.limits, clearance=mg.clearance, padding=0.0, deadline=time.perf_counter() + 60.0)
    free = optimize_trajectory(*args, **kw)
    assert free.solves > 4
    for budget in (1, 4):
        res = optimize_trajectory(*args, **kw, max_solves=budget)
        assert res.solves == budget
    a, b = optimize_trajectory(*args, **kw, max_solves=4), optimize_trajectory(*args, **kw, max_solves=4)
    np.testing.assert_array_equal(a.control, b.control)


def test_smooth_motions_keep_jerk_well_under_the_limit(mg):
    r = mg.plan_joints(LEFT, RIGHT, seed=3, smoothness="smooth")
    assert r.success
    assert np.abs(r.trajectory.jerks).max() <= 0.25 * mg.jerk_limits.max() * (1 + 1e-9)


def test_optimiser_rejects_bad_input(mg):
    kw = dict(limits=mg.limits, clearance=mg.clearance, padding=0.0, deadline=time.perf_counter() + 1)
    q = np.stack([READY, READY + 0.1])
    t01 = np.array([0.0, 1.0])
    with pytest.raises(InvalidInputError, match="shape"):
        optimize_trajectory(READY, np.array([0.0]), **kw)
    with pytest.raises(InvalidInputError, match="finite"):
        optimize_trajectory(np.stack([READY, READY * np.nan]), t01, **kw)
    with pytest.raises(InvalidInputError, match="increase"):
        optimize_trajectory(q, np.array([0.0, 0.0]), **kw)
    with pytest.raises(InvalidInputError, match="JointLimits.velocity"):
        JointLimits(-mg.velocity_limits, mg.acceleration_limits, mg.jerk_limits)
    with pytest.raises(InvalidInputError, match="limits must be a manip.JointLimits"):
        optimize_trajectory(q, t01, **{**kw, "limits": (mg.velocity_limits, mg.acceleration_limits)})
    with pytest.raises(InvalidInputError, match="position limits"):
        optimize_trajectory(q, t01, **{**kw, "limits": JointLimits(1.0, 1.0, 1.0, joint_names=mg.joint_names)})
    with pytest.raises(InvalidInputError, match="for the seed's 7 joints"):
        optimize_trajectory(q, t01, **{**kw, "limits": JointLimits([1.0] * 6, 1.0, 1.0, lower=[-1] * 6,
                                                                      upper=[1] * 6)})
    with pytest.raises(InvalidInputError, match="max_duration"):
        optimize_trajectory(q, t01, **kw, max_duration=0.0)
    with pytest.raises(InvalidInputError, match="max_solves"):
        optimize_trajectory(q, t01, **kw, max_solves=0)
    for bad in ({"intervals": 2}, {"bisection": 1.0}, {"margin": -0.01}, {"line_search": -1}, {"iterations": 2.5},
                {"ray_points": 7}, {"penalty": 0.0}, {"solver": "no-such-solver"}):
        with pytest.raises(InvalidInputError, match=next(iter(bad))):
            TrajOptSettings(**bad)


def test_clearance_gradient_matches_finite_differences(mg):
    model = ClearanceModel(mg.checker)
    rng = np.random.default_rng(1)
    Q = rng.uniform(mg.lower_limits, mg.upper_limits, (40, 7))
    terms = model.terms(Q, 0.2)
    assert terms.config.size > 0
    eps = 1e-6
    for k in range(0, terms.config.size, max(1, terms.config.size // 8)):
        q = Q[terms.config[k]]
        fd = np.zeros(7)
        for i in range(7):
            e = np.zeros(7)
            e[i] = eps
            plus, minus = model.terms((q + e)[None], 10.0), model.terms((q - e)[None], 10.0)
            here = model.terms(q[None], 10.0)
            m = int(np.argmin(np.abs(here.distance - terms.distance[k])))
            fd[i] = (plus.distance[m] - minus.distance[m]) / (2 * eps)
        np.testing.assert_allclose(terms.gradient[k], fd, atol=1e-4)


def test_world_edits_reach_the_clearance_model(mg):
    model = ClearanceModel(mg.checker)
    q = LEFT[None]
    before = model.terms(q, 5.0).distance.min()
    other = MotionGenerator("franka", WorldConfig())
    assert ClearanceModel(other.checker).terms(q, 5.0).config.size == 0  # no obstacles: no terms
    assert np.isfinite(before)
