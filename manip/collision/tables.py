"""The tables `CollisionChecker` checks with, built from the robot's geometry and the world.

- `collect_parts`: every geometry moving with the robot (the robot's parts from
  `RobotGeometry`, plus attached objects with their own sphere covers) and the part pairs
  checked for self-collision.
- `part_tables`: the flat arrays of the compiled broadphase (`manip.collision.broadphase`)
  for those parts: fine and coarse sphere covers, one bounding ball per part, per moving
  joint and per body, and the body pairs grouping the enabled part pairs.
- `ObstacleTables`: the world's obstacles as broadphase shapes (rounded boxes and
  cylinders in closed form, meshes through their bounding box) and as coal geometries.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Mapping, NamedTuple, Sequence

import coal
import numpy as np

from manip.collision.occupancy import OccupancyMap
from manip.collision.pair_maps import PairMap, convex_hull
from manip.collision.results import AttachedObject
from manip.collision.robot_geometry import COARSE_MAX_SPHERES, COARSE_TOLERANCE, RobotGeometry, sphere_cover
from manip.collision.shapes import Capsule, Cylinder, Obstacle, Sphere, coal_geometry
from manip.kinematics import Kinematics
from manip.pose import Pose

logger = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class Part:
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
    hull = convex_hull(geometry)
    return geometry if hull is None else hull


def coal_transform(R: np.ndarray, p: np.ndarray) -> coal.Transform3s:
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


class SphereTable:
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


# ---------------------------------------------------------------------- robot side
def collect_parts(robot: RobotGeometry, kinematics: Kinematics,
                  attached: Mapping[str, AttachedObject]) -> tuple[list[Part], list[tuple[int, int]]]:
    """The robot's parts then the attached objects, and the part pairs checked for self-collision
    (the robot's enabled pairs, then every attached object against every link it may touch)."""
    parts: list[Part] = []
    for rp in robot.parts:
        parts.append(Part(rp.link, False, rp.joint, rp.R, rp.p, rp.geometry, _hull(rp.geometry), rp.centres, rp.radii,
                           rp.coarse_centres, rp.coarse_radii))
    n_robot = len(parts)
    pairs = list(robot.self_pairs)
    kin = kinematics
    for name, att in attached.items():
        f = kin.model.frames[kin.frame_id(att.link)]
        T_joint_obj = Pose.from_matrix(f.placement.homogeneous) @ att.pose_in_link
        local = att.obstacle.with_pose(Pose(np.zeros(3)))
        geom = coal_geometry(local)
        C, r = sphere_cover(geom, robot.sphere_tolerance)
        Cc, rc = sphere_cover(geom, COARSE_TOLERANCE, COARSE_MAX_SPHERES)
        Rj = T_joint_obj.rotation
        pj = T_joint_obj.position
        parts.append(Part(name, True, f.parentJoint, Rj, pj, geom, _hull(geom), C @ Rj.T + pj, r, Cc @ Rj.T + pj, rc))
        ai = len(parts) - 1
        for i in range(n_robot):
            if parts[i].name not in att.allowed_links:
                pairs.append((i, ai))
    return parts, pairs


class PartTables(NamedTuple):
    """The arrays of the robot side (see `part_tables`)."""

    joint: np.ndarray         # (G,) joint of each part (0 = fixed to the base)
    fine: SphereTable        # the parts' fine sphere covers
    coarse: SphereTable      # the parts' coarse sphere covers
    ball_centres: np.ndarray  # (G, 3) one bounding ball per part (joint frame)
    ball_radii: np.ndarray    # (G,)
    l0_joint: np.ndarray      # the moving joints (level 0 of the world broadphase)
    pairs: np.ndarray         # (P, 2) enabled self-collision part pairs
    body_pairs: np.ndarray    # (B, 2) body pairs with at least one checked part pair
    gR: np.ndarray            # (G, 3, 3) geometry placements in joint frames
    gp: np.ndarray            # (G, 3)
    bp_world: tuple           # tables of `broadphase.world_candidates` (robot side)
    bp_pairs: np.ndarray      # (P', 2) checked part pairs (not proved clear) grouped by body pair
    bp_self: tuple            # tables of `broadphase.self_candidates`


def _fine_groups(fine: SphereTable, coarse: SphereTable) -> tuple[np.ndarray, ...]:
    """Each part's fine balls grouped by their nearest coarse ball (the tables of
    `broadphase.self_candidates`): (radii (Kc,), start (Kc,), count (Kc,), members (Kf,)),
    group k centred at coarse ball k's centre and holding its member fine balls."""
    Kc = coarse.radii.size
    radii = np.zeros(Kc)
    members: list[list[int]] = [[] for _ in range(Kc)]
    for g in range(coarse.start.size):
        fc = fine.centres_of(g)
        cs = coarse.start[g]
        cc = coarse.centres_of(g)
        if fc.shape[0] == 0:
            continue
        near = np.argmin(np.linalg.norm(fc[:, None] - cc[None], axis=2), axis=1)
        for b, k in enumerate(near):
            members[cs + k].append(int(fine.start[g] + b))
            radii[cs + k] = max(radii[cs + k], float(np.linalg.norm(fc[b] - cc[k]) + fine.radii_of(g)[b]))
    count = np.array([len(m) for m in members], dtype=np.int64)
    flat = np.array([i for m in members for i in m], dtype=np.int64)
    return (np.ascontiguousarray(radii), np.ascontiguousarray(np.cumsum(count) - count), count, flat)


def _map_tables(bp_pairs: np.ndarray, maps: Mapping[tuple[int, int], PairMap]) -> tuple[np.ndarray, ...]:
    """The clearance maps of the checked pairs `bp_pairs` (P, 2) as the tables of
    `broadphase.self_candidates`: (map of each pair (P,) or -1, q indices (M, 2), cells per
    joint (M, 2), start of each map in the flat bounds (M,), flat bounds)."""
    of_pair = np.full(bp_pairs.shape[0], -1, dtype=np.int64)
    q_rows, count_rows, starts, flat = [], [], [], []
    offset = 0
    for k, (a, b) in enumerate(bp_pairs.tolist()):
        m = maps.get((a, b))
        if m is None:
            continue
        of_pair[k] = len(q_rows)
        q = [int(i) for i in m.q_index]
        c = list(m.bounds.shape)
        q_rows.append(q + [q[0]] * (2 - len(q)))  # a map over one joint: one cell along the second
        count_rows.append(c + [1] * (2 - len(c)))
        starts.append(offset)
        flat.append(m.bounds.ravel())
        offset += m.bounds.size
    i64 = lambda a: np.ascontiguousarray(np.asarray(a, dtype=np.int64).reshape(-1, 2))  # noqa: E731
    return (of_pair, i64(q_rows), i64(count_rows), np.ascontiguousarray(starts, dtype=np.int64),
            np.ascontiguousarray(np.concatenate(flat) if flat else np.zeros(0), dtype=np.float64))


def part_tables(parts: Sequence[Part], pairs: Sequence[tuple[int, int]],
                skip: frozenset[tuple[int, int]] = frozenset(),
                maps: Mapping[tuple[int, int], PairMap] | None = None) -> PartTables:
    """The broadphase tables of `parts` and their enabled self-collision `pairs`; the pairs
    in `skip` (proved clear at the self padding) are left out of the broadphase tables (the
    checks and certificates) but kept in `pairs` (exact references, distances); `maps`
    gives the clearance maps of some pairs (`manip.collision.pair_maps`)."""
    G = len(parts)
    pj = np.array([p.joint for p in parts])
    fine = SphereTable([p.centres for p in parts], [p.radii for p in parts], pj)
    coarse = SphereTable([p.coarse_centres for p in parts], [p.coarse_radii for p in parts], pj)

    def bounding_ball(gs: Sequence[int]) -> tuple[np.ndarray, float]:
        """A ball holding every fine and coarse ball of the parts gs (joint frame)."""
        allc = np.concatenate([fine.centres_of(g) for g in gs] + [coarse.centres_of(g) for g in gs])
        allr = np.concatenate([fine.radii_of(g) for g in gs] + [coarse.radii_of(g) for g in gs])
        c = ((allc - allr[:, None]).min(axis=0) + (allc + allr[:, None]).max(axis=0)) / 2.0
        return c, float((np.linalg.norm(allc - c, axis=1) + allr).max())

    # one bounding ball per part (distance queries' branch and bound)
    balls = [bounding_ball([g]) for g in range(G)]
    pbc = np.array([c for c, _ in balls]).reshape(G, 3)
    pbr = np.array([r for _, r in balls])
    # level 0 of the world check: one bounding ball per moving joint (all its parts)
    joints = sorted({p.joint for p in parts if p.joint != 0})
    members = [np.array([g for g, p in enumerate(parts) if p.joint == j], dtype=np.int64) for j in joints]
    balls = [bounding_ball(m) for m in members]
    l0_joint = np.array(joints, dtype=np.int64)
    pair_arr = np.array(pairs, dtype=np.int64).reshape(-1, 2)
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
        if (int(a_), int(b_)) in skip:
            continue
        bpairs.setdefault((int(part_body[a_]), int(part_body[b_])), []).append(k)
    body_pairs = np.array(list(bpairs), dtype=np.int64).reshape(-1, 2)
    pair_count = np.array([len(m) for m in bpairs.values()], dtype=np.int64)
    pair_order = np.array([k for m in bpairs.values() for k in m], dtype=np.int64)
    body_balls = [bounding_ball(gs) for gs in body_parts]
    body_joint = np.array([parts[gs[0]].joint for gs in body_parts], dtype=np.int64)
    # tables of the compiled broadphase (`broadphase.world_candidates` / `self_candidates`)
    i64 = lambda a: np.ascontiguousarray(a, dtype=np.int64)  # noqa: E731
    f64 = lambda a: np.ascontiguousarray(a, dtype=np.float64)  # noqa: E731
    mem_count = np.array([m.size for m in members], dtype=np.int64)
    covers = (i64(pj), i64(coarse.start), i64(coarse.count), f64(coarse.centres), f64(coarse.radii))
    bp_world = (l0_joint, f64(np.array([c for c, _ in balls]).reshape(-1, 3)),
                f64([r for _, r in balls]), i64(np.cumsum(mem_count) - mem_count), mem_count,
                i64(np.concatenate(members) if members else np.zeros(0)), *covers,
                i64(fine.start), i64(fine.count), f64(fine.centres), f64(fine.radii))
    bp_pairs = i64(pair_arr[pair_order].reshape(-1, 2))
    bp_self = (body_joint, f64(np.array([c for c, _ in body_balls]).reshape(-1, 3)), f64([r for _, r in body_balls]),
               body_pairs, i64(np.cumsum(pair_count) - pair_count), pair_count, bp_pairs, *covers,
               f64(fine.centres), f64(fine.radii), *_fine_groups(fine, coarse), *_map_tables(bp_pairs, maps or {}))
    # geometry placements in joint frames, for batched transforms of the exact checks
    gR = np.array([p.R for p in parts])
    gp = np.array([p.p for p in parts])
    return PartTables(pj, fine, coarse, pbc, pbr, l0_joint, pair_arr, body_pairs, gR, gp, bp_world, bp_pairs, bp_self)


# ---------------------------------------------------------------------- world side
#: An obstacle whose top lies at most this far [m] above the base frame's xy-plane counts as
#: the surface the robot stands on (`ObstacleTables.below_base`).
SUPPORT_TOLERANCE = 1e-3
#: Where the closed-form broadphase shapes put an occupancy map [m] (never near the robot).
_FAR = 1e6


class ObstacleTables:
    """The obstacles as broadphase shapes (`broadphase` arrays, closed-form signed distances)
    and as coal geometries with their placements.

    Immutable once built: an edit of the world builds new tables (`added`, `removed`,
    `replaced` copy the arrays and change one row, O(obstacles) memory copies and no
    geometry rebuilt), so a `CollisionChecker` snapshot holding these tables never sees
    them change.

    Args:
        obstacles: the world's obstacles.
        cache: id(obstacle) -> (obstacle, coal geometry), reused for unchanged obstacles;
            updated in place (entries of obstacles no longer in the world are dropped).
    """

    def __init__(self, obstacles: list[Obstacle], cache: dict[int, tuple]):
        O = len(obstacles)
        self.obstacles = list(obstacles)
        self.R = np.zeros((O, 3, 3))
        self.c = np.zeros((O, 3))
        self.h = np.zeros((O, 3))
        self.rho = np.zeros(O)
        self.cyl = np.zeros(O, dtype=bool)
        self.geometries: list = []
        self.transforms: list = []
        for i, ob in enumerate(obstacles):
            R, c, h, rho, cyl, geom, tf = _obstacle_row(ob, cache)
            self.R[i], self.c[i], self.h[i], self.rho[i], self.cyl[i] = R, c, h, rho, cyl
            self.geometries.append(geom)
            self.transforms.append(tf)
        live = {id(o) for o in obstacles}
        for key in [k for k in cache if k not in live]:
            del cache[key]
        self._index_broadphase()

    def _index_broadphase(self) -> None:
        self.any_cyl = bool(self.cyl.any())
        #: (obstacle index, tables) of the occupancy maps (`manip.collision.occupancy`), which
        #: the closed-form shapes see as a row far away: their own kernels bound them
        self.occupancy_maps = tuple((i, ob.broadphase_tables) for i, ob in enumerate(self.obstacles)
                                    if isinstance(ob, OccupancyMap))
        #: the obstacle tables of `broadphase.world_candidates`
        self.broadphase = (np.ascontiguousarray(self.R), np.ascontiguousarray(self.c), np.ascontiguousarray(self.h),
                           np.ascontiguousarray(self.rho), np.ascontiguousarray(self.cyl))

    def _derived(self, obstacles, R, c, h, rho, cyl, geometries, transforms) -> ObstacleTables:
        out = ObstacleTables.__new__(ObstacleTables)
        out.obstacles, out.R, out.c, out.h, out.rho, out.cyl = obstacles, R, c, h, rho, cyl
        out.geometries, out.transforms = geometries, transforms
        out._index_broadphase()
        return out

    def added(self, obstacle: Obstacle, cache: dict[int, tuple]) -> ObstacleTables:
        """New tables with `obstacle` appended (these tables are unchanged)."""
        R, c, h, rho, cyl, geom, tf = _obstacle_row(obstacle, cache)
        return self._derived(
            self.obstacles + [obstacle], np.concatenate([self.R, R[None]]), np.concatenate([self.c, c[None]]),
            np.concatenate([self.h, h[None]]), np.append(self.rho, rho), np.append(self.cyl, cyl),
            self.geometries + [geom], self.transforms + [tf],
        )

    def removed(self, index: int, cache: dict[int, tuple]) -> ObstacleTables:
        """New tables without obstacle `index` (these tables are unchanged)."""
        cache.pop(id(self.obstacles[index]), None)
        keep = lambda lst: lst[:index] + lst[index + 1:]  # noqa: E731
        return self._derived(
            keep(self.obstacles), np.delete(self.R, index, axis=0), np.delete(self.c, index, axis=0),
            np.delete(self.h, index, axis=0), np.delete(self.rho, index), np.delete(self.cyl, index),
            keep(self.geometries), keep(self.transforms),
        )

    def replaced(self, index: int, obstacle: Obstacle, cache: dict[int, tuple]) -> ObstacleTables:
        """New tables with obstacle `index` replaced by `obstacle` (e.g. moved)."""
        cache.pop(id(self.obstacles[index]), None)
        row = _obstacle_row(obstacle, cache)
        arrays = [self.R.copy(), self.c.copy(), self.h.copy(), self.rho.copy(), self.cyl.copy()]
        for a, v in zip(arrays, row[:5]):
            a[index] = v
        lists = [list(self.obstacles), list(self.geometries), list(self.transforms)]
        for lst, v in zip(lists, (obstacle, row[5], row[6])):
            lst[index] = v
        return self._derived(lists[0], *arrays, lists[1], lists[2])

    def below_base(self, index: int | slice = slice(None)) -> np.ndarray:
        """(O,) True for the obstacles wholly below the base frame's xy-plane (their bounding
        shape's top at most SUPPORT_TOLERANCE [m] above z = 0): the ground or table the
        robot stands on (or that entry only, for an int `index`), and the occupancy maps
        (what cameras saw, floor included). Their contacts with the parts fixed to the base
        are not checked (no motion changes them); every moving part is checked against them."""
        R, h = self.R[index], self.h[index]
        top = self.c[index, 2] + (np.abs(R[..., 2, :]) * h).sum(axis=-1) + self.rho[index]
        below = top <= SUPPORT_TOLERANCE
        for i, _ in self.occupancy_maps:   # what cameras saw is never checked against the base's links
            if isinstance(index, slice):
                below[i] = True
            elif i == index:
                return np.True_
        return below

    def signed_distances(self, X: np.ndarray) -> np.ndarray:
        """Signed distances (M, O) of points X (M, 3) to every obstacle's broadphase shape."""
        d = X[:, None, :] - self.c[None]
        L = np.einsum("moj,oji->moi", d, self.R)
        out = _sd_local(L, self.h[None], self.rho[None], self.cyl[None] if self.any_cyl else None)
        for i, _ in self.occupancy_maps:
            out[:, i] = self.obstacles[i].lower_bounds(X)
        return out


def _obstacle_row(ob: Obstacle, cache: dict[int, tuple]) -> tuple:
    """(R (3, 3), centre (3,), half extents (3,), rounding, is_cylinder, coal geometry, coal
    placement) of one obstacle's broadphase shape; the geometry is taken from or put in `cache`."""
    key = id(ob)
    if isinstance(ob, OccupancyMap):   # bounded by its own kernels: a point far away here
        if key not in cache:
            cache[key] = (ob, coal_geometry(ob))
        return (np.eye(3), np.full(3, _FAR), np.zeros(3), 0.0, False, cache[key][1],
                coal_transform(np.eye(3), np.zeros(3)))
    R = ob.pose.rotation
    c_local, h = ob.local_aabb()
    c = ob.pose.position + R @ c_local
    rho, cyl = 0.0, False
    if isinstance(ob, Sphere):
        h, rho = np.zeros(3), ob.radius
    elif isinstance(ob, Capsule):
        h, rho = np.array([0.0, 0.0, ob.height / 2.0]), ob.radius
    elif isinstance(ob, Cylinder):
        h, cyl = np.array([ob.radius, ob.radius, ob.height / 2.0]), True
    if key not in cache:  # keep coal geometries of unchanged obstacles
        cache[key] = (ob, coal_geometry(ob))
    return R, c, np.asarray(h, dtype=float), float(rho), cyl, cache[key][1], coal_transform(R, ob.pose.position)
