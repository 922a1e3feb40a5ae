"""Clearance maps of self-collision pairs over the joints that move them relative to each other.

A self pair whose relative placement depends on at most `MAX_MAP_JOINTS` revolute joints
but that can touch (so `manip.collision.self_pairs` cannot prove it clear everywhere) may
still be far apart in most of those joints' range while its sphere covers overlap (the UR10
forearm and wrist_2 link: 19 mm apart at most angles, closer than the covers' 2 cm
protrusion, so coal ran on them at every check). The map stores, for every cell of a grid
over one turn of each of those joints, a proved lower bound of the pair's distance over the
whole cell; the broadphase looks the cell of a configuration up (two floor operations) and
drops the pair when the bound exceeds the padding asked for.

Cells are bounded as in `manip.collision.self_pairs`: with d a lower bound of the pair's
distance at the cell's centre (the convex hulls' distance first, which is cheap and holds
the meshes, then coal's exact mesh distance when the hulls do not suffice), every point
moves by at most sum_k h_k rho_k over a cell of half widths h_k, ball by ball of the
sphere covers (`ball_slack`). The grid is refined like a quadtree, from `BASE_CELLS` to
`LOOKUP_CELLS` cells per turn; a cell whose bound stays below `PROOF_CLEARANCE` at the
finest level (the pair touches or nearly does there) is stored as -inf and stays checked.

A pair moved by one joint more (the UR10 forearm and wrist_3 link: wrist_1, wrist_2 and
wrist_3) is mapped when its fine covers overlap often (`SWEEP_OVERLAP`) and one of its parts
is carried by one of those joints: over the other joints, against that part swept over a
whole turn of its own joint (`_sweep`: a convex solid of revolution holding it at every
angle), so the bound holds whatever that joint's angle; only the part-wide motion bound is
used there (the swept part's cover is one ball).

A revolute joint's placement is 2 pi-periodic whatever its limits, so a configuration
outside the limits looks up a valid cell too (cells wholly outside the limits are never
computed: -inf). Results are cached on disk beside the sphere covers.
"""

from __future__ import annotations

import hashlib
import logging
import math
from collections.abc import Sequence
from dataclasses import replace
from typing import NamedTuple

import coal
import numpy as np

from manip.disk_cache import DiskCache
from manip.collision.self_pairs import PROOF_CLEARANCE, ball_slack, joint_reach, relative_joints
from manip.kinematics import Kinematics

logger = logging.getLogger(__name__)

#: Pairs whose relative placement depends on more joints than this get no map, except
#: pairs of one more joint where one part is carried by one of them (it turns about its
#: own axis): mapped over the others against that part swept over a whole turn, when
#: their fine covers overlap at >= `SWEEP_OVERLAP` of `OVERLAP_SAMPLES` seeded random
#: configurations (such maps cost more to build; only where the covers fail often).
MAX_MAP_JOINTS = 2
SWEEP_OVERLAP = 0.25
OVERLAP_SAMPLES = 500
#: Angles of the polygons circumscribing the circles of a swept part.
_SWEEP_ANGLES = 32
#: Cells per turn of each joint in the lookup grid (the finest level).
LOOKUP_CELLS = 128
#: Cells per turn of each joint at the first level of the refinement.
BASE_CELLS = 16
#: Distance queries (hull and mesh) spent on one map; cells left are stored as -inf.
MAP_QUERIES = 40000
_VERSION = "map-v1"
#: [m] taken off every stored bound (coal's distances converge from above to ~1e-6).
_SLACK = 2e-6
_MEMORY: dict[str, PairMap] = {}


class PairMap(NamedTuple):
    """A proved lower bound of one self pair's distance per cell of its joints' grid.

    Attributes:
        q_index: (n,) the q indices of the joints the pair's relative placement depends on.
        bounds: (LOOKUP_CELLS,) * n: the bound [m] over cell (i_0, ..., i_n-1), which holds
            q[q_index[k]] mod 2 pi in [i_k, i_k + 1] * 2 pi / LOOKUP_CELLS; -inf where none
            was proved.
    """

    q_index: np.ndarray
    bounds: np.ndarray

    def bound_at(self, q: np.ndarray) -> float:
        """The map's bound [m] at configuration q (dof,) (-inf where none was proved)."""
        n = self.bounds.shape[0]
        cell = tuple(int(math.floor(float(q[i]) * n / (2.0 * math.pi))) % n for i in self.q_index)
        return float(self.bounds[cell])

    @property
    def proved_fraction(self) -> float:
        """The fraction of the cells with a bound."""
        return float(np.isfinite(self.bounds).mean())


