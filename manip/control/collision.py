"""Collision avoidance as QP inequalities: `CollisionLimit`, a mink `Limit`.

For each checked geom pair (robot vs obstacle, and the robot's self-collision pairs) whose
distance d is below the detection distance, one row bounds how fast the pair may close
over the step:

    -n' (J2 - J1) dq <= gain * (d - margin)      (0 once d <= margin)

where n is the unit vector between the pair's nearest points and J1, J2 the translation
Jacobians of those points (MuJoCo's `mj_geomDistance` and `mj_jac`). With gain < 1 the
distance decays geometrically towards the margin and never crosses it (up to the
linearisation error of one step, which the margin absorbs); moving away is never
restricted. A pair already closer than the margin may not get closer.

Each pair has its own margin: obstacle pairs the controller's, self pairs at most that
(`self_pair_margins`). Some robots' links lie closer to each other than the margin by
design (the UR10's, 18-20 mm apart at home, with no SRDF to disable them): with the
controller's margin each such pair would forbid half of the joint space from the first step
(a row with bound 0), and a few of them together stop the arm short of its target. Rule:
a self pair at distance d0 at the robot configuration's default joint positions keeps
min(margin, d0 / 2) (still half its designed clearance); a pair touching there (d0 <= 0)
is not checked, as MoveIt's setup assistant disables pairs in collision at the default pose.

Differences from mink's `CollisionAvoidanceLimit`, which this replaces:

- the bound is on the displacement dq of the step, as for mink's configuration limit
  (mink divides the same bound by dt, which lets a pair close 1/dt times faster than the
  gain says: at 60 Hz a geom 2 cm from an obstacle may move 1 m in one step);
- an axis-aligned-box broadphase (compiled with numba) culls the pairs farther apart than the
  detection distance before the narrow phase (the robot's link meshes are long, so their
  bounding spheres, which mink uses, cull little; a floor is never culled by a sphere);
- it reports the smallest distances it measured (`obstacle_clearance`, `self_clearance`)
  and returns only the active rows.

Which pairs are checked (`robot_collision_geoms`, `self_collision_pairs`):
robot geoms that move (not welded to the world) against every obstacle; for self-collision,
the body pairs that the robot configuration does not disable (its SRDF's disabled pairs:
adjacent links and links that can never touch), skipping parent/child and welded bodies.
"""

from __future__ import annotations

import itertools
import math

import mujoco
import numpy as np
from mink import Configuration, Constraint, Limit

from manip.errors import InvalidInputError
from manip.jit import kernel

#: Rows of a pair's local box in `model.geom_aabb`: centre (3) then half extents (3).
_AABB_CENTRE = slice(0, 3)
_AABB_HALF = slice(3, 6)


def robot_collision_geoms(model: mujoco.MjModel, robot_bodies: set[int], moving_only: bool = True) -> list[int]:
    """Colliding geoms (contype or conaffinity set) of the robot's bodies; with
    `moving_only`, only those whose body is not welded to the world (the base cannot avoid
    anything)."""
    out = []
    for g in range(model.ngeom):
        b = int(model.geom_bodyid[g])
        if b not in robot_bodies or (model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0):
            continue
        if moving_only and model.body_weldid[b] == 0:
            continue
        out.append(g)
    return out


def self_collision_pairs(
    model: mujoco.MjModel, robot_bodies: set[int], disabled: set[frozenset[str]]
) -> list[tuple[int, int]]:
    """Geom pairs of the robot that may collide with each other.

    A pair is kept unless its bodies are the same or welded together, parent and child
    (after welding), or named as a disabled pair (by body name; a body welded into another
    counts under its own name and its weld's).
    """
    geoms = robot_collision_geoms(model, robot_bodies, moving_only=False)
    weld = model.body_weldid
    parent = model.body_parentid

    def names(b: int) -> set[str]:
        return {model.body(b).name, model.body(int(weld[b])).name}

    pairs = []
    for g1, g2 in itertools.combinations(geoms, 2):
        b1, b2 = int(model.geom_bodyid[g1]), int(model.geom_bodyid[g2])
        w1, w2 = int(weld[b1]), int(weld[b2])
        if w1 == w2:
            continue
        if int(weld[parent[w1]]) == w2 or int(weld[parent[w2]]) == w1:
            continue
        if any(frozenset((n1, n2)) in disabled for n1 in names(b1) for n2 in names(b2)):
            continue
        pairs.append((g1, g2))
    return pairs


