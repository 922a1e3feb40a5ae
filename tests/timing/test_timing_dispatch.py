"""Tests of manip.timing's single entry point (`time_path`, `TimingLimits`) and package layout."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import manip.timing
from manip.errors import InvalidInputError
from manip.status import Status
from manip.timing import (
    MODES,
    TimingLimits,
    TimingStatus,
    time_parameterize,
    time_parameterize_dense,
    time_parameterize_for_robot,
    time_path,
)

TIMING_DIR = Path(manip.timing.__file__).parent


@pytest.fixture(scope="module")
def limits(cfg):
    return TimingLimits.from_robot(cfg)


@pytest.fixture(scope="module")
def corner_path(cfg):
    a = np.array(cfg.default_joint_positions)
    return np.array([a, a + [0.5, 0.3, -0.2, 0.4, 0.1, -0.3, 0.6], a + [0.9, -0.1, 0.3, 0.6, -0.4, 0.2, 1.2]])


@pytest.fixture(scope="module")
def dense_path(cfg):
    a = np.array(cfg.default_joint_positions)
    s = np.linspace(0.0, 1.0, 25)[:, None]
    return a + s * [0.4, -0.2, 0.3, 0.3, 0.2, 0.1, 0.5] + 0.05 * np.sin(np.pi * s)


def assert_same_result(r1, r2):
    """Two results of the same deterministic computation are identical (but for compute_time)."""
    assert r1.status is r2.status and r1.success == r2.success and r1.mode == r2.mode
    assert r1.message == r2.message
    for f in ("minimum_duration", "max_deviation"):
        np.testing.assert_array_equal(getattr(r1, f), getattr(r2, f))
    for f in ("waypoints", "waypoint_velocities", "segment_durations"):
        np.testing.assert_array_equal(getattr(r1, f), getattr(r2, f))
    assert (r1.trajectory is None) == (r2.trajectory is None)
    if r1.trajectory is not None:
        t1, t2 = r1.trajectory, r2.trajectory
        assert t1.joint_names == t2.joint_names and t1.dt == t2.dt
        for f in ("times", "positions", "velocities", "accelerations", "jerks"):
            np.testing.assert_array_equal(getattr(t1, f), getattr(t2, f))


# ---------------------------------------------------------------------------- limits (TimingLimits = JointLimits)
def test_limits_from_robot(cfg, limits):
    assert limits.dof == 7 and limits.joint_names == tuple(cfg.arm_joints)
    np.testing.assert_array_equal(limits.velocity, cfg.velocity_limits)
    np.testing.assert_array_equal(limits.acceleration, cfg.acceleration_limits)
    np.testing.assert_array_equal(limits.jerk, cfg.jerk_limits)
    np.testing.assert_array_equal(limits.lower, cfg.lower_limits)
    np.testing.assert_array_equal(limits.upper, cfg.upper_limits)
    for a in (limits.velocity, limits.acceleration, limits.jerk, limits.lower, limits.upper):
        assert not a.flags.writeable  # shared with the config, which cannot change them either
    with pytest.raises(Exception):
        limits.velocity = np.ones(7)  # frozen


def test_limits_defaults_and_scalars():
    lim = TimingLimits([1.0, 2.0], 5.0, 50.0)
    assert lim.dof == 2 and lim.joint_names == ("joint_0", "joint_1")
    np.testing.assert_array_equal(lim.acceleration, [5.0, 5.0])
    assert lim.lower is None and lim.upper is None
    named = TimingLimits(1.0, 1.0, 1.0, joint_names=["a", "b", "c"])
    assert named.dof == 3 and named.velocity.shape == (3,)


def test_limits_validate():
    with pytest.raises(InvalidInputError, match="JointLimits.velocity"):
        TimingLimits([1.0, -1.0], 1.0, 1.0)
    with pytest.raises(InvalidInputError, match="JointLimits.jerk"):
        TimingLimits([1.0, 1.0], 1.0, [1.0, 2.0, 3.0])
    with pytest.raises(InvalidInputError, match="both lower and upper"):
        TimingLimits([1.0, 1.0], 1.0, 1.0, lower=[0.0, 0.0])
    with pytest.raises(InvalidInputError, match="lower must be <= upper"):
        TimingLimits([1.0, 1.0], 1.0, 1.0, lower=[0.0, 1.0], upper=[1.0, 0.0])
    with pytest.raises(InvalidInputError, match="number of joints"):
        TimingLimits(1.0, 1.0, 1.0)


# ---------------------------------------------------------------------------- time_path
def test_modes():
    assert MODES == ("exact", "blend", "along_path")


@pytest.mark.parametrize("mode", ["exact", "blend"])
def test_time_path_matches_time_parameterize(cfg, limits, corner_path, mode):
    direct = time_parameterize(
        corner_path, cfg.velocity_limits, cfg.acceleration_limits, cfg.jerk_limits, joint_names=cfg.arm_joints,
        lower_limits=cfg.lower_limits, upper_limits=cfg.upper_limits, mode=mode,
    )
    assert direct.success and direct.mode == mode
    assert_same_result(time_path(corner_path, limits, mode=mode), direct)
    assert_same_result(time_parameterize_for_robot(corner_path, cfg, mode=mode), direct)


def test_time_path_default_is_blend(limits, corner_path):
    assert time_path(corner_path, limits).mode == "blend"


def test_time_path_along_path_matches_dense(cfg, limits, dense_path):
    direct = time_parameterize_dense(
        dense_path, cfg.velocity_limits, cfg.acceleration_limits, cfg.jerk_limits, joint_names=cfg.arm_joints,
        lower_limits=cfg.lower_limits, upper_limits=cfg.upper_limits,
    )
    assert direct.success and direct.mode == "along_path"
    assert_same_result(time_path(dense_path, limits, mode="along_path"), direct)


def test_time_path_forwards_every_option(cfg, limits, corner_path, dense_path):
    options = dict(
        dt=0.01, position_tolerance=1e-5, velocity_scale=0.5, acceleration_scale=0.7, jerk_scale=0.9, duration=6.0,
    )
    for mode, path, dev in (("exact", corner_path, 0.05), ("blend", corner_path, 0.02), ("along_path", dense_path, 0.02)):
        direct = (time_parameterize_dense if mode == "along_path" else time_parameterize)(
            path, cfg.velocity_limits, cfg.acceleration_limits, cfg.jerk_limits, joint_names=cfg.arm_joints,
            lower_limits=cfg.lower_limits, upper_limits=cfg.upper_limits, deviation_tolerance=dev,
            **options, **({} if mode == "along_path" else {"mode": mode}),
        )
        assert direct.success and direct.trajectory.duration == pytest.approx(6.0)
        assert_same_result(time_path(path, limits, mode=mode, deviation_tolerance=dev, **options), direct)
    # a failure is reported the same way
    tight = time_path(dense_path, limits, mode="along_path", deviation_tolerance=1e-9)
    assert tight.status is TimingStatus.DEVIATION_TOO_LARGE
    short = time_path(corner_path, limits, duration=0.1)
    assert short.status is TimingStatus.DURATION_TOO_SHORT and short.minimum_duration > 0.1


def test_time_path_unknown_mode_lists_the_valid_ones(limits, corner_path):
    with pytest.raises(InvalidInputError) as e:
        time_path(corner_path, limits, mode="fast")
    assert "'fast'" in str(e.value)
    for m in MODES:
        assert repr(m) in str(e.value)


def test_time_path_bad_inputs(limits, corner_path):
    with pytest.raises(InvalidInputError, match="JointLimits"):
        time_path(corner_path, {"velocity": 1.0})
    with pytest.raises(InvalidInputError, match="6 joints per waypoint but limits are for 7"):
        time_path(corner_path[:, :6], limits)
    with pytest.raises(InvalidInputError, match="velocity_scale"):
        time_path(corner_path, limits, velocity_scale=2.0)
    with pytest.raises(InvalidInputError, match="deviation_tolerance"):
        time_path(corner_path, limits, deviation_tolerance=-1.0)


# ---------------------------------------------------------------------------- status and layout
def test_status_style():
    assert issubclass(TimingStatus, Status)
    assert [s.value for s in TimingStatus] == [s.name.lower() for s in TimingStatus]
    for s in TimingStatus:
        assert s.hint, s
    assert "minimum_duration" in TimingStatus.DURATION_TOO_SHORT.hint


def _imports(path: Path) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            out.add(node.module)
    return out


def test_algorithms_do_not_import_each_other():
    waypoints = _imports(TIMING_DIR / "waypoints.py") | _imports(TIMING_DIR / "segments.py")
    dense = _imports(TIMING_DIR / "dense.py")
    assert not {"manip.timing.dense", "manip.timing.dispatch", "manip.timing"} & waypoints
    assert not {"manip.timing.waypoints", "manip.timing.segments", "manip.timing.dispatch", "manip.timing"} & dense
    for shared in ("shared.py", "checks.py", "result.py"):
        assert not any(m.startswith("manip.timing.") and m.rsplit(".", 1)[1] in ("waypoints", "segments", "dense",
                                                                                  "dispatch")
                       for m in _imports(TIMING_DIR / shared)), shared
