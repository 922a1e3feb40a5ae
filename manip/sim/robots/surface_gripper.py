"""`SurfaceGripper`: Isaac's suction gripper (`omni.isaac.manipulators.grippers.SurfaceGripper`)
as a MuJoCo weld constraint.

    gripper = SurfaceGripper(end_effector_prim_path="/World/UR10/ee_link", translate=0.0, direction="x")
    ur10 = world.scene.add(SingleManipulator("/World/UR10", end_effector_prim_name="ee_link", gripper=gripper))
    world.reset()
    gripper.close()          # grips the object in front of the grip point, if one is there
    gripper.is_closed()

Isaac casts a ray from the grip point (the end effector's origin moved `translate` [m] along
its `direction` axis) along that axis and joins the first rigid body within `grip_threshold`
[m] with a D6 joint that pulls it in onto the grip point. Here the compiled model holds one
inactive weld equality per surface gripper (its end effector's body to the world); `close()`
casts the same ray (MuJoCo's `mj_ray`) and, when it hits a free body (a Dynamic object) within
`grip_threshold`, points the weld at that body and activates it, with the object's pose relative
to the end effector as it is but moved along the axis by the gap, so that the constraint pulls
the touched point onto the grip point (in a few 10 ms) and holds it there, the object's
orientation unchanged (less where the robot's own collision geometry is nearer: pressed into
it, the object would be tilted by the contact); the object then moves with the end effector,
its weight and inertia carried by the arm through the constraint.
`open()` deactivates it. After every physics step (and at `update()`), the weld's force and
torque are compared with `force_limit` [N] and `torque_limit` [N m] and the object's turn
from its gripped orientation with `bend_angle` [rad]: past any of them the grip breaks (the
gripper opens), as PhysX breaks the joint. `disable_gravity=True` (Isaac's default) cancels
the held object's weight while it is held.

Differences from Isaac: `kp` / `kd` (the D6 joint's stiffness and damping in Isaac) are not
used: the weld is MuJoCo's stiff constraint (`WELD_SOLREF`), so the pull-in takes a few 10 ms
whatever they are, and a value other than Isaac's defaults (100, 100) is warned about (once per
gripper); a gripper made after a `world.reset()` is in the model from the next reset.
Why not map them (decided in round six): a MuJoCo weld does take a stiffness and a damping
(solref's direct form (-k, -b)), but per unit of the constraint's effective mass [1/s^2, 1/s],
where Isaac's are the D6 drive's (force per metre, applied on axes its documentation does not
name). Dividing by the held object's mass would make Isaac's defaults (100, 100) an overdamped
pull-in of about a second on a 1 kg box, and a 10 cm sag under its weight with
`disable_gravity=False` - not what Isaac's suction tutorials show - so the weld stays stiff and
the warning stays.
"""

from __future__ import annotations

import logging
import math
import warnings

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim.scenes.stage import SimHandle, SimulationError, get_current_stage, validate_prim_path
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.validation import non_negative, positive

logger = logging.getLogger(__name__)

AXES = {"x": 0, "y": 1, "z": 2}
#: MuJoCo's solref of the weld (time constant [s], damping ratio): stiff at the 1-2 ms substeps.
WELD_SOLREF = (0.01, 1.0)
#: Isaac's defaults of the D6 joint's stiffness and damping (not used here: other values warn).
DEFAULT_KP = DEFAULT_KD = 1.0e2


