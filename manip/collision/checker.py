"""`CollisionChecker`: exact robot-vs-world and self-collision checks, fast in batches.

Answers are those of coal on the robot's URDF collision geometry (meshes as triangle
surfaces, primitives as solids), the same as Pinocchio's `computeCollisions` over the same
pairs with the same security margin (the padding). Speed comes from a compiled (numba)
broadphase, `manip.collision.broadphase`, that can only say "free", never "colliding":

1. batched forward kinematics of the configurations (`Kinematics.joint_transforms`);
2. world: one bounding ball per moving joint (all its parts) against every obstacle
   (closed-form signed distances to boxes, spheres, capsules, cylinders; meshes through
   their bounding box), then the coarse sphere cover of each of that joint's parts, then
   the fine cover of each part still flagged; parts fixed to the base are checked once per
   world;
3. self: one bounding ball per body (a link's parts, or an attached object) for the enabled
   pairs, then the coarse covers of each enabled part pair;
4. coal's exact narrowphase for the (configuration, pair) candidates left, stopping at the
   first collision of each configuration, or of each group of configurations when only
   "any collision in this segment?" is asked (most penetrating candidates first), or at the
   first colliding configuration in order (`first_collision`).

The covers (`manip.collision.spheres`) are generated automatically from the meshes and hold
every point of the surfaces (of the volume for solid primitives): if no ball comes within
the padding of an obstacle, no point of the geometry does, so coal would say "free" too.
"""

from __future__ import annotations

import functools
import logging
import math
from dataclasses import dataclass
from typing import Literal, NamedTuple, Sequence

import coal
import numpy as np

from manip.collision import broadphase
from manip.collision.robot_geometry import COARSE_MAX_SPHERES, COARSE_TOLERANCE, RobotGeometry, sphere_cover
from manip.collision.shapes import Capsule, Cylinder, Obstacle, Sphere, coal_geometry
from manip.collision.world import WorldConfig
from manip.errors import InvalidInputError, UnknownNameError
from manip.kinematics import Kinematics
from manip.pose import Pose
from manip.robot_config import RobotConfig

logger = logging.getLogger(__name__)

ContactKind = Literal["world", "self", "attached_world", "attached_self"]


@dataclass(frozen=True)
class Contact:
    """One colliding (or closest) pair.

    Attributes:
        kind: "world" (robot link vs obstacle), "self" (link vs link), "attached_world"
            (attached object vs obstacle) or "attached_self" (attached object vs link).
        a: the robot link or attached object.
        b: the obstacle or the other link.
        distance: signed distance [m] between the two (negative = penetration depth,
            approximate for meshes; see `CollisionChecker.distance`).
    """

    kind: ContactKind
    a: str
    b: str
    distance: float


@dataclass(frozen=True)
class CollisionReport:
    """What collides in one configuration (padding included).

    Attributes:
        in_collision: True if any pair collides.
        contacts: every colliding pair, deepest first.
    """

    in_collision: bool
    contacts: tuple[Contact, ...]

    @property
    def world_collision(self) -> bool:
        """True if the robot or an attached object touches an obstacle."""
        return any(c.kind in ("world", "attached_world") for c in self.contacts)

    @property
    def self_collision(self) -> bool:
        """True if two links (or an attached object and a link) touch."""
        return any(c.kind in ("self", "attached_self") for c in self.contacts)


@dataclass(frozen=True)
class DistanceReport:
    """Signed distances [m] of one configuration (without padding).

    Attributes:
        distance: min(world_distance, self_distance).
        world_distance: smallest distance between the robot (and attached objects) and
            the obstacles; +inf with no obstacles.
        self_distance: smallest distance over the enabled self-collision pairs.
        closest: the pair achieving `distance` (None if there is none).
    """

    distance: float
    world_distance: float
    self_distance: float
    closest: Contact | None


class PathCheck(NamedTuple):
    """Result of `CollisionChecker.path_valid`."""

    valid: bool
    first_invalid_segment: int | None


@dataclass(frozen=True, eq=False)
class AttachedObject:
    """An obstacle carried by a link.

    Attributes:
        obstacle: the shape (its `pose` is where it was when attached, base frame).
        link: the carrying link.
        pose_in_link: the shape's pose in the link frame.
        allowed_links: links never checked against it (those rigidly attached to the same
            joint as `link`, plus any given by the caller).
    """

    obstacle: Obstacle
    link: str
    pose_in_link: Pose
    allowed_links: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class _Part:
    """A geometry moving with the robot: a robot part or an attached object."""

    name: str           # robot link or attached object name
    attached: bool
    joint: int
    R: np.ndarray       # (3, 3) geometry frame in joint frame
    p: np.ndarray       # (3,)
    geometry: object    # coal geometry for boolean checks
    hull: object        # coal geometry for distances (convex hull of meshes)
    centres: np.ndarray  # (K, 3) in joint frame
    radii: np.ndarray   # (K,)
    coarse_centres: np.ndarray  # (k, 3) in joint frame
    coarse_radii: np.ndarray    # (k,)


def _hull(geometry):
    """Convex hull of a coal mesh (for fast signed distances), or the geometry itself."""
    if hasattr(geometry, "num_tris") and hasattr(geometry, "buildConvexHull"):
        try:
            if geometry.convex is None:
                geometry.buildConvexHull(True, "Qt")
            if geometry.convex is not None:
                return geometry.convex
        except Exception:  # pragma: no cover - qhull failure on degenerate meshes
            logger.debug("convex hull failed; distances use the mesh itself")
    return geometry


def _tf(R: np.ndarray, p: np.ndarray) -> coal.Transform3s:
    return coal.Transform3s(R, p)


