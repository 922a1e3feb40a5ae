"""Object and joint setters refuse absurd values up front (manip.sim.utils.bounds), naming the argument
and the bound, as robot commands are: MuJoCo never gets a state it would diverge from and reset.
Values at the bounds simulate without instability."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import ArticulationAction, DynamicCuboid, Franka, RigidPrimView, World
from manip.sim.utils import bounds


def scene():
    world = World()
    world.scene.add_default_ground_plane()
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.3], size=0.05))
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    return world, cube, franka


def steps(world, n: int = 60) -> None:
    for _ in range(n):
        world.step(render=False)


@pytest.mark.parametrize("setter, value, words", [
    ("set_world_pose", [2e4, 0.0, 0.3], ["position", "2e+04 m exceeds manip.sim.utils.bounds.MAX_WORLD_POSITION = 10000 m"]),
    ("set_linear_velocity", [0.0, 0.0, -5e3], ["linear velocity", "MAX_LINEAR_SPEED = 1000 m/s"]),
    ("set_angular_velocity", [3e3, 0.0, 0.0], ["angular velocity", "MAX_ANGULAR_SPEED = 1000 rad/s"]),
])
def test_absurd_object_poses_and_velocities_are_refused_and_change_nothing(setter, value, words) -> None:
    world, cube, _ = scene()
    before = cube.get_world_pose()[0], cube.get_linear_velocity(), cube.get_angular_velocity()
    with pytest.raises(InvalidInputError) as info:
        getattr(cube, setter)(value)
    for w in words:
        assert w in str(info.value)
    after = cube.get_world_pose()[0], cube.get_linear_velocity(), cube.get_angular_velocity()
    for a, b in zip(before, after):
        np.testing.assert_array_equal(a, b)
    steps(world)   # no SimulationInstabilityError: MuJoCo never saw the value


def test_object_values_at_the_bounds_simulate_stably() -> None:
    world, cube, _ = scene()
    cube.set_world_pose([0.4, 0.0, 0.03])
    cube.set_linear_velocity([-0.999 * bounds.MAX_LINEAR_SPEED, 0.0, 0.0])    # at the robot
    cube.set_angular_velocity([0.999 * bounds.MAX_ANGULAR_SPEED, 0.0, 0.0])
    steps(world, 120)
    assert np.all(np.isfinite(cube.get_world_pose()[0]))
    cube.set_world_pose([0.999 * bounds.MAX_WORLD_POSITION, 0.0, 0.3])
    steps(world)


def test_constructors_default_states_and_views_are_held_to_the_same_bounds() -> None:
    world, cube, franka = scene()
    with pytest.raises(InvalidInputError, match="linear_velocity.*MAX_LINEAR_SPEED"):
        DynamicCuboid("/World/fast", name="fast", position=[0, 0, 1], size=0.05, linear_velocity=[1e4, 0, 0])
    with pytest.raises(InvalidInputError, match="position.*MAX_WORLD_POSITION"):
        DynamicCuboid("/World/far", name="far", position=[0, 5e4, 1], size=0.05)
    with pytest.raises(InvalidInputError, match="angular_velocity.*MAX_ANGULAR_SPEED"):
        cube.set_default_state(angular_velocity=[0, 0, 1e5])
    with pytest.raises(InvalidInputError, match="position.*MAX_WORLD_POSITION"):
        franka.set_world_pose([1e5, 0, 0])
    view = world.scene.add(RigidPrimView("/World/cube", name="cubes"))
    world.reset()
    with pytest.raises(InvalidInputError, match=r"velocities \(angular part\) \(row 0\).*MAX_ANGULAR_SPEED"):
        view.set_velocities([[0.0, 0.0, 0.0, 0.0, 0.0, 2e3]])
    with pytest.raises(InvalidInputError, match=r"positions \(row 0\).*MAX_WORLD_POSITION"):
        view.set_world_poses(positions=[[0.0, 0.0, 1e6 - 1]])
    view.set_velocities([[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]])
    steps(world)


def test_absurd_joint_speeds_and_efforts_below_the_old_cap_are_refused_naming_the_joint() -> None:
    world, _, franka = scene()
    q = franka.get_joint_positions()
    with pytest.raises(InvalidInputError) as info:
        franka.set_joint_velocities(np.r_[1e3, np.zeros(8)])   # below the 1e6 cap: diverged within 30 ms
    assert "velocities: panda_joint1=1000 rad/s beyond manip.sim.utils.bounds.MAX_JOINT_SPEED = 100 rad/s" in str(info.value)
    with pytest.raises(InvalidInputError, match=r"panda_finger_joint1=20 m/s.*MAX_JOINT_LINEAR_SPEED = 10 m/s"):
        franka.set_joint_velocities([20.0], joint_indices=[7])
    with pytest.raises(InvalidInputError) as info:
        franka.set_joint_efforts([1e5], joint_indices=[7])   # a finger's motor gives 70 N
    assert "efforts: panda_finger_joint1=1e+05 N (at most 250)" in str(info.value)
    assert "MAX_EFFORT_ACCELERATION = 10000" in str(info.value)
    with pytest.raises(InvalidInputError, match=r"ArticulationAction.joint_efforts: panda_joint7=5000 N m"):
        franka.apply_action(ArticulationAction(joint_efforts=[5e3], joint_indices=[6]))
    with pytest.raises(InvalidInputError, match="default joint velocities: panda_joint2=500 rad/s"):
        franka.set_joints_default_state(velocities=np.r_[0.0, 500.0, np.zeros(7)])
    np.testing.assert_array_equal(franka.get_joint_positions(), q)
    np.testing.assert_array_equal(franka.get_applied_action().joint_efforts, 0.0)
    steps(world)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_joint_values_at_the_bounds_simulate_stably(sign) -> None:
    world, _, franka = scene()
    m0 = world.model.dof_M0[franka._core.dadr]   # the joints' inertia at the reference configuration
    franka.set_joint_efforts(sign * 0.999 * bounds.MAX_EFFORT_ACCELERATION * m0)   # every joint at once
    franka.set_joint_velocities(sign * 0.999 * np.r_[[bounds.MAX_JOINT_SPEED] * 7, [bounds.MAX_JOINT_LINEAR_SPEED] * 2])
    steps(world, 120)
    assert np.all(np.isfinite(franka.get_joint_positions()))
    franka.set_joint_efforts(np.r_[87.0, np.zeros(8)])   # the Franka's own torques are far inside
    steps(world)


def test_absurd_shape_sizes_are_refused_at_construction_and_by_setters() -> None:
    """A 1e6 m cube dropped beside the Franka made MuJoCo diverge at the first step
    (SimulationInstabilityError naming only the cube's free joint); now the constructor and the
    size, radius, height and scale setters name the dimension and MAX_OBJECT_SIZE, and a
    refused setter changes nothing. A shape at the bound (a 1e4 m floor slab) simulates."""
    world, cube, _ = scene()
    with pytest.raises(InvalidInputError, match=r"DynamicCuboid '/World/big': size \(scale included\) = 1e\+06 m "
                                                r"exceeds manip.sim.utils.bounds.MAX_OBJECT_SIZE = 10000 m"):
        DynamicCuboid("/World/big", name="big", position=[0.5, 0.3, 2.0], size=1e6)
    for call, word in ((lambda: cube.set_size(2e4), "size"), (lambda: cube.set_local_scale([1e6, 1.0, 1.0]), "size")):
        with pytest.raises(InvalidInputError, match=f"{word} .*MAX_OBJECT_SIZE"):
            call()
    assert cube.get_size() == 0.05 and np.array_equal(cube.get_local_scale(), np.ones(3))
    from manip.sim import DynamicSphere, FixedCuboid, FixedCylinder
    with pytest.raises(InvalidInputError, match="radius .*MAX_OBJECT_SIZE"):
        DynamicSphere("/World/s", name="s", radius=2e4)
    with pytest.raises(InvalidInputError, match="height .*MAX_OBJECT_SIZE"):
        FixedCylinder("/World/y", name="y", radius=0.1, height=3e4)
    world.scene.add(FixedCuboid("/World/slab", name="slab", position=[0.0, 0.0, -0.6], size=1.0,
                                scale=[bounds.MAX_OBJECT_SIZE, bounds.MAX_OBJECT_SIZE, 1.0]))
    world.reset()
    steps(world)
    assert abs(cube.get_world_pose()[0][2] - 0.025) < 2e-3
