"""Compiled (numba) broadphase of `CollisionChecker`: which (configuration, pair) candidates
the sphere covers cannot clear.

The covers hold every point of the geometry (see `manip.collision.spheres`), so a pair
whose balls all keep more than the margin apart is free for certain; every other pair is a
candidate for coal's exact narrowphase. These kernels only filter: they never decide a
collision. Each configuration is visited once, with the hierarchy

- world: one bounding ball per moving joint (all its parts) against each obstacle, then
  the part's coarse cover, then its fine cover;
- self: one bounding ball per body (parts moving together), then the pair's clearance map
  when it has one (a proved bound per cell of the few joints moving the pair,
  `manip.collision.pair_maps`), then the coarse covers of each enabled part pair, then
  their fine covers.

Obstacles are seen through their broadphase shape: a box (cuboids, mesh bounding boxes), a
rounded box (spheres, capsules) or a cylinder, given in their own frame by a centre `oc`,
rotation `oR`, half extents `oh` and rounding `orho`.

Array conventions: joint frames R (N, J+1, 3, 3), p (N, J+1, 3) as in
`Kinematics.joint_transforms`; ball centres (K, 3) in their joint's frame [m]; radii (K,) [m].
"""

from __future__ import annotations

import math

import numpy as np

from manip.jit import kernel

_TWO_PI = 2.0 * math.pi


@kernel
def _push(ids, depth, T, a, b, c, d):
    """Row T of the growing outputs ids (cap, 3) int64 and depth (cap,): (a, b, c) and d.

    Returns the (possibly reallocated, doubled) arrays.
    """
    if T == ids.shape[0]:
        ids2 = np.empty((2 * T, 3), dtype=np.int64)
        ids2[:T] = ids
        depth2 = np.empty(2 * T)
        depth2[:T] = depth
        ids, depth = ids2, depth2
    ids[T, 0] = a
    ids[T, 1] = b
    ids[T, 2] = c
    depth[T] = d
    return ids, depth


@kernel(inline="always")
def _place(R, p, n, j, c, out):
    """out (3,) = R[n, j] @ c + p[n, j]: a point of joint j's frame in the base frame."""
    for r in range(3):
        out[r] = R[n, j, r, 0] * c[0] + R[n, j, r, 1] * c[1] + R[n, j, r, 2] * c[2] + p[n, j, r]


@kernel(inline="always")
def _distance(x, i, y, j):
    """Euclidean distance [m] between the points x[i] and y[j] (rows of (N, 3) arrays)."""
    d0 = x[i, 0] - y[j, 0]
    d1 = x[i, 1] - y[j, 1]
    d2 = x[i, 2] - y[j, 2]
    return math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)


@kernel(inline="always")
def obstacle_local(x, o, oR, oc):
    """The point x (3,) (base frame) in obstacle o's frame, oR^T (x - oc): (l0, l1, l2) [m]."""
    d0 = x[0] - oc[o, 0]
    d1 = x[1] - oc[o, 1]
    d2 = x[2] - oc[o, 2]
    l0 = oR[o, 0, 0] * d0 + oR[o, 1, 0] * d1 + oR[o, 2, 0] * d2
    l1 = oR[o, 0, 1] * d0 + oR[o, 1, 1] * d1 + oR[o, 2, 1] * d2
    l2 = oR[o, 0, 2] * d0 + oR[o, 1, 2] * d1 + oR[o, 2, 2] * d2
    return l0, l1, l2


@kernel(inline="always")
def _obstacle_sd(x, o, oR, oc, oh, orho, ocyl):
    """Signed distance [m] of the point x (3,) (base frame) to obstacle o's broadphase shape."""
    l0, l1, l2 = obstacle_local(x, o, oR, oc)
    z = abs(l2) - oh[o, 2]
    if ocyl[o]:
        r = math.sqrt(l0 * l0 + l1 * l1) - oh[o, 0]
        inside = min(max(r, z), 0.0)
        r = max(r, 0.0)
        z = max(z, 0.0)
        return math.sqrt(r * r + z * z) + inside
    a = abs(l0) - oh[o, 0]
    b = abs(l1) - oh[o, 1]
    inside = min(max(max(a, b), z), 0.0)
    a = max(a, 0.0)
    b = max(b, 0.0)
    z = max(z, 0.0)
    return math.sqrt(a * a + b * b + z * z) + inside - orho[o]


@kernel(inline="always")
def cover_clearance(R, p, n, g, o, margin, part_joint, c_start, c_count, c_centres, c_radii,
                    f_start, f_count, f_centres, f_radii, oR, oc, oh, orho, ocyl, x):
    """Part g's smallest fine-ball clearance [m] to obstacle o in configuration n, or inf when
    every ball of its coarse cover keeps `margin` [m] away (then no fine ball is placed); x (3,)
    is work space. Arguments as in `world_candidates`."""
    j = part_joint[g]
    near = False
    for b in range(c_start[g], c_start[g] + c_count[g]):
        _place(R, p, n, j, c_centres[b], x)
        if _obstacle_sd(x, o, oR, oc, oh, orho, ocyl) - c_radii[b] < margin:
            near = True
            break
    m = np.inf
    if not near:
        return m
    for b in range(f_start[g], f_start[g] + f_count[g]):
        _place(R, p, n, j, f_centres[b], x)
        s = _obstacle_sd(x, o, oR, oc, oh, orho, ocyl) - f_radii[b]
        if s < m:  # noqa: PLR1730 (a NaN distance leaves m as it is)
            m = s
    return m


