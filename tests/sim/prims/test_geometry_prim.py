"""GeometryPrim's collision switch: kept across compiles, set before the first reset, never
written into another geom, and Isaac's constructor arguments."""

from __future__ import annotations

import pytest

from manip.errors import InvalidInputError
from manip.sim import (DynamicCuboid, FixedCuboid, Franka, GeometryPrim, PhysicsMaterial, SimulationError,
                       VisualCuboid, World)


def test_collisions_switched_off_before_the_first_reset_stay_off_across_recompiles():
    world = World()
    world.scene.add_default_ground_plane()
    wall = world.scene.add(FixedCuboid("/World/wall", name="wall", position=[0.0, 0.0, 0.1], size=0.2))
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.0, 0.0, 0.5], size=0.05))
    cube.set_collision_enabled(False)  # was ignored before the World compiled
    assert not cube.get_collision_enabled()
    world.reset()
    assert not cube.get_collision_enabled()
    for _ in range(60):
        world.step(render=False)
    assert cube.get_world_pose()[0][2] < -1.0  # fell through the wall and the ground
    cube.set_collision_enabled(True)
    wall.set_collision_enabled(False)
    world.scene.add(VisualCuboid("/World/mark", name="mark", position=[2.0, 2.0, 2.0], size=0.1))
    world.reset()  # recompiles (a prim was added): the switches were lost
    assert cube.get_collision_enabled() and not wall.get_collision_enabled()
    for _ in range(60):
        world.step(render=False)
    assert cube.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)  # through the wall, onto the ground


def test_collisions_switched_off_while_running_stop_the_friction_pairs_too():
    """A shape with a physics material touches the ground through an explicit MuJoCo pair
    (PhysX's combined friction), which MuJoCo collides whatever contype/conaffinity say: switched
    off after the reset, a cube resting on a fixed box and one on the ground stayed put."""
    world = World()
    world.scene.add_default_ground_plane()
    rubber = PhysicsMaterial("/World/Physics_Materials/rubber", static_friction=1.2, dynamic_friction=1.2)
    box = world.scene.add(FixedCuboid("/World/box", name="box", position=[0.5, 0.0, 0.05], size=0.1))
    on_box = world.scene.add(DynamicCuboid("/World/a", name="a", position=[0.5, 0.0, 0.2], size=0.05,
                                           physics_material=rubber))
    on_ground = world.scene.add(DynamicCuboid("/World/b", name="b", position=[0.0, 0.0, 0.2], size=0.05,
                                              physics_material=rubber))
    world.reset()
    assert world.model.npair > 0  # the friction pairs exist
    for _ in range(60):
        world.step(render=False)
    assert on_box.get_world_pose()[0][2] == pytest.approx(0.125, abs=2e-3)
    assert on_ground.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)
    box.set_collision_enabled(False)
    on_ground.set_collision_enabled(False)
    for _ in range(30):
        world.step(render=False)
    assert on_box.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)  # through the box, onto the ground
    assert on_ground.get_world_pose()[0][2] < -0.5  # through the ground
    box.set_collision_enabled(True)  # on again: the pair is back
    on_box.set_world_pose([0.5, 0.0, 0.3])
    for _ in range(60):
        world.step(render=False)
    assert on_box.get_world_pose()[0][2] == pytest.approx(0.125, abs=2e-3)


def test_isaacs_collision_argument_and_a_robot_link_is_refused_not_another_geom_written():
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    mark = world.scene.add(VisualCuboid("/World/mark", name="mark", position=[0.5, 0.5, 0.05], size=0.1))
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, -0.5, 0.5], size=0.05))
    assert not mark.get_collision_enabled()
    GeometryPrim("/World/mark", name="mark_geom", collision=True)  # was TypeError: unexpected keyword
    assert mark.get_collision_enabled()
    world.reset()
    last = world.model.ngeom - 1
    before = (world.model.geom_contype.copy(), world.model.geom_conaffinity.copy())
    hand = GeometryPrim("/World/Franka/panda_hand", name="hand_geom")
    # It wrote contype 0 into the model's last geom (geom id -1): here the cube's.
    with pytest.raises(SimulationError, match="link of the model"):
        hand.set_collision_enabled(False)
    assert (world.model.geom_contype == before[0]).all() and (world.model.geom_conaffinity == before[1]).all()
    assert world.model.geom(last).name in (cube.prim_path + "/geom", mark.prim_path + "/geom")
    friction = world.model.geom_friction.copy()
    with pytest.raises(SimulationError, match="link of the model"):  # wrote the last geom's friction too
        hand.apply_physics_material(PhysicsMaterial("/World/Physics_Materials/rubber", dynamic_friction=1.5))
    assert (world.model.geom_friction == friction).all()
    with pytest.raises(InvalidInputError, match="True or False"):
        cube.set_collision_enabled("no")
    # Through a GeometryPrim wrapping a shape, the material is the shape's (kept when the World recompiles).
    ice = PhysicsMaterial("/World/Physics_Materials/ice", static_friction=0.05, dynamic_friction=0.05)
    GeometryPrim("/World/cube", name="cube_geom").apply_physics_material(ice)
    assert cube.get_applied_physics_material() is ice
    world.scene.add(VisualCuboid("/World/mark2", name="mark2", position=[2.0, 2.0, 2.0], size=0.1))
    world.reset()
    assert world.model.geom_friction[cube.geom_id, 0] == pytest.approx(0.05)
    assert franka.num_dof == 9
