"""Scene.compute_object_AABB as Isaac scripts use it: after `enable_bounding_boxes_computations()`
(it raised NotImplementedError), in `set_up_scene` before any reset (it raised), tight (MuJoCo's
geom boxes overestimated turned shapes and put the Franka's base 8 cm under its floor), a
ground plane at its height (it was at -5e9 m), an object added since the last reset bounded
itself (it was given another object's box)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.sim import (BaseTask, DynamicCapsule, DynamicCone, DynamicCuboid, DynamicCylinder, DynamicSphere,
                       FixedCuboid, Franka, SimulationError, World, euler_angles_to_quat,
                       quat_to_rot_matrix)


class TableTask(BaseTask):
    """Puts a cube on a table whose top it reads from the table's bounding box, as Isaac users do."""

    def set_up_scene(self, scene):
        super().set_up_scene(scene)
        scene.enable_bounding_boxes_computations()
        scene.add_default_ground_plane()
        scene.add(FixedCuboid("/World/table", name="table", position=[0.5, 0.0, 0.2], scale=[0.6, 0.8, 0.4], size=1.0))
        lo, hi = scene.compute_object_AABB("table")
        np.testing.assert_allclose([lo, hi], [[0.2, -0.4, 0.0], [0.8, 0.4, 0.4]], atol=1e-12)
        self.cube = scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, hi[2] + 0.025],
                                            size=0.05))


def test_bounds_in_set_up_scene_place_a_cube_on_the_table():
    world = World()
    task = TableTask(name="table_task")
    world.add_task(task)
    world.reset()
    for _ in range(60):
        world.step(render=False)
    lo, hi = world.scene.compute_object_AABB("cube")
    assert lo[2] == pytest.approx(0.4, abs=2e-3) and hi[2] == pytest.approx(0.45, abs=2e-3)  # resting on the top
    assert np.linalg.norm(task.cube.get_linear_velocity()) < 1e-3


def test_a_ground_plane_is_bounded_at_its_height():
    world = World()
    world.scene.add_default_ground_plane(z_position=0.3)
    world.reset()
    lo, hi = world.scene.compute_object_AABB("default_ground_plane")
    assert lo[2] == hi[2] == pytest.approx(0.3)
    assert np.all(hi[:2] - lo[:2] > 1.0)


def test_the_franka_is_bounded_above_its_floor():
    world = World()
    world.scene.add(Franka("/World/Franka", name="franka", position=[0, 0, 0.1]))
    world.reset()
    lo, hi = world.scene.compute_object_AABB("franka")
    assert lo[2] == pytest.approx(0.1, abs=1e-3)  # its base's underside (was 0.023: 7.7 cm lower)
    hand = world.scene.get_object("franka").end_effector.get_world_pose()[0]
    assert np.all(lo <= hand) and np.all(hand <= hi)


def _surface_points(obj) -> np.ndarray:
    """Dense points (N, 3) of a shape's surface in its own frame."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 181), np.linspace(0, np.pi, 91))
    ball = np.c_[(np.cos(u) * np.sin(v)).ravel(), (np.sin(u) * np.sin(v)).ravel(), np.cos(v).ravel()]
    ring = np.c_[np.cos(u[0]), np.sin(u[0]), np.zeros(u.shape[1])]
    d = obj.shape_dimensions()
    if obj.shape_kind == "cuboid":
        return np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * 0.5 * d
    if obj.shape_kind == "sphere":
        return ball * d
    r, h = d
    if obj.shape_kind == "cylinder":
        return np.vstack([ring * r + [0, 0, 0.5 * h], ring * r - [0, 0, 0.5 * h]])
    if obj.shape_kind == "capsule":
        return np.vstack([ball * r + [0, 0, 0.5 * h], ball * r - [0, 0, 0.5 * h]])
    return np.vstack([ring * r - [0, 0, 0.5 * h], [[0, 0, 0.5 * h]]])  # cone: base rim and apex


SHAPES = [(DynamicCuboid, dict(size=0.2, scale=[1.0, 0.5, 0.25])), (DynamicSphere, dict(radius=0.1)),
          (DynamicSphere, dict(radius=0.1, scale=[1.0, 2.0, 0.5])), (DynamicCylinder, dict(radius=0.05, height=0.3)),
          (DynamicCapsule, dict(radius=0.05, height=0.3)), (DynamicCone, dict(radius=0.1, height=0.2))]


@pytest.mark.parametrize("cls, dims", SHAPES)
def test_a_turned_shape_is_bounded_tightly_before_and_after_compiling(cls, dims):
    world = World()
    q = euler_angles_to_quat(np.array([30.0, 50.0, 20.0]), degrees=True)
    obj = world.scene.add(cls("/World/shape", name="shape", position=[0.2, -0.1, 1.0], orientation=q, **dims))
    authored = world.scene.compute_object_AABB("shape")
    world.reset()  # gravity acts during the reset's warm-up step: compare at the same pose
    obj.set_world_pose([0.2, -0.1, 1.0], q)
    compiled = world.scene.compute_object_AABB("shape")
    tol = 0.01 * dims.get("radius", 0.1) if cls is DynamicCone else 1e-9  # the cone: a 48-sided mesh
    np.testing.assert_allclose(compiled, authored, atol=tol)
    # tight and enclosing: dense points of the shape's surface fill the box to its faces
    pts = _surface_points(obj) @ quat_to_rot_matrix(q).T + np.array([0.2, -0.1, 1.0])
    assert np.all(pts >= compiled[0] - tol - 1e-9) and np.all(pts <= compiled[1] + tol + 1e-9)
    np.testing.assert_allclose([pts.min(axis=0), pts.max(axis=0)], compiled, atol=2e-3)
    if cls is DynamicSphere and "scale" not in dims:
        np.testing.assert_allclose(compiled, [[0.1, -0.2, 0.9], [0.3, 0.0, 1.1]], atol=1e-12)


def test_an_object_added_since_the_last_reset_is_bounded_by_itself_or_raises():
    world = World()
    world.scene.add(FixedCuboid("/World/a", name="a", position=[0, 0, 0.5], size=0.2))
    world.reset()
    world.scene.add(DynamicCuboid("/World/b", name="b", position=[3, 3, 3], size=0.1))
    np.testing.assert_allclose(world.scene.compute_object_AABB("b"), [[2.95] * 3, [3.05] * 3], atol=1e-12)
    world.scene.add(Franka("/World/Franka", name="franka"))
    with pytest.raises(SimulationError, match="reset first"):
        world.scene.compute_object_AABB("franka")
    world.reset()
    assert world.scene.compute_object_AABB("franka").shape == (2, 3)
