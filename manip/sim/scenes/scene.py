"""`Scene`: the World's registry of named objects, and the collision-object export for planners."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any, Protocol

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.sim.prims.geometry_prim import GeometryPrim
from manip.sim.objects.ground_plane import GroundPlane
from manip.sim.scenes.aabb import geom_box, shape_box
from manip.sim.scenes.stage import ReferencePrim, SimHandle, SimulationError, get_current_stage
from manip.sim.utils.not_supported import declare as declare_not_supported

logger = logging.getLogger(__name__)

_GEOM_SHAPES = {
    int(mujoco.mjtGeom.mjGEOM_BOX): "cuboid",
    int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere",
    int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder",
    int(mujoco.mjtGeom.mjGEOM_CAPSULE): "capsule",
    int(mujoco.mjtGeom.mjGEOM_ELLIPSOID): "ellipsoid",
    int(mujoco.mjtGeom.mjGEOM_MESH): "mesh",
    int(mujoco.mjtGeom.mjGEOM_PLANE): "plane",
}


@dataclass(frozen=True, eq=False)
class CollisionObject:
    """One collision shape of the World, in the World's current state.

    Attributes:
        name: the scene object's name (shapes created with the object classes), else the
            MuJoCo geom name (`<prim_path>/<geom>`, or `<body>/geom<i>` for unnamed geoms).
        prim_path: prim of the object or of the referenced model the geom belongs to.
        shape: "cuboid", "sphere", "cylinder", "capsule", "cone", "ellipsoid", "mesh" or "plane".
        dimensions: cuboid (3,) full edge lengths [m] (scale included); sphere (1,) radius;
            cylinder/capsule/cone (2,) radius, height (capsule: length of the cylindrical
            part, as USD; a cone's axis is z, base at -height/2); ellipsoid (3,) semi-axes;
            mesh and plane (0,).
        pose: world pose of the shape: for objects made with the shape classes, the
            object's own frame (cuboid/sphere/cylinder/capsule centre, cone mid-height);
            for geoms of referenced models, the MuJoCo geom frame (for meshes, MuJoCo's
            recentred mesh frame, in which `vertices` are given). A plane's normal is its z axis.
        is_robot: the geom belongs to an articulation (a referenced model with joints).
        robot_prim_path: prim path of that articulation, else None.
        body_name: MuJoCo body the geom is attached to.
        is_dynamic: the body moves by physics (free joint or articulated).
        vertices: mesh (V, 3) in the shape frame [m], else None (also set for cones).
        faces: mesh (F, 3) vertex indices of the convex hull MuJoCo collides with, else None.
    """

    name: str
    prim_path: str
    shape: str
    dimensions: np.ndarray
    pose: Pose
    is_robot: bool
    robot_prim_path: str | None
    body_name: str
    is_dynamic: bool
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None

    @property
    def position(self) -> np.ndarray:
        return self.pose.position

    @property
    def orientation(self) -> np.ndarray:
        """(w, x, y, z)."""
        return self.pose.quaternion


class CompiledWorld(Protocol):
    """What the scene reads from its World: the compiled model (None before the first reset)."""

    _sim: SimHandle | None


class Scene:
    """Objects registered with the World by name (Isaac's `Scene`).

    `add` only registers: creating an object already put it on the stage. Registered
    objects get `post_reset()` at every `World.reset()`.

    Args:
        world: the World owning the scene.
    """

    def __init__(self, world: CompiledWorld):
        self._world = world
        self._objects: dict[str, Any] = {}

    @property
    def stage(self):
        """The stage the scene's objects live on."""
        return get_current_stage()

    # ------------------------------------------------------------------ registry
    def add(self, obj: Any) -> Any:
        """Register `obj` under `obj.name` and return it.

        Raises:
            InvalidInputError: the name is taken (the message lists the names in use) or
                the object has no name/prim_path.
        """
        name = getattr(obj, "name", None)
        if not isinstance(name, str) or not hasattr(obj, "prim_path"):
            raise InvalidInputError(f"scene.add expects an object with a name and a prim_path; got {obj!r}")
        if name in self._objects:
            raise InvalidInputError(
                f"an object named {name!r} is already in the scene ({self._objects[name]!r}); names in use: "
                f"{sorted(self._objects)}"
            )
        self._objects[name] = obj
        return obj

    def get_object(self, name: str) -> Any | None:
        """The object registered as `name`, or None (Isaac's behaviour) with a log message."""
        obj = self._objects.get(name)
        if obj is None:
            logger.info("no object named %r in the scene; names: %s", name, sorted(self._objects))
        return obj

    def object_exists(self, name: str) -> bool:
        return name in self._objects

    def get_object_names(self) -> list[str]:
        return list(self._objects)

    def remove_object(self, name: str, registry_only: bool = False) -> None:
        """Unregister `name` and (unless registry_only) delete its prim from the stage; the
        model changes at the next `World.reset()`.

        Raises:
            InvalidInputError: no such object.
        """
        if name not in self._objects:
            raise InvalidInputError(f"no object named {name!r} in the scene; names: {sorted(self._objects)}")
        obj = self._objects.pop(name)
        if not registry_only:
            get_current_stage().remove_prim(obj.prim_path)

    def clear(self, registry_only: bool = False) -> None:
        """Unregister every object (and delete their prims unless registry_only)."""
        for name in list(self._objects):
            self.remove_object(name, registry_only)

    def post_reset(self) -> None:
        """Every object's `post_reset()`, the views' (objects with `prim_paths`) last, as
        Isaac's scene orders them: a view's default state applies over its prims'."""
        objects = list(self._objects.values())
        for obj in sorted(objects, key=lambda o: hasattr(o, "prim_paths")):
            if hasattr(obj, "post_reset"):
                obj.post_reset()

    # ------------------------------------------------------------------ ground
    def add_default_ground_plane(
        self,
        z_position: float = 0.0,
        name: str = "default_ground_plane",
        prim_path: str = "/World/defaultGroundPlane",
        static_friction: float = 0.5,
        dynamic_friction: float = 0.5,
        restitution: float = 0.8,
    ) -> GroundPlane:
        """Add the default ground (a second call returns the existing one)."""
        return self.add_ground_plane(None, z_position, name, prim_path, static_friction, dynamic_friction,
                                     restitution)

    def add_ground_plane(
        self,
        size: float | None = None,
        z_position: float = 0.0,
        name: str = "ground_plane",
        prim_path: str = "/World/groundPlane",
        static_friction: float = 0.5,
        dynamic_friction: float = 0.5,
        restitution: float = 0.8,
        color=None,
    ) -> GroundPlane:
        """Add a ground plane (a second call with the same name returns the existing one)."""
        existing = self._objects.get(name)
        if isinstance(existing, GroundPlane):
            return existing
        return self.add(GroundPlane(prim_path, name, size=size, z_position=z_position, color=color,
                                    static_friction=static_friction, dynamic_friction=dynamic_friction,
                                    restitution=restitution))

    # ------------------------------------------------------------------ geometry queries
    def enable_bounding_boxes_computations(self) -> None:
        """Nothing to enable: `compute_object_AABB` computes bounds on demand (Isaac scripts
        call this first, as Isaac's requires)."""

    def disable_bounding_boxes_computations(self) -> None:
        """Nothing to disable (bounds are computed on demand; `compute_object_AABB` keeps working)."""

    def compute_object_AABB(self, name: str) -> np.ndarray:
        """Axis-aligned bounding box [[min x, y, z], [max x, y, z]] (2, 3) [m] of an object,
        tight (`manip.sim.scenes.aabb`): its geoms in the current state; a plane's box is its
        drawn square at its height. A shape not compiled yet (before the first reset, or added
        since) is bounded from its pose and dimensions, as Isaac bounds USD prims at any time.

        Raises:
            InvalidInputError: no such object. SimulationError: a robot (or other referenced
                model) or view not compiled yet.
        """
        obj = self._objects.get(name)
        if obj is None:
            raise InvalidInputError(f"no object named {name!r} in the scene; names: {sorted(self._objects)}")
        sim = self._world.physics_sim_view
        if isinstance(obj, GeometryPrim) and (sim is None or obj.geom_id < 0):
            if obj.shape_kind in ("cuboid", "sphere", "cylinder", "capsule", "cone"):
                return shape_box(obj.shape_kind, obj.shape_dimensions(), *obj.get_world_pose())
        if sim is None:
            raise SimulationError(f"compute_object_AABB({name!r}): the world is not compiled yet; call world.reset() "
                                  "first (shapes are bounded before; robots once compiled)")
        m = sim.model
        path = getattr(obj, "prim_path", None)
        bodies = [b for b in range(m.nbody) if path is not None and
                  (m.body(b).name == path or m.body(b).name.startswith(path + "/"))]
        if not bodies and getattr(obj, "simulated", False):  # a frame fixed to a robot's link
            p = obj.get_world_pose()[0]
            return np.stack([p, p])
        if not bodies:
            raise SimulationError(f"compute_object_AABB({name!r}): the object was added after the last world.reset() "
                                  "and is not in the compiled world yet; reset first")
        geoms = [g for g in range(m.ngeom) if m.geom_bodyid[g] in bodies]
        if not geoms:  # a bare transform
            p = obj.get_world_pose()[0]
            return np.stack([p, p])
        sim.ensure_kinematics()
        boxes = np.array([geom_box(m, sim.data, g) for g in geoms])
        return np.stack([boxes[:, 0].min(axis=0), boxes[:, 1].max(axis=0)])

    def get_collision_objects(self, include_robots: bool = True) -> list[CollisionObject]:
        """Every colliding shape of the World with its world pose (for planners' world sync).

        Shapes created with the object classes appear once, under their scene name (or
        their prim path if not in the scene); geoms of referenced models appear one per
        geom. Visual-only geoms (no contype/conaffinity) are left out.

        Raises:
            SimulationError: before the first `World.reset()`.
        """
        sim = self._world.physics_sim_view
        if sim is None:
            raise SimulationError("get_collision_objects: the world is not compiled yet; call world.reset() first")
        sim.ensure_kinematics()
        m, d = sim.model, sim.data
        stage = get_current_stage()
        by_geom: dict[int, GeometryPrim] = {}
        names = {id(o): n for n, o in self._objects.items()}
        refs: list[ReferencePrim] = []
        for prim in stage.prims():
            if isinstance(prim, GeometryPrim) and prim.geom_id >= 0:
                by_geom[prim.geom_id] = prim
            elif isinstance(prim, ReferencePrim):
                refs.append(prim)
        out = []
        for g in range(m.ngeom):
            if m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 0:
                continue
            b = int(m.geom_bodyid[g])
            body = m.body(b).name
            pose = Pose(d.geom_xpos[g].copy(), quat.from_matrix(d.geom_xmat[g].reshape(3, 3)))
            dynamic = bool(m.body_dofnum[b] > 0 or m.body_weldid[b] != 0) and m.body_mocapid[b] < 0
            obj = by_geom.get(g)
            if obj is not None:
                # The object's frame is its body frame (MuJoCo recentres meshes, so a cone's
                # geom frame sits at its centroid, not at the centre of its height).
                dims = obj.shape_dimensions()
                pose = Pose(d.xpos[b].copy(), d.xquat[b].copy())
                verts = faces = None
                if obj.shape_kind == "cone":
                    verts, faces = _mesh_arrays(m, int(m.geom_dataid[g]))
                    Rg, Rb = d.geom_xmat[g].reshape(3, 3), d.xmat[b].reshape(3, 3)
                    verts = (verts @ Rg.T + d.geom_xpos[g] - d.xpos[b]) @ Rb
                out.append(CollisionObject(names.get(id(obj), obj.prim_path), obj.prim_path, obj.shape_kind, dims, pose,
                                           False, None, body, dynamic, verts, faces))
                continue
            ref = next((r for r in refs if body.startswith(r.prefix)), None)
            is_robot = ref is not None and ref.core is not None and ref.core.n > 0
            if is_robot and not include_robots:
                continue
            shape = _GEOM_SHAPES.get(int(m.geom_type[g]), "mesh")
            s = m.geom_size[g]
            dims = {
                "cuboid": 2 * s[:3], "sphere": s[:1], "cylinder": np.array([s[0], 2 * s[1]]),
                "capsule": np.array([s[0], 2 * s[1]]), "ellipsoid": s[:3].copy(),
            }.get(shape, np.zeros(0))
            verts = faces = None
            if shape == "mesh":
                verts, faces = _mesh_arrays(m, int(m.geom_dataid[g]))
            gname = m.geom(g).name or f"{body}/geom{g - m.body_geomadr[b]}"
            out.append(CollisionObject(gname, ref.prim_path if ref else body, shape, np.array(dims, dtype=float), pose,
                                       is_robot, ref.prim_path if is_robot else None, body, dynamic, verts, faces))
        return out


def _mesh_arrays(m: mujoco.MjModel, mesh_id: int) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) and convex-hull faces (F, 3) of a compiled mesh (its hull when MuJoCo
    computed one, else the mesh faces)."""
    va, vn = m.mesh_vertadr[mesh_id], m.mesh_vertnum[mesh_id]
    verts = m.mesh_vert[va:va + vn].astype(float).copy()
    ga = m.mesh_graphadr[mesh_id]
    if ga >= 0:
        g = m.mesh_graph[ga:]
        numvert, numface = int(g[0]), int(g[1])
        # Layout (MuJoCo docs, mjModel.mesh_graph): numvert, numface, vert_edgeadr[numvert],
        # vert_globalid[numvert], edge_localid[numvert+3*numface], face_globalid[3*numface].
        start = 2 + 2 * numvert + numvert + 3 * numface
        faces = np.asarray(g[start:start + 3 * numface], dtype=int).reshape(-1, 3)
        return verts, faces
    fa, fn = m.mesh_faceadr[mesh_id], m.mesh_facenum[mesh_id]
    return verts, m.mesh_face[fa:fa + fn].astype(int).copy()


declare_not_supported(Scene)
