"""manip.control.ReactiveController against closed-form cases, without the simulator."""

from __future__ import annotations

import mink
import mujoco
import numpy as np
import pytest

from manip.collision import Capsule, Cuboid, Cylinder, Mesh, Sphere, WorldConfig
from manip.control import ReactiveController, StepStatus, TaskWeights, UnknownFrameError
from manip.control.collision import CollisionLimit
from manip.errors import InvalidInputError, UnknownNameError
from manip.kinematics import Kinematics
from manip.pose import Pose
from manip.robot_config import load_robot_config

DT = 1.0 / 60.0
HAND_DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # (w, x, y, z): the TCP's orientation at the ready pose


@pytest.fixture(scope="module")
def ctrl():
    return ReactiveController("franka")


def run(c: ReactiveController, q, target, steps: int, check=None):
    results = []
    for _ in range(steps):
        r = c.step(q, target, DT)
        if check is not None:
            check(q, r)
        q = r.q
        results.append(r)
    return q, results


# ---------------------------------------------------------------------------- convergence
def test_static_reachable_target_converges_and_matches_pinocchio(ctrl):
    ctrl.reset()
    q0 = ctrl.rest_configuration
    start = ctrl.forward_kinematics(q0)
    goal = Pose(start.position + np.array([0.15, -0.2, -0.1]), HAND_DOWN)
    q, results = run(ctrl, q0, goal, 240)
    final = ctrl.forward_kinematics(q)
    assert np.linalg.norm(final.position - goal.position) < 1e-3
    assert results[-1].status is StepStatus.SOLVED
    assert np.max(np.abs(results[-1].velocities)) < 1e-3  # settled
    # The same configuration through the planner's kinematics (Pinocchio, URDF) lands there too.
    kin = Kinematics(load_robot_config("franka"))
    T = kin.fk(q, "panda_hand_tcp")
    assert np.linalg.norm(T.position - goal.position) < 2e-3
    assert abs(abs(float(np.dot(T.quaternion, goal.quaternion))) - 1.0) < 1e-4


def test_without_posture_the_frame_error_vanishes():
    c = ReactiveController("franka", weights=TaskWeights(posture=0.0))
    q0 = c.rest_configuration
    goal = Pose(c.forward_kinematics(q0).position + np.array([0.05, 0.05, 0.05]), HAND_DOWN)
    q, _ = run(c, q0, goal, 200)
    assert np.linalg.norm(c.forward_kinematics(q).position - goal.position) < 1e-5


def test_position_only_target_leaves_orientation_free(ctrl):
    ctrl.reset()
    q0 = ctrl.rest_configuration
    p = ctrl.forward_kinematics(q0).position + np.array([0.1, 0.1, 0.0])
    q, results = run(ctrl, q0, p, 200)
    assert np.linalg.norm(ctrl.forward_kinematics(q).position - p) < 1e-3
    assert results[-1].orientation_error == 0.0


