"""`manip.sim.Camera`: depth, point clouds and intrinsics against known geometry."""

from __future__ import annotations

import math

import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.sim import Camera, FixedCuboid, World
from manip.sim.scenes.stage import SimulationError


def _wall_world(x=1.5, thickness=0.1, camera=None):
    world = World()
    world.scene.add(FixedCuboid("/World/wall", name="wall", position=[x, 0, 0.5], scale=[thickness, 6, 6], size=1.0))
    cam = camera or Camera("/World/camera", position=[0, 0, 0.5], resolution=(640, 480))
    world.reset()
    cam.initialize()
    return world, cam


def test_plane_at_known_distance_gives_that_depth_to_1mm():
    _, cam = _wall_world(x=1.5, thickness=0.1)   # the wall's face at x = 1.45
    depth = cam.get_depth()
    assert depth.shape == (480, 640) and depth.dtype == np.float32
    assert np.all(np.abs(depth - 1.45) < 1e-3)


def test_depth_is_distance_to_the_image_plane_for_a_tilted_camera():
    # yawed 20 deg: the distance to the image plane is not the face's x distance; the points
    # back-projected from it must still lie on the face x = 1.45
    q = quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), math.radians(20.0))
    cam = Camera("/World/camera", position=[0, 0.1, 0.5], orientation=q, resolution=(320, 240))
    _, cam = _wall_world(camera=cam)
    depth = cam.get_depth()
    assert np.all(np.isfinite(depth))
    centre = depth[120, 160]   # near the optical axis: 1.45 / cos(20 deg)
    assert abs(centre - 1.45 / math.cos(math.radians(20.0))) < 0.02
    pts = cam.get_pointcloud()
    assert pts.shape == (320 * 240, 3)
    assert np.abs(pts[:, 0] - 1.45).max() < 2e-3


def test_nothing_hit_is_inf():
    # looking up at the sky: no surface
    q = quat.from_axis_angle(np.array([0.0, 1.0, 0.0]), -math.pi / 2)   # +X forward turned to +Z
    cam = Camera("/World/camera", position=[0, 0, 0.5], orientation=q, resolution=(64, 48))
    world = World()
    world.reset()
    assert np.all(np.isinf(cam.get_depth()))
    assert cam.get_pointcloud().shape == (0, 3)
    assert world is not None


def test_intrinsics_match_the_field_of_view():
    cam = Camera("/World/camera", position=[0, 0, 0.5], resolution=(640, 480))
    cam.set_focal_length(2.0)
    K = cam.get_intrinsics_matrix()
    assert K.shape == (3, 3)
    hfov = cam.get_horizontal_fov()
    assert abs(K[0, 0] - (640 / 2) / math.tan(hfov / 2)) < 1e-9
    assert abs(K[1, 1] - (480 / 2) / math.tan(cam.get_vertical_fov() / 2)) < 1e-9
    # an edge seen at a known angle: a wall covering y <= 0.2 at 1.45 m is seen from column
    # cx - fx * 0.2 / 1.45 rightwards (the image's +u is the world's -y)
    world = World()
    world.scene.add(FixedCuboid("/World/wall", name="wall", position=[1.5, -2.8, 0.5], scale=[0.1, 6, 6], size=1.0))
    world.reset()
    depth = cam.get_depth()
    row = depth[240]
    hit = np.flatnonzero(np.isfinite(row))
    expected = K[0, 2] - K[0, 0] * 0.2 / 1.45
    assert hit.min() == pytest.approx(expected, abs=1.0)
    assert hit.max() == 639


def test_pose_axes_conventions_agree():
    q = quat.from_axis_angle(np.array([0.3, -0.2, 0.9]) / np.linalg.norm([0.3, -0.2, 0.9]), 0.7)
    cam = Camera("/World/camera", position=[0.1, 0.2, 0.3], orientation=q)
    p, qw = cam.get_world_pose()
    assert np.allclose(p, [0.1, 0.2, 0.3]) and abs(abs(qw @ q) - 1) < 1e-9
    Rw = quat.to_matrix(qw)
    Rros = quat.to_matrix(cam.get_world_pose(camera_axes="ros")[1])
    Rusd = quat.to_matrix(cam.get_world_pose(camera_axes="usd")[1])
    assert np.allclose(Rros[:, 2], Rw[:, 0])      # forward: ROS +Z = world-axes +X
    assert np.allclose(Rusd[:, 2], -Rw[:, 0])     # USD looks along -Z
    assert np.allclose(Rusd[:, 1], Rw[:, 2])      # up
    cam.set_world_pose(orientation=cam.get_world_pose(camera_axes="ros")[1], camera_axes="ros")
    assert np.allclose(quat.to_matrix(cam.get_world_pose()[1]), Rw)


