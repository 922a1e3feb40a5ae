"""`RigidPrim`: velocities and mass of a free rigid body (the API of the Dynamic* shapes)."""

from __future__ import annotations

import logging

import mujoco
import numpy as np

from manip.errors import InvalidInputError
from manip.sim.prims.sleep import RigidSleepThreshold
from manip.sim.prims.xform_prim import XFormPrim
from manip.sim.scenes.stage import SimulationError
from manip.sim.utils.bounds import bounded_vec
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.sim.utils.types import DynamicState
from manip.validation import positive

logger = logging.getLogger(__name__)


class RigidPrim(RigidSleepThreshold, XFormPrim):
    """Velocity/mass API of a rigid body: the Dynamic* shapes (free bodies), or, created at
    a prim path inside a referenced model (e.g. "/World/Franka/panda_hand"), a link of it
    (velocities and mass readable, not settable: the joints move it)."""

    _mounts_on_links = False  # a body (a robot's link) or a shape of its own, never a frame on a link

    def __init__(self, prim_path: str, name: str | None = None, position=None, translation=None, orientation=None,
                 scale=None, visible: bool | None = None, mass: float | None = None, density: float | None = None,
                 linear_velocity=None, angular_velocity=None, *, reset_xform_properties: bool = True):
        """Wrap a rigid body on the stage (a Dynamic* object, a robot's link), with Isaac's
        arguments: `mass` [kg] or `density` [kg/m^3] (not both), and for a free body its
        `linear_velocity` [m/s] and `angular_velocity` [rad/s] (set now; before the first
        `World.reset()` they are its default state).

        Raises:
            InvalidInputError: both mass and density, or a bad value.
            SimulationError: velocities for a robot's link (its joints move it).
        """
        if mass is not None and density is not None:  # before the prim is on the stage
            raise InvalidInputError("give either mass or density, not both")
        super().__init__(prim_path, name, position, translation, orientation, scale, visible)
        if mass is not None:
            self.set_mass(mass)
        elif density is not None:
            self.set_density(density)
        for v, setter in ((linear_velocity, self.set_linear_velocity), (angular_velocity, self.set_angular_velocity)):
            if v is not None:
                if self._wrapped_reference is not None:
                    raise SimulationError(f"{self.prim_path!r} is a link of the model at "
                                          f"{self._wrapped_reference.prim_path!r}: its velocity follows the joints")
                setter(v)

    def _make_default_state(self) -> DynamicState:
        return DynamicState(self._pose[0].copy(), self._pose[1].copy(), np.zeros(3), np.zeros(3))

    def _require_dynamic(self) -> None:
        if self._sim is not None and self._qadr < 0:
            raise SimulationError(f"{self.prim_path!r} is not a free rigid body: its velocity follows the joints "
                                  "of its articulation (set the joint velocities instead)")

    def _link_velocity(self) -> np.ndarray:
        """(6,) linear [m/s] then angular [rad/s] world velocity of a link at its centre of
        mass (what PhysX reports for a rigid body)."""
        sim = self._sim
        if self._body_id < 0:
            raise SimulationError(f"{self.prim_path!r} is a site, not a rigid body: it has no velocity")
        sim.ensure_kinematics()
        res = np.zeros(6)
        mujoco.mj_objectVelocity(sim.model, sim.data, mujoco.mjtObj.mjOBJ_BODY, self._body_id, res, 0)
        return np.concatenate([res[3:], res[:3]])

    def get_linear_velocity(self) -> np.ndarray:
        """Linear velocity of the body origin (3,) [m/s], world frame (a link's: zero
        before the first reset, as authored)."""
        if self._sim is None:
            return self._unbound_velocity("linear_velocity")
        if self._wrapped_reference is not None:
            return self._link_velocity()[:3]
        self._require_dynamic()
        return self._sim.data.qvel[self._dadr : self._dadr + 3].copy()

    def get_angular_velocity(self) -> np.ndarray:
        """Angular velocity (3,) [rad/s], world frame."""
        if self._sim is None:
            return self._unbound_velocity("angular_velocity")
        if self._wrapped_reference is not None:
            return self._link_velocity()[3:]
        self._require_dynamic()
        return self._sim.free_angular_velocity(self._qadr, self._dadr)

    def _unbound_velocity(self, which: str) -> np.ndarray | None:
        """Before the World compiled: the default velocity, or zeros for a link (the model
        is authored at rest)."""
        if self._wrapped_reference is not None:
            return np.zeros(3)
        if self._removed(f"get_{which}"):
            return None
        return getattr(self._default_state, which).copy()

    def set_linear_velocity(self, velocity) -> None:
        """Set the linear velocity (3,) [m/s], world frame; a speed above
        `manip.sim.utils.bounds.MAX_LINEAR_SPEED` (1e3 m/s) raises InvalidInputError."""
        v = bounded_vec(velocity, "linear", "linear velocity")
        if self._sim is None and self._wrapped_object is not None and hasattr(self._wrapped_object,
                                                                               "set_linear_velocity"):
            self._wrapped_object.set_linear_velocity(v)  # the object holds the state the World compiles
            return
        if self._sim is None:
            self._require_on_stage("set_linear_velocity")
            self._default_state.linear_velocity = v
            return
        self._require_dynamic()
        self._sim.data.qvel[self._dadr : self._dadr + 3] = v
        self._sim.mark_stale()

    def set_angular_velocity(self, velocity) -> None:
        """Set the angular velocity (3,) [rad/s], world frame; an angular speed above
        `manip.sim.utils.bounds.MAX_ANGULAR_SPEED` (1e3 rad/s) raises InvalidInputError."""
        w = bounded_vec(velocity, "angular", "angular velocity")
        if self._sim is None and self._wrapped_object is not None and hasattr(self._wrapped_object,
                                                                               "set_angular_velocity"):
            self._wrapped_object.set_angular_velocity(w)
            return
        if self._sim is None:
            self._require_on_stage("set_angular_velocity")
            self._default_state.angular_velocity = w
            return
        self._require_dynamic()
        self._sim.set_free_angular_velocity(self._qadr, self._dadr, w)
        self._sim.mark_stale()

    def get_velocities(self) -> np.ndarray:
        """(6,) linear then angular velocity, world frame."""
        return np.concatenate([self.get_linear_velocity(), self.get_angular_velocity()])

    def get_mass(self) -> float:
        """Mass [kg]."""
        if self._sim is not None:
            return float(self._sim.model.body_mass[self._body_id])
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "get_mass"):
            return self._wrapped_object.get_mass()
        if getattr(self, "_mass", None) is not None:
            return float(self._mass)
        return float(self._density * self._volume())

    def set_mass(self, mass: float) -> None:
        """Change the mass [kg]; the inertia is scaled with it. Immediate if compiled, and kept
        when the World compiles again (for a robot's link too; through a wrapper, the wrapped
        object's)."""
        m = positive(mass, "mass", "kg")
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "set_mass"):
            self._wrapped_object.set_mass(m)
            return
        if self._sim is not None:
            self._apply_mass(m)
        self._mass, self._density = m, None

    def _apply_mass(self, m: float) -> None:
        model = self._sim.model
        old = model.body_mass[self._body_id]
        model.body_inertia[self._body_id] *= m / old
        model.body_mass[self._body_id] = m
        mujoco.mj_setConst(model, self._sim.data)

    def bind_simulation(self, sim) -> None:
        super().bind_simulation(sim)
        mass = getattr(self, "_mass", None)
        if self._wrapped_reference is not None and mass is not None and self._body_id >= 0:
            self._apply_mass(mass)  # a link's mass set by the script, over the model's

    def get_density(self) -> float:
        """Density [kg/m^3]: mass over the shape's volume."""
        return self.get_mass() / self._volume()

    def set_density(self, density: float) -> None:
        """Set the mass to `density` [kg/m^3] times the shape's volume (immediate if compiled)."""
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "set_density"):
            self._wrapped_object.set_density(density)
            return
        self.set_mass(positive(density, "density", "kg/m^3") * self._volume())
        self._mass, self._density = None, float(density)

    def get_current_dynamic_state(self) -> DynamicState:
        """Pose and velocities now (world frame)."""
        p, q = self.get_world_pose()
        return DynamicState(p, q, self.get_linear_velocity(), self.get_angular_velocity())

    def get_com(self) -> tuple[np.ndarray, np.ndarray]:
        """Centre of mass in the body frame: position (3,) [m], principal-axes orientation (4,)
        (the shape's centre before the World compiles)."""
        if self._sim is None:
            return np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0])
        m = self._sim.model
        return m.body_ipos[self._body_id].copy(), m.body_iquat[self._body_id].copy()

    def _volume(self) -> float:
        """Volume of the shape [m^3] (the shape classes define it)."""
        raise SimulationError(f"{self.prim_path!r} has no shape of its own here (a robot's link): set its mass, "
                              "not a density")

    def set_default_state(self, position=None, orientation=None, linear_velocity=None, angular_velocity=None) -> None:
        """State restored by `post_reset()`; None keeps a part."""
        super().set_default_state(position, orientation)
        if linear_velocity is not None:
            self._default_state.linear_velocity = bounded_vec(linear_velocity, "linear", "linear_velocity")
        if angular_velocity is not None:
            self._default_state.angular_velocity = bounded_vec(angular_velocity, "angular", "angular_velocity")

    def get_default_state(self) -> DynamicState:
        s = self._default_state
        return DynamicState(
            s.position.copy(), s.orientation.copy(), s.linear_velocity.copy(), s.angular_velocity.copy()
        )

    def post_reset(self) -> None:
        super().post_reset()
        if self._wrapped_reference is not None:
            return  # a link: the articulation restores its joints
        self.set_linear_velocity(self._default_state.linear_velocity)
        self.set_angular_velocity(self._default_state.angular_velocity)


declare_not_supported(RigidPrim)
