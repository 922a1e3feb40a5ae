"""A coarse closed mesh that holds a fine one: the surface of the voxels its triangles touch.

`voxel_solid(V, F, cell)` marks every cell of a grid of edge `cell` that a triangle may touch
(each triangle cut into pieces no longer than a cell, each piece's bounding box marked),
fills what the marked cells enclose, fills the critical configurations that would make the
surface non-manifold (two cells meeting only at an edge or a corner; L. J. Latecki,
"3D well-composed pictures", 1997), and returns the boundary faces of the union as a closed,
consistently oriented triangle mesh. Used as a solid (`Mesh.decimated`), it holds every point
of the original triangles and of the volume they enclose, and lies within one cell diagonal
(`cell * sqrt(3)`) of them: coarser, never smaller.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from manip.errors import InvalidInputError

#: Largest grid (cells) `voxel_solid` builds.
MAX_CELLS = 64_000_000


def _mark(V: np.ndarray, F: np.ndarray, cell: float, origin: np.ndarray, shape: tuple[int, int, int]) -> np.ndarray:
    """Boolean grid (shape) of the cells that a triangle's pieces' bounding boxes touch."""
    grid = np.zeros(shape, dtype=bool)
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    longest = np.max(np.stack([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                               np.linalg.norm(a - c, axis=1)]), axis=0)
    parts = np.maximum(1, np.ceil(longest / cell)).astype(np.int64)
    for s in np.unique(parts):
        sel = parts == s
        A, B, C = a[sel], b[sel], c[sel]
        # the s^2 pieces of a uniform subdivision: corners at barycentric (i, j) / s
        corners = []
        for i in range(s):
            for j in range(s - i):
                corners.append(((i, j), (i + 1, j), (i, j + 1)))
                if i + j < s - 1:
                    corners.append(((i + 1, j), (i + 1, j + 1), (i, j + 1)))
        for tri in corners:
            P = [A + (B - A) * (i / s) + (C - A) * (j / s) for i, j in tri]
            lo = np.floor((np.minimum(np.minimum(P[0], P[1]), P[2]) - origin) / cell).astype(np.int64)
            hi = np.floor((np.maximum(np.maximum(P[0], P[1]), P[2]) - origin) / cell).astype(np.int64)
            span = hi - lo   # 0 or 1 per axis: a piece is no longer than a cell
            for dx in range(int(span[:, 0].max()) + 1):
                for dy in range(int(span[:, 1].max()) + 1):
                    for dz in range(int(span[:, 2].max()) + 1):
                        d = np.array([dx, dy, dz])
                        ok = np.all(d <= span, axis=1)
                        idx = lo[ok] + d
                        grid[idx[:, 0], idx[:, 1], idx[:, 2]] = True
    return grid


def _well_composed(grid: np.ndarray) -> np.ndarray:
    """Fill the cells of the critical configurations (until none is left): in any 2x2 square,
    two cells diagonal with the other two of the other kind; in any 2x2x2 block, two antipodal
    cells of one kind with the six others of the other kind. Only fills (never shrinks)."""
    g = grid
    for _ in range(1000):
        changed = False
        for axis in range(3):   # 2x2 squares normal to each axis
            u, v = [k for k in range(3) if k != axis]

            def sl(du: int, dv: int) -> tuple:
                idx = [slice(None)] * 3
                n_u, n_v = g.shape[u], g.shape[v]
                idx[u] = slice(du, n_u - 1 + du)
                idx[v] = slice(dv, n_v - 1 + dv)
                return tuple(idx)

            p00, p11, p01, p10 = g[sl(0, 0)], g[sl(1, 1)], g[sl(0, 1)], g[sl(1, 0)]
            diag = (p00 == p11) & (p01 == p10) & (p00 != p01)
            if diag.any():
                for d in ((0, 0), (1, 1), (0, 1), (1, 0)):
                    view = g[sl(*d)]
                    view |= diag
                changed = True
        n = [g[i:g.shape[0] - 1 + i, j:g.shape[1] - 1 + j, k:g.shape[2] - 1 + k]
             for i in (0, 1) for j in (0, 1) for k in (0, 1)]
        total = sum(x.astype(np.int8) for x in n)
        for c in range(4):   # antipodal pairs of the block's corners: (0, 7), (1, 6), (2, 5), (3, 4)
            a, b = n[c], n[7 - c]
            pair = a & b & (total == 2)
            hole = ~a & ~b & (total == 6)
            crit = pair | hole
            if crit.any():
                for x in n:
                    x |= crit
                changed = True
        if not changed:
            return g
    raise AssertionError("critical configurations did not resolve")  # pragma: no cover


def voxel_solid(V: np.ndarray, F: np.ndarray, cell: float, what: str = "mesh") -> tuple[np.ndarray, np.ndarray]:
    """A closed mesh holding the triangles (V (V, 3), F (F, 3)) and what they enclose.

    Args:
        cell: the grid's cell edge [m] > 0.

    Returns:
        (vertices (V', 3), faces (F', 3)): a closed, consistently oriented (outward) mesh.

    Raises:
        InvalidInputError: a cell so small that the grid would exceed MAX_CELLS.
    """
    lo, hi = V.min(axis=0), V.max(axis=0)
    n = np.floor((hi - lo) / cell).astype(np.int64) + 1
    cells = int(np.prod(n + 2))
    if cells > MAX_CELLS:
        need = float(np.max(hi - lo)) * (cells / MAX_CELLS) ** (1.0 / 3.0) / float(np.max(n))
        raise InvalidInputError(f"{what}: a {cell:g} m cell makes a grid of {cells:,} cells (at most "
                                f"{MAX_CELLS:,}); use a cell of at least {math.ceil(need * 1e4) / 1e4:g} m")
    origin = lo - cell   # one empty layer all round
    grid = _mark(V, F, cell, origin, tuple(int(x) for x in n + 2))
    grid = ndimage.binary_fill_holes(grid)
    grid = _well_composed(grid)
    # boundary faces: an occupied cell next to an empty one, as two triangles seen from outside
    faces = []
    shape = np.array(grid.shape)
    corner_id = lambda ijk: (ijk[:, 0] * (shape[1] + 1) + ijk[:, 1]) * (shape[2] + 1) + ijk[:, 2]  # noqa: E731
    occ = np.argwhere(grid)
    for axis in range(3):
        for sign in (-1, 1):
            nb = occ.copy()
            nb[:, axis] += sign
            inside = np.all((nb >= 0) & (nb < shape), axis=1)
            empty = np.ones(len(occ), dtype=bool)
            empty[inside] = ~grid[nb[inside, 0], nb[inside, 1], nb[inside, 2]]
            c = occ[empty] + (1 if sign > 0 else 0) * np.eye(3, dtype=np.int64)[axis]
            u, v = [k for k in range(3) if k != axis]
            eu, ev = np.eye(3, dtype=np.int64)[u], np.eye(3, dtype=np.int64)[v]
            q = [corner_id(c), corner_id(c + eu), corner_id(c + eu + ev), corner_id(c + ev)]
            if int(np.cross(eu, ev)[axis]) != sign:   # counter-clockwise seen from outside
                q = q[::-1]
            faces.append(np.stack([q[0], q[1], q[2]], axis=1))
            faces.append(np.stack([q[0], q[2], q[3]], axis=1))
    Fq = np.concatenate(faces)
    used, Fc = np.unique(Fq, return_inverse=True)
    i = used // ((shape[1] + 1) * (shape[2] + 1))
    j = (used // (shape[2] + 1)) % (shape[1] + 1)
    k = used % (shape[2] + 1)
    Vc = origin + cell * np.stack([i, j, k], axis=1).astype(float)
    return Vc, Fc.reshape(-1, 3).astype(np.int64)