def convex_hull(geometry):
    """The convex hull of a coal mesh (which holds it), or None when it has none."""
    if not (hasattr(geometry, "num_tris") and hasattr(geometry, "buildConvexHull")):
        return None
    try:
        if geometry.convex is None:
            geometry.buildConvexHull(True, "Qt")
        return geometry.convex
    except Exception:  # pragma: no cover - qhull failure on degenerate meshes
        logger.debug("convex hull failed")
        return None


def build_pair_map(parts: Sequence, a: int, b: int, kinematics: Kinematics, *, digests: Sequence[str],
                   cache: DiskCache | None = None) -> PairMap | None:
    """The clearance map of parts a and b, or None when their relative placement depends on
    no joint, on a prismatic one, on more than `MAX_MAP_JOINTS` (one more when one part can
    be swept and the covers overlap often: see the module doc), or no cell was proved.

    Args:
        parts: the robot's parts (`RobotPart`: geometry, joint, placement, sphere cover).
        a, b: indices into `parts`.
        kinematics: the robot's `Kinematics`.
        digests: one string per part identifying its geometry, placement and cover.
        cache: the on-disk cache (None: no cache).
    """
    pa, pb = parts[a], parts[b]
    rel = relative_joints(kinematics, pa.joint, pb.joint)
    specs = kinematics.joint_specs
    if not rel or len(rel) > MAX_MAP_JOINTS + 1 or not all(specs[k - 1].revolute for k in rel):
        return None
    sweep = ""
    if len(rel) == MAX_MAP_JOINTS + 1:
        found = _swept_pair(pa, pb, rel, kinematics)
        if found is None:
            return None
        pa, pb = found
        rel = [k for k in rel if k != pb.joint]
        sweep = f"swept/{pb.name}/{_SWEEP_ANGLES}/{SWEEP_OVERLAP!r}/{OVERLAP_SAMPLES}"
    qidx = np.array([specs[k - 1].q_index for k in rel], dtype=np.int64)
    base = np.clip(np.zeros(kinematics.dof), kinematics.lower, kinematics.upper)
    chain_a = set(relative_joints(kinematics, pa.joint, 0))
    L = np.array([joint_reach(kinematics, pa if k in chain_a else pb, k) for k in rel])
    lo = kinematics.lower[qidx].astype(float)
    hi = kinematics.upper[qidx].astype(float)
    h = hashlib.sha1(f"{_VERSION}/{PROOF_CLEARANCE!r}/{LOOKUP_CELLS}/{BASE_CELLS}/{MAP_QUERIES}".encode())
    h.update(f"{digests[a]}/{digests[b]}/{sweep}".encode())
    for s in specs:
        h.update(s.R_placement.tobytes() + s.p_placement.tobytes() + s.axis.tobytes() + bytes([s.revolute]))
    h.update(np.asarray(rel, dtype=np.int64).tobytes() + lo.tobytes() + hi.tobytes() + base.tobytes())
    key = h.hexdigest()
    if key not in _MEMORY:
        bounds = _cached(cache, key)
        if bounds is None:
            bounds = _refine(pa, pb, kinematics, qidx, rel, lo, hi, L, base, balls=not sweep)
            _store(cache, key, bounds)
        _MEMORY[key] = PairMap(qidx, bounds)
    out = _MEMORY[key]
    return out if np.isfinite(out.bounds).any() else None


def _points(part) -> np.ndarray | None:
    """(V, 3) points whose convex hull holds the part, in its joint frame (meshes, boxes)."""
    g = part.geometry
    if hasattr(g, "num_tris") and hasattr(g, "vertices"):
        V = np.array(g.vertices(), dtype=float).reshape(-1, 3)
    elif isinstance(g, coal.Box):
        V = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
        V *= np.asarray(g.halfSide, dtype=float)
    else:
        return None
    return V @ np.asarray(part.R).T + np.asarray(part.p)


