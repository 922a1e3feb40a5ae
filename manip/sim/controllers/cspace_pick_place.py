"""Isaac's generic pick-and-place state machine driving a c-space controller of the user's.

Isaac Sim has two `PickPlaceController`s: the Franka's (`omni.isaac.franka.controllers`,
manip's `pick_place_controller.py`) and the base class of the manipulators extension
(`omni.isaac.manipulators.controllers` / `isaacsim.robot.manipulators.controllers`),
`PickPlaceController(name, cspace_controller, gripper, end_effector_initial_height=None,
events_dt=None)`, which a new robot's tutorial subclasses with an RMPflow controller of its own.
`manip.sim.PickPlaceController` called with a `cspace_controller` runs this one: Isaac's ten
phases (see `pick_place_controller.py`), each advancing `t` by its `events_dt` entry per call;
phases 2, 3 and 7 return "nothing", the gripper's "close" and its "open" action; the others
send an end-effector position target to `cspace_controller.forward(target_end_effector_position=...,
target_end_effector_orientation=...)`, moving as Isaac's: the height along a cosine profile
between h1 (`end_effector_initial_height`), the pick height and the place height, the
horizontal position in a straight line from the pick to the place position during phase 5.
"""

from __future__ import annotations

import math

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim.controllers.base_controller import BaseController
from manip.validation import unit_quat, vec

#: Isaac's default events_dt of the generic controller (the Franka's values).
DEFAULT_EVENTS_DT = (0.008, 0.005, 0.1, 0.1, 0.0025, 0.001, 0.0025, 1.0, 0.008, 0.08)
#: Isaac's default end-effector orientation, euler (0, pi, 0): (w, x, y, z).
DEFAULT_ORIENTATION = np.array([0.0, 0.0, 1.0, 0.0])


def _mix(t: float) -> float:
    return 0.5 * (1.0 - math.cos(t * math.pi))


def is_cspace_controller(value) -> bool:
    """True for a c-space controller (a `BaseController`-like with `forward`, not a gripper)."""
    return isinstance(value, BaseController) or (callable(getattr(value, "forward", None))
                                                 and not hasattr(value, "get_joint_positions")
                                                 and not hasattr(value, "open"))


class CspacePickPlace:
    """Isaac's generic pick-and-place phases (one `forward` call per physics step).

    Args:
        name: controller name.
        cspace_controller: turns an end-effector target into an ArticulationAction
            (`forward(target_end_effector_position=(3,), target_end_effector_orientation=(4,))`,
            world frame, quaternion (w, x, y, z)); e.g. `RMPFlowController(name, robot)`.
        gripper: the robot's gripper (`forward("open" | "close")` -> ArticulationAction).
        end_effector_initial_height: h1 [m] (default 0.3).
        events_dt: (10,) progress per call of each phase, each in (0, 1] (default Isaac's).

    Raises:
        InvalidInputError: a controller without `forward`, a gripper without `forward`, bad
            events_dt or height.
    """

    def __init__(self, name: str, cspace_controller, gripper, end_effector_initial_height=None, events_dt=None):
        if not callable(getattr(cspace_controller, "forward", None)):
            raise InvalidInputError(f"{name}: cspace_controller must be a controller with forward(target_end_effector_"
                                    f"position, target_end_effector_orientation); got {type(cspace_controller).__name__}")
        if not callable(getattr(gripper, "forward", None)):
            raise InvalidInputError(f"{name}: gripper must have forward('open' | 'close') (a ParallelGripper, a "
                                    f"SurfaceGripper); got {type(gripper).__name__}")
        self.name = name
        self.cspace_controller = cspace_controller
        self.gripper = gripper
        self._h1 = 0.3 if end_effector_initial_height is None else self._height_arg(end_effector_initial_height)
        self._events_dt = self._events_arg(DEFAULT_EVENTS_DT if events_dt is None else events_dt)
        self._event, self._t, self._pause = 0, 0.0, False
        self._h0 = 0.0
        self._xy = np.zeros(2)

    @staticmethod
    def _height_arg(h) -> float:
        v = float(h)
        if not math.isfinite(v):
            raise InvalidInputError(f"end_effector_initial_height must be a finite height [m]; got {h!r}")
        return v

    @staticmethod
    def _events_arg(events_dt) -> list[float]:
        a = np.asarray(events_dt, dtype=float)
        if a.shape != (10,) or not np.all(np.isfinite(a)) or np.any(a <= 0) or np.any(a > 1):
            raise InvalidInputError(f"events_dt must be 10 numbers in (0, 1] (progress per call of each phase); "
                                    f"got {events_dt!r}")
        return [float(x) for x in a]

    def forward(self, picking_position, placing_position, current_joint_positions, end_effector_offset=None,
                end_effector_orientation=None) -> ArticulationAction:
        """The action of this physics step (Isaac's arguments; world positions [m])."""
        pick = vec(picking_position, 3, "picking_position")
        place = vec(placing_position, 3, "placing_position")
        n = np.asarray(current_joint_positions).shape[0]
        offset = np.zeros(3) if end_effector_offset is None else vec(end_effector_offset, 3, "end_effector_offset")
        orientation = (DEFAULT_ORIENTATION if end_effector_orientation is None
                       else unit_quat(end_effector_orientation, "end_effector_orientation"))
        if self._pause or self.is_done():
            self._pause = True
            return ArticulationAction(joint_positions=np.full(n, np.nan))
        e = self._event
        if e == 2:
            action = ArticulationAction(joint_positions=np.full(n, np.nan))
        elif e in (3, 7):
            action = self.gripper.forward(action="close" if e == 3 else "open")
        else:
            if e in (0, 1):
                self._xy = pick[:2].copy()
                self._h0 = float(pick[2])
            alpha = 0.0 if e < 5 else (_mix(self._t) if e == 5 else 1.0)
            xy = (1.0 - alpha) * self._xy + alpha * place[:2]
            target = np.array([xy[0], xy[1], self._target_height(float(place[2]))]) + offset
            action = self.cspace_controller.forward(target_end_effector_position=target,
                                                    target_end_effector_orientation=orientation)
        self._t += self._events_dt[e]
        if self._t >= 1.0:
            self._event += 1
            self._t = 0.0
        return action

    def _target_height(self, place_z: float) -> float:
        e, a = self._event, _mix(max(0.0, self._t))
        h0, h1 = self._h0, self._h1
        return {0: h1, 1: (1 - a) * h1 + a * h0, 3: h0, 4: (1 - a) * h0 + a * h1, 5: h1,
                6: (1 - a) * h1 + a * place_z, 7: place_z, 8: (1 - a) * place_z + a * h1, 9: h1}[e]

    def reset(self, end_effector_initial_height=None, events_dt=None) -> None:
        """Phase 0 again (the c-space controller reset too); optionally a new h1 [m] and events_dt."""
        if end_effector_initial_height is not None:
            self._h1 = self._height_arg(end_effector_initial_height)
        if events_dt is not None:
            self._events_dt = self._events_arg(events_dt)
        self.cspace_controller.reset()
        self._event, self._t, self._pause = 0, 0.0, False

    def is_done(self) -> bool:
        return self._event >= len(self._events_dt)

    def get_current_event(self) -> int:
        return self._event

    def pause(self) -> None:
        self._pause = True

    def resume(self) -> None:
        self._pause = False

    def is_paused(self) -> bool:
        return self._pause
