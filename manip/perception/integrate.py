"""Depth images and point clouds integrated into an occupancy map of the planner's world.

`integrate_depth(checker, depth, intrinsics, camera_pose, ...)` updates the occupancy obstacle
`name` of a `CollisionChecker` (created on first use; `manip.collision.OccupancyMap`) with one
depth image; `integrate_pointcloud` does the same with a cloud. `MotionGenerator`'s
`update_world_from_depth` / `update_world_from_pointcloud` call them. One update:

1. the points: each pixel with a depth is back-projected into the base frame (pinhole;
   depth = distance to the image plane); points farther than `max_range` from the camera,
   or beyond the robot's reach (`reach`), are dropped;
2. self-filtering: with `q`, points within `self_margin` of the robot at q are dropped: of
   a part's 26-DOP (the polytope of 26 fixed directions around the convex hull of its
   collision geometry; links and attached objects), looked up through the sphere cover
   (built once per q: the images of several cameras taken at the same q share it);
3. occupied: the cell of every remaining point (`manip.perception.kernels`), holding the
   points measured in it (`OccupancyMap.points`, with their bounding box `bounds`: the
   surface as the camera saw it, each cell the convex hull of its points; what a point hides
   behind it is unknown: not in the cell, or with `unknown="occupied"` in it, the ray a cell
   diagonal behind the point clamped to the cell; over every update until the cell is freed,
   so two cameras' views add up; a cell over `MAX_CELL_POINTS` keeps its box instead);
4. free: a cell occupied before (or, with `unknown="occupied"`, never observed) is freed
   when the image sees through it: every pixel ray crossing it measures a surface beyond the
   point where it leaves the cell (`cells_seen_free`), so an object that moved away
   disappears from where it was, while a cell next to a surface, or hidden behind one,
   keeps what it held. Cells seen occupied in this image stay occupied.

What the map guarantees: every point a camera measured (and kept) lies in its cell's solid
(to `SNAP`) until an image sees through that cell; the solids of face-adjacent occupied cells
meet where a measured surface goes on from one to the other (`OccupancyMap`,
`manip.collision.occupancy_hulls`), so a surface seen as face-adjacent cells is a closed
sheet, and elsewhere the gap is at most the spacing of the measured points there (about
depth / focal length [px]: 2-3 mm at 1.5 m for the cameras of `benchmarks/perception.py`). The volume behind a seen surface is not in the map (with
`unknown="free"`): a part can only get there through the seen surface (which the checks and
the continuous certificate refuse) or through a face no camera saw. With
`fill="cells"` every occupied cell is whole (surfaces inflated by up to a cell). With
`unknown="free"` (the default), space never observed is free: an object no camera saw is
not avoided. With `unknown="occupied"`, every
cell within `bounds` that no image has seen free is an obstacle and a surface's own cell holds
what the surface hides in it, so only space observed free (or outside `bounds`) is planned
through.

The map's state between updates (the cells seen occupied; with `unknown="occupied"` which
cells were observed) is kept beside the map obstacle of the world (keyed by that very
obstacle): removing the obstacle, or replacing it with another shape, starts a new map.
Threads updating the maps of one checker take turns in applying their images (read the
map, free, merge, build and install the new one), so no observation is lost; the
back-projection and the self-filter run in parallel.
"""

from __future__ import annotations

import logging
import math
import threading
import weakref
from dataclasses import dataclass

import numpy as np

from manip.collision.occupancy import OccupancyMap
from manip.errors import InvalidInputError
from manip.perception.kernels import SNAP, cells_seen_free, depth_cells, on_robot, pack_all, sphere_index, unpack
from manip.perception.observations import difference, merge_observation, reduce_points
from manip.pose import Pose
from manip.validation import as_real_array, non_negative, positive

logger = logging.getLogger(__name__)

