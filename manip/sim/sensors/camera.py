"""`Camera`: Isaac Sim's camera sensor (`omni.isaac.sensor.Camera`) on MuJoCo's offscreen renderer.

A pinhole camera placed in the World: RGBA images, depth (distance to the image plane [m],
noise-free, inf where no surface is hit within the clipping range), the point cloud in the
world frame and the intrinsics, rendered on demand from the simulation's current state
(EGL or OSMesa, chosen as recording chooses, `manip.sim.core.gl_backend`).

Camera axes (Isaac's three conventions, `camera_axes=`):

- "world" (the default of `position` / `orientation` and of the pose calls): +X forward,
  +Y left, +Z up;
- "ros": +Z forward, +X right, +Y down (OpenCV's, the convention of `get_intrinsics_matrix`);
- "usd": -Z forward, +X right, +Y up (OpenGL's, and MuJoCo's camera frame).

The lens: Isaac's units and defaults (a new USD camera: focal length 5.0 and horizontal
aperture 2.0955 in Isaac's tenths of the stage unit, so a 23.7 deg horizontal field of
view), square pixels (the vertical aperture follows the resolution, as in Isaac).
`get_intrinsics_matrix()` gives fx = fy = W * focal_length / horizontal_aperture and the
principal point at the image centre in OpenCV's pixel convention (pixel (u, v) = (column,
row) at the pixel's centre: cx = (W - 1) / 2, cy = (H - 1) / 2; Isaac's formula writes W / 2,
half a pixel off). The clipping range defaults to (0.01, 1e4) m (USD's default near plane
of 1 m would hide a tabletop).
"""

from __future__ import annotations

import logging
import math

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.sim.prims.xform_prim import XFormPrim
from manip.sim.scenes.stage import SimulationError
from manip.sim.sensors import annotators, segmentation
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.validation import positive

logger = logging.getLogger(__name__)

#: Rotations from each camera convention's axes to USD's (MuJoCo's) camera axes: R_world_usd =
#: R_world_axes @ _TO_USD[axes] (Isaac's U_W_TRANSFORM / U_R_TRANSFORM, transposed as rotations).
_TO_USD = {
    "usd": np.eye(3),
    "world": np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
    "ros": np.diag([1.0, -1.0, -1.0]),
}
#: Isaac's defaults of a new camera prim (tenths of the stage unit, as Isaac reports them).
DEFAULT_FOCAL_LENGTH = 5.0
DEFAULT_HORIZONTAL_APERTURE = 2.0955
DEFAULT_CLIPPING_RANGE = (0.01, 1.0e4)
#: Largest image the World's offscreen buffer holds [px] (`manip.sim.scenes.compiler`).
MAX_RESOLUTION = (1920, 1080)


def _axes(camera_axes: str) -> np.ndarray:
    if camera_axes not in _TO_USD:
        raise InvalidInputError(f"camera_axes must be one of {', '.join(_TO_USD)}; got {camera_axes!r}")
    return _TO_USD[camera_axes]


def _resolution(value) -> tuple[int, int]:
    try:
        w, h = value
        ok = all(isinstance(x, (int, np.integer)) and not isinstance(x, bool) for x in (w, h))
    except (TypeError, ValueError):
        ok = False
    if not ok or not (0 < w <= MAX_RESOLUTION[0] and 0 < h <= MAX_RESOLUTION[1]):
        raise InvalidInputError(f"resolution must be (width, height) integers within 1..{MAX_RESOLUTION[0]} x "
                                f"1..{MAX_RESOLUTION[1]} px; got {value!r}")
    return int(w), int(h)


