"""Depth images into the planner's occupancy map: what is seen, what is freed, the robot itself."""

from __future__ import annotations

import math

import coal
import numpy as np
import pytest

from manip import MotionGenerator, Pose
from manip import quaternion as quat
from manip.collision import OccupancyMap
from manip.errors import InvalidInputError
from manip.sim import Camera, DynamicCuboid, Franka, World


def look_at(eye, target) -> np.ndarray:
    """Quaternion (w, x, y, z) of a camera at `eye` looking at `target` in Isaac's world axes
    (+X forward, +Z up)."""
    f = np.asarray(target, float) - np.asarray(eye, float)
    f /= np.linalg.norm(f)
    left = np.cross([0.0, 0.0, 1.0], f)
    left /= np.linalg.norm(left)
    return quat.from_matrix(np.stack([f, left, np.cross(f, left)], axis=1))


def camera_at(path, eye, target, resolution=(320, 240), focal=1.8) -> Camera:
    cam = Camera(path, position=np.asarray(eye, float), orientation=look_at(eye, target), resolution=resolution)
    cam.set_focal_length(focal)
    return cam


def integrate(mg, cam, **kwargs):
    p, o = cam.get_world_pose()
    return mg.update_world_from_depth(cam.get_depth(), cam.get_intrinsics_matrix(), Pose(p, o), **kwargs)


@pytest.fixture
def mg():
    return MotionGenerator("franka")


def _box_scene(box_at=(0.6, 0.1, 0.1), second_camera=False):
    world = World()
    world.scene.add_default_ground_plane()
    box = world.scene.add(DynamicCuboid("/World/box", name="box", position=list(box_at), size=1.0,
                                        scale=[0.1, 0.12, 0.2], mass=1.0))
    cam = camera_at("/World/cam", [1.5, -0.8, 0.9], [0.5, 0.1, 0.1])
    other = camera_at("/World/cam_b", [1.5, 0.8, 0.9], [0.5, 0.0, 0.1]) if second_camera else None
    world.reset()
    return (world, box, cam, other) if second_camera else (world, box, cam)


def test_a_box_seen_gives_occupied_cells_on_its_visible_faces(mg):
    world, box, cam = _box_scene()
    m = integrate(mg, cam)
    assert isinstance(m, OccupancyMap) and "camera" in mg.world
    assert m.num_hulls > 0   # fill="points": cells are the hulls of their points (flat ones their boxes)
    # the faces the camera sees: +x (towards it) and -y; every point of them between the measured
    # points lies in the map, and every point of them within one point spacing of it (at the edges
    # the surface beyond the last measured point is held only where the next pixel sees far beyond)
    eye = cam.get_world_pose()[0]
    fx = cam.get_intrinsics_matrix()[0, 0]
    geometry = m.coal_geometry()
    c = np.array([0.6, 0.1, 0.1])
    h = np.array([0.05, 0.06, 0.1])
    s = np.linspace(-0.97, 0.97, 9)
    A, B = np.meshgrid(s, s)
    edge_points = 0
    for axis, sign in ((0, 1.0), (1, -1.0)):
        u, v = [k for k in range(3) if k != axis]
        P = np.zeros((A.size, 3))
        P[:, axis] = c[axis] + sign * h[axis]
        P[:, u] = c[u] + A.ravel() * h[u]
        P[:, v] = c[v] + B.ravel() * h[v]
        keep = P[:, 2] > 0.005   # the bottom edge touches the ground
        inner = (np.abs(A.ravel()) < 0.9) & (np.abs(B.ravel()) < 0.9)
        for x, interior in zip(P[keep], inner[keep]):
            if interior:
                assert m.contains_points(x[None]), f"face point {x} not in an occupied cell"
                continue
            to_eye = eye - x
            spacing = np.linalg.norm(to_eye) / fx / (abs(to_eye[axis]) / np.linalg.norm(to_eye))
            d, _ = geometry.distance(coal.Sphere(1e-6), coal.Transform3s(np.eye(3), x), coal.DistanceRequest(),
                                     coal.DistanceResult())
            assert d < spacing, f"face point {x} {d * 1e3:.1f} mm from the map (point spacing {spacing * 1e3:.1f} mm)"
            edge_points += 1
    assert edge_points > 20
    # and no cell farther than one cell from the box or the ground
    C = m.cell_centres()
    off_ground = C[C[:, 2] > 0.0]
    assert off_ground.size
    outside = np.abs(off_ground - c) - h
    assert np.all(outside.max(axis=1) < 0.02 + 1e-9)


