"""`ArticulationView`: Isaac's batched articulation API over one articulation (`robot._articulation_view`).

Isaac's `SingleArticulation` keeps an `ArticulationView` of count 1 as `_articulation_view`;
tutorials read gains, joint counts and limits through it. Here it is a thin view of the
articulation's drives (`ArticulationCore`): getters return arrays with a leading batch axis
of size 1, e.g. `get_gains()` -> (kps (1, num_dof), kds (1, num_dof)).

Differences from Isaac: one articulation only (`indices` may be None or [0]); `num_joints`
counts one joint per body below the articulation's root (fixed joints included, as USD
does), since MuJoCo merges no bodies but has no fixed-joint objects.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.articulation_core import ArticulationCore
from manip.sim.stage import SimulationError


class ViewedArticulation(Protocol):
    """What the view reads: the articulation's core (None before the World compiles)."""

    prim_path: str
    _core: ArticulationCore | None


class ArticulationView:
    """Batched (count 1) access to one articulation's joints and drives.

    Args:
        articulation: the `Articulation` viewed.
    """

    def __init__(self, articulation: ViewedArticulation):
        self._articulation = articulation

    def _c(self, what: str) -> ArticulationCore:
        c = self._articulation._core
        if c is None:
            raise SimulationError(f"articulation view {self.prim_paths[0]!r}: {what} before world.reset()")
        return c

    @staticmethod
    def _check_indices(indices) -> None:
        if indices is not None and np.asarray(indices).ravel().tolist() not in ([0], []):
            raise InvalidInputError(f"this view holds one articulation (index 0); got indices {indices!r}")

    # ------------------------------------------------------------------ description
    @property
    def prim_paths(self) -> list[str]:
        return [self._articulation.prim_path]

    @property
    def count(self) -> int:
        return 1

    @property
    def num_dof(self) -> int:
        return self._c("num_dof").n

    @property
    def num_bodies(self) -> int:
        return len(self._c("num_bodies").body_ids)

    @property
    def num_joints(self) -> int:
        """Joints of the articulation, fixed ones included: one per body below a root body."""
        c = self._c("num_joints")
        return len(c.body_ids) - len(c.root_ids)

    @property
    def dof_names(self) -> list[str]:
        return list(self._c("dof_names").dof_names)

    @property
    def body_names(self) -> list[str]:
        return list(self._c("body_names").body_names)

    def get_dof_index(self, dof_name: str) -> int:
        names = self.dof_names
        if dof_name not in names:
            raise InvalidInputError(f"no joint {dof_name!r}; joints: {names}")
        return names.index(dof_name)

    def is_physics_handle_valid(self) -> bool:
        return self._articulation._core is not None

    # ------------------------------------------------------------------ drives
    def get_gains(self, indices=None, joint_indices=None, clone: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Drive stiffness and damping: (kps (1, K), kds (1, K)) for the joints `joint_indices` (all for None)."""
        self._check_indices(indices)
        c = self._c("get_gains")
        idx = c.indices(joint_indices)
        return c.kps[idx][None, :].copy(), c.kds[idx][None, :].copy()

    def set_gains(self, kps=None, kds=None, indices=None, joint_indices=None, save_to_usd: bool = False) -> None:
        """Set drive stiffness `kps` and damping `kds`, (1, K) or (K,) each, of `joint_indices` (all for None).

        Raises:
            InvalidInputError: wrong shape, a negative or non-finite gain.
        """
        self._check_indices(indices)
        c = self._c("set_gains")
        idx = c.indices(joint_indices)
        new_kp, new_kd = c.kps.copy(), c.kds.copy()
        if kps is not None:
            new_kp[idx] = c.values(kps, idx, "kps")
        if kds is not None:
            new_kd[idx] = c.values(kds, idx, "kds")
        if np.any(new_kp < 0) or np.any(new_kd < 0):
            raise InvalidInputError("gains must be >= 0")
        c.check_drive(new_kp, new_kd, c.pos_target, c.vel_target, "kps/kds")
        c.kps, c.kds = new_kp, new_kd
        c.write_gains()

    def get_max_efforts(self, indices=None, joint_indices=None, clone: bool = True) -> np.ndarray:
        """Drive force limits (1, K) [N m or N] (inf = unlimited)."""
        self._check_indices(indices)
        c = self._c("get_max_efforts")
        return c.max_efforts[c.indices(joint_indices)][None, :].copy()

    def get_dof_limits(self) -> np.ndarray:
        """(1, num_dof, 2) lower and upper joint limits [rad or m]."""
        c = self._c("get_dof_limits")
        return np.stack([c.lower, c.upper], axis=1)[None, :, :]

    def get_joint_max_velocities(self, indices=None, joint_indices=None, clone: bool = True) -> np.ndarray:
        """(1, K) joint velocity limits [rad/s or m/s] (inf where the model gives none)."""
        self._check_indices(indices)
        c = self._c("get_joint_max_velocities")
        return c.max_velocities[c.indices(joint_indices)][None, :].copy()

    # ------------------------------------------------------------------ state
    def get_joint_positions(self, indices=None, joint_indices=None, clone: bool = True) -> np.ndarray:
        """(1, K) joint positions [rad or m]."""
        self._check_indices(indices)
        c = self._c("get_joint_positions")
        return c.sim.data.qpos[c.qadr[c.indices(joint_indices)]][None, :].copy()

    def get_joint_velocities(self, indices=None, joint_indices=None, clone: bool = True) -> np.ndarray:
        """(1, K) joint velocities [rad/s or m/s]."""
        self._check_indices(indices)
        c = self._c("get_joint_velocities")
        return c.sim.data.qvel[c.dadr[c.indices(joint_indices)]][None, :].copy()

    def __repr__(self) -> str:
        return f"ArticulationView(prim_paths={self.prim_paths})"
