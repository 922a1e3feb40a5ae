"""Tests of the simulator bridge of trajectories (`manip.sim_bridge`) and of the trajectory package layout."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import manip.sim_bridge as sim_bridge
import manip.trajectory
from manip.errors import InvalidInputError, UnknownNameError
from manip.robot_config import load_robot_config
from manip.sim_bridge import joint_indices_for, trajectory_to_actions
from manip.timing import time_parameterize_for_robot


class DofNamesRobot:
    def __init__(self, names):
        self.dof_names = list(names)


class IndexOnlyRobot:
    def __init__(self, names):
        self._names = list(names)

    def get_dof_index(self, name):
        return self._names.index(name) if name in self._names else -1


@pytest.fixture(scope="module")
def traj():
    cfg = load_robot_config("franka")
    a = np.array(cfg.default_joint_positions)
    r = time_parameterize_for_robot(np.array([a, a + 0.3]), cfg)
    assert r.success
    return r.trajectory


def test_functions_match_the_methods(traj):
    names = list(reversed(traj.joint_names)) + ["finger"]
    robot = DofNamesRobot(names)
    idx = joint_indices_for(traj, robot)
    np.testing.assert_array_equal(idx, traj.joint_indices_for(robot))
    np.testing.assert_array_equal(idx, [names.index(n) for n in traj.joint_names])
    for physics_dt in (None, 1 / 240):
        a = trajectory_to_actions(traj, robot, physics_dt)
        b = traj.to_articulation_actions(robot, physics_dt=physics_dt)
        assert len(a) == len(b) > 0
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x.joint_positions, y.joint_positions)
            np.testing.assert_array_equal(x.joint_velocities, y.joint_velocities)
            np.testing.assert_array_equal(x.joint_indices, y.joint_indices)
    np.testing.assert_array_equal(joint_indices_for(traj, IndexOnlyRobot(names)), idx)


def test_duck_typed_trajectory():
    """The bridge reads attributes only: any object with the trajectory's fields works."""

    class Samples:
        joint_names = ("b", "a")
        positions = np.array([[0.0, 0.0], [1.0, 2.0]])
        velocities = np.zeros((2, 2))
        num_samples = 2

    actions = trajectory_to_actions(Samples(), DofNamesRobot(["a", "b"]))
    assert len(actions) == 1
    np.testing.assert_array_equal(actions[0].joint_indices, [1, 0])
    np.testing.assert_array_equal(actions[0].joint_positions, [1.0, 2.0])


def test_errors(traj):
    with pytest.raises(UnknownNameError):
        joint_indices_for(traj, DofNamesRobot(["x"]))
    with pytest.raises(UnknownNameError):
        joint_indices_for(traj, IndexOnlyRobot(["x"]))
    with pytest.raises(InvalidInputError, match="dof_names"):
        joint_indices_for(traj, object())


def _imports(path: Path) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            out.add(node.module)
    return out


def test_bridge_imports_neither_the_simulator_nor_trajectory():
    imports = _imports(Path(sim_bridge.__file__))
    assert not any(m == "manip.sim" or m.startswith(("manip.sim.", "manip.trajectory")) for m in imports)


def test_trajectory_package_reexports():
    assert set(manip.trajectory.__all__) == {
        "CubicSplinePath", "PathProfile", "PiecewiseJerkProfile", "Trajectory", "evaluate_pieces", "sample_times",
    }
    for name in manip.trajectory.__all__:
        assert getattr(manip.trajectory, name).__module__.startswith("manip.trajectory.")