def test_an_unchanged_view_integrated_again_adds_no_points_and_a_second_camera_adds_its_own(mg):
    world, box, cam, other = _box_scene(second_camera=True)
    first = integrate(mg, cam)
    n, hulls = first.points.shape[0], first.num_hulls
    again = integrate(mg, cam)   # the same image: its points are already there
    assert again.points.shape[0] == n and again.num_hulls == hulls
    both = integrate(mg, other)
    assert both.points.shape[0] > n
    kept = set(map(tuple, both.points)) & set(map(tuple, first.points))
    assert len(kept) > 0.95 * len(set(map(tuple, first.points)))   # the first view's points are kept


def test_moving_the_box_away_and_integrating_again_frees_its_cells(mg):
    world, box, cam = _box_scene()
    integrate(mg, cam)
    before = mg.world.get("camera")
    inside_old = lambda C: np.all(np.abs(C - [0.6, 0.1, 0.11]) < [0.07, 0.08, 0.11], axis=1)  # noqa: E731 (above the ground)
    assert inside_old(before.cell_centres()).sum() > 20
    box.set_world_pose(position=[0.3, -0.5, 0.1])
    for _ in range(5):
        world.step(render=False)
    after = integrate(mg, cam)
    assert after is mg.world.get("camera")
    assert inside_old(after.cell_centres()).sum() == 0
    # the box at its new place is in the map
    assert after.contains_points(np.array([[0.35, -0.5, 0.1]]))


def franka_in_view():
    """(world, franka, cameras): a Franka on the ground, reset, seen by two cameras from its front corners."""
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    cams = [camera_at(f"/World/cam{i}", eye, [0.3, 0.0, 0.4]) for i, eye in
            enumerate(([1.4, -0.9, 1.0], [1.4, 0.9, 1.0]))]
    world.reset()
    return world, franka, cams


def test_the_robot_in_view_adds_no_cell_on_itself(mg):
    world, franka, cams = franka_in_view()
    q = franka.get_joint_positions()
    for cam in cams:
        integrate(mg, cam, q=q)
    m = mg.world.get("camera")
    assert m.num_cells > 100          # the ground around the robot
    assert not mg.check_collision(q)
    assert mg.distance(q) > 0.05
    # without the self-filter, the robot's own surface becomes cells it collides with
    mg.remove_obstacle("camera")
    integrate(mg, cams[0])
    assert mg.check_collision(q)


def test_the_robot_moved_between_images_adds_no_cell_where_it_now_is(mg):
    """The self-filter is built once per configuration (both cameras at the same q share it):
    an image taken after the robot moved is filtered at the new q, not the last one."""
    world, franka, cams = franka_in_view()
    q0 = franka.get_joint_positions().copy()
    for cam in cams:
        integrate(mg, cam, q=q0)
    q1 = q0.copy()
    q1[0] += 0.8          # the arm turned to one side
    q1[3] += 0.5
    franka.set_joint_positions(q1)
    world.step(render=False)
    q1 = franka.get_joint_positions().copy()
    for cam in cams:
        integrate(mg, cam, q=q1)
    assert not mg.check_collision(q1[:7])
    assert mg.distance(q1[:7]) > 0.05


def test_two_threads_integrating_into_one_map_keep_both_observations(mg):
    """Updates of one map take turns: two threads each adding their own points keep all of them."""
    import threading

    n = 25
    clouds = [[np.array([[0.31 + 0.02 * i, y, 0.41]]) for i in range(n)] for y in (-0.29, 0.29)]

    def add(cloud):
        for points in cloud:
            mg.update_world_from_pointcloud(points, name="shared")

    threads = [threading.Thread(target=add, args=(c,)) for c in clouds]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    m = mg.world.get("shared")
    assert m.num_cells == 2 * n
    assert all(m.contains_points(c[0]) for cloud in clouds for c in cloud)


