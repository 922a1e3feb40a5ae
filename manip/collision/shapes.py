"""Obstacle shapes of the planner's world: cuboids, spheres, cylinders, capsules, meshes.

Every shape is a frozen dataclass with a `name` and a `pose` (a `Pose` of the shape's
local frame in the robot base frame). Sizes are in metres. The local frames follow coal's
(and cuRobo's) conventions: a cuboid is centred on its frame with edges along its axes; a
cylinder and a capsule are centred on their frame with their axis along local z.

A pose may be given as a `Pose`, as a position [x, y, z] (identity rotation) or as
cuRobo's 7-vector [x, y, z, qw, qx, qy, qz]. cuRobo's keyword forms work as written for it:
`Cuboid(name=..., pose=..., dims=..., color=...)` (`color`, RGB or RGBA, is for a viewer and
not used here), `Sphere(..., position=...)`, `Capsule(..., base=..., tip=...)`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar, Sequence

import numpy as np

from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.validation import as_real_array, non_negative, positive


def as_pose(value: Pose | Sequence[float] | np.ndarray | None, what: str) -> Pose:
    """A `Pose` from a Pose, a position (3,) or a cuRobo pose [x, y, z, qw, qx, qy, qz] (7,).

    Raises:
        InvalidInputError: any other shape, or non-finite values.
    """
    if value is None:
        return Pose(np.zeros(3))
    if isinstance(value, Pose):
        if value.is_batch:
            raise InvalidInputError(f"{what}: expected a single pose, got a batch of {len(value)}")
        return value
    try:
        v = as_real_array(value, f"{what}: pose")
    except InvalidInputError as exc:
        raise InvalidInputError(f"{what}: a pose must be a Pose, [x, y, z] or [x, y, z, qw, qx, qy, qz]; got {value!r}") from exc
    if v.shape == (3,):
        if not np.all(np.isfinite(v)):
            raise InvalidInputError(f"{what}: pose has non-finite values: {v.tolist()}")
        return Pose(v)
    if v.shape == (7,):
        if not np.all(np.isfinite(v)):
            raise InvalidInputError(f"{what}: pose has non-finite values: {v.tolist()}")
        return Pose.from_xyz_wxyz(v)
    raise InvalidInputError(f"{what}: a pose must be a Pose, [x, y, z] or [x, y, z, qw, qx, qy, qz]; got shape {v.shape}")


def _check_color(color: object, what: str) -> None:
    """cuRobo's `color` (for its viewer; not used here): None or 3-4 finite numbers."""
    if color is None:
        return
    try:
        c = as_real_array(color, f"{what}: color")
    except InvalidInputError:
        c = np.zeros(0)
    if c.shape not in ((3,), (4,)) or not np.all(np.isfinite(c)):
        raise InvalidInputError(f"{what}: color must be None or [r, g, b] / [r, g, b, a] numbers; got {color!r}")


def _curobo_order(value: object, kind: str, sizes: tuple[str, ...]) -> str:
    """The hint for a pose given where manip takes a size: cuRobo's shapes take (name, pose, ...)
    positionally, manip's (name, sizes..., pose) ("" when `value` is not 3 or 7 numbers)."""
    if np.ndim(value) == 1 and np.size(value) in (3, 7):
        return (f" (a pose? manip's order is {kind}(name, {', '.join(sizes)}, pose), cuRobo's is (name, pose, ...): "
                f"pass them by keyword, pose=..., {'=..., '.join(sizes)}=...)")
    return ""


def _radius(radius: object, name: str, kind: str, sizes: tuple[str, ...]) -> float:
    try:
        return positive(radius, f"{kind.lower()} '{name}': radius", "m")
    except InvalidInputError as exc:
        raise InvalidInputError(f"{exc}{_curobo_order(radius, kind, sizes)}") from None


def _check_name(name: object, kind: str) -> str:
    if not isinstance(name, str) or not name:
        raise InvalidInputError(f"{kind}: name must be a non-empty string; got {name!r}")
    return name


