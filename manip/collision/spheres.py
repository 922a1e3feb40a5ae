"""Automatic sphere covers of triangle meshes (no hand fitting).

`cover_with_spheres(vertices, faces)` returns balls whose union contains every point of the
mesh's surface. Construction (deterministic):

1. Candidate centres: grid points inside the mesh (ray-parity test), each with rho = its
   distance to the surface. A ball of radius rho + delta around such a point sticks out of
   a closed mesh by at most delta.
2. Greedy set cover of the (subdivided) triangles by those candidate balls, up to
   `max_spheres` balls; if that is not enough, delta is doubled and the tighter of the
   resulting covers (measured by `protrusion`) is kept.
3. Exact coverage: every sub-triangle is given to the ball that needs to grow least to hold
   its three vertices, and each radius is the largest distance to an assigned vertex. A ball
   holding a triangle's vertices holds the triangle (balls are convex), so the union covers
   the surface exactly, whatever the sampling.
"""

from __future__ import annotations

import numpy as np

# An irrational-looking ray direction: rays parallel to mesh edges or faces are unlikely.
_RAY = np.array([0.5377, 0.3119, 0.7834]) / np.linalg.norm([0.5377, 0.3119, 0.7834])


def subdivide(vertices: np.ndarray, faces: np.ndarray, resolution: float) -> tuple[np.ndarray, np.ndarray]:
    """Split every triangle into n^2 similar triangles so that every edge is <= resolution.

    Returns:
        (points (P, 3), triangles (T, 3) indices into points); points may repeat.
    """
    V = np.asarray(vertices, dtype=float)
    tris = V[np.asarray(faces)]  # (F, 3, 3)
    edges = np.stack([np.linalg.norm(tris[:, 1] - tris[:, 0], axis=1),
                      np.linalg.norm(tris[:, 2] - tris[:, 1], axis=1),
                      np.linalg.norm(tris[:, 0] - tris[:, 2], axis=1)], axis=1).max(axis=1)
    n_per = np.maximum(1, np.ceil(edges / resolution).astype(int))
    pts_out, tri_out = [], []
    offset = 0
    for n in np.unique(n_per):
        sel = tris[n_per == n]
        # barycentric grid of (n+1)(n+2)/2 points
        ij = [(i, j) for i in range(n + 1) for j in range(n + 1 - i)]
        index = {p: k for k, p in enumerate(ij)}
        bary = np.array([[1.0 - (i + j) / n, i / n, j / n] for i, j in ij])  # (G, 3)
        local = []
        for i in range(n):
            for j in range(n - i):
                local.append((index[(i, j)], index[(i + 1, j)], index[(i, j + 1)]))
                if i + j < n - 1:
                    local.append((index[(i + 1, j)], index[(i + 1, j + 1)], index[(i, j + 1)]))
        local = np.array(local)
        G = bary.shape[0]
        P = np.einsum("gk,fkd->fgd", bary, sel).reshape(-1, 3)
        T = (np.arange(sel.shape[0])[:, None, None] * G + local[None]).reshape(-1, 3) + offset
        pts_out.append(P)
        tri_out.append(T)
        offset += P.shape[0]
    return np.concatenate(pts_out), np.concatenate(tri_out)


