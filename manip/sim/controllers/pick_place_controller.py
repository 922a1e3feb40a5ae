"""Isaac Sim's `PickPlaceController` (Franka flavour): a ten-phase pick-and-place state machine.

The controller is called once per physics step. Each phase advances a progress variable
`t` by its `events_dt` entry per call and ends when `t` reaches 1 (so phase k lasts about
`1 / events_dt[k]` calls). The phases (Isaac's numbering):

====  ==========================================================================
0     move above the pick position, to `end_effector_initial_height` (h1)
1     descend to the pick position
2     wait (arm and fingers keep their targets; the robot settles)
3     close the gripper
4     lift back to h1
5     move at h1 to above the place position
6     descend to the place position
7     open the gripper
8     lift back to h1
9     hold at h1
====  ==========================================================================

Isaac follows the moving end-effector target with an RMPflow c-space controller. Here
the target is turned into joint position targets by manip's inverse kinematics
(`manip.ik.IKSolver`, one local solve per call seeded with the previous target), and the
targets themselves move smoothly: within every phase they follow a cosine profile
0.5 (1 - cos(pi t)), so the Franka's PD drives never see a step (a step saturates the wrist
drives, see robots/franka/README.md). Differences from Isaac, all for that reason:

- phase 0 interpolates in joint space from the configuration at its start to the IK
  solution above the pick position (Isaac jumps the target there and lets RMPflow move);
- phase 5 interpolates the horizontal position in polar coordinates about the robot base
  (radius and azimuth in (-pi, pi], never wrapped), so that a move to the other side of
  the robot goes around the base instead of through it (Isaac: a straight line plus
  RMPflow's avoidance);
- an IK solution more than `max_joint_step` away from the previous one (another branch of
  the arm's redundancy), or a failed solve, is not used: the previous target is held
  (logged; counted in `ik_failures`).

Positions are world coordinates [m] of the end effector (`panda_hand_tcp`, the point
between the fingertips, unless the Franka was built with another `end_effector_prim_name`);
a cube is grasped with the TCP at its centre (z = 0.025 for a 5 cm cube on the ground).
The default orientation points the hand down as at the Franka's home configuration
(w, x, y, z) = (0, 1, 0, 0); Isaac's default (0, 0, 1, 0) is the same turned 180 deg about
z (its end-effector frame differs), which the Franka's wrist reaches only near its limit.

A parallel gripper's grasp is the same turned half a turn about its approach axis: by
default the controller uses whichever of the two orientations is nearer the hand's at the
first call (`symmetric_grasp`), so Isaac's (0, 0, 1, 0) works as (0, 1, 0, 0) does. Before
opening at the place position (phase 7) it checks that the end effector got there (within
`PLACE_TOLERANCE`): when the IK could not follow (an unreachable place), the sequence stops
with the gripper closed and `failure` says why, instead of dropping the object elsewhere.

The grasp is physics only: the fingers are driven to their closed positions and hold the
object by friction. Unlike Isaac's, the controller checks the grasp before carrying (at the
first call of phase 4, `check_grasp=True`): the object (`picking_position` of that call)
must be within `GRASP_TOLERANCE` of where the end effector was sent to grasp it, and the
fingers must not have closed completely (nothing between them). Otherwise the grasp failed
(the object moved away, was pushed, or was never there): the controller logs the reason,
returns the gripper's "open" action and ends the sequence; `is_done()` is then True and
`failure` says why, instead of carrying nothing to the place position.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.ik import IKSolver
from manip.kinematics import Kinematics
from manip.pose import Pose
from manip.robot_config import RobotConfig, load_robot_config
from manip.sim.controllers.base_controller import BaseController
from manip.sim.controllers.cspace_pick_place import CspacePickPlace, is_cspace_controller
from manip.sim.scenes.stage import SimulationError
from manip.validation import positive, unit_quat, vec

logger = logging.getLogger(__name__)

#: Isaac's per-phase progress increments for the Franka (phase k lasts ~1/events_dt[k] calls).
FRANKA_EVENTS_DT = (0.008, 0.005, 0.1, 0.1, 0.0025, 0.001, 0.0025, 1.0, 0.008, 0.08)
NUM_EVENTS = 10
DEFAULT_INITIAL_HEIGHT = 0.3  # [m] h1, Isaac's default
HAND_DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # (w, x, y, z): hand z axis = world -z, as at home
#: Half a turn about the end effector's own z axis (its approach axis), (w, x, y, z).
HALF_TURN_Z = np.array([0.0, 0.0, 0.0, 1.0])
#: [m] the end effector must be this close to the place position before the gripper opens.
PLACE_TOLERANCE = 0.02

#: [m] a grasped object's centre lies at most this far from where the end effector was sent.
GRASP_TOLERANCE = 0.03
#: [m] fingers closer than this to their closed positions hold nothing.
GRASP_EMPTY_GAP = 0.001

# Each Cartesian IK solve starts this fraction of the way from the previous target toward
# the robot's default configuration: the local solve then lands near it, which keeps the
# redundant joint from drifting toward its limits over hundreds of small steps.
POSTURE_PULL = 0.02


def _mix(t: float) -> float:
    """Cosine profile 0.5 (1 - cos(pi t)) for t in [0, 1] (zero slope at both ends)."""
    t = min(max(t, 0.0), 1.0)
    return 0.5 * (1.0 - math.cos(math.pi * t))


def _check_events_dt(events_dt) -> list[float]:
    a = np.asarray(events_dt, dtype=float)
    if a.shape != (NUM_EVENTS,) or not np.all(np.isfinite(a)) or np.any(a <= 0) or np.any(a > 1):
        raise InvalidInputError(
            f"events_dt must be {NUM_EVENTS} numbers in (0, 1] (progress per call of each phase); got {events_dt!r}"
        )
    return [float(x) for x in a]


def _check_height(h) -> float:
    v = float(h)
    if not math.isfinite(v):
        raise InvalidInputError(f"end_effector_initial_height must be a finite height [m]; got {h!r}")
    return v


class PickPlaceController(BaseController):
    """Pick an object and place it, one `forward` call per physics step (Isaac's
    `omni.isaac.franka.controllers.PickPlaceController`).

    Given a `cspace_controller` (keyword, or second by position), it is instead Isaac's generic
    `omni.isaac.manipulators.controllers.PickPlaceController(name, cspace_controller, gripper,
    end_effector_initial_height=None, events_dt=None)`, driving that controller
    (`cspace_pick_place.py`); a subclass calling `super().__init__(name=..., cspace_controller=...,
    gripper=...)` gets it too. The keywords after `*` are the Franka flavour's.

    Args:
        name: controller name.
        gripper: the robot's `ParallelGripper` (`franka.gripper`); phases 3 and 7 return its
            "close" / "open" actions.
        robot_articulation: the robot (`manip.sim.Franka`); its base pose maps world targets
            to the base frame of the kinematics, its dof names locate the arm joints.
        end_effector_initial_height: h1, the world height [m] of the end effector for the
            moves above the pick and place positions (default 0.3).
        events_dt: (10,) progress per call of each phase, each in (0, 1] (default Isaac's
            Franka values `FRANKA_EVENTS_DT`, about 38 s of motion at 60 calls/s).
        end_effector_link: frame of the kinematics placed at the targets (default the robot
            configuration's tool centre point, the Franka's "panda_hand_tcp", where Isaac's
            controller places its RMPflow end effector "right_gripper", whatever the
            articulation's `end_effector` is: Isaac's pick-up example makes it the right finger).
        robot: robot configuration name or `RobotConfig` of the kinematics (default "franka").
        max_joint_step: largest accepted change [rad] of an arm joint's IK solution between
            two calls (a larger one means the solver switched to another arm configuration):
            such solutions are not used, the previous target is held. With the default
            events_dt the targets move < 0.01 rad per call; raise it for much faster phases.
        check_grasp: check the grasp before carrying (see the module docstring); False
            carries on whatever the fingers hold, as Isaac's controller does.
        symmetric_grasp: a parallel gripper grasps the same turned half a turn about its
            approach axis: use whichever of `end_effector_orientation` and that orientation
            turned is nearer the end effector's at the first call (Isaac's (0, 0, 1, 0) is
            then reached as (0, 1, 0, 0)); False: the orientation as given.

    Raises:
        InvalidInputError: bad events_dt, height or max_joint_step.
    """

    def __init__(self, name: str, gripper=None, robot_articulation=None, end_effector_initial_height: float | None = None,
                 events_dt=None, *, cspace_controller=None, end_effector_link: str | None = None,
                 robot: str | RobotConfig = "franka", max_joint_step: float = 0.2, check_grasp: bool = True,
                 symmetric_grasp: bool = True):
        super().__init__(name)
        if cspace_controller is None and is_cspace_controller(gripper):  # Isaac's generic signature, by position
            cspace_controller, gripper, robot_articulation = gripper, robot_articulation, None
        self._generic = None if cspace_controller is None else CspacePickPlace(
            name, cspace_controller, gripper, end_effector_initial_height, events_dt)
        self._ik_failures, self._link = 0, None
        if self._generic is not None:
            return
        if gripper is None or robot_articulation is None:
            raise InvalidInputError(f"{name}: PickPlaceController needs gripper and robot_articulation (the Franka "
                                    "flavour), or cspace_controller and gripper (Isaac's generic controller)")
        self._gripper = gripper
        self._robot = robot_articulation
        self._h1 = DEFAULT_INITIAL_HEIGHT if end_effector_initial_height is None else _check_height(
            end_effector_initial_height)
        self._events_dt = _check_events_dt(FRANKA_EVENTS_DT if events_dt is None else events_dt)
        self._max_joint_step = positive(max_joint_step, "max_joint_step", "rad")
        if not isinstance(check_grasp, (bool, np.bool_)):
            raise InvalidInputError(f"check_grasp must be True or False; got {check_grasp!r}")
        self._check_grasp = bool(check_grasp)
        if not isinstance(symmetric_grasp, (bool, np.bool_)):
            raise InvalidInputError(f"symmetric_grasp must be True or False; got {symmetric_grasp!r}")
        self._symmetric_grasp = bool(symmetric_grasp)
        config = robot if isinstance(robot, RobotConfig) else load_robot_config(robot)
        self._kin = Kinematics(config)
        # One local solve from the seed: a random restart could land on another branch.
        self._ik = IKSolver(self._kin, max_attempts=1)
        if end_effector_link is None:  # Isaac's: its RMPflow end effector, whatever robot.end_effector is
            end_effector_link = config.tcp_link or config.ee_link
        self._kin.frame_id(end_effector_link)  # raises UnknownNameError with the valid frames
        self._link = end_effector_link
        self._rest = np.asarray(config.default_joint_positions, dtype=float).copy()
        self._arm_idx: np.ndarray | None = None
        self._ik_failures = 0
        self._clear_state()

    # ------------------------------------------------------------------ state
    def _clear_state(self) -> None:
        self._event = 0
        self._t = 0.0
        self._pause = False
        self._q_target: np.ndarray | None = None  # last arm joint targets sent (7,) [rad]
        self._q_start: np.ndarray | None = None  # arm configuration at the start of phase 0
        self._q_above_pick: np.ndarray | None = None  # IK solution above the pick position
        self._pick_xy: np.ndarray | None = None  # pick position (world xy) frozen after phase 1
        self._h0: float | None = None  # pick height (world z) frozen after phase 1
        self._failed_event = -1
        self._failure: str | None = None
        self._half_turn: bool | None = None  # use the orientation turned half a turn about z (decided once)

    def reset(self, end_effector_initial_height: float | None = None, events_dt=None) -> None:
        """Restart at phase 0 (unpaused); optionally change h1 [m] and events_dt (10,)."""
        if self._generic is not None:
            return self._generic.reset(end_effector_initial_height, events_dt)
        h1 = self._h1 if end_effector_initial_height is None else _check_height(end_effector_initial_height)
        dts = self._events_dt if events_dt is None else _check_events_dt(events_dt)
        self._h1, self._events_dt = h1, dts
        self._ik_failures = 0
        self._clear_state()

    def is_done(self) -> bool:
        """True once the last phase (9) has ended, or the sequence stopped on a failed grasp or
        an unreached place position (see `failure`)."""
        return self._generic.is_done() if self._generic else self._event >= len(self._events_dt)

    @property
    def failure(self) -> str | None:
        """Why the sequence stopped before its end (a failed grasp, a place position the end
        effector could not reach), or None (always None for the generic controller)."""
        return None if self._generic else self._failure

    def get_current_event(self) -> int:
        """The current phase, 0..9 (10 when done, also after a failed grasp)."""
        return self._generic.get_current_event() if self._generic else self._event

    def pause(self) -> None:
        """`forward` returns empty actions (targets kept) and the phases stop advancing."""
        self._pause = True
        if self._generic:
            self._generic.pause()

    def resume(self) -> None:
        self._pause = False
        if self._generic:
            self._generic.resume()

    def is_paused(self) -> bool:
        return self._generic.is_paused() if self._generic else self._pause

    @property
    def ik_failures(self) -> int:
        """Calls since the last reset whose IK target was not used (failed or too far)."""
        return self._ik_failures

    @property
    def end_effector_link(self) -> str:
        return self._link

    # ------------------------------------------------------------------ helpers
    def _bind(self, n_dof: int) -> None:
        names = getattr(self._robot, "dof_names", None)
        if names is None:
            raise SimulationError(f"{self.name}: the robot is not simulated yet; call world.reset() before forward()")
        if len(names) != n_dof:
            raise InvalidInputError(
                f"current_joint_positions has {n_dof} entries; {getattr(self._robot, 'name', 'the robot')} has "
                f"{len(names)} joints ({names})"
            )
        if self._arm_idx is None:
            self._arm_idx = np.array([self._robot.get_dof_index(j) for j in self._kin.joint_names], dtype=int)

    def _base_from_world(self) -> Pose:
        pose = self._robot.get_world_pose()
        if pose is None:
            raise SimulationError(f"{self.name}: the robot has no pose yet; call world.reset() before forward()")
        return Pose(np.asarray(pose[0], dtype=float), np.asarray(pose[1], dtype=float)).inverse()

    def _solve(self, base_T_world: Pose, position: np.ndarray, orientation: np.ndarray,
               seed: np.ndarray) -> np.ndarray | None:
        """Arm joints (7,) placing the end effector at the world pose, near `seed`; None if
        the local solve fails or lands farther than max_joint_step from the seed."""
        goal = base_T_world @ Pose(position, orientation)
        r = self._ik.solve(goal, link=self._link, seed_q=seed)
        if r.success and np.max(np.abs(r.q - self._q_target)) <= self._max_joint_step:
            return np.asarray(r.q, dtype=float)
        self._ik_failures += 1
        if self._failed_event != self._event:  # one warning per phase
            self._failed_event = self._event
            why = r.status.name if not r.success else f"a jump of {np.max(np.abs(r.q - self._q_target)):.3f} rad"
            logger.warning("%s: phase %d: no IK target near the previous one for the end effector at %s (%s); "
                           "holding the previous target", self.name, self._event, np.round(position, 4), why)
        return None

    def _nearer_half_turn(self, orientation: np.ndarray, q_now: np.ndarray) -> bool:
        """Whether `orientation` turned half a turn about the end effector's z axis is nearer
        the end effector's current world orientation (the same grasp for a parallel gripper)."""
        current = (self._base_from_world().inverse() @ self._kin.fk(q_now[self._arm_idx], self._link)).quaternion
        turned = quat.multiply(orientation, HALF_TURN_Z)
        return float(quat.angle_between(current, turned)) < float(quat.angle_between(current, orientation)) - 1e-9

    def _place_miss(self, target: np.ndarray) -> float | None:
        """The distance [m] of the end effector's last target from the place position, if
        more than PLACE_TOLERANCE (the IK could not follow), else None."""
        if self._q_target is None:
            return None
        tcp = self._base_from_world().inverse() @ self._kin.fk(self._q_target, self._link)
        miss = float(np.linalg.norm(tcp.position - target))
        return miss if miss > PLACE_TOLERANCE else None

    def _grasp_problem(self, obj: np.ndarray, q_now: np.ndarray, offset: np.ndarray) -> str | None:
        """Why the object at world position `obj` (3,) [m] is not held, or None: its centre
        must be within GRASP_TOLERANCE of where the end effector was sent (obj + offset), and
        the fingers must not have closed completely."""
        tcp = self._base_from_world().inverse() @ self._kin.fk(q_now[self._arm_idx], self._link)
        miss = float(np.linalg.norm(obj + offset - tcp.position))
        problems = []
        if miss > GRASP_TOLERANCE:
            problems.append(
                f"the object (picking_position {np.round(obj, 3).tolist()} m) is {miss * 100:.1f} cm from where the "
                f"end effector closed the gripper, not between the fingers")
        idx = getattr(self._gripper, "joint_dof_indices", None)
        closed = getattr(self._gripper, "joint_closed_positions", None)
        if idx is not None and closed is not None:
            fingers = q_now[np.asarray(idx, dtype=int)]
            closed = np.asarray(closed, dtype=float)
            if closed.shape == fingers.shape and np.all(np.abs(fingers - closed) < GRASP_EMPTY_GAP):
                problems.append(f"the fingers closed completely (at {np.round(fingers * 1e3, 1).tolist()} mm): "
                                "nothing is between them")
        return "; ".join(problems) if problems else None

    def _action(self, n_dof: int, arm: np.ndarray | None = None) -> ArticulationAction:
        full = np.full(n_dof, np.nan)
        if arm is not None:
            full[self._arm_idx] = arm
        return ArticulationAction(joint_positions=full)

    def _height(self, place_z: float) -> float:
        e, s = self._event, _mix(self._t)
        if e == 0:
            return self._h1
        if e == 1:
            return (1 - s) * self._h1 + s * self._h0
        if e == 4:
            return (1 - s) * self._h0 + s * self._h1
        if e == 5:
            return self._h1
        if e == 6:
            return (1 - s) * self._h1 + s * place_z
        if e == 8:
            return (1 - s) * place_z + s * self._h1
        return self._h1  # 9

    def _xy(self, place_xy: np.ndarray, base_xy: np.ndarray) -> np.ndarray:
        e = self._event
        if e in (0, 1, 4):
            return self._pick_xy
        if e != 5:
            return place_xy
        # Polar interpolation about the base: around the robot, never through it.
        s = _mix(self._t)
        a, b = self._pick_xy - base_xy, place_xy - base_xy
        ra, rb = float(np.hypot(*a)), float(np.hypot(*b))
        if min(ra, rb) < 1e-3:
            return (1 - s) * self._pick_xy + s * place_xy
        phi = (1 - s) * math.atan2(a[1], a[0]) + s * math.atan2(b[1], b[0])
        r = (1 - s) * ra + s * rb
        return base_xy + r * np.array([math.cos(phi), math.sin(phi)])

    # ------------------------------------------------------------------ control
    def forward(self, picking_position, placing_position, current_joint_positions, end_effector_offset=None,
                end_effector_orientation=None) -> ArticulationAction:
        """The action for this physics step; advances the phase progress by events_dt[phase].

        Args:
            picking_position: (3,) world position [m] of the end effector at the grasp
                (e.g. the cube's centre); followed until the descent (phase 1) ends.
            placing_position: (3,) world position [m] of the end effector at the release.
            current_joint_positions: (num_dof,) the robot's measured joint positions [rad, m].
            end_effector_offset: (3,) world offset [m] added to every end-effector target
                (default 0).
            end_effector_orientation: (4,) world orientation (w, x, y, z) of the end effector
                (default the hand pointing down, (0, 1, 0, 0)).

        Returns:
            ArticulationAction with joint_positions of length num_dof; NaN entries keep their
            targets (phase 2, paused or done: all NaN; phases 3 and 7: the gripper's action;
            a failed grasp: the gripper's "open" action, once; otherwise arm targets and NaN
            fingers).

        Raises:
            InvalidInputError: a non-finite value or a wrong shape (the state is unchanged).
            SimulationError: the robot is not simulated yet (before `world.reset()`).
        """
        if self._generic is not None:
            return self._generic.forward(picking_position, placing_position, current_joint_positions,
                                         end_effector_offset, end_effector_orientation)
        pick = vec(picking_position, 3, "picking_position")
        place = vec(placing_position, 3, "placing_position")
        q_now = np.asarray(current_joint_positions, dtype=float)
        if q_now.ndim != 1 or not np.all(np.isfinite(q_now)):
            raise InvalidInputError(
                f"current_joint_positions must be a finite 1-D array; got {current_joint_positions!r}")
        offset = np.zeros(3) if end_effector_offset is None else vec(end_effector_offset, 3, "end_effector_offset")
        if end_effector_orientation is None:
            orientation = HAND_DOWN.copy()
        else:
            orientation = unit_quat(end_effector_orientation, "end_effector_orientation")
            if not np.all(np.isfinite(orientation)):
                raise InvalidInputError(f"end_effector_orientation must be finite; got {end_effector_orientation!r}")
        n = q_now.size
        self._bind(n)
        if self._pause or self.is_done():
            return self._action(n)
        if self._symmetric_grasp:
            if self._half_turn is None:
                self._half_turn = self._nearer_half_turn(orientation, q_now)
            if self._half_turn:
                orientation = quat.multiply(orientation, HALF_TURN_Z)

        e = self._event
        if e == 7 and self._t == 0.0:
            miss = self._place_miss(place + offset)
            if miss is not None:
                self._failure = (f"the end effector could not reach the place position "
                                 f"{np.round(place + offset, 3).tolist()} m ({miss * 100:.1f} cm away; "
                                 f"{self._ik_failures} IK targets not found): the gripper stays closed")
                logger.warning("%s: %s; the sequence stops", self.name, self._failure)
                self._event = len(self._events_dt)
                return self._action(n)
        if e == 4 and self._t == 0.0 and self._check_grasp:
            problem = self._grasp_problem(pick, q_now, offset)
            if problem is not None:
                self._failure = f"the grasp failed: {problem}"
                logger.warning("%s: %s; the gripper opens and the sequence stops", self.name, self._failure)
                self._event = len(self._events_dt)
                return self._gripper.forward("open")
        if e == 2:
            action = self._action(n)
        elif e == 3:
            action = self._gripper.forward("close")
        elif e == 7:
            action = self._gripper.forward("open")
        else:
            action = self._arm_action(e, pick, place, q_now, offset, orientation)
        self._t += self._events_dt[e]
        if self._t >= 1.0 - 1e-9:
            self._event += 1
            self._t = 0.0
        return action

    def _arm_action(self, e: int, pick: np.ndarray, place: np.ndarray, q_now: np.ndarray, offset: np.ndarray,
                    orientation: np.ndarray) -> ArticulationAction:
        n = q_now.size
        base_T_world = self._base_from_world()
        world_T_base = base_T_world.inverse()
        if self._q_target is None:
            self._q_target = q_now[self._arm_idx].copy()
        if e in (0, 1):
            self._pick_xy = pick[:2].copy()
            self._h0 = float(pick[2])
        if e == 0:
            if self._q_start is None:
                self._q_start = q_now[self._arm_idx].copy()
            p = np.array([pick[0], pick[1], self._h1]) + offset
            seed = self._q_above_pick if self._q_above_pick is not None else self._q_start
            goal = base_T_world @ Pose(p, orientation)
            r = self._ik.solve(goal, link=self._link, seed_q=seed)
            if r.success and (self._q_above_pick is None
                              or np.max(np.abs(r.q - self._q_above_pick)) <= self._max_joint_step):
                self._q_above_pick = np.asarray(r.q, dtype=float)
            else:  # no solution, or the goal's solution jumped to another branch
                self._ik_failures += 1
                if self._failed_event != e:
                    self._failed_event = e
                    logger.warning("%s: phase 0: no IK solution above the pick position %s near the previous one "
                                   "(%s); keeping the previous goal", self.name, np.round(p, 4), r.status.name)
            if self._q_above_pick is None:
                return self._action(n, self._q_target)
            s = _mix(self._t + self._events_dt[0])  # the profile's value at the end of this step
            self._q_target = self._q_start + s * (self._q_above_pick - self._q_start)
            return self._action(n, self._q_target)
        # Cartesian phases: the end-effector target of the end of this step.
        saved = self._t
        self._t = min(saved + self._events_dt[e], 1.0)
        try:
            xy = self._xy(place[:2], world_T_base.position[:2])
            p = np.array([xy[0], xy[1], self._height(float(place[2]))]) + offset
        finally:
            self._t = saved
        seed = self._q_target + POSTURE_PULL * (self._rest - self._q_target)
        q = self._solve(base_T_world, p, orientation, seed)
        if q is not None:
            self._q_target = q
        return self._action(n, self._q_target)


__all__ = ["FRANKA_EVENTS_DT", "PickPlaceController"]