@dataclass(frozen=True, eq=False)
class Obstacle:
    """Base class of the world's shapes (do not instantiate)."""

    kind: ClassVar[str] = ""

    name: str
    pose: Pose

    def with_pose(self, pose: Pose | Sequence[float]) -> Obstacle:
        """A copy of this shape at another pose (base frame)."""
        return dataclasses.replace(self, pose=as_pose(pose, f"{self.kind} '{self.name}'"))

    def with_name(self, name: str) -> Obstacle:
        """A copy of this shape with another name."""
        return dataclasses.replace(self, name=name)

    def local_aabb(self) -> tuple[np.ndarray, np.ndarray]:
        """(centre (3,), half extents (3,)) of the shape's bounding box in its own frame [m]."""
        raise NotImplementedError

    def to_dict(self) -> dict:
        """This shape's entry in cuRobo's world format (without the name)."""
        raise NotImplementedError

    def _pose_list(self) -> list[float]:
        return [float(x) for x in self.pose.to_xyz_wxyz()]


@dataclass(frozen=True, eq=False)
class Cuboid(Obstacle):
    """A box.

    Args:
        name: unique name in the world.
        dims: (3,) full edge lengths along the local x, y, z axes [m].
        pose: the box centre's pose in the base frame.
        color: cuRobo's viewer colour (not used).
    """

    kind: ClassVar[str] = "cuboid"

    dims: np.ndarray = field(default=None)  # type: ignore[assignment]

    def __init__(self, name: str, dims: Sequence[float] | np.ndarray, pose: Pose | Sequence[float] | None = None, *,
                 color: Sequence[float] | None = None):
        object.__setattr__(self, "name", _check_name(name, "cuboid"))
        _check_color(color, f"cuboid '{name}'")
        try:
            d = as_real_array(dims, f"cuboid '{name}': dims") if dims is not None else np.zeros(0)
        except InvalidInputError:
            d = np.zeros(0)
        if d.shape != (3,) or not np.all(np.isfinite(d)) or np.any(d <= 0):
            raise InvalidInputError(f"cuboid '{name}': dims must be 3 positive full edge lengths [x, y, z] in m; got {dims!r}"
                                    + (_curobo_order(dims, "Cuboid", ("dims",)) if d.shape == (7,) else ""))
        d.setflags(write=False)
        object.__setattr__(self, "dims", d)
        object.__setattr__(self, "pose", as_pose(pose, f"cuboid '{name}'"))

    def local_aabb(self) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(3), self.dims / 2.0

    def to_dict(self) -> dict:
        return {"dims": [float(x) for x in self.dims], "pose": self._pose_list()}


@dataclass(frozen=True, eq=False)
class Sphere(Obstacle):
    """A ball.

    Args:
        name: unique name in the world.
        radius: [m] > 0.
        pose: the centre as a Pose or a position [x, y, z] in the base frame.
        position: cuRobo's name for the centre [x, y, z] (instead of `pose`).
        color: cuRobo's viewer colour (not used).
    """

    kind: ClassVar[str] = "sphere"

    radius: float = 0.0

    def __init__(self, name: str, radius: float, pose: Pose | Sequence[float] | None = None, *,
                 position: Sequence[float] | None = None, color: Sequence[float] | None = None):
        object.__setattr__(self, "name", _check_name(name, "sphere"))
        object.__setattr__(self, "radius", _radius(radius, name, "Sphere", ("radius",)))
        _check_color(color, f"sphere '{name}'")
        if position is not None:
            if pose is not None:
                raise InvalidInputError(f"sphere '{name}': give its centre as position or as pose, not both")
            pose = as_real_array(position, f"sphere '{name}': position")
            if pose.shape != (3,):
                raise InvalidInputError(f"sphere '{name}': position must be [x, y, z]; got {position!r}")
        object.__setattr__(self, "pose", as_pose(pose, f"sphere '{name}'"))

    @property
    def position(self) -> np.ndarray:
        """(3,) centre in the base frame [m]."""
        return self.pose.position

    def local_aabb(self) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(3), np.full(3, self.radius)

    def to_dict(self) -> dict:
        return {"radius": self.radius, "position": [float(x) for x in self.pose.position]}