#: The optical axes (x right, y down, z forward) in Isaac's "world" camera axes (+X forward,
#: +Z up): R_base_optical = R_base_camera @ WORLD_AXES_TO_OPTICAL.
WORLD_AXES_TO_OPTICAL = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
#: Cell edge [m] of the self-filter's index of the robot's balls.
SELF_CELL = 0.02
#: Cells with a corner closer than this to a camera's image plane are never freed by it [m].
NEAR = 1e-3
#: Pixels per face of the virtual cube map that turns a cloud with an origin into rays.
CLOUD_PIXELS = 256
#: Largest bounds grid of `unknown="occupied"` (cells).
MAX_BOUNDS_CELLS = 8_000_000
#: Largest cell edge [m]: a coarser cell would fill much of a manipulator's workspace.
MAX_RESOLUTION = 0.5
#: A cell keeps at most this many measured points (its convex hull); beyond, it is its box.
MAX_CELL_POINTS = 256
_UNKNOWN = ("free", "occupied")
_FILL = ("points", "cells")


@dataclass
class _MapState:
    """What a map remembers between updates (module docstring)."""

    resolution: float
    seen: np.ndarray             # (C,) sorted keys of the cells seen occupied
    seen_bounds: np.ndarray      # (C, 6) [m] (lo, hi) the bounds of the points measured in each (fill="cells": the cell)
    unknown: str
    bounds_lo: np.ndarray | None = None   # (3,) int64 first cell of the bounds grid
    observed: np.ndarray | None = None    # bool grid over the bounds: seen (free or occupied)
    seen_start: np.ndarray | None = None   # (C + 1,) cell c's points: seen_points[seen_start[c]:seen_start[c + 1]]
    seen_points: np.ndarray | None = None  # (N, 3) [m] the points measured in the cells (none: a box)


_STATES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


# ---------------------------------------------------------------------- inputs
def _depth(depth) -> np.ndarray:
    if not isinstance(depth, np.ndarray) or depth.dtype not in (np.float32, np.float64):
        raise InvalidInputError(f"depth must be a float32 or float64 (H, W) array [m]; got "
                                f"{type(depth).__name__}{'' if not isinstance(depth, np.ndarray) else ' ' + str(depth.dtype)}")
    d = depth[..., 0] if depth.ndim == 3 and depth.shape[2] == 1 else depth
    if d.ndim != 2 or d.shape[0] < 1 or d.shape[1] < 1:
        raise InvalidInputError(f"depth must have shape (H, W) (or (H, W, 1)); got {depth.shape}")
    if not d.flags.c_contiguous or not d.flags.writeable:   # the kernels' signature: a writable C array
        d = np.array(d, order="C")
    return d   # float32 or float64 as given (negative values: `depth_cells` counts them)


def _resolution(resolution) -> float:
    res = positive(resolution, "resolution", "m")
    if res > MAX_RESOLUTION:
        raise InvalidInputError(f"resolution must be at most {MAX_RESOLUTION} m (a cell edge; a coarser cell fills much "
                                f"of the workspace); got {resolution} m")
    return res


def _intrinsics(K) -> tuple[float, float, float, float]:
    K = as_real_array(K, "intrinsics")
    if K.shape != (3, 3):
        raise InvalidInputError(f"intrinsics must be a (3, 3) matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]; got {K.shape}")
    (fx, s, cx), (k10, fy, cy), (k20, k21, k22) = K.tolist()   # floats: cheaper than NumPy's calls on 9 values
    if not all(math.isfinite(v) for v in (fx, s, cx, k10, fy, cy, k20, k21, k22)):
        raise InvalidInputError(f"intrinsics must be finite; got {K.tolist()}")
    # the last row [0, 0, 1] to NumPy's allclose tolerance (atol 1e-8, rtol 1e-5)
    last_row = abs(k20) <= 1e-8 and abs(k21) <= 1e-8 and abs(k22 - 1.0) <= 1e-8 + 1e-5
    if not (fx > 0 and fy > 0) or not last_row or k10 != 0:
        raise InvalidInputError(f"intrinsics must be [[fx, s, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0; "
                                f"got {K.tolist()}")
    if s != 0:
        raise InvalidInputError(f"intrinsics with skew are not supported (K[0, 1] = {s}); give K[0, 1] = 0")
    return fx, fy, cx, cy


