"""The MuJoCo models robots/franka/franka.xml and robots/jetbot/jetbot.xml.

Checks that the Franka MJCF has the URDF's names, limits and kinematics (against Pinocchio),
that it attaches into a bigger MjSpec under a prefix, that its drives hold and track targets
under gravity, that the gripper lifts and holds a cube by friction, and that the Jetbot drives
with the wheel radius and wheel base it advertises.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from manip.kinematics import Kinematics
from manip.robot_config import RobotConfig, robots_root
from robot_constants import load_script

ARM = [f"panda_joint{i}" for i in range(1, 8)]
FINGERS = ["panda_finger_joint1", "panda_finger_joint2"]
DT = 0.002  # [s] the timestep the drives are tuned for


def _min_jerk(q0: np.ndarray, q1: np.ndarray, duration: float, t: float) -> np.ndarray:
    s = np.clip(t / duration, 0.0, 1.0)
    return q0 + (q1 - q0) * (10 * s**3 - 15 * s**4 + 6 * s**5)


def _scene(
    franka_path: str,
    *,
    cube_pos: np.ndarray | None = None,
    elliptic: bool = False,
) -> mujoco.MjModel:
    """A floor, optionally a 5 cm 0.05 kg cube, and the Franka attached under "franka/"."""
    spec = mujoco.MjSpec()
    spec.option.timestep = DT
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    if elliptic:
        spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
        spec.option.impratio = 10.0
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[2, 2, 0.1])
    if cube_pos is not None:
        cube = spec.worldbody.add_body(name="cube", pos=cube_pos)
        cube.add_freejoint()
        cube.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.025] * 3, mass=0.05)
    frame = spec.worldbody.add_frame()
    frame.attach_body(mujoco.MjSpec.from_file(franka_path).body("panda_link0"), "franka/", "")
    return spec.compile()


@pytest.fixture(scope="module")
def franka_path(franka_config: RobotConfig) -> str:
    return str(franka_config.mjcf_path)


@pytest.fixture(scope="module")
def franka_model(franka_path: str) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(franka_path)


def _tcp_ik(kin: Kinematics, p: np.ndarray, R: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Damped least squares on the TCP frame (test helper, converges from nearby seeds)."""
    fid = kin.frame_id("panda_hand_tcp")
    for _ in range(200):
        M = kin.frame_transform(q, fid)
        err = np.r_[p - M.translation, M.rotation @ pin.log3(M.rotation.T @ R)]
        if np.linalg.norm(err) < 1e-10:
            break
        J = kin.frame_jacobian(q, fid)
        q = np.clip(q + J.T @ np.linalg.solve(J @ J.T + 1e-8 * np.eye(6), err), kin.lower, kin.upper)
    return q


# ---------------------------------------------------------------------------------- Franka


def test_franka_generated_file_is_up_to_date(franka_config: RobotConfig, franka_path: str) -> None:
    path = robots_root() / "tools" / "make_franka_mjcf.py"
    if not path.exists():
        pytest.skip("generator not shipped (installed wheel)")
    mod = load_script(path, "make_franka_mjcf")
    with open(franka_path) as f:
        assert f.read() == mod.generate(franka_config.urdf_path, franka_config.srdf_path)


