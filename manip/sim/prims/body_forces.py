"""Forces on rigid bodies and the contact forces they feel, for the views (`RigidPrimView`).

External forces go through MuJoCo's `xfrc_applied` (a force at the body's centre of mass
and a torque, world frame). As in PhysX's tensor API, a force applied with `apply_forces`
acts during the next physics step only (the World clears it after that step,
`manip.sim.core.substeps`); apply it again before every step to keep pushing.

Contact forces are MuJoCo's (`mj_contactForce`) at the last substep, summed per body, world
frame, on the body named first. Isaac returns contact *impulses* divided by its `dt`
argument (default 1, i.e. impulses [N s]); so do these functions: force * physics_dt / dt.
"""

from __future__ import annotations

import mujoco
import numpy as np

from manip.sim.scenes.stage import SimHandle


def apply(sim: SimHandle, bodies: np.ndarray, forces: np.ndarray | None, torques: np.ndarray | None,
          positions: np.ndarray | None, is_global: bool) -> None:
    """Add forces (K, 3) [N] at `positions` (K, 3) [m] (the centres of mass for None) and
    torques (K, 3) [N m] to `bodies` (K,) for the next physics step; body frame unless
    `is_global` (positions then in the body frame too)."""
    sim.ensure_kinematics()
    d = sim.data
    for k, b in enumerate(bodies):
        R = d.xmat[b].reshape(3, 3)
        f = np.zeros(3) if forces is None else (forces[k] if is_global else R @ forces[k])
        t = np.zeros(3) if torques is None else (torques[k] if is_global else R @ torques[k])
        if positions is not None and forces is not None:
            p = positions[k] if is_global else d.xpos[b] + R @ positions[k]
            t = t + np.cross(p - d.xipos[b], f)
        d.xfrc_applied[b, :3] += f
        d.xfrc_applied[b, 3:] += t
        sim.pulsed_bodies.add(int(b))


def contact_forces(sim: SimHandle) -> list[tuple[int, int, np.ndarray]]:
    """(body1, body2, force (3,) [N] on body1 from body2, world frame) of every active contact."""
    m, d = sim.model, sim.data
    out = []
    f6 = np.zeros(6)
    for i in range(d.ncon):
        c = d.contact[i]
        if c.exclude != 0 or c.efc_address < 0:
            continue
        mujoco.mj_contactForce(m, d, i, f6)
        frame = c.frame.reshape(3, 3)  # rows: normal (from geom1 to geom2), tangents
        f_on_2 = frame.T @ f6[:3]     # MuJoCo's force is the one geom1 exerts on geom2
        b1, b2 = int(m.geom_bodyid[c.geom[0]]), int(m.geom_bodyid[c.geom[1]])
        out.append((b2, b1, f_on_2))
        out.append((b1, b2, -f_on_2))
    return out


def net_contact_forces(sim: SimHandle, bodies: np.ndarray) -> np.ndarray:
    """(K, 3) total contact force [N] on each of `bodies` (K,), world frame."""
    row = {int(b): k for k, b in enumerate(bodies)}
    out = np.zeros((len(bodies), 3))
    for b1, _, f in contact_forces(sim):
        if b1 in row:
            out[row[b1]] += f
    return out


def contact_force_matrix(sim: SimHandle, bodies: np.ndarray, filters: np.ndarray) -> np.ndarray:
    """(K, F, 3) contact force [N] on each of `bodies` (K,) from each of `filters` (F,)."""
    row = {int(b): k for k, b in enumerate(bodies)}
    col = {int(b): k for k, b in enumerate(filters)}
    out = np.zeros((len(bodies), len(filters), 3))
    for b1, b2, f in contact_forces(sim):
        if b1 in row and b2 in col:
            out[row[b1], col[b2]] += f
    return out