@dataclass(frozen=True, eq=False)
class Cylinder(Obstacle):
    """A solid cylinder with its axis along local z, centred on its frame.

    Args:
        name: unique name in the world.
        radius: [m] > 0.
        height: full length along the axis [m] > 0.
        pose: the centre's pose in the base frame.
        color: cuRobo's viewer colour (not used).
    """

    kind: ClassVar[str] = "cylinder"

    radius: float = 0.0
    height: float = 0.0

    def __init__(self, name: str, radius: float, height: float, pose: Pose | Sequence[float] | None = None, *,
                 color: Sequence[float] | None = None):
        object.__setattr__(self, "name", _check_name(name, "cylinder"))
        _check_color(color, f"cylinder '{name}'")
        object.__setattr__(self, "radius", _radius(radius, name, "Cylinder", ("radius", "height")))
        object.__setattr__(self, "height", positive(height, f"cylinder '{name}': height", "m"))
        object.__setattr__(self, "pose", as_pose(pose, f"cylinder '{name}'"))

    def local_aabb(self) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(3), np.array([self.radius, self.radius, self.height / 2.0])

    def to_dict(self) -> dict:
        return {"radius": self.radius, "height": self.height, "pose": self._pose_list()}


@dataclass(frozen=True, eq=False)
class Capsule(Obstacle):
    """A capsule (a segment swept by a ball) with its axis along local z, centred on its frame.

    Args:
        name: unique name in the world.
        radius: [m] > 0.
        height: length of the segment between the two sphere centres [m] >= 0 (the total
            length is `height + 2 * radius`; coal's convention).
        pose: the segment midpoint's pose in the base frame.
        base, tip: cuRobo's form, instead of `height`: the two sphere centres (3,) [m] in the
            frame `pose` (as `Capsule.from_base_tip`).
        color: cuRobo's viewer colour (not used).
    """

    kind: ClassVar[str] = "capsule"

    radius: float = 0.0
    height: float = 0.0

    def __init__(self, name: str, radius: float, height: float | None = None, pose: Pose | Sequence[float] | None = None,
                 *, base: Sequence[float] | None = None, tip: Sequence[float] | None = None,
                 color: Sequence[float] | None = None):
        object.__setattr__(self, "name", _check_name(name, "capsule"))
        _check_color(color, f"capsule '{name}'")
        if base is not None or tip is not None or height is None:
            if height is not None or base is None or tip is None:
                raise InvalidInputError(f"capsule '{name}': give either height (and pose) or both base and tip points")
            height, pose = _base_tip(name, base, tip, pose)
        object.__setattr__(self, "radius", _radius(radius, name, "Capsule", ("radius", "height")))
        object.__setattr__(self, "height", non_negative(height, f"capsule '{name}': height (segment length)", "m"))
        object.__setattr__(self, "pose", as_pose(pose, f"capsule '{name}'"))

    @classmethod
    def from_base_tip(
        cls,
        name: str,
        radius: float,
        base: Sequence[float],
        tip: Sequence[float],
        pose: Pose | Sequence[float] | None = None,
    ) -> Capsule:
        """cuRobo's capsule: sphere centres `base` and `tip` (3,) given in the frame `pose`."""
        return cls(name, radius, pose=pose, base=base, tip=tip)

    def local_aabb(self) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(3), np.array([self.radius, self.radius, self.height / 2.0 + self.radius])

    def to_dict(self) -> dict:
        return {"radius": self.radius, "height": self.height, "pose": self._pose_list()}


def _base_tip(name: str, base, tip, pose) -> tuple[float, Pose]:
    """(segment length [m], midpoint pose) of a capsule given by its sphere centres `base` and
    `tip` (3,) in the frame `pose`."""
    a = as_real_array(base, f"capsule '{name}': base")
    b = as_real_array(tip, f"capsule '{name}': tip")
    if a.shape != (3,) or b.shape != (3,) or not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise InvalidInputError(f"capsule '{name}': base and tip must be finite points [x, y, z]; got {base!r}, {tip!r}")
    frame = as_pose(pose, f"capsule '{name}'")
    axis = b - a
    length = float(np.linalg.norm(axis))
    if length < 1e-12:
        q = np.array([1.0, 0.0, 0.0, 0.0])
    else:
        z = np.array([0.0, 0.0, 1.0])
        u = axis / length
        c = float(np.dot(z, u))
        if c < -1.0 + 1e-12:
            q = np.array([0.0, 1.0, 0.0, 0.0])
        else:
            q = np.concatenate([[1.0 + c], np.cross(z, u)])  # half-way quaternion z -> u
            q = q / np.linalg.norm(q)
    return length, frame @ Pose((a + b) / 2.0, q)


