"""WorldConfig and its shapes: construction, cuRobo's world format, MoveIt scenes, errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from manip.collision import Capsule, Cuboid, Cylinder, Mesh, Sphere, WorldConfig
from manip.errors import InvalidInputError, UnknownNameError
from manip.pose import Pose

CUROBO_WORLD = {
    "cuboid": {
        "table": {"dims": [1.0, 1.2, 0.04], "pose": [0.5, 0.0, -0.02, 1.0, 0.0, 0.0, 0.0]},
        "wall": {"dims": [0.1, 1.0, 0.6], "pose": [0.9, 0.0, 0.3, 0.7071068, 0.0, 0.0, 0.7071068]},
    },
    "sphere": {"ball": {"radius": 0.05, "position": [0.4, 0.3, 0.2]}},
    "cylinder": {"can": {"radius": 0.03, "height": 0.12, "pose": [0.5, -0.3, 0.06, 1, 0, 0, 0]}},
    "capsule": {
        "rod": {"radius": 0.02, "height": 0.3, "pose": [0.3, 0.0, 0.5, 1, 0, 0, 0]},
        "pipe": {"radius": 0.02, "base": [0.0, 0.0, 0.0], "tip": [0.2, 0.0, 0.0], "pose": [0.5, 0.5, 0.5, 1, 0, 0, 0]},
    },
}


def test_from_dict_reads_every_kind_with_curobo_conventions():
    w = WorldConfig.from_dict(CUROBO_WORLD)
    assert w.names == ["table", "wall", "ball", "can", "rod", "pipe"]
    table = w.get("table")
    assert isinstance(table, Cuboid)
    np.testing.assert_allclose(table.dims, [1.0, 1.2, 0.04])
    np.testing.assert_allclose(table.pose.position, [0.5, 0.0, -0.02])
    wall = w.get("wall")
    # cuRobo's pose is [x, y, z, qw, qx, qy, qz]: a 90 degree turn about z
    np.testing.assert_allclose(wall.pose.rotation @ [1, 0, 0], [0, 1, 0], atol=1e-6)
    ball = w.get("ball")
    assert isinstance(ball, Sphere) and ball.radius == 0.05
    np.testing.assert_allclose(ball.position, [0.4, 0.3, 0.2])
    can = w.get("can")
    assert isinstance(can, Cylinder) and (can.radius, can.height) == (0.03, 0.12)
    pipe = w.get("pipe")
    assert isinstance(pipe, Capsule)
    assert pipe.height == pytest.approx(0.2)
    # the capsule's axis (local z) runs from base to tip, centred between them
    np.testing.assert_allclose(pipe.pose.position, [0.6, 0.5, 0.5], atol=1e-12)
    np.testing.assert_allclose(pipe.pose.rotation @ [0, 0, 1], [1, 0, 0], atol=1e-9)


def test_to_dict_round_trips():
    w = WorldConfig.from_dict(CUROBO_WORLD)
    w2 = WorldConfig.from_dict(w.to_dict())
    assert w2.names == w.names
    for a, b in zip(w, w2):
        assert type(a) is type(b)
        assert a.pose.isclose(b.pose, 1e-12, 1e-9)
        assert a.to_dict() == b.to_dict()


def test_yaml_round_trip_and_relative_mesh_path(tmp_path: Path):
    stl = tmp_path / "tri.obj"
    stl.write_text("v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
    d = dict(CUROBO_WORLD)
    d["mesh"] = {"tet": {"file_path": "tri.obj", "pose": [0.2, 0, 0, 1, 0, 0, 0]}}
    import yaml

    (tmp_path / "world.yaml").write_text(yaml.safe_dump(d))
    w = WorldConfig.from_yaml(tmp_path / "world.yaml")
    tet = w.get("tet")
    assert isinstance(tet, Mesh)
    assert tet.vertices.shape[0] >= 4 and tet.faces.shape == (4, 3)
    out = tmp_path / "out.yaml"
    w.to_yaml(out)
    assert WorldConfig.from_yaml(out).names == w.names


def test_container_semantics():
    w = WorldConfig([Cuboid("a", [0.1, 0.1, 0.1], [0, 0, 1]), Sphere("b", 0.1, [1, 0, 0])])
    assert len(w) == 2 and "a" in w and [o.name for o in w] == ["a", "b"]
    with pytest.raises(InvalidInputError, match="already"):
        w.add(Sphere("a", 0.2))
    removed = w.remove("a")
    assert removed.name == "a" and w.names == ["b"]
    with pytest.raises(UnknownNameError, match="available: b"):
        w.get("a")
    with pytest.raises(UnknownNameError):
        w.remove("zzz")


@pytest.mark.parametrize(
    "bad, match",
    [
        ({"box": {}}, "unknown obstacle kind 'box'; valid: cuboid"),
        ({"cuboid": {"a": {"dims": [1, 1], "pose": [0, 0, 0, 1, 0, 0, 0]}}}, "3 positive"),
        ({"cuboid": {"a": {"dims": [1, -1, 1], "pose": [0, 0, 0, 1, 0, 0, 0]}}}, "3 positive"),
        ({"cuboid": {"a": {"dims": [1, float("nan"), 1]}}}, "3 positive"),
        ({"cuboid": {"a": {"dims": [1, 1, 1], "pose": [0, 0, float("nan"), 1, 0, 0, 0]}}}, "non-finite"),
        ({"cuboid": {"a": {"dims": [1, 1, 1], "pose": [0, 0, 0, 1, 0, 0]}}}, r"\[x, y, z, qw, qx, qy, qz\]"),
        ({"cuboid": {"a": {"dims": [1, 1, 1], "colour": "red"}}}, r"unknown key\(s\) \['colour'\]; valid"),
        ({"cuboid": {"a": {"pose": [0, 0, 0, 1, 0, 0, 0]}}}, r"missing key\(s\) \['dims'\]"),
        ({"sphere": {"s": {"radius": 0.0, "position": [0, 0, 0]}}}, "positive"),
        ({"cylinder": {"c": {"radius": 0.1, "height": -1}}}, "positive"),
        ({"capsule": {"c": {"radius": 0.1}}}, "height' or both 'base' and 'tip'"),
        ({"mesh": {"m": {"file_path": "/nonexistent/x.stl"}}}, "file_path not found"),
    ],
)
def test_bad_input_says_what_is_valid(bad, match):
    with pytest.raises(InvalidInputError, match=match):
        WorldConfig.from_dict(bad)


def test_shape_constructors_validate():
    with pytest.raises(InvalidInputError):
        Cuboid("", [1, 1, 1])
    with pytest.raises(InvalidInputError):
        Sphere("s", -0.1)
    with pytest.raises(InvalidInputError):
        Mesh("m", vertices=np.zeros((3, 3)), faces=np.array([[0, 1, 5]]))
    with pytest.raises(InvalidInputError, match="file_path"):
        Mesh("m")
    # a position alone gives the identity rotation; a Pose is kept
    s = Sphere("s", 0.1, [1, 2, 3])
    np.testing.assert_allclose(s.pose.quaternion, [1, 0, 0, 0])
    p = Pose([0, 0, 1], [0, 1, 0, 0])
    assert Cuboid("c", [1, 1, 1], p).pose is p
    moved = s.with_pose([0, 0, 0])
    np.testing.assert_allclose(moved.position, 0.0)
    np.testing.assert_allclose(s.position, [1, 2, 3])


def test_moveit_scene_uses_xyzw_and_height_radius():
    scene = {"world": {"collision_objects": [
        {"id": "can", "primitives": [{"type": "cylinder", "dimensions": [0.14, 0.03]}],
         "primitive_poses": [{"position": [0.5, 0, 0.3], "orientation": [0, 0, 0.7071068, 0.7071068]}]},
        {"id": "shelf", "primitives": [{"type": "box", "dimensions": [1.2, 1.0, 0.04]},
                                        {"type": "box", "dimensions": [1.2, 0.04, 0.5]}],
         "primitive_poses": [{"position": [0.6, 0, 0.2], "orientation": [0, 0, 0, 1]},
                             {"position": [0.6, 0.5, 0.45], "orientation": [0, 0, 0, 1]}]},
    ]}}
    w = WorldConfig.from_moveit_scene(scene)
    assert w.names == ["can", "shelf", "shelf_1"]
    can = w.get("can")
    assert (can.height, can.radius) == (0.14, 0.03)
    np.testing.assert_allclose(can.pose.quaternion, [0.7071068, 0, 0, 0.7071068], atol=1e-6)
    np.testing.assert_allclose(w.get("shelf_1").dims, [1.2, 0.04, 0.5])


def test_curobo_keyword_construction_as_its_tutorial_writes_it():
    """cuRobo's "Collision World Representation" page builds its world this way: each shape by
    keywords (a `color` for its viewer, a capsule by `base` / `tip`, a sphere by `position` or
    `pose`) and `WorldConfig(cuboid=[...], mesh=[...], ...)`; the same world as its dict."""
    link3 = Path(__file__).resolve().parents[2] / "robots" / "franka"
    mesh_file = next(link3.rglob("link3.stl"))
    pose = [0.0, 0.0, 0.0, 0.043, -0.471, 0.284, 0.834]
    pose = list(np.r_[pose[:3], np.array(pose[3:]) / np.linalg.norm(pose[3:])])
    cube = Cuboid(name="cube_1", pose=pose, dims=[0.2, 1.0, 0.2], color=[0.8, 0.0, 0.0, 1.0])
    mesh = Mesh(name="mesh_1", pose=[0.0, 2, 0.5] + pose[3:], file_path=str(mesh_file), scale=[0.5, 0.5, 0.5])
    capsule = Capsule(name="capsule", radius=0.2, base=[0, 0, 0], tip=[0, 0, 0.5], pose=[0.0, 5, 0.0] + pose[3:],
                      color=[0, 1.0, 0, 1.0])
    cylinder = Cylinder(name="cylinder_1", radius=0.01, height=0.1, pose=[0.0, 6, 0.0] + pose[3:], color=[0, 1.0, 0, 1.0])
    sphere = Sphere(name="sphere_1", radius=0.01, pose=[0.0, 7, 0.0] + pose[3:], color=[0, 1.0, 0, 1.0])
    ball = Sphere(name="ball", radius=0.05, position=[0.4, 0.3, 0.2])
    world = WorldConfig(mesh=[mesh], cuboid=[cube], capsule=[capsule], cylinder=[cylinder], sphere=[sphere, ball])
    assert sorted(world.names) == ["ball", "capsule", "cube_1", "cylinder_1", "mesh_1", "sphere_1"]
    same = WorldConfig.from_dict({
        "capsule": {"capsule": {"radius": 0.2, "base": [0, 0, 0], "tip": [0, 0, 0.5], "pose": [0.0, 5, 0.0] + pose[3:]}},
        "sphere": {"ball": {"radius": 0.05, "position": [0.4, 0.3, 0.2]}},
    })
    for name in ("capsule", "ball"):
        assert world.get(name).to_dict() == same.get(name).to_dict()
    np.testing.assert_allclose(world.get("ball").position, [0.4, 0.3, 0.2])
    # each list holds its own kind; a shape given twice, or a position and a pose, says so
    with pytest.raises(InvalidInputError, match="cuboid"):
        WorldConfig(cuboid=[ball])
    with pytest.raises(InvalidInputError, match="sphere_1"):
        WorldConfig([sphere], sphere=[sphere])
    with pytest.raises(InvalidInputError, match="position"):
        Sphere(name="s", radius=0.1, position=[0, 0, 0], pose=[0, 0, 0, 1, 0, 0, 0])
    with pytest.raises(InvalidInputError, match="base"):
        Capsule(name="c", radius=0.1, height=0.2, base=[0, 0, 0], tip=[0, 0, 1])
    with pytest.raises(InvalidInputError, match="height"):
        Capsule(name="c", radius=0.1)
    with pytest.raises(InvalidInputError, match="color"):
        Cuboid(name="c", dims=[1, 1, 1], color="red")
    # cuRobo's positional order is (name, pose, ...), manip's (name, sizes..., pose): the message
    # says so when a pose stands where a size is expected
    order = r"\(a pose\? manip's order is {}, cuRobo's is \(name, pose, \.\.\.\): pass them by keyword"
    with pytest.raises(InvalidInputError, match=order.format(r"Cuboid\(name, dims, pose\)")):
        Cuboid("c", [0.5, 0, 0.3, 1, 0, 0, 0], [0.1, 0.1, 0.1])
    with pytest.raises(InvalidInputError, match=order.format(r"Sphere\(name, radius, pose\)")):
        Sphere("s", [0.5, 0, 0.3], 0.1)
    with pytest.raises(InvalidInputError, match=order.format(r"Cylinder\(name, radius, height, pose\)")):
        Cylinder("c", [0.5, 0, 0.3, 1, 0, 0, 0], 0.1, 0.2)
    with pytest.raises(InvalidInputError) as plain:
        Sphere("s", -0.1)
    assert "cuRobo" not in str(plain.value)
