"""`manip.sim.CameraView`: the World's free camera (viewer, recordings), and Isaac's name it shares."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import CameraView


def test_set_camera_view_looks_from_eye_at_target(fresh_world):
    world = fresh_world()
    world.set_camera_view(eye=[1.0, 1.0, 1.2], target=[0.0, 0.0, 0.2])
    view = world.get_camera_view()
    np.testing.assert_allclose(view.lookat, [0.0, 0.0, 0.2])
    assert view.distance == pytest.approx(np.sqrt(3.0))
    assert view.azimuth == pytest.approx(-135.0)                       # looking towards -x, -y
    assert view.elevation == pytest.approx(-np.degrees(np.arcsin(1 / np.sqrt(3))))   # looking down


def test_bad_views_and_isaacs_batched_camera_view_are_refused():
    with pytest.raises(InvalidInputError, match="lookat"):
        CameraView((0.0, 0.0))
    with pytest.raises(InvalidInputError, match="distance"):
        CameraView(distance=0.0)
    with pytest.raises(InvalidInputError, match="elevation"):
        CameraView(elevation=float("nan"))
    # omni.isaac.sensor.CameraView(prim_paths_expr=...) with only its import changed: a clear refusal
    with pytest.raises(NotImplementedError, match="batched view of camera prims"):
        CameraView("/World/Camera_*")
    with pytest.raises(NotImplementedError, match="manip.sim.Camera per camera prim"):
        CameraView(prim_paths_expr="/World/Camera_*", camera_resolution=(256, 256))
