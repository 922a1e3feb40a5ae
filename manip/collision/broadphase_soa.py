"""The world broadphase of `manip.collision.broadphase` over many configurations at once
(structure of arrays): the same candidates, the same depths, in the same order, cheaper per
configuration.

`broadphase.world_candidates` visits one configuration at a time: each moving joint's bounding
ball against every obstacle, then the part covers of the pairs that ball cannot clear. Most
configurations stop at the first level, which is branchy scalar code there. Here the first level
runs for all N configurations of a batch at once, with the configuration index innermost
(the ball centres as three (N,) lanes, one obstacle's shape held in registers, a loop without
branches the compiler vectorises); the covers of the (configuration, joint, obstacle) triples it
leaves are then visited in the per-configuration kernel's order. Every floating-point operation
on a value that is compared or returned is the one of `broadphase` (same operands, same order,
no `fastmath`), so every comparison, hence every candidate, is the same bit for bit.

Array conventions as in `manip.collision.broadphase`.
"""

from __future__ import annotations

import math

import numpy as np

from manip.collision.broadphase import _push, cover_clearance
from manip.jit import kernel

#: Configurations per block of the first level's bounding-box test.
LANES = 32
#: How far [m] beyond the reach a block's bounding box must keep for the block to be skipped:
#: far more than the rounding error of the signed distances (~1e-15 m).
SLACK = 1e-6


@kernel(inline="always")
def _place_lanes(R, p, joint, centres, X):
    """X (B, 3, N) = each ball b's centre centres[b] (joint joint[b]'s frame) placed in each
    configuration n (`_place`'s arithmetic), visited configuration by configuration (each one's
    frames stay in cache)."""
    for n in range(R.shape[0]):
        for b in range(joint.shape[0]):
            j = joint[b]
            c0, c1, c2 = centres[b, 0], centres[b, 1], centres[b, 2]
            for r in range(3):
                X[b, r, n] = R[n, j, r, 0] * c0 + R[n, j, r, 1] * c1 + R[n, j, r, 2] * c2 + p[n, j, r]


@kernel(inline="always")
def _lanes_near(X, oR, oc, oh, orho, ocyl, o, reach, near):
    """near (N,) bool: obstacle o's broadphase signed distance of the points X (3, N) [m] is not
    >= reach [m] (`broadphase._obstacle_sd`'s arithmetic, lane by lane, without branches)."""
    c0, c1, c2 = oc[o, 0], oc[o, 1], oc[o, 2]
    r00, r10, r20 = oR[o, 0, 0], oR[o, 1, 0], oR[o, 2, 0]
    r01, r11, r21 = oR[o, 0, 1], oR[o, 1, 1], oR[o, 2, 1]
    r02, r12, r22 = oR[o, 0, 2], oR[o, 1, 2], oR[o, 2, 2]
    h0, h1, h2 = oh[o, 0], oh[o, 1], oh[o, 2]
    rho = orho[o]
    x0, x1, x2 = X[0], X[1], X[2]
    N = x0.shape[0]
    if ocyl[o]:
        for n in range(N):
            d0 = x0[n] - c0
            d1 = x1[n] - c1
            d2 = x2[n] - c2
            l0 = r00 * d0 + r10 * d1 + r20 * d2
            l1 = r01 * d0 + r11 * d1 + r21 * d2
            l2 = r02 * d0 + r12 * d1 + r22 * d2
            z = abs(l2) - h2
            r = math.sqrt(l0 * l0 + l1 * l1) - h0
            inside = min(max(r, z), 0.0)
            r = max(r, 0.0)
            z = max(z, 0.0)
            near[n] = not (math.sqrt(r * r + z * z) + inside >= reach)
        return
    for n in range(N):
        d0 = x0[n] - c0
        d1 = x1[n] - c1
        d2 = x2[n] - c2
        l0 = r00 * d0 + r10 * d1 + r20 * d2
        l1 = r01 * d0 + r11 * d1 + r21 * d2
        l2 = r02 * d0 + r12 * d1 + r22 * d2
        z = abs(l2) - h2
        a = abs(l0) - h0
        b = abs(l1) - h1
        inside = min(max(max(a, b), z), 0.0)
        a = max(a, 0.0)
        b = max(b, 0.0)
        z = max(z, 0.0)
        near[n] = not (math.sqrt(a * a + b * b + z * z) + inside - rho >= reach)