def test_closed_fingers_given_in_the_robot_state_add_no_cell(mg):
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    cams = [camera_at(f"/World/cam{i}", eye, [0.45, 0.0, 0.45]) for i, eye in
            enumerate(([0.9, -0.5, 0.9], [0.9, 0.5, 0.9]))]
    world.reset()
    state = franka.get_joint_positions()
    state[7:] = 0.02   # the fingers half closed, as on a 4 cm object (the planner's model holds them open)
    franka.set_joint_positions(state)
    for cam in cams:
        m = integrate(mg, cam, q=state)       # the full state: arm joints, then the fingers
    assert not mg.check_collision(state[:7])
    tips = mg.fk(state[:7], "panda_hand").position + mg.fk(state[:7], "panda_hand").rotation @ [0.0, 0.0, 0.1]
    near = lambda m: int((np.linalg.norm(m.cell_centres() - tips, axis=1) < 0.06).sum())  # noqa: E731
    assert near(m) == 0
    # given the arm alone, the fingers are taken where the planner's model has them: their
    # surface seen where they really are stays in the map
    mg.remove_obstacle("camera")
    for cam in cams:
        m = integrate(mg, cam, q=state[:7])
    assert near(m) > 0


def test_unknown_occupied_within_bounds(mg):
    world, box, cam = _box_scene()
    bounds = [[0.2, -0.4, 0.0], [0.9, 0.5, 0.5]]
    m = integrate(mg, cam, unknown="occupied", bounds=bounds)
    eye, c = np.array([1.5, -0.8, 0.9]), np.array([0.6, 0.1, 0.1])
    behind = (c + 0.13 * (c - eye) / np.linalg.norm(c - eye))[None]   # hidden behind the box from the camera
    seen_free = np.array([[0.8, -0.3, 0.3]])  # between the camera and the ground, in view
    outside = np.array([[0.0, 0.6, 0.3]])
    assert m.contains_points(behind)
    assert not m.contains_points(seen_free)
    assert not m.contains_points(outside)
    default = MotionGenerator("franka")
    assert not integrate(default, cam).contains_points(behind)


def test_a_point_cloud_with_an_origin_frees_what_it_sees_through(mg):
    world, box, cam = _box_scene()
    p, _ = cam.get_world_pose()
    pts = cam.get_pointcloud()
    m = mg.update_world_from_pointcloud(pts, origin=p)
    assert m.contains_points(np.array([[0.65, 0.1, 0.1]]))
    box.set_world_pose(position=[0.3, -0.5, 0.1])
    for _ in range(5):
        world.step(render=False)
    m = mg.update_world_from_pointcloud(cam.get_pointcloud(), origin=p)
    assert not m.contains_points(np.array([[0.65, 0.1, 0.15]]))
    # without an origin the cloud only adds cells
    m = mg.update_world_from_pointcloud(pts, name="no_rays")
    m = mg.update_world_from_pointcloud(cam.get_pointcloud(), name="no_rays")
    assert m.contains_points(np.array([[0.65, 0.1, 0.15]]))


def test_plans_on_the_map_avoid_the_box_and_are_certified(mg):
    world, box, cam, other = _box_scene(box_at=(0.5, 0.0, 0.1), second_camera=True)
    integrate(mg, cam)
    integrate(mg, other)
    q0 = mg.default_joint_positions
    truth = MotionGenerator("franka", {"cuboid": {"box": {"dims": [0.1, 0.12, 0.2], "pose": [0.5, 0, 0.1, 1, 0, 0, 0]}}})
    for goal in (Pose([0.5, 0.3, 0.15], [0, 1, 0, 0]), Pose([0.5, -0.3, 0.15], [0, 1, 0, 0])):
        r = mg.plan_pose(q0, goal)
        assert r.success, r.message
        assert mg.checker.certify_path(r.trajectory.positions).certified
        assert truth.checker.certify_path(r.trajectory.positions).certified