def test_franka_names_limits_and_home(franka_model: mujoco.MjModel, franka_config: RobotConfig) -> None:
    m = franka_model
    bodies = {m.body(i).name for i in range(m.nbody)}
    assert {f"panda_link{i}" for i in range(8)} | {"panda_hand", "panda_leftfinger", "panda_rightfinger"} <= bodies
    assert [m.joint(i).name for i in range(m.njnt)] == ARM + FINGERS
    assert [m.actuator(i).name for i in range(m.nu)] == ARM + FINGERS
    for i in range(m.nu):  # each actuator drives the joint of its name
        assert m.joint(m.actuator_trnid[i, 0]).name == m.actuator(i).name
    assert m.site("panda_hand").bodyid == m.body("panda_hand").id
    np.testing.assert_allclose(m.site("panda_hand_tcp").pos, [0, 0, 0.1034])
    # limits: URDF (as in the robot config); drive torques: URDF efforts
    np.testing.assert_allclose(m.jnt_range[:7, 0], franka_config.lower_limits)
    np.testing.assert_allclose(m.jnt_range[:7, 1], franka_config.upper_limits)
    np.testing.assert_allclose(m.jnt_range[7:], [[0.0, 0.04]] * 2)
    np.testing.assert_allclose(m.actuator_forcerange[:7, 1], [87, 87, 87, 87, 12, 12, 12])
    np.testing.assert_allclose(m.actuator_ctrlrange[:7], m.jnt_range[:7])
    # prismatic fingers opening along +y / -y of the hand, as the URDF's axes
    assert m.jnt_type[7] == m.jnt_type[8] == mujoco.mjtJoint.mjJNT_SLIDE
    np.testing.assert_allclose(m.jnt_axis[7:], [[0, 1, 0], [0, -1, 0]])
    # no equality coupling the fingers: each has its own actuator
    assert m.neq == 0
    key = m.key("home")
    np.testing.assert_allclose(key.qpos, list(franka_config.default_joint_positions) + [0.04, 0.04])
    np.testing.assert_allclose(key.ctrl, key.qpos)
    # inertials from the URDF
    urdf = ET.parse(franka_config.urdf_path).getroot()
    for link in urdf.findall("link"):
        if link.get("name") in {m.body(i).name for i in range(m.nbody)}:
            mass = float(link.find("inertial/mass").get("value"))
            assert m.body(link.get("name")).mass[0] == pytest.approx(mass)


def test_franka_fk_matches_pinocchio(
    franka_model: mujoco.MjModel, franka_kinematics: Kinematics
) -> None:
    m, d = franka_model, mujoco.MjData(franka_model)
    rng = np.random.default_rng(7)
    kin = franka_kinematics
    for _ in range(50):
        q = rng.uniform(kin.lower, kin.upper)
        d.qpos[:7] = q
        d.qpos[7:] = 0.04
        mujoco.mj_kinematics(m, d)
        for site in ("panda_hand", "panda_hand_tcp"):
            pose = kin.fk(q, site)
            sid = m.site(site).id
            np.testing.assert_allclose(d.site_xpos[sid], pose.position, atol=1e-6, rtol=0)
            R_mj = d.site_xmat[sid].reshape(3, 3)
            angle = np.linalg.norm(pin.log3(R_mj.T @ pose.as_matrix()[:3, :3]))
            assert angle < 1e-6


def test_franka_home_has_no_contacts(franka_path: str) -> None:
    m = _scene(franka_path)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("franka/home").id)
    mujoco.mj_forward(m, d)
    assert d.ncon == 0


def test_franka_attaches_twice_with_prefixes(franka_path: str, franka_kinematics: Kinematics) -> None:
    spec = mujoco.MjSpec()
    offsets = {"left/": [0.0, 0.5, 0.0], "right/": [0.0, -0.5, 0.0]}
    for prefix, pos in offsets.items():
        frame = spec.worldbody.add_frame(pos=pos)
        spec.attach(mujoco.MjSpec.from_file(franka_path), prefix=prefix, frame=frame)
    m = spec.compile()
    assert m.nu == 18 and m.njnt == 18
    assert {m.key(i).name for i in range(m.nkey)} == {"left/home", "right/home"}
    d = mujoco.MjData(m)
    q = np.array([0.3, -0.2, 0.1, -2.0, 0.2, 1.8, 0.4])
    for prefix in offsets:
        d.qpos[m.joint(prefix + "panda_joint1").qposadr[0] + np.arange(7)] = q
    mujoco.mj_kinematics(m, d)
    expected = franka_kinematics.fk(q, "panda_hand_tcp").position
    for prefix, pos in offsets.items():
        np.testing.assert_allclose(d.site(prefix + "panda_hand_tcp").xpos, expected + pos, atol=1e-9)
        assert m.actuator(prefix + "panda_joint4").id >= 0


