"""MuJoCo's warnings as Python ones, after every physics step (`SimulationContext.step`).

NaN, infinite or huge (> 1e10) positions, velocities or accelerations (MuJoCo then resets
the physics state to the compiled initial state) and bad controls (MuJoCo then ignores every
control) are fatal: `WarningMonitor.check` returns their message, which the World raises as
`SimulationInstabilityError` naming the joint or actuator. A full contact or constraint
buffer and a bad inertia issue a `SimulationWarning` (`warnings.warn`).
"""

from __future__ import annotations

import warnings

import mujoco
import numpy as np

from manip.sim.scenes.stage import SimulationError

__all__ = ["SimulationInstabilityError", "SimulationWarning", "WarningMonitor"]


class SimulationInstabilityError(SimulationError):
    """MuJoCo found the simulation numerically unstable (NaN, infinite or huge values) in a
    physics step and reset its state or ignored the controls; the message says where."""


class SimulationWarning(UserWarning):
    """A MuJoCo warning that does not stop the simulation (e.g. a full contact buffer)."""


_W = mujoco.mjtWarning
#: MuJoCo warnings that mean the physics state is lost: what MuJoCo did, and what was bad.
_FATAL_WARNINGS = {
    int(_W.mjWARN_BADQPOS): ("positions", "DoF"),
    int(_W.mjWARN_BADQVEL): ("velocities", "DoF"),
    int(_W.mjWARN_BADQACC): ("accelerations", "DoF"),
    int(_W.mjWARN_BADCTRL): ("controls", "actuator"),
}
_MILD_WARNINGS = {
    int(_W.mjWARN_INERTIA): "a body has a mass or an inertia too small or invalid (body index {info})",
    int(_W.mjWARN_CONTACTFULL): "the contact buffer is full: contacts were dropped (increase the model's nconmax "
                                "/ memory)",
    int(_W.mjWARN_CNSTRFULL): "the constraint buffer is full: constraints were dropped (increase the model's "
                              "njmax / memory)",
}


class WarningMonitor:
    """MuJoCo's warning counts of one simulation's data, each warning reported once."""

    def __init__(self) -> None:
        self._counts = np.zeros(0, dtype=np.int32)
        self._set_seen(np.zeros(0))

    def watch(self, data: mujoco.MjData) -> None:
        """Follow `data`'s warning counts (a view: MjData's buffers never move); none seen yet."""
        self._counts = data.warning.number
        self.reset()

    def unwatch(self) -> None:
        """Let go of the data's view: the view kept the whole MjData (and with the model about
        15 MB for a Franka and a cube) alive as long as the World, and a cleared World is in
        reference cycles that only the cyclic collector's rare full passes free: RSS crept by
        20-30 KB per rebuild (tests/sim/test_rebuild_memory.py)."""
        self._counts = np.zeros(0, dtype=np.int32)

    def reset(self) -> None:
        """No warning reported yet (after a reset of the data)."""
        self._set_seen(np.zeros(int(_W.mjNWARNING)))

    def check(self, model: mujoco.MjModel, data: mujoco.MjData, time: float) -> str | None:
        """Report the warnings raised since the last check: a `SimulationWarning` for each new
        mild one; the message of the first fatal one (its count is cleared) or None. `time`:
        the simulation time [s], for the message."""
        counts = self._counts
        if counts.tobytes() == self._seen_bytes:  # the usual case, fast
            return None
        stats = data.warning
        new = counts - self._seen
        new = np.where(new < 0, counts, new)  # counts cleared by a reset of the data
        fatal = None
        for kind in np.flatnonzero(new):
            kind = int(kind)
            info = int(stats.lastinfo[kind])
            if kind in _FATAL_WARNINGS and fatal is None:
                fatal = _fatal_message(model, kind, info, time)
            elif kind in _MILD_WARNINGS:
                warnings.warn(f"MuJoCo: {_MILD_WARNINGS[kind].format(info=info)}", SimulationWarning, stacklevel=3)
        for kind in _FATAL_WARNINGS:
            counts[kind] = 0  # so that the next one is seen (and MuJoCo prints it again)
        self._set_seen(counts)
        return fatal

    def _set_seen(self, counts: np.ndarray) -> None:
        """MuJoCo's warning counts (mjNWARNING,) that are reported already."""
        self._seen = np.array(counts, dtype=np.int32)  # MuJoCo's type (int)
        self._seen_bytes = self._seen.tobytes()


def _fatal_message(m: mujoco.MjModel, kind: int, info: int, time: float) -> str:
    what, unit = _FATAL_WARNINGS[kind]
    if unit == "DoF":
        where = f"DoF {info}"
        if 0 <= info < m.nv:
            where += f" (joint {m.joint(int(m.dof_jntid[info])).name!r})"
    else:
        where = f"actuator {info}"
        if 0 <= info < m.nu:
            where += f" ({m.actuator(info).name!r})"
    t = f"{time:.4f} s"
    if kind == int(_W.mjWARN_BADCTRL):
        done = ("MuJoCo ignored every control in that step. Controls come from the drive targets and gains "
                "(checked by the articulation API); a control written to world.data.ctrl directly is not checked")
    else:
        done = ("MuJoCo reset the physics state to the compiled model's initial state. Usual causes: huge "
                "efforts, velocities or gains, or objects placed deep inside each other")
    return (f"the simulation became unstable at t = {t}: NaN, infinite or huge (> 1e10) {what} at {where}. "
            f"{done}. The drive targets are now the current joint positions and the efforts 0; call "
            "world.reset() to restart from the default states.")