def _pose(camera_pose) -> Pose:
    if not isinstance(camera_pose, Pose) or camera_pose.is_batch:
        raise InvalidInputError(f"camera_pose must be one manip.Pose (position [m], quaternion wxyz, in the robot "
                                f"base frame, Isaac's camera axes: +X forward, +Z up); got {type(camera_pose).__name__}")
    return camera_pose


def _bounds(bounds, unknown: str) -> np.ndarray | None:
    if unknown not in _UNKNOWN:
        raise InvalidInputError(f"unknown must be one of {', '.join(map(repr, _UNKNOWN))}; got {unknown!r}")
    if bounds is None:
        if unknown == "occupied":
            raise InvalidInputError('unknown="occupied" needs bounds: [[x0, y0, z0], [x1, y1, z1]] [m] (base frame), '
                                    "the box where unobserved space is an obstacle")
        return None
    b = as_real_array(bounds, "bounds")
    if b.shape != (2, 3) or not np.all(np.isfinite(b)) or not np.all(b[1] > b[0]):
        raise InvalidInputError(f"bounds must be [[x0, y0, z0], [x1, y1, z1]] [m] with x0 < x1, y0 < y1, z0 < z1; "
                                f"got {bounds!r}")
    return b


# ---------------------------------------------------------------------- the update
#: The 26 directions of the k-DOPs that stand for the robot's parts in the self-filter.
_DIRECTIONS = np.array([d for d in np.ndindex(3, 3, 3) if d != (1, 1, 1)], dtype=float) - 1.0
_DIRECTIONS /= np.linalg.norm(_DIRECTIONS, axis=1, keepdims=True)


@dataclass(frozen=True)
class _Robot:
    """The robot at q for the self-filter: its balls (the index of candidate parts) and each
    part as a 26-DOP (the box of 26 directions holding its convex hull)."""

    centres: np.ndarray   # (S, 3) [m] ball centres, base frame
    radii: np.ndarray     # (S,) [m] radii grown by the margin
    part: np.ndarray      # (S,) int64 part of each ball
    dop: np.ndarray       # (G, 4, 26): per face n (unit, base frame; 3 rows) and offset d: the part is in n.x <= d
    margin: float


@dataclass(frozen=True)
class _SelfFilter:
    """The self-filter at one q: the robot (`_Robot`), the index of its balls (`sphere_index`)
    and the reach [m] (`reach`) beyond which points are dropped."""

    robot: _Robot
    index: tuple
    reach: float


#: {checker: (robot cover, key, _SelfFilter)}: the last self-filter of each checker, so that
#: the images of several cameras taken at the same q build it once.
_FILTERS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _self_filter(checker, q, margin: float) -> _SelfFilter:
    """The self-filter of `checker` at q (as `_robot`), built once per (robot model, q, margin)."""
    fine = checker.state.fine   # replaced when the robot's parts change (attached objects, fingers)
    a = None if q is None else np.asarray(q)
    key = (margin, None) if a is None else (margin, a.dtype.str, a.shape, a.tobytes())
    got = _FILTERS.get(checker)
    if got is not None and got[0] is fine and got[1] == key:
        return got[2]
    rob = _robot(checker, q, margin)
    far = got[2].reach if got is not None and got[0] is fine else reach(checker)   # the robot's, not q's
    out = _SelfFilter(rob, sphere_index(rob.centres, rob.radii, rob.part, rob.dop.shape[0], SELF_CELL), far)
    _FILTERS[checker] = (fine, key, out)
    return out


#: {checker state's sphere cover: (part joint (G,), R (G, 3, 3), p (G, 3), h (G, 26))}: each
#: part's place on its joint and its 26-DOP in its own frame (h: the offsets of the faces
#: `_DIRECTIONS`), so that the DOP at q is n = R_part D, d = h + n.p_part.
_PARTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _parts(st) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The robot parts' constants of `_PARTS` for the checker state `st` (built once per cover)."""
    got = _PARTS.get(st.fine)
    if got is None:
        tb = st.motion_bounds
        joint = np.array([part.joint for part in st.parts], dtype=np.int64)
        R = np.array([part.R for part in st.parts], dtype=np.float64).reshape(-1, 3, 3)
        p = np.array([part.p for part in st.parts], dtype=np.float64).reshape(-1, 3)
        # max over the support points s (part frame) of D.s, grown by the support radius
        h = np.array([(tb.support[g] @ _DIRECTIONS.T).max(axis=0) + tb.support_radius[g]
                      for g in range(len(st.parts))]).reshape(-1, 26)
        got = _PARTS[st.fine] = (joint, R, p, h)
    return got