@kernel
def world_candidates(R, p, margin,
                     l0_joint, l0_c, l0_r, mem_start, mem_count, mem_parts,
                     part_joint, c_start, c_count, c_centres, c_radii,
                     f_start, f_count, f_centres, f_radii,
                     oR, oc, oh, orho, ocyl):
    """(configuration, moving part, obstacle) triples the covers cannot clear by `margin` [m].

    Args:
        R, p: joint frames of N configurations.
        margin: the padding [m] (pairs closer than this are candidates).
        l0_joint (J0,), l0_c (J0, 3), l0_r (J0,): one bounding ball per moving joint.
        mem_start, mem_count (J0,), mem_parts: the parts of each moving joint (ragged).
        part_joint (G,): each part's joint.
        c_start, c_count (G,), c_centres (Kc, 3), c_radii (Kc,): coarse covers (ragged by part).
        f_start, f_count (G,), f_centres (Kf, 3), f_radii (Kf,): fine covers (ragged by part).
        oR (O, 3, 3), oc (O, 3), oh (O, 3), orho (O,), ocyl (O,): obstacle shapes.

    Returns:
        n, part, obstacle (T,) int64 and depth (T,): the smallest fine-ball clearance [m].
    """
    N = R.shape[0]
    O = oc.shape[0]
    ids = np.empty((64, 3), dtype=np.int64)
    depth = np.empty(64)
    T = 0
    x = np.empty(3)
    for n in range(N):
        for k in range(l0_joint.shape[0]):
            _place(R, p, n, l0_joint[k], l0_c[k], x)
            reach = l0_r[k] + margin
            for o in range(O):
                if _obstacle_sd(x, o, oR, oc, oh, orho, ocyl) >= reach:
                    continue
                for mi in range(mem_start[k], mem_start[k] + mem_count[k]):
                    g = mem_parts[mi]
                    m = cover_clearance(R, p, n, g, o, margin, part_joint, c_start, c_count, c_centres, c_radii,
                                        f_start, f_count, f_centres, f_radii, oR, oc, oh, orho, ocyl, x)
                    if m < margin:
                        ids, depth = _push(ids, depth, T, n, g, o, m)
                        T += 1
                # the joint ball centre was overwritten by the covers' balls
                _place(R, p, n, l0_joint[k], l0_c[k], x)
    return ids[:T, 0].copy(), ids[:T, 1].copy(), ids[:T, 2].copy(), depth[:T].copy()


