"""Physical bounds of the values `manip.sim` setters accept: poses, velocities, joint efforts.

A value beyond its bound raises `InvalidInputError` naming the argument and the bound before
it reaches MuJoCo (which would otherwise diverge at the next `step()` and reset the whole
state). Each bound is far beyond any manipulation scene, and chosen where the simulation
stops meaning anything:

- `MAX_WORLD_POSITION` = 1e4 m from the World's origin (a work cell is metres across; the
  viewer's float32 geometry loses millimetres beyond it).
- `MAX_OBJECT_SIZE` = 1e4 m: an edge, radius or height of a shape (times its scale), so a
  shape stays within the reach of `MAX_WORLD_POSITION` (a 1e6 m cube dropped on a robot
  made MuJoCo diverge at the first step).
- `MAX_LINEAR_SPEED` = 1e3 m/s of a free body (faster than a rifle bullet: 2 m per 2 ms
  physics substep, so contacts are missed anyway).
- `MAX_ANGULAR_SPEED` = 1e3 rad/s of a free body (about 9,500 rpm: 2 rad per substep).
- `MAX_JOINT_SPEED` = 100 rad/s for a revolute joint (about 950 rpm; the Franka's joints
  reach 2.6 rad/s, and the Franka diverges within 30 ms at 1000 rad/s) and
  `MAX_JOINT_LINEAR_SPEED` = 10 m/s for a prismatic joint (`set_joint_velocities`).
- `MAX_EFFORT_ACCELERATION` = 1e4 rad/s^2 (or m/s^2): an applied joint effort
  (`set_joint_efforts`, `ArticulationAction.joint_efforts`) may not accelerate its joint,
  alone, on the joint's own inertia (the model's diagonal inertia at its reference
  configuration, armature included), faster than that: from rest it would pass
  `MAX_JOINT_SPEED` within 10 ms (5 physics substeps). For the Franka: 2.2e3 N m on joint
  1, 1.1e3 N m on joint 7 (its motors give 87 and 12 N m), 250 N on a finger (70 N); the
  Franka stays stable for 2 s with every joint pushed at 3 times these (at 5 times, against
  its lower limits, MuJoCo diverges).
"""

from __future__ import annotations

import numpy as np

from manip.errors import InvalidInputError
from manip.validation import as_real_array, vec

#: Largest distance [m] of a prim's position from the World's origin.
MAX_WORLD_POSITION = 1e4
#: Largest speed [m/s] of a free body.
MAX_LINEAR_SPEED = 1e3
#: Largest dimension [m] of a shape (edge, radius or height, scale included).
MAX_OBJECT_SIZE = MAX_WORLD_POSITION
#: Largest angular speed [rad/s] of a free body.
MAX_ANGULAR_SPEED = 1e3
#: Largest speed [rad/s] a revolute joint is set to.
MAX_JOINT_SPEED = 100.0
#: Largest speed [m/s] a prismatic joint is set to.
MAX_JOINT_LINEAR_SPEED = 10.0
#: Largest acceleration [rad/s^2 or m/s^2] an applied effort alone may give its joint.
MAX_EFFORT_ACCELERATION = 1e4

_BOUNDS = {
    "position": (MAX_WORLD_POSITION, "m", "MAX_WORLD_POSITION", "distance from the World's origin"),
    "linear": (MAX_LINEAR_SPEED, "m/s", "MAX_LINEAR_SPEED", "speed"),
    "angular": (MAX_ANGULAR_SPEED, "rad/s", "MAX_ANGULAR_SPEED", "angular speed"),
}


def _check_rows(a: np.ndarray, kind: str, what: str) -> np.ndarray:
    bound, unit, name, quantity = _BOUNDS[kind]
    norms = np.linalg.norm(a.reshape(-1, 3), axis=1)
    bad = np.flatnonzero(~(norms <= bound))
    if bad.size:
        k = int(bad[0])
        row = f" (row {k})" if a.ndim == 2 else ""
        raise InvalidInputError(
            f"{what}{row} = {a.reshape(-1, 3)[k].tolist()} {unit}: its {quantity} {norms[k]:.4g} {unit} exceeds "
            f"manip.sim.utils.bounds.{name} = {bound:g} {unit}")
    return a