def _robot(checker, q, margin: float) -> _Robot:
    """The robot at q for the self-filter (empty without q): q (dof,) the arm, or the full
    robot state (dof + G,) with the gripper's joints last, whose fingers are then placed where
    they are (the planner's model holds them at its planning positions)."""
    if q is None:
        return _Robot(np.zeros((0, 3)), np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros((0, 4, 26)), margin)
    kin = checker.kinematics
    gripper = checker.config.gripper
    fingers = None
    a = as_real_array(q, "q")
    if gripper is not None and a.ndim == 1 and a.shape[0] == kin.dof + len(gripper.joints):
        a, fingers = a[:kin.dof], a[kin.dof:]
    q = kin.check_q(a, "q")
    if q.ndim != 1:
        raise InvalidInputError(f"q must be one configuration ({kin.dof},) or a full robot state; got {q.shape}")
    st = checker.state
    joint, Rp, pp, h = _parts(st)
    C, r, _ = checker.spheres(q)
    R, p = st.joint_transforms(q[None])
    Rw = R[0, joint] @ Rp                                    # (G, 3, 3) each part in the base frame
    pw = p[0, joint] + np.einsum("gij,gj->gi", R[0, joint], pp)
    C = np.array(C, dtype=np.float64)
    moved = _finger_motions(checker, q, fingers)
    for g, part in enumerate(st.parts):
        T = moved.get(part.name)
        if T is not None:   # a finger: from its planning place to where it is
            Rw[g], pw[g] = T[0] @ Rw[g], T[0] @ pw[g] + T[1]
            sel = st.fine.part == g
            C[sel] = C[sel] @ T[0].T + T[1]
    n = np.einsum("gij,fj->gif", Rw, _DIRECTIONS)             # (G, 3, 26) the faces' normals, base frame
    dop = np.empty((len(st.parts), 4, 26))
    dop[:, :3] = n
    dop[:, 3] = h + np.einsum("gif,gi->gf", n, pw)
    return _Robot(np.ascontiguousarray(C), np.ascontiguousarray(r + margin, dtype=np.float64),
                  np.ascontiguousarray(st.fine.part, dtype=np.int64), dop, margin)


def _finger_motions(checker, q: np.ndarray, fingers: np.ndarray | None) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """{link: (R (3, 3), t (3,))}: the rigid motion (base frame) taking each link the gripper's
    joints move from its place in the checker's model (its gripper positions) to its place at
    `fingers` [m] (the arm at q)."""
    gripper = checker.config.gripper
    if fingers is None or gripper is None:
        return {}
    import pinocchio as pin

    kin = checker.kinematics
    full = kin.full_model
    data = full.createData()
    places = []
    for values in (checker.robot.gripper_positions, fingers):   # where the checker's model has them; where they are
        qf = kin.locked_configuration.copy()
        for name, v in zip(checker.config.arm_joints, q):
            qf[full.joints[full.getJointId(name)].idx_q] = v
        for name, v in zip(gripper.joints, values):
            qf[full.joints[full.getJointId(name)].idx_q] = v
        pin.forwardKinematics(full, data, qf)
        pin.updateFramePlacements(full, data)
        places.append({f.name: data.oMf[i].copy() for i, f in enumerate(full.frames)})
    finger_joints = {full.getJointId(name) for name in gripper.joints}
    out = {}
    for i, f in enumerate(full.frames):
        j = f.parentJoint
        while j > 0 and j not in finger_joints:
            j = full.parents[j]
        if j > 0 and f.name in places[0]:
            M = places[1][f.name] * places[0][f.name].inverse()
            out[f.name] = (np.array(M.rotation), np.array(M.translation))
    return out