def self_pair_margins(
    model: mujoco.MjModel, data: mujoco.MjData, pairs: list[tuple[int, int]], margin: float
) -> tuple[list[tuple[int, int]], np.ndarray]:
    """Self pairs to check and their margins [m], from their distances in `data` (the
    robot at its default joint positions, kinematics computed).

    A pair at distance d0 keeps min(margin, d0 / 2); a pair with d0 <= 0 (touching by design)
    is left out. Returns (kept pairs, (len(kept),) margins).
    """
    fromto = np.zeros(6)
    kept, margins = [], []
    for g1, g2 in pairs:
        d0 = mujoco.mj_geomDistance(model, data, g1, g2, 2.0 * margin + 1.0, fromto)
        if d0 <= 0.0:
            continue
        kept.append((g1, g2))
        margins.append(min(margin, 0.5 * d0))
    return kept, np.array(margins, dtype=float)


@kernel
def _aabb_candidates(xpos, xmat, geoms, centre, half, s1, s2, distance):  # pragma: no cover (compiled)
    """Pairs (s1[k], s2[k]) of `geoms` whose world-aligned boxes are closer than `distance`.

    Each geom's box (local `centre`, `half` extents from MuJoCo's geom_aabb) is rotated by
    the geom's orientation and bounded by an axis-aligned box in the world.
    """
    n = geoms.shape[0]
    lo = np.empty((n, 3))
    hi = np.empty((n, 3))
    for i in range(n):
        g = geoms[i]
        for a in range(3):
            c = xpos[g, a]
            h = 0.0
            for b in range(3):
                r = xmat[g, 3 * a + b]
                c += r * centre[i, b]
                h += abs(r) * half[i, b]
            lo[i, a] = c - h
            hi[i, a] = c + h
    out = np.empty(s1.shape[0], dtype=np.int64)
    m = 0
    d2 = distance * distance
    for k in range(s1.shape[0]):
        i, j = s1[k], s2[k]
        acc = 0.0
        for a in range(3):
            gap = max(lo[i, a] - hi[j, a], lo[j, a] - hi[i, a], 0.0)
            acc += gap * gap
        if acc < d2:
            out[m] = k
            m += 1
    return out[:m]