def test_franka_drives_track_a_smooth_motion_and_hold_under_gravity(
    franka_path: str, franka_kinematics: Kinematics, franka_config: RobotConfig
) -> None:
    """1.5 s min-jerk moves at up to 80 % of the velocity limits: lag < 0.03 rad, rest < 0.02 rad."""
    m = _scene(franka_path)
    d = mujoco.MjData(m)
    kin = franka_kinematics
    rng = np.random.default_rng(3)
    home = np.asarray(franka_config.default_joint_positions)
    vmax = np.asarray(franka_config.velocity_limits)
    duration = 1.5
    for _ in range(4):
        mujoco.mj_resetDataKeyframe(m, d, 0)
        while True:  # a collision-free target reachable by a move within the velocity limits
            step = rng.uniform(-1, 1, 7) * 0.8 * vmax * duration / 1.875
            q1 = np.clip(home + step, kin.lower + 0.2, kin.upper - 0.2)
            d.qpos[:7] = q1
            mujoco.mj_forward(m, d)
            if d.ncon == 0:
                break
        mujoco.mj_resetDataKeyframe(m, d, 0)
        lag = 0.0
        for i in range(int(round((duration + 1.5) / DT))):
            ref = _min_jerk(home, q1, duration, (i + 1) * DT)
            d.ctrl[:7] = ref
            mujoco.mj_step(m, d)
            lag = max(lag, np.abs(d.qpos[:7] - ref).max())
        assert lag < 0.03
        assert np.abs(d.qpos[:7] - q1).max() < 0.02
        assert np.abs(d.qvel[:7]).max() < 1e-3  # settled, no oscillation


@pytest.mark.parametrize("elliptic", [False, True], ids=["pyramidal", "elliptic"])
def test_franka_grasps_lifts_and_holds_a_cube(
    franka_path: str, franka_kinematics: Kinematics, franka_config: RobotConfig, elliptic: bool
) -> None:
    """Close on a 5 cm, 0.05 kg cube, lift it 20 cm in 1.5 s, hold 2 s: it stays in the hand."""
    cube = np.array([0.5, 0.1, 0.025])
    m = _scene(franka_path, cube_pos=cube, elliptic=elliptic)
    d = mujoco.MjData(m)
    R_down = np.diag([1.0, -1.0, -1.0])  # hand z pointing down, fingers closing along world y
    home = np.asarray(franka_config.default_joint_positions)
    q_grasp = _tcp_ik(franka_kinematics, cube, R_down, home.copy())
    q_lift = _tcp_ik(franka_kinematics, cube + [0, 0, 0.2], R_down, q_grasp.copy())
    for q, target in ((q_grasp, cube), (q_lift, cube + [0, 0, 0.2])):
        assert np.linalg.norm(franka_kinematics.fk(q, "panda_hand_tcp").position - target) < 1e-6

    arm = m.joint("franka/panda_joint1").qposadr[0] + np.arange(7)
    fingers = m.joint("franka/panda_finger_joint1").qposadr[0] + np.arange(2)
    d.qpos[arm], d.qpos[fingers] = q_grasp, 0.04
    d.ctrl[:7], d.ctrl[7:] = q_grasp, 0.04
    hand, body = m.body("franka/panda_hand").id, m.body("cube").id

    def cube_in_hand() -> np.ndarray:
        return d.xmat[hand].reshape(3, 3).T @ (d.xpos[body] - d.xpos[hand])

    def run(seconds: float, arm_target=None) -> float:
        drift = 0.0
        for i in range(int(round(seconds / DT))):
            if arm_target is not None:
                d.ctrl[:7] = arm_target((i + 1) * DT)
            mujoco.mj_step(m, d)
            if arm_target is not None:
                drift = max(drift, np.linalg.norm(cube_in_hand() - grasped))
        return drift

    grasped = np.zeros(3)
    run(0.3)
    d.ctrl[7:] = 0.0  # close both fingers
    run(0.7)
    # stalled on the cube, symmetric, squeezing with 20-70 N
    np.testing.assert_allclose(d.qpos[fingers], 0.0244, atol=1e-3)
    grip = -d.actuator_force[7:]
    assert np.all((grip > 20) & (grip < 70))
    grasped = cube_in_hand()
    drift = run(1.5, lambda t: _min_jerk(q_grasp, q_lift, 1.5, t))
    drift = max(drift, run(2.0, lambda t: q_lift))
    assert d.xpos[body][2] > 0.025 + 0.19
    assert drift < 0.005