def reach(checker) -> float:
    """A bound [m] of how far from the base origin any point of the robot (and its attached
    objects) can get: beyond it, nothing a camera sees can touch the robot."""
    st = checker.state
    tb = st.motion_bounds
    specs = st.kinematics.joint_specs
    first = float(np.linalg.norm(specs[0].p_placement)) if specs else 0.0
    moving = float(np.max(tb.dist[:, 1], initial=0.0)) + first if tb.dist.shape[1] > 1 else 0.0
    C, r = st.fine.centres, st.fine.radii
    fixed = st.fine.joint == 0
    static = float(np.max(np.linalg.norm(C[fixed], axis=1) + r[fixed], initial=0.0))
    return max(moving, static)


class _Frame:
    """One observation: `keys` (occupied cells, sorted), `bounds` (the bounds (C, 6) [m] of
    the points in each), the points measured in each (`start` (C + 1,), `points` (N, 3) [m];
    a cell without points is its box) and `seen_free(cells)`."""

    def __init__(self, keys: np.ndarray, bounds: np.ndarray, points: np.ndarray, rows: np.ndarray, seen_free):
        self.keys, self.bounds, self.start, self.points = reduce_points(
            np.ascontiguousarray(keys, dtype=np.int64), np.ascontiguousarray(bounds, dtype=np.float64),
            np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3), np.ascontiguousarray(rows, dtype=np.int64))
        self.seen_free = seen_free


def _full_cells(cells: np.ndarray, res: float) -> np.ndarray:
    """(C, 6) [m] the whole cells of cells (C, 3)."""
    return np.hstack([cells * res, (cells + 1) * res]).astype(np.float64)


def _fill(fill: str) -> str:
    if fill not in _FILL:
        raise InvalidInputError(f"fill must be one of {', '.join(map(repr, _FILL))}; got {fill!r}")
    return fill


#: {checker: lock}: one update of a checker's maps at a time (read the map, build, install).
_LOCKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_LOCKS_LOCK = threading.Lock()


def _update(checker, name: str, resolution: float, unknown: str, bounds, frame: _Frame, fill: str) -> OccupancyMap:
    """Apply one observation to the map `name` of `checker` and install the new map; threads
    updating the same checker take turns, so every observation is kept."""
    with _LOCKS_LOCK:
        lock = _LOCKS.setdefault(checker, threading.Lock())
    with lock:
        return _update_locked(checker, name, resolution, unknown, bounds, frame, fill)


