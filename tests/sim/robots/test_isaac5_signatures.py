"""Isaac 5's call forms (checked against isaacsim.core.prims / isaacsim.robot.manipulators 5.x):
SingleManipulator's second argument is the end effector's full path, the single prims take
`reset_xform_properties`, `World.step` takes `update_fabric`, a floating or fixed robot's root
velocity is `get_world_velocity` / `set_world_velocity` (4.x and 5.x; they raised TypeError or
AttributeError)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import (Articulation, DynamicCuboid, GeometryPrim, ParallelGripper, RigidPrim, SimulationError,
                       SingleManipulator, World, XFormPrim, add_reference_to_stage, get_assets_root_path,
                       WheeledRobot)


def test_single_manipulator_with_isaac5s_positional_end_effector_path():
    world = World()
    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", "/World/Franka")
    gripper = ParallelGripper("/World/Franka/panda_rightfinger", ["panda_finger_joint1", "panda_finger_joint2"],
                              [0.04, 0.04], [0.0, 0.0])
    arm = world.scene.add(SingleManipulator("/World/Franka", "/World/Franka/panda_hand", "my_franka",
                                            np.array([0.5, 0.0, 0.0]), gripper=gripper))
    world.reset()
    assert arm.end_effector.prim_path == "/World/Franka/panda_hand" and arm.name == "my_franka"
    np.testing.assert_allclose(arm.get_world_pose()[0], [0.5, 0.0, 0.0])  # position: the 4th argument
    hand = arm.end_effector.get_world_pose()[0]
    assert hand[0] > 0.5  # the ready pose reaches forward from the moved base
    gripper.close()
    for _ in range(30):
        world.step(render=False, update_fabric=True)
    assert np.all(gripper.get_joint_positions() < 0.002)


def test_single_prims_accept_reset_xform_properties():
    world = World()
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[-1.0, 0, 0.5], size=0.1))
    XFormPrim("/World/frame", name="frame", position=[1.0, 0, 0], reset_xform_properties=False)
    RigidPrim("/World/cube", name="cube_rigid", reset_xform_properties=True)
    GeometryPrim("/World/cube", name="cube_geom", reset_xform_properties=True)
    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", "/World/Franka")
    world.scene.add(Articulation("/World/Franka", name="arm", reset_xform_properties=True))
    world.reset()
    world.step(render=True, update_fabric=False)
    assert cube.get_linear_velocity()[2] < 0


def test_world_velocity_of_a_floating_and_a_fixed_base():
    world = World()
    world.scene.add_default_ground_plane()
    jetbot = world.scene.add(WheeledRobot("/World/Jetbot", name="jetbot", wheel_dof_names=["left_wheel_joint",
                                          "right_wheel_joint"], create_robot=True,
                                          usd_path=get_assets_root_path() + "/Isaac/Robots/Jetbot/jetbot.usd"))
    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", "/World/Franka")
    arm = world.scene.add(Articulation("/World/Franka", name="arm", position=[2.0, 0, 0]))
    world.reset()
    np.testing.assert_allclose(jetbot.get_world_velocity(), np.zeros(6), atol=1e-2)  # settling on its wheels
    jetbot.set_world_velocity(np.array([0.4, 0.0, 0.0, 0.0, 0.0, 1.0]))
    v = jetbot.get_world_velocity()
    np.testing.assert_allclose(v[[0, 5]], [0.4, 1.0], atol=1e-9)
    world.step(render=False)
    assert jetbot.get_world_pose()[0][0] > 0.001  # it moved
    np.testing.assert_allclose(arm.get_world_velocity(), np.zeros(6))
    with pytest.raises(SimulationError, match="fixed"):
        arm.set_world_velocity(np.zeros(6))
    with pytest.raises(InvalidInputError, match="6 values"):
        jetbot.set_world_velocity([0.4, 0.0, 0.0])


def test_a_rigid_prim_given_mass_and_density_leaves_nothing_behind():
    world = World()
    world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0, 0, 0.5], size=0.1))
    with pytest.raises(InvalidInputError, match="mass or density"):
        RigidPrim("/World/cube", name="cube_rigid", mass=1.0, density=10.0)
    world.reset()
    assert not [w for w in world.stage.wrappers() if getattr(w, "name", None) == "cube_rigid"]