@dataclass(frozen=True, eq=False)
class Mesh(Obstacle):
    """A triangle mesh: a surface (coal checks its triangles), or with `solid=True` the volume
    a closed mesh bounds.

    As a surface, a robot part that touches no triangle is free, even inside a closed mesh
    (a robot inside a closed mesh box plans as free, where a `Cuboid` of that volume
    collides). With `solid=True` the mesh must be closed (every edge shared by exactly two
    consistently oriented triangles; checked here) and a part inside it collides, in every
    check of the planner and in its continuous certificate (`manip.collision.solids`).

    Cost: coal's bounding-volume tree takes about 5 us and 540 bytes per triangle when the
    mesh is added to a world (1e6 triangles: about 5 s and 540 MB, BENCHMARKS.md "Mesh
    obstacles"); moving it (`update_obstacle_pose`) reuses the tree. `decimated(cell)`
    offers a coarser solid that holds the mesh.

    Args:
        name: unique name in the world.
        file_path: an STL/OBJ/DAE/PLY file (binary STL read directly, others with coal's
            mesh loader), or None when `vertices` and `faces` are given.
        pose: the mesh frame's pose in the base frame.
        scale: (3,) scale applied to the file's coordinates (e.g. 0.001 for millimetres).
        vertices: (V, 3) vertex positions [m] in the mesh frame (before `scale`).
        faces: (F, 3) vertex indices of the triangles.
        solid: True: the closed mesh is a solid (InvalidInputError if it is not closed);
            False (default): a surface.
        color: cuRobo's viewer colour (not used).
    """

    kind: ClassVar[str] = "mesh"

    file_path: str | None = None
    scale: np.ndarray = field(default=None)  # type: ignore[assignment]
    vertices: np.ndarray = field(default=None, repr=False)  # type: ignore[assignment]
    faces: np.ndarray = field(default=None, repr=False)  # type: ignore[assignment]
    solid: bool = False

    def __init__(
        self,
        name: str,
        file_path: str | Path | None = None,
        pose: Pose | Sequence[float] | None = None,
        scale: float | Sequence[float] = 1.0,
        vertices: np.ndarray | None = None,
        faces: np.ndarray | None = None,
        solid: bool = False,
        *,
        color: Sequence[float] | None = None,
    ):
        object.__setattr__(self, "name", _check_name(name, "mesh"))
        _check_color(color, f"mesh '{name}'")
        if not isinstance(solid, (bool, np.bool_)):
            raise InvalidInputError(f"mesh '{name}': solid must be True or False; got {solid!r}")
        object.__setattr__(self, "pose", as_pose(pose, f"mesh '{name}'"))
        try:
            s = np.broadcast_to(as_real_array(scale, f"mesh '{name}': scale"), (3,)).copy()
        except (InvalidInputError, ValueError):
            s = None
        if s is None or not np.all(np.isfinite(s)) or np.any(s <= 0):
            raise InvalidInputError(f"mesh '{name}': scale must be a positive number or 3 positive numbers; got {scale!r}")
        s.setflags(write=False)
        object.__setattr__(self, "scale", s)
        if file_path is not None:
            path = Path(file_path)
            if not path.is_file():
                raise InvalidInputError(f"mesh '{name}': file_path not found: {path}")
            V, F = _load_mesh_file(path, name)
            object.__setattr__(self, "file_path", str(path))
        else:
            if vertices is None or faces is None:
                raise InvalidInputError(f"mesh '{name}': give a file_path, or both vertices (V, 3) and faces (F, 3)")
            V = as_real_array(vertices, f"mesh '{name}': vertices")
            F = _face_indices(faces, name)
            object.__setattr__(self, "file_path", None)
        if V.ndim != 2 or V.shape[1] != 3 or V.shape[0] < 3 or not np.all(np.isfinite(V)):
            raise InvalidInputError(f"mesh '{name}': vertices must be a finite (V, 3) array with V >= 3; got shape {V.shape}")
        if F.ndim != 2 or F.shape[1] != 3 or F.shape[0] < 1:
            raise InvalidInputError(f"mesh '{name}': faces must be an integer (F, 3) array of vertex indices; got shape {F.shape}")
        if F.min() < 0 or F.max() >= V.shape[0]:
            raise InvalidInputError(f"mesh '{name}': face indices must lie in [0, {V.shape[0] - 1}]")
        V = V.copy()
        F = F.astype(np.int64)
        V.setflags(write=False)
        F.setflags(write=False)
        object.__setattr__(self, "vertices", V)
        object.__setattr__(self, "faces", F)
        object.__setattr__(self, "solid", bool(solid))
        # derived data shared by the copies at other poses (`with_pose`): coal's tree, the box
        shared: dict = {}
        if solid:
            from manip.collision.solids import solid_data, weld

            shared["solid"] = solid_data(*weld(V * self.scale, F), name)
        object.__setattr__(self, "_shared", shared)

    def _sharing_copy(self) -> Mesh:
        """A shallow copy holding the same derived data (`copy.copy` would drop coal's tree)."""
        out = object.__new__(Mesh)
        out.__dict__.update(self.__dict__)
        return out

    def __getstate__(self) -> dict:
        """Pickled without coal's tree (rebuilt where it is needed)."""
        state = dict(self.__dict__)
        state["_shared"] = {k: v for k, v in self._shared.items() if k == "solid"}
        return state

    def with_pose(self, pose: Pose | Sequence[float]) -> Mesh:
        """A copy of this mesh at another pose (base frame), sharing its data (no reload)."""
        out = self._sharing_copy()
        object.__setattr__(out, "pose", as_pose(pose, f"mesh '{self.name}'"))
        return out

    def with_name(self, name: str) -> Mesh:
        """A copy of this mesh with another name, sharing its data."""
        out = self._sharing_copy()
        object.__setattr__(out, "name", _check_name(name, "mesh"))
        return out

    def decimated(self, cell: float) -> Mesh:
        """A coarser solid mesh that holds this one: the surface of the grid cells of edge
        `cell` [m] its triangles touch, with what they enclose (`manip.collision.voxel_solid`).

        It holds every point of this mesh (and of its volume when closed) and lies within
        `cell * sqrt(3)` of it, so it is never smaller: a surface becomes a slab about one to
        two cells thick. A 1e6-triangle scan decimated at 1-2 cm keeps tens of thousands of
        triangles (BENCHMARKS.md "Mesh obstacles").

        Returns:
            A `Mesh(solid=True)` of the same name and pose (vertices scaled, scale 1).

        Raises:
            InvalidInputError: a cell that is not positive, or so small the grid is too large.
        """
        from manip.collision.voxel_solid import voxel_solid

        cell = positive(cell, f"mesh '{self.name}': decimated cell", "m")
        V, F = voxel_solid(self.scaled_vertices, self.faces, cell, f"mesh '{self.name}'")
        return Mesh(self.name, pose=self.pose, vertices=V, faces=F, solid=True)

    @property
    def solid_data(self):
        """The `manip.collision.solids.SolidData` of a solid mesh (None for a surface)."""
        return self._shared.get("solid")

    @property
    def scaled_vertices(self) -> np.ndarray:
        """(V, 3) vertices in the mesh frame after scaling [m]."""
        return self.vertices * self.scale

    def local_aabb(self) -> tuple[np.ndarray, np.ndarray]:
        box = self._shared.get("aabb")
        if box is None:
            V = self.scaled_vertices
            lo, hi = V.min(axis=0), V.max(axis=0)
            box = self._shared["aabb"] = ((lo + hi) / 2.0, (hi - lo) / 2.0)
        return box[0].copy(), box[1].copy()

    def to_dict(self) -> dict:
        d: dict = {"pose": self._pose_list()}
        if self.file_path is not None:
            d["file_path"] = self.file_path
        else:
            d["vertices"] = self.vertices.tolist()
            d["faces"] = self.faces.tolist()
        if not np.allclose(self.scale, 1.0):
            d["scale"] = [float(x) for x in self.scale]
        if self.solid:
            d["solid"] = True
        return d


