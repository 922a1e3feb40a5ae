"""Isaac's SurfaceGripper on a simulated UR10 (real MuJoCo physics): a cube lifted by suction,
released, a grip broken by its force limit, and nothing gripped out of reach."""

from __future__ import annotations

import numpy as np
import pytest

from manip import IKSolver, Kinematics, Pose, load_robot_config
from manip.errors import InvalidInputError
from manip.sim import (
    ArticulationAction,
    DynamicCuboid,
    FixedCuboid,
    SingleManipulator,
    SurfaceGripper,
    World,
    get_assets_root_path,
)
from manip.sim.scenes.stage import SimulationError

KIN = Kinematics(load_robot_config("ur10"))
HOME = np.array(KIN.config.default_joint_positions)   # the flange pointing down
FLANGE = KIN.fk(HOME, "tool0")


def ur10_over_a_cube(gap=0.004, mass=0.5, **gripper_args):
    """A UR10 at home whose flange (ee_link: x out of the flange) is `gap` [m] above a cube on a pedestal."""
    world = World()
    world.scene.add_default_ground_plane()
    x, y, z = FLANGE.position
    top = z - gap
    world.scene.add(FixedCuboid("/World/pedestal", name="pedestal", position=[x, y, (top - 0.05) / 2],
                                scale=[0.1, 0.1, top - 0.05], size=1.0))
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[x, y, top - 0.025], size=0.05,
                                         mass=mass))
    gripper = SurfaceGripper(end_effector_prim_path="/World/UR10/ee_link", translate=0.0, direction="x",
                             **gripper_args)
    ur10 = world.scene.add(SingleManipulator(prim_path="/World/UR10", name="ur10", end_effector_prim_name="ee_link",
                                             gripper=gripper, usd_path=get_assets_root_path() + "/ur10/ur10.xml"))
    ur10.set_joints_default_state(positions=HOME)
    world.reset()
    for _ in range(20):
        world.step(render=False)
    return world, ur10, gripper, cube


def lift(world, ur10, height=0.2, steps=120):
    """Raise the flange by `height` [m] along a cosine profile over `steps` physics steps, then hold 30."""
    q = IKSolver(KIN).solve(Pose(FLANGE.position + [0, 0, height], FLANGE.quaternion), "tool0", seed_q=HOME).q
    q0 = ur10.get_joint_positions()
    for k in range(steps + 30):
        s = 0.5 * (1 - np.cos(np.pi * min(1.0, (k + 1) / steps)))
        ur10.apply_action(ArticulationAction(joint_positions=q0 + s * (q - q0)))
        world.step(render=False)


def test_a_cube_is_lifted_by_suction_and_released():
    world, ur10, gripper, cube = ur10_over_a_cube()
    start = cube.get_world_pose()[0]
    assert not gripper.is_closed()
    gripper.forward("close")                      # as a pick-and-place controller calls it
    assert gripper.is_closed()
    lift(world, ur10)
    held = cube.get_world_pose()[0]
    assert held[2] - start[2] == pytest.approx(0.2, abs=0.005)
    # held where it was pulled in to: against the wrist's collision hull, 2.8 mm below the flange
    np.testing.assert_allclose(held - ur10.end_effector.get_world_pose()[0], [0, 0, -0.0028 - 0.025], atol=3e-4)
    gripper.open()
    for _ in range(60):
        world.step(render=False)
    assert not gripper.is_closed()
    assert cube.get_world_pose()[0][2] == pytest.approx(start[2], abs=2e-3)   # fell back onto the pedestal
    world.reset()                                   # open again after a reset (the default state)
    assert not gripper.is_closed() and gripper.get_default_state() == {"opened": True}


def test_close_pulls_the_object_in_onto_the_grip_point():
    """Isaac's gripper pulls what its ray finds within grip_threshold in onto the grip point (manip's
    held it where it was, 8 mm away): here up against the UR10 wrist's collision hull, which
    reaches 2.8 mm past the flange (the grip point), without turning it; kp / kd, which Isaac's
    joint uses and manip's weld does not, warn when set."""
    world, ur10, gripper, cube = ur10_over_a_cube(gap=0.008, grip_threshold=0.01)
    top = cube.get_world_pose()[0][2] + 0.025
    assert FLANGE.position[2] - top == pytest.approx(0.008, abs=1e-3)   # resting on the pedestal, 8 mm below
    gripper.close()
    for _ in range(30):                             # 0.5 s
        world.step(render=False)
    assert gripper.is_closed()
    flange = ur10.end_effector.get_world_pose()[0]
    cube_position, cube_orientation = cube.get_world_pose()
    assert flange[2] - (cube_position[2] + 0.025) == pytest.approx(0.0028, abs=3e-4)   # 5.2 mm up
    np.testing.assert_allclose(cube_position[:2], flange[:2], atol=1e-3)
    np.testing.assert_allclose(np.abs(cube_orientation), [1, 0, 0, 0], atol=1e-3)   # not turned
    with pytest.warns(UserWarning, match=r"kp=1000, kd=100 are not used"):
        SurfaceGripper("/World/UR10/ee_link", kp=1.0e3)


def test_the_grip_breaks_past_its_force_limit():
    # with gravity the 2 kg cube weighs 19.6 N: a 10 N limit breaks on the way up, a 40 N one holds
    world, ur10, gripper, cube = ur10_over_a_cube(mass=2.0, force_limit=10.0, disable_gravity=False)
    start = cube.get_world_pose()[0]
    gripper.close()
    assert gripper.is_closed()
    lift(world, ur10)
    assert not gripper.is_closed()
    assert cube.get_world_pose()[0][2] == pytest.approx(start[2], abs=2e-3)   # left on the pedestal
    gripper.set_force_limit(40.0)
    lift(world, ur10, height=0.0)                   # back down to the cube
    gripper.close()
    lift(world, ur10)
    assert gripper.is_closed() and cube.get_world_pose()[0][2] - start[2] == pytest.approx(0.2, abs=0.01)


def test_nothing_within_reach_stays_open_and_bad_arguments_raise():
    gripper = ur10_over_a_cube(gap=0.03)[2]   # 3 cm away, grip_threshold 1 cm
    gripper.close()
    assert not gripper.is_closed()
    with pytest.raises(InvalidInputError, match="direction must be 'x', 'y' or 'z'"):
        SurfaceGripper("/World/UR10/ee_link", direction="w")
    with pytest.raises(InvalidInputError, match="force_limit"):
        gripper.set_force_limit(-1.0)
    with pytest.raises(InvalidInputError, match="action must be 'open' or 'close'"):
        gripper.forward("grip")
    with pytest.raises(NotImplementedError, match="no joints"):
        gripper.apply_action(ArticulationAction(joint_positions=[0.0]))
    late = SurfaceGripper("/World/UR10/wrist_3_link")     # made after the reset: in the model from the next
    with pytest.raises(SimulationError, match="not simulated yet"):
        late.close()
