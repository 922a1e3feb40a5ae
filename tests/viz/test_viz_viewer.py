"""`manip.viz.Viewer`, headless: what the viser scene holds, read through the server's API."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("viser", reason="the viewer needs the viz extra: pip install 'manip-robotics[viz]'")

from manip import MotionGenerator, Pose  # noqa: E402
from manip.collision import Capsule, Cuboid, Cylinder, Mesh, Sphere, WorldConfig  # noqa: E402
from manip.errors import InvalidInputError  # noqa: E402
from manip.viz import Viewer  # noqa: E402
from manip.viz.obstacles import ATTACHED_COLOR  # noqa: E402

TETRAHEDRON = dict(vertices=[[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]],
                   faces=[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def every_obstacle_type() -> WorldConfig:
    return WorldConfig([
        Cuboid("table", [0.8, 1.2, 0.04], [0.55, 0.0, -0.03, 1, 0, 0, 0]),
        Sphere("ball", 0.05, [0.45, 0.35, 0.55]),
        Cylinder("can", 0.03, 0.12, [0.6, -0.35, 0.06, 1, 0, 0, 0]),
        Capsule("bar", 0.02, 0.3, [-0.3, 0.4, 0.3, 1, 0, 0, 0]),
        Mesh("tet", pose=[-0.4, -0.4, 0.5, 1, 0, 0, 0], **TETRAHEDRON),
    ])


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka", every_obstacle_type(), seed=0)


@pytest.fixture
def view(mg, port):
    v = Viewer(mg, port=port, verbose=False)
    yield v
    v.close()


def node(v: Viewer, name: str):
    h = v.server.scene.get_handle_by_name(name)
    assert h is not None, f"{name} not in the scene; the viewer drew {v.node_names()}"
    return h


def test_scene_holds_the_robot_meshes_at_the_configuration(view, mg):
    robot_nodes = [n for n in view.node_names() if n.startswith("/robot/")]
    assert len(robot_nodes) == len(view.robot._geom.geometryObjects) == 11  # Panda: link0-7, hand, 2 fingers
    q = mg.default_joint_positions + np.array([0.4, -0.2, 0.1, 0.3, 0.0, -0.2, 0.5])
    view.set_configuration(q)
    hand = node(view, "/robot/panda_hand_0")
    expected = mg.fk(q, "panda_hand")
    np.testing.assert_allclose(hand.position, expected.position, atol=1e-6)
    assert abs(abs(float(np.dot(hand.wxyz, expected.quaternion))) - 1.0) < 1e-6
    assert type(hand).__name__ == "GlbHandle"  # the URDF's visual mesh, sent as GLB


def test_scene_holds_every_obstacle_type(view, mg):
    for ob in mg.world:
        h = node(view, f"/world/{ob.name}")
        np.testing.assert_allclose(h.position, ob.pose.position)
    assert type(node(view, "/world/table")).__name__ == "BoxHandle"
    np.testing.assert_allclose(node(view, "/world/table").dimensions, [0.8, 1.2, 0.04])
    assert node(view, "/world/ball").radius == pytest.approx(0.05)
    can = node(view, "/world/can")
    assert (can.radius, can.height) == (pytest.approx(0.03), pytest.approx(0.12))
    bar = np.asarray(node(view, "/world/bar").vertices)
    assert np.ptp(bar[:, 2]) == pytest.approx(0.3 + 2 * 0.02, abs=1e-6)  # segment + two radii along z
    assert len(node(view, "/world/tet").faces) == 4
    # world edits are drawn on update_world
    mg.remove_obstacle("ball")
    try:
        view.update_world()
        assert view.server.scene.get_handle_by_name("/world/ball") is None
    finally:
        mg.add_obstacle(Sphere("ball", 0.05, [0.45, 0.35, 0.55]))


def test_attached_object_follows_the_hand_in_its_colour(port):
    mg = MotionGenerator("franka", seed=0)
    q = mg.default_joint_positions
    box = Cuboid("parcel", [0.04, 0.04, 0.04], mg.fk(q, "panda_hand_tcp"))
    mg.attach_object(box, q=q)
    v = Viewer(mg, port=port, verbose=False, gizmo=False)
    try:
        h = node(v, "/attached/parcel")
        assert tuple(h.color) == ATTACHED_COLOR
        q2 = q + np.array([0.5, 0.0, 0.0, 0.2, 0.0, 0.0, 0.0])
        v.set_configuration(q2)
        np.testing.assert_allclose(h.position, mg.fk(q2, "panda_hand_tcp").position, atol=1e-6)
    finally:
        v.close()


def test_show_plan_draws_the_tool_path_and_plays_with_the_slider(view, mg):
    start = mg.default_joint_positions
    goal = start + np.array([0.6, 0.2, 0.0, 0.3, 0.0, 0.0, 0.0])
    result = mg.plan_joints(start, goal)
    assert result.success, result.message
    playback = view.show_plan(result, play=False)
    traj = result.trajectory
    path = np.asarray(node(view, "/plan/tool_path").points)  # (segments, 2, 3)
    np.testing.assert_allclose(path[0, 0], mg.fk(start, "panda_hand_tcp").position, atol=1e-6)
    np.testing.assert_allclose(path[-1, 1], mg.fk(traj.goal, "panda_hand_tcp").position, atol=1e-6)
    frames = node(view, "/plan/frames")
    assert len(frames.batched_positions) == 8
    assert playback.time_slider.max == pytest.approx(traj.duration)
    t = 0.4 * traj.duration
    playback.time_slider.value = t  # what the user's drag does
    q_t = traj.at_time(t)[0]
    np.testing.assert_allclose(view.configuration, q_t, atol=1e-9)
    np.testing.assert_allclose(node(view, "/robot/panda_hand_0").position, mg.fk(q_t, "panda_hand").position,
                               atol=1e-6)
    assert "SUCCESS" in view.status.content


def test_failed_plan_shows_its_status_and_no_motion(view, mg):
    inside_the_table = Pose([0.55, 0.0, -0.03], [0.0, 1.0, 0.0, 0.0])
    result = view.plan_to(inside_the_table)  # what releasing the gizmo there does
    assert not result.success
    assert result.status.name in view.status.content
    assert view.playback is None
    assert view.server.scene.get_handle_by_name("/plan/tool_path") is None


def test_gizmo_release_plans_to_the_target(view, mg):
    assert view.gizmo is not None and node(view, "/target") is view.gizmo.handle
    target = mg.fk(view.configuration) @ Pose([0.05, -0.05, 0.05])
    view.gizmo.move_to(target)
    result = view.plan_to(view.gizmo.pose)
    assert result.success, result.message
    np.testing.assert_allclose(mg.fk(result.trajectory.goal).position, target.position, atol=2e-3)
    assert view.playback is not None and node(view, "/plan/tool_path") is not None


def test_collision_spheres_on_demand(view, mg):
    assert view.server.scene.get_handle_by_name("/collision_spheres") is None
    view.show_spheres(True)
    centres, radii, _ = mg.checker.spheres(view.configuration)
    h = node(view, "/collision_spheres")
    np.testing.assert_allclose(h.batched_positions, centres, atol=1e-6)
    np.testing.assert_allclose(h.batched_scales, radii, atol=1e-6)
    assert view.spheres_checkbox.value
    view.spheres_checkbox.value = False  # the GUI checkbox hides them
    assert view.server.scene.get_handle_by_name("/collision_spheres") is None


def test_bad_input_is_refused(view):
    with pytest.raises(InvalidInputError, match="MotionGenerator"):
        Viewer("franka")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="PlanResult or a Trajectory"):
        view.show_plan(np.zeros((10, 7)))  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError):
        view.set_configuration(np.zeros(6))


def test_an_occupancy_map_is_drawn_as_its_cells(port):
    from manip.collision import OccupancyMap
    from manip.viz.obstacles import MAP_COLOR

    cells = np.array([[20, 0, 5], [21, 0, 5], [20, 1, 5], [30, -5, 10]])
    mg = MotionGenerator("franka", WorldConfig([OccupancyMap.from_cells("camera", 0.02, cells)]))
    v = Viewer(mg, port=port, verbose=False)
    try:
        h = node(v, "/world/camera")
        V = np.asarray(h.vertices)
        assert tuple(np.asarray(h.color).ravel()[:3]) == MAP_COLOR
        np.testing.assert_allclose(V.min(axis=0), [0.40, -0.10, 0.10], atol=1e-9)   # the cells' boxes, no more
        np.testing.assert_allclose(V.max(axis=0), [0.62, 0.04, 0.22], atol=1e-9)
    finally:
        v.close()


def test_a_map_of_measured_points_is_drawn_as_the_hulls_the_checks_use(port):
    from manip.collision import OccupancyMap

    P = np.array([[0.40 + 0.002 * i, 0.002 * j, 0.21 + 0.001 * i] for i in range(10) for j in range(10)])   # a slope
    cells, of_point = np.unique(np.floor(P / 0.02).astype(np.int64), axis=0, return_inverse=True)
    order = np.argsort(of_point.ravel(), kind="stable")
    start = np.concatenate([[0], np.cumsum(np.bincount(of_point.ravel(), minlength=len(cells)))])
    m = OccupancyMap.from_cells("camera", 0.02, cells, None, (start, P[order]))
    assert m.num_hulls == 1
    v = Viewer(MotionGenerator("franka", WorldConfig([m])), port=port, verbose=False)
    try:
        h = node(v, "/world/camera")
        V, F = m.solids_mesh()
        np.testing.assert_allclose(np.asarray(h.vertices), V, atol=1e-6)   # viser keeps float32
        np.testing.assert_array_equal(np.asarray(h.faces), F)
        drawn = np.asarray(h.vertices)
        low_end = drawn[drawn[:, 0] < 0.401]   # where the slope starts: its hull is 1 cm lower than its box's top
        assert low_end.size and low_end[:, 2].max() < 0.2105 and drawn[:, 2].max() > 0.2185
    finally:
        v.close()