def _face_indices(faces, name: str) -> np.ndarray:
    """Face vertex indices as int64; integral floats (3.0) are accepted, fractional ones (0.5),
    booleans and anything non-numeric raise (never truncated)."""
    if faces is None:
        raise InvalidInputError(f"mesh '{name}': faces must be an integer (F, 3) array of vertex indices; got None")
    try:
        F = np.asarray(faces)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"mesh '{name}': faces must be an integer (F, 3) array of vertex indices") from exc
    if F.dtype.kind in "iu":
        return F.astype(np.int64)
    if F.dtype.kind == "f" and np.all(np.isfinite(F)) and np.all(F == np.round(F)):
        return F.astype(np.int64)
    raise InvalidInputError(
        f"mesh '{name}': faces must be integer vertex indices (F, 3); got {F.dtype.name} values such as "
        f"{F.ravel()[:6].tolist()}"
    )


def _read_binary_stl(path: Path) -> tuple[np.ndarray, np.ndarray] | None:
    """(vertices (V, 3), faces (F, 3)) of a binary STL file, equal vertices merged; None when
    the file is not a binary STL (an 80-byte header, a count, 50 bytes per triangle)."""
    size = path.stat().st_size
    with open(path, "rb") as f:
        head = f.read(84)
        if len(head) < 84:
            return None
        n = int(np.frombuffer(head[80:84], dtype="<u4")[0])
        if size != 84 + 50 * n or n == 0:
            return None
        rec = np.fromfile(f, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), count=n)
    from manip.collision.solids import weld

    return weld(rec["v"].reshape(-1, 3).astype(float), np.arange(3 * n, dtype=np.int64).reshape(-1, 3))