def _sd_local(L: np.ndarray, h: np.ndarray, rho: np.ndarray, cyl: np.ndarray | None) -> np.ndarray:
    """Signed distance of local points L (..., 3) to rounded boxes (half extents h, rounding rho)
    or, where `cyl`, to cylinders (radius h[..., 0], half height h[..., 2]).

    Written per component: reductions over a trailing axis of 3 are slow in NumPy.
    """
    x = np.abs(L[..., 0]) - h[..., 0]
    y = np.abs(L[..., 1]) - h[..., 1]
    z = np.abs(L[..., 2]) - h[..., 2]
    inside = np.minimum(np.maximum(np.maximum(x, y), z), 0.0)
    np.maximum(x, 0.0, out=x)
    np.maximum(y, 0.0, out=y)
    zc = np.maximum(z, 0.0)
    out = np.sqrt(x * x + y * y + zc * zc) + inside - rho
    if cyl is not None and np.any(cyl):
        r = np.sqrt(L[..., 0] ** 2 + L[..., 1] ** 2) - h[..., 0]
        inside_c = np.minimum(np.maximum(r, z), 0.0)
        np.maximum(r, 0.0, out=r)
        out = np.where(cyl, np.sqrt(r * r + zc * zc) + inside_c, out)
    return out


@functools.lru_cache(maxsize=512)
def _coarse_to_fine(n: int) -> np.ndarray:
    """Indices 0..n ordered endpoints first, then by halving strides (bisection order); cached."""
    idx = np.arange(n + 1)
    level = np.zeros(n + 1, dtype=np.int64)
    inner = idx[1:n]
    if inner.size:
        # trailing zero bits of the index: large strides first
        tz = np.zeros(inner.size, dtype=np.int64)
        x = inner.copy()
        for _ in range(64):
            m = (x & 1) == 0
            if not m.any():
                break
            tz[m] += 1
            x[m] >>= 1
        level[1:n] = 64 - tz
    out = idx[np.argsort(level, kind="stable")]
    out.setflags(write=False)
    return out


_CHUNK = 1024  # configurations per broadphase batch


class _SphereTable:
    """The balls of all parts in flat arrays (ragged by part), centres in joint frames."""

    def __init__(self, centres: list[np.ndarray], radii: list[np.ndarray], joints: np.ndarray):
        self.count = np.array([len(r) for r in radii], dtype=np.int64)
        self.start = np.cumsum(self.count) - self.count
        self.centres = np.concatenate(centres).reshape(-1, 3)
        self.radii = np.concatenate(radii).astype(float)
        self.part = np.repeat(np.arange(len(radii)), self.count)
        self.joint = np.asarray(joints)[self.part]

    def centres_of(self, g: int) -> np.ndarray:
        return self.centres[self.start[g]:self.start[g] + self.count[g]]

    def radii_of(self, g: int) -> np.ndarray:
        return self.radii[self.start[g]:self.start[g] + self.count[g]]


