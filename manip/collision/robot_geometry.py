"""The robot's collision geometry: URDF collision shapes, their sphere covers, self-collision pairs.

The geometry comes from the URDF's `<collision>` elements (meshes or primitives), loaded
with Pinocchio and reduced like `Kinematics` (the gripper joints locked at given finger
positions, by default the planning positions). Each geometry object becomes a `RobotPart`
with its coal geometry, the arm joint that carries it (an index into
`Kinematics.joint_transforms`), its placement in that joint's frame, and an automatically
generated sphere cover (`manip.collision.spheres.cover_with_spheres`).
"""

from __future__ import annotations

import hashlib
import logging
from dataclasses import dataclass

import coal
import numpy as np
import pinocchio as pin

from manip.collision.pair_maps import PairMap, build_pair_map
from manip.collision.self_pairs import prove_pair_clear
from manip.collision.solids import mesh_arrays
from manip.collision.spheres import cover_with_spheres
from manip.disk_cache import default_cache, user_folder
from manip.errors import InvalidInputError
from manip.kinematics import Kinematics
from manip.robot_config import RobotConfig
from manip.validation import positive

logger = logging.getLogger(__name__)

COARSE_TOLERANCE = 0.05  # [m] protrusion of the coarse covers (first broadphase level)
COARSE_MAX_SPHERES = 6
_COVER_CACHE: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}
_ANNOUNCED: set[str] = set()


@dataclass(frozen=True, eq=False)
class RobotPart:
    """One collision geometry carried by an arm joint.

    Attributes:
        name: geometry name (e.g. "panda_link3_0").
        link: the link (frame) it belongs to.
        joint: index of the carrying joint in `Kinematics.joint_transforms` (0 = base).
        R: (3, 3) rotation of the geometry frame in the joint frame.
        p: (3,) position of the geometry frame in the joint frame [m].
        geometry: the coal collision geometry (in the geometry frame).
        centres: (K, 3) sphere centres in the JOINT frame [m].
        radii: (K,) sphere radii [m]; the balls contain the geometry's surface.
        coarse_centres: (k, 3) a coarser cover (fewer, larger balls), joint frame [m].
        coarse_radii: (k,) [m].
    """

    name: str
    link: str
    joint: int
    R: np.ndarray
    p: np.ndarray
    geometry: object
    centres: np.ndarray
    radii: np.ndarray
    coarse_centres: np.ndarray
    coarse_radii: np.ndarray

    @property
    def bounding_sphere(self) -> tuple[np.ndarray, float]:
        """(centre (3,) in the joint frame, radius) of one ball holding all the part's balls."""
        lo = (self.centres - self.radii[:, None]).min(axis=0)
        hi = (self.centres + self.radii[:, None]).max(axis=0)
        c = (lo + hi) / 2.0
        return c, float((np.linalg.norm(self.centres - c, axis=1) + self.radii).max())


def geometry_triangles(geometry) -> tuple[np.ndarray, np.ndarray] | None:
    """(vertices (V, 3), faces (F, 3)) of a closed triangle surface that contains the surface of
    a coal geometry (exact for meshes and boxes, circumscribed for round shapes), or None for
    a sphere (whose cover is itself)."""
    if isinstance(geometry, coal.Box):
        h = np.asarray(geometry.halfSide, dtype=float)
        V = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float) * h
        F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
        return V, F
    if isinstance(geometry, (coal.Cylinder, coal.Capsule)):
        r = float(geometry.radius)
        hz = float(geometry.halfLength) + (r if isinstance(geometry, coal.Capsule) else 0.0)
        n = 24
        rc = r / np.cos(np.pi / n)  # circumscribed polygon
        a = 2 * np.pi * np.arange(n) / n
        ring = np.stack([rc * np.cos(a), rc * np.sin(a)], axis=1)
        V = np.concatenate([np.c_[ring, np.full(n, -hz)], np.c_[ring, np.full(n, hz)], [[0, 0, -hz], [0, 0, hz]]])
        F = []
        for i in range(n):
            j = (i + 1) % n
            F += [[i, j, n + j], [i, n + j, n + i], [2 * n, j, i], [2 * n + 1, n + i, n + j]]
        return V, np.array(F)
    if isinstance(geometry, coal.Sphere):
        return None
    if hasattr(geometry, "num_tris") and hasattr(geometry, "vertices"):
        return mesh_arrays(geometry)
    # anything else (convex, height fields, ...): its local bounding box
    geometry.computeLocalAABB()
    aabb = geometry.aabb_local
    lo, hi = np.asarray(aabb.min_, dtype=float), np.asarray(aabb.max_, dtype=float)
    V, F = geometry_triangles(coal.Box(*(hi - lo)))  # type: ignore[misc]
    return V + (lo + hi) / 2.0, F


_CACHE_VERSION = "cover-v7"