def _update_locked(checker, name: str, resolution: float, unknown: str, bounds, frame: _Frame,
                   fill: str) -> OccupancyMap:
    world = checker.world
    prev = world.get(name) if name in world else None
    if prev is not None and not isinstance(prev, OccupancyMap):
        raise InvalidInputError(f"name: the obstacle '{name}' is a {prev.kind}, not an occupancy map; choose another "
                                "name or remove it first")
    state = _STATES.get(prev) if prev is not None else None
    if state is not None and (state.resolution != resolution or state.unknown != unknown):
        raise InvalidInputError(f"the map '{name}' has resolution {state.resolution} m and unknown={state.unknown!r}; "
                                f"got resolution {resolution} m and unknown={unknown!r}: remove_obstacle('{name}') "
                                "to start a new map")
    if state is None:
        seen, sb = np.zeros(0, dtype=np.int64), np.zeros((0, 6))
        ss, sp = np.zeros(1, dtype=np.int64), np.zeros((0, 3))
        if prev is not None:   # a map given as cells: its bounds, or whole cells (the cells are sorted, so the keys)
            seen = pack_all(np.array(prev.cells))   # a writable copy: the compiled signature
            sb = prev.bounds if prev.bounds is not None else _full_cells(prev.cells, prev.resolution)
            ss = np.zeros(seen.size + 1, dtype=np.int64) if prev.points is None else np.array(prev.point_start)
            sp = np.zeros((0, 3)) if prev.points is None else np.array(prev.points)
        state = _MapState(resolution, seen, np.asarray(sb, dtype=np.float64), unknown, seen_start=ss, seen_points=sp)
        if unknown == "occupied":
            lo = np.floor(bounds[0] / resolution).astype(np.int64)
            hi = np.ceil(bounds[1] / resolution).astype(np.int64)
            if float(np.prod((hi - lo).astype(float))) > MAX_BOUNDS_CELLS:
                raise InvalidInputError(f"bounds: {np.prod(hi - lo):,} cells at {resolution} m (at most "
                                        f"{MAX_BOUNDS_CELLS:,}); use smaller bounds or a coarser resolution")
            state.bounds_lo = lo
            state.observed = np.zeros(tuple(int(x) for x in hi - lo), dtype=bool)
    # cells occupied before and not seen occupied now: freed where the image sees through them
    old = difference(state.seen, frame.keys)
    freed = np.ascontiguousarray(old[frame.seen_free(unpack(old))]) if old.size else old
    seen, seen_bounds, seen_start, seen_points = merge_observation(
        state.seen, state.seen_bounds, state.seen_start, state.seen_points, freed, frame.keys, frame.bounds,
        frame.start, frame.points, MAX_CELL_POINTS)
    cells = unpack(seen)
    cb = seen_bounds
    start = seen_start
    if state.observed is not None:
        obs = state.observed
        rel = cells - state.bounds_lo
        inside = np.all((rel >= 0) & (rel < obs.shape), axis=1)
        obs = obs.copy()
        obs[rel[inside, 0], rel[inside, 1], rel[inside, 2]] = True
        hidden = np.argwhere(~obs)
        if hidden.size:
            free = frame.seen_free(np.ascontiguousarray(hidden + state.bounds_lo))
            obs[tuple(hidden[free].T)] = True
            hidden = hidden[~free]
        state = _MapState(resolution, seen, seen_bounds, unknown, state.bounds_lo, obs, seen_start, seen_points)
        hidden = hidden + state.bounds_lo
        cells = np.vstack([cells, hidden])
        cb = np.vstack([cb, _full_cells(hidden, resolution)])
        start = np.concatenate([start, np.full(hidden.shape[0], start[-1])])   # whole cells: no points
    else:
        state = _MapState(resolution, seen, seen_bounds, unknown, seen_start=seen_start, seen_points=seen_points)
    hulls = fill == "points" and seen_points.shape[0] > 0
    new = OccupancyMap.from_cells(name, resolution, cells, cb if fill == "points" else None,
                                  (start, seen_points) if hulls else None, _sorted=state.observed is None)
    if prev is None:
        checker.add_obstacle(new)
    else:
        checker.replace_obstacle(new)
    _STATES[new] = state
    return new


