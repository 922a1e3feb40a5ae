"""Edits of a `CollisionChecker`'s world and robot, and the snapshots that make it thread-safe.

`WorldEdits` is a part of `CollisionChecker` (a mixin, like `SegmentChecks`): the padding,
the obstacles (replaced, added, removed, moved), the gripper's finger positions and the
attached objects.

Edits are serialised by a lock and never modify a table in place: they build new tables
and install them (`ObstacleTables.added` / `removed` / `replaced` copy the obstacle arrays
and change one row, so an edit costs tens of microseconds with a thousand obstacles, and
no coal geometry is rebuilt). `snapshot()` returns a view of one state (O(1)); the
checker's public checks run on such a view (`segments.consistent`), and a planner holding
one sees one world for a whole plan while other threads edit.
"""

from __future__ import annotations

import threading
from collections.abc import Sequence
from pathlib import Path

import coal
import numpy as np

from manip.collision import convex_parts
from manip.collision.certify import MotionBoundTables
from manip.collision.results import AttachedObject
from manip.collision.shapes import Obstacle, as_pose
from manip.collision.solids import part_inside
from manip.collision.tables import ObstacleTables, coal_transform, collect_parts, part_tables
from manip.collision.world import WorldConfig
from manip.errors import InvalidInputError, UnknownNameError
from manip.pose import Pose
from manip.validation import as_real_array, non_negative

#: Meshes with more triangles than this are screened by their convex hull before the exact
#: check (a hull test costs about the same whatever the mesh; a mesh test grows with it).
HULL_SCREEN_TRIANGLES = 2000