def test_objective_is_minks_frame_posture_and_damping_tasks(ctrl):
    """The closed-form posture/damping terms give mink's build_ik objective."""
    q = ctrl.rest_configuration + 0.1
    ctrl.reset()
    ctrl.step(q, Pose([0.5, 0.1, 0.4], HAND_DOWN), DT)  # sets the frame target
    tasks, conf = ctrl._tasks, ctrl._conf
    H, c = tasks.objective(conf, 1e-9)
    w = ctrl.weights
    posture = mink.PostureTask(ctrl.model, cost=w.posture)
    posture.set_target(tasks.rest)
    damping = mink.DampingTask(ctrl.model, cost=w.damping)
    problem = mink.build_ik(conf, [tasks.frame, posture, damping], DT, damping=1e-9, limits=[])
    np.testing.assert_allclose(H, problem.P, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(c, problem.q, rtol=1e-9, atol=1e-12)


def test_target_jumps_are_approached_at_max_speed():
    c = ReactiveController("franka", max_speed=0.5)
    q0 = c.rest_configuration
    p0 = c.forward_kinematics(q0).position
    goal = p0 + np.array([0.0, 0.3, 0.0])
    q, _ = run(c, q0, goal, 6)
    moved = np.linalg.norm(c.forward_kinematics(q).position - p0)
    assert moved <= 0.5 * 6 * DT + 1e-3


# ---------------------------------------------------------------------------- limits
def test_joint_limits_hold_at_every_step():
    c = ReactiveController("franka")
    lo, hi, vmax = c.lower_limits, c.upper_limits, c.velocity_limits
    rng = np.random.default_rng(3)
    q = c.rest_configuration
    closest = np.inf

    def check(q_in, r):
        nonlocal closest
        assert np.all(r.q >= lo - 1e-12) and np.all(r.q <= hi + 1e-12)
        assert np.all(np.abs(r.velocities) <= vmax + 1e-9)
        np.testing.assert_allclose(r.q, q_in + r.velocities * DT, atol=1e-12)
        closest = min(closest, float(np.min(np.minimum(r.q - lo, hi - r.q))))

    # Unreachable targets far out and behind, and random jumps: joints run into their limits.
    for goal in ([1.5, 0.0, 0.3], [-0.6, -0.4, 0.2], [0.0, 0.0, 1.4]):
        q, _ = run(c, q, goal, 120, check)
    for _ in range(10):
        quaternion = rng.normal(size=4)
        goal = Pose(rng.uniform([-0.8, -0.8, 0.0], [0.8, 0.8, 1.0]), quaternion / np.linalg.norm(quaternion))
        q, _ = run(c, q, goal, 40, check)
    assert closest < 1e-4  # the test did drive a joint to its limit


def test_acceleration_limits_hold_in_free_space():
    c = ReactiveController("franka", max_speed=2.0)
    amax = c.acceleration_limits
    q = c.rest_configuration
    p = c.forward_kinematics(q).position
    v_prev = np.zeros(7)
    for goal in (p + [0.2, 0.2, -0.1], p + [-0.1, -0.3, 0.1]):
        for _ in range(90):
            r = c.step(q, goal, DT)
            assert np.all(np.abs(r.velocities - v_prev) <= amax * DT + 1e-9)
            q, v_prev = r.q, r.velocities


def test_a_configuration_outside_the_limits_is_brought_back():
    c = ReactiveController("franka", acceleration_scale=None)
    q = c.rest_configuration
    q[3] = c.upper_limits[3] + 0.01  # a simulated arm overshooting joint 4
    r = c.step(q, c.forward_kinematics(c.rest_configuration), DT)
    assert r.solved and r.q[3] < q[3]
    assert abs(r.velocities[3]) <= c.velocity_limits[3] + 1e-9


# ---------------------------------------------------------------------------- obstacles
def wall_world() -> WorldConfig:
    # A wall in front of the arm, between the TCP (x ~ 0.31 at the ready pose) and x = 0.6.
    return WorldConfig([Cuboid("wall", [0.04, 0.8, 0.8], [0.48, 0.0, 0.4])])


def test_obstacle_between_arm_and_target_is_never_penetrated_and_the_arm_recovers():
    margin = 0.01
    c = ReactiveController("franka", wall_world(), safety_margin=margin)
    q0 = c.rest_configuration
    start = c.forward_kinematics(q0)
    behind = Pose([0.65, 0.0, start.position[2]], HAND_DOWN)
    clearances = []
    q, results = run(c, q0, behind, 300, lambda q_in, r: clearances.append(c.clearance(r.q)[0]))
    assert min(clearances) > 0.5 * margin  # never closer than half the margin, never penetrating
    # It stopped at the closest safe configuration: at the margin, at rest, target not reached.
    assert abs(clearances[-1] - margin) < 3e-3
    assert np.max(np.abs(results[-1].velocities)) < 1e-2
    assert results[-1].position_error > 0.1
    # The target comes back in front of the wall: followed again.
    front = Pose(start.position + [0.05, 0.1, 0.0], HAND_DOWN)
    q, results = run(c, q, front, 200, lambda q_in, r: clearances.append(c.clearance(r.q)[0]))
    assert np.linalg.norm(c.forward_kinematics(q).position - front.position) < 2e-3
    assert min(clearances) > 0.5 * margin


def test_moving_obstacle_pushes_nothing_through():
    """An obstacle moved towards the arm between steps: the arm cannot get closer (it is not
    pushed away either: the controller keeps distances, it does not dodge)."""
    c = ReactiveController("franka", WorldConfig([Sphere("ball", 0.05, [0.3, 0.3, 0.45])]), safety_margin=0.01)
    q = c.rest_configuration
    goal = c.forward_kinematics(q)
    before = c.clearance(q)[0]
    r = c.step(q, goal, DT)
    assert c.clearance(r.q)[0] >= min(before, 0.01) - 1e-4


@pytest.mark.parametrize("shape", [
    Cuboid("o", [0.1, 0.1, 0.1], [0.45, 0.0, 0.45]),
    Sphere("o", 0.05, [0.45, 0.0, 0.45]),
    Cylinder("o", 0.05, 0.2, [0.45, 0.0, 0.45]),
    Capsule("o", 0.05, 0.1, [0.45, 0.0, 0.45]),
])
def test_every_shape_is_avoided(shape):
    c = ReactiveController("franka", WorldConfig([shape]), safety_margin=0.01)
    q = c.rest_configuration
    p = c.forward_kinematics(q).position
    target = Pose([0.6, 0.0, p[2] - 0.05], HAND_DOWN)
    q, results = run(c, q, target, 150)
    d = c.clearance(q)[0]
    assert 0.005 < d < 0.03  # stopped near the margin
    assert all(r.obstacle_clearance > 0.005 for r in results if np.isfinite(r.obstacle_clearance))


def test_mesh_obstacle_is_its_hull_in_its_own_frame():
    """A cube given as a mesh, off-centre in its frame, gives the clearance of the same Cuboid."""
    V = np.array([[x, y, z] for x in (0, 0.1) for y in (0, 0.1) for z in (0, 0.1)], dtype=float)
    F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],
                  [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    mesh = Mesh("m", pose=[0.35, -0.05, 0.25], vertices=V, faces=F)
    box = Cuboid("m", [0.1, 0.1, 0.1], [0.4, 0.0, 0.3])
    q = ReactiveController("franka").rest_configuration
    d_mesh = ReactiveController("franka", WorldConfig([mesh])).clearance(q)[0]
    d_box = ReactiveController("franka", WorldConfig([box])).clearance(q)[0]
    assert d_mesh == pytest.approx(d_box, abs=1e-6)
    assert 0.0 < d_box < 0.2


def test_broadphase_keeps_every_pair_within_the_detection_distance():
    c = ReactiveController("franka", WorldConfig([Cuboid("box", [0.2, 0.2, 0.2], [0.45, 0.1, 0.3]),
                                                  Sphere("ball", 0.08, [0.2, -0.3, 0.6])]))
    lim: CollisionLimit = c._collision
    rng = np.random.default_rng(0)
    fromto = np.zeros(6)
    for _ in range(20):
        q = rng.uniform(c.lower_limits, c.upper_limits)
        c._conf.update(c._model.q_to_qpos(q))
        data = c._conf.data
        kept = set(lim.candidates(data, 0.1).tolist())
        for k, (g1, g2) in enumerate(lim.pairs):
            if mujoco.mj_geomDistance(c.model, data, int(g1), int(g2), 0.1, fromto) < 0.1:
                assert k in kept


def test_set_world_moves_or_rebuilds():
    c = ReactiveController("franka", WorldConfig([Sphere("ball", 0.05, [0.5, 0.0, 0.5])]))
    model = c.model
    n_one = c.collision_pair_counts[0]
    q = c.rest_configuration
    c.set_world(WorldConfig([Sphere("ball", 0.05, [0.5, 0.2, 0.5])]))
    assert c.model is model  # same shapes: moved only
    assert np.allclose(c.world.get("ball").pose.position, [0.5, 0.2, 0.5])
    far = c.clearance(q)[0]
    c.set_obstacle_pose("ball", [0.31, 0.0, 0.36])
    assert c.clearance(q)[0] < far - 0.05
    c.add_obstacle(Cuboid("box", [0.1, 0.1, 0.1], [0.0, 0.5, 0.3]))
    assert c.model is not model and c.world.names == ["ball", "box"]
    assert c.collision_pair_counts[0] == 2 * n_one > 0
    c.remove_obstacle("ball")
    assert c.world.names == ["box"]
    with pytest.raises(UnknownNameError):
        c.remove_obstacle("ball")


def test_self_collision_pairs_exclude_the_disabled_ones(ctrl):
    n_obs, n_self = ctrl.collision_pair_counts
    assert n_obs == 0 and n_self > 10
    lim = ctrl._collision
    m = ctrl.model
    disabled = {frozenset(p) for p in ctrl.config.disabled_collision_pairs}
    for g1, g2 in lim.pairs:
        b1, b2 = m.body(m.geom_bodyid[g1]).name, m.body(m.geom_bodyid[g2]).name
        assert frozenset((b1, b2)) not in disabled
    assert np.isfinite(ctrl.clearance(ctrl.rest_configuration)[1])


@pytest.mark.parametrize("solver", ["daqp", "quadprog", "proxqp", "osqp"])
def test_solvers_agree(solver):
    import qpsolvers

    if solver not in qpsolvers.available_solvers:
        pytest.skip(f"{solver} not installed")
    world = wall_world()
    q = ReactiveController("franka").rest_configuration
    goal = Pose([0.6, 0.1, 0.4], HAND_DOWN)
    ref = ReactiveController("franka", world, solver="daqp").step(q, goal, DT)
    r = ReactiveController("franka", world, solver=solver).step(q, goal, DT)
    assert r.solved
    np.testing.assert_allclose(r.q, ref.q, atol=1e-6 if solver in ("daqp", "quadprog") else 2e-4)


def test_a_failed_qp_holds_the_arm(monkeypatch):
    import manip.control.controller as controller_module

    c = ReactiveController("franka")
    monkeypatch.setattr(controller_module, "solve_qp", lambda *a, **k: None)
    q = c.rest_configuration
    r = c.step(q, [0.5, 0.0, 0.4], DT)
    assert r.status is StepStatus.HELD and not r.solved
    np.testing.assert_array_equal(r.q, q)
    assert np.all(r.velocities == 0)


# ---------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("target, word", [
    ([np.nan, 0.0, 0.5], "target"),
    ([0.5, 0.0], "target"),
    ([0.5, 0.0, 0.4, np.nan, 1.0, 0.0, 0.0], "target"),
    ([0.5, 0.0, 0.4, 0.0, 0.0, 0.0, 0.0], "target"),  # zero quaternion
    (np.eye(3), "target"),
    (2.0 * np.eye(4), "target"),
    ("up", "target"),
    (None, "target"),
])
def test_bad_targets_raise_naming_the_argument(ctrl, target, word):
    with pytest.raises(InvalidInputError, match=word):
        ctrl.step(ctrl.rest_configuration, target, DT)


