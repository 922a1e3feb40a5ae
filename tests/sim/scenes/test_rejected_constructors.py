"""A constructor that rejects its arguments leaves the stage as it was: the prim path can be
used again at once (it used to stay taken, and the retry raised "a prim already exists")."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import (DynamicCuboid, DynamicSphere, Franka, SingleManipulator, World, add_reference_to_stage,
                       get_assets_root_path, is_prim_path_valid)
from manip.sim.articulations.articulation import Robot


@pytest.mark.parametrize("bad", [dict(mass=-1.0), dict(density=0.0), dict(mass=1.0, density=10.0),
                                 dict(linear_velocity=[np.nan, 0, 0]), dict(angular_velocity=[0, 0, 1e9])])
def test_a_rejected_dynamic_shape_leaves_no_prim(bad):
    world = World()
    world.scene.add_default_ground_plane()
    with pytest.raises(InvalidInputError):
        DynamicCuboid("/World/cube", name="cube", size=0.1, **bad)
    assert not is_prim_path_valid("/World/cube")
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0, 0, 0.3], size=0.1, mass=0.5))
    world.reset()
    for _ in range(60):
        world.step(render=False)
    assert cube.get_mass() == pytest.approx(0.5)
    assert cube.get_world_pose()[0][2] == pytest.approx(0.05, abs=2e-3)  # fell onto the ground


def test_a_rejected_franka_removes_the_model_it_referenced():
    world = World()
    with pytest.raises(InvalidInputError, match="position"):
        Franka("/World/Franka", name="franka", position=[np.nan, 0, 0])
    assert not is_prim_path_valid("/World/Franka")
    with pytest.raises(InvalidInputError, match="below none of its links"):
        Franka("/World/Franka", name="franka", end_effector_prim_name="no_such_link")
    assert not is_prim_path_valid("/World/Franka")
    franka = world.scene.add(Franka("/World/Franka", name="franka", position=[0.3, 0, 0]))
    world.reset()
    assert franka.num_dof == 9
    np.testing.assert_allclose(franka.get_world_pose()[0], [0.3, 0, 0])


def test_a_rejected_wrapper_leaves_the_users_model_and_its_pose():
    """A model the script referenced itself stays (as in Isaac), at its pose: the rejected
    call changed nothing."""
    world = World()
    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", "/World/Franka")
    with pytest.raises(InvalidInputError, match="scal"):
        Robot("/World/Franka", name="arm", position=[1.0, 0, 0], scale=[2, 2, 2])
    with pytest.raises(InvalidInputError):
        SingleManipulator("/World/Franka", end_effector_prim_name="panda_hand", name="arm",
                          orientation=[0, 0, 0, 0])
    assert is_prim_path_valid("/World/Franka")
    arm = world.scene.add(SingleManipulator("/World/Franka", end_effector_prim_name="panda_hand", name="arm"))
    world.reset()
    np.testing.assert_allclose(arm.get_world_pose()[0], [0, 0, 0])


def test_a_rejected_sphere_of_another_family_argument_leaves_no_prim():
    World()
    with pytest.raises(InvalidInputError):
        DynamicSphere("/World/ball", radius=-0.1)
    assert not is_prim_path_valid("/World/ball")