def _sweep(part, axis: np.ndarray) -> tuple[object, float] | None:
    """(convex solid of revolution holding `part` turned by any angle about `axis` through
    its joint's origin, its largest distance from the axis [m]).

    The part's points at (z, r) (along and from the axis) lie in the 2-D convex hull of
    those pairs and of their feet on the axis; revolving it, each vertex (z_i, r_i) gives a
    circle, held by the polygon circumscribing it (`_SWEEP_ANGLES` corners at r_i /
    cos(pi / angles)); the hull of all the corners holds every circle, hence every point
    of the part at every angle (each is a convex combination of circle points).
    """
    from scipy.spatial import ConvexHull, QhullError  # here: scipy.spatial costs ~0.25 s to import

    X = _points(part)
    if X is None:
        return None
    axis = axis / np.linalg.norm(axis)
    z = X @ axis
    r = np.linalg.norm(X - np.outer(z, axis), axis=1)
    prof = np.unique(np.round(np.c_[np.r_[z, z], np.r_[r, np.zeros_like(r)]], 12), axis=0)
    try:
        prof = prof[ConvexHull(prof).vertices]
    except QhullError:  # a degenerate (flat) profile: every point is kept
        pass
    u = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(axis, u)
    th = 2.0 * math.pi * np.arange(_SWEEP_ANGLES) / _SWEEP_ANGLES
    ring = np.outer(np.cos(th), u) + np.outer(np.sin(th), w)  # (A, 3)
    P = (prof[:, 0, None, None] * axis + (prof[:, 1, None, None] / math.cos(math.pi / _SWEEP_ANGLES)) * ring[None])
    points = coal.StdVec_Vec3s()
    for x in P.reshape(-1, 3):
        points.append(x)
    return coal.ConvexBase.convexHull(points, False, "Qt"), float(r.max())


def _overlap(pa, pb, kinematics: Kinematics) -> float:
    """The fraction of `OVERLAP_SAMPLES` seeded random configurations (within the limits) at
    which the fine sphere covers of parts pa and pb overlap."""
    Q = np.random.default_rng(0).uniform(kinematics.lower, kinematics.upper, size=(OVERLAP_SAMPLES, kinematics.dof))
    R, p = kinematics.joint_transforms(Q)
    Xa = np.einsum("nij,kj->nki", R[:, pa.joint], pa.centres) + p[:, pa.joint][:, None]
    Xb = np.einsum("nij,kj->nki", R[:, pb.joint], pb.centres) + p[:, pb.joint][:, None]
    gap = np.linalg.norm(Xa[:, :, None] - Xb[:, None], axis=3) - pa.radii[None, :, None] - pb.radii[None, None]
    return float((gap.min(axis=(1, 2)) < 0.0).mean())


def _swept_pair(pa, pb, rel: list[int], kinematics: Kinematics) -> tuple[object, object] | None:
    """(the other part, the swept part) for a pair moved by `rel` (MAX_MAP_JOINTS + 1 joints)
    whose fine covers overlap often, sweeping the part carried by one of those joints that
    turns closest about its axis; None when there is none."""
    if _overlap(pa, pb, kinematics) < SWEEP_OVERLAP:
        return None
    best = None
    for part, other in ((pa, pb), (pb, pa)):
        if part.joint not in rel:
            continue
        found = _sweep(part, kinematics.joint_specs[part.joint - 1].axis)
        if found is not None and (best is None or found[1] < best[0]):
            geom, radius = found
            reach = float(np.max(np.linalg.norm(_points(part), axis=1)))
            # the part swept about its joint: the solid in the joint frame, with one ball at the
            # joint's origin holding it (for the motion bounds of the joints further up)
            ball, radii = np.zeros((1, 3)), np.array([reach])
            best = (radius, other, replace(part, name=f"{part.name} (swept)", R=np.eye(3), p=np.zeros(3), geometry=geom,
                                           centres=ball, radii=radii, coarse_centres=ball, coarse_radii=radii))
    return None if best is None else (best[1], best[2])


def _cached(cache: DiskCache | None, key: str) -> np.ndarray | None:
    file = cache.find(f"pairmap-{key}.npz") if cache is not None else None
    if file is None:
        return None
    try:
        with np.load(file) as z:
            return np.asarray(z["bounds"], dtype=float)
    except Exception:  # a corrupt entry is recomputed
        return None


def _store(cache: DiskCache | None, key: str, bounds: np.ndarray) -> None:
    if cache is not None:
        cache.write(f"pairmap-{key}.npz", lambda path: np.savez(path, bounds=bounds))


def _in_limits(lo: float, hi: float) -> np.ndarray:
    """(LOOKUP_CELLS,) True for the cells of one turn that meet [lo, hi] (mod 2 pi)."""
    w = 2.0 * math.pi / LOOKUP_CELLS
    if hi - lo >= 2.0 * math.pi - w:
        return np.ones(LOOKUP_CELLS, dtype=bool)
    start = math.floor(lo / w)
    stop = math.floor(hi / w)
    out = np.zeros(LOOKUP_CELLS, dtype=bool)
    out[np.arange(start, stop + 1) % LOOKUP_CELLS] = True
    return out