@pytest.mark.parametrize("q, word", [
    (np.zeros(6), "q"),
    (np.zeros(9), "q"),
    ([0, 0, 0, np.nan, 0, 0, 0], "q"),
    (np.zeros((7, 1)), "q"),
    (["a"] * 7, "q"),
])
def test_bad_configurations_raise_naming_the_argument(ctrl, q, word):
    with pytest.raises(InvalidInputError, match=rf"\b{word}\b"):
        ctrl.step(q, [0.5, 0.0, 0.4], DT)


@pytest.mark.parametrize("dt", [0.0, -0.01, np.nan, np.inf, "fast"])
def test_bad_dt_raises(ctrl, dt):
    with pytest.raises(InvalidInputError, match="dt"):
        ctrl.step(ctrl.rest_configuration, [0.5, 0.0, 0.4], dt)


def test_bad_velocity_raises(ctrl):
    with pytest.raises(InvalidInputError, match="velocity"):
        ctrl.step(ctrl.rest_configuration, [0.5, 0.0, 0.4], DT, velocity=np.zeros(3))


def test_unknown_frames_raise_a_clear_error(ctrl):
    with pytest.raises(InvalidInputError, match="frame .*'panda_nose' not found; available: .*panda_hand_tcp"):
        ReactiveController("franka", frame="panda_nose")
    with pytest.raises(UnknownFrameError):
        ctrl.forward_kinematics(ctrl.rest_configuration, frame="panda_nose")
    with pytest.raises(UnknownNameError):  # also a KeyError-style unknown name
        ReactiveController("franka", frame="world_frame")
    assert ReactiveController("franka", frame="panda_hand").frame == "panda_hand"  # a body works too


