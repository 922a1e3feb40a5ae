"""`Camera`'s normals, motion vectors and pause, and the Isaac camera tutorial's calls."""

from __future__ import annotations

import numpy as np
import pytest

from manip.sim import Camera, DynamicCuboid, FixedCuboid, World, euler_angles_to_quats

DOWN = euler_angles_to_quats(np.array([0.0, 90.0, 0.0]), degrees=True)   # "world" axes: +X forward turned to -Z


def test_normals_of_a_floor_seen_from_above_point_up():
    world = World()
    world.scene.add(FixedCuboid("/World/floor", name="floor", position=[0, 0, -0.05], scale=[4, 4, 0.1], size=1.0))
    cam = Camera("/World/camera", position=[0.1, 0.0, 1.0], orientation=DOWN, resolution=(64, 48))
    world.reset()
    cam.add_normals_to_frame()
    n = cam.get_current_frame()["normals"]
    assert n.shape == (48, 64, 4) and n.dtype == np.float32
    assert np.allclose(n[1:-1, 1:-1, :3], [0.0, 0.0, 1.0], atol=1e-4)
    assert np.all(n[0] == 0) and np.all(n[:, -1] == 0)   # borders: no neighbour
    cam.remove_normals_from_frame()
    assert "normals" not in cam.get_current_frame()


def test_the_pointcloud_annotator_gives_world_points_colours_and_normals_as_isaacs():
    # Isaac: add_pointcloud_to_frame(); get_current_frame()["pointcloud"]["data"] (was a KeyError).
    world = World()
    world.scene.add(FixedCuboid("/World/floor", name="floor", position=[0, 0, -0.05], scale=[4, 4, 0.1], size=1.0,
                                color=[0.0, 1.0, 0.0]))
    cube = world.scene.add(FixedCuboid("/World/box", name="box", position=[0.1, 0.0, 0.1], size=0.2,
                                       color=[1.0, 0.0, 0.0]))
    cam = Camera("/World/camera", position=[0.1, 0.0, 1.0], orientation=DOWN, resolution=(64, 48))
    world.reset()
    cam.add_pointcloud_to_frame(include_unlabelled=True)
    pc = cam.get_current_frame()["pointcloud"]
    data, info = pc["data"], pc["info"]
    assert data.dtype == np.float32 and data.shape == (64 * 48, 3)  # every pixel sees the floor or the box
    np.testing.assert_allclose(data, cam.get_pointcloud(), atol=1e-5)
    assert info["pointRgb"].shape == (len(data), 4) and info["pointNormals"].shape == (len(data), 4)
    on_top = np.abs(data[:, 2] - 0.2) < 1e-3  # the box's top face: red, facing up
    assert on_top.sum() > 50
    assert np.all(np.abs(data[on_top, :2] - cube.get_world_pose()[0][:2]) <= 0.1 + 1e-3)
    red = info["pointRgb"][on_top]
    assert np.all(red[:, 0] > 2 * red[:, 1])
    # normals from the depth image: away from the face's edges (the neighbours there are on the floor)
    inner = on_top & np.all(np.abs(data[:, :2] - cube.get_world_pose()[0][:2]) < 0.07, axis=1)
    assert inner.sum() > 20 and np.allclose(info["pointNormals"][inner, :3], [0.0, 0.0, 1.0], atol=1e-3)
    cam.remove_pointcloud_from_frame()
    assert "pointcloud" not in cam.get_current_frame()


def test_motion_vectors_match_the_projected_motion_of_a_moving_cube():
    world = World(physics_dt=1.0 / 200.0)
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.0, 0.0, 0.5], scale=[0.2, 0.2, 0.2],
                                         size=1.0))
    cam = Camera("/World/camera", position=[0.0, 0.0, 2.0], orientation=DOWN, resolution=(160, 120), frequency=20)
    world.reset()
    cube.set_linear_velocity(np.array([0.4, -0.3, 0.0]))
    cube.set_angular_velocity(np.array([0.0, 0.0, 1.5]))
    world.step(render=False)
    cam.add_motion_vectors_to_frame()
    frame = cam.get_current_frame()
    mv = frame["motion_vectors"]
    assert mv.shape == (120, 160, 4) and mv.dtype == np.float32
    # the cube's top face: each pixel's point moves with the cube's rigid motion over 1/20 s
    p, _ = cube.get_world_pose()
    v, w = cube.get_linear_velocity(), cube.get_angular_velocity()
    uv = np.round(cam.get_image_coords_from_world_points(p[None] + [[0.0, 0.0, 0.1]])[0]).astype(int)
    depth = frame["distance_to_image_plane"]
    u, r = uv[0], uv[1]
    top = cam.get_world_points_from_image_coords(np.array([[u, r]], dtype=float), np.array([depth[r, u]]))[0]
    dt = 1.0 / 20.0
    moved = top + (v + np.cross(w, top - p)) * dt
    expected = cam.get_image_coords_from_world_points(moved[None])[0] - [u, r]
    assert np.allclose(mv[r, u, :2], expected, rtol=0.02, atol=0.02)
    assert np.linalg.norm(expected) > 1.0   # the test sees a real motion (pixels)
    assert np.all(mv[0, 0] == 0)            # the corner sees only the sky: still


