"""Shared fixtures: the robot is loaded once per test session."""

from __future__ import annotations

import pytest

from manip.kinematics import Kinematics
from robot_constants import DOWN_XYZW, FRANKA_READY  # noqa: F401  (shared constants, importable by tests)
from manip.robot_config import RobotConfig, load_robot_config


@pytest.fixture
def fresh_world():
    """No World and an empty stage before and after the test (the simulator's World is a
    singleton); yields the World class."""
    from manip.sim import World, create_new_stage

    World.clear_instance()
    create_new_stage()
    yield World
    World.clear_instance()
    create_new_stage()


@pytest.fixture(scope="session")
def franka_config() -> RobotConfig:
    """The Franka Panda configuration of robots/franka."""
    return load_robot_config("franka")


@pytest.fixture(scope="session")
def cfg(franka_config: RobotConfig) -> RobotConfig:
    """`franka_config` by its short name (the timing and trajectory tests use it)."""
    return franka_config


@pytest.fixture(scope="session")
def franka_kinematics(franka_config: RobotConfig) -> Kinematics:
    """Kinematics of the Franka's 7 arm joints (fingers locked at their planning positions)."""
    return Kinematics(franka_config)

