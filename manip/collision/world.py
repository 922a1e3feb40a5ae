"""`WorldConfig`: the named obstacles the planner avoids, in the robot base frame.

Reads and writes cuRobo's world format::

    {"cuboid":   {name: {"dims": [x, y, z], "pose": [x, y, z, qw, qx, qy, qz]}},
     "sphere":   {name: {"radius": r, "position": [x, y, z]}},
     "cylinder": {name: {"radius": r, "height": h, "pose": [...]}},
     "capsule":  {name: {"radius": r, "height": h, "pose": [...]}}   # or "base"/"tip" points
     "mesh":     {name: {"file_path": path, "pose": [...], "scale": [sx, sy, sz], "solid": false}},
     "occupancy": {name: {"resolution": r, "cells": [[i, j, k], ...],          # manip's: an OccupancyMap
                          "bounds": [[x0, y0, z0, x1, y1, z1], ...],          # (optional: whole cells)
                          "point_start": [0, ...], "points": [[x, y, z], ...]}}}   # (optional: hulls)

A mesh is a surface unless `"solid": true` (a closed mesh as the volume it bounds; see `Mesh`).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from manip import curobo_names
from manip.errors import InvalidInputError, UnknownNameError
from manip.pose import Pose
from manip.collision.occupancy import OccupancyMap
from manip.collision.shapes import SHAPE_TYPES, Capsule, Cuboid, Cylinder, Mesh, Obstacle, Sphere

_FIELDS = {
    "cuboid": ({"dims"}, {"pose"}),
    "sphere": ({"radius"}, {"position", "pose"}),
    "cylinder": ({"radius", "height"}, {"pose"}),
    "capsule": ({"radius"}, {"height", "base", "tip", "pose"}),
    "mesh": (set(), {"file_path", "pose", "scale", "vertices", "faces", "solid"}),
    "occupancy": ({"resolution", "cells"}, {"pose", "bounds", "point_start", "points"}),
}
# Keys of cuRobo's entries that carry no geometry (colours, textures): accepted and ignored.
_IGNORED = {"color", "texture", "tensor_args"}


class WorldConfig:
    """An ordered set of uniquely named obstacles.

    Args:
        obstacles: shapes (`Cuboid`, `Sphere`, `Cylinder`, `Capsule`, `Mesh`) with poses in
            the robot base frame.
        cuboid, sphere, cylinder, capsule, mesh: cuRobo's form, `WorldConfig(cuboid=[...],
            mesh=[...])`: shapes of that kind each (added after `obstacles`, in this order).

    Raises:
        InvalidInputError: two obstacles share a name, an entry is not a shape, or a keyword's
            list holds a shape of another kind.
    """

    def __init__(self, obstacles: Iterable[Obstacle] = (), *, cuboid: Iterable[Cuboid] = (),
                 sphere: Iterable[Sphere] = (), cylinder: Iterable[Cylinder] = (), capsule: Iterable[Capsule] = (),
                 mesh: Iterable[Mesh] = ()):
        self._obstacles: dict[str, Obstacle] = {}
        for ob in obstacles:
            self.add(ob)
        for kind, shapes in (("cuboid", cuboid), ("sphere", sphere), ("cylinder", cylinder), ("capsule", capsule),
                             ("mesh", mesh)):
            for ob in shapes or ():
                if getattr(ob, "kind", None) != kind:
                    raise InvalidInputError(f"WorldConfig({kind}=[...]) holds {kind} shapes only; got {ob!r}")
                self.add(ob)

    # ------------------------------------------------------------------ container
    def add(self, obstacle: Obstacle) -> None:
        """Add a shape; raises InvalidInputError if its name is already used."""
        if not isinstance(obstacle, Obstacle) or type(obstacle) is Obstacle:
            raise InvalidInputError(
                f"an obstacle must be one of {', '.join(t.__name__ for t in SHAPE_TYPES.values())}; got {type(obstacle).__name__}"
            )
        if obstacle.name in self._obstacles:
            raise InvalidInputError(f"an obstacle named '{obstacle.name}' is already in the world; names must be unique")
        self._obstacles[obstacle.name] = obstacle

    def remove(self, name: str) -> Obstacle:
        """Remove and return the obstacle `name`; raises UnknownNameError listing the names."""
        if name not in self._obstacles:
            raise UnknownNameError("obstacle", name, self._obstacles)
        return self._obstacles.pop(name)

    def get(self, name: str) -> Obstacle:
        """The obstacle `name`; raises UnknownNameError listing the names."""
        if name not in self._obstacles:
            raise UnknownNameError("obstacle", name, self._obstacles)
        return self._obstacles[name]

    def replace(self, obstacle: Obstacle) -> None:
        """Replace the obstacle of the same name (e.g. moved), keeping its place in the order."""
        if obstacle.name not in self._obstacles:
            raise UnknownNameError("obstacle", obstacle.name, self._obstacles)
        self._obstacles[obstacle.name] = obstacle

    @property
    def names(self) -> list[str]:
        """Obstacle names in insertion order."""
        return list(self._obstacles)

    @property
    def obstacles(self) -> list[Obstacle]:
        """The obstacles in insertion order (a new list)."""
        return list(self._obstacles.values())

    def copy(self) -> WorldConfig:
        """A shallow copy (shapes are immutable); O(obstacles) without re-validating them."""
        out = WorldConfig.__new__(WorldConfig)
        out.__dict__["_obstacles"] = dict(self._obstacles)
        return out

    def index(self, name: str) -> int:
        """Position of the obstacle `name` in the insertion order; raises UnknownNameError."""
        if name not in self._obstacles:
            raise UnknownNameError("obstacle", name, self._obstacles)
        for i, n in enumerate(self._obstacles):
            if n == name:
                return i
        raise AssertionError("unreachable")  # pragma: no cover

    def __iter__(self) -> Iterator[Obstacle]:
        return iter(list(self._obstacles.values()))

    def __len__(self) -> int:
        return len(self._obstacles)

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's (add_obstacle, ...) say where manip has them
        if name.startswith("_"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.WORLD_CONFIG, name)

    def __contains__(self, name: object) -> bool:
        return name in self._obstacles

    def __repr__(self) -> str:
        kinds: dict[str, int] = {}
        for ob in self._obstacles.values():
            kinds[ob.kind] = kinds.get(ob.kind, 0) + 1
        return f"WorldConfig({', '.join(f'{v} {k}' for k, v in kinds.items()) or 'empty'})"

    # ------------------------------------------------------------------ cuRobo format
    @classmethod
    def from_dict(cls, d: dict[str, Any], base_dir: str | Path | None = None) -> WorldConfig:
        """Read cuRobo's world format (see the module docstring).

        Args:
            d: {kind: {name: entry}} with kind one of cuboid, sphere, cylinder, capsule, mesh.
            base_dir: folder against which relative mesh `file_path`s are resolved.

        Raises:
            InvalidInputError: unknown kind or key, missing key, wrong sizes, NaN, sizes <= 0.
        """
        if d is None:
            return cls()
        if not isinstance(d, dict):
            raise InvalidInputError(f"a world must be a mapping {{kind: {{name: entry}}}}; got {type(d).__name__}")
        world = cls()
        for kind, entries in d.items():
            if kind not in _FIELDS:
                raise InvalidInputError(f"unknown obstacle kind '{kind}'; valid: {', '.join(_FIELDS)}")
            if entries is None:
                continue
            if not isinstance(entries, dict):
                raise InvalidInputError(f"world['{kind}'] must map names to entries; got {type(entries).__name__}")
            for name, entry in entries.items():
                world.add(_from_entry(kind, str(name), entry, base_dir))
        return world

    def to_dict(self) -> dict[str, dict[str, dict]]:
        """cuRobo's world format; `WorldConfig.from_dict(w.to_dict())` gives the same world."""
        out: dict[str, dict[str, dict]] = {}
        for ob in self._obstacles.values():
            out.setdefault(ob.kind, {})[ob.name] = ob.to_dict()
        return out

    @classmethod
    def from_yaml(cls, path: str | Path) -> WorldConfig:
        """Read a YAML file in cuRobo's world format; mesh paths are relative to the file."""
        path = Path(path)
        if not path.is_file():
            raise InvalidInputError(f"world file not found: {path}")
        with open(path) as f:
            d = yaml.safe_load(f)
        return cls.from_dict(d, base_dir=path.parent)

    def to_yaml(self, path: str | Path) -> None:
        """Write the world in cuRobo's format."""
        with open(path, "w") as f:
            yaml.safe_dump(self.to_dict(), f, sort_keys=False)

    @classmethod
    def from_moveit_scene(cls, scene: dict[str, Any]) -> WorldConfig:
        """Read the boxes, spheres and cylinders of a MoveIt PlanningScene (as loaded from YAML).

        MoveIt conventions: orientations are [x, y, z, w]; box dimensions are full edges;
        cylinder dimensions are [height, radius]; sphere dimensions are [radius]. An object
        with several primitives gives obstacles `<id>`, `<id>_1`, ... Poses are taken to be
        in the robot base frame (MotionBenchMaker's scenes are).
        """
        objects = ((scene or {}).get("world") or {}).get("collision_objects") or []
        world = cls()
        for obj in objects:
            oid = str(obj.get("id", f"object{len(world)}"))
            prims = obj.get("primitives") or []
            poses = obj.get("primitive_poses") or []
            if len(prims) != len(poses):
                raise InvalidInputError(f"object '{oid}': {len(prims)} primitives but {len(poses)} primitive_poses")
            for i, (prim, pp) in enumerate(zip(prims, poses)):
                name = oid if i == 0 else f"{oid}_{i}"
                pos = pp.get("position", [0.0, 0.0, 0.0])
                ori = pp.get("orientation", [0.0, 0.0, 0.0, 1.0])
                pose = Pose.from_xyz_xyzw(list(pos) + list(ori))
                dims = prim.get("dimensions", [])
                t = prim.get("type")
                if t == "box":
                    world.add(Cuboid(name, dims, pose))
                elif t == "cylinder":
                    if len(dims) != 2:
                        raise InvalidInputError(f"object '{oid}': cylinder dimensions must be [height, radius]; got {dims}")
                    world.add(Cylinder(name, radius=dims[1], height=dims[0], pose=pose))
                elif t == "sphere":
                    if len(dims) != 1:
                        raise InvalidInputError(f"object '{oid}': sphere dimensions must be [radius]; got {dims}")
                    world.add(Sphere(name, dims[0], pose))
                else:
                    raise InvalidInputError(f"object '{oid}': primitive type {t!r} not supported; valid: box, cylinder, sphere")
        return world


def _from_entry(kind: str, name: str, entry: Any, base_dir: str | Path | None) -> Obstacle:
    if not isinstance(entry, dict):
        raise InvalidInputError(f"{kind} '{name}': entry must be a mapping; got {type(entry).__name__}")
    required, optional = _FIELDS[kind]
    keys = set(entry) - _IGNORED
    unknown = keys - required - optional
    if unknown:
        raise InvalidInputError(
            f"{kind} '{name}': unknown key(s) {sorted(unknown)}; valid: {sorted(required | optional)}"
        )
    missing = required - keys
    if missing:
        raise InvalidInputError(f"{kind} '{name}': missing key(s) {sorted(missing)}")
    pose = entry.get("pose")
    if kind == "cuboid":
        return Cuboid(name, entry["dims"], pose)
    if kind == "sphere":
        if "position" in entry and "pose" in entry:
            raise InvalidInputError(f"sphere '{name}': give 'position' or 'pose', not both")
        return Sphere(name, entry["radius"], entry.get("position", pose))
    if kind == "cylinder":
        return Cylinder(name, entry["radius"], entry["height"], pose)
    if kind == "capsule":
        if "base" in entry or "tip" in entry:
            if "height" in entry or "base" not in entry or "tip" not in entry:
                raise InvalidInputError(f"capsule '{name}': give either 'height' or both 'base' and 'tip'")
            return Capsule.from_base_tip(name, entry["radius"], entry["base"], entry["tip"], pose)
        if "height" not in entry:
            raise InvalidInputError(f"capsule '{name}': give either 'height' or both 'base' and 'tip'")
        return Capsule(name, entry["radius"], entry["height"], pose)
    if kind == "occupancy":
        if pose is not None and not np.allclose(np.asarray(pose, dtype=float), [0, 0, 0, 1, 0, 0, 0]):
            raise InvalidInputError(f"occupancy '{name}': an occupancy map lies in the base frame (pose identity)")
        if ("points" in entry) != ("point_start" in entry):
            raise InvalidInputError(f"occupancy '{name}': give both 'points' and 'point_start', or neither")
        points = (entry["point_start"], entry["points"]) if "points" in entry else None
        return OccupancyMap.from_cells(name, entry["resolution"], entry["cells"], entry.get("bounds"), points)
    # mesh
    fp = entry.get("file_path")
    if fp is not None:
        p = Path(fp)
        if not p.is_absolute() and base_dir is not None:
            p = Path(base_dir) / p
        return Mesh(name, file_path=p, pose=pose, scale=entry.get("scale", 1.0), solid=entry.get("solid", False))
    if "vertices" not in entry or "faces" not in entry:
        raise InvalidInputError(f"mesh '{name}': give 'file_path', or 'vertices' and 'faces'")
    return Mesh(name, pose=pose, scale=entry.get("scale", 1.0),
                vertices=entry["vertices"], faces=entry["faces"], solid=entry.get("solid", False))


__all__ = ["WorldConfig", "Cuboid", "Sphere", "Cylinder", "Capsule", "Mesh", "Obstacle"]