# ---------------------------------------------------------------------------------- Jetbot


@pytest.fixture(scope="module")
def jetbot_model() -> mujoco.MjModel:
    spec = mujoco.MjSpec()
    spec.option.timestep = DT
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 5, 0.1])
    frame = spec.worldbody.add_frame()
    child = mujoco.MjSpec.from_file(str(robots_root() / "jetbot" / "jetbot.xml"))
    frame.attach_body(child.body("chassis"), "jetbot/", "")
    return spec.compile()


def test_jetbot_names_and_dimensions(jetbot_model: mujoco.MjModel) -> None:
    m = jetbot_model
    names = ["jetbot/left_wheel_joint", "jetbot/right_wheel_joint"]
    assert [m.actuator(i).name for i in range(m.nu)] == names
    assert m.joint("jetbot/chassis_joint").type[0] == mujoco.mjtJoint.mjJNT_FREE
    left, right = (m.body(n).pos for n in ("jetbot/left_wheel", "jetbot/right_wheel"))
    assert np.linalg.norm(left - right) == pytest.approx(0.1125)
    assert m.geom("jetbot/left_wheel_geom").size[0] == pytest.approx(0.03)
    assert 0.5 <= m.body_subtreemass[m.body("jetbot/chassis").id] <= 1.0


def _drive(m: mujoco.MjModel, wheel_velocities: tuple[float, float], seconds: float):
    """Drive from rest; return (velocity (3,), yaw rate) averaged over the last second."""
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    chassis = m.body("jetbot/chassis").id
    d.ctrl[:] = wheel_velocities
    yaw = 0.0

    def heading() -> float:
        R = d.xmat[chassis].reshape(3, 3)
        return float(np.arctan2(R[1, 0], R[0, 0]))

    n = int(round(seconds / DT))
    for i in range(n):
        if i == n - int(round(1.0 / DT)):
            p0, yaw0 = d.xpos[chassis].copy(), yaw
        h = heading()
        mujoco.mj_step(m, d)
        yaw += (heading() - h + np.pi) % (2 * np.pi) - np.pi
        assert d.xmat[chassis][8] > 0.99  # stays upright
    return d.xpos[chassis] - p0, yaw - yaw0


def test_jetbot_drives_forward_at_wheel_speed_times_radius(jetbot_model: mujoco.MjModel) -> None:
    v, yaw_rate = _drive(jetbot_model, (10.0, 10.0), 2.0)
    assert v[0] == pytest.approx(0.3, rel=0.05)
    assert abs(v[1]) < 1e-3 and abs(yaw_rate) < 1e-3


def test_jetbot_turns_counter_clockwise(jetbot_model: mujoco.MjModel) -> None:
    v, yaw_rate = _drive(jetbot_model, (-5.0, 5.0), 2.0)
    # differential drive: yaw rate = r (w_right - w_left) / wheel_base
    assert yaw_rate == pytest.approx(0.03 * 10.0 / 0.1125, rel=0.05)
    assert np.linalg.norm(v[:2]) < 0.01
