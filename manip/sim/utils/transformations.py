"""Isaac's `omni.isaac.core.utils.transformations` (`isaacsim.core.utils.transformations`):
4x4 homogeneous transforms from poses and back, and relative transforms between prims.

Matrices are column-major as Isaac's: `T @ [x, y, z, 1]` maps a point of the frame into its
parent (the translation in `T[:3, 3]`). Quaternions are (w, x, y, z). A prim is what
`get_prim_at_path` returns (a shape, an XFormPrim, a Camera, a robot), the wrapper object
itself, or a prim path string (Isaac 5's experimental utilities take paths too): a robot's
link is given by its path ("/World/Franka/panda_hand"), read from the simulation (after
`world.reset()`). As USD's, a prim's transform includes its scale; a Camera's frame is USD's
camera frame (-z forward, +y up), as Isaac's camera prim.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from manip import quaternion as qmath
from manip.errors import InvalidInputError


def _vector(value, n: int, what: str) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be {n} finite numbers; got {value!r}")
    return a


def _unit(orientation, what: str = "orientation") -> np.ndarray:
    q = _vector(orientation, 4, f"{what} (a quaternion w, x, y, z)")
    norm = np.linalg.norm(q)
    if abs(norm - 1.0) > 1e-3:
        raise InvalidInputError(f"{what} must be a unit quaternion (w, x, y, z); got norm {norm:.4f}")
    return q / norm


def _matrix(transformation, what: str = "transformation") -> np.ndarray:
    T = np.asarray(transformation, dtype=float)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        raise InvalidInputError(f"{what} must be a finite (4, 4) matrix; got shape {T.shape}")
    return T


def tf_matrix_from_pose(translation: Sequence[float], orientation: Sequence[float]) -> np.ndarray:
    """The (4, 4) transform of a pose: `translation` (3,) [m], `orientation` (4,) (w, x, y, z)."""
    T = np.eye(4)
    T[:3, :3] = qmath.to_matrix(_unit(orientation))
    T[:3, 3] = _vector(translation, 3, "translation")
    return T


def pose_from_tf_matrix(transformation) -> tuple[np.ndarray, np.ndarray]:
    """(translation (3,) [m], orientation (4,) (w, x, y, z)) of a (4, 4) transform (its rotation
    part normalised first: a scaled transform gives its pose)."""
    T = get_transform_with_normalized_rotation(_matrix(transformation))
    return T[:3, 3].copy(), qmath.from_matrix(T[:3, :3])


def tf_matrices_from_poses(translations, orientations) -> np.ndarray:
    """(N, 4, 4) transforms of N poses: `translations` (N, 3) [m], `orientations` (N, 4) (w, x, y, z)."""
    t = np.asarray(translations, dtype=float)
    q = np.asarray(orientations, dtype=float)
    if t.ndim != 2 or t.shape[1] != 3 or q.shape != (len(t), 4):
        raise InvalidInputError(f"translations must be (N, 3) and orientations (N, 4); got {t.shape} and {q.shape}")
    return np.stack([tf_matrix_from_pose(a, b) for a, b in zip(t, q)]) if len(t) else np.zeros((0, 4, 4))


def get_transform_with_normalized_rotation(transform) -> np.ndarray:
    """`transform` (4, 4) with the columns of its rotation part made unit (its scale removed)."""
    T = _matrix(transform, "transform").copy()
    norms = np.linalg.norm(T[:3, :3], axis=0)
    if np.any(norms < 1e-12):
        raise InvalidInputError(f"transform has a zero column in its rotation part (column norms {norms})")
    T[:3, :3] /= norms
    return T


def prim_to_world(prim) -> np.ndarray:
    """The (4, 4) transform from `prim`'s frame to the world (with its scale; see the module
    docstring for what a prim may be)."""
    from manip.sim.scenes.stage import get_current_stage
    from manip.sim.sensors.camera import Camera

    if prim is None:
        raise InvalidInputError("prim is None (get_prim_at_path found nothing there): give an existing prim, its "
                                "wrapper, or the path of a robot's link (read from the simulation after world.reset())")
    stage = get_current_stage()
    path = prim if isinstance(prim, str) else getattr(prim, "prim_path", None)
    obj = stage.get_prim(path) if isinstance(prim, str) else prim
    if obj is not None and hasattr(obj, "get_world_pose"):
        position, orientation = obj.get_world_pose(camera_axes="usd") if isinstance(obj, Camera) \
            else obj.get_world_pose()
        T = tf_matrix_from_pose(position, orientation)
        scale = obj.get_world_scale() if hasattr(obj, "get_world_scale") else np.ones(3)
        T[:3, :3] *= np.asarray(scale, dtype=float)
        return T
    sim = stage.sim
    body = -1 if sim is None or path is None else mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_BODY, path)
    if body >= 0:
        sim.ensure_kinematics()
        T = np.eye(4)
        T[:3, :3] = sim.data.xmat[body].reshape(3, 3)
        T[:3, 3] = sim.data.xpos[body]
        return T
    if obj is not None and hasattr(obj, "position"):  # a referenced model not simulated yet: its authored pose
        return tf_matrix_from_pose(obj.position, obj.orientation)
    raise InvalidInputError(f"no prim at {path!r}: give a prim of the stage, its wrapper, or a robot link's path "
                            "(links are read from the simulation: after world.reset())")


def get_relative_transform(source_prim, target_prim) -> np.ndarray:
    """The (4, 4) transform from `source_prim`'s frame to `target_prim`'s: it maps a point given
    in the source's frame to the same point in the target's."""
    return np.linalg.inv(prim_to_world(target_prim)) @ prim_to_world(source_prim)


def get_translation_from_target(translation_from_source, source_prim, target_prim) -> np.ndarray:
    """A point (3,) [m] given in `source_prim`'s frame, in `target_prim`'s frame."""
    p = np.append(_vector(translation_from_source, 3, "translation_from_source"), 1.0)
    return (get_relative_transform(source_prim, target_prim) @ p)[:3]


def get_world_pose_from_relative(coord_prim, relative_translation, relative_orientation) -> tuple[np.ndarray, np.ndarray]:
    """The world pose (position (3,) [m], orientation (4,) (w, x, y, z)) of a pose given in
    `coord_prim`'s frame."""
    return pose_from_tf_matrix(prim_to_world(coord_prim) @ tf_matrix_from_pose(relative_translation,
                                                                                 relative_orientation))