def integrate_depth(checker, depth, intrinsics, camera_pose: Pose, *, name: str = "camera", resolution: float = 0.02,
                    q: np.ndarray | None = None, max_range: float = 3.0, unknown: str = "free", bounds=None,
                    self_margin: float = 0.01, fill: str = "points") -> OccupancyMap:
    """Integrate one depth image into the occupancy map `name` of `checker` (module docstring).

    Args:
        checker: the `CollisionChecker` whose world holds the map.
        depth: (H, W) float32/float64 distances to the image plane [m] (inf: nothing hit; NaN:
            no measurement), as `manip.sim.Camera.get_depth()` gives.
        intrinsics: (3, 3) [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] [px], pixel (u, v) =
            (column, row) at the pixel's centre.
        camera_pose: the camera in the robot base frame, Isaac's camera axes (+X forward, +Z up).
        name: the map obstacle (created on first use).
        resolution: cell edge [m].
        q: (dof,) the robot's configuration when the image was taken, or the full robot state
            (dof + G,) with the gripper's joints last (the fingers where they are): points on
            the robot (within `self_margin` [m] of a part's 26-DOP) are dropped; None: no
            self-filter.
        max_range: points farther than this from the camera [m] are ignored.
        unknown: "free" (never observed = free) or "occupied" (within `bounds`).
        bounds: [[x0, y0, z0], [x1, y1, z1]] [m], base frame (needed with unknown="occupied").
        self_margin: points within this of the robot [m] are dropped.
        fill: "points" (the default): an occupied cell is the convex hull of the points
            measured in it (`OccupancyMap.points`: the surface as the camera saw it; a flat,
            axis-aligned one their box); "cells": the whole cell (surfaces inflated by up to a
            cell).

    Returns:
        The new `OccupancyMap` (also in the checker's world).
    """
    d = _depth(depth)
    fx, fy, cx, cy = _intrinsics(intrinsics)
    pose = _pose(camera_pose)
    res = _resolution(resolution)
    rng = positive(max_range, "max_range", "m")
    margin = non_negative(self_margin, "self_margin", "m")
    b = _bounds(bounds, unknown)
    fill = _fill(fill)
    R = np.ascontiguousarray(pose.rotation @ WORLD_AXES_TO_OPTICAL)
    t = np.array(pose.position, dtype=np.float64)   # a writable copy: the compiled signature
    sf = _self_filter(checker, q, margin)
    rob = sf.robot
    keys, kb, pts, rows, on_robot, negative = depth_cells(d, fx, fy, cx, cy, R, t, rng, res, fill == "points",
                                               _hidden_depth(unknown, res), np.zeros(3), sf.reach + 0.1,
                                               rob.centres, rob.radii, rob.part, rob.dop, rob.margin, SELF_CELL,
                                               *sf.index)
    if negative:
        raise InvalidInputError(f"depth must be >= 0 (inf or NaN where nothing was measured); got {negative} "
                                "negative values")
    logger.debug("depth image: %d points kept, %d on the robot", keys.size, on_robot)

    def seen_free(cells: np.ndarray) -> np.ndarray:
        return cells_seen_free(np.ascontiguousarray(cells, dtype=np.int64), d, fx, fy, cx, cy, R, t, res, NEAR)

    return _update(checker, name, res, unknown, b, _Frame(keys, kb, pts, rows, seen_free), fill)


def _cube_faces() -> list[np.ndarray]:
    """The optical frames (x right, y down, z forward) of the six faces of a cube map."""
    out = []
    for axis in range(3):
        for sign in (1.0, -1.0):
            z = np.zeros(3)
            z[axis] = sign
            up = np.array([0.0, 0.0, 1.0]) if axis != 2 else np.array([1.0, 0.0, 0.0])
            x = np.cross(z, up)
            x /= np.linalg.norm(x)
            y = np.cross(z, x)
            out.append(np.stack([x, y, z], axis=1))
    return out


def integrate_pointcloud(checker, points, origin=None, *, name: str = "camera", resolution: float = 0.02,
                         q: np.ndarray | None = None, max_range: float = 3.0, unknown: str = "free", bounds=None,
                         self_margin: float = 0.01, fill: str = "points") -> OccupancyMap:
    """Integrate a point cloud into the occupancy map `name` of `checker`.

    As `integrate_depth`, with the points given: (N, 3) [m] in the robot base frame (NaN
    rows are skipped). With `origin` (3,) [m], the sensor's position, the rays from it to the
    points also free the cells they see through: the cloud is binned into a virtual cube
    map of `CLOUD_PIXELS` pixels per face around the origin (the nearest point of each
    pixel stands for its ray; a pixel without a point frees nothing), so a sparse cloud
    frees little. Without `origin` the points only add occupied cells.
    """
    P = as_real_array(points, "points")
    if P.ndim != 2 or P.shape[1] != 3:
        raise InvalidInputError(f"points must have shape (N, 3) [m]; got {P.shape}")
    if np.any(np.isinf(P)):
        raise InvalidInputError("points must be finite (NaN rows are skipped); got inf")
    P = P[~np.isnan(P).any(axis=1)]
    res = _resolution(resolution)
    rng = positive(max_range, "max_range", "m")
    margin = non_negative(self_margin, "self_margin", "m")
    b = _bounds(bounds, unknown)
    fill = _fill(fill)
    o = np.zeros(3) if origin is None else as_real_array(origin, "origin")
    if o.shape != (3,) or not np.all(np.isfinite(o)):
        raise InvalidInputError(f"origin must be a finite position (3,) [m] or None; got {origin!r}")
    sf = _self_filter(checker, q, margin)
    n = CLOUD_PIXELS
    f = n / 2.0   # 90 deg per face
    faces = []
    if origin is not None:
        for Rf in _cube_faces():
            Y = (P - o) @ Rf
            z = Y[:, 2]
            with np.errstate(divide="ignore", invalid="ignore"):
                u = np.rint(f * Y[:, 0] / z + (n - 1) / 2.0)
                v = np.rint(f * Y[:, 1] / z + (n - 1) / 2.0)
            sel = (z > 0) & (u >= 0) & (u < n) & (v >= 0) & (v < n)
            img = np.full((n, n), np.inf)
            np.minimum.at(img, (v[sel].astype(np.int64), u[sel].astype(np.int64)), z[sel])
            img[np.isinf(img)] = np.nan   # no point in this pixel: no ray
            faces.append((np.ascontiguousarray(Rf), img))
    dist = np.linalg.norm(P - o, axis=1) if origin is not None else np.zeros(P.shape[0])
    keep = (dist <= rng) & (np.linalg.norm(P, axis=1) <= sf.reach + 0.1)
    keys, kb, pts, rows = _cloud_cells(P[keep], None if origin is None else o, res, sf, _hidden_depth(unknown, res))

    def seen_free(cells: np.ndarray) -> np.ndarray:
        out = np.zeros(cells.shape[0], dtype=bool)
        c = np.ascontiguousarray(cells, dtype=np.int64)
        for Rf, img in faces:
            out |= cells_seen_free(c, img, f, f, (n - 1) / 2.0, (n - 1) / 2.0, Rf, o, res, NEAR)
        return out

    return _update(checker, name, res, unknown, b, _Frame(keys, kb, pts, rows, seen_free), fill)