class Camera(XFormPrim):
    """A pinhole camera of the World (Isaac's `Camera`), rendered by MuJoCo.

    Args:
        prim_path: where the camera lives, e.g. "/World/camera".
        name: unique name in the scene (default "camera").
        position: (3,) world position [m].
        orientation: (4,) (w, x, y, z) of the camera in the world, in the "world" camera
            axes (+X forward, +Z up): the identity looks along the world's +X.
        resolution: (width, height) [px], at most 1920 x 1080.
        frequency: frames per second Isaac would update the data at; kept for scripts
            (`get_frequency`): here every getter renders the current state.
        dt: 1 / frequency (give one of them).
        translation: the same as `position` (no parent transform), except for a camera
            mounted on a robot's link (below): there, its position in the link's frame.

    A camera whose prim path lies inside a referenced robot ("/World/Franka/panda_hand/wrist_cam")
    is fixed to the nearest link above it (panda_hand) and moves with it, as in Isaac:
    `translation` / `orientation` (with translation) are its pose in the link's frame
    (`get_local_pose` / `set_local_pose`), `position` / `orientation` (without translation)
    its world pose when the robot stands at its authored pose, kept fixed to the link.
    """

    _default_name = "camera"
    _wraps_existing = False

    def __init__(self, prim_path: str, name: str | None = None, frequency: float | None = None,
                 dt: float | None = None, resolution=(640, 480), position=None, orientation=None,
                 translation=None, render_product_path: str | None = None):
        if frequency is not None and dt is not None:
            raise InvalidInputError("give frequency or dt, not both")
        self._resolution = _resolution((128, 128) if resolution is None else resolution)
        self._frequency = -1.0
        if dt is not None:
            frequency = 1.0 / positive(dt, "dt", "s")
        if frequency is not None:
            self.set_frequency(frequency)
        self._focal_length = DEFAULT_FOCAL_LENGTH
        self._horizontal_aperture = DEFAULT_HORIZONTAL_APERTURE
        self._clipping = DEFAULT_CLIPPING_RANGE
        self._lens = {"focus_distance": 400.0, "f_stop": 0.0, "stereo_role": "mono"}  # kept, not rendered
        self._renderers: dict[str, mujoco.Renderer] = {}   # by mode: "rgb", "depth", "segmentation"
        self._annotators: set[str] = set()   # the optional frame entries asked for ("normals", "motion_vectors")
        self._segmentation_types: list[str] = ["class"]   # semantic_segmentation's semanticTypes
        self._paused_frame: dict | None = None
        self._renderer_model = None
        self._frame: dict[str, int] = {"rendering_frame": 0}
        R_usd = self._to_usd(orientation, "world") if orientation is not None else _TO_USD["world"]
        super().__init__(prim_path, name=name, position=position, translation=translation,
                         orientation=quat.from_matrix(R_usd))

    # ------------------------------------------------------------------ building
    def add_to_spec(self, spec: mujoco.MjSpec):
        body = super().add_to_spec(spec)
        if self._mount_link is None:
            body.add_camera(name=self.prim_path, fovy=self._fovy())
        return body

    def _add_mounted(self, body: mujoco.MjsBody) -> None:
        body.add_camera(name=self.prim_path, pos=self._pose[0].tolist(), quat=self._pose[1].tolist(),
                        fovy=self._fovy())

    def _write_local(self, model: mujoco.MjModel, position: np.ndarray, orientation: np.ndarray) -> None:
        model.cam_pos[self._cam_id] = position
        model.cam_quat[self._cam_id] = orientation

    def bind_simulation(self, sim) -> None:
        super().bind_simulation(sim)
        self._cam_id = mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_CAMERA, self.prim_path)
        self._close_renderers()

    def unbind_simulation(self) -> None:
        self._close_renderers()
        super().unbind_simulation()

    def initialize(self, physics_sim_view=None) -> None:
        """Nothing to do: the camera is bound when the World compiles (kept for Isaac scripts)."""

    # ------------------------------------------------------------------ pose (camera axes)
    @staticmethod
    def _to_usd(orientation, camera_axes: str) -> np.ndarray:
        from manip.validation import unit_quat

        return quat.to_matrix(unit_quat(orientation)) @ _axes(camera_axes)

    def get_world_pose(self, camera_axes: str = "world") -> tuple[np.ndarray, np.ndarray]:
        """Position (3,) [m] and orientation (4,) (w, x, y, z) in the given camera axes."""
        M = _axes(camera_axes)
        pose = super().get_world_pose()
        if pose is None:
            return None  # type: ignore[return-value]
        p, q_usd = pose
        return p, quat.from_matrix(quat.to_matrix(q_usd) @ M.T)

    def set_world_pose(self, position=None, orientation=None, camera_axes: str = "world") -> None:
        """Move the camera; `orientation` (w, x, y, z) in the given camera axes (None keeps it).
        A camera on a robot's link stays fixed to it, at the pose this gives in the link's frame."""
        _axes(camera_axes)
        q_usd = None if orientation is None else quat.from_matrix(self._to_usd(orientation, camera_axes))
        super().set_world_pose(position, q_usd)

    def get_local_pose(self, camera_axes: str = "world") -> tuple[np.ndarray, np.ndarray]:
        """The pose in the link's frame for a camera on a robot's link, else the world pose."""
        if self._mount_link is None:
            return self.get_world_pose(camera_axes)
        p, q_usd = super().get_local_pose()
        return p, quat.from_matrix(quat.to_matrix(q_usd) @ _axes(camera_axes).T)

    def set_local_pose(self, translation=None, orientation=None, camera_axes: str = "world") -> None:
        """The pose in the link's frame for a camera on a robot's link, else the world pose."""
        if self._mount_link is None:
            self.set_world_pose(translation, orientation, camera_axes)
            return
        _axes(camera_axes)
        q_usd = None if orientation is None else quat.from_matrix(self._to_usd(orientation, camera_axes))
        super().set_local_pose(translation, q_usd)

    def post_reset(self) -> None:
        """Back to the default pose (kept in USD's axes)."""
        if self._mount_link is not None:
            super().post_reset()
            return
        self.set_world_pose(self._default_state.position, self._default_state.orientation, camera_axes="usd")

    # ------------------------------------------------------------------ lens
    def get_resolution(self) -> tuple[int, int]:
        """(width, height) [px]."""
        return self._resolution

    def set_resolution(self, value) -> None:
        """(width, height) [px], at most 1920 x 1080."""
        self._resolution = _resolution(value)
        self._close_renderers()
        self._apply_lens()

    def get_frequency(self) -> float:
        return self._frequency

    def set_frequency(self, value: float) -> None:
        self._frequency = positive(value, "frequency", "1/s")

    def get_dt(self) -> float:
        return 1.0 / self._frequency

    def set_dt(self, value: float) -> None:
        self._frequency = 1.0 / positive(value, "dt", "s")

    def get_focal_length(self) -> float:
        """Focal length (Isaac's units: tenths of the stage unit)."""
        return self._focal_length

    def set_focal_length(self, value: float) -> None:
        self._focal_length = positive(value, "focal_length", "tenths of the stage unit")
        self._apply_lens()

    def get_horizontal_aperture(self) -> float:
        return self._horizontal_aperture

    def set_horizontal_aperture(self, value: float) -> None:
        self._horizontal_aperture = positive(value, "horizontal_aperture", "tenths of the stage unit")
        self._apply_lens()

    def get_vertical_aperture(self) -> float:
        """The horizontal aperture times height / width (square pixels, as Isaac keeps them)."""
        w, h = self._resolution
        return self._horizontal_aperture * h / w

    def set_vertical_aperture(self, value: float) -> None:
        """Sets the horizontal aperture to value * width / height (square pixels)."""
        w, h = self._resolution
        self.set_horizontal_aperture(positive(value, "vertical_aperture", "tenths of the stage unit") * w / h)

    def get_clipping_range(self) -> tuple[float, float]:
        """(near, far) [m]: depth outside it is inf."""
        return self._clipping

    def set_clipping_range(self, near_distance: float | None = None, far_distance: float | None = None) -> None:
        near = self._clipping[0] if near_distance is None else positive(near_distance, "near_distance", "m")
        far = self._clipping[1] if far_distance is None else positive(far_distance, "far_distance", "m")
        if not far > near:
            raise InvalidInputError(f"far_distance must exceed near_distance; got ({near}, {far})")
        self._clipping = (near, far)

    def get_horizontal_fov(self) -> float:
        """Horizontal field of view [rad]."""
        return 2.0 * math.atan(self._horizontal_aperture / (2.0 * self._focal_length))

    def get_vertical_fov(self) -> float:
        """Vertical field of view [rad]."""
        return 2.0 * math.atan(self.get_vertical_aperture() / (2.0 * self._focal_length))

    def get_projection_type(self) -> str:
        return "pinhole"

    def set_projection_type(self, value: str) -> None:
        """Only "pinhole" (MuJoCo renders pinhole cameras; Isaac's fisheye models are not available)."""
        if value != "pinhole":
            raise InvalidInputError(f"projection type must be 'pinhole' (MuJoCo renders pinhole cameras); got {value!r}")

    def get_projection_mode(self) -> str:
        return "perspective"

    def set_projection_mode(self, value: str) -> None:
        """Only "perspective" (the intrinsics and point clouds here are a perspective camera's)."""
        if value != "perspective":
            raise InvalidInputError(f"projection mode must be 'perspective'; got {value!r}")

    def get_aspect_ratio(self) -> float:
        """Width / height of the image (square pixels)."""
        w, h = self._resolution
        return w / float(h)

    def get_view_matrix_ros(self) -> np.ndarray:
        """(4, 4) transform of world points [m] into the camera's ROS frame (+Z forward, +X right,
        +Y down): x_cam = V @ [x_world, 1]."""
        p, q = self.get_world_pose(camera_axes="ros")
        R = quat.to_matrix(q)
        V = np.eye(4)
        V[:3, :3], V[:3, 3] = R.T, -R.T @ p
        return V

    def get_focus_distance(self) -> float:
        return self._lens["focus_distance"]

    def set_focus_distance(self, value: float) -> None:
        """Kept, not rendered (MuJoCo's cameras have no depth of field) [stage units]."""
        self._lens["focus_distance"] = positive(value, "focus_distance", "m")

    def get_lens_aperture(self) -> float:
        return self._lens["f_stop"]

    def set_lens_aperture(self, value: float) -> None:
        """The f-stop; kept, not rendered (0: no depth of field, USD's default)."""
        v = float(value)
        if not math.isfinite(v) or v < 0:
            raise InvalidInputError(f"lens aperture (f-stop) must be >= 0; got {value!r}")
        self._lens["f_stop"] = v

    def get_stereo_role(self) -> str:
        return self._lens["stereo_role"]

    def set_stereo_role(self, value: str) -> None:
        """"mono", "left" or "right"; kept (the images are the same)."""
        if value not in ("mono", "left", "right"):
            raise InvalidInputError(f"stereo role must be 'mono', 'left' or 'right'; got {value!r}")
        self._lens["stereo_role"] = value

    def get_intrinsics_matrix(self) -> np.ndarray:
        """(3, 3) pinhole intrinsics [px]: [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (OpenCV's
        convention, see the module docstring)."""
        w, h = self._resolution
        f = w * self._focal_length / self._horizontal_aperture
        return np.array([[f, 0.0, (w - 1) / 2.0], [0.0, f, (h - 1) / 2.0], [0.0, 0.0, 1.0]])

    def _fovy(self) -> float:
        return math.degrees(self.get_vertical_fov())

    def _apply_lens(self) -> None:
        if self._sim is not None and getattr(self, "_cam_id", -1) >= 0:
            self._sim.model.cam_fovy[self._cam_id] = self._fovy()

    # ------------------------------------------------------------------ Isaac's annotators (always on here)
    def add_distance_to_image_plane_to_frame(self) -> None:
        """Kept for Isaac scripts: depth is always available (`get_depth`)."""

    def add_pointcloud_to_frame(self, include_unlabelled: bool = False) -> None:
        """`get_current_frame()["pointcloud"]`, Isaac's pointcloud annotator: {"data": (N, 3)
        float32 world points [m] of the pixels that hit a surface (row-major, as
        `get_pointcloud`), "info": {"pointRgb": (N, 4) uint8, "pointNormals": (N, 4) float32
        world normals}}. Every surface is in it, whatever `include_unlabelled` (Isaac's default
        False keeps only labelled prims' points: mask with the semantic_segmentation annotator)."""
        self._annotators.add("pointcloud")

    def remove_pointcloud_from_frame(self) -> None:
        self._annotators.discard("pointcloud")

    def add_distance_to_camera_to_frame(self) -> None:
        """Kept for Isaac scripts: `get_current_frame()["distance_to_camera"]` is filled."""

    def add_normals_to_frame(self) -> None:
        """`get_current_frame()["normals"]`: (H, W, 4) float32 world-frame surface normals
        (`manip.sim.sensors.annotators.normals`)."""
        self._annotators.add("normals")

    def add_motion_vectors_to_frame(self) -> None:
        """`get_current_frame()["motion_vectors"]`: (H, W, 4) float32, the image motion [px] of
        each pixel's surface over the camera's frame period (`get_dt()`, or the World's physics
        step when no frequency is set), from the simulation's velocities
        (`manip.sim.sensors.annotators.motion_vectors`)."""
        self._annotators.add("motion_vectors")

    def add_semantic_segmentation_to_frame(self, init_params: dict | None = None) -> None:
        """`get_current_frame()["semantic_segmentation"]`: {"data": (H, W) uint32 label ids,
        "info": {"idToLabels": ...}} from the prims' labels (`add_update_semantics`; layout:
        `manip.sim.sensors.segmentation`). `init_params`: {"colorize": False, "semanticTypes"}."""
        self._segmentation_types = segmentation.init_params(init_params, "semantic_segmentation")["semanticTypes"]
        self._annotators.add("semantic_segmentation")

    def remove_semantic_segmentation_from_frame(self) -> None:
        self._annotators.discard("semantic_segmentation")

    def add_instance_id_segmentation_to_frame(self, init_params: dict | None = None) -> None:
        """`get_current_frame()["instance_id_segmentation"]`: {"data": (H, W) uint32 ids, "info":
        {"idToLabels": {id: prim path}}}, one id per prim seen (`manip.sim.sensors.segmentation`)."""
        segmentation.init_params(init_params, "instance_id_segmentation")
        self._annotators.add("instance_id_segmentation")

    def remove_instance_id_segmentation_from_frame(self) -> None:
        self._annotators.discard("instance_id_segmentation")

    def remove_distance_to_image_plane_from_frame(self) -> None:
        """Nothing to remove: depth is always in the frame (`get_depth`)."""

    def remove_distance_to_camera_from_frame(self) -> None:
        """Nothing to remove: the frame always holds it."""

    @property
    def supported_annotators(self) -> list[str]:
        """The annotators of `get_current_frame()` here (not Isaac's bounding-box, instance
        (by semantic class) and occlusion annotators)."""
        return ["normals", "motion_vectors", "distance_to_image_plane", "distance_to_camera", "pointcloud",
                "semantic_segmentation", "instance_id_segmentation"]

    def remove_normals_from_frame(self) -> None:
        self._annotators.discard("normals")

    def remove_motion_vectors_from_frame(self) -> None:
        self._annotators.discard("motion_vectors")

    def pause(self) -> None:
        """Freeze `get_current_frame()` at the current frame until `resume()` (Isaac's sensor pause)."""
        self._paused_frame = self._current_frame()

    def resume(self) -> None:
        self._paused_frame = None

    def is_paused(self) -> bool:
        return self._paused_frame is not None

    def get_current_frame(self, clone: bool = False) -> dict:
        """{"rgba", "distance_to_image_plane", "distance_to_camera", "rendering_frame"} of the
        current state, plus "normals" / "motion_vectors" / "pointcloud" / "semantic_segmentation" /
        "instance_id_segmentation" once added
        (`add_..._to_frame`)."""
        return self._paused_frame if self._paused_frame is not None else self._current_frame()

    def _current_frame(self) -> dict:
        depth = self.get_depth()
        K = self.get_intrinsics_matrix()
        points = annotators.camera_points(depth, K)
        frame = {"rgba": self.get_rgba(), "distance_to_image_plane": depth,
                 "distance_to_camera": np.linalg.norm(np.nan_to_num(points, nan=np.inf), axis=-1).astype(np.float32)}
        p_cam, q_cam = self.get_world_pose(camera_axes="ros")
        R_cam = quat.to_matrix(q_cam)
        if "normals" in self._annotators or "pointcloud" in self._annotators:
            world_normals = annotators.normals(points, R_cam)
            if "normals" in self._annotators:
                frame["normals"] = world_normals
            if "pointcloud" in self._annotators:
                hit = np.isfinite(depth)
                frame["pointcloud"] = {"data": (points[hit] @ R_cam.T + p_cam).astype(np.float32),
                                       "info": {"pointRgb": frame["rgba"][hit], "pointNormals": world_normals[hit]}}
        sim = self._sim
        if self._annotators & {"motion_vectors", "semantic_segmentation", "instance_id_segmentation"}:
            seg = self._render("segmentation")
        if "semantic_segmentation" in self._annotators:
            frame["semantic_segmentation"] = segmentation.semantic_segmentation(sim.model, seg,
                                                                                self._segmentation_types)
        if "instance_id_segmentation" in self._annotators:
            frame["instance_id_segmentation"] = segmentation.instance_id_segmentation(sim.model, seg)
        if "motion_vectors" in self._annotators:
            period = self.get_dt() if self._frequency > 0 else (sim.physics_dt or float(sim.model.opt.timestep))
            geom_ids = np.where(seg[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM), seg[..., 0], -1)
            frame["motion_vectors"] = annotators.motion_vectors(sim.model, sim.data, points, geom_ids, K, p_cam,
                                                                R_cam, period)
        frame["rendering_frame"] = self._frame["rendering_frame"]
        return frame

    # ------------------------------------------------------------------ images
    def _renderer(self, mode: str) -> mujoco.Renderer:
        sim = self._sim
        if sim is None:
            raise SimulationError(f"Camera {self.prim_path!r}: call World.reset() before reading images")
        if self._renderer_model is not sim.model:
            self._close_renderers()
            self._renderer_model = sim.model
            self._apply_lens()
        r = self._renderers.get(mode)
        if r is None:
            from manip.sim.core.recording import make_renderer

            w, h = self._resolution
            r = self._renderers[mode] = make_renderer(sim.model, w, h)
            if mode == "depth":
                r.enable_depth_rendering()
            elif mode == "segmentation":
                r.enable_segmentation_rendering()
        return r

    def _render(self, mode: str) -> np.ndarray:
        """The current state rendered: "rgb" (H, W, 3) uint8, "depth" (H, W) [m] or
        "segmentation" (H, W, 2) (object id, object type; -1 where nothing)."""
        r = self._renderer(mode)
        sim = self._sim
        sim.ensure_kinematics()
        m = sim.model
        mujoco.mj_camlight(m, sim.data)   # camera frames (mj_kinematics leaves them)
        opt = mujoco.MjvOption()
        opt.sitegroup[:] = 0   # sites are markers, not surfaces
        near, far = self._clipping
        extent = float(m.stat.extent)
        saved = (float(m.vis.map.znear), float(m.vis.map.zfar))
        m.vis.map.znear, m.vis.map.zfar = near / extent, far / extent
        try:
            r.update_scene(sim.data, camera=self._cam_id, scene_option=opt)
            img = r.render()
        finally:
            m.vis.map.znear, m.vis.map.zfar = saved
        self._frame["rendering_frame"] += 1
        return img

    def get_rgba(self) -> np.ndarray:
        """(H, W, 4) uint8 RGBA image of the current state (alpha 255)."""
        rgb = self._render("rgb")
        out = np.empty(rgb.shape[:2] + (4,), dtype=np.uint8)
        out[..., :3] = rgb
        out[..., 3] = 255
        return out

    def get_rgb(self) -> np.ndarray:
        """(H, W, 3) uint8 RGB image of the current state."""
        return self.get_rgba()[..., :3]

    def get_depth(self) -> np.ndarray:
        """(H, W) float32 depth [m]: the distance of the surface seen at each pixel to the
        image plane (along the optical axis), inf where nothing is hit within the clipping range."""
        z = np.array(self._render("depth"), dtype=np.float32)
        near, far = self._clipping
        z[(z >= np.float32(far) * np.float32(1.0 - 1e-5)) | (z < np.float32(near))] = np.inf
        return z

    def get_pointcloud(self) -> np.ndarray:
        """(N, 3) points [m] in the world frame, one per pixel that hit a surface (row-major)."""
        depth = self.get_depth()
        P_ros = annotators.camera_points(depth, self.get_intrinsics_matrix())[np.isfinite(depth)]
        p, q = self.get_world_pose(camera_axes="ros")
        return P_ros @ quat.to_matrix(q).T + p

    def get_world_points_from_image_coords(self, points_2d: np.ndarray, depth: np.ndarray) -> np.ndarray:
        """(N, 3) world points [m] of pixel coordinates points_2d (N, 2) (u, v) at depths (N,) [m]."""
        uv = np.asarray(points_2d, dtype=float).reshape(-1, 2)
        z = np.asarray(depth, dtype=float).reshape(-1)
        if z.shape[0] != uv.shape[0]:
            raise InvalidInputError(f"depth must have one value per point; got {z.shape[0]} for {uv.shape[0]} points")
        K = self.get_intrinsics_matrix()
        P = np.stack([(uv[:, 0] - K[0, 2]) / K[0, 0] * z, (uv[:, 1] - K[1, 2]) / K[1, 1] * z, z], axis=1)
        p, q = self.get_world_pose(camera_axes="ros")
        return P @ quat.to_matrix(q).T + p

    def get_image_coords_from_world_points(self, points_3d: np.ndarray) -> np.ndarray:
        """(N, 2) pixel coordinates (u, v) of world points (N, 3) [m] (in front of the camera)."""
        X = np.asarray(points_3d, dtype=float).reshape(-1, 3)
        p, q = self.get_world_pose(camera_axes="ros")
        P = (X - p) @ quat.to_matrix(q)
        K = self.get_intrinsics_matrix()
        return np.stack([K[0, 0] * P[:, 0] / P[:, 2] + K[0, 2], K[1, 1] * P[:, 1] / P[:, 2] + K[1, 2]], axis=1)

    def _close_renderers(self) -> None:
        for r in self._renderers.values():
            try:
                r.close()
            except Exception:  # pragma: no cover - a context already gone
                pass
        self._renderers = {}
        self._renderer_model = None

    def __del__(self):
        try:
            self._close_renderers()
        except Exception:  # pragma: no cover
            pass


declare_not_supported(Camera)
