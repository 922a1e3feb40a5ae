"""Certified continuous collision checking of joint-space polylines.

`certify_path(state, path)` proves that the straight joint-space interpolation between
consecutive configurations of `path` (K, dof) never comes within the padding of an obstacle
(or within the self padding of another link), over the whole continuous motion, not only
at sampled configurations. Each pair of geometries (a robot part or attached object against
an obstacle, or against another part) that the sphere-cover broadphase cannot clear with a
margin of its motion bound is proved free on each segment by the first test that succeeds:

1. Conservative advancement. Along q(t) = q_a + t (q_b - q_a) a point x of a part carried
   by joint j moves with velocity sum_k dq_k a_k x (x - p_k) over the joints k supporting
   j, so it travels at most M = sum_k |dq_k| rho_k, where rho_k bounds its distance from
   joint k's axis over the segment (measured at both ends on the part's sphere cover, whose
   balls hold every point of the geometry, widened by how far the joints between k and j
   can move it); for a self pair only the joints not shared by both parts count. With
   lower bounds d_a, d_b of the pair's distance at the ends (coal's distance on the convex
   hull of a mesh, then on the mesh itself), every point of the segment is at least
   max(d_a - t M, d_b - (1 - t) M) away.
2. Chords. Every point of a part stays within E = max|x''| / 8 of the chord between its
   positions at the ends, with |x''| <= sum_k |dq_k| (2 theta_k D_k + sum_{m >= k}
   |dq_m| D_m) (theta_k: the summed |dq| of the joints before k; D_m: the largest distance
   of the part from joint m); E is second order in the segment's length. So with C the
   largest true displacement of the part's points between the ends (of its sphere
   cover's centres in the broadphase, of its hull's vertices on the exact geometry: a
   rigid body's displacement is convex in the point), every point is at least
   max(d_a - t C, d_b - (1 - t) C) - E away, usually far tighter than M; and the part
   stays on one side of the plane n.x = max over its hull vertices at both ends + E,
   where n is the direction between coal's closest points: when the obstacle's exact
   support in the direction n (or the other part's, likewise) lies beyond that plane by
   more than the padding, a motion past the obstacle is certified without subdivision.
3. Otherwise the segment is bisected (M and C halve, E quarters) until every piece is
   certified, a configuration is found within the padding (a collision), or the pair
   cannot be certified within `MAX_DEPTH` halvings or `MAX_QUERIES` distance queries (the
   path is then reported as not certified: callers reject it).

A solid mesh obstacle (`Mesh(solid=True)`) is also checked at the path's first
configuration: a part inside it there stays inside over the whole path, as no part comes
within the padding of its surface (`manip.collision.solids`).

The geometry (the URDF's meshes, the obstacles' shapes) and the padding are those of the
`CollisionChecker`'s state (`manip.collision.state.CollisionState`); nothing is inflated.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import coal
import numpy as np

from manip.collision import broadphase
from manip.collision.bound_products import contract, pair_motion, rows_times
from manip.collision.occupancy import geometry_distance, occupancy_candidates
from manip.collision.robot_geometry import geometry_triangles
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Mesh, Sphere
from manip.collision.solids import part_inside_a_solid
from manip.collision.state import CollisionState
from manip.jit import kernel

#: A pair is not certified after this many halvings of a segment (2^-40 of its length).
MAX_DEPTH = 40
#: A path is reported as not certified after this many exact distance queries.
MAX_QUERIES = 20_000
#: Slack [m] added to the broadphase margins so that round-off never drops a pair.
_EPS = 1e-9
#: Segments whose rows are bounded together before the plane tests and bisections.
_BLOCK = 8
#: Slack [m] taken off coal's distances (GJK converges to within its tolerance from above).
_DISTANCE_SLACK = 1e-6


class MotionCertificate(NamedTuple):
    """Result of `certify_path`.

    Attributes:
        certified: True when the whole continuous interpolation of the path is proved
            collision-free (padding included).
        first_failed_segment: the index s of the first segment path[s] -> path[s+1] that
            could not be certified (None when certified).
        reason: "" when certified, "collision" when a configuration on that segment was
            found in collision, "uncertified" when the proof did not close (a pair grazing
            within the numerical limits, or the query budget ran out).
        pair: names of the two geometries of the failed pair (None when certified).
        queries: number of exact distance queries made.
    """

    certified: bool
    first_failed_segment: int | None = None
    reason: str = ""
    pair: tuple[str, str] | None = None
    queries: int = 0


class MotionBoundTables:
    """The robot-side constants of the motion bound (built once per set of parts).

    Args:
        parts: the checker's parts (`manip.collision.tables.Part`).
        fine: the parts' fine sphere table (`SphereTable`).
        kinematics: the robot's `Kinematics`.
        pairs: (P, 2) the self-collision part pairs in the broadphase's order.
    """

    def __init__(self, parts, fine, kinematics, pairs: np.ndarray):
        specs = kinematics.joint_specs
        J = len(specs)
        G = len(parts)
        parent = np.array([0] + [s.parent for s in specs], dtype=np.int64)  # parent[j] of joint frame j
        # ancestors[j, k]: joint k (1..J) moves joint frame j (k == j included); row 0 = base
        anc = np.zeros((J + 1, J + 1), dtype=np.bool_)
        for j in range(1, J + 1):
            a = j
            while a > 0:
                anc[j, a] = True
                a = int(parent[a])
        self.ancestors = anc
        self.revolute = np.array([True] + [bool(s.revolute) for s in specs], dtype=np.bool_)
        self.axes = np.zeros((J + 1, 3))
        self.axes[1:] = [s.axis for s in specs]
        self.q_of_joint = np.array([-1] + [int(s.q_index) for s in specs], dtype=np.int64)
        lower, upper = kinematics.lower, kinematics.upper
        pj = np.array([p.joint for p in parts], dtype=np.int64)
        self.part_joint = pj
        self.part_chain = anc[pj]  # (G, J+1)
        # fine balls of the moving parts
        moving = fine.joint != 0
        self.centres = np.ascontiguousarray(fine.centres[moving], dtype=np.float64)
        self.radii = np.ascontiguousarray(fine.radii[moving], dtype=np.float64)
        self.ball_part = np.ascontiguousarray(fine.part[moving], dtype=np.int64)
        self.ball_joint = np.ascontiguousarray(fine.joint[moving], dtype=np.int64)
        # configuration-independent bound of a part's distance from joint m's origin: the
        # placements between m and the part's joint, plus the part's extent in its joint frame
        extent = np.zeros(G)
        for g in range(G):
            sel = fine.part == g
            if sel.any():
                extent[g] = float(np.max(np.linalg.norm(fine.centres[sel], axis=1) + fine.radii[sel]))
        # coef[g, m]: bound of the speed of part g's points per unit speed of joint m
        coef = np.zeros((G, J + 1))
        dist = np.zeros((G, J + 1))  # bound of |x - p_m| for the part's points x
        for g in range(G):
            j = int(pj[g])
            reach = extent[g]
            m = j
            while m > 0:
                s = specs[m - 1]
                coef[g, m] = reach if s.revolute else 1.0
                dist[g, m] = reach
                reach += float(np.linalg.norm(s.p_placement))
                if not s.revolute:
                    reach += float(max(abs(lower[s.q_index]), abs(upper[s.q_index])))
                m = int(parent[m])
        # W[g, k, m]: joint m lies strictly between joint k and part g's joint (it changes the
        # part's distance from k's axis at rate coef[g, m])
        W = np.zeros((G, J + 1, J + 1))
        for g in range(G):
            chain = np.flatnonzero(anc[pj[g]])
            for k in chain:
                for m in chain:
                    if m != k and anc[m, k]:
                        W[g, k, m] = coef[g, m]
        self.W = W
        # chord deviation tables: strict[m, k] = m is an ancestor of k (m != k);
        # tail[g, k, m] = D[g, m] where m is k or a descendant of k on part g's chain
        self.strict = (anc.T & ~np.eye(J + 1, dtype=bool)).astype(float)
        tail = np.zeros((G, J + 1, J + 1))
        for g in range(G):
            chain = np.flatnonzero(anc[pj[g]])
            for k in chain:
                for m in chain:
                    if anc[m, k]:
                        tail[g, k, m] = dist[g, m]
        self.tail = tail
        self.dist = dist * self.part_chain
        prismatic_chain = (self.part_chain & ~self.revolute[None]).any(axis=1)
        self.no_chord = prismatic_chain  # parts whose chord deviation bound is not derived (prismatic joints)
        # support points of each part in its geometry frame (the part lies in their convex
        # hull, widened by `support_radius`)
        self.support = []
        self.support_radius = np.zeros(G)
        for g, part in enumerate(parts):
            P, r = _support_points(part)
            self.support.append(np.ascontiguousarray(P))
            self.support_radius[g] = r
        pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
        ca, cb = self.part_chain[pairs[:, 0]], self.part_chain[pairs[:, 1]]
        self.pair_mask_a = (ca & ~cb).astype(float)  # joints moving part a relative to part b
        self.pair_mask_b = (cb & ~ca).astype(float)


def _support_points(part) -> tuple[np.ndarray, float]:
    """(points (V, 3) in the part's geometry frame, radius): the part lies within the convex
    hull of the points widened by the radius."""
    hull = part.hull
    if hasattr(hull, "points") and hasattr(hull, "num_points"):
        return np.asarray(hull.points(), dtype=float).reshape(-1, 3), 0.0
    if isinstance(hull, coal.Sphere):
        return np.zeros((1, 3)), float(hull.radius)
    tri = geometry_triangles(hull)  # boxes exactly, round shapes circumscribed
    if tri is None:  # pragma: no cover - spheres are handled above
        raise AssertionError("no support points")
    return np.asarray(tri[0], dtype=float), 0.0


def _obstacle_support(ob, n: np.ndarray, cache: dict) -> float:
    """min over the obstacle's points y of n . y (its support in direction -n), exact."""
    key = id(ob)
    frame = cache.get(key)
    if frame is None:
        R, c = ob.pose.rotation, ob.pose.position
        V = ob.scaled_vertices @ R.T + c if isinstance(ob, Mesh) else None
        frame = cache[key] = (R, c, V)
    R, c, V = frame
    if V is not None:
        return float(np.min(V @ n))
    nl = R.T @ n
    base = float(n @ c)
    if isinstance(ob, Cuboid):
        return base - float(np.abs(nl) @ (np.asarray(ob.dims) / 2.0))
    if isinstance(ob, Sphere):
        return base - ob.radius
    if isinstance(ob, Capsule):
        return base - abs(nl[2]) * ob.height / 2.0 - ob.radius
    if isinstance(ob, Cylinder):
        return base - abs(nl[2]) * ob.height / 2.0 - ob.radius * math.sqrt(max(0.0, 1.0 - nl[2] ** 2))
    return -math.inf  # pragma: no cover - unknown shape: no bound


@kernel
def _axis_reach(R, p, centres, radii, ball_part, ball_joint, ancestors, axes, revolute, n_parts):
    """rho (N, G, J+1): for each configuration, part and supporting joint k, the largest
    distance of the part's balls (centre distance from k's axis plus radius); 1 for a
    prismatic k (a unit of joint motion moves every point by 1). And chord (N-1, G): the
    largest displacement of a ball centre of each part between consecutive configurations."""
    N = R.shape[0]
    J1 = ancestors.shape[0]
    out = np.zeros((N, n_parts, J1))
    chord = np.zeros((max(N - 1, 0), n_parts))
    prev = np.empty((centres.shape[0], 3))
    x = np.empty(3)
    a = np.empty((J1, 3))
    for n in range(N):
        for k in range(1, J1):  # world axes of the joints
            for r in range(3):
                a[k, r] = R[n, k, r, 0] * axes[k, 0] + R[n, k, r, 1] * axes[k, 1] + R[n, k, r, 2] * axes[k, 2]
        for s in range(centres.shape[0]):
            j = ball_joint[s]
            g = ball_part[s]
            for r in range(3):
                x[r] = R[n, j, r, 0] * centres[s, 0] + R[n, j, r, 1] * centres[s, 1] + R[n, j, r, 2] * centres[s, 2] \
                    + p[n, j, r]
            if n > 0:
                c = math.sqrt((x[0] - prev[s, 0]) ** 2 + (x[1] - prev[s, 1]) ** 2 + (x[2] - prev[s, 2]) ** 2)
                if c > chord[n - 1, g]:
                    chord[n - 1, g] = c
            prev[s, 0] = x[0]
            prev[s, 1] = x[1]
            prev[s, 2] = x[2]
            for k in range(1, J1):
                if not ancestors[j, k]:
                    continue
                if revolute[k]:
                    d0 = x[0] - p[n, k, 0]
                    d1 = x[1] - p[n, k, 1]
                    d2 = x[2] - p[n, k, 2]
                    dp = d0 * a[k, 0] + d1 * a[k, 1] + d2 * a[k, 2]
                    v = math.sqrt(max(d0 * d0 + d1 * d1 + d2 * d2 - dp * dp, 0.0)) + radii[s]
                else:
                    v = 1.0
                if v > out[n, g, k]:
                    out[n, g, k] = v
    return out, chord


def _lower(da: float, db: float, M: float) -> float:
    """Lower bound of the distance over a segment with end distances da, db and motion bound M."""
    if M <= 0.0:
        return max(da, db)
    t = min(1.0, max(0.0, (da - db + M) / (2.0 * M)))
    return max(da - t * M, db - (1.0 - t) * M)


def _lower_batch(da: np.ndarray, db: np.ndarray, M: np.ndarray) -> np.ndarray:
    Ms = np.maximum(M, 1e-300)
    t = np.clip((da - db + M) / (2.0 * Ms), 0.0, 1.0)
    return np.maximum(da - t * M, db - (1.0 - t) * M)


class _End:
    """One configuration of a segment for one pair: placements, distances, support values."""

    __slots__ = ("ctx", "pair", "tf", "Rw", "pw", "d_hull", "normal", "d_mesh", "_world_pts")

    def __init__(self, ctx: _Context, pair: tuple[int, int, int], Rw: list, pw: list, tf: list):
        self.ctx, self.pair, self.Rw, self.pw, self.tf = ctx, pair, Rw, pw, tf
        self.d_hull = self.normal = self.d_mesh = None
        self._world_pts = [None, None]

    def hull(self) -> float:
        """Distance on the convex hulls (a lower bound), with the direction between the closest points."""
        if self.d_hull is None:
            d, n = self.ctx.distance(self.pair, self.tf, False)
            self.d_hull, self.normal = d, n
        return self.d_hull

    def best(self, mesh: bool) -> float:
        """The best lower bound of the distance (the exact mesh distance with `mesh`)."""
        d = self.hull()
        if mesh:
            if self.d_mesh is None:
                self.d_mesh = self.ctx.distance(self.pair, self.tf, True)[0]
            d = max(d, self.d_mesh)
        return d

    def points(self, side: int) -> np.ndarray:
        """The support points (V, 3) of the pair's part `side` (0 or 1) in the world."""
        pts = self._world_pts[side]
        if pts is None:
            P = self.ctx.tb.support[self.pair[1 + side]]
            pts = self._world_pts[side] = P @ self.Rw[side].T + self.pw[side]
        return pts

    def support(self, side: int, n: np.ndarray) -> tuple[float, float]:
        """(max, min) of n . x over the support points of the pair's part `side` (0 or 1)."""
        v = self.points(side) @ n
        return float(v.max()), float(v.min())

    def chord(self, other: _End, side: int) -> float:
        """The largest displacement of a point of part `side` from this end to `other`: at
        a support point (the displacement of a rigid body's points is convex in the point),
        plus the support radius times the rotation's change."""
        d = other.points(side) - self.points(side)
        c = math.sqrt(float(np.max(np.einsum("ij,ij->i", d, d))))
        r = self.ctx.tb.support_radius[self.pair[1 + side]]
        if r:
            c += r * float(np.linalg.norm(other.Rw[side] - self.Rw[side]))
        return c


class _Context:
    """The exact queries of one `certify_path` call: placements, distances, counters."""

    def __init__(self, state: CollisionState, R: np.ndarray, p: np.ndarray):
        self.state = state
        self.tb = state.motion_bounds
        self.parts = state.parts
        self._pj = np.array([pt.joint for pt in self.parts], dtype=np.int64)
        self._gR = np.array([pt.R for pt in self.parts])
        self._gp = np.array([pt.p for pt in self.parts])
        Rj = R[:, self._pj]
        self.Rw = np.matmul(Rj, self._gR)
        self.pw = np.matmul(Rj, self._gp[:, :, None])[..., 0] + p[:, self._pj]
        self.ends: dict = {}
        self.tfs: dict = {}
        self.obstacle_frames: dict = {}
        self.queries = 0
        self.req = coal.DistanceRequest()
        self.req.gjk_variant = coal.GJKVariant.NesterovAcceleration
        self.res = coal.DistanceResult()

    def distance(self, pair, tf, mesh: bool) -> tuple[float, np.ndarray | None]:
        """(a lower bound of the pair's distance [m], the unit direction from the part to the
        other geometry between the closest points, or None)."""
        kind, i, j = pair
        self.queries += 1
        pa = self.parts[i]
        res = self.res
        res.clear()
        if kind == 0:
            d, n = geometry_distance(pa.geometry if mesh else pa.hull, tf[0], self.state.obstacle_geometries[j],
                                     self.state.obstacle_transforms[j], self.req, res)
        else:
            pb = self.parts[j]
            d = coal.distance(pa.geometry if mesh else pa.hull, tf[0], pb.geometry if mesh else pb.hull, tf[1],
                              self.req, res)
            n = res.normal.copy() if d > 0.0 else None
        n = None if mesh else n
        # GJK stops within its tolerance of the true distance: keep a slack below it
        return float(d) - _DISTANCE_SLACK, n

    def _tf(self, n: int, g: int):
        tf = self.tfs.get((n, g))
        if tf is None:
            tf = self.tfs[(n, g)] = coal.Transform3s(self.Rw[n, g], self.pw[n, g])
        return tf

    def at_sample(self, pair, n: int) -> _End:
        key = (pair, n)
        end = self.ends.get(key)
        if end is None:
            kind, i, j = pair
            jj = j if kind else i  # a world pair's second geometry is an obstacle (static)
            end = self.ends[key] = _End(self, pair, [self.Rw[n, i], self.Rw[n, jj]], [self.pw[n, i], self.pw[n, jj]],
                                        [self._tf(n, i), self._tf(n, j) if kind else None])
        return end

    def at_config(self, pair, q: np.ndarray) -> _End:
        R, p = self.state.joint_transforms(q[None])
        Rw, pw = [], []
        for g in (pair[1], pair[2] if pair[0] else pair[1]):
            Rj = R[0, self._pj[g]]
            Rw.append(Rj @ self._gR[g])
            pw.append(p[0, self._pj[g]] + Rj @ self._gp[g])
        tf = [coal.Transform3s(Rw[0], pw[0]), coal.Transform3s(Rw[1], pw[1]) if pair[0] else None]
        return _End(self, pair, Rw, pw, tf)

    def convex(self, pair) -> bool:
        """True when the hull distance of the pair is its exact distance."""
        kind, i, j = pair
        if self.parts[i].hull is not self.parts[i].geometry:
            return False
        return kind == 0 or self.parts[j].hull is self.parts[j].geometry

    def plane(self, pair, a: _End, b: _End, n: np.ndarray | None, E: tuple[float, float], margin: float) -> bool:
        """True when a plane of normal n separates the pair over the whole segment a -> b."""
        if n is None:
            return False
        kind, i, j = pair
        tb = self.tb
        hi = max(a.support(0, n)[0], b.support(0, n)[0]) + E[0] + tb.support_radius[i]
        if kind == 0:
            lo = _obstacle_support(self.state.obstacles[j], n, self.obstacle_frames)
        else:
            lo = min(a.support(1, n)[1], b.support(1, n)[1]) - E[1] - tb.support_radius[j]
        return lo - hi > margin


def _candidates(kernel, R, p, margins: np.ndarray, tables, Q: np.ndarray | None = None) -> tuple:
    """A broadphase kernel with a margin per configuration: configurations are grouped by
    their margin rounded up to a power of four (a few calls), results merged in order.
    `Q` (N, dof): the configurations, for the kernels that take them after R, p."""
    level = np.ceil(np.log(np.maximum(margins, 1e-4)) / np.log(4.0)).astype(np.int64)
    outs = []
    for lv in np.unique(level):
        idx = np.flatnonzero(level == lv)
        head = (R[idx], p[idx]) if Q is None else (R[idx], p[idx], Q[idx])
        res = kernel(*head, float(4.0 ** lv) + _EPS, *tables)
        outs.append((idx[res[0]],) + tuple(res[1:]))
    return tuple(np.concatenate([o[k] for o in outs]) for k in range(len(outs[0])))


def certify_path(state: CollisionState, path: np.ndarray) -> MotionCertificate:
    """Prove the straight interpolation of `path` (K, dof) collision-free (see the module doc).

    Args:
        state: the checker's tables (`CollisionChecker.state`: one world, whatever edits follow).
        path: (K, dof) configurations [rad], K >= 1.

    Returns:
        MotionCertificate.
    """
    Q = np.array(path, dtype=np.float64)  # a writable copy (the kernels' signature)
    if Q.shape[0] == 1:
        Q = np.vstack([Q, Q])
    st = state
    if st.every_configuration_collides:
        g, o = st.always_colliding[0]
        return MotionCertificate(False, 0, "collision", (st.parts[g].name, st.obstacles[o].name))
    tb: MotionBoundTables = st.motion_bounds
    R, p = st.joint_transforms(Q)
    # the certificate keeps every part off every surface, so the start decides for each solid
    inside = part_inside_a_solid(st.parts, st.obstacles, st.obstacle_geometries, R[0], p[0])
    if inside is not None:
        return MotionCertificate(False, 0, "collision", inside)
    rho, chord = _axis_reach(R, p, tb.centres, tb.radii, tb.ball_part, tb.ball_joint, tb.ancestors, tb.axes,
                             tb.revolute, len(st.parts))
    S = Q.shape[0] - 1
    Dj = np.zeros((S, tb.axes.shape[0]))
    Dj[:, 1:] = np.abs(np.diff(Q, axis=0))[:, tb.q_of_joint[1:]]
    rho_seg = 0.5 * (rho[:-1] + rho[1:] + contract(Dj, tb.W))  # (S, G, J+1)
    rho_seg *= tb.part_chain[None]
    M_part = rows_times(rho_seg, Dj)  # (S, G) motion bound of each part
    # chord deviation bounds E (S, G) of every part on every segment
    theta = contract(Dj, np.ascontiguousarray(tb.strict.T)[None])[:, 0]  # (S, J+1): summed |dq| of the joints before k
    inner = 2.0 * theta[:, None, :] * tb.dist[None] + contract(Dj, tb.tail)
    E_part = rows_times(inner, Dj) / 8.0
    E_part[:, tb.no_chord] = np.inf
    # how far a ball of each part can get from its place at either end of a segment
    B_part = np.minimum(M_part, chord + E_part)
    pad, spad = st.padding, st.self_padding
    segments: list[np.ndarray] = []  # per pair kind: (segment, i, j) rows left uncertified
    motion: list[np.ndarray] = []

    def both_ends(n, a, b, d, n_codes):
        """Entries flagged at sample s and s+1: (segment, a, b, d_s, d_s+1)."""
        key = (n * n_codes[0] + a) * n_codes[1] + b
        order = np.argsort(key, kind="stable")
        key, n, a, b, d = key[order], n[order], a[order], b[order], d[order]
        nxt = key + n_codes[0] * n_codes[1]
        idx = np.minimum(np.searchsorted(key, nxt), max(key.size - 1, 0))
        hit = (key[idx] == nxt) & (n < S)
        return n[hit], a[hit], b[hit], d[hit], d[idx[hit]]

    def sample_margins(M: np.ndarray, base: float) -> np.ndarray:
        """The margin each configuration needs: its adjacent segments' largest bound."""
        m = M.max(axis=1, initial=0.0)
        return base + np.maximum(np.r_[m, 0.0], np.r_[0.0, m])

    # world pairs
    O = len(st.obstacles)
    if O and st.moving_world_parts:
        margins = sample_margins(B_part, pad)
        n, g, o, d = _candidates(broadphase.world_candidates, R, p, margins, (*st.world_tables, *st.obstacle_tables))
        if st.occupancy_maps:   # occupancy maps: their own bounds (`manip.collision.occupancy`)
            extra = occupancy_candidates(R, p, margins + _EPS, st.world_tables, st.occupancy_maps)
            n, g, o, d = (np.concatenate(c) for c in zip((n, g, o, d), extra))
        if n.size and st.allowed_world is not None:  # contacts allowed (`CollisionChecker.allowing`)
            n, g, o, d = (a[~st.allowed_world[g, o]] for a in (n, g, o, d))
        if n.size:
            s, g, o, da, db = both_ends(n, g, o, d, (len(st.parts), O))
            lower = np.maximum(_lower_batch(da, db, M_part[s, g]), _lower_batch(da, db, chord[s, g]) - E_part[s, g])
            bad = lower <= pad
            segments.append(np.stack([s[bad], np.zeros(int(bad.sum()), dtype=np.int64), g[bad], o[bad]], axis=1))
            motion.append(M_part[:, g[bad]])
    # self pairs
    bp_pairs = st.self_pairs
    if bp_pairs.shape[0]:
        M_pair = pair_motion(rho_seg, np.ascontiguousarray(bp_pairs[:, 0]), np.ascontiguousarray(bp_pairs[:, 1]),
                              tb.pair_mask_a, tb.pair_mask_b, Dj)
        n, k, d = _candidates(broadphase.self_candidates, R, p, sample_margins(M_pair, spad), st.self_tables, Q)
        if n.size:
            s, k, _, da, db = both_ends(n, k, np.zeros(n.size, dtype=np.int64), d, (bp_pairs.shape[0], 1))
            bad = _lower_batch(da, db, M_pair[s, k]) <= spad
            kb = k[bad]
            segments.append(np.stack([s[bad], np.ones(kb.size, dtype=np.int64), bp_pairs[kb, 0], bp_pairs[kb, 1]], axis=1))
            motion.append(M_pair[:, kb])
    rows = np.concatenate(segments) if segments else np.zeros((0, 4), dtype=np.int64)
    if rows.shape[0] == 0:
        return MotionCertificate(True)
    Ms = np.concatenate(motion, axis=1)  # (S, rows): the motion bound of each row's pair
    ctx = _Context(st, R, p)
    # rows in segment order, a block of segments at a time: exact (hull) distances at both
    # ends of every row and the two-sided advancement bound for the block at once, then the
    # plane test and bisection for the rows it leaves; the first failure ends the proof (it
    # is the first failed segment, as every earlier row was certified)
    order = np.argsort(rows[:, 0], kind="stable")
    rows, Ms = rows[order], Ms[:, order]
    M = Ms[rows[:, 0], np.arange(rows.shape[0])]
    margins = np.where(rows[:, 1] == 0, pad, spad)
    bounds = np.searchsorted(rows[:, 0], np.arange(0, S + _BLOCK, _BLOCK))
    for b0, b1 in zip(bounds[:-1], bounds[1:]):
        if b0 == b1:
            continue
        block = rows[b0:b1].tolist()
        da = np.empty(b1 - b0)
        db = np.empty(b1 - b0)
        for r, (s_, k_, i_, j_) in enumerate(block):
            da[r] = ctx.at_sample((k_, i_, j_), s_).hull()
            db[r] = ctx.at_sample((k_, i_, j_), s_ + 1).hull()
        for r in np.flatnonzero(_lower_batch(da, db, M[b0:b1]) <= margins[b0:b1]):
            seg, kind, i, j = block[r]
            E = (float(E_part[seg, i]), float(E_part[seg, j]) if kind else 0.0)
            why = _certify_segment(ctx, Q, (kind, i, j), seg, float(M[b0 + r]), E, float(margins[b0 + r]))
            if why:
                names = (st.parts[i].name, st.obstacles[j].name if kind == 0 else st.parts[j].name)
                return MotionCertificate(False, seg, why, names, ctx.queries)
    return MotionCertificate(True, queries=ctx.queries)


def _certify_segment(ctx: _Context, Q: np.ndarray, pair, seg: int, M: float, E: tuple[float, float],
                     margin: float) -> str:
    """"" when the pair is certified on segment seg, else "collision" / "uncertified"."""
    convex = ctx.convex(pair)
    stack = [(Q[seg], Q[seg + 1], ctx.at_sample(pair, seg), ctx.at_sample(pair, seg + 1), M, E, 0)]
    while stack:
        qa, qb, a, b, M, E, depth = stack.pop()
        if _lower(a.hull(), b.hull(), M) > margin:
            continue
        # every point stays within E of its chord: the true displacements, not the bound M
        C = a.chord(b, 0) + (a.chord(b, 1) if pair[0] else 0.0)
        if _lower(a.hull(), b.hull(), C) - E[0] - E[1] > margin:
            continue
        if ctx.plane(pair, a, b, a.normal, E, margin) or ctx.plane(pair, a, b, b.normal, E, margin):
            continue
        if not convex and min(a.hull(), b.hull()) <= margin:
            # the hull of a mesh touches: the mesh itself decides (it is a surface, its hull a solid)
            if max(_lower(a.best(True), b.best(True), M), _lower(a.best(True), b.best(True), C) - E[0] - E[1]) > margin:
                continue
        for end, q in ((a, qa), (b, qb)):
            if end.hull() <= margin and end.best(not convex) <= margin:
                # within the padding up to the distance's slack: the checker's own answer
                # names it a collision; either way the segment is not certified
                return "collision" if ctx.state.collides(q[None])[0] else "uncertified"
        if depth >= MAX_DEPTH or ctx.queries >= MAX_QUERIES:
            return "uncertified"
        qm = 0.5 * (qa + qb)
        m = ctx.at_config(pair, qm)
        h, e = 0.5 * M, (0.25 * E[0], 0.25 * E[1])
        stack.append((qm, qb, m, b, h, e, depth + 1))
        stack.append((qa, qm, a, m, h, e, depth + 1))
    return ""