def _cloud_cells(P: np.ndarray, origin: np.ndarray | None, res: float, sf: _SelfFilter,
                 behind: float = 0.0) -> tuple[np.ndarray, ...]:
    """Keys (N,) of the cells of points P (N, 3) [m] off the robot (`_SelfFilter`), the
    points as bounds (N, 6) [m] and as points (M, 3) with the row of each (M,); with an
    origin, a point within SNAP before a cell face along its ray counts in the cell behind,
    and the bounds (and points) hold its ray `behind` [m] further (`_hidden_depth`; without an
    origin, `behind` > 0 gives the whole cell, and no points)."""
    if P.shape[0] == 0:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 6)), np.zeros((0, 3)), np.zeros(0, dtype=np.int64)
    rob = sf.robot
    if rob.dop.shape[0]:
        P = np.ascontiguousarray(P, dtype=np.float64)
        P = P[~on_robot(P, rob.centres, rob.radii, rob.part, rob.dop, rob.margin, SELF_CELL, *sf.index)]
    at = P
    lo = hi = P
    rows = np.arange(P.shape[0])
    pts, prow = P, rows
    if origin is not None:
        ray = P - origin
        ray = ray / np.maximum(np.linalg.norm(ray, axis=1, keepdims=True), 1e-12)
        at = P + SNAP * ray
        if behind > 0.0:
            lo, hi = np.minimum(P, P + behind * ray), np.maximum(P, P + behind * ray)
            pts, prow = np.vstack([P, P + behind * ray]), np.concatenate([rows, rows])
    elif behind > 0.0:   # no ray: which side a point hides is not known; its whole cell
        lo = np.floor(at / res) * res
        hi = lo + res
        pts, prow = np.zeros((0, 3)), np.zeros(0, dtype=np.int64)
    return pack_all(np.ascontiguousarray(np.floor(at / res).astype(np.int64))), np.hstack([lo, hi]), pts, prow


def _hidden_depth(unknown: str, res: float) -> float:
    """How far behind a measured point its cell's box reaches along the ray [m]: with
    `unknown="occupied"` a cell diagonal (clamped to the cell: the part of a surface's own cell
    the surface hides is unknown, so an obstacle), else 0 (the points alone: hidden = free)."""
    return math.sqrt(3.0) * res if unknown == "occupied" else 0.0


__all__ = ["integrate_depth", "integrate_pointcloud", "reach", "WORLD_AXES_TO_OPTICAL"]