def _announce(robot: str | None) -> None:
    """One log line per robot and process when its geometry is computed rather than read."""
    if robot is not None and robot not in _ANNOUNCED:
        _ANNOUNCED.add(robot)
        folder = user_folder()
        logger.warning("computing the collision geometry of '%s' (sphere covers, self-pair bounds): 5-70 s of CPU "
                       "once, cached %s", robot, f"in {folder}" if folder is not None else "nowhere (MANIP_CACHE_DIR=off)")


def sphere_cover(geometry, tolerance: float = 0.02, max_spheres: int = 48, *,
                 robot: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Sphere cover (centres (K, 3), radii (K,)) of a coal geometry in its own frame.

    Triangle meshes are surfaces for coal, so their cover holds their surface; primitives
    (boxes, cylinders, capsules) are solids, so theirs holds their whole bounding box.
    Covers are cached in memory and on disk (`manip.disk_cache`), keyed by the triangles and
    the parameters; computing one takes 0.1-1 s for a robot link (`robot`: the name a log line
    gives when it is computed).
    """
    if isinstance(geometry, coal.Sphere):
        return np.zeros((1, 3)), np.array([float(geometry.radius)])
    tri = geometry_triangles(geometry)
    assert tri is not None
    V, F = tri
    # primitives (and anything not a triangle mesh) are solids: their inside counts for coal
    solid = not (hasattr(geometry, "num_tris") and hasattr(geometry, "vertices"))
    digest = hashlib.sha1(V.tobytes() + F.astype(np.int64).tobytes()
                          + f"{_CACHE_VERSION}/{tolerance!r}/{max_spheres}/{solid}".encode()).hexdigest()
    if digest not in _COVER_CACHE:
        cache = default_cache()
        name = f"spheres-{digest}.npz"
        file = cache.find(name)
        C = R = None
        if file is not None:
            try:
                with np.load(file) as z:
                    C, R = z["centres"], z["radii"]
            except Exception:  # a corrupt cache entry is recomputed
                C = R = None
        if C is None:
            _announce(robot)
            C, R = cover_with_spheres(V, F, tolerance=tolerance, max_spheres=max_spheres, solid=solid)
            cache.write(name, lambda path: np.savez(path, centres=C, radii=R))
        _COVER_CACHE[digest] = (np.asarray(C, dtype=float), np.asarray(R, dtype=float))
    C, R = _COVER_CACHE[digest]
    return C.copy(), R.copy()


def _part_digest(part: RobotPart) -> str:
    """A string identifying a part's geometry, placement in its joint frame and sphere cover."""
    h = hashlib.sha1(type(part.geometry).__name__.encode())
    tri = geometry_triangles(part.geometry)
    if tri is None:  # a sphere
        h.update(repr(float(part.geometry.radius)).encode())
    else:
        h.update(tri[0].tobytes() + tri[1].astype(np.int64).tobytes())
    for a in (part.R, part.p, part.centres, part.radii):
        h.update(np.ascontiguousarray(a, dtype=float).tobytes())
    return f"{part.joint}:{h.hexdigest()}"


class RobotGeometry:
    """The robot's collision parts and self-collision pairs.

    Args:
        config: the robot configuration (URDF, SRDF disabled pairs, gripper).
        kinematics: the arm's `Kinematics` (its joint indices are used).
        gripper_positions: finger joint positions [m] the geometry assumes; default the
            config's planning positions.
        sphere_tolerance: how far the automatic sphere covers may stick out of the meshes [m].
    """

    def __init__(self, config: RobotConfig, kinematics: Kinematics, gripper_positions: np.ndarray | None = None,
                 sphere_tolerance: float = 0.02):
        self.config = config
        self.kinematics = kinematics
        self.sphere_tolerance = positive(sphere_tolerance, "sphere_tolerance", "m")
        full = kinematics.full_model
        self._full_geom = pin.buildGeomFromUrdf(full, str(config.urdf_path), pin.COLLISION,
                                                package_dirs=list(config.package_dirs))
        self.set_gripper_positions(gripper_positions)

    def set_gripper_positions(self, positions: np.ndarray | None) -> None:
        """Rebuild the parts with the fingers at `positions` [m] (None = planning positions)."""
        kin, config = self.kinematics, self.config
        full = kin.full_model
        q_lock = kin.locked_configuration.copy()
        if config.gripper is not None:
            g = config.gripper
            pos = g.planning_positions if positions is None else np.asarray(positions, dtype=float)
            if pos.shape != (len(g.joints),) or not np.all(np.isfinite(pos)):
                raise InvalidInputError(f"gripper positions must be {len(g.joints)} finite values for {list(g.joints)}; got {positions!r}")
            for name, v in zip(g.joints, pos):
                jid = full.getJointId(name)
                lo, hi = full.lowerPositionLimit[full.joints[jid].idx_q], full.upperPositionLimit[full.joints[jid].idx_q]
                if v < lo - 1e-9 or v > hi + 1e-9:
                    raise InvalidInputError(f"gripper joint {name}={v} outside its limits [{lo}, {hi}]")
                q_lock[full.joints[jid].idx_q] = v
            self.gripper_positions = pos.copy()
        elif positions is not None:
            raise InvalidInputError(f"robot '{config.name}' has no gripper configured")
        else:
            self.gripper_positions = np.zeros(0)
        locked = [j for j in range(1, full.njoints) if full.names[j] not in config.arm_joints]
        if locked:
            model, geom = pin.buildReducedModel(full, self._full_geom, locked, q_lock)
        else:
            model, geom = full, self._full_geom
        joint_names = list(kin.model.names)
        parts: list[RobotPart] = []
        for go in geom.geometryObjects:
            link = model.frames[go.parentFrame].name
            joint = joint_names.index(model.names[go.parentJoint])
            C, R = sphere_cover(go.geometry, self.sphere_tolerance, robot=config.name)
            Cc, Rc = sphere_cover(go.geometry, COARSE_TOLERANCE, COARSE_MAX_SPHERES, robot=config.name)
            Rg = go.placement.rotation.copy()
            pg = go.placement.translation.copy()
            parts.append(RobotPart(go.name, link, joint, Rg, pg, go.geometry, C @ Rg.T + pg, R, Cc @ Rg.T + pg, Rc))
        self.parts: list[RobotPart] = parts
        self.geometry_model = geom
        self.model = model
        disabled = {frozenset(p) for p in config.disabled_collision_pairs}
        pairs = []
        for a in range(len(parts)):
            for b in range(a + 1, len(parts)):
                la, lb = parts[a].link, parts[b].link
                # parts on one link, or carried rigidly by the same joint, never move
                # relative to each other: nothing to check
                if la == lb or parts[a].joint == parts[b].joint or frozenset((la, lb)) in disabled:
                    continue
                pairs.append((a, b))
        self.self_pairs: list[tuple[int, int]] = pairs
        _check_fixed_parts_apart(config, parts)
        # pairs that can never come within PROOF_CLEARANCE (`manip.collision.self_pairs`)
        digests = [_part_digest(part) for part in parts]
        cache = default_cache()
        self.proved_clear: dict[tuple[int, int], float] = {}
        for a, b in pairs:
            bound = prove_pair_clear(parts, a, b, kin, digests=digests, cache=cache)
            if bound is not None:
                self.proved_clear[(a, b)] = bound
        # the others, when few joints move them: a proved bound per cell of those joints
        # (`manip.collision.pair_maps`), looked up by the broadphase
        self.clearance_maps: dict[tuple[int, int], PairMap] = {}
        for a, b in pairs:
            if (a, b) not in self.proved_clear:
                found = build_pair_map(parts, a, b, kin, digests=digests, cache=cache)
                if found is not None:
                    self.clearance_maps[(a, b)] = found
        logger.debug("robot geometry: %d parts, %d spheres, %d self pairs (%d proved clear, %d mapped)", len(parts),
                     sum(len(p.radii) for p in parts), len(pairs), len(self.proved_clear), len(self.clearance_maps))

    @property
    def link_names(self) -> list[str]:
        """Links that carry collision geometry, in part order (unique)."""
        return list(dict.fromkeys(p.link for p in self.parts))


def _check_fixed_parts_apart(config: RobotConfig, parts: list[RobotPart]) -> None:
    """Raise when two arms' parts fixed to the combined base (joint 0: their base links, never
    checked by the planner, as they never move) overlap: arms placed into each other.

    Raises:
        InvalidInputError: names both arms, their links and base poses.
    """
    if len(config.arms) < 2:
        return
    owner = {}
    for g, part in enumerate(parts):
        if part.joint == 0:
            arm = next((a for a in config.arms if a.owns(part.link)), None)
            if arm is not None:
                owner[g] = arm
    request, fixed = coal.CollisionRequest(), sorted(owner)
    for i, a in enumerate(fixed):
        for b in fixed[i + 1:]:
            if owner[a] is owner[b]:
                continue
            ta = coal.Transform3s(parts[a].R, parts[a].p)
            tb = coal.Transform3s(parts[b].R, parts[b].p)
            if coal.collide(parts[a].geometry, ta, parts[b].geometry, tb, request, coal.CollisionResult()):
                A, B = owner[a], owner[b]
                raise InvalidInputError(
                    f"arms: the arms '{A.name}' and '{B.name}' overlap where they are fixed: '{parts[a].link}' and "
                    f"'{parts[b].link}' intersect at their base poses ({A.name}: {A.base_pose}, {B.name}: "
                    f"{B.base_pose}); place the bases apart")
