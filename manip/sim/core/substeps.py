"""How many MuJoCo substeps a World physics step takes: more while a free body moves fast.

A physics step of `physics_dt` (1/60 s) is integrated in at least `ceil(physics_dt /
substep_dt)` substeps (9 of 1.85 ms by default). Contacts are found at the start of each
substep, so a body falling onto the ground can travel one substep's distance into it before
the contact acts: 8 mm at 4.4 m/s (a drop from 1 m) with 1.85 ms substeps. PhysX prevents
this with speculative contacts; here the substep is shortened instead while a free body
(a Dynamic object, a floating base) moves fast, so that no point of it travels more than
`MAX_TRAVEL` (2 mm) per substep, up to `MAX_SUBSTEPS` substeps per physics step. Slow scenes
keep the base substeps; the extra cost is paid only during fast motion.
"""

from __future__ import annotations

import math

import mujoco

from manip.sim.scenes.stage import SimHandle

#: Largest distance a point of a free body travels in one substep [m].
MAX_TRAVEL = 0.002
#: Most substeps in one physics step (at 1/60 s: 0.17 ms, 12 m/s within MAX_TRAVEL).
MAX_SUBSTEPS = 100


def substeps_for(sim: SimHandle, physics_dt: float, base: int) -> int:
    """Substeps for the next physics step of `physics_dt` [s]: `base`, or more while a free
    body's fastest point (linear speed + angular speed * bounding radius) would travel more
    than MAX_TRAVEL in a substep."""
    dofs = sim.free_dofs
    if not dofs.size:
        return base
    qvel = sim.data.qvel
    speed = 0.0
    for k, a in enumerate(dofs):
        s = math.sqrt(qvel[a] ** 2 + qvel[a + 1] ** 2 + qvel[a + 2] ** 2) \
            + sim.free_radii[k] * math.sqrt(qvel[a + 3] ** 2 + qvel[a + 4] ** 2 + qvel[a + 5] ** 2)
        speed = max(speed, s)
    need = math.ceil(physics_dt * speed / MAX_TRAVEL)
    return int(min(MAX_SUBSTEPS, max(base, need)))


def step(sim: SimHandle, physics_dt: float, base: int) -> int:
    """Integrate one physics step of `physics_dt` [s] in `substeps_for(...)` equal substeps;
    returns how many."""
    n = substeps_for(sim, physics_dt, base)
    sim.model.opt.timestep = physics_dt / n
    sim.physics_dt = physics_dt
    lift = None
    if sim.gravity_off:  # gravity cancelled by its opposite at the centre of mass, during this step
        bodies = sorted(sim.gravity_off)
        lift = -sim.model.body_mass[bodies, None] * sim.model.opt.gravity[None, :]
        sim.data.xfrc_applied[bodies, :3] += lift
    mujoco.mj_step(sim.model, sim.data, nstep=n)
    if lift is not None:
        sim.data.xfrc_applied[bodies, :3] -= lift
    if sim.pulsed_bodies:  # forces applied for one step (RigidPrimView.apply_forces) end with it
        sim.data.xfrc_applied[sorted(sim.pulsed_bodies)] = 0.0
        sim.pulsed_bodies.clear()
    return n
