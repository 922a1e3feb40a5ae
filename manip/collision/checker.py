"""`CollisionChecker`: exact robot-vs-world and self-collision checks, fast in batches.

Answers are those of coal on the robot's URDF collision geometry (meshes as triangle
surfaces, primitives as solids), the same as Pinocchio's `computeCollisions` over the same
pairs with the same security margin (the padding). Speed comes from a compiled (numba)
broadphase, `manip.collision.broadphase`, that can only say "free", never "colliding":

1. batched forward kinematics of the configurations (`Kinematics.joint_transforms`);
2. world: one bounding ball per moving joint (all its parts) against every obstacle
   (closed-form signed distances to boxes, spheres, capsules, cylinders; meshes through
   their bounding box), then the coarse sphere cover of each of that joint's parts, then
   the fine cover of each part still flagged (the first level over the whole batch at once,
   `manip.collision.broadphase_soa`); parts fixed to the base are checked once per world;
3. self: one bounding ball per body (a link's parts, or an attached object) for the enabled
   pairs, then the pair's clearance map if it has one (`manip.collision.pair_maps`: a
   proved distance bound per cell of the few joints moving the pair), then the coarse
   covers of each enabled part pair, then their fine covers;
4. coal's exact narrowphase for the (configuration, pair) candidates left (a mesh of more
   than `HULL_SCREEN_TRIANGLES` triangles is first tested through its convex hull, which
   holds it: a hull kept clear answers "free" at the cost of one GJK), stopping at the
   first collision of each configuration, or of each group of configurations when only
   "any collision in this segment?" is asked (most penetrating candidates first), or at the
   first colliding configuration in order (`first_collision`).

The covers (`manip.collision.spheres`) are generated automatically from the meshes and hold
every point of the surfaces (of the volume for solid primitives): if no ball comes within
the padding of an obstacle, no point of the geometry does, so coal would say "free" too.

Beside this module: the result types (`manip.collision.results`, re-exported here), the
tables the checks run on (`manip.collision.tables`, rebuilt when the parts or the world
change) and the checks of segments and paths (`manip.collision.segments`), and the
certificate of continuous motions (`manip.collision.certify`).

Threads: edits (set_world, add/remove/update obstacles, attach/detach, padding, gripper)
are serialised by a lock and never modify tables in place: they build new ones and swap
them in. `snapshot()` returns a read-only view of one state of the world (O(1)); every
public check of the checker runs on such a view, so a check never sees half an edit, and
a planner holding a snapshot sees one world for a whole plan while edits go on.
"""

from __future__ import annotations

import math
import threading

import coal
import numpy as np

from manip.collision import broadphase, broadphase_soa, hull_screen
from manip.collision.certify import MotionCertificate, certify_path
from manip.collision.edits import WorldEdits
from manip.collision.inside import inside_table, wholly_inside
from manip.collision.occupancy import geometry_collide, geometry_distance, occupancy_candidates
from manip.collision.results import (  # noqa: F401  (re-exported: manip.collision.checker.X keeps working)
    AttachedObject,
    CollisionReport,
    Contact,
    ContactKind,
    DistanceReport,
    PathCheck,
)
from manip.collision.robot_geometry import RobotGeometry
from manip.collision.segments import SegmentChecks, consistent
from manip.collision.shapes import Obstacle  # noqa: F401  (re-exported)
from manip.collision.solids import part_inside
from manip.collision.state import CollisionState
from manip.collision.tables import coal_transform
from manip.collision.world import WorldConfig
from manip.errors import InvalidInputError
from manip.jit import kernel_array
from manip.kinematics import Kinematics
from manip.robot_config import RobotConfig
from manip.validation import non_negative

_CHUNK = 1024  # configurations per broadphase batch