def test_bad_input_names_the_argument(mg):
    K = np.array([[300.0, 0, 159.5], [0, 300.0, 119.5], [0, 0, 1]])
    d = np.full((240, 320), 1.0, dtype=np.float32)
    pose = Pose([0.0, 0.0, 1.0], [1, 0, 0, 0])
    with pytest.raises(InvalidInputError, match="depth"):
        mg.update_world_from_depth(np.ones((240, 320, 3), dtype=np.float32), K, pose)
    with pytest.raises(InvalidInputError, match="depth"):
        mg.update_world_from_depth(np.ones((240, 320), dtype=np.int32), K, pose)
    with pytest.raises(InvalidInputError, match="depth"):
        mg.update_world_from_depth(-d, K, pose)
    bad = K.copy()
    bad[0, 0] = math.nan
    with pytest.raises(InvalidInputError, match="intrinsics"):
        mg.update_world_from_depth(d, bad, pose)
    with pytest.raises(InvalidInputError, match="camera_pose"):
        mg.update_world_from_depth(d, K, [0.0, 0.0, 1.0, 1, 0, 0, 0])
    with pytest.raises(InvalidInputError, match="resolution"):
        mg.update_world_from_depth(d, K, pose, resolution=-0.02)
    with pytest.raises(InvalidInputError, match="resolution must be at most 0.5 m"):
        mg.update_world_from_depth(d, K, pose, resolution=50.0)
    with pytest.raises(InvalidInputError, match="resolution must be at most 0.5 m"):
        mg.update_world_from_pointcloud(np.zeros((1, 3)), resolution=1.0)
    with pytest.raises(InvalidInputError, match="max_range"):
        mg.update_world_from_depth(d, K, pose, max_range=0.0)
    with pytest.raises(InvalidInputError, match="unknown"):
        mg.update_world_from_depth(d, K, pose, unknown="maybe")
    with pytest.raises(InvalidInputError, match="bounds"):
        mg.update_world_from_depth(d, K, pose, unknown="occupied")
    with pytest.raises(InvalidInputError, match="fill"):
        mg.update_world_from_depth(d, K, pose, fill="solid")
    with pytest.raises(InvalidInputError, match="points"):
        mg.update_world_from_pointcloud(np.zeros((10, 2)))
    with pytest.raises(InvalidInputError, match="q"):
        mg.update_world_from_depth(d, K, pose, q=np.zeros(3))
    mg.update_world_from_depth(d, K, pose)
    with pytest.raises(InvalidInputError, match="resolution"):
        mg.update_world_from_depth(d, K, pose, resolution=0.05)   # another resolution for the same map
    mg.add_obstacle(__import__("manip").Cuboid("wall", [0.1, 0.1, 0.1], [2.0, 2.0, 2.0]))
    with pytest.raises(InvalidInputError, match="name"):
        mg.update_world_from_depth(d, K, pose, name="wall")


def test_closing_fingers_add_no_cell_on_themselves(mg):
    """The planner's model holds the fingers open; the real ones, half closed (on an object),
    are still the robot's own: no cell on them (without the fingers' travel in the filter,
    this scene gives cells the model's fingers touch at 2 cm)."""
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    cams = [camera_at(f"/World/cam{i}", eye, [0.45, 0.0, 0.35]) for i, eye in
            enumerate(([1.2, -0.7, 0.8], [1.2, 0.7, 0.8], [0.8, 0.0, 1.2], [0.45, -1.0, 0.4]))]
    world.reset()
    q = franka.get_joint_positions().copy()
    q[7:] = 0.02                                 # each finger 2 cm in from open
    franka.set_joint_positions(q)
    world.step(render=False)
    assert np.allclose(franka.get_joint_positions()[7:], 0.02, atol=2e-3)
    for cam in cams:
        integrate(mg, cam, q=q, resolution=0.02)
    assert mg.world.get("camera").num_cells > 100
    assert not mg.check_collision(q)
    assert mg.distance(q) > 0.05


def _plane_under(mg, q, z: float, fill=None, **options):
    """Integrate a synthetic image of a horizontal surface at height z [m], 12 cm around the
    hand, seen by a camera 1 m above it looking straight down (inf elsewhere)."""
    hand = mg.fk(q, "panda_hand").position
    K = np.array([[300.0, 0.0, 99.5], [0.0, 300.0, 99.5], [0.0, 0.0, 1.0]])
    eye = np.array([hand[0], hand[1], z + 1.0])
    down = Pose(eye, [np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0])   # Isaac's +X forward turned to -Z
    u, v = np.meshgrid(np.arange(200), np.arange(200))
    # optical x = world -y, optical y = world -x for this camera: the pixel's point on the plane
    off = np.stack([-(v - K[1, 2]) / K[1, 1], -(u - K[0, 2]) / K[0, 0]], axis=-1) * 1.0
    depth = np.where(np.linalg.norm(off, axis=-1) < 0.12, 1.0, np.inf).astype(np.float32)
    kwargs = {} if fill is None else {"fill": fill}
    return mg.update_world_from_depth(depth, K, down, **kwargs, **options)


