"""Isaac's camera annotators that MuJoCo's images do not give directly, computed from the
depth image and the simulation state: surface normals and motion vectors.

Both follow Isaac's layouts: (H, W, 4) float32, pixels without a surface all zero.
- normals: the world-frame unit normal (x, y, z) of the surface seen at each pixel, facing the
  camera, from the depth image's neighbouring points (0 at silhouettes and image borders,
  where a neighbour is missing); channel 3 is 0.
- motion vectors: channels 0 and 1 are the image motion (du, dv) [px] of the surface point
  seen at each pixel over `period` [s], to first order from the simulation's body velocities
  (the camera itself taken as still); channels 2 and 3 are 0. (Isaac's renderer takes them
  from its previous frame; here they are the motion the current velocities make.)
"""

from __future__ import annotations

import mujoco
import numpy as np


def camera_points(depth: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Points (H, W, 3) [m] in the camera's optical frame (x right, y down, z forward) of a
    depth image (H, W) [m]; NaN where the depth is not finite."""
    h, w = depth.shape
    z = np.where(np.isfinite(depth), depth, np.nan).astype(float)
    u, v = np.meshgrid((np.arange(w) - K[0, 2]) / K[0, 0], (np.arange(h) - K[1, 2]) / K[1, 1])
    return np.stack([u * z, v * z, z], axis=-1)


def normals(points_cam: np.ndarray, R_cam: np.ndarray) -> np.ndarray:
    """World-frame normals (H, W, 4) float32 of camera-frame points (H, W, 3); `R_cam` (3, 3)
    rotates the optical frame into the world."""
    out = np.zeros(points_cam.shape[:2] + (4,), dtype=np.float32)
    dx = points_cam[1:-1, 2:] - points_cam[1:-1, :-2]
    dy = points_cam[2:, 1:-1] - points_cam[:-2, 1:-1]
    n = np.cross(dy, dx)
    n *= np.where(np.sum(n * points_cam[1:-1, 1:-1], axis=-1, keepdims=True) > 0, -1.0, 1.0)  # face the camera
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    ok = np.isfinite(norm[..., 0]) & (norm[..., 0] > 0)
    unit = np.divide(n, norm, out=np.zeros_like(n), where=ok[..., None])
    out[1:-1, 1:-1, :3] = np.where(ok[..., None], unit @ R_cam.T, 0.0)
    return out


def motion_vectors(model: mujoco.MjModel, data: mujoco.MjData, points_cam: np.ndarray, geom_ids: np.ndarray,
                   K: np.ndarray, p_cam: np.ndarray, R_cam: np.ndarray, period: float) -> np.ndarray:
    """Image motion (H, W, 4) float32 [px] over `period` [s] of the surface points (H, W, 3)
    (camera frame) seen through geoms `geom_ids` (H, W) (-1: none), with the camera at
    `p_cam` (3,), optical frame `R_cam` (3, 3) in the world. `data`'s com velocities must
    be current (`mj_comVel`)."""
    out = np.zeros(points_cam.shape[:2] + (4,), dtype=np.float32)
    hit = (geom_ids >= 0) & np.isfinite(points_cam[..., 2])
    if not np.any(hit):
        return out
    P = points_cam[hit]                                    # (N, 3) camera frame
    p_world = P @ R_cam.T + p_cam
    bodies = model.geom_bodyid[geom_ids[hit]]
    v_world = np.zeros_like(p_world)
    vel = np.zeros(6)
    for b in np.unique(bodies):
        mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, int(b), vel, 0)  # (rot, lin) at xpos
        sel = bodies == b
        v_world[sel] = vel[3:] + np.cross(vel[:3], p_world[sel] - data.xpos[b])
    V = v_world @ R_cam                                    # camera frame velocities (N, 3)
    z = P[:, 2]
    out[hit, 0] = K[0, 0] * (V[:, 0] * z - P[:, 0] * V[:, 2]) / (z * z) * period
    out[hit, 1] = K[1, 1] * (V[:, 1] * z - P[:, 1] * V[:, 2]) / (z * z) * period
    return out