class CollisionChecker(WorldEdits, SegmentChecks):
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
        self._lock = threading.RLock()
        self._is_snapshot = False
        self.config = config
        self.kinematics = kinematics if kinematics is not None else Kinematics(config)
        self.robot = RobotGeometry(config, self.kinematics, sphere_tolerance=sphere_tolerance)
        self._padding = non_negative(config.collision_padding if padding is None else padding, "padding", "m")
        self._self_padding = non_negative(self_padding, "self_padding", "m")
        self._world = WorldConfig()
        self._attached: dict[str, AttachedObject] = {}
        self._obstacle_cache: dict[int, tuple] = {}
        self._rebuild_parts()
        self.set_world(world if world is not None else WorldConfig())

    # ------------------------------------------------------------------ state
    @property
    def state(self) -> CollisionState:
        """The checker's tables as they are now, read-only (`manip.collision.state`): what the
        certificate, the clearance model and the planners read. Later edits do not change it."""
        if not self._is_snapshot:
            return self.snapshot().state
        state = self.__dict__.get("_state_of_snapshot")
        if state is None:
            state = self._state_of_snapshot = CollisionState(
                kinematics=self.kinematics, parts=tuple(self._parts), obstacles=tuple(self._obs),
                obstacle_geometries=tuple(self._ogeom), obstacle_transforms=tuple(self._otf), padding=self._padding,
                self_padding=self._self_padding, always_colliding=tuple(self._always_colliding), fine=self._fine,
                motion_bounds=self._motion_bounds, world_tables=tuple(self._bp_world),
                moving_world_parts=bool(self._l0_joint.size), obstacle_tables=tuple(self._bp_obstacles),
                self_tables=tuple(self._bp_self), self_pairs=self._bp_pairs,
                allowed_world=self.__dict__.get("_allowed_world"), _collides=self._check,
                _collides_given=self._collides_given,
                _motion_free=self._motion_free_at, _segments_free=self._segments_free, _advance=self._advance_to,
                occupancy_maps=tuple(self._occupancy))
        return state

    # ------------------------------------------------------------------ geometry helpers
    def _sd_all(self, X: np.ndarray) -> np.ndarray:
        """Signed distances (M, O) of points X (M, 3) to every obstacle's broadphase shape."""
        return self._world_tables.signed_distances(X)

    def _fk(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint frames (N, J+1, 3, 3), (N, J+1, 3) (the compiled batched kinematics)."""
        return self.kinematics.joint_transforms(Q)

    def _part_tf(self, R: np.ndarray, p: np.ndarray, n: int, g: int) -> coal.Transform3s:
        part = self._parts[g]
        Rj, pj = R[n, part.joint], p[n, part.joint]
        return coal_transform(Rj @ part.R, pj + Rj @ part.p)

    # ------------------------------------------------------------------ broadphase
    def _candidates(self, Q: np.ndarray, R: np.ndarray, p: np.ndarray, world: bool = True, self_: bool = True,
                    deepest_first: bool = False):
        """Pairs the balls cannot clear (the compiled `broadphase` kernels).

        Returns:
            (n (T,), kind (T,) 0=world/1=self, i (T,), j (T,)): for world i = part and
            j = obstacle; for self (i, j) = parts. Sorted by configuration then depth, or
            by depth alone with `deepest_first`.
        """
        found = []
        if world and len(self._obs) and self._l0_joint.size:
            # the per-configuration kernel's answers, its first level over the batch at once
            n, g, o, d = broadphase_soa.world_candidates(R, p, self._padding + 1e-9, *self._bp_world,
                                                         *self._bp_obstacles, broadphase_soa.LANES)
            allowed = self.__dict__.get("_allowed_world")  # a view of `allowing`
            if allowed is not None and n.size:
                keep = ~allowed[g, o]
                n, g, o, d = n[keep], g[keep], o[keep], d[keep]
            if n.size:
                found.append((n, np.zeros(n.size, dtype=np.int64), g, o, d))
            if self._occupancy:   # occupancy maps: their own bounds (`manip.collision.occupancy`)
                n, g, o, d = occupancy_candidates(R, p, np.full(R.shape[0], self._padding + 1e-9), self._bp_world,
                                                  self._occupancy, exact_depth=False)
                if allowed is not None and n.size:
                    keep = ~allowed[g, o]
                    n, g, o, d = n[keep], g[keep], o[keep], d[keep]
                if n.size:
                    found.append((n, np.zeros(n.size, dtype=np.int64), g, o, d))
        if self_ and self._bpairs.shape[0]:
            Q = kernel_array(Q)  # one compiled signature of the kernel: C order, writable (a trajectory's is neither)
            n, k, d = broadphase.self_candidates(R, p, Q, self._self_padding + 1e-9, *self._bp_self)
            if n.size:
                pairs = self._bp_pairs
                found.append((n, np.ones(n.size, dtype=np.int64), pairs[k, 0], pairs[k, 1], d))
        if not found:
            e = np.zeros(0, dtype=np.int64)
            return e, e, e, e
        n, kind, i, j, d = found[0] if len(found) == 1 else (np.concatenate(c) for c in zip(*found))
        if n.size == 1:
            return n, kind, i, j
        order = np.argsort(d, kind="stable") if deepest_first else np.lexsort((d, n))
        return n[order], kind[order], i[order], j[order]

    def _exact(self, R, p, n: int, kind: int, i: int, j: int, tfs: dict) -> bool:
        key = (n, i)
        tfa = tfs.get(key)
        if tfa is None:
            tfa = tfs[key] = self._part_tf(R, p, n, i)
        res = coal.CollisionResult()
        if kind == 0:
            hit = geometry_collide(self._parts[i].geometry, tfa, self._ogeom[j], self._otf[j], self._req_world, res,
                                   lambda: self._balls_at(i, tfa.getRotation(), tfa.getTranslation()))
            return hit or self._inside_solid(i, j, tfa.getRotation(), tfa.getTranslation())
        key = (n, j)
        tfb = tfs.get(key)
        if tfb is None:
            tfb = tfs[key] = self._part_tf(R, p, n, j)
        return bool(coal.collide(self._parts[i].geometry, tfa, self._parts[j].geometry, tfb, self._req_self, res))

    def _check(self, Q: np.ndarray, stop_at_first: bool = False, group: np.ndarray | None = None,
               deepest_first: bool = True, inside: bool = False) -> np.ndarray:
        """(N,) bool: which configurations of Q (N, dof) collide.

        Args:
            stop_at_first: stop at the first collision found (only `out.any()` is meaningful).
            group: (N,) ints: stop looking in a group once one of its configurations collides
                (only `out[group == g].any()` is meaningful for each group g).
            deepest_first: with `stop_at_first` or `group`, try the most penetrating ball
                pairs first (the likeliest collisions); else go in configuration order, so
                that with `stop_at_first` the first True is the first colliding row.
            inside: also find a part or obstacle wholly inside a part's closed mesh (`_parts_inside`), for
                configurations checked on their own. Motions need not: a motion that enters a
                part from outside crosses its surface, which the checks along it see.
        """
        if self._always_colliding:
            return np.ones(Q.shape[0], dtype=bool)
        out = np.zeros(Q.shape[0], dtype=bool)
        if stop_at_first:  # one group: no bookkeeping, stop at the first collision found
            for s in range(0, Q.shape[0], _CHUNK):
                if self._check_chunk(Q[s:s + _CHUNK], None, deepest_first, None, out[s:s + _CHUNK], inside):
                    break
            return out
        ordered = not (deepest_first and group is not None)
        if group is None:  # every configuration on its own
            group = np.arange(Q.shape[0])
        done: set[int] = set()
        for s in range(0, Q.shape[0], _CHUNK):  # bounded memory for large batches
            self._check_chunk(Q[s:s + _CHUNK], group[s:s + _CHUNK], not ordered, done, out[s:s + _CHUNK], inside)
        return out

    def _check_chunk(self, Q: np.ndarray, group: np.ndarray | None, deepest_first: bool, done: set[int] | None,
                     out: np.ndarray, inside: bool = False) -> bool:
        """`_check` of at most _CHUNK configurations: sets `out` where they collide, skipping
        the groups (N,) in `done` and adding those found colliding; with `group` None, one
        group: returns at the first collision found. Returns True when one was found."""
        R, p = self._fk(Q)
        n, kind, i, j = self._candidates(Q, R, p, deepest_first=deepest_first)
        found = bool(n.size) and self._narrowphase(R, p, n, kind, i, j, group, done, out)
        if inside and not (found and group is None):
            found = self._parts_inside(R, p, group, done, out) or found
        return found

    def _parts_inside(self, R: np.ndarray, p: np.ndarray, group: np.ndarray | None, done: set[int] | None,
                      out: np.ndarray, hits: list | None = None) -> bool:
        """`_check_chunk`'s configurations not found colliding where a part or an obstacle lies wholly
        inside a part's closed mesh (coal sees surfaces; no sphere-cover candidate need reach a
        finger inside panda_link5): sets `out` (and `done`) there; True when one was found. `hits`:
        every such pair (kind, part, part or obstacle) is appended to it."""
        rows = np.flatnonzero(~out)
        if group is not None and done:
            rows = rows[[group[r] not in done for r in rows.tolist()]]
        if not rows.size:
            return False
        tab = self.__dict__.get("_inside")
        if tab is None or tab.parts is not self._parts:   # built once per parts list (`collision.inside`)
            tab = self._inside = inside_table(self._parts, self._pairs, self._pj, self._gR, self._gp)
        if rows.size < out.size:
            R, p = R[rows], p[rows]
        rows = rows[wholly_inside(tab, self._world_tables, R, p, self.__dict__.get("_allowed_world"), hits)]
        out[rows] = True
        if group is not None:
            done.update(group[rows].tolist())
        return bool(rows.size)

    def _collides_given(self, R: np.ndarray, p: np.ndarray, kind: np.ndarray, i: np.ndarray, j: np.ndarray) -> bool:
        """True when the one configuration whose joint frames are R (1, J+1, 3, 3), p (1, J+1, 3)
        collides, given its broadphase candidates (T,) kind (0 = world, 1 = self), i (part), j
        (obstacle or part) in the order to try them, computed by a caller's kernel on this
        checker's tables (`broadphase.world_candidates`, `self_candidates`; no occupancy maps)."""
        allowed = self.__dict__.get("_allowed_world")
        if allowed is not None and (kind == 0).any():   # contacts `allowing` allows are not checked
            keep = kind == 1
            keep[~keep] = ~allowed[i[~keep], j[~keep]]
            kind, i, j = kind[keep], i[keep], j[keep]
        if i.size == 0:
            return False
        return self._narrowphase(R, p, np.zeros(i.size, dtype=np.int64), kind, i, j, None, None, np.zeros(1, dtype=bool))

    def _narrowphase(self, R: np.ndarray, p: np.ndarray, n: np.ndarray, kind: np.ndarray, i: np.ndarray,
                     j: np.ndarray, group: np.ndarray | None, done: set[int] | None, out: np.ndarray) -> bool:
        """Coal on the candidates (n, kind, i, j) (T,) of `_candidates`, in their order (see
        `_check_chunk` and `_check`, whose arguments the others are)."""
        # world placements of both geometries of every candidate pair, in one go
        RA, pA = broadphase.part_placements(R, p, n, i, self._pj, self._gR, self._gp)
        selfp = kind == 1
        if selfp.any():
            RB, pB = broadphase.part_placements(R, p, n, np.where(selfp, j, 0), self._pj, self._gR, self._gp)
        else:
            RB, pB = RA, pA   # not read
        if hull_screen.ENABLED:   # the pairs GJK keeps clearly apart: free for coal too (`hull_screen`)
            keep = ~hull_screen.apart(kind, i, j, RA, pA, RB, pB, *self._hull_parts, self._hull_okind,
                                      *self._bp_obstacles[:4], self._padding + hull_screen.SLACK,
                                      self._self_padding + hull_screen.SLACK)
            if not keep.any():
                return False
            n, kind, i, j, RA, pA, RB, pB = (x[keep] for x in (n, kind, i, j, RA, pA, RB, pB))
        geoms = self._geoms
        hulls, convex = self._screen_hulls, self._hulls
        ogeom, otf = self._ogeom, self._otf
        req_w, req_s = self._req_world, self._req_self
        res = coal.CollisionResult()
        Tf = coal.Transform3s
        collide = coal.collide
        wcollide = geometry_collide
        maps = {o for o, _ in self._occupancy}
        n_l = n.tolist()
        keys = None if group is None else group[n].tolist()
        kind_l, i_l, j_l = kind.tolist(), i.tolist(), j.tolist()
        found = False
        for t in range(len(n_l)):
            if keys is not None and keys[t] in done:
                continue
            a, b = i_l[t], j_l[t]
            res.clear()
            ta = Tf(RA[t], pA[t])
            if kind_l[t] == 0:
                # a large mesh's convex hull (which holds it) first: free there, free for certain
                # (of a solid mesh's surface: then inside or outside it, `_inside_solid` says)
                balls = (lambda: self._balls_at(a, RA[t], pA[t])) if b in maps else None  # noqa: B023
                if hulls[a] is not None and not wcollide(hulls[a], ta, ogeom[b], otf[b], req_w, res, balls):
                    hit = False
                else:
                    res.clear()
                    hit = wcollide(geoms[a], ta, ogeom[b], otf[b], req_w, res, balls)
                hit = hit or self._inside_solid(a, b, RA[t], pA[t])
            else:
                tb = Tf(RB[t], pB[t])
                # both hulls (convex against convex: GJK) when either mesh is large
                if ((hulls[a] is not None or hulls[b] is not None) and convex[a] is not None and convex[b] is not None
                        and not collide(convex[a], ta, convex[b], tb, req_s, res)):
                    continue
                res.clear()
                hit = collide(geoms[a], ta, geoms[b], tb, req_s, res)
            if hit:
                out[n_l[t]] = True
                if keys is None:
                    return True
                done.add(keys[t])
                found = True
        return found

    def _balls_at(self, g: int, R: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The fine balls of part g (which hold its geometry) with the part placed at (R, p)
        (base frame): centres (K, 3) [m], radii (K,) [m]."""
        cache = self.__dict__.get("_part_balls")
        if cache is None or cache[0] is not self._fine:
            cache = self._part_balls = (self._fine, {})
        local = cache[1].get(g)
        if local is None:
            part, fine = self._parts[g], self._fine
            C = (fine.centres_of(g) - part.p) @ part.R   # joint frame -> the part's geometry frame
            local = cache[1][g] = (np.ascontiguousarray(C), np.ascontiguousarray(fine.radii_of(g), dtype=np.float64))
        return np.ascontiguousarray(local[0] @ R.T + p), local[1]

    def _inside_solid(self, g: int, o: int, R: np.ndarray, p: np.ndarray) -> bool:
        """True when obstacle o is a solid mesh and part g, placed at (R, p) (base frame) and
        touching no triangle of it, lies inside it (`manip.collision.solids`)."""
        ob = self._obs[o]
        if not getattr(ob, "solid", False):
            return False
        return part_inside(self._parts[g].geometry, np.asarray(R), np.asarray(p), ob, self._ogeom[o])

    # ------------------------------------------------------------------ public checks
    def _one_q(self, q: np.ndarray, what: str = "q", note: str = "") -> np.ndarray:
        """`q` checked as one configuration (dof,)."""
        q = self.kinematics.check_q(q, what)
        if q.ndim != 1:
            raise InvalidInputError(f"{what} must have shape ({self.kinematics.dof},){note}; got {q.shape}")
        return q

    def _rows(self, Q: np.ndarray, what: str = "Q") -> np.ndarray:
        """`Q` checked as configurations (N, dof) (one row (dof,) becomes (1, dof))."""
        Q = self.kinematics.check_q(Q, what)
        return Q[None] if Q.ndim == 1 else Q

    @consistent
    def in_collision(self, q: np.ndarray) -> bool:
        """True if configuration q (dof,) collides with the world (within the padding) or itself."""
        q = self._one_q(q, note=" (one configuration; in_collision_batch takes several)")
        return bool(self._check(q[None], inside=True)[0])

    @consistent
    def in_collision_batch(self, Q: np.ndarray) -> np.ndarray:
        """(N,) bool: `in_collision` of each row of Q (N, dof), computed together."""
        Q = self._rows(Q)
        if Q.shape[0] == 0:
            return np.zeros(0, dtype=bool)
        return self._check(Q, inside=True)

    @consistent
    def any_in_collision(self, Q: np.ndarray) -> bool:
        """True if any row of Q (N, dof) collides (stops at the first collision found)."""
        Q = self._rows(Q)
        return bool(Q.shape[0] and self._check(Q, stop_at_first=True, inside=True).any())

    @consistent
    def in_collision_exact(self, q: np.ndarray) -> bool:
        """`in_collision` without any broadphase: coal on every pair (slow; a reference).

        The same pairs as `in_collision`: the surface the base stands on (`below_base`) is not
        checked against the links fixed to the base, nor are contacts `allowing` allows."""
        R, p = self._fk(self._one_q(q)[None])
        tfs: dict = {}
        skip = np.zeros((len(self._parts), len(self._obs)), dtype=bool)
        if len(self._obs):
            skip[np.ix_(self._pj == 0, self._world_tables.below_base())] = True
            allowed = self.__dict__.get("_allowed_world")
            if allowed is not None:
                skip |= allowed
        for g in range(len(self._parts)):
            for o in range(len(self._obs)):
                if not skip[g, o] and self._exact(R, p, 0, 0, g, o, tfs):
                    return True
        for a, b in self._pairs:
            if self._exact(R, p, 0, 1, int(a), int(b), tfs):
                return True
        return self._parts_inside(R, p, None, None, np.zeros(1, dtype=bool))   # wholly inside a part

    # ------------------------------------------------------------------ reports and distances
    def _pair_distance(self, geom_a, tf_a, geom_b, tf_b) -> float:
        return geometry_distance(geom_a, tf_a, geom_b, tf_b, coal.DistanceRequest(), coal.DistanceResult())[0]

    def _contact(self, kind: int, a: int, b: int, distance: float) -> Contact:
        """The `Contact` of part a with obstacle b (kind 0) or with part b (kind 1); an
        attached object comes first."""
        pa = self._parts[a]
        if kind == 0:
            return Contact("attached_world" if pa.attached else "world", pa.name, self._obs[b].name, distance)
        pb = self._parts[b]
        if pb.attached:
            pa, pb = pb, pa
        return Contact("attached_self" if pa.attached else "self", pa.name, pb.name, distance)

    @consistent
    def collision_report(self, q: np.ndarray) -> CollisionReport:
        """Every colliding pair of configuration q (dof,), with signed distances, deepest first."""
        Q = self._one_q(q)[None]
        R, p = self._fk(Q)
        n, kind, i, j = self._candidates(Q, R, p)
        tfs: dict = {}
        contacts = []
        for g, o in self._always_colliding:
            tfs[(0, g)] = self._part_tf(R, p, 0, g)
            n, kind, i, j = np.r_[0, n], np.r_[0, kind], np.r_[g, i], np.r_[o, j]
        for t in range(n.size):
            k, a, b = int(kind[t]), int(i[t]), int(j[t])
            if not self._exact(R, p, 0, k, a, b, tfs):
                continue
            if k == 0:
                d = self._pair_distance(self._parts[a].hull, tfs[(0, a)], self._ogeom[b], self._otf[b])
                if d > self._padding and self._inside_solid(a, b, tfs[(0, a)].getRotation(), tfs[(0, a)].getTranslation()):
                    d = -d   # inside a solid mesh
            else:
                d = self._pair_distance(self._parts[a].hull, tfs[(0, a)], self._parts[b].hull, tfs[(0, b)])
            contacts.append(self._contact(k, a, b, d))
        found: list = []   # parts and obstacles wholly inside a part's closed mesh
        self._parts_inside(R, p, None, None, np.zeros(1, dtype=bool), found)
        named = {frozenset((c.a, c.b)) for c in contacts}
        for k, a, b in found:
            d = self._pair_distance(self._parts[a].hull, self._part_tf(R, p, 0, a), *(
                (self._ogeom[b], self._otf[b]) if k == 0 else (self._parts[b].hull, self._part_tf(R, p, 0, b))))
            c = self._contact(k, a, b, min(d, 0.0))
            contacts += [] if frozenset((c.a, c.b)) in named else [c]
        contacts.sort(key=lambda c: c.distance)
        return CollisionReport(bool(contacts), tuple(contacts))

    @consistent
    def distance_report(self, q: np.ndarray) -> DistanceReport:
        """Smallest signed distances [m] of q (dof,) to the world and to itself (no padding).

        Meshes of the robot enter through their convex hulls (exact for convex link meshes
        such as the Panda's; otherwise a lower bound), which gives penetration depths (EPA)
        where mesh-vs-mesh queries cannot; obstacles are exact. Pairs whose bounding balls
        prove them farther than the best found are skipped (branch and bound). A colliding
        configuration has a distance <= 0, also with a part or obstacle wholly inside a closed mesh
        (inside a link: inside its hull; inside a solid mesh obstacle: minus the distance to its surface).
        """
        R, p = self._fk(self._one_q(q)[None])
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
            lb = self._sd_all(bc) - self._pbr[:, None]
            lb[np.ix_(pj == 0, self._world_tables.below_base())] = math.inf  # the surface the base stands on
            lb = lb.ravel()
            for flat in np.argsort(lb):
                if lb[flat] >= best_w:
                    break
                g, o = divmod(int(flat), O)
                d = self._pair_distance(self._parts[g].hull, tf(g), self._ogeom[o], self._otf[o])
                if d > 0.0 and self._inside_solid(g, o, tf(g).getRotation(), tf(g).getTranslation()):
                    d = -d   # inside a solid mesh: as deep as its surface is far (a bound)
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
            closest = self._contact(0, *pair_w, best_w)
        elif pair_s is not None:
            closest = self._contact(1, *pair_s, best_s)
        return DistanceReport(min(best_w, best_s), best_w, best_s, closest)

    @consistent
    def certify_path(self, path: np.ndarray) -> MotionCertificate:
        """Prove the continuous straight interpolation of `path` (K, dof) collision-free.

        Unlike `path_valid`, which checks configurations a resolution apart, this proves
        that no configuration between consecutive rows comes within the padding of an
        obstacle (or the self padding of another link), by conservative advancement on
        the exact geometry (`manip.collision.certify`). A path that cannot be proved free
        (in collision, or grazing within the numerical limits) is not certified.
        """
        path = self.kinematics.check_q(path, "path")
        if path.ndim != 2 or path.shape[0] < 1:
            raise InvalidInputError(f"path must have shape (K, {self.kinematics.dof}) with K >= 1; got {path.shape}")
        return certify_path(self.state, path)

    def distance(self, q: np.ndarray) -> float:
        """Signed distance [m] of q (dof,): min over world and self pairs (negative = penetration)."""
        return self.distance_report(q).distance

    @consistent
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
        Q = self._rows(Q)
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

    # ------------------------------------------------------------------ introspection
    @property
    def num_spheres(self) -> int:
        """Number of balls in the robot's (and attached objects') sphere covers."""
        return int(self._fine.radii.size)

    @consistent
    def spheres(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[str]]:
        """The sphere covers at q (dof,): centres (S, 3) [m], radii (S,) [m], owner names (S,)."""
        R, p = self._fk(self._one_q(q)[None])
        cs, rs, names = [], [], []
        for g, part in enumerate(self._parts):
            Rj, pj = R[0, part.joint], p[0, part.joint]
            cs.append(part.centres @ Rj.T + pj)
            rs.append(part.radii)
            names += [part.name] * len(part.radii)
        return np.concatenate(cs), np.concatenate(rs), names

