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

A revolute joint's placement is 2 pi-periodic whatever its limits, so a configuration
outside the limits looks up a valid cell too (cells wholly outside the limits are never
computed: -inf). Results are cached on disk beside the sphere covers.
"""

from __future__ import annotations

import hashlib
import logging
import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import coal
import numpy as np

from manip.collision.self_pairs import PROOF_CLEARANCE, ball_slack, joint_reach, relative_joints
from manip.kinematics import Kinematics

logger = logging.getLogger(__name__)

#: Pairs whose relative placement depends on more joints than this get no map.
MAX_MAP_JOINTS = 2
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
        n = LOOKUP_CELLS
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
                   cache: Path | None = None) -> PairMap | None:
    """The clearance map of parts a and b, or None when their relative placement depends on
    no joint, on more than `MAX_MAP_JOINTS` or on a prismatic one, or no cell was proved.

    Args:
        parts: the robot's parts (`RobotPart`: geometry, joint, placement, sphere cover).
        a, b: indices into `parts`.
        kinematics: the robot's `Kinematics`.
        digests: one string per part identifying its geometry, placement and cover.
        cache: folder of the on-disk cache (None: no cache).
    """
    pa, pb = parts[a], parts[b]
    rel = relative_joints(kinematics, pa.joint, pb.joint)
    specs = kinematics._joints
    if not rel or len(rel) > MAX_MAP_JOINTS or not all(specs[k - 1].revolute for k in rel):
        return None
    qidx = np.array([specs[k - 1].q_index for k in rel], dtype=np.int64)
    base = np.clip(np.zeros(kinematics.dof), kinematics.lower, kinematics.upper)
    chain_a = set(relative_joints(kinematics, pa.joint, 0))
    L = np.array([joint_reach(kinematics, pa if k in chain_a else pb, k) for k in rel])
    lo = kinematics.lower[qidx].astype(float)
    hi = kinematics.upper[qidx].astype(float)
    h = hashlib.sha1(f"{_VERSION}/{PROOF_CLEARANCE!r}/{LOOKUP_CELLS}/{BASE_CELLS}/{MAP_QUERIES}".encode())
    h.update(f"{digests[a]}/{digests[b]}".encode())
    for s in specs:
        h.update(s.R_placement.tobytes() + s.p_placement.tobytes() + s.axis.tobytes() + bytes([s.revolute]))
    h.update(np.asarray(rel, dtype=np.int64).tobytes() + lo.tobytes() + hi.tobytes() + base.tobytes())
    key = h.hexdigest()
    if key not in _MEMORY:
        bounds = _cached(cache, key)
        if bounds is None:
            bounds = _refine(pa, pb, kinematics, qidx, rel, lo, hi, L, base)
            _store(cache, key, bounds)
        _MEMORY[key] = PairMap(qidx, bounds)
    out = _MEMORY[key]
    return out if np.isfinite(out.bounds).any() else None


def _cached(cache: Path | None, key: str) -> np.ndarray | None:
    file = cache / f"pairmap-{key}.npz" if cache is not None else None
    if file is None or not file.is_file():
        return None
    try:
        with np.load(file) as z:
            return np.asarray(z["bounds"], dtype=float)
    except Exception:  # a corrupt entry is recomputed
        return None


def _store(cache: Path | None, key: str, bounds: np.ndarray) -> None:
    if cache is None:
        return
    file = cache / f"pairmap-{key}.npz"
    try:
        cache.mkdir(parents=True, exist_ok=True)
        tmp = file.with_suffix(f".{os.getpid()}.tmp.npz")
        np.savez(tmp, bounds=bounds)
        os.replace(tmp, file)
    except OSError as exc:
        logger.debug("self-pair map not cached (%s)", exc)


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
            L: np.ndarray, base: np.ndarray) -> np.ndarray:
    """The map's bounds (LOOKUP_CELLS,) * n, refined level by level (deterministic)."""
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