class WorldEdits:
    """The editing half of `CollisionChecker`.

    Needs, from the class it is mixed into: `_lock`, `_is_snapshot`, `config`, `kinematics`,
    `robot`, `_padding`, `_self_padding`, `_world`, `_attached`, `_obstacle_cache`, `_one_q`.
    """

    # ------------------------------------------------------------------ configuration
    @property
    def padding(self) -> float:
        """Clearance [m] kept from the world."""
        return self._padding

    @padding.setter
    def padding(self, value: float) -> None:
        value = non_negative(value, "padding", "m")
        with self._writing():
            self._padding = value
            self._req_world = _request(value)
            self._update_always_colliding()

    @property
    def self_padding(self) -> float:
        """Clearance [m] kept between links."""
        return self._self_padding

    @self_padding.setter
    def self_padding(self, value: float) -> None:
        value = non_negative(value, "self_padding", "m")
        with self._writing():
            self._self_padding = value
            self._req_self = _request(value)
            if self._proved_clear_pairs() != self._skipped_pairs:
                self._rebuild_parts()

    @property
    def world(self) -> WorldConfig:
        """A copy of the current world (attached objects are not in it)."""
        return self._world.copy()

    @property
    def attached_objects(self) -> dict[str, AttachedObject]:
        """The objects carried by the robot, by name (a copy)."""
        return dict(self._attached)

    def set_world(self, world: WorldConfig | dict | None) -> None:
        """Replace the obstacles (a `WorldConfig` or cuRobo's world dict); attached objects stay."""
        if world is None:
            world = WorldConfig()
        elif isinstance(world, dict):
            world = WorldConfig.from_dict(world)
        elif not isinstance(world, WorldConfig):
            hint = " (a YAML file: WorldConfig.from_yaml(path))" if isinstance(world, (str, Path)) else ""
            raise InvalidInputError(f"world must be a WorldConfig or a dict in cuRobo's world format; got "
                                    f"{type(world).__name__}{hint}")
        with self._writing():
            clash = [n for n in world.names if n in self._attached]
            if clash:
                raise InvalidInputError(f"obstacle name(s) {clash} are used by attached objects; detach them or rename")
            self._world = world.copy()
            self._rebuild_world()

    def add_obstacle(self, obstacle: Obstacle) -> None:
        """Add one obstacle to the world (names must be unique).

        Incremental: the world's tables are extended by one row (no rebuild), so an edit
        costs tens of microseconds even with a thousand obstacles.
        """
        with self._writing():
            if isinstance(obstacle, Obstacle) and obstacle.name in self._attached:
                raise InvalidInputError(f"'{obstacle.name}' is the name of an attached object")
            world = self._world.copy()
            world.add(obstacle)  # validates the shape and the name
            tables = self._world_tables.added(obstacle, self._obstacle_cache)
            static = self._always_colliding + self._fixed_part_collisions(tables, len(tables.obstacles) - 1)
            self._set_world_tables(world, tables, static)

    def remove_obstacle(self, name: str) -> Obstacle:
        """Remove and return the obstacle `name` (UnknownNameError lists the names); incremental."""
        with self._writing():
            self._not_attached(name, "remove_obstacle")
            world = self._world.copy()
            index = world.index(name)
            ob = world.remove(name)
            tables = self._world_tables.removed(index, self._obstacle_cache)
            static = [(g, o - (o > index)) for g, o in self._always_colliding if o != index]
            self._set_world_tables(world, tables, static)
            return ob

    def _not_attached(self, name: str, what: str) -> None:
        """Raise for an edit of the world naming an attached object (it said "not found")."""
        if isinstance(name, str) and name in self._attached and name not in self._world:
            raise InvalidInputError(f"{what}('{name}'): '{name}' is attached to the robot (to "
                                    f"{self._attached[name].link}), not in the world; detach_object(q) it first")

    def update_obstacle_pose(self, name: str, pose: Pose | Sequence[float]) -> None:
        """Move the obstacle `name` to `pose` (base frame): a Pose, [x, y, z, qw, qx, qy, qz],
        or a position [x, y, z] alone, which keeps the obstacle's rotation; incremental."""
        with self._writing():
            self._not_attached(name, "update_obstacle_pose")
            world = self._world.copy()
            index = world.index(name)
            ob = world.get(name)
            new = as_pose(pose, f"update_obstacle_pose('{name}')")
            if not isinstance(pose, Pose) and np.shape(pose) == (3,):  # a position alone: keep the rotation
                new = Pose(new.position, ob.pose.quaternion)
            ob = ob.with_pose(new)
            world.replace(ob)
            tables = self._world_tables.replaced(index, ob, self._obstacle_cache)
            static = [(g, o) for g, o in self._always_colliding if o != index] + self._fixed_part_collisions(tables, index)
            self._set_world_tables(world, tables, static)

    def replace_obstacle(self, obstacle: Obstacle) -> None:
        """Replace the obstacle of the same name by `obstacle` (e.g. an updated occupancy map),
        keeping its place in the world; incremental, and atomic for other threads."""
        with self._writing():
            if not isinstance(obstacle, Obstacle):
                raise InvalidInputError(f"obstacle must be a shape; got {type(obstacle).__name__}")
            world = self._world.copy()
            index = world.index(obstacle.name)
            world.replace(obstacle)
            tables = self._world_tables.replaced(index, obstacle, self._obstacle_cache)
            static = [(g, o) for g, o in self._always_colliding if o != index] + self._fixed_part_collisions(tables, index)
            self._set_world_tables(world, tables, static)

    def set_gripper_positions(self, positions: Sequence[float] | np.ndarray | None) -> None:
        """Finger positions [m] the collision model assumes (None = the planning positions).

        Attached objects keep their pose relative to their link.
        """
        with self._writing():
            self.robot.set_gripper_positions(None if positions is None else as_real_array(positions, "gripper positions"))
            self._rebuild_parts()

    # ------------------------------------------------------------------ threads
    def snapshot(self):  # -> CollisionChecker (this mixin's host class)
        """A read-only view of the checker as it is now (O(1)): later edits of this checker
        do not change it. Every check gives the same answers on the view as on this
        checker before the edits. A snapshot of a snapshot is itself."""
        if self._is_snapshot:
            return self
        with self._lock:
            view = object.__new__(type(self))
            view.__dict__.update(self.__dict__, _is_snapshot=True)
        return view

    def fork(self):  # -> CollisionChecker
        """An independent, editable copy of the checker as it is now (O(1): the tables are
        shared until either side edits, and edits build new tables instead of changing
        them). For planning against a world that differs a little from this one (an object
        attached, removed) without touching this checker."""
        with self._lock:
            copy = object.__new__(type(self))
            copy.__dict__.update(self.__dict__, _is_snapshot=False, _lock=threading.RLock())
            copy.__dict__.pop("_state_of_snapshot", None)
            copy.__dict__.pop("_allowed_world", None)
        return copy

    def allowing(self, pairs):  # -> CollisionChecker
        """A read-only view (a `snapshot`) where the given contacts are allowed.

        Args:
            pairs: (part, obstacle) names: a robot link (all its collision parts) or an attached
                object, and a world obstacle; every check and certificate of the view skips
                these pairs (and only these: every other pair is checked as before), e.g. the
                fingers and the object they close on.

        Raises:
            UnknownNameError: a link, attached object or obstacle that does not exist.
        """
        view = object.__new__(type(self))
        view.__dict__.update(self.snapshot().__dict__)
        view.__dict__.pop("_state_of_snapshot", None)
        parts, obstacles = view.__dict__["_parts"], view.__dict__["_obs"]
        mask = np.zeros((len(parts), len(obstacles)), dtype=bool)
        names = [o.name for o in obstacles]
        for part, obstacle in pairs:
            rows = [g for g, p in enumerate(parts) if p.name == part]
            if not rows:
                known = sorted({p.name for p in parts})
                raise UnknownNameError("link or attached object", part, known)
            if obstacle not in names:
                raise UnknownNameError("obstacle", obstacle, names)
            mask[rows, names.index(obstacle)] = True
        view.__dict__["_allowed_world"] = mask
        return view

    def _writing(self):
        """The lock of an edit (edits of a snapshot are refused)."""
        if self._is_snapshot:
            raise InvalidInputError("a CollisionChecker snapshot is read-only; edit the checker it was taken from")
        return self._lock

    # ------------------------------------------------------------------ internal tables
    def _rebuild_parts(self) -> None:
        """The robot side's tables (`manip.collision.tables`), after a change of parts."""
        self._parts, pairs = collect_parts(self.robot, self.kinematics, self._attached)
        self._skipped_pairs = self._proved_clear_pairs()
        t = part_tables(self._parts, pairs, self._skipped_pairs, self.robot.clearance_maps)
        self._pj, self._fine, self._coarse = t.joint, t.fine, t.coarse
        self._pbc, self._pbr, self._l0_joint, self._pairs, self._bpairs = (
            t.ball_centres, t.ball_radii, t.l0_joint, t.pairs, t.body_pairs)
        self._gR, self._gp = t.gR, t.gp
        # convex hulls of the meshes, screened before the exact check of meshes with many
        # triangles (the hull holds the mesh: a hull kept clear keeps the mesh clear)
        self._geoms = [p.geometry for p in self._parts]
        self._hulls = [p.hull if p.hull is not p.geometry else None for p in self._parts]
        self._screen_hulls = [h if h is not None and getattr(p.geometry, "num_tris", 0) > HULL_SCREEN_TRIANGLES
                              else None for h, p in zip(self._hulls, self._parts)]
        self._bp_world, self._bp_pairs, self._bp_self = t.bp_world, t.bp_pairs, t.bp_self
        self._hull_parts_lazy = []   # `_hull_parts`, built at the screen's first use
        self._motion_bounds = MotionBoundTables(self._parts, t.fine, self.kinematics, t.bp_pairs)
        self._req_self = _request(self._self_padding)
        self._update_always_colliding()

    @property
    def _hull_parts(self) -> tuple:
        """The parts' `gjk` tables of the narrowphase's screen (`collision.hull_screen`,
        `convex_parts.part_tables`), built at its first use for this parts list (the screen
        is off by default: an edit does not build them)."""
        lazy = self._hull_parts_lazy   # one per parts list, shared by its snapshots
        if not lazy:
            lazy.append(convex_parts.part_tables(self._parts))
        return lazy[0]

    @property
    def _hull_okind(self) -> np.ndarray:
        """(O,) the obstacles' `gjk` kinds of the narrowphase's screen (`convex_parts.obstacle_kinds`),
        built at its first use for these obstacle tables (not at each edit)."""
        lazy = self._hull_okind_lazy   # one per world state, shared by its snapshots
        if not lazy:
            lazy.append(convex_parts.obstacle_kinds(self._obs))
        return lazy[0]

    def _proved_clear_pairs(self) -> frozenset[tuple[int, int]]:
        """The robot's self pairs proved to keep more than the self padding at every
        configuration (`manip.collision.self_pairs`): the checks skip them."""
        return frozenset(pair for pair, bound in self.robot.proved_clear.items() if bound > self._self_padding)

    def _rebuild_world(self) -> None:
        """The world side's tables (`manip.collision.tables`), after a change of obstacles."""
        w = ObstacleTables(self._world.obstacles, self._obstacle_cache)
        self._req_world = _request(self._padding)
        self._set_world_tables(self._world, w, None)

    def _set_world_tables(self, world: WorldConfig, w: ObstacleTables, static: list | None) -> None:
        """Install a new world state (under the lock); `static` None = recompute it."""
        self._world = world
        self._world_tables = w
        self._obs, self._ogeom, self._otf, self._bp_obstacles = w.obstacles, w.geometries, w.transforms, w.broadphase
        self._occupancy = w.occupancy_maps
        self._hull_okind_lazy = []   # `_hull_okind`, built at the screen's first use
        if static is None:
            self._update_always_colliding()
        else:
            self._always_colliding = static

    def _fixed_part_collisions(self, tables: ObstacleTables, o: int) -> list[tuple[int, int]]:
        """The (part fixed to the base, obstacle o) pairs of `tables` that collide; none when
        o is below the base (the surface the robot stands on, `ObstacleTables.below_base`)."""
        out = []
        if tables.below_base(o):
            return out
        res = coal.CollisionResult()
        for g in np.nonzero(self._pj == 0)[0]:
            part = self._parts[int(g)]
            res.clear()
            if coal.collide(part.geometry, coal_transform(part.R, part.p), tables.geometries[o], tables.transforms[o],
                            self._req_world, res) or (getattr(tables.obstacles[o], "solid", False) and part_inside(
                                part.geometry, part.R, part.p, tables.obstacles[o], tables.geometries[o])):
                out.append((int(g), o))
        return out

    def _update_always_colliding(self) -> None:
        """Parts fixed to the base (joint 0) vs the world: the same answer for every q, so a
        non-empty `_always_colliding` (pairs (part, obstacle)) means every configuration collides."""
        if not hasattr(self, "_world_tables") or not hasattr(self, "_parts"):
            return
        static = []
        for o in range(len(self._obs)):
            static += self._fixed_part_collisions(self._world_tables, o)
        self._always_colliding = sorted(static)

    # ------------------------------------------------------------------ attached objects
    def attach_object(
        self,
        obstacle: str | Obstacle,
        q: np.ndarray | None = None,
        link: str | None = None,
        pose_in_link: Pose | Sequence[float] | None = None,
        allowed_links: Sequence[str] = (),
    ) -> AttachedObject:
        """Carry an object with a link (a grasp): it leaves the world and moves with the link.

        Args:
            obstacle: the name of an obstacle of the world (removed from it), or a shape.
            q: (dof,) the configuration at the grasp: the object keeps its current pose
                relative to the link at q. Needed unless `pose_in_link` is given.
            link: the carrying link; default the config's `ee_link` (panda_hand).
            pose_in_link: the object's pose in the link frame (overrides q).
            allowed_links: links never checked against the object, in addition to the
                links rigidly attached to the same joint as `link` (hand, fingers, ...).

        Returns:
            The `AttachedObject`. It is checked against the world (with the padding) and
            against the other links (with the self padding).
        """
        with self._writing():
            return self._attach(obstacle, q, link, pose_in_link, allowed_links)

    def _attach(self, obstacle, q, link, pose_in_link, allowed_links) -> AttachedObject:
        kin = self.kinematics
        link = self.config.ee_link if link is None else link
        fid = kin.frame_id(link, "link")
        if isinstance(obstacle, str):
            if obstacle in self._attached:
                raise InvalidInputError(f"'{obstacle}' is already attached (to {self._attached[obstacle].link}); "
                                        "detach_object it first")
            shape = self._world.get(obstacle)
            in_world = True
        elif isinstance(obstacle, Obstacle) and type(obstacle) is not Obstacle:
            shape = obstacle
            in_world = False
            if shape.name in self._world:
                raise InvalidInputError(f"an obstacle named '{shape.name}' is in the world; attach it by name")
        else:
            raise InvalidInputError(f"obstacle must be an obstacle name or a shape; got {type(obstacle).__name__}")
        if shape.name in self._attached:
            raise InvalidInputError(f"'{shape.name}' is already attached")
        if pose_in_link is not None:
            rel = as_pose(pose_in_link, f"attach '{shape.name}'")
        else:
            if q is None:
                raise InvalidInputError("attach_object needs q (the grasp configuration) or pose_in_link")
            q = kin.check_q(q)
            rel = kin.fk(q, link).inverse() @ shape.pose
        joint = kin.model.frames[fid].parentJoint
        rigid = {p.link for p in self.robot.parts if p.joint == joint}
        if isinstance(allowed_links, str) or not all(isinstance(n, str) for n in allowed_links):
            raise InvalidInputError(f"allowed_links must be a list of link names; got {allowed_links!r}")
        unknown = [n for n in allowed_links if n not in self.robot.link_names]
        if unknown:
            raise UnknownNameError("link", unknown[0], self.robot.link_names)
        att = AttachedObject(shape, link, rel, tuple(sorted(rigid | set(allowed_links))))
        if in_world:
            world = self._world.copy()
            world.remove(shape.name)
            self._world = world
            self._rebuild_world()
        self._attached = {**self._attached, shape.name: att}
        self._rebuild_parts()
        return att

    def detach_object(self, q: np.ndarray, name: str | None = None) -> list[Obstacle]:
        """Put attached object(s) back into the world at their pose for configuration q.

        Args:
            q: (dof,) the configuration at release.
            name: the object to detach; None detaches all.

        Returns:
            The obstacles added to the world (base-frame poses at q).
        """
        q = self._one_q(q)
        with self._writing():
            if name is not None and name not in self._attached:
                raise UnknownNameError("attached object", name, self._attached)
            names = [name] if name is not None else list(self._attached)
            attached = dict(self._attached)
            world = self._world.copy()
            out = []
            for nm in names:
                att = attached.pop(nm)
                T = self.kinematics.fk(q, att.link) @ att.pose_in_link
                ob = att.obstacle.with_pose(T)
                world.add(ob)
                out.append(ob)
            self._attached = attached
            self._world = world
            self._rebuild_parts()
            self._rebuild_world()
            return out



def _request(margin: float) -> coal.CollisionRequest:
    """A coal collision request with the security margin `margin` [m] (never modified later)."""
    req = coal.CollisionRequest()
    req.security_margin = margin
    return req
