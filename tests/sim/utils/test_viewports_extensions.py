"""Isaac's `set_camera_view` (viewports) and `enable_extension` (extensions): standalone scripts
call both after creating the World; `from manip.sim import ...` raised ImportError on them."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, World, disable_extension, enable_extension, set_camera_view


def test_set_camera_view_points_the_worlds_view_and_its_recording_camera():
    world = World()
    world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.5], size=0.1))
    world.reset()
    set_camera_view(eye=np.array([2.5, 2.5, 2.0]), target=np.array([0.0, 0.0, 0.5]),
                    camera_prim_path="/OmniverseKit_Persp")
    view = world.get_camera_view()
    np.testing.assert_allclose(view.lookat, [0.0, 0.0, 0.5])
    assert view.distance == pytest.approx(np.linalg.norm([2.5, 2.5, 1.5]))
    assert view.azimuth == pytest.approx(-135.0) and view.elevation < 0  # looking along -x, -y, down
    with pytest.raises(InvalidInputError, match="eye"):
        set_camera_view(eye=[1.0, 2.0], target=[0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="set_world_pose"):
        set_camera_view([1, 1, 1], [0, 0, 0], camera_prim_path="/World/camera")


def test_set_camera_view_before_a_world_warns_and_does_nothing(caplog):
    with caplog.at_level(logging.WARNING):
        set_camera_view([1, 1, 1], [0, 0, 0])
    assert "no World" in caplog.text


def test_enable_extension_true_for_what_manip_mirrors_false_for_the_rest(caplog):
    assert enable_extension("omni.isaac.examples") and enable_extension("isaacsim.robot.manipulators.examples")
    assert enable_extension("isaacsim.core.api")
    with caplog.at_level(logging.WARNING):
        assert enable_extension("isaacsim.ros2.bridge") is False
    assert "isaacsim.ros2.bridge" in caplog.text
    assert disable_extension("omni.isaac.core")
    with pytest.raises(InvalidInputError):
        enable_extension("")
