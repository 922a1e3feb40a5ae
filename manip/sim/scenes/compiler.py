"""Compile the stage into one MuJoCo model: the World's solver options, lights and prims."""

from __future__ import annotations

import mujoco
import numpy as np

from manip.sim.scenes.contact_model import compile_with_physx_friction, stiffen_contacts
from manip.sim.scenes.stage import SimHandle, SimulationError, Stage


def compile_stage(stage: Stage, *, timestep: float, gravity: np.ndarray) -> SimHandle:
    """Build every prim of `stage` into a new `mujoco.MjSpec`, compile it and run `mj_forward`.

    Solver options: the `implicitfast` integrator (implicit drive damping), elliptic
    friction cones; contacts as PhysX makes them (`manip.sim.scenes.contact_model`); offscreen buffer 1920 x 1080 px; a headlight and a shadow-casting key light.

    Args:
        stage: the prims, built in insertion order.
        timestep: MuJoCo integration step [s] (one substep of a World physics step).
        gravity: (3,) [m/s^2].

    Raises:
        SimulationError: the assembled model does not compile (MuJoCo's message is kept).
    """
    spec = mujoco.MjSpec()
    spec.modelname = "manip_world"
    spec.option.timestep = timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.gravity = np.asarray(gravity, dtype=float).tolist()
    spec.visual.global_.offwidth = 1920
    spec.visual.global_.offheight = 1080
    spec.visual.headlight.ambient = [0.3, 0.3, 0.3]
    spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]
    spec.worldbody.add_light(name="__manip_key_light", pos=[0.0, 0.0, 3.0], dir=[0.0, 0.0, -1.0],
                             type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, diffuse=[0.6, 0.6, 0.6],
                             castshadow=True)
    for prim in stage.prims():
        prim.add_to_spec(spec)
    for wrapper in stage.wrappers():  # a SurfaceGripper's weld (manip.sim.robots.surface_gripper)
        if hasattr(wrapper, "add_equalities_to_spec"):
            wrapper.add_equalities_to_spec(spec)
    stiffen_contacts(spec)
    modes = {}
    for prim in stage.prims():  # the combine modes of the shapes' physics materials
        material = prim.get_applied_physics_material() if hasattr(prim, "get_applied_physics_material") else None
        if material is not None:
            modes[prim.prim_path + "/geom"] = material.get_friction_combine_mode()
    try:
        model = compile_with_physx_friction(spec, modes)
    except ValueError as exc:
        hint = ""
        if "mjMINVAL" in str(exc):   # MuJoCo's bound on a moving body's mass and inertia (1e-15)
            hint = ("\n(MuJoCo needs every moving body's mass and inertia above mjMINVAL = 1e-15: the named object "
                    "is too small or too light; e.g. a DynamicCuboid of 0.02 kg compiles at size 1e-4 m, not at 1e-6 m)")
        raise SimulationError(f"the stage does not compile into a MuJoCo model: {exc}{hint}") from exc
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    sim = SimHandle(model, data)
    sim.free_dofs, sim.free_radii = free_bodies(model)
    return sim


def free_bodies(model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
    """The dof address (K,) of each free joint and the bounding radius [m] (K,) of its body's
    geoms about the body origin."""
    dofs, radii = [], []
    for j in range(model.njnt):
        if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE):
            b = model.jnt_bodyid[j]
            geoms = np.flatnonzero(model.geom_bodyid == b)
            r = max((np.linalg.norm(model.geom_pos[g]) + model.geom_rbound[g] for g in geoms), default=0.0)
            dofs.append(int(model.jnt_dofadr[j]))
            radii.append(float(r))
    return np.array(dofs, dtype=int), np.array(radii)