@kernel
def _far_radii(oh, orho, ocyl):
    """(O,) the radius [m] of a ball about each obstacle's centre `oc` that holds its
    broadphase shape (box corners plus rounding; a cylinder's rim)."""
    O = oh.shape[0]
    out = np.empty(O)
    for o in range(O):
        if ocyl[o]:
            out[o] = math.sqrt(oh[o, 0] * oh[o, 0] + oh[o, 2] * oh[o, 2])
        else:
            out[o] = math.sqrt(oh[o, 0] * oh[o, 0] + oh[o, 1] * oh[o, 1] + oh[o, 2] * oh[o, 2]) + orho[o]
    return out


@kernel
def world_candidates(R, p, margin,
                     l0_joint, l0_c, l0_r, mem_start, mem_count, mem_parts,
                     part_joint, c_start, c_count, c_centres, c_radii,
                     f_start, f_count, f_centres, f_radii,
                     oR, oc, oh, orho, ocyl, lanes):
    """`broadphase.world_candidates` (same arguments, then `lanes`; same returns, identical
    values and order), its first level (each moving joint's ball against each obstacle) over
    the configurations `lanes` at a time: a block of lanes whose ball centres' bounding box
    keeps more than `SLACK` beyond the ball holding the obstacle is far for all of them (the
    obstacle's signed distance is at least that box-to-ball distance, and its rounding error
    is ~1e-15 m); the other blocks get each lane's signed distance."""
    N = R.shape[0]
    O = oc.shape[0]
    K = l0_joint.shape[0]
    ro = _far_radii(oh, orho, ocyl)
    KO = K * O
    trip = np.empty(64, dtype=np.int64)   # n * K * O + k * O + o of the triples the balls cannot clear
    nt = 0
    XK = np.empty((K, 3, N))
    _place_lanes(R, p, l0_joint, l0_c, XK)
    nk = np.empty(lanes, dtype=np.bool_)
    for k in range(K):
        X = XK[k]
        reach = l0_r[k] + margin
        for s in range(0, N, lanes):
            e = min(s + lanes, N)
            lo0, lo1, lo2 = X[0, s], X[1, s], X[2, s]
            hi0, hi1, hi2 = lo0, lo1, lo2
            total = 0.0
            for n in range(s, e):
                lo0 = min(lo0, X[0, n])
                hi0 = max(hi0, X[0, n])
                lo1 = min(lo1, X[1, n])
                hi1 = max(hi1, X[1, n])
                lo2 = min(lo2, X[2, n])
                hi2 = max(hi2, X[2, n])
                total += X[0, n] + X[1, n] + X[2, n]
            finite = total - total == 0.0   # no NaN or infinity among the lanes: the box holds them
            Xs = X[:, s:e]
            for o in range(O):
                if finite:
                    g0 = max(max(lo0 - oc[o, 0], oc[o, 0] - hi0), 0.0)
                    g1 = max(max(lo1 - oc[o, 1], oc[o, 1] - hi1), 0.0)
                    g2 = max(max(lo2 - oc[o, 2], oc[o, 2] - hi2), 0.0)
                    if math.sqrt(g0 * g0 + g1 * g1 + g2 * g2) - ro[o] - reach >= SLACK:
                        continue
                _lanes_near(Xs, oR, oc, oh, orho, ocyl, o, reach, nk)
                for n in range(e - s):
                    if nk[n]:
                        if nt == trip.shape[0]:
                            grown = np.empty(2 * nt, dtype=np.int64)
                            grown[:nt] = trip
                            trip = grown
                        trip[nt] = (s + n) * KO + k * O + o
                        nt += 1
    trip = np.sort(trip[:nt])   # the per-configuration kernel's order: n, then k, then o
    ids = np.empty((64, 3), dtype=np.int64)
    depth = np.empty(64)
    T = 0
    x = np.empty(3)
    for t in range(nt):
        n = trip[t] // KO
        k = (trip[t] // O) % K
        o = trip[t] % O
        for mi in range(mem_start[k], mem_start[k] + mem_count[k]):
            g = mem_parts[mi]
            m = cover_clearance(R, p, n, g, o, margin, part_joint, c_start, c_count, c_centres, c_radii,
                                f_start, f_count, f_centres, f_radii, oR, oc, oh, orho, ocyl, x)
            if m < margin:
                ids, depth = _push(ids, depth, T, n, g, o, m)
                T += 1
    return ids[:T, 0].copy(), ids[:T, 1].copy(), ids[:T, 2].copy(), depth[:T].copy()