def test_pause_freezes_the_frame_until_resume():
    world = World()
    world.scene.add(FixedCuboid("/World/wall", name="wall", position=[1.5, 0, 0.5], scale=[0.1, 6, 6], size=1.0))
    cam = Camera("/World/camera", position=[0, 0, 0.5], resolution=(32, 24))
    world.reset()
    frozen = cam.get_current_frame()
    cam.pause()
    assert cam.is_paused()
    cam.set_world_pose(position=[0.5, 0, 0.5])
    assert np.array_equal(cam.get_current_frame()["distance_to_image_plane"], frozen["distance_to_image_plane"])
    cam.resume()
    assert not cam.is_paused()
    assert np.allclose(cam.get_current_frame()["distance_to_image_plane"], 0.95, atol=1e-3)


ISAAC_CAMERA_TUTORIAL = """
import numpy as np
import manip.sim as rot_utils                    # was: import omni.isaac.core.utils.numpy.rotations as rot_utils
from manip.sim import World, DynamicCuboid, Camera   # was: omni.isaac.core / omni.isaac.sensor

my_world = World(stage_units_in_meters=1.0)
cube_2 = my_world.scene.add(DynamicCuboid(prim_path="/new_cube_2", name="cube_1", position=np.array([5.0, 3, 1.0]),
                                          scale=np.array([0.6, 0.5, 0.2]), size=1.0, color=np.array([255, 0, 0])))
cube_3 = my_world.scene.add(DynamicCuboid(prim_path="/new_cube_3", name="cube_2", position=np.array([-5, 1, 3.0]),
                                          scale=np.array([0.1, 0.1, 0.1]), size=1.0, color=np.array([0, 0, 255]),
                                          linear_velocity=np.array([0, 0, 0.4])))
camera = Camera(prim_path="/World/camera", position=np.array([0.0, 0.0, 25.0]), frequency=20, resolution=(256, 256),
                orientation=rot_utils.euler_angles_to_quats(np.array([0, 90, 0]), degrees=True))
my_world.scene.add_default_ground_plane()
my_world.reset()
camera.initialize()
camera.add_motion_vectors_to_frame()
for i in range(STEPS):
    my_world.step(render=True)
    frame = camera.get_current_frame()
    if i == STEPS - 1:
        points_2d = camera.get_image_coords_from_world_points(
            np.array([cube_3.get_world_pose()[0], cube_2.get_world_pose()[0]]))
        points_3d = camera.get_world_points_from_image_coords(points_2d, np.array([24.94, 24.9]))
        rgba = camera.get_rgba()
"""


def test_the_isaac_camera_tutorial_runs_with_its_imports_changed():
    scope = {"STEPS": 30}
    exec(compile(ISAAC_CAMERA_TUTORIAL, "isaac_camera_tutorial", "exec"), scope)
    assert scope["rgba"].shape == (256, 256, 4)
    assert set(scope["frame"]) >= {"rgba", "distance_to_image_plane", "motion_vectors"}
    # looking straight down from 25 m: the red cube rests on the ground (top at z = 0.1), so the
    # tutorial's image-plane depth 24.9 puts its pixel back at its x, y
    assert np.allclose(scope["points_3d"][1, :2], scope["cube_2"].get_world_pose()[0][:2], atol=0.02)
    # the red cube: the tutorial's 0-255 colour drawn saturated red, as in Isaac
    u, v = np.round(scope["points_2d"][1]).astype(int)
    assert tuple(scope["rgba"][v, u, :3] > 100) == (True, False, False)
