"""`manip.JointLimits`: one validated, read-only limits record shared by every part of a plan."""

from __future__ import annotations

import numpy as np
import pytest

from manip import JointLimits, MotionGenerator, load_robot_config
from manip.control import ReactiveController
from manip.errors import InvalidInputError
from manip.timing import TimingLimits


def test_the_robot_config_builds_one_limits_record_shared_by_every_user():
    cfg = load_robot_config("franka")
    lim = cfg.limits
    assert isinstance(lim, JointLimits) and lim.dof == 7 and lim.joint_names == cfg.arm_joints
    for name, array in (("lower", cfg.lower_limits), ("upper", cfg.upper_limits), ("velocity", cfg.velocity_limits),
                        ("acceleration", cfg.acceleration_limits), ("jerk", cfg.jerk_limits)):
        assert getattr(lim, name) is array and array.shape == (7,)
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 0.0
    mg = MotionGenerator(cfg)
    assert mg.limits is cfg.limits and mg.kinematics.limits is cfg.limits
    assert JointLimits.from_robot(cfg) is cfg.limits
    assert TimingLimits is JointLimits  # the old name of the timing call's limits


def test_scaled_limits_multiply_velocity_acceleration_and_jerk_only():
    lim = load_robot_config("franka").limits
    half = lim.scaled(0.5, 0.25, jerk=0.1)
    np.testing.assert_array_equal(half.velocity, lim.velocity * 0.5)
    np.testing.assert_array_equal(half.acceleration, lim.acceleration * 0.25)
    np.testing.assert_array_equal(half.jerk, lim.jerk * 0.1)
    np.testing.assert_array_equal(half.lower, lim.lower)
    np.testing.assert_array_equal(half.upper, lim.upper)
    assert half.joint_names == lim.joint_names
    assert lim.scaled() is lim
    for bad in (0.0, 1.5, float("nan")):
        with pytest.raises(InvalidInputError, match=r"velocity must be a number in \(0, 1\]"):
            lim.scaled(bad)
    with pytest.raises(InvalidInputError, match="acceleration"):
        lim.scaled(1.0, -1.0)


def test_limits_are_validated_once_and_name_the_field():
    lim = JointLimits([1.0, 2.0], 5.0, 50.0)
    assert lim.dof == 2 and lim.joint_names == ("joint_0", "joint_1") and lim.lower is None
    np.testing.assert_array_equal(lim.acceleration, [5.0, 5.0])
    with pytest.raises(InvalidInputError, match="JointLimits.velocity must be > 0"):
        JointLimits([1.0, -1.0], 1.0, 1.0)
    with pytest.raises(InvalidInputError, match="JointLimits.jerk has non-finite"):
        JointLimits([1.0, 1.0], 1.0, [1.0, np.inf])
    with pytest.raises(InvalidInputError, match=r"JointLimits.acceleration must have shape \(2,\)"):
        JointLimits([1.0, 1.0], [1.0, 2.0, 3.0], 1.0)
    with pytest.raises(InvalidInputError, match="both lower and upper"):
        JointLimits(1.0, 1.0, 1.0, upper=[1.0], joint_names=["a"])
    with pytest.raises(InvalidInputError, match="lower must be <= upper"):
        JointLimits(1.0, 1.0, 1.0, lower=[1.0], upper=[0.0], joint_names=["a"])


def test_the_reactive_controller_keeps_the_scaled_limits():
    cfg = load_robot_config("franka")
    ctrl = ReactiveController(cfg, velocity_scale=0.5, acceleration_scale=0.5)
    np.testing.assert_array_equal(ctrl.velocity_limits, cfg.velocity_limits * 0.5)
    np.testing.assert_array_equal(ctrl.acceleration_limits, cfg.acceleration_limits * 0.5)
    np.testing.assert_array_equal(ctrl.lower_limits, cfg.lower_limits)
    assert ReactiveController(cfg, acceleration_scale=None).acceleration_limits is None
