"""`ArticulationController`: the implicit PD drives of an articulation (Isaac's name).

The drive law is documented in `manip.sim.articulations.articulation`; the controller edits the gains,
targets and effort limits held by the articulation's `ArticulationCore`.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim.articulations.articulation_core import ArticulationCore
from manip.sim.scenes.stage import SimulationError
from manip.sim.utils.not_supported import declare as declare_not_supported

CONTROL_MODES = ("position", "velocity", "effort")


class DrivenArticulation(Protocol):
    """What the controller drives: an object holding the compiled model's core (None before
    the World compiles), e.g. an `Articulation`."""

    core: ArticulationCore | None


class ArticulationController:
    """The implicit PD drives of an articulation (Isaac's `ArticulationController`)."""

    def __init__(self) -> None:
        self._articulation: DrivenArticulation | None = None

    def initialize(self, articulation: DrivenArticulation) -> None:
        """Attach to an articulation (done by `Articulation` when the World compiles)."""
        self._articulation = articulation

    def _core(self) -> ArticulationCore:
        if self._articulation is None or self._articulation.core is None:
            raise SimulationError("the articulation controller is used before World.reset() compiled the world")
        return self._articulation.core

    def apply_action(self, control_actions: ArticulationAction) -> None:
        """Set drive targets; they take effect from the next physics step and persist.

        A None field is untouched; a NaN (None) entry of positions/velocities keeps that
        joint's target (Isaac's behaviour); a NaN effort is 0. A position target beyond a
        joint's limit drives the joint to the limit, where it stops (the limits hold, as in
        Isaac); the target itself is kept as given.

        Raises:
            InvalidInputError: not an ArticulationAction, a length that differs from the
                number of DoF (without joint_indices) or from joint_indices, indices out
                of range, an entry of magnitude above 1e6 (positions [rad or m], velocities
                [rad/s or m/s], efforts [N m or N]) or a drive command kp * target + kd *
                velocity target above 1e9. The message names the field and the joint;
                targets are unchanged then.
        """
        self._core().apply_action(control_actions)

    def get_applied_action(self) -> ArticulationAction:
        """The current targets: positions, velocities and efforts, (num_dof,) each."""
        c = self._core()
        return ArticulationAction(c.pos_target.copy(), c.vel_target.copy(), c.efforts.copy())

    def set_gains(self, kps=None, kds=None, save_to_usd: bool = False) -> None:
        """Set the drive stiffness kps [N m/rad or N/m] and damping kds [N m s/rad or N s/m], (num_dof,)."""
        c = self._core()
        idx = np.arange(c.n)
        new_kp = c.values(kps, idx, "kps") if kps is not None else c.kps
        new_kd = c.values(kds, idx, "kds") if kds is not None else c.kds
        if np.any(new_kp < 0) or np.any(new_kd < 0):
            raise InvalidInputError(f"gains must be >= 0; got kps={new_kp}, kds={new_kd}")
        c.check_drive(new_kp, new_kd, c.pos_target, c.vel_target, "kps/kds")
        c.kps, c.kds = new_kp.copy(), new_kd.copy()
        c.write_gains()

    def get_gains(self) -> tuple[np.ndarray, np.ndarray]:
        """(kps, kds), (num_dof,) each."""
        c = self._core()
        return c.kps.copy(), c.kds.copy()

    def switch_control_mode(self, mode: str, joint_indices=None) -> None:
        """Switch drives to "position" (default gains), "velocity" (kp = 0, default kd; if
        the default kd is 0, kd = 10 * default kp or 1e3) or "effort" (kp = kd = 0).

        As in Isaac, only the gains change: the position and velocity targets stay as last
        applied. After moving in velocity mode, switching back to "position" drives the joints
        back to the old position target with the old velocity target still set (on the Franka
        the drives then saturate at their 87 N m); apply the current positions and zero
        velocities first: `apply_action(ArticulationAction(joint_positions=q, joint_velocities=zeros))`.
        """
        if mode not in CONTROL_MODES:
            raise InvalidInputError(f"unknown control mode {mode!r}; valid: {list(CONTROL_MODES)}")
        c = self._core()
        idx = c.indices(joint_indices)
        kp, kd = c.kps.copy(), c.kds.copy()
        if mode == "position":
            kp[idx], kd[idx] = c.default_kps[idx], c.default_kds[idx]
        elif mode == "velocity":
            dkd = c.default_kds[idx]
            kp[idx] = 0.0
            kd[idx] = np.where(dkd > 0, dkd, np.where(c.default_kps[idx] > 0, 10 * c.default_kps[idx], 1e3))
        else:
            kp[idx], kd[idx] = 0.0, 0.0
        c.kps, c.kds = kp, kd
        c.write_gains()

    def switch_dof_control_mode(self, dof_index: int, mode: str) -> None:
        """`switch_control_mode` for one DoF."""
        self.switch_control_mode(mode, [dof_index])

    def set_max_efforts(self, values, joint_indices=None) -> None:
        """Clip of each drive's force [N m or N] (> 0; inf = unlimited)."""
        c = self._core()
        idx = c.indices(joint_indices)
        try:
            v = np.asarray(values, dtype=float).ravel()
        except (TypeError, ValueError) as exc:
            raise InvalidInputError(
                f"values (max efforts) must be {idx.size} positive numbers; got {values!r}") from exc
        if v.size != idx.size or np.any(np.isnan(v)) or np.any(v <= 0):
            raise InvalidInputError(f"values (max efforts) must be {idx.size} positive values; got {values!r}")
        c.max_efforts = c.max_efforts.copy()
        c.max_efforts[idx] = v
        c.write_gains()

    def get_max_efforts(self) -> np.ndarray:
        return self._core().max_efforts.copy()

    def get_joint_limits(self) -> np.ndarray:
        """(num_dof, 2) lower and upper position limits (-inf/inf if unlimited)."""
        c = self._core()
        return np.stack([c.lower, c.upper], axis=1)


declare_not_supported(ArticulationController)
