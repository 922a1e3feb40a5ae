"""Isaac's Camera `semantic_segmentation` / `instance_id_segmentation` annotators (NotImplementedError
before: "no semantic labels in manip"): labels set with `add_update_semantics` (or
`create_prim(semantic_label=...)`) on a prim and inherited below it, read from MuJoCo's
segmentation render, in Isaac's layout ((H, W) uint32 ids, "info"/"idToLabels")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.sim import (
    Camera,
    DynamicCuboid,
    Franka,
    World,
    add_update_semantics,
    create_prim,
    delete_prim,
    get_semantics,
    remove_all_semantics,
)

DOWN = quat.from_axis_angle(np.array([0.0, 1.0, 0.0]), math.pi / 2)     # the camera's +x turned to -z


def _scene(label_robot=True):
    world = World()
    world.scene.add_default_ground_plane()
    world.scene.add(Franka("/World/Franka", name="franka"))
    cube = world.scene.add(DynamicCuboid("/World/Cube", name="cube", position=[0.5, 0.1, 0.05], size=0.1))
    add_update_semantics(cube.prim, "cube")
    if label_robot:
        add_update_semantics("/World/Franka", "robot")
        add_update_semantics("/World/Franka/panda_hand", "hand")        # a link's own label wins
    cam = Camera("/World/camera", position=[0.4, 0.0, 1.5], orientation=DOWN, resolution=(96, 96))
    world.reset()
    cam.initialize()
    return world, cam, cube


def test_semantic_segmentation_labels_the_cube_pixels_where_the_cube_is():
    _, cam, _ = _scene()
    cam.add_semantic_segmentation_to_frame()
    frame = cam.get_current_frame()
    seg = frame["semantic_segmentation"]
    assert seg["data"].shape == (96, 96) and seg["data"].dtype == np.uint32
    names = {label["class"]: int(i) for i, label in seg["info"]["idToLabels"].items()}
    assert {"BACKGROUND", "UNLABELLED", "cube", "robot", "hand"} <= set(names)
    assert names["BACKGROUND"] == 0 and names["UNLABELLED"] == 1
    cube_px = seg["data"] == names["cube"]
    assert cube_px.sum() > 20
    depth = frame["distance_to_image_plane"]
    rows, cols = np.nonzero(cube_px)
    points = cam.get_world_points_from_image_coords(np.stack([cols, rows], axis=1), depth[rows, cols])
    lo, hi = np.array([0.45, 0.05, 0.0]) - 2e-3, np.array([0.55, 0.15, 0.1]) + 2e-3
    assert np.all((points >= lo) & (points <= hi))                     # every cube pixel sees the cube
    ground = seg["data"] == names["UNLABELLED"]                        # the unlabelled ground plane
    rows, cols = np.nonzero(ground)
    points = cam.get_world_points_from_image_coords(np.stack([cols, rows], axis=1), depth[rows, cols])
    assert ground.sum() > 1000 and np.allclose(points[:, 2], 0.0, atol=2e-3)
    assert (seg["data"] == names["robot"]).sum() > 0 and (seg["data"] == names["hand"]).sum() > 0


def test_instance_ids_name_the_prims_and_background_is_zero():
    _, cam, _ = _scene(label_robot=False)
    cam.set_world_pose(orientation=quat.from_axis_angle(np.array([0.0, 1.0, 0.0]), math.radians(20)))  # sky above
    cam.add_instance_id_segmentation_to_frame()
    cam.add_semantic_segmentation_to_frame({"colorize": False, "semanticTypes": ["class"]})
    frame = cam.get_current_frame()
    inst, sem = frame["instance_id_segmentation"], frame["semantic_segmentation"]
    assert (inst["data"] == 0).sum() > 0 and np.array_equal(inst["data"] == 0, sem["data"] == 0)
    paths = inst["info"]["idToLabels"]
    assert "/World/defaultGroundPlane" in paths.values()
    assert all(p in ("BACKGROUND", "UNLABELLED") or p.startswith("/World/") for p in paths.values())


def test_labels_from_create_prim_go_with_the_prim():
    World()
    create_prim("/World/Box", "Cube", position=[0.0, 0.0, 0.5], semantic_label="box")
    assert get_semantics("/World/Box") == {"Semantics_class": ("class", "box")}
    add_update_semantics("/World/Box", "red", type_label="color")
    remove_all_semantics("/World/Box")
    assert get_semantics("/World/Box") == {}
    add_update_semantics("/World/Box", "box")
    delete_prim("/World/Box")
    create_prim("/World/Box", "Cube", position=[0.0, 0.0, 0.5])         # a new prim there: no label
    assert get_semantics("/World/Box") == {}


@pytest.mark.parametrize("call, match", [
    (lambda cam: cam.add_semantic_segmentation_to_frame({"colorize": True}), "colorize=True is not available"),
    (lambda cam: cam.add_semantic_segmentation_to_frame({"semanticTypes": "class"}), "semanticTypes must be"),
    (lambda cam: cam.add_instance_id_segmentation_to_frame({"colour": False}), "unknown keys"),
    (lambda cam: add_update_semantics("/World/Nothing", "x"), "prim must be a prim path of the stage"),
    (lambda cam: add_update_semantics("/World/Cube", ""), "semantic_label must be a non-empty string"),
])
def test_bad_segmentation_input_says_what_is_valid(call, match):
    _, cam, _ = _scene(label_robot=False)
    with pytest.raises(InvalidInputError, match=match):
        call(cam)