class SurfaceGripper:
    """A suction gripper at an end effector (Isaac's `SurfaceGripper`; see the module docstring).

    Args:
        end_effector_prim_path: the end effector: a body or a site of a referenced robot
            ("/World/UR10/ee_link"), or a path below one of its bodies (that body's frame).
        translate: offset [m] of the grip point from the end effector along `direction`.
        direction: the end effector's axis the gripper faces, "x", "y" or "z".
        grip_threshold: how far [m] from the grip point an object is gripped.
        force_limit: force [N] that breaks the grip.
        torque_limit: torque [N m] that breaks the grip.
        bend_angle: turn [rad] of the object from its gripped orientation that breaks the grip.
        kp, kd: Isaac's joint stiffness and damping (kept for reading; not used, see the module
            docstring: other values than 100 warn).
        disable_gravity: no gravity on a held object.

    Raises:
        InvalidInputError: a bad path, direction or limit (named in the message).
    """

    def __init__(self, end_effector_prim_path: str, translate: float = 0.0, direction: str = "x",
                 grip_threshold: float = 0.01, force_limit: float = 1.0e6, torque_limit: float = 1.0e4,
                 bend_angle: float = np.pi / 24, kp: float = 1.0e2, kd: float = 1.0e2, disable_gravity: bool = True):
        self.prim_path = validate_prim_path(end_effector_prim_path)
        self.set_translate(translate)
        self.set_direction(direction)
        self._threshold = positive(grip_threshold, "grip_threshold", "m")
        self.set_force_limit(force_limit)
        self.set_torque_limit(torque_limit)
        self._bend = positive(bend_angle, "bend_angle", "rad")
        self.kp, self.kd = non_negative(kp, "kp"), non_negative(kd, "kd")
        if (self.kp, self.kd) != (DEFAULT_KP, DEFAULT_KD):
            warnings.warn(f"SurfaceGripper at {self.prim_path}: kp={self.kp:g}, kd={self.kd:g} are not used (manip's "
                          "grip is MuJoCo's stiff weld, which pulls the object onto the grip point in a few 10 ms "
                          "whatever the stiffness; Isaac's D6 joint uses them)", UserWarning, stacklevel=2)
        self._disable_gravity = bool(disable_gravity)
        self._default_opened = True
        self._sim: SimHandle | None = None
        self._eq = self._body = self._site = -1
        self._lifted = -1  # the body whose gravity this gripper cancelled
        stage = get_current_stage()
        if stage.sim is not None:
            stage.mark_changed(self.prim_path)  # its weld enters the model at the next reset
        stage.register_wrapper(self)

    # ------------------------------------------------------------------ model
    @property
    def _weld_name(self) -> str:
        return self.prim_path + "/__surface_gripper_weld"

    def add_equalities_to_spec(self, spec: mujoco.MjSpec) -> None:
        """Add this gripper's inactive weld (end effector's body -> world) to `spec` (the compiler calls it)."""
        body = self._spec_body(spec)
        spec.add_equality(name=self._weld_name, type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY,
                          name1=body, name2="world", active=False, solref=list(WELD_SOLREF))

    def _spec_body(self, spec: mujoco.MjSpec) -> str:
        if spec.body(self.prim_path) is not None:
            return self.prim_path
        site = spec.site(self.prim_path)
        if site is not None:
            return site.parent.name
        path = self.prim_path
        while "/" in path.strip("/"):
            path = path.rsplit("/", 1)[0]
            if spec.body(path) is not None and path.count("/") > 2:  # a link, not the robot's prim
                return path
        raise SimulationError(f"SurfaceGripper: no body or site of a referenced robot at {self.prim_path!r} "
                              "(give the end effector's link, e.g. '/World/UR10/ee_link')")

    def _bindable(self) -> bool:
        sim = get_current_stage().sim
        return sim is not None and mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_EQUALITY, self._weld_name) >= 0

    def bind_simulation(self, sim: SimHandle) -> None:
        m = sim.model
        self._eq = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_EQUALITY, self._weld_name)
        if self._eq < 0:
            return
        self._sim = sim
        self._body = int(m.eq_obj1id[self._eq])
        self._site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, self.prim_path)
        self._lifted = -1
        sim.after_step.append(self.update)

    def unbind_simulation(self) -> None:
        self._sim = None

    def initialize(self, *args, physics_sim_view=None, articulation_num_dofs=None, **kwargs) -> None:
        """Isaac's `initialize(physics_sim_view=None, articulation_num_dofs=None)`: the gripper is
        bound when the World compiles; this checks it was (after `world.reset()`)."""
        self._need()

    def _need(self) -> SimHandle:
        if self._sim is None:
            raise SimulationError(f"SurfaceGripper at {self.prim_path}: not simulated yet; call world.reset() first "
                                  "(a gripper made after a reset is in the model from the next one)")
        return self._sim

    # ------------------------------------------------------------------ grip
    def _grip_point(self) -> tuple[np.ndarray, np.ndarray]:
        """World grip point (3,) [m] and the unit axis (3,) it faces."""
        sim = self._need()
        sim.ensure_kinematics()
        d = sim.data
        if self._site >= 0:
            p, R = d.site_xpos[self._site], d.site_xmat[self._site].reshape(3, 3)
        else:
            p, R = d.xpos[self._body], d.xmat[self._body].reshape(3, 3)
        axis = R[:, AXES[self._direction]].copy()
        return p + self._translate * axis, axis

    def close(self) -> None:
        """Grip the free body the grip point faces within `grip_threshold`, if any (else stay open)."""
        sim = self._need()
        if self.is_closed():
            return
        m, d = sim.model, sim.data
        start, axis = self._grip_point()
        geom = np.zeros(1, dtype=np.int32)
        distance = mujoco.mj_ray(m, d, start, axis, None, 1, self._body, geom)
        if geom[0] < 0 or distance > self._threshold:
            logger.info("SurfaceGripper at %s: nothing within %.3f m of the grip point; stays open", self.prim_path,
                        self._threshold)
            return
        body = int(m.geom_bodyid[geom[0]])
        jnt = m.body_jntadr[body]
        if jnt < 0 or m.jnt_type[jnt] != mujoco.mjtJoint.mjJNT_FREE:
            logger.info("SurfaceGripper at %s: %s is not a free rigid body; stays open", self.prim_path, m.body(body).name)
            return
        distance = self._pull(body, axis, distance)
        x1, q1 = d.xpos[self._body], d.xquat[self._body]
        x2, q2 = d.xpos[body], d.xquat[body]
        m.eq_obj2id[self._eq] = body
        m.eq_data[self._eq, :] = 0.0
        # the object's pose in the end effector's frame, moved by the gap: its touched point on the grip point
        m.eq_data[self._eq, 3:6] = d.xmat[self._body].reshape(3, 3).T @ (x2 - distance * axis - x1)
        m.eq_data[self._eq, 6:10] = quat.multiply(quat.conjugate(q1), q2)
        m.eq_data[self._eq, 10] = 1.0  # torquescale
        d.eq_active[self._eq] = 1
        if self._disable_gravity:
            sim.gravity_off.add(body)
            self._lifted = body

    def _pull(self, body: int, axis: np.ndarray, gap: float) -> float:
        """How far [m] (at most `gap`) the free `body` moves towards the grip point along `axis`
        before it touches the end effector's robot: a few steps, each by the distance between
        its geoms and the robot's at that point (MuJoCo collides meshes by their hulls, which a
        ray misses). The state is left as it was."""
        m, d = self._sim.model, self._sim.data
        adr = m.jnt_qposadr[m.body_jntadr[body]]
        position = d.qpos[adr:adr + 3].copy()
        ours = np.flatnonzero(m.geom_bodyid == body)
        robot = np.flatnonzero((m.body_rootid[m.geom_bodyid] == m.body_rootid[self._body])
                               & ((m.geom_contype | m.geom_conaffinity) > 0))
        fromto, pulled = np.zeros(6), 0.0
        try:
            for _ in range(8):
                room = min((mujoco.mj_geomDistance(m, d, int(g), int(h), gap - pulled, fromto)
                            for g in ours for h in robot), default=gap - pulled)
                pulled += max(room, 0.0)
                if room < 1e-4 or pulled >= gap:
                    break
                d.qpos[adr:adr + 3] = position - pulled * axis
                mujoco.mj_kinematics(m, d)
        finally:
            d.qpos[adr:adr + 3] = position
            mujoco.mj_kinematics(m, d)
        return min(pulled, gap)

    def open(self) -> None:
        """Let go of the held object (nothing when open)."""
        sim = self._need()
        sim.data.eq_active[self._eq] = 0
        self._restore_gravity()

    def _restore_gravity(self) -> None:
        if self._lifted >= 0 and self._sim is not None:
            self._sim.gravity_off.discard(self._lifted)
        self._lifted = -1

    def is_closed(self) -> bool:
        """True while an object is held."""
        return self._sim is not None and self._eq >= 0 and bool(self._sim.data.eq_active[self._eq])

    def update(self) -> None:
        """Break the grip past `force_limit`, `torque_limit` or `bend_angle` (run after every physics step)."""
        if not self.is_closed():
            if self._lifted >= 0:  # a reset or a stop deactivated the weld
                self._restore_gravity()
            return
        m, d = self._sim.model, self._sim.data
        n = d.nefc
        rows = np.flatnonzero((d.efc_type[:n] == mujoco.mjtConstraint.mjCNSTR_EQUALITY) & (d.efc_id[:n] == self._eq))
        force = d.efc_force[rows]
        # the object's turn from its gripped orientation: (q_body * relquat)^-1 * q_object (MuJoCo's C helpers:
        # this runs after every physics step)
        gripped, inverse, q_rel = np.empty(4), np.empty(4), np.empty(4)
        mujoco.mju_mulQuat(gripped, d.xquat[self._body], m.eq_data[self._eq, 6:10])
        mujoco.mju_negQuat(inverse, gripped)
        mujoco.mju_mulQuat(q_rel, inverse, d.xquat[int(m.eq_obj2id[self._eq])])
        bend = 2.0 * math.acos(min(1.0, abs(float(q_rel[0]))))
        why = None
        if rows.size >= 3 and np.linalg.norm(force[:3]) > self._force_limit:
            why = f"force {np.linalg.norm(force[:3]):.1f} N > force_limit {self._force_limit:g} N"
        elif rows.size >= 6 and np.linalg.norm(force[3:6]) > self._torque_limit:
            why = f"torque {np.linalg.norm(force[3:6]):.2f} N m > torque_limit {self._torque_limit:g} N m"
        elif bend > self._bend:
            why = f"bent {bend:.3f} rad > bend_angle {self._bend:.3f} rad"
        if why is not None:
            logger.info("SurfaceGripper at %s: the grip broke (%s)", self.prim_path, why)
            self.open()

    # ------------------------------------------------------------------ Isaac's setters and actions
    def set_translate(self, value: float) -> None:
        """Offset [m] of the grip point along `direction`."""
        v = float(value)
        if not math.isfinite(v):
            raise InvalidInputError(f"translate must be a finite offset [m]; got {value!r}")
        self._translate = v

    def set_direction(self, value: str) -> None:
        """The end effector's axis the gripper faces: "x", "y" or "z"."""
        if value not in AXES:
            raise InvalidInputError(f"direction must be 'x', 'y' or 'z'; got {value!r}")
        self._direction = value

    def set_force_limit(self, value: float) -> None:
        """Force [N] that breaks the grip."""
        self._force_limit = positive(value, "force_limit", "N")

    def set_torque_limit(self, value: float) -> None:
        """Torque [N m] that breaks the grip."""
        self._torque_limit = positive(value, "torque_limit", "N m")

    def set_default_state(self, opened: bool) -> None:
        """Whether `post_reset` (each `world.reset()`) leaves the gripper open."""
        self._default_opened = bool(opened)

    def get_default_state(self) -> dict:
        return {"opened": self._default_opened}

    def post_reset(self) -> None:
        """Back to the default state: open (or closed on what the grip point faces)."""
        if self._sim is None:
            return
        self.open()
        if not self._default_opened:
            self.close()

    def forward(self, action: str) -> ArticulationAction:
        """`close()` or `open()` for "close" / "open"; an empty action (no joints to drive)."""
        if action == "close":
            self.close()
        elif action == "open":
            self.open()
        else:
            raise InvalidInputError(f"SurfaceGripper.forward: action must be 'open' or 'close'; got {action!r}")
        return ArticulationAction()


declare_not_supported(SurfaceGripper)  # apply_action: no joints to drive (manip.sim.isaac_api)