class CollisionChecker:
    """Collision checking of a robot's configurations against a world of obstacles and itself.

    Args:
        config: the robot configuration (URDF geometry, SRDF disabled pairs, padding).
        kinematics: the robot's `Kinematics` (built from `config` if None).
        world: the obstacles (a `WorldConfig` or a dict in cuRobo's world format).
        padding: clearance [m] >= 0 the robot (and attached objects) must keep from the
            obstacles: a pair closer than this counts as a collision. Default: the
            config's `collision_padding`.
        self_padding: clearance [m] >= 0 between link pairs (default 0).
        sphere_tolerance: how far the automatic sphere covers may stick out of the links'
            meshes [m] (a speed knob only; answers do not depend on it).
    """

    def __init__(
        self,
        config: RobotConfig,
        kinematics: Kinematics | None = None,
        world: WorldConfig | dict | None = None,
        padding: float | None = None,
        self_padding: float = 0.0,
        sphere_tolerance: float = 0.02,
    ):
        self.config = config
        self.kinematics = kinematics if kinematics is not None else Kinematics(config)
        self.robot = RobotGeometry(config, self.kinematics, sphere_tolerance=sphere_tolerance)
        self._padding = self._check_padding(config.collision_padding if padding is None else padding, "padding")
        self._self_padding = self._check_padding(self_padding, "self_padding")
        self._world = WorldConfig()
        self._attached: dict[str, AttachedObject] = {}
        self._obstacle_cache: dict[int, tuple] = {}
        self._rebuild_parts()
        self.set_world(world if world is not None else WorldConfig())

    # ------------------------------------------------------------------ configuration
    @staticmethod
    def _check_padding(value: float, what: str) -> float:
        try:
            v = float(value)
        except (TypeError, ValueError) as exc:
            raise InvalidInputError(f"{what} must be a number >= 0 [m]; got {value!r}") from exc
        if not math.isfinite(v) or v < 0:
            raise InvalidInputError(f"{what} must be a finite number >= 0 [m]; got {value!r}")
        return v

    @property
    def padding(self) -> float:
        """Clearance [m] kept from the world."""
        return self._padding

    @padding.setter
    def padding(self, value: float) -> None:
        self._padding = self._check_padding(value, "padding")
        self._req_world.security_margin = self._padding
        self._update_static()

    @property
    def self_padding(self) -> float:
        """Clearance [m] kept between links."""
        return self._self_padding

    @self_padding.setter
    def self_padding(self, value: float) -> None:
        self._self_padding = self._check_padding(value, "self_padding")
        self._req_self.security_margin = self._self_padding

    @property
    def world(self) -> WorldConfig:
        """A copy of the current world (attached objects are not in it)."""
        return self._world.copy()

    @property
    def attached_objects(self) -> dict[str, AttachedObject]:
        """The objects carried by the robot, by name (a copy)."""
        return dict(self._attached)

    def set_world(self, world: WorldConfig | dict | None) -> None:
        """Replace the obstacles (a `WorldConfig` or cuRobo's world dict); attached objects stay."""
        if world is None:
            world = WorldConfig()
        elif isinstance(world, dict):
            world = WorldConfig.from_dict(world)
        elif not isinstance(world, WorldConfig):
            raise InvalidInputError(f"world must be a WorldConfig or a dict in cuRobo's world format; got {type(world).__name__}")
        clash = [n for n in world.names if n in self._attached]
        if clash:
            raise InvalidInputError(f"obstacle name(s) {clash} are used by attached objects; detach them or rename")
        self._world = world.copy()
        self._rebuild_world()

    def add_obstacle(self, obstacle: Obstacle) -> None:
        """Add one obstacle to the world (names must be unique)."""
        if isinstance(obstacle, Obstacle) and obstacle.name in self._attached:
            raise InvalidInputError(f"'{obstacle.name}' is the name of an attached object")
        self._world.add(obstacle)
        self._rebuild_world()

    def remove_obstacle(self, name: str) -> Obstacle:
        """Remove and return the obstacle `name` (UnknownNameError lists the names)."""
        ob = self._world.remove(name)
        self._rebuild_world()
        return ob

    def update_obstacle_pose(self, name: str, pose: Pose | Sequence[float]) -> None:
        """Move the obstacle `name` to `pose` (base frame)."""
        ob = self._world.get(name)
        self._world.replace(ob.with_pose(pose))
        self._rebuild_world()

    def set_gripper_positions(self, positions: Sequence[float] | np.ndarray | None) -> None:
        """Finger positions [m] the collision model assumes (None = the planning positions).

        Attached objects keep their pose relative to their link.
        """
        self.robot.set_gripper_positions(None if positions is None else np.asarray(positions, dtype=float))
        self._rebuild_parts()

    # ------------------------------------------------------------------ internal tables
    def _rebuild_parts(self) -> None:
        parts: list[_Part] = []
        self._robot_part_links: list[str] = []
        for rp in self.robot.parts:
            parts.append(_Part(rp.link, False, rp.joint, rp.R, rp.p, rp.geometry, _hull(rp.geometry), rp.centres, rp.radii,
                               rp.coarse_centres, rp.coarse_radii))
        n_robot = len(parts)
        pairs = list(self.robot.self_pairs)
        kin = self.kinematics
        for name, att in self._attached.items():
            f = kin.model.frames[kin.frame_id(att.link)]
            T_joint_obj = Pose.from_matrix(f.placement.homogeneous) @ att.pose_in_link
            local = att.obstacle.with_pose(Pose(np.zeros(3)))
            geom = coal_geometry(local)
            C, r = sphere_cover(geom, self.robot.sphere_tolerance)
            Cc, rc = sphere_cover(geom, COARSE_TOLERANCE, COARSE_MAX_SPHERES)
            Rj = T_joint_obj.rotation
            pj = T_joint_obj.position
            parts.append(_Part(name, True, f.parentJoint, Rj, pj, geom, _hull(geom), C @ Rj.T + pj, r, Cc @ Rj.T + pj, rc))
            ai = len(parts) - 1
            for i in range(n_robot):
                if parts[i].name not in att.allowed_links:
                    pairs.append((i, ai))
        self._parts = parts
        G = len(parts)
        self._pj = np.array([p.joint for p in parts])
        self._fine = _SphereTable([p.centres for p in parts], [p.radii for p in parts], self._pj)
        self._coarse = _SphereTable([p.coarse_centres for p in parts], [p.coarse_radii for p in parts], self._pj)

        def bounding_ball(gs: Sequence[int]) -> tuple[np.ndarray, float]:
            """A ball holding every fine and coarse ball of the parts gs (joint frame)."""
            allc = np.concatenate([self._fine.centres_of(g) for g in gs] + [self._coarse.centres_of(g) for g in gs])
            allr = np.concatenate([self._fine.radii_of(g) for g in gs] + [self._coarse.radii_of(g) for g in gs])
            c = ((allc - allr[:, None]).min(axis=0) + (allc + allr[:, None]).max(axis=0)) / 2.0
            return c, float((np.linalg.norm(allc - c, axis=1) + allr).max())

        # one bounding ball per part (distance queries' branch and bound)
        balls = [bounding_ball([g]) for g in range(G)]
        self._pbc = np.array([c for c, _ in balls]).reshape(G, 3)
        self._pbr = np.array([r for _, r in balls])
        # level 0 of the world check: one bounding ball per moving joint (all its parts)
        joints = sorted({p.joint for p in parts if p.joint != 0})
        members = [np.array([g for g, p in enumerate(parts) if p.joint == j], dtype=np.int64) for j in joints]
        balls = [bounding_ball(m) for m in members]
        self._l0_joint = np.array(joints, dtype=np.int64)
        self._pairs = np.array(pairs, dtype=np.int64).reshape(-1, 2)
        # self-collision broadphase per body (a link's parts together, or an attached object):
        # body pairs with at least one enabled part pair
        body_of: dict[str, int] = {}
        body_parts: list[list[int]] = []
        for g, part in enumerate(parts):
            key = ("attached:" if part.attached else "") + part.name
            if key not in body_of:
                body_of[key] = len(body_parts)
                body_parts.append([])
            body_parts[body_of[key]].append(g)
        part_body = np.zeros(G, dtype=np.int64)
        for b_, gs in enumerate(body_parts):
            part_body[gs] = b_
        bpairs: dict[tuple[int, int], list[int]] = {}
        for k, (a_, b_) in enumerate(pairs):
            bpairs.setdefault((int(part_body[a_]), int(part_body[b_])), []).append(k)
        self._bpairs = np.array(list(bpairs), dtype=np.int64).reshape(-1, 2)
        pair_count = np.array([len(m) for m in bpairs.values()], dtype=np.int64)
        pair_order = np.array([k for m in bpairs.values() for k in m], dtype=np.int64)
        body_balls = [bounding_ball(gs) for gs in body_parts]
        body_joint = np.array([parts[gs[0]].joint for gs in body_parts], dtype=np.int64)
        # geometry placements in joint frames, for batched transforms of the exact checks
        self._gR = np.array([p.R for p in parts])
        self._gp = np.array([p.p for p in parts])
        # tables of the compiled broadphase (`broadphase.world_candidates` / `self_candidates`)
        i64 = lambda a: np.ascontiguousarray(a, dtype=np.int64)  # noqa: E731
        f64 = lambda a: np.ascontiguousarray(a, dtype=np.float64)  # noqa: E731
        mem_count = np.array([m.size for m in members], dtype=np.int64)
        covers = (i64(self._pj), i64(self._coarse.start), i64(self._coarse.count), f64(self._coarse.centres),
                  f64(self._coarse.radii))
        self._bp_world = (self._l0_joint, f64(np.array([c for c, _ in balls]).reshape(-1, 3)),
                          f64([r for _, r in balls]), i64(np.cumsum(mem_count) - mem_count), mem_count,
                          i64(np.concatenate(members) if members else np.zeros(0)), *covers,
                          i64(self._fine.start), i64(self._fine.count), f64(self._fine.centres), f64(self._fine.radii))
        self._bp_pairs = i64(self._pairs[pair_order].reshape(-1, 2))  # part pairs grouped by body pair
        self._bp_self = (body_joint, f64(np.array([c for c, _ in body_balls]).reshape(-1, 3)), f64([r for _, r in body_balls]),
                         self._bpairs, i64(np.cumsum(pair_count) - pair_count), pair_count, self._bp_pairs, *covers)
        self._req_self = coal.CollisionRequest()
        self._req_self.security_margin = self._self_padding
        self._update_static()

    def _rebuild_world(self) -> None:
        obs = self._world.obstacles
        O = len(obs)
        self._obs = obs
        self._oR = np.zeros((O, 3, 3))
        self._oc = np.zeros((O, 3))
        self._oh = np.zeros((O, 3))
        self._orho = np.zeros(O)
        self._ocyl = np.zeros(O, dtype=bool)
        self._ogeom = []
        self._otf = []
        for i, ob in enumerate(obs):
            R = ob.pose.rotation
            self._oR[i] = R
            c_local, h = ob.local_aabb()
            self._oc[i] = ob.pose.position + R @ c_local
            if isinstance(ob, Sphere):
                self._oh[i] = 0.0
                self._orho[i] = ob.radius
            elif isinstance(ob, Capsule):
                self._oh[i] = [0.0, 0.0, ob.height / 2.0]
                self._orho[i] = ob.radius
            elif isinstance(ob, Cylinder):
                self._oh[i] = [ob.radius, ob.radius, ob.height / 2.0]
                self._ocyl[i] = True
            else:  # cuboid, mesh (bounding box)
                self._oh[i] = h
            key = id(ob)
            if key not in self._obstacle_cache:  # keep coal geometries of unchanged obstacles
                self._obstacle_cache[key] = (ob, coal_geometry(ob))
            self._ogeom.append(self._obstacle_cache[key][1])
            self._otf.append(_tf(R, ob.pose.position))
        live = {id(o) for o in obs}
        self._obstacle_cache = {k: v for k, v in self._obstacle_cache.items() if k in live}
        self._any_cyl = bool(self._ocyl.any())
        self._bp_obstacles = (np.ascontiguousarray(self._oR), np.ascontiguousarray(self._oc), np.ascontiguousarray(self._oh),
                              np.ascontiguousarray(self._orho), np.ascontiguousarray(self._ocyl))
        self._req_world = coal.CollisionRequest()
        self._req_world.security_margin = self._padding
        self._update_static()

    def _update_static(self) -> None:
        """Parts fixed to the base (joint 0) vs the world: the same answer for every q."""
        if not hasattr(self, "_obs") or not hasattr(self, "_parts"):
            return
        self._moving = np.nonzero(self._pj != 0)[0]
        static = []
        res = coal.CollisionResult()
        for g in np.nonzero(self._pj == 0)[0]:
            part = self._parts[int(g)]
            tf = _tf(part.R, part.p)
            for o in range(len(self._obs)):
                res.clear()
                if coal.collide(part.geometry, tf, self._ogeom[o], self._otf[o], self._req_world, res):
                    static.append((int(g), o))
        self._static_world = static

    # ------------------------------------------------------------------ geometry helpers
    def _sd_all(self, X: np.ndarray) -> np.ndarray:
        """Signed distances (M, O) of points X (M, 3) to every obstacle's broadphase shape."""
        d = X[:, None, :] - self._oc[None]
        L = np.einsum("moj,oji->moi", d, self._oR)
        return _sd_local(L, self._oh[None], self._orho[None], self._ocyl[None] if self._any_cyl else None)

    def _fk(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint frames (N, J+1, 3, 3), (N, J+1, 3) (the compiled batched kinematics)."""
        return self.kinematics.joint_transforms(Q)

    def _part_tf(self, R: np.ndarray, p: np.ndarray, n: int, g: int) -> coal.Transform3s:
        part = self._parts[g]
        Rj, pj = R[n, part.joint], p[n, part.joint]
        return _tf(Rj @ part.R, pj + Rj @ part.p)

    # ------------------------------------------------------------------ broadphase
    def _candidates(self, Q: np.ndarray, R: np.ndarray, p: np.ndarray, world: bool = True, self_: bool = True,
                    deepest_first: bool = False):
        """Pairs the balls cannot clear (the compiled `broadphase` kernels).

        Returns:
            (n (T,), kind (T,) 0=world/1=self, i (T,), j (T,)): for world i = part and
            j = obstacle; for self (i, j) = parts. Sorted by configuration then depth, or
            by depth alone with `deepest_first`.
        """
        ns, kinds, ii, jj, depth = [], [], [], [], []
        if world and len(self._obs) and self._l0_joint.size:
            n, g, o, d = broadphase.world_candidates(R, p, self._padding + 1e-9, *self._bp_world, *self._bp_obstacles)
            if n.size:
                ns.append(n); kinds.append(np.zeros(n.size, dtype=np.int64)); ii.append(g); jj.append(o); depth.append(d)
        if self_ and self._bpairs.shape[0]:
            n, k, d = broadphase.self_candidates(R, p, self._self_padding + 1e-9, *self._bp_self)
            if n.size:
                pairs = self._bp_pairs
                ns.append(n); kinds.append(np.ones(n.size, dtype=np.int64))
                ii.append(pairs[k, 0]); jj.append(pairs[k, 1]); depth.append(d)
        if not ns:
            e = np.zeros(0, dtype=np.int64)
            return e, e, e, e
        if len(ns) == 1:
            n, kind, i, j, d = ns[0], kinds[0], ii[0], jj[0], depth[0]
        else:
            n = np.concatenate(ns); kind = np.concatenate(kinds); i = np.concatenate(ii); j = np.concatenate(jj)
            d = np.concatenate(depth)
        order = np.argsort(d, kind="stable") if deepest_first else np.lexsort((d, n))
        return n[order], kind[order], i[order], j[order]

    def _exact(self, R, p, n: int, kind: int, i: int, j: int, tfs: dict) -> bool:
        key = (n, i)
        tfa = tfs.get(key)
        if tfa is None:
            tfa = tfs[key] = self._part_tf(R, p, n, i)
        res = coal.CollisionResult()
        if kind == 0:
            return bool(coal.collide(self._parts[i].geometry, tfa, self._ogeom[j], self._otf[j], self._req_world, res))
        key = (n, j)
        tfb = tfs.get(key)
        if tfb is None:
            tfb = tfs[key] = self._part_tf(R, p, n, j)
        return bool(coal.collide(self._parts[i].geometry, tfa, self._parts[j].geometry, tfb, self._req_self, res))

    def _check(self, Q: np.ndarray, stop_at_first: bool = False, group: np.ndarray | None = None,
               deepest_first: bool = True) -> np.ndarray:
        """(N,) bool: which configurations of Q (N, dof) collide.

        Args:
            stop_at_first: stop at the first collision found (only `out.any()` is meaningful).
            group: (N,) ints: stop looking in a group once one of its configurations collides
                (only `out[group == g].any()` is meaningful for each group g).
            deepest_first: with `stop_at_first` or `group`, try the most penetrating ball
                pairs first (the likeliest collisions); else go in configuration order, so
                that with `stop_at_first` the first True is the first colliding row.
        """
        if self._static_world:
            return np.ones(Q.shape[0], dtype=bool)
        if stop_at_first:
            group = np.zeros(Q.shape[0], dtype=np.int64)
        ordered = not (deepest_first and group is not None)
        if group is None:  # every configuration on its own
            group = np.arange(Q.shape[0])
        out = np.zeros(Q.shape[0], dtype=bool)
        done: set[int] = set()
        for s in range(0, Q.shape[0], _CHUNK):  # bounded memory for large batches
            self._check_chunk(Q[s:s + _CHUNK], group[s:s + _CHUNK], not ordered, done, out[s:s + _CHUNK])
            if stop_at_first and done:
                break
        return out

    def _check_chunk(self, Q: np.ndarray, group: np.ndarray, deepest_first: bool, done: set[int], out: np.ndarray) -> None:
        """`_check` of at most _CHUNK configurations: sets `out` where they collide, skipping
        the groups (N,) in `done` and adding those found colliding."""
        R, p = self._fk(Q)
        n, kind, i, j = self._candidates(Q, R, p, deepest_first=deepest_first)
        if n.size == 0:
            return
        # world placements of both geometries of every candidate pair, in one go
        selfp = kind == 1
        RA, pA = broadphase.part_placements(R, p, n, i, self._pj, self._gR, self._gp)
        RB, pB = broadphase.part_placements(R, p, n, np.where(selfp, j, 0), self._pj, self._gR, self._gp)
        geoms = [pt.geometry for pt in self._parts]
        ogeom, otf = self._ogeom, self._otf
        req_w, req_s = self._req_world, self._req_self
        res = coal.CollisionResult()
        Tf = coal.Transform3s
        collide = coal.collide
        keys = group[n].tolist()
        for nn, key, k, a, b, Ra_, pa_, Rb_, pb_ in zip(n.tolist(), keys, kind.tolist(), i.tolist(), j.tolist(),
                                                         RA, pA, RB, pB):
            if key in done:
                continue
            res.clear()
            if k == 0:
                hit = collide(geoms[a], Tf(Ra_, pa_), ogeom[b], otf[b], req_w, res)
            else:
                hit = collide(geoms[a], Tf(Ra_, pa_), geoms[b], Tf(Rb_, pb_), req_s, res)
            if hit:
                out[nn] = True
                done.add(key)

    # ------------------------------------------------------------------ public checks
    def in_collision(self, q: np.ndarray) -> bool:
        """True if configuration q (dof,) collides with the world (within the padding) or itself."""
        q = self.kinematics.check_q(q)
        if q.ndim != 1:
            raise InvalidInputError(f"in_collision takes one configuration ({self.kinematics.dof},); use in_collision_batch for {q.shape}")
        return bool(self._check(q[None])[0])

    def in_collision_batch(self, Q: np.ndarray) -> np.ndarray:
        """(N,) bool: `in_collision` of each row of Q (N, dof), computed together."""
        Q = self.kinematics.check_q(Q, "Q")
        if Q.ndim == 1:
            Q = Q[None]
        if Q.shape[0] == 0:
            return np.zeros(0, dtype=bool)
        return self._check(Q)

    def any_in_collision(self, Q: np.ndarray) -> bool:
        """True if any row of Q (N, dof) collides (stops at the first collision found)."""
        Q = self.kinematics.check_q(Q, "Q")
        if Q.ndim == 1:
            Q = Q[None]
        return bool(Q.shape[0] and self._check(Q, stop_at_first=True).any())

    def in_collision_exact(self, q: np.ndarray) -> bool:
        """`in_collision` without any broadphase: coal on every pair (slow; a reference)."""
        q = self.kinematics.check_q(q)
        if q.ndim != 1:
            raise InvalidInputError(f"q must have shape ({self.kinematics.dof},); got {q.shape}")
        R, p = self._fk(q[None])
        tfs: dict = {}
        for g in range(len(self._parts)):
            for o in range(len(self._obs)):
                if self._exact(R, p, 0, 0, g, o, tfs):
                    return True
        for a, b in self._pairs:
            if self._exact(R, p, 0, 1, int(a), int(b), tfs):
                return True
        return False

    def motion_valid(self, q0: np.ndarray, q1: np.ndarray, resolution: float = 0.01, chunk: int = 32) -> bool:
        """True if the straight joint-space segment q0 -> q1 is collision-free.

        Checks q0, q1 and evenly spaced configurations between them such that consecutive
        checked configurations differ by at most `resolution` [rad] on every joint (L-inf),
        in bisection order (coarse first), stopping at the first collision.

        Args:
            q0, q1: (dof,) endpoints.
            resolution: largest joint step between checked configurations [rad] > 0.
            chunk: size of the first (coarse) batch.
        """
        q0 = self.kinematics.check_q(q0, "q0")
        q1 = self.kinematics.check_q(q1, "q1")
        if q0.ndim != 1 or q1.ndim != 1:
            raise InvalidInputError(f"q0 and q1 must have shape ({self.kinematics.dof},)")
        if not (resolution > 0 and math.isfinite(resolution)):
            raise InvalidInputError(f"resolution must be a positive number [rad]; got {resolution!r}")
        steps = max(1, int(math.ceil(float(np.abs(q1 - q0).max()) / resolution - 1e-12)))
        order = _coarse_to_fine(steps)
        t = order / steps
        Q = q0[None] + t[:, None] * (q1 - q0)[None]
        if Q.shape[0] <= 2 * chunk:
            return not self._check(Q, stop_at_first=True).any()
        if self._check(Q[:chunk], stop_at_first=True).any():
            return False
        return not self._check(Q[chunk:], stop_at_first=True).any()

    def first_collision(self, q0: np.ndarray, q1: np.ndarray, resolution: float = 0.01, chunk: int = 48) -> float | None:
        """Advance along the straight segment q0 -> q1 until the first collision.

        The segment is sampled like `motion_valid` and checked in order, in chunks.

        Args:
            q0, q1: (dof,) endpoints.
            resolution: largest joint step between checked configurations [rad] > 0.
            chunk: configurations checked per batch.

        Returns:
            None if the whole segment is free, else the parameter t in [0, 1] of the first
            colliding sample (q0 + t (q1 - q0)); every sample before it is free, so the
            configuration one sample earlier (t - 1/steps, see `segment_steps`) is a valid
            place to stop (RRT-Connect's "connect" in one call).
        """
        q0 = self.kinematics.check_q(q0, "q0")
        q1 = self.kinematics.check_q(q1, "q1")
        if q0.ndim != 1 or q1.ndim != 1:
            raise InvalidInputError(f"q0 and q1 must have shape ({self.kinematics.dof},)")
        steps = self.segment_steps(q0, q1, resolution)
        t_all = np.arange(steps + 1) / steps
        d = q1 - q0
        for s in range(0, steps + 1, chunk):
            t = t_all[s:s + chunk]
            hit = self._check(q0[None] + t[:, None] * d[None], stop_at_first=True, deepest_first=False)
            if hit.any():
                return float(t[np.argmax(hit)])
        return None

    @staticmethod
    def segment_steps(q0: np.ndarray, q1: np.ndarray, resolution: float = 0.01) -> int:
        """Number of intervals `motion_valid` splits q0 -> q1 into: ceil(max|q1 - q0| / resolution), >= 1."""
        if not (resolution > 0 and math.isfinite(resolution)):
            raise InvalidInputError(f"resolution must be a positive number [rad]; got {resolution!r}")
        return max(1, int(math.ceil(float(np.abs(np.asarray(q1) - np.asarray(q0)).max()) / resolution - 1e-12)))

    def motion_valid_batch(self, Q0: np.ndarray, Q1: np.ndarray, resolution: float = 0.01) -> np.ndarray:
        """(M,) bool: `motion_valid` of the M straight segments Q0[m] -> Q1[m], checked together.

        All segments' coarse samples (endpoints and midpoints) are checked in one batch first,
        then the remaining samples of the segments still valid, so that several candidate
        edges (RRT extensions, shortcuts) cost about one call.

        Args:
            Q0, Q1: (M, dof) segment endpoints.
            resolution: largest joint step between checked configurations [rad] > 0.
        """
        Q0 = self.kinematics.check_q(Q0, "Q0")
        Q1 = self.kinematics.check_q(Q1, "Q1")
        if Q0.ndim == 1:
            Q0 = Q0[None]
        if Q1.ndim == 1:
            Q1 = Q1[None]
        if Q0.shape != Q1.shape:
            raise InvalidInputError(f"Q0 and Q1 must have the same shape (M, {self.kinematics.dof}); got {Q0.shape} and {Q1.shape}")
        if not (resolution > 0 and math.isfinite(resolution)):
            raise InvalidInputError(f"resolution must be a positive number [rad]; got {resolution!r}")
        return self._segments_valid(Q0, Q1, resolution)

    def _segments_valid(self, Q0: np.ndarray, Q1: np.ndarray, resolution: float, coarse: int = 9) -> np.ndarray:
        M = Q0.shape[0]
        valid = np.ones(M, dtype=bool)
        if M == 0:
            return valid
        D = Q1 - Q0
        steps = np.maximum(1, np.ceil(np.abs(D).max(axis=1) / resolution - 1e-12).astype(np.int64))
        first_q, first_seg, rest_q, rest_seg = [], [], [], []
        for m in range(M):
            order = _coarse_to_fine(int(steps[m]))
            t = order / steps[m]
            S = Q0[m] + t[:, None] * D[m]
            first_q.append(S[:coarse])
            first_seg.append(np.full(min(coarse, S.shape[0]), m))
            if S.shape[0] > coarse:
                rest_q.append(S[coarse:])
                rest_seg.append(np.full(S.shape[0] - coarse, m))
        seg = np.concatenate(first_seg)
        hit = self._check(np.concatenate(first_q), group=seg)
        valid[np.unique(seg[hit])] = False
        if rest_q and valid.any():
            Qr = np.concatenate(rest_q)
            seg = np.concatenate(rest_seg)
            keep = valid[seg]
            if keep.any():
                hit = self._check(Qr[keep], group=seg[keep])
                valid[np.unique(seg[keep][hit])] = False
        return valid

    def path_valid(self, path: np.ndarray, resolution: float = 0.01) -> PathCheck:
        """Check a piecewise-linear joint path (K, dof) densely (see `motion_valid`).

        Returns:
            PathCheck(valid, first_invalid_segment): segment s joins path[s] and path[s+1];
            for a single-configuration path a collision gives segment 0.
        """
        path = self.kinematics.check_q(path, "path")
        if path.ndim != 2 or path.shape[0] < 1:
            raise InvalidInputError(f"path must have shape (K, {self.kinematics.dof}) with K >= 1; got {path.shape}")
        if not (resolution > 0 and math.isfinite(resolution)):
            raise InvalidInputError(f"resolution must be a positive number [rad]; got {resolution!r}")
        if path.shape[0] == 1:
            bad = bool(self._check(path)[0])
            return PathCheck(not bad, 0 if bad else None)
        ok = self._segments_valid(path[:-1], path[1:], resolution)
        if ok.all():
            return PathCheck(True, None)
        return PathCheck(False, int(np.argmin(ok)))

    # ------------------------------------------------------------------ reports and distances
    def _pair_distance(self, geom_a, tf_a, geom_b, tf_b) -> float:
        res = coal.DistanceResult()
        return float(coal.distance(geom_a, tf_a, geom_b, tf_b, coal.DistanceRequest(), res))

    def collision_report(self, q: np.ndarray) -> CollisionReport:
        """Every colliding pair of configuration q (dof,), with signed distances, deepest first."""
        q = self.kinematics.check_q(q)
        if q.ndim != 1:
            raise InvalidInputError(f"q must have shape ({self.kinematics.dof},); got {q.shape}")
        Q = q[None]
        R, p = self._fk(Q)
        n, kind, i, j = self._candidates(Q, R, p)
        tfs: dict = {}
        contacts = []
        for g, o in self._static_world:
            tfs[(0, g)] = self._part_tf(R, p, 0, g)
            n, kind, i, j = np.r_[0, n], np.r_[0, kind], np.r_[g, i], np.r_[o, j]
        for t in range(n.size):
            k, a, b = int(kind[t]), int(i[t]), int(j[t])
            if not self._exact(R, p, 0, k, a, b, tfs):
                continue
            pa = self._parts[a]
            if k == 0:
                d = self._pair_distance(pa.hull, tfs[(0, a)], self._ogeom[b], self._otf[b])
                contacts.append(Contact("attached_world" if pa.attached else "world", pa.name, self._obs[b].name, d))
            else:
                pb = self._parts[b]
                d = self._pair_distance(pa.hull, tfs[(0, a)], pb.hull, tfs[(0, b)])
                if pb.attached:
                    pa, pb = pb, pa
                contacts.append(Contact("attached_self" if pa.attached else "self", pa.name, pb.name, d))
        contacts.sort(key=lambda c: c.distance)
        return CollisionReport(bool(contacts), tuple(contacts))

    def distance_report(self, q: np.ndarray) -> DistanceReport:
        """Smallest signed distances [m] of q (dof,) to the world and to itself (no padding).

        Meshes of the robot enter through their convex hulls (exact for convex link meshes
        such as the Panda's; otherwise a lower bound), which gives penetration depths (EPA)
        where mesh-vs-mesh queries cannot; obstacles are exact. Pairs whose bounding balls
        prove them farther than the best found are skipped (branch and bound).
        """
        q = self.kinematics.check_q(q)
        if q.ndim != 1:
            raise InvalidInputError(f"q must have shape ({self.kinematics.dof},); got {q.shape}")
        R, p = self._fk(q[None])
        pj = self._pj
        bc = np.einsum("gij,gj->gi", R[0, pj], self._pbc) + p[0, pj]
        tfs: dict = {}

        def tf(g: int):
            if (0, g) not in tfs:
                tfs[(0, g)] = self._part_tf(R, p, 0, g)
            return tfs[(0, g)]

        best_w, pair_w = math.inf, None
        O = len(self._obs)
        if O:
            lb = (self._sd_all(bc) - self._pbr[:, None]).ravel()
            for flat in np.argsort(lb):
                if lb[flat] >= best_w:
                    break
                g, o = divmod(int(flat), O)
                d = self._pair_distance(self._parts[g].hull, tf(g), self._ogeom[o], self._otf[o])
                if d < best_w:
                    best_w, pair_w = d, (g, o)
        best_s, pair_s = math.inf, None
        if self._pairs.shape[0]:
            a, b = self._pairs[:, 0], self._pairs[:, 1]
            lb = np.linalg.norm(bc[a] - bc[b], axis=1) - self._pbr[a] - self._pbr[b]
            for k in np.argsort(lb):
                if lb[k] >= best_s:
                    break
                ga, gb = int(a[k]), int(b[k])
                d = self._pair_distance(self._parts[ga].hull, tf(ga), self._parts[gb].hull, tf(gb))
                if d < best_s:
                    best_s, pair_s = d, (ga, gb)
        closest = None
        if pair_w is not None and best_w <= best_s:
            pa = self._parts[pair_w[0]]
            closest = Contact("attached_world" if pa.attached else "world", pa.name, self._obs[pair_w[1]].name, best_w)
        elif pair_s is not None:
            pa, pb = self._parts[pair_s[0]], self._parts[pair_s[1]]
            if pb.attached:
                pa, pb = pb, pa
            closest = Contact("attached_self" if pa.attached else "self", pa.name, pb.name, best_s)
        return DistanceReport(min(best_w, best_s), best_w, best_s, closest)

    def distance(self, q: np.ndarray) -> float:
        """Signed distance [m] of q (dof,): min over world and self pairs (negative = penetration)."""
        return self.distance_report(q).distance

    def world_clearance_batch(self, Q: np.ndarray) -> np.ndarray:
        """(N,) approximate signed clearance [m] of each configuration to the world (no padding).

        The smallest signed distance from the balls of the moving parts' sphere covers (and
        attached objects) to the obstacles, in closed form and vectorised: a lower bound of
        the true mesh distance when that is positive (the covers stick out of the meshes by
        up to ~2 cm), <= 0 when a part touches an obstacle; +inf without obstacles. Parts fixed
        to the base are left out (no configuration moves them). Cheap enough for
        finite-difference gradients over a batch.

        Args:
            Q: (N, dof) or (dof,) configurations.
        """
        Q = self.kinematics.check_q(Q, "Q")
        if Q.ndim == 1:
            Q = Q[None]
        N = Q.shape[0]
        O = len(self._obs)
        moving = self._fine.joint != 0
        if O == 0 or not moving.any():
            return np.full(N, np.inf)
        C = self._fine.centres[moving]
        r = self._fine.radii[moving]
        sj = self._fine.joint[moving]
        out = np.empty(N)
        for s in range(0, N, _CHUNK):
            R, p = self._fk(Q[s:s + _CHUNK])
            X = np.einsum("nsij,sj->nsi", R[:, sj], C) + p[:, sj]
            n = X.shape[0]
            sd = self._sd_all(X.reshape(-1, 3)).reshape(n, -1, O) - r[None, :, None]
            out[s:s + n] = sd.reshape(n, -1).min(axis=1)
        return out

    # ------------------------------------------------------------------ attached objects
    def attach_object(
        self,
        obstacle: str | Obstacle,
        q: np.ndarray | None = None,
        link: str | None = None,
        pose_in_link: Pose | Sequence[float] | None = None,
        allowed_links: Sequence[str] = (),
    ) -> AttachedObject:
        """Carry an object with a link (a grasp): it leaves the world and moves with the link.

        Args:
            obstacle: the name of an obstacle of the world (removed from it), or a shape.
            q: (dof,) the configuration at the grasp: the object keeps its current pose
                relative to the link at q. Needed unless `pose_in_link` is given.
            link: the carrying link; default the config's `ee_link` (panda_hand).
            pose_in_link: the object's pose in the link frame (overrides q).
            allowed_links: links never checked against the object, in addition to the
                links rigidly attached to the same joint as `link` (hand, fingers, ...).

        Returns:
            The `AttachedObject`. It is checked against the world (with the padding) and
            against the other links (with the self padding).
        """
        kin = self.kinematics
        link = link or self.config.ee_link
        fid = kin.frame_id(link)
        if isinstance(obstacle, str):
            shape = self._world.get(obstacle)
            in_world = True
        elif isinstance(obstacle, Obstacle) and type(obstacle) is not Obstacle:
            shape = obstacle
            in_world = False
            if shape.name in self._world:
                raise InvalidInputError(f"an obstacle named '{shape.name}' is in the world; attach it by name")
        else:
            raise InvalidInputError(f"obstacle must be an obstacle name or a shape; got {type(obstacle).__name__}")
        if shape.name in self._attached:
            raise InvalidInputError(f"'{shape.name}' is already attached")
        if pose_in_link is not None:
            from manip.collision.shapes import as_pose
            rel = as_pose(pose_in_link, f"attach '{shape.name}'")
        else:
            if q is None:
                raise InvalidInputError("attach_object needs q (the grasp configuration) or pose_in_link")
            q = kin.check_q(q)
            rel = kin.fk(q, link).inverse() @ shape.pose
        joint = kin.model.frames[fid].parentJoint
        rigid = {p.link for p in self.robot.parts if p.joint == joint}
        unknown = [n for n in allowed_links if n not in self.robot.link_names]
        if unknown:
            raise UnknownNameError("link", unknown[0], self.robot.link_names)
        att = AttachedObject(shape, link, rel, tuple(sorted(rigid | set(allowed_links))))
        if in_world:
            self._world.remove(shape.name)
            self._rebuild_world()
        self._attached[shape.name] = att
        self._rebuild_parts()
        return att

    def detach_object(self, q: np.ndarray, name: str | None = None) -> list[Obstacle]:
        """Put attached object(s) back into the world at their pose for configuration q.

        Args:
            q: (dof,) the configuration at release.
            name: the object to detach; None detaches all.

        Returns:
            The obstacles added to the world (base-frame poses at q).
        """
        q = self.kinematics.check_q(q)
        if name is not None and name not in self._attached:
            raise UnknownNameError("attached object", name, self._attached)
        names = [name] if name is not None else list(self._attached)
        out = []
        for nm in names:
            att = self._attached.pop(nm)
            T = self.kinematics.fk(q, att.link) @ att.pose_in_link
            ob = att.obstacle.with_pose(T)
            self._world.add(ob)
            out.append(ob)
        self._rebuild_parts()
        self._rebuild_world()
        return out

    # ------------------------------------------------------------------ introspection
    @property
    def num_spheres(self) -> int:
        """Number of balls in the robot's (and attached objects') sphere covers."""
        return int(self._fine.radii.size)

    def spheres(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[str]]:
        """The sphere covers at q (dof,): centres (S, 3) [m], radii (S,) [m], owner names (S,)."""
        q = self.kinematics.check_q(q)
        R, p = self._fk(q[None])
        cs, rs, names = [], [], []
        for g, part in enumerate(self._parts):
            Rj, pj = R[0, part.joint], p[0, part.joint]
            cs.append(part.centres @ Rj.T + pj)
            rs.append(part.radii)
            names += [part.name] * len(part.radii)
        return np.concatenate(cs), np.concatenate(rs), names