@kernel
def self_candidates(R, p, Q, margin,
                    body_joint, body_c, body_r, bpairs, pp_start, pp_count, pairs,
                    part_joint, c_start, c_count, c_centres, c_radii,
                    f_centres, f_radii, g_radii, g_start, g_count, g_members,
                    m_of_pair, m_q, m_count, m_start, m_bounds):
    """(configuration, part pair) candidates of self-collision the covers cannot clear.

    Args:
        R, p: joint frames of N configurations.
        Q: (N, dof) the configurations [rad] (the clearance maps' cells).
        margin: the self padding [m].
        body_joint (B,), body_c (B, 3), body_r (B,): one bounding ball per body.
        bpairs (P, 2): body pairs with at least one enabled part pair.
        pp_start, pp_count (P,): the enabled part pairs of each body pair, as ragged
            ranges of `pairs` (Q, 2).
        part_joint, c_start, c_count, c_centres, c_radii: coarse covers as in
            `world_candidates`.
        f_centres (Kf, 3), f_radii (Kf,): the fine covers' balls.
        g_radii (Kc,), g_start, g_count (Kc,), g_members: the fine balls of each part grouped
            by their nearest coarse ball: group k (coarse ball k) holds the fine balls
            `g_members[g_start[k]:g_start[k] + g_count[k]]`, all inside the ball of coarse
            ball k's centre and radius g_radii[k]. Groups that cannot come closer than
            the best fine pair found so far are skipped (the clearance stays exact).
        m_of_pair (Q,): the clearance map of each pair of `pairs` (-1: none;
            `manip.collision.pair_maps`); map m bounds the pair's distance over the cells of
            a grid over one turn of the joints m_q[m] (2,) (q indices), m_count[m] (2,) cells
            each (1 for a map over one joint), row-major from m_bounds[m_start[m]]. A pair
            whose bound at a configuration's cell is >= margin is dropped there.
    Returns:
        n, pair index into `pairs` (T,) int64 and depth (T,): the larger of the smallest
        fine-ball clearance of the part pair and its map's bound [m] (a lower bound of the
        pair's distance).
    """
    N = R.shape[0]
    ids = np.empty((64, 3), dtype=np.int64)
    depth = np.empty(64)
    T = 0
    nb = body_c.shape[0]
    xb = np.empty((nb, 3))
    xc = np.empty((c_centres.shape[0], 3))
    placed = np.zeros(c_centres.shape[0], dtype=np.bool_)
    xf = np.empty((f_centres.shape[0], 3))
    fplaced = np.zeros(f_centres.shape[0], dtype=np.bool_)
    glb = np.empty(c_centres.shape[0] ** 2)
    for n in range(N):
        for b in range(nb):
            _place(R, p, n, body_joint[b], body_c[b], xb[b])
        placed[:] = False
        fplaced[:] = False
        for e in range(bpairs.shape[0]):
            a = bpairs[e, 0]
            b = bpairs[e, 1]
            d0 = xb[a, 0] - xb[b, 0]
            d1 = xb[a, 1] - xb[b, 1]
            d2 = xb[a, 2] - xb[b, 2]
            reach = body_r[a] + body_r[b] + margin
            if d0 * d0 + d1 * d1 + d2 * d2 >= reach * reach:
                continue
            for k in range(pp_start[e], pp_start[e] + pp_count[e]):
                mb = -np.inf
                mi = m_of_pair[k]
                if mi >= 0:
                    cell = 0
                    for d in range(2):
                        cnt = m_count[mi, d]
                        cell = cell * cnt + int(math.floor(Q[n, m_q[mi, d]] * cnt / _TWO_PI)) % cnt
                    mb = m_bounds[m_start[mi] + cell]
                    if mb >= margin:
                        continue
                ga = pairs[k, 0]
                gb = pairs[k, 1]
                for g in (ga, gb):
                    for i in range(c_start[g], c_start[g] + c_count[g]):
                        if not placed[i]:
                            _place(R, p, n, part_joint[g], c_centres[i], xc[i])
                            placed[i] = True
                m = np.inf
                for i in range(c_start[ga], c_start[ga] + c_count[ga]):
                    for j in range(c_start[gb], c_start[gb] + c_count[gb]):
                        s = _distance(xc, i, xc, j) - c_radii[i] - c_radii[j]
                        if s < m:
                            m = s
                if m >= margin:
                    continue
                # the coarse covers touch: the fine covers (tighter, more balls) decide, group
                # by group (the fine balls nearest each coarse ball), closest groups first
                na = c_count[ga]
                nb_ = c_count[gb]
                for u in range(na):
                    for v in range(nb_):
                        i = c_start[ga] + u
                        j = c_start[gb] + v
                        glb[u * nb_ + v] = _distance(xc, i, xc, j) - g_radii[i] - g_radii[j]
                order = np.argsort(glb[:na * nb_])
                m = np.inf
                for w in order:
                    if glb[w] >= m:
                        break
                    A = c_start[ga] + w // nb_
                    B = c_start[gb] + w % nb_
                    for ii in range(g_start[A], g_start[A] + g_count[A]):
                        i = g_members[ii]
                        if not fplaced[i]:
                            _place(R, p, n, part_joint[ga], f_centres[i], xf[i])
                            fplaced[i] = True
                        if _distance(xf, i, xc, B) - f_radii[i] - g_radii[B] >= m:
                            continue
                        for jj in range(g_start[B], g_start[B] + g_count[B]):
                            j = g_members[jj]
                            if not fplaced[j]:
                                _place(R, p, n, part_joint[gb], f_centres[j], xf[j])
                                fplaced[j] = True
                            s = _distance(xf, i, xf, j) - f_radii[i] - f_radii[j]
                            if s < m:
                                m = s
                if m < margin:
                    ids, depth = _push(ids, depth, T, n, k, 0, max(m, mb))
                    T += 1
    return ids[:T, 0].copy(), ids[:T, 1].copy(), depth[:T].copy()


@kernel
def part_placements(R, p, n, g, part_joint, gR, gp):
    """Base-frame placements of parts g (T,) in configurations n (T,).

    gR (G, 3, 3), gp (G, 3): each part's geometry frame in its joint frame.
    Returns Rw (T, 3, 3), pw (T, 3).
    """
    T = n.shape[0]
    Rw = np.empty((T, 3, 3))
    pw = np.empty((T, 3))
    for t in range(T):
        j = part_joint[g[t]]
        for r in range(3):
            for c in range(3):
                Rw[t, r, c] = (R[n[t], j, r, 0] * gR[g[t], 0, c] + R[n[t], j, r, 1] * gR[g[t], 1, c]
                               + R[n[t], j, r, 2] * gR[g[t], 2, c])
            pw[t, r] = (R[n[t], j, r, 0] * gp[g[t], 0] + R[n[t], j, r, 1] * gp[g[t], 1]
                        + R[n[t], j, r, 2] * gp[g[t], 2] + p[n[t], j, r])
    return Rw, pw
