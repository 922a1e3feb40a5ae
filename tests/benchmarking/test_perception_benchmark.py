"""benchmarks/perception.py: the true surfaces it samples, what it counts as seen, one run."""

from __future__ import annotations


import numpy as np
import pytest
from robot_constants import REPO_ROOT, load_script

from manip import Pose
from manip import quaternion as quat


@pytest.fixture(scope="module")
def bench():
    return load_script(REPO_ROOT / "benchmarks" / "perception.py", "perception_benchmark")


BOX = {"dims": [0.1, 0.2, 0.3], "pose": [0.6, 0.1, 0.15, *quat.from_axis_angle([0, 0, 1], 0.4)]}


def test_surface_points_lie_on_the_surfaces_a_spacing_apart(bench):
    P = bench.surface_points({"cuboid": {"box": BOX}, "cylinder": {"can": {"radius": 0.04, "height": 0.1,
                                                                          "pose": [0.3, -0.2, 0.05, 1, 0, 0, 0]}}})
    R = quat.to_matrix(np.array(BOX["pose"][3:]))
    local = (P - BOX["pose"][:3]) @ R
    on_box = np.all(np.abs(local) <= np.array(BOX["dims"]) / 2 + 1e-9, axis=1)
    assert np.allclose(np.max(np.abs(local[on_box]) / (np.array(BOX["dims"]) / 2), axis=1), 1.0)
    can = P[~on_box] - [0.3, -0.2, 0.05]
    r = np.linalg.norm(can[:, :2], axis=1)
    assert np.all((np.isclose(r, 0.04) & (np.abs(can[:, 2]) <= 0.05 + 1e-9)) | np.isclose(np.abs(can[:, 2]), 0.05))
    # every point of the box's faces is within a spacing of a sample
    from scipy.spatial import cKDTree
    rng = np.random.default_rng(0)
    probe = rng.uniform(-1, 1, (500, 3)) * np.array(BOX["dims"]) / 2
    probe[np.arange(500), rng.integers(0, 3, 500)] = 0.0
    face = rng.integers(0, 3, 500)
    probe[np.arange(500), face] = np.sign(rng.uniform(-1, 1, 500)) * np.array(BOX["dims"])[face] / 2
    assert cKDTree(P[on_box]).query(probe @ R.T + BOX["pose"][:3])[0].max() <= bench.SPACING


def test_a_camera_sees_the_faces_towards_it_and_not_the_far_ones(bench, fresh_world):
    from manip.sim import Camera, FixedCuboid, World

    world = World()
    world.scene.add(FixedCuboid("/World/box", name="box", position=np.array(BOX["pose"][:3]), size=1.0,
                                scale=np.array(BOX["dims"]), orientation=np.array(BOX["pose"][3:])))
    look_at = bench.load_example("perception_rig").look_at
    eye = np.array([1.6, 0.1, 0.15])   # in front of the box, at its height
    cam = Camera("/World/cam", position=eye, orientation=look_at(eye, BOX["pose"][:3]), resolution=(320, 240))
    world.reset()
    p, o = cam.get_world_pose()
    views = [(cam.get_depth(), cam.get_intrinsics_matrix(), Pose(p, o))]
    R = quat.to_matrix(np.array(BOX["pose"][3:]))
    s = np.linspace(-0.8, 0.8, 9)
    A, B = np.meshgrid(s, s)
    h = np.array(BOX["dims"]) / 2

    def face(sign):   # interior points of the +x / -x face (local x towards / away from the camera)
        local = np.stack([np.full(A.size, sign * h[0]), A.ravel() * h[1], B.ravel() * h[2]], axis=1)
        return local @ R.T + BOX["pose"][:3]

    assert bench.visible(face(+1.0), views).all()
    assert not bench.visible(face(-1.0), views).any()


def test_one_problem_with_both_fills(bench, capsys, fresh_world):
    assert bench.main(["--per-kind", "1", "--kinds", "table"]) == 0
    out = capsys.readouterr().out
    for fill in ("cells", "points"):
        assert f'`fill="{fill}"`' in out
    assert "| map plans colliding, of those whose reached faces the cameras saw |" in out