class CollisionLimit(Limit):
    """Robot-obstacle and self-collision avoidance rows for the step's QP.

    Args:
        model: the controller's MuJoCo model.
        obstacle_pairs: (robot geom, obstacle geom) pairs.
        self_pairs: (robot geom, robot geom) pairs.
        margin: distance [m] the pairs keep (>= 0).
        detection_distance: pairs farther apart than this [m] add no row (> margin).
        gain: fraction of the distance above the margin a pair may close per step, (0, 1].
        self_margins: (len(self_pairs),) the self pairs' own margins [m], each in [0, margin]
            (default: all `margin`; see `self_pair_margins`).

    After each `compute_qp_inequalities`, `obstacle_clearance` and `self_clearance` hold
    the smallest measured distances [m] (inf if no pair was within the detection distance)
    and `active_rows` the number of rows returned.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        obstacle_pairs: list[tuple[int, int]],
        self_pairs: list[tuple[int, int]],
        margin: float,
        detection_distance: float,
        gain: float,
        self_margins=None,
    ):
        self.model = model
        self.margin = float(margin)
        self.detection_distance = float(detection_distance)
        self.gain = float(gain)
        pairs = [(int(a), int(b)) for a, b in obstacle_pairs] + [(int(a), int(b)) for a, b in self_pairs]
        self.n_obstacle_pairs = len(obstacle_pairs)
        self.pairs = np.array(pairs, dtype=int).reshape(-1, 2)
        self._is_obstacle = np.arange(len(pairs)) < self.n_obstacle_pairs
        own = np.full(len(self_pairs), self.margin) if self_margins is None else np.asarray(self_margins, dtype=float)
        if own.shape != (len(self_pairs),) or not np.all((own >= 0.0) & (own <= self.margin)):
            raise InvalidInputError(f"self_margins must be {len(self_pairs)} values in [0, margin = {self.margin} m]; "
                                    f"got {np.asarray(self_margins).tolist()}")
        #: (n_pairs,) each pair's margin [m]: obstacle pairs first, then self pairs.
        self.margins = np.concatenate([np.full(len(obstacle_pairs), self.margin), own])
        self._margin_of = self.margins.tolist()
        geoms = np.unique(self.pairs).astype(np.int64) if len(pairs) else np.zeros(0, dtype=np.int64)
        self._geoms = geoms
        slot = {int(g): i for i, g in enumerate(geoms)}
        self._s1 = np.array([slot[a] for a, _ in pairs], dtype=np.int64)
        self._s2 = np.array([slot[b] for _, b in pairs], dtype=np.int64)
        self._centre = np.ascontiguousarray(model.geom_aabb[geoms, _AABB_CENTRE], dtype=float)
        self._half = np.ascontiguousarray(model.geom_aabb[geoms, _AABB_HALF], dtype=float)
        self._pair_info = [(int(a), int(b), int(model.geom_bodyid[a]), int(model.geom_bodyid[b]), bool(o))
                           for (a, b), o in zip(pairs, self._is_obstacle)]
        self._G = np.zeros((len(pairs), model.nv))
        self._h = np.zeros(len(pairs))
        self._fromto = np.zeros(6)
        self._jac1 = np.zeros((3, model.nv))
        self._jac2 = np.zeros((3, model.nv))
        self.obstacle_clearance = float("inf")
        self.self_clearance = float("inf")
        self.active_rows = 0

    @property
    def n_pairs(self) -> int:
        """Number of checked pairs (obstacle and self)."""
        return len(self.pairs)

    def candidates(self, data: mujoco.MjData, distance: float) -> np.ndarray:
        """Indices of the pairs whose world-aligned bounding boxes are closer than `distance`."""
        if not len(self.pairs):
            return np.zeros(0, dtype=np.int64)
        return _aabb_candidates(data.geom_xpos, data.geom_xmat, self._geoms, self._centre, self._half, self._s1,
                                self._s2, float(distance))

    def distances(self, data: mujoco.MjData, distance: float = 10.0) -> tuple[float, float]:
        """(obstacle, self) smallest distances [m] at the state of `data` among the pairs
        within `distance` (inf if none); no QP rows."""
        best = [float("inf"), float("inf")]
        for k in self.candidates(data, distance).tolist():
            g1, g2, _, _, is_obstacle = self._pair_info[k]
            d = mujoco.mj_geomDistance(self.model, data, g1, g2, distance, self._fromto)
            i = 0 if is_obstacle else 1
            if d < best[i]:
                best[i] = float(d)
        return best[0], best[1]

    def compute_qp_inequalities(self, configuration: Configuration, dt: float) -> Constraint:
        model, data = self.model, configuration.data
        dmax = self.detection_distance
        margins, gain = self._margin_of, self.gain
        fromto, jac1, jac2 = self._fromto, self._jac1, self._jac2
        G, h = self._G, self._h
        n_rows = 0
        best_obstacle = best_self = math.inf
        for k in self.candidates(data, dmax).tolist():
            g1, g2, b1, b2, is_obstacle = self._pair_info[k]
            d = mujoco.mj_geomDistance(model, data, g1, g2, dmax, fromto)
            if d >= dmax:
                continue
            if is_obstacle:
                best_obstacle = min(best_obstacle, d)
            else:
                best_self = min(best_self, d)
            margin = margins[k]
            n = fromto[3:] - fromto[:3]
            norm = math.sqrt(float(n @ n))
            if norm < 1e-12:
                continue  # touching at one point: no direction (the margin keeps pairs apart before this)
            n *= (-1.0 if d < 0 else 1.0) / norm  # penetrating: the nearest points are crossed over
            mujoco.mj_jac(model, data, jac1, None, fromto[:3], b1)
            mujoco.mj_jac(model, data, jac2, None, fromto[3:], b2)
            G[n_rows] = n @ jac1 - n @ jac2
            h[n_rows] = gain * (d - margin) if d > margin else 0.0
            n_rows += 1
        self.obstacle_clearance = best_obstacle
        self.self_clearance = best_self
        self.active_rows = n_rows
        if not n_rows:
            return Constraint()
        return Constraint(G=G[:n_rows].copy(), h=h[:n_rows].copy())