def _load_mesh_file(path: Path, name: str) -> tuple[np.ndarray, np.ndarray]:
    import coal

    from manip.collision.solids import mesh_arrays

    if path.suffix.lower() == ".stl":
        VF = _read_binary_stl(path)   # 1e6 triangles in about 1 s (coal's loader: 14 s)
        if VF is not None:
            return VF

    try:
        bvh = coal.MeshLoader().load(str(path), np.ones(3))
    except Exception as exc:  # coal raises plain RuntimeErrors for unreadable files
        raise InvalidInputError(f"mesh '{name}': could not read {path} ({exc}); coal reads STL, OBJ, DAE, PLY") from exc
    return mesh_arrays(bvh)


SHAPE_TYPES: dict[str, type[Obstacle]] = {
    "cuboid": Cuboid,
    "sphere": Sphere,
    "cylinder": Cylinder,
    "capsule": Capsule,
    "mesh": Mesh,
}


def coal_geometry(shape: Obstacle):
    """A new coal collision geometry of `shape` in its local frame (a shape with its own
    `coal_geometry()`, such as an `OccupancyMap`, builds it itself)."""
    import coal

    own = getattr(shape, "coal_geometry", None)
    if own is not None:
        return own()

    if isinstance(shape, Cuboid):
        return coal.Box(*[float(x) for x in shape.dims])
    if isinstance(shape, Sphere):
        return coal.Sphere(shape.radius)
    if isinstance(shape, Cylinder):
        return coal.Cylinder(shape.radius, shape.height)
    if isinstance(shape, Capsule):
        return coal.Capsule(shape.radius, shape.height)
    if isinstance(shape, Mesh):
        bvh = shape._shared.get("bvh")   # the same mesh at another pose: the same tree (its frame's)
        if bvh is None:
            bvh = coal.BVHModelOBBRSS()
            bvh.beginModel(shape.faces.shape[0], shape.vertices.shape[0])
            bvh.addVertices(np.ascontiguousarray(shape.scaled_vertices, dtype=float))
            bvh.addTriangles(np.ascontiguousarray(shape.faces, dtype=np.int64))
            bvh.endModel()
            shape._shared["bvh"] = bvh
        return bvh
    raise InvalidInputError(f"unsupported shape type {type(shape).__name__}; valid: {', '.join(SHAPE_TYPES)}")