@pytest.mark.parametrize("kwargs, word", [
    ({"solver": "cplex"}, "solver"),
    ({"safety_margin": -0.01}, "safety_margin"),
    ({"safety_margin": 0.2, "detection_distance": 0.1}, "detection_distance"),
    ({"collision_gain": 0.0}, "collision_gain"),
    ({"velocity_scale": 1.5}, "velocity_scale"),
    ({"max_speed": 0.0}, "max_speed"),
    ({"rest_configuration": np.zeros(6)}, "rest_configuration"),
    ({"world": {"cuboid": {}}}, "world"),
    ({"weights": {"position": 1.0}}, "weights"),
])
def test_bad_constructor_arguments_raise_naming_them(kwargs, word):
    with pytest.raises(InvalidInputError, match=word):
        ReactiveController("franka", **kwargs)


def test_bad_weights_raise(ctrl):
    with pytest.raises(InvalidInputError, match="speed"):
        ctrl.set_weights(speed=1.0)
    with pytest.raises(InvalidInputError, match="orientation"):
        ctrl.set_weights(orientation=-1.0)
    with pytest.raises(InvalidInputError, match="both 0"):
        ctrl.set_weights(position=0.0, orientation=0.0)
    assert ctrl.weights == TaskWeights()  # unchanged


