"""Isaac 5's names for the views: `XFormPrim`, `RigidPrim`, `GeometryPrim` and `Articulation`
of `isaacsim.core.prims` are views; called as views (`prim_paths_expr=`, plural pose arguments
or a path expression) manip's classes of those names make the view (they raised TypeError)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.sim import (
    Articulation,
    ArticulationView,
    DynamicCuboid,
    Franka,
    GeometryPrim,
    RigidPrim,
    RigidPrimView,
    SingleArticulation,
    SingleRigidPrim,
    SingleXFormPrim,
    World,
    XFormPrim,
    XFormPrimView,
)


def _cubes(world, n=3):
    return [world.scene.add(DynamicCuboid(f"/World/Cube_{i}", name=f"cube_{i}", position=[0.5, 0.2 * i, 0.5 + 0.1 * i],
                                          size=0.05)) for i in range(n)]


def test_rigid_prim_with_prim_paths_expr_is_a_view_of_the_falling_cubes():
    world = World()
    world.scene.add_default_ground_plane()
    cubes = _cubes(world)
    view = world.scene.add(RigidPrim(prim_paths_expr="/World/Cube_.*", name="cubes"))
    by_position = RigidPrim("/World/Cube_[0-9]", name="cubes_2")  # Isaac 5's first positional argument
    assert isinstance(view, RigidPrimView) and isinstance(by_position, RigidPrimView)
    world.reset()
    for _ in range(10):
        world.step(render=False)
    v = view.get_linear_velocities()
    assert v.shape == (3, 3) and np.all(v[:, 2] < -0.5)  # falling
    np.testing.assert_allclose(view.get_world_poses()[0], [c.get_world_pose()[0] for c in cubes])
    np.testing.assert_allclose(by_position.get_world_poses()[0], view.get_world_poses()[0])
    view.set_world_poses(positions=np.array([[0.0, 0.0, 1.0]]), indices=[1])
    np.testing.assert_allclose(cubes[1].get_world_pose()[0], [0.0, 0.0, 1.0])


def test_xform_prim_with_plural_positions_is_a_view_that_places_the_prims():
    world = World()
    cubes = _cubes(world, 2)
    view = XFormPrim("/World/Cube_.*", name="xs", positions=np.array([[0.0, 0.0, 0.3], [0.0, 0.5, 0.3]]))
    assert isinstance(view, XFormPrimView)
    world.scene.add(view)
    world.reset()
    np.testing.assert_allclose(cubes[1].get_world_pose()[0], [0.0, 0.5, 0.3], atol=1e-2)


def test_articulation_with_prim_paths_expr_is_a_view_driving_the_robot():
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    arm = world.scene.add(Articulation(prim_paths_expr="/World/Franka", name="franka_view"))
    assert isinstance(arm, ArticulationView)
    world.reset()
    q = franka.get_joint_positions()
    target = q.copy()
    target[0] += 0.3
    arm.set_joint_position_targets(target[None, :])
    for _ in range(90):
        world.step(render=False)
    assert arm.get_joint_positions().shape == (1, 9)
    assert franka.get_joint_positions()[0] == pytest.approx(target[0], abs=5e-3)


def test_single_names_and_plain_paths_stay_single_prims():
    world = World()
    _cubes(world, 1)
    Franka("/World/Franka", name="franka")
    assert SingleXFormPrim is XFormPrim and SingleRigidPrim is RigidPrim and SingleArticulation is Articulation
    assert type(RigidPrim("/World/Cube_0", name="c")) is RigidPrim
    assert type(XFormPrim(prim_path="/World/frame", name="f")) is XFormPrim
    assert type(Articulation("/World/Franka", name="a")) is Articulation
    assert type(DynamicCuboid("/World/other", name="o", position=[0, 0, 1])) is DynamicCuboid


def test_geometry_prim_with_prim_paths_expr_is_a_geometry_prim_view():
    """Isaac 5's GeometryPrim view (it raised NotImplementedError): `tests/sim/prims/test_geometry_view.py`."""
    from manip.sim import GeometryPrimView

    world = World()
    _cubes(world, 2)
    view = GeometryPrim(prim_paths_expr="/World/Cube_.*")
    assert isinstance(view, GeometryPrimView)
    world.reset()
    assert view.count == 2 and view.is_collision_enabled().tolist() == [True, True]


def test_an_isaac5_articulation_view_addresses_joints_by_name():
    """Isaac 5's views take `joint_names=` besides `joint_indices=` (it raised TypeError)."""
    from manip.errors import InvalidInputError, UnknownNameError

    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    arm = world.scene.add(Articulation(prim_paths_expr="/World/Franka", name="arm"))
    world.reset()
    q = franka.get_joint_positions()
    arm.set_joint_position_targets(np.array([[q[0] + 0.3, q[3] - 0.2]]), joint_names=["panda_joint1", "panda_joint4"])
    for _ in range(90):
        world.step(render=False)
    np.testing.assert_allclose(arm.get_joint_positions(joint_names=["panda_joint1", "panda_joint4"]),
                               [[q[0] + 0.3, q[3] - 0.2]], atol=5e-3)
    kps, _ = arm.get_gains(joint_names="panda_finger_joint1")
    assert kps.shape == (1, 1) and kps[0, 0] == franka.get_articulation_controller().get_gains()[0][7]
    with pytest.raises(UnknownNameError, match="panda_joint1"):
        arm.get_joint_positions(joint_names=["elbow_joint"])
    with pytest.raises(InvalidInputError, match="not both"):
        arm.get_joint_positions(joint_indices=[0], joint_names=["panda_joint1"])