def _distances(pa, pb, geoms: tuple, R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """(M,) coal's distance of the geometries `geoms` (of parts pa, pb) at M joint frames."""
    request, result = coal.DistanceRequest(), coal.DistanceResult()
    d = np.empty(R.shape[0])
    for i in range(R.shape[0]):
        tfs = [coal.Transform3s(R[i, x.joint] @ x.R, p[i, x.joint] + R[i, x.joint] @ x.p) for x in (pa, pb)]
        result.clear()
        d[i] = coal.distance(geoms[0], tfs[0], geoms[1], tfs[1], request, result) - _SLACK
    return d


def _refine(pa, pb, kinematics: Kinematics, qidx: np.ndarray, rel: list[int], lo: np.ndarray, hi: np.ndarray,
            L: np.ndarray, base: np.ndarray, balls: bool = True) -> np.ndarray:
    """The map's bounds (LOOKUP_CELLS,) * n, refined level by level (deterministic); `balls`:
    also bound ball by ball (not for a swept part, whose cover is one ball)."""
    n = qidx.size
    w = 2.0 * math.pi / LOOKUP_CELLS
    inside = [_in_limits(lo[k], hi[k]) for k in range(n)]
    bounds = np.full((LOOKUP_CELLS,) * n, -np.inf)
    hulls = (convex_hull(pa.geometry), convex_hull(pb.geometry))
    has_hulls = hulls[0] is not None or hulls[1] is not None
    hull_geoms = tuple(h if h is not None else part.geometry for h, part in zip(hulls, (pa, pb)))
    size = LOOKUP_CELLS // BASE_CELLS  # cell size in lookup cells
    cells = np.stack(np.meshgrid(*[np.arange(BASE_CELLS)] * n, indexing="ij"), axis=-1).reshape(-1, n) * size
    signs = np.stack(np.meshgrid(*[[0, 1]] * n, indexing="ij"), axis=-1).reshape(-1, n)
    queries = 0

    def meets_limits(C: np.ndarray, size: int) -> np.ndarray:
        ok = np.ones(C.shape[0], dtype=bool)
        for k in range(n):
            ok &= np.array([inside[k][c:c + size].any() for c in C[:, k]])
        return ok

    while cells.shape[0] and size >= 1:
        cells = cells[meets_limits(cells, size)]
        if queries + cells.shape[0] > MAP_QUERIES:
            logger.debug("self-pair map %s/%s: query budget spent at %d-cell level", pa.name, pb.name, size)
            break
        H = np.full((cells.shape[0], n), 0.5 * size * w)
        Q = np.tile(base, (cells.shape[0], 1))
        Q[:, qidx] = (cells + 0.5 * size) * w
        R, p = kinematics.joint_transforms(Q)

        def slack(d: np.ndarray) -> np.ndarray:
            if not balls:
                return d - H @ L
            parts_slack = [ball_slack(kinematics, pa, pb, rel, R[s:s + 256], p[s:s + 256], H[s:s + 256], L,
                                      d[s:s + 256]) for s in range(0, d.size, 256)]
            return np.maximum(d - H @ L, np.concatenate(parts_slack) if parts_slack else np.zeros(0))

        # the hulls' distance (a lower bound of the meshes'), then the meshes' where it is not enough
        d = _distances(pa, pb, hull_geoms, R, p)
        queries += cells.shape[0]
        s = slack(d)
        if has_hulls:
            redo = np.flatnonzero(s <= PROOF_CLEARANCE)
            if redo.size:
                if queries + redo.size > MAP_QUERIES:
                    break
                d[redo] = _distances(pa, pb, (pa.geometry, pb.geometry), R[redo], p[redo])
                queries += redo.size
                s = slack(d)
        done = s > PROOF_CLEARANCE
        for c, v in zip(cells[done], s[done]):
            block = tuple(slice(int(c[k]), int(c[k]) + size) for k in range(n))
            bounds[block] = v
        size //= 2
        cells = (cells[~done][:, None, :] + signs[None] * size).reshape(-1, n) if size >= 1 else cells[:0]
    logger.debug("self-pair map %s/%s: %d queries, %.1f %% of the cells proved", pa.name, pb.name, queries,
                 100.0 * np.isfinite(bounds).mean())
    return bounds