def inside_mesh(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(M,) True for points inside a closed mesh (ray-parity test, Moller-Trumbore)."""
    tris = np.asarray(vertices, dtype=float)[np.asarray(faces)]
    v0, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    h = np.cross(_RAY, e2)  # (F, 3)
    a = np.einsum("fd,fd->f", e1, h)
    ok = np.abs(a) > 1e-12
    v0, e1, e2, h, a = v0[ok], e1[ok], e2[ok], h[ok], a[ok]
    inside = np.zeros(points.shape[0], dtype=bool)
    for start in range(0, points.shape[0], 512):
        P = points[start:start + 512]
        s = P[:, None, :] - v0[None]  # (M, F, 3)
        u = np.einsum("mfd,fd->mf", s, h) / a
        qv = np.cross(s, e1[None])
        v = (qv @ _RAY) / a
        t = np.einsum("mfd,fd->mf", qv, e2) / a
        hit = (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        inside[start:start + 512] = (hit.sum(axis=1) % 2) == 1
    return inside


def _fibonacci_sphere(n: int) -> np.ndarray:
    i = np.arange(n) + 0.5
    phi = np.arccos(1 - 2 * i / n)
    theta = np.pi * (1 + 5**0.5) * i
    return np.stack([np.cos(theta) * np.sin(phi), np.sin(theta) * np.sin(phi), np.cos(phi)], axis=1)


def protrusion(centres: np.ndarray, radii: np.ndarray, vertices: np.ndarray, faces: np.ndarray,
               surface: np.ndarray, closed: bool, directions: int = 96) -> float:
    """How far [m] the union of balls sticks out of the mesh (sampled on the balls' surfaces)."""
    D = _fibonacci_sphere(directions)
    S = (centres[:, None, :] + radii[:, None, None] * D[None]).reshape(-1, 3)
    # keep points on the union's boundary only
    d_other = np.sqrt(((S[:, None, :] - centres[None]) ** 2).sum(-1)) - radii[None]
    S = S[(d_other < -1e-9).sum(axis=1) == 0]
    if S.shape[0] == 0:
        return 0.0
    if closed:
        S = S[~inside_mesh(S, vertices, faces)]
        if S.shape[0] == 0:
            return 0.0
    best = np.full(S.shape[0], np.inf)
    for start in range(0, surface.shape[0], 2048):
        chunk = surface[start:start + 2048]
        best = np.minimum(best, np.sqrt(((S[:, None, :] - chunk[None]) ** 2).sum(-1)).min(axis=1))
    return float(best.max())


def is_closed(faces: np.ndarray) -> bool:
    """True when every edge of the mesh is shared by exactly two triangles."""
    F = np.asarray(faces)
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return bool(np.all(counts == 2))


_MAX_FINE_TRIANGLES = 40000
_MAX_COARSE_TRIANGLES = 2000
_MAX_GRID_POINTS = 20000
_MAX_CANDIDATES = 600
_MAX_CELLS = 4000


def _box_cells(lo: np.ndarray, hi: np.ndarray, spacing: float) -> np.ndarray:
    """(K, 8, 3) corners of cube cells tiling the box [lo, hi] with edges <= spacing."""
    edges = [np.linspace(lo[d], hi[d], max(1, int(np.ceil((hi[d] - lo[d]) / spacing))) + 1) for d in range(3)]
    a = [np.stack([e[:-1], e[1:]], axis=1) for e in edges]  # (n_d, 2)
    cells = []
    for i in range(2):
        for j in range(2):
            for k in range(2):
                X, Y, Z = np.meshgrid(a[0][:, i], a[1][:, j], a[2][:, k], indexing="ij")
                cells.append(np.stack([X, Y, Z], axis=-1).reshape(-1, 3))
    return np.stack(cells, axis=1)


def _sqdist(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Squared distances (len(A), len(B)) between point sets, via one matrix product."""
    d = (A * A).sum(1)[:, None] + (B * B).sum(1)[None] - 2.0 * (A @ B.T)
    return np.maximum(d, 0.0)


def _greedy_cover(need2: np.ndarray, rho: np.ndarray, delta: float, max_spheres: int) -> tuple[list[int], int]:
    """Greedy set cover of triangles by candidate balls of radius rho + delta, given the
    squared radius (M, T) each candidate needs to hold each triangle: (chosen indices,
    number of triangles left uncovered)."""
    T = need2.shape[1]
    covers = (need2 <= ((rho + delta) ** 2)[:, None]).astype(np.float32)
    uncovered = np.ones(T, dtype=np.float32)
    chosen: list[int] = []
    while uncovered.any() and len(chosen) < max_spheres:
        gain = covers @ uncovered
        best = int(np.argmax(gain))
        if gain[best] == 0:
            break
        chosen.append(best)
        uncovered *= 1.0 - covers[best]
    return chosen, int(uncovered.sum())


def cover_with_spheres(
    vertices: np.ndarray,
    faces: np.ndarray,
    tolerance: float = 0.02,
    max_spheres: int = 32,
    resolution: float | None = None,
    solid: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Balls whose union contains the whole surface of a triangle mesh (and, with `solid`,
    its whole bounding box volume: for solid primitives, whose inside counts as colliding).

    Centres are chosen among interior grid points by a greedy set cover: a centre c at
    distance rho(c) from the surface gets radius rho(c) + tolerance, which sticks out of a
    closed mesh by at most `tolerance` (any point of the ball outside the mesh lies within
    `tolerance` of where the ray from c crosses the surface). Surface parts left uncovered
    (thin features, or `max_spheres` reached) are given to the ball that needs to grow least.

    Args:
        vertices: (V, 3) [m].
        faces: (F, 3) vertex indices.
        tolerance: how far the balls may stick out of the mesh [m].
        max_spheres: upper bound on the number of balls.
        resolution: longest sub-triangle edge [m] of the subdivision on which coverage is
            enforced; default min(tolerance / 1.5, extent / 20).
        solid: also cover the mesh's bounding box (as cube cells, each held whole by one ball).

    Returns:
        (centres (K, 3) [m], radii (K,) [m]) in the mesh frame; the union of the balls
        contains every point of every triangle (and of the bounding box if `solid`).
    """
    V = np.asarray(vertices, dtype=float)
    F = np.asarray(faces, dtype=np.int64)
    extent = float((V.max(axis=0) - V.min(axis=0)).max())
    if extent <= 0:
        return V[:1].copy(), np.array([1e-9])
    tri = V[F]
    area = float(0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1).sum())
    res = resolution if resolution is not None else min(tolerance / 1.5, extent / 20.0)
    res = max(res, np.sqrt(2.0 * area / _MAX_FINE_TRIANGLES))  # bounded work for large meshes
    points, tris = subdivide(V, F, res)
    closed = is_closed(F)
    lo, hi = V.min(axis=0), V.max(axis=0)
    box_volume = float(np.prod(np.maximum(hi - lo, 1e-9)))
    step = max(min(extent / 12.0, max(tolerance, extent / 40.0)), (box_volume / _MAX_GRID_POINTS) ** (1.0 / 3.0))
    axes = [np.arange(lo[d] + step / 2, hi[d], step) if hi[d] - lo[d] > step else np.array([(lo[d] + hi[d]) / 2]) for d in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    cand = grid[inside_mesh(grid, V, F)] if closed else np.zeros((0, 3))
    if cand.shape[0] == 0:  # open or very thin mesh: centres on the surface itself
        cand = np.unique(np.round(points / step) * step, axis=0)
    if cand.shape[0] > _MAX_CANDIDATES:
        cand = cand[np.linspace(0, cand.shape[0] - 1, _MAX_CANDIDATES).astype(np.int64)]
    upts = np.unique(points, axis=0)
    rho = np.full(cand.shape[0], np.inf)
    for s in range(0, upts.shape[0], 4096):
        rho = np.minimum(rho, _sqdist(cand, upts[s:s + 4096]).min(axis=1))
    rho = np.sqrt(rho)
    # the greedy runs on a coarser subdivision; exact coverage is enforced on the fine one below
    # (a coarse triangle must fit in a candidate ball to count, so not coarser than the balls)
    coarse = min(max(2.0 * tolerance, extent / 15.0), 1.5 * (float(np.median(rho)) + tolerance))
    coarse = max(res, coarse, np.sqrt(2.0 * area / _MAX_COARSE_TRIANGLES))
    cpts, ctris = subdivide(V, F, coarse)
    # items to cover: convex pieces (triangles, cube cells) held whole by one ball each
    fine_items = [points[tris]]
    coarse_items = [cpts[ctris]]
    if solid:
        cell = max(res, (box_volume / _MAX_CELLS) ** (1.0 / 3.0))
        fine_items.append(_box_cells(lo, hi, cell))
        coarse_items.append(_box_cells(lo, hi, max(cell, coarse)))
    surf = points if points.shape[0] <= 2000 else points[:: int(np.ceil(points.shape[0] / 2000))]

    def need_of(items: list[np.ndarray], C: np.ndarray) -> np.ndarray:
        """(K, items) squared radius a ball at C[k] needs to hold each item."""
        out = []
        for it in items:
            v = it.shape[1]
            out.append(_sqdist(C, it.reshape(-1, 3)).reshape(C.shape[0], it.shape[0], v).max(axis=2))
        return np.concatenate(out, axis=1)

    def finish(chosen: list[int], delta: float) -> tuple[np.ndarray, np.ndarray]:
        if not chosen:
            chosen = [int(np.argmax(rho))]
        C = cand[chosen]
        R0 = rho[chosen] + delta
        need = np.sqrt(need_of(fine_items, C)).T  # (items, K)
        lab = np.argmin(need - R0[None], axis=1)  # the ball that needs to grow least
        R = np.zeros(C.shape[0])
        np.maximum.at(R, lab, need[np.arange(need.shape[0]), lab])
        keep = np.unique(lab)
        return C[keep], R[keep]

    # When max_spheres balls cannot cover at `tolerance` (thin plates, sharp edges), compare
    # inflating the balls found with covering at doubled protrusions; keep the tighter cover.
    best, best_protrusion = None, np.inf
    delta = tolerance
    need2 = need_of(coarse_items, cand)  # (M, items)
    for _ in range(4):
        chosen, left = _greedy_cover(need2, rho, delta, max_spheres)
        C, R = finish(chosen, delta)
        if left == 0:
            if best is None:
                best = (C, R)
            else:
                pr = protrusion(C, R, V, F, surf, closed)
                if pr < best_protrusion:
                    best = (C, R)
            break
        pr = protrusion(C, R, V, F, surf, closed)
        if pr < best_protrusion:
            best, best_protrusion = (C, R), pr
        delta *= 2.0
    assert best is not None
    return best