def bounded_vec(value, kind: str, what: str) -> np.ndarray:
    """`value` as a finite (3,) array within its bound: kind "position" [m], "linear" [m/s]
    or "angular" [rad/s] (see the module doc).

    Raises:
        InvalidInputError: a wrong shape, a non-finite value or a value beyond the bound.
    """
    return _check_rows(vec(value, 3, what), kind, what)


def check_bounded_rows(a: np.ndarray, kind: str, what: str) -> np.ndarray:
    """Raise InvalidInputError if a row of `a` (K, 3) is beyond the bound of `kind` (see `bounded_vec`)."""
    return _check_rows(np.asarray(as_real_array(a, what), dtype=float), kind, what)


def check_joint_speeds(v: np.ndarray, revolute: np.ndarray, names: list[str], what: str) -> None:
    """Raise InvalidInputError naming the joints whose speed |v| (K,) exceeds MAX_JOINT_SPEED
    (revolute, [rad/s]) or MAX_JOINT_LINEAR_SPEED (prismatic, [m/s])."""
    bound = np.where(revolute, MAX_JOINT_SPEED, MAX_JOINT_LINEAR_SPEED)
    bad = np.flatnonzero(~(np.abs(v) <= bound))
    if bad.size:
        raise InvalidInputError(
            f"{what}: " + ", ".join(
                f"{names[k]}={v[k]:.4g} {'rad/s' if revolute[k] else 'm/s'}" for k in bad)
            + f" beyond manip.sim.utils.bounds.MAX_JOINT_SPEED = {MAX_JOINT_SPEED:g} rad/s (revolute) / "
              f"MAX_JOINT_LINEAR_SPEED = {MAX_JOINT_LINEAR_SPEED:g} m/s (prismatic)")


def check_efforts(e: np.ndarray, inertia: np.ndarray, revolute: np.ndarray, names: list[str], what: str) -> None:
    """Raise InvalidInputError naming the joints whose effort |e| (K,) [N m or N] exceeds
    MAX_EFFORT_ACCELERATION times their inertia (K,) [kg m^2 or kg] (NaN efforts are skipped:
    "no effort" in an ArticulationAction)."""
    bound = MAX_EFFORT_ACCELERATION * inertia
    bad = np.flatnonzero(np.abs(e) > bound)
    if bad.size:
        raise InvalidInputError(
            f"{what}: " + ", ".join(
                f"{names[k]}={e[k]:.4g} {'N m' if revolute[k] else 'N'} (at most {bound[k]:.4g})" for k in bad)
            + f"; an effort may not accelerate its joint alone beyond manip.sim.utils.bounds.MAX_EFFORT_ACCELERATION = "
              f"{MAX_EFFORT_ACCELERATION:g} rad/s^2 (or m/s^2) on the joint's inertia")


def check_object_size(dimensions, names: tuple[str, ...], what: str) -> None:
    """Raise InvalidInputError when a shape's dimension (`dimensions` (K,) [m], scale
    included, named by `names`) exceeds MAX_OBJECT_SIZE."""
    d = np.asarray(dimensions, dtype=float).ravel()
    bad = np.flatnonzero(~(d <= MAX_OBJECT_SIZE))
    if bad.size:
        k = int(bad[0])
        raise InvalidInputError(
            f"{what}: {names[min(k, len(names) - 1)]} (scale included) = {d[k]:.4g} m exceeds "
            f"manip.sim.utils.bounds.MAX_OBJECT_SIZE = {MAX_OBJECT_SIZE:g} m (a shape must fit in the World: "
            f"positions reach MAX_WORLD_POSITION = {MAX_WORLD_POSITION:g} m)")
