"""`Pose`: a rigid transform as a position [m] and a (w, x, y, z) unit quaternion.

A Pose is single (position (3,), quaternion (4,)) or batched (position (N, 3),
quaternion (N, 4)). Name poses by frames: `T_world_tcp = T_world_base @ T_base_tcp`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from manip import curobo_names
from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.validation import as_real_array

IDENTITY_QUATERNION = np.array([1.0, 0.0, 0.0, 0.0])


@dataclass(frozen=True, eq=False)
class Pose:
    """A rigid transform (or a batch of them).

    Args:
        position: (3,) or (N, 3) translation [m].
        quaternion: (4,) or (N, 4) rotation as (w, x, y, z); defaults to identity. Norms
            within 1e-3 of 1 are normalised; anything further raises InvalidInputError.
    """

    position: np.ndarray
    quaternion: np.ndarray = (1.0, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        p = np.array(as_real_array(self.position, "Pose position"), dtype=float)
        q = np.array(as_real_array(self.quaternion, "Pose quaternion"), dtype=float)
        if p.ndim not in (1, 2) or p.shape[-1] != 3:
            raise InvalidInputError(f"Pose position must have shape (3,) or (N, 3); got {p.shape}")
        if not np.all(np.isfinite(p)):
            raise InvalidInputError(f"Pose position has non-finite values: {p}")
        if q.ndim not in (1, 2) or q.shape[-1] != 4:
            raise InvalidInputError(
                f"Pose quaternion must have shape (4,) or (N, 4) in (w, x, y, z) order; got {q.shape}"
            )
        q = quat.normalize(q, what="Pose quaternion")
        if p.ndim == 2 and q.ndim == 1:
            q = np.broadcast_to(q, (p.shape[0], 4)).copy()
        if p.ndim == 1 and q.ndim == 2:
            p = np.broadcast_to(p, (q.shape[0], 3)).copy()
        if p.ndim == 2 and p.shape[0] != q.shape[0]:
            raise InvalidInputError(
                f"Pose batch sizes differ: {p.shape[0]} positions, {q.shape[0]} quaternions"
            )
        p.setflags(write=False)
        q.setflags(write=False)
        object.__setattr__(self, "position", p)
        object.__setattr__(self, "quaternion", q)

    # ------------------------------------------------------------------ construction
    @classmethod
    def _trusted(cls, position: np.ndarray, quaternion: np.ndarray) -> Pose:
        """A Pose from arrays already known valid (finite float position (3,) / (N, 3), unit
        quaternions of matching shape), e.g. computed by the kinematics: no checks, no copies."""
        pose = object.__new__(cls)
        position.setflags(write=False)
        quaternion.setflags(write=False)
        object.__setattr__(pose, "position", position)
        object.__setattr__(pose, "quaternion", quaternion)
        return pose

    @classmethod
    def identity(cls, n: int | None = None) -> Pose:
        """The identity transform, or a batch of `n` of them."""
        if n is None:
            return cls(np.zeros(3), IDENTITY_QUATERNION)
        return cls(np.zeros((n, 3)), np.tile(IDENTITY_QUATERNION, (n, 1)))

    @classmethod
    def from_matrix(cls, T: np.ndarray) -> Pose:
        """From a homogeneous transform (4, 4) or a batch (N, 4, 4)."""
        T = as_real_array(T, "matrix")
        if T.shape[-2:] != (4, 4) or T.ndim not in (2, 3):
            raise InvalidInputError(f"matrix must have shape (4, 4) or (N, 4, 4); got {T.shape}")
        if not np.all(np.isfinite(T)):
            raise InvalidInputError("matrix has non-finite values")
        R = T[..., :3, :3]
        err = np.abs(R @ np.swapaxes(R, -1, -2) - np.eye(3)).max()
        if err > 1e-4:
            raise InvalidInputError(f"matrix rotation block is not orthonormal (|R R^T - I| = {err:.2e})")
        return cls(T[..., :3, 3], quat.from_matrix(R))

    @classmethod
    def from_xyz_xyzw(cls, v: Sequence[float] | np.ndarray) -> Pose:
        """From [x, y, z, qx, qy, qz, qw] (7,) or (N, 7): the ROS / cuRobo-wrapper order."""
        v = as_real_array(v, "pose [x, y, z, qx, qy, qz, qw]")
        if v.ndim not in (1, 2) or v.shape[-1] != 7:
            raise InvalidInputError(f"expected [x, y, z, qx, qy, qz, qw] of shape (7,) or (N, 7); got {v.shape}")
        norm = np.linalg.norm(v[..., 3:], axis=-1)
        bad = np.abs(norm - 1.0) > quat.UNIT_NORM_TOLERANCE   # said here: Pose would name its (w, x, y, z) order
        if np.any(bad):
            raise InvalidInputError(
                f"pose [x, y, z, qx, qy, qz, qw]: the quaternion's norm must be 1 within {quat.UNIT_NORM_TOLERANCE} "
                f"(got {norm[bad].ravel()[:5]}); quaternions here are (x, y, z, w), normalise yours first")
        return cls(v[..., :3], quat.xyzw_to_wxyz(v[..., 3:]))

    @classmethod
    def from_xyz_wxyz(cls, v: Sequence[float] | np.ndarray) -> Pose:
        """From [x, y, z, qw, qx, qy, qz] (7,) or (N, 7): cuRobo's world-config order."""
        v = as_real_array(v, "pose [x, y, z, qw, qx, qy, qz]")
        if v.ndim not in (1, 2) or v.shape[-1] != 7:
            raise InvalidInputError(f"expected [x, y, z, qw, qx, qy, qz] of shape (7,) or (N, 7); got {v.shape}")
        return cls(v[..., :3], v[..., 3:])

    @classmethod
    def from_list(cls, v: Sequence[float] | np.ndarray) -> Pose:
        """cuRobo's `Pose.from_list`: the same as `from_xyz_wxyz` ([x, y, z, qw, qx, qy, qz])."""
        return cls.from_xyz_wxyz(v)

    @classmethod
    def stack(cls, poses: Sequence[Pose]) -> Pose:
        """Batch single poses (or concatenate batches) into one batched Pose."""
        if len(poses) == 0:
            raise InvalidInputError("poses: cannot stack an empty list of poses")
        bad = [type(p).__name__ for p in poses if not isinstance(p, Pose)]
        if bad:
            raise InvalidInputError(f"poses must be manip.Pose values; got {bad[0]}")
        return cls(
            np.concatenate([np.atleast_2d(p.position) for p in poses]),
            np.concatenate([np.atleast_2d(p.quaternion) for p in poses]),
        )

    # ------------------------------------------------------------------ conversion
    @property
    def is_batch(self) -> bool:
        """True for a batched pose (position (N, 3))."""
        return self.position.ndim == 2

    def __len__(self) -> int:
        if not self.is_batch:
            raise TypeError("a single Pose has no len(); check `is_batch`")
        return self.position.shape[0]

    def __getitem__(self, index) -> Pose:
        if not self.is_batch:
            raise TypeError("a single Pose cannot be indexed")
        return Pose(self.position[index], self.quaternion[index])

    def __iter__(self):
        for i in range(len(self)):
            yield self[i]

    @property
    def rotation(self) -> np.ndarray:
        """Rotation matrix (3, 3) or (N, 3, 3)."""
        return quat.to_matrix(self.quaternion)

    def as_matrix(self) -> np.ndarray:
        """Homogeneous transform (4, 4) or (N, 4, 4)."""
        batch = self.position.shape[:-1]
        T = np.zeros((*batch, 4, 4))
        T[..., :3, :3] = self.rotation
        T[..., :3, 3] = self.position
        T[..., 3, 3] = 1.0
        return T

    def to_xyz_xyzw(self) -> np.ndarray:
        """[x, y, z, qx, qy, qz, qw] (7,) or (N, 7)."""
        return np.concatenate([self.position, quat.wxyz_to_xyzw(self.quaternion)], axis=-1)

    def to_xyz_wxyz(self) -> np.ndarray:
        """[x, y, z, qw, qx, qy, qz] (7,) or (N, 7)."""
        return np.concatenate([self.position, self.quaternion], axis=-1)

    # ------------------------------------------------------------------ algebra
    def __matmul__(self, other: Pose) -> Pose:
        """Composition: (A @ B) maps B's frame through A (T_a_c = T_a_b @ T_b_c)."""
        if isinstance(other, (np.ndarray, list, tuple)):
            raise InvalidInputError(f"Pose @ {type(other).__name__}: `@` composes two Poses; map points (..., 3) "
                                    "with pose.transform_points(points)")
        if not isinstance(other, Pose):
            return NotImplemented
        if self.is_batch and other.is_batch and len(self) != len(other):
            raise InvalidInputError(f"cannot compose batches of {len(self)} and {len(other)} poses")
        p = self.position + np.einsum("...ij,...j->...i", self.rotation, other.position)
        return Pose(p, quat.multiply(self.quaternion, other.quaternion))

    def inverse(self) -> Pose:
        """The inverse transform."""
        q_inv = quat.conjugate(self.quaternion)
        p = -np.einsum("...ij,...j->...i", quat.to_matrix(q_inv), self.position)
        return Pose(p, q_inv)

    def transform_points(self, points: np.ndarray) -> np.ndarray:
        """Apply a single pose to points (..., 3)."""
        if self.is_batch:
            raise InvalidInputError("transform_points needs a single pose")
        pts = as_real_array(points, "points")
        if pts.ndim == 0 or pts.shape[-1] != 3:
            raise InvalidInputError(f"points must have shape (..., 3); got {pts.shape}")
        return pts @ self.rotation.T + self.position

    def distance(self, other: Pose) -> tuple[np.ndarray, np.ndarray]:
        """(position error [m], rotation angle [rad]) between this pose and `other`."""
        if not isinstance(other, Pose):
            raise InvalidInputError(f"other must be a manip.Pose; got {type(other).__name__}")
        dp = np.linalg.norm(self.position - other.position, axis=-1)
        return dp, quat.angle_between(self.quaternion, other.quaternion)

    def isclose(self, other: Pose, position_tol: float = 1e-9, rotation_tol: float = 1e-9) -> bool:
        """True when every pose is within the tolerances [m], [rad] of `other`."""
        dp, dr = self.distance(other)
        return bool(np.all(dp <= position_tol) and np.all(dr <= rotation_tol))

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's (to_list, get_matrix, ...) say where manip has them
        if name.startswith("_"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.POSE, name)

    def __repr__(self) -> str:
        if self.is_batch:
            return f"Pose(batch of {len(self)})"
        p = np.array2string(self.position, precision=4, separator=", ")
        q = np.array2string(self.quaternion, precision=4, separator=", ")
        return f"Pose(position={p}, quaternion(wxyz)={q})"