# ---------------------------------------------------------------------------- self pairs closer than the margin
def pair_distance(c: ReactiveController, q, body1: str, body2: str) -> float:
    m = c.model
    d = mujoco.MjData(m)
    d.qpos[:] = c._model.q_to_qpos(q)
    mujoco.mj_kinematics(m, d)
    g1, g2 = (next(g for g in range(m.ngeom) if m.body(int(m.geom_bodyid[g])).name == b) for b in (body1, body2))
    return mujoco.mj_geomDistance(m, d, g1, g2, 1.0, np.zeros(6))


def test_self_pairs_closer_than_twice_the_margin_at_home_keep_half_their_distance():
    c = ReactiveController("ur10", safety_margin=0.02)
    home = c.config.default_joint_positions
    reduced = c.self_margins
    assert set(reduced) == {("base_link", "upper_arm_link"), ("forearm_link", "wrist_2_link"),
                            ("wrist_1_link", "wrist_3_link")}
    for (a, b), margin in reduced.items():
        d0 = pair_distance(c, home, a, b)
        assert 0.0 < d0 < 0.04 and margin == pytest.approx(d0 / 2, abs=1e-9)
    assert ReactiveController("ur10", safety_margin=0.005).self_margins == {}   # 18-20 mm > 2 x 5 mm
    assert ReactiveController("franka", safety_margin=0.02).self_margins == {}  # the Franka's pairs: unchanged
    lim = c._collision
    assert np.all(lim.margins[: lim.n_obstacle_pairs] == 0.02) and np.all(lim.margins <= 0.02)


def test_ur10_reaches_its_target_with_a_2cm_margin():
    """The UR10's links lie 18-20 mm apart at home: with one 2 cm margin for every pair, their
    rows (bound 0 from the first step) stopped the flange 0.29 m short of this target."""
    c = ReactiveController("ur10", safety_margin=0.02)
    target = np.array([0.6, 0.3, 0.43])
    q, results = run(c, c.rest_configuration, target, 240)
    assert np.linalg.norm(c.forward_kinematics(q).position - target) < 1e-3
    assert all(r.solved for r in results)
    assert min(r.self_clearance for r in results) > 0.009  # the reduced margins (9.2-10 mm) hold


def test_a_self_pair_with_a_reduced_margin_still_keeps_it():
    """The frame and posture tasks pull the UR10 towards a configuration where its forearm and
    wrist_2 overlap (by 3.7 mm): the pair stops at its own margin (half its 18.4 mm at home)."""
    c0 = ReactiveController("ur10", safety_margin=0.02)
    q_bad = c0.rest_configuration + np.array([0.0, 0.0, 0.0, 2.0, -1.0, 0.0])
    assert pair_distance(c0, q_bad, "forearm_link", "wrist_2_link") < -0.003
    c = ReactiveController("ur10", safety_margin=0.02, rest_configuration=q_bad)
    margin = c.self_margins[("forearm_link", "wrist_2_link")]
    goal = c.forward_kinematics(q_bad)
    q = c0.rest_configuration
    dists = []
    for _ in range(600):
        q = c.step(q, goal, DT).q
        dists.append(pair_distance(c, q, "forearm_link", "wrist_2_link"))
    assert min(dists) > margin - 1e-3          # kept, up to one step's linearisation error
    assert dists[-1] < margin + 2e-3           # and it did press against it


def test_bad_self_margins_raise(ctrl):
    lim = ctrl._collision
    self_pairs = [tuple(p) for p in lim.pairs[lim.n_obstacle_pairs:]]
    with pytest.raises(InvalidInputError, match="self_margins"):
        CollisionLimit(ctrl.model, [], self_pairs, 0.01, 0.1, 0.1, np.full(len(self_pairs), 0.02))
    with pytest.raises(InvalidInputError, match="self_margins"):
        CollisionLimit(ctrl.model, [], self_pairs, 0.01, 0.1, 0.1, [0.005])
