"""Tight axis-aligned bounding boxes of the World's geometry (`Scene.compute_object_AABB`).

MuJoCo's `geom_aabb` is a box in the geom's frame (a mesh's principal axes): its rotated
corners overestimate, by up to sqrt(3) for a turned ball, and put the Franka's base 8 cm
below the floor it stands on. Here each geom is bounded exactly: a box by its corners, a
mesh by its vertices, a sphere, ellipsoid, cylinder or capsule by its exact extent along
each world axis; a plane by its drawn square at its height (MuJoCo's plane box spans
-5e9 m in z). Shapes not compiled yet are bounded from their authored pose and dimensions,
as Isaac bounds USD prims before any simulation.

Boxes are (2, 3) arrays [[min x, y, z], [max x, y, z]] [m].
"""

from __future__ import annotations

import mujoco
import numpy as np

from manip import quaternion as quat

_G = mujoco.mjtGeom


def _axis_extent(R: np.ndarray, half_length: float, radius: float, round_ends: bool) -> np.ndarray:
    """Half extents (3,) of a cylinder (flat ends) or capsule (round ends) whose axis is R's z."""
    a = R[:, 2]
    ring = radius if round_ends else radius * np.sqrt(np.clip(1.0 - a * a, 0.0, 1.0))
    return np.abs(a) * half_length + ring


def geom_box(model: mujoco.MjModel, data: mujoco.MjData, g: int) -> np.ndarray:
    """The world box (2, 3) of geom `g` in the current state (kinematics up to date)."""
    p, R, s = data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3), model.geom_size[g]
    t = int(model.geom_type[g])
    if t == _G.mjGEOM_MESH:
        m = model.geom_dataid[g]
        v = model.mesh_vert[model.mesh_vertadr[m]: model.mesh_vertadr[m] + model.mesh_vertnum[m]]
        w = p + v @ R.T
        return np.stack([w.min(axis=0), w.max(axis=0)])
    if t == _G.mjGEOM_PLANE:
        h = np.abs(R[:, :2]) @ s[:2]
    elif t == _G.mjGEOM_BOX:
        h = np.abs(R) @ s
    elif t == _G.mjGEOM_SPHERE:
        h = np.full(3, s[0])
    elif t == _G.mjGEOM_ELLIPSOID:
        h = np.sqrt((R * R) @ (s * s))
    elif t in (_G.mjGEOM_CYLINDER, _G.mjGEOM_CAPSULE):
        h = _axis_extent(R, s[1], s[0], t == _G.mjGEOM_CAPSULE)
    else:  # heightfields, SDFs: MuJoCo's box in the geom frame
        c, hh = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
        signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
        w = p + (c + signs * hh) @ R.T
        return np.stack([w.min(axis=0), w.max(axis=0)])
    return np.stack([p - h, p + h])


def shape_box(kind: str, dimensions: np.ndarray, position: np.ndarray, orientation: np.ndarray) -> np.ndarray:
    """The world box (2, 3) of a manip.sim shape from its pose and `shape_dimensions()`:
    cuboid (3,) edges; sphere (1,) radius or (3,) ellipsoid radii; cylinder, capsule
    (cylindrical part) and cone (radius, height) along the shape's z [m]."""
    R = quat.to_matrix(orientation)
    d = np.asarray(dimensions, dtype=float)
    p = np.asarray(position, dtype=float)
    if kind == "cuboid":
        h = np.abs(R) @ (0.5 * d)
    elif kind == "sphere":
        h = np.full(3, d[0]) if d.size == 1 else np.sqrt((R * R) @ (d * d))
    elif kind in ("cylinder", "capsule"):
        h = _axis_extent(R, 0.5 * d[1], d[0], kind == "capsule")
    elif kind == "cone":  # base disc at -height/2, apex at +height/2
        a = R[:, 2]
        base = p - 0.5 * d[1] * a
        ring = d[0] * np.sqrt(np.clip(1.0 - a * a, 0.0, 1.0))
        apex = p + 0.5 * d[1] * a
        return np.stack([np.minimum(base - ring, apex), np.maximum(base + ring, apex)])
    else:
        raise ValueError(f"no bounds for shape kind {kind!r}")
    return np.stack([p - h, p + h])
