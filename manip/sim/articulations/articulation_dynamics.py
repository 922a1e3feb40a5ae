"""Jacobians, mass matrix and generalized forces of one articulation, in Isaac's layout
(what `ArticulationView.get_jacobians`, `get_mass_matrices`, ... return, without the batch axis).

Isaac's layout: a fixed-base articulation has `num_dof` generalized coordinates and its
Jacobians cover the bodies below the root (`num_bodies - 1`); a floating base adds its 6
root DoF first (linear then angular velocity, world frame) and every body's Jacobian. Each
Jacobian is (6, n): the linear velocity of the body's origin, then its angular velocity,
world frame [m/s, rad/s per unit of generalized velocity]. From MuJoCo's `mj_jacBody`,
`mj_fullM` and `mj_rne`.
"""

from __future__ import annotations

import mujoco
import numpy as np

from manip.sim.articulations.articulation_core import ArticulationCore


def dof_columns(core: ArticulationCore) -> np.ndarray:
    """MuJoCo dof addresses (n,) of the articulation's generalized coordinates, Isaac's order
    (a floating base's 6 first)."""
    joints = core.dadr
    if core.free_dadr >= 0:
        return np.concatenate([np.arange(core.free_dadr, core.free_dadr + 6), joints])
    return joints


def jacobians(core: ArticulationCore) -> np.ndarray:
    """(B, 6, n) Jacobians of the bodies (below the root for a fixed base)."""
    m, d = core.sim.model, core.sim.data
    core.sim.ensure_kinematics()
    cols = dof_columns(core)
    bodies = core.body_ids if core.free_dadr >= 0 else np.array([b for b in core.body_ids if b not in core.root_ids])
    out = np.zeros((len(bodies), 6, cols.size))
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    for k, b in enumerate(bodies):
        mujoco.mj_jacBody(m, d, jp, jr, int(b))
        out[k, :3], out[k, 3:] = jp[:, cols], jr[:, cols]
    if core.free_dadr >= 0:  # MuJoCo's free-joint angular velocity is in the body frame: map to world
        R = core.sim.free_rotation(core.free_qadr)
        out[:, :, 3:6] = out[:, :, 3:6] @ R.T
    return out


def mass_matrix(core: ArticulationCore) -> np.ndarray:
    """(n, n) joint-space inertia [kg m^2, kg m, kg] of the articulation's coordinates."""
    m, d = core.sim.model, core.sim.data
    core.sim.ensure_kinematics()
    mujoco.mj_crb(m, d)
    full = np.zeros((m.nv, m.nv))
    try:
        mujoco.mj_fullM(m, d, full)  # MuJoCo 4: (model, data, dst)
    except TypeError:
        mujoco.mj_fullM(m, full, d.qM)  # MuJoCo 3: (model, dst, qM)
    cols = dof_columns(core)
    return full[np.ix_(cols, cols)]


def _bias(core: ArticulationCore, with_velocity: bool) -> np.ndarray:
    """MuJoCo's bias force (n,) at the current state: gravity, plus Coriolis and centrifugal
    forces with `with_velocity` (computed on a copy of the data; the World's is untouched)."""
    m = core.sim.model
    d = mujoco.MjData(m)
    d.qpos[:] = core.sim.data.qpos
    if with_velocity:
        d.qvel[:] = core.sim.data.qvel
    mujoco.mj_kinematics(m, d)
    mujoco.mj_comPos(m, d)
    mujoco.mj_comVel(m, d)
    out = np.zeros(m.nv)
    mujoco.mj_rne(m, d, 0, out)
    return out[dof_columns(core)]


def gravity_forces(core: ArticulationCore) -> np.ndarray:
    """(n,) generalized forces that hold the articulation against gravity [N m or N]."""
    return _bias(core, with_velocity=False)


def coriolis_and_centrifugal_forces(core: ArticulationCore) -> np.ndarray:
    """(n,) Coriolis and centrifugal generalized forces at the current velocities [N m or N]."""
    return _bias(core, with_velocity=True) - _bias(core, with_velocity=False)