def test_by_default_a_start_5_mm_above_a_seen_surface_is_free(mg):
    """The default map holds a surface as it was measured (what it hides is unknown, not in
    the map): the hand 5 mm above a seen table is free, and a motion along it
    is certified; whole cells (`fill="cells"`) put it in collision."""
    q = mg.default_joint_positions
    z = 0.2
    for _ in range(3):   # raise the surface until it is 5 mm below the robot
        _plane_under(mg, q, z)
        z += mg.checker.distance_report(q).world_distance - 0.005
        mg.remove_obstacle("camera")
    _plane_under(mg, q, z)
    assert not mg.check_collision(q)
    assert mg.checker.distance_report(q).world_distance == pytest.approx(0.005, abs=5e-4)
    q2 = q.copy()
    q2[0] += 0.05
    assert mg.checker.certify_path(np.array([q, q2])).certified
    whole = MotionGenerator("franka")
    _plane_under(whole, q, z, fill="cells")
    assert (math.floor(z / 0.02) + 1) * 0.02 > z + 0.005   # the surface's cell reaches above the hand
    assert whole.check_collision(q)


def test_what_a_seen_surface_hides_is_unknown_not_occupied(mg):
    """A surface seen from above holds its measured points only: a point 5 mm under it, in
    the same cell, is not in the default map (the space a surface hides is unknown, free by
    default, like a board's underside no camera saw); whole cells hold it."""
    q = mg.default_joint_positions
    hand = mg.fk(q, "panda_hand").position
    z = (math.floor((hand[2] - 0.3) / 0.02) + 0.75) * 0.02   # 3/4 up its cell: 15 mm of the cell below it
    m = _plane_under(mg, q, z)
    on, under = np.array([[hand[0], hand[1], z]]), np.array([[hand[0], hand[1], z - 0.005]])
    assert m.contains_points(on)
    assert not m.contains_points(under)
    whole = _plane_under(MotionGenerator("franka"), q, z, fill="cells")
    assert whole.contains_points(under)


def test_with_unknown_occupied_what_a_seen_surface_hides_in_its_own_cell_is_an_obstacle(mg):
    """With unknown="occupied" only observed free space is free: the part of a surface's own
    cell behind the surface (hidden from the camera) is in the map, the part in front of it
    (which the rays crossed) is not. The bounds end at that cell's lower face, so no unknown
    cell behind it covers the hidden part (below the bounds, unknown space is free)."""
    q = mg.default_joint_positions
    hand = mg.fk(q, "panda_hand").position
    z = (math.floor((hand[2] - 0.3) / 0.02) + 0.75) * 0.02   # 3/4 up its cell
    bottom = math.floor(z / 0.02) * 0.02
    box = [[hand[0] - 0.2, hand[1] - 0.2, bottom], [hand[0] + 0.2, hand[1] + 0.2, z + 0.2]]
    m = _plane_under(mg, q, z, unknown="occupied", bounds=box)
    at = lambda dz: np.array([[hand[0], hand[1], z + dz]])   # noqa: E731
    assert m.contains_points(at(0.0))
    assert m.contains_points(at(-0.005))       # hidden, in the surface's cell
    assert not m.contains_points(at(0.003))    # in front of the surface, in its cell: seen free
    assert not m.contains_points(at(0.1))      # seen free
    assert not m.contains_points(at(-0.05))    # below the bounds: unknown = free there


def test_contains_points_takes_points_and_refuses_anything_else(mg):
    m = _plane_under(mg, mg.default_joint_positions, 0.3)
    on = m.points[0].copy()   # a measured point
    ro = np.array([on]); ro.setflags(write=False)   # a caller's read-only array (no second kernel compiled)
    assert m.contains_points(on) and m.contains_points(ro) and m.contains_points(on.tolist())
    for bad in (np.zeros(6), np.zeros((2, 2)), [[np.nan, 0.0, 0.0]], "abc", np.zeros((1, 1, 3))):
        with pytest.raises(InvalidInputError, match="contains_points"):
            m.contains_points(bad)