def test_moving_the_camera_after_reset_changes_what_it_sees():
    _, cam = _wall_world(x=1.5)
    cam.set_world_pose(position=[0.45, 0, 0.5])
    assert np.all(np.abs(cam.get_depth() - 1.0) < 1e-3)
    assert np.allclose(cam.get_world_pose()[0], [0.45, 0, 0.5])


def test_bad_input_names_the_argument():
    with pytest.raises(InvalidInputError, match="resolution"):
        Camera("/World/c1", resolution=(0, 480))
    with pytest.raises(InvalidInputError, match="resolution"):
        Camera("/World/c2", resolution=(4000, 480))
    cam = Camera("/World/c3")
    with pytest.raises(InvalidInputError, match="camera_axes"):
        cam.get_world_pose(camera_axes="opencv")
    with pytest.raises(InvalidInputError, match="focal_length"):
        cam.set_focal_length(-1.0)
    with pytest.raises(InvalidInputError, match="far_distance"):
        cam.set_clipping_range(1.0, 0.5)
    with pytest.raises(SimulationError, match="reset"):
        cam.get_depth()


def test_view_matrix_ros_aspect_ratio_and_the_lens_settings_isaac_scripts_call():
    """get_view_matrix_ros, get_aspect_ratio, the projection, focus and stereo getters and setters
    (they raised AttributeError); the bounding-box annotators raise saying so."""
    q = quat.from_axis_angle(np.array([0.0, 0.0, 1.0]), math.radians(30.0))
    cam = Camera("/World/camera", position=[0.2, -0.1, 0.5], orientation=q, resolution=(320, 240))
    _, cam = _wall_world(camera=cam)
    V = cam.get_view_matrix_ros()
    pts = cam.get_pointcloud()[::997]
    cam_pts = pts @ V[:3, :3].T + V[:3, 3]
    depth = cam.get_depth().ravel()
    hit = depth[np.isfinite(depth)][::997]
    np.testing.assert_allclose(cam_pts[:, 2], hit, atol=1e-4)  # +Z forward: the depth of each point
    uv = cam.get_image_coords_from_world_points(pts)
    K = cam.get_intrinsics_matrix()
    np.testing.assert_allclose(cam_pts[:, :2] / cam_pts[:, 2:] * [K[0, 0], K[1, 1]] + K[:2, 2], uv, atol=1e-6)
    assert cam.get_aspect_ratio() == pytest.approx(320 / 240)
    assert cam.get_projection_mode() == "perspective" and cam.get_projection_type() == "pinhole"
    cam.set_projection_mode("perspective")
    with pytest.raises(InvalidInputError, match="perspective"):
        cam.set_projection_mode("orthographic")
    with pytest.raises(InvalidInputError, match="pinhole"):
        cam.set_projection_type("fisheyePolynomial")
    cam.set_focus_distance(2.0)
    cam.set_lens_aperture(1.8)
    cam.set_stereo_role("left")
    assert (cam.get_focus_distance(), cam.get_lens_aperture(), cam.get_stereo_role()) == (2.0, 1.8, "left")
    before = cam.get_rgba()
    np.testing.assert_array_equal(cam.get_rgba(), before)  # kept, not rendered: the same image
    cam.remove_distance_to_image_plane_from_frame()
    assert "distance_to_image_plane" in cam.get_current_frame()
    assert "pointcloud" in cam.supported_annotators and "bounding_box_2d_tight" not in cam.supported_annotators
    with pytest.raises(NotImplementedError, match="not computed here: the semantic_segmentation"):
        cam.add_bounding_box_2d_tight_to_frame()
    with pytest.raises(NotImplementedError, match="pinhole"):
        cam.set_fisheye_polynomial_properties(1920, 1080, 2.0, 0.0, 0.0, 3.0, [0.0, 0.0, 0.0, 0.0, 0.0])
