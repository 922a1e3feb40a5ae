"""Two simulated depth cameras feeding the planner's occupancy map (pick_and_place.py --perceive).

The planner gets no obstacle from the simulator: before each motion, both cameras render a
depth image of the World as it is (`manip.sim.Camera`), and each image is integrated into the
map `"camera"` (`MotionGenerator.update_world_from_depth`, self-filtered at the robot's
measured configuration). Two things are left out of the images, as the non-perceiving
example leaves them out of the planner's world: the ground (its points become rays that see
all the way through, so nothing is marked there; the example's floor guard keeps motions
off it) and the cube to pick (its pixels become "no measurement": they neither mark nor free
a cell, so whatever the cube hides keeps what the map held).

Run alone, it builds the flagship's scene with its obstacles, refreshes the map once from both
cameras and prints how much of each obstacle's faces the map holds:

    python examples/perception_rig.py --seed 0
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from manip import Pose
from manip import quaternion as quat
from manip.sim import Camera

#: (eye, target) [m] of the two cameras: above and behind the robot's base, on either side,
#: looking at the workspace, so that they see the faces and tops the arm can reach.
CAMERAS = (((-0.55, -0.75, 1.45), (0.55, -0.15, 0.05)), ((-0.55, 0.75, 1.45), (0.55, -0.15, 0.05)))
RESOLUTION = (640, 480)
FOCAL_LENGTH = 1.2  # Isaac's units (with its 2.0955 aperture: an 82 deg horizontal field of view)
GROUND_HEIGHT = 0.005  # [m] points lower than this are the ground
CUBE_MARGIN = 0.015  # [m] points this close to the cube to pick are the cube's


def look_at(eye, target) -> np.ndarray:
    """(w, x, y, z) of a camera at `eye` looking at `target`, in Isaac's world camera axes (+X forward, +Z up)."""
    f = np.asarray(target, float) - np.asarray(eye, float)
    f /= np.linalg.norm(f)
    left = np.cross([0.0, 0.0, 1.0], f)
    left /= np.linalg.norm(left)
    return quat.from_matrix(np.stack([f, left, np.cross(f, left)], axis=1))


class CameraRig:
    """The cameras (created before the World's first reset) and the refresh of the map."""

    def __init__(self, resolution=RESOLUTION):
        self.cameras = []
        for i, (eye, target) in enumerate(CAMERAS):
            cam = Camera(f"/World/DepthCamera{i}", name=f"depth_camera_{i}", position=np.array(eye),
                         orientation=look_at(eye, target), resolution=resolution)
            cam.set_focal_length(FOCAL_LENGTH)
            self.cameras.append(cam)
        self.frames = 0
        self.integrate_time = 0.0  # [s] of wall time inside update_world_from_depth

    def refresh(self, mg, q, base_pose: Pose, cube_pose: Pose | None, cube_size: float) -> None:
        """Render both cameras and integrate them into the map of `mg` (self-filter at `q`, the
        robot's state: arm joints then fingers).

        Args:
            base_pose: the robot's base in the World (the map is in the base frame).
            cube_pose: the cube to pick, left out of the images (None: nothing left out).
        """
        T_base_world = base_pose.inverse()
        for cam in self.cameras:
            depth = cam.get_depth()
            p, o = cam.get_world_pose()
            K = cam.get_intrinsics_matrix()
            X = _points(depth, K, Pose(p, o))           # (H, W, 3) world points (NaN: no hit)
            depth = depth.copy()
            depth[X[..., 2] < GROUND_HEIGHT] = np.inf   # the ground: seen through
            if cube_pose is not None:
                local = (X - cube_pose.position) @ cube_pose.rotation
                on_cube = np.all(np.abs(local) <= cube_size / 2 + CUBE_MARGIN, axis=-1)
                depth[on_cube] = np.nan                 # the cube: no measurement
            t0 = time.perf_counter()
            mg.update_world_from_depth(depth, K, T_base_world @ Pose(p, o), q=q)
            self.integrate_time += time.perf_counter() - t0
            self.frames += 1


def _points(depth: np.ndarray, K: np.ndarray, pose: Pose) -> np.ndarray:
    """(H, W, 3) world points [m] of a depth image (NaN where nothing was hit)."""
    H, W = depth.shape
    u, v = np.meshgrid(np.arange(W), np.arange(H))
    z = np.where(np.isfinite(depth), depth, np.nan)
    P = np.stack([(u - K[0, 2]) / K[0, 0] * z, (v - K[1, 2]) / K[1, 1] * z, z], axis=-1)
    R = pose.rotation @ np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])  # optical axes
    return P @ R.T + pose.position


def face_coverage(occupancy, centre, dims, yaw, n: int = 7) -> dict[str, float]:
    """Fraction of points on each face of a yawed box (all but the bottom) inside occupied cells."""
    R = quat.to_matrix(quat.from_axis_angle([0.0, 0.0, 1.0], yaw))
    s = np.linspace(-0.95, 0.95, n)
    A, B = np.meshgrid(s, s)
    out = {}
    for axis, sign in ((0, -1), (0, 1), (1, -1), (1, 1), (2, 1)):
        u, v = [k for k in range(3) if k != axis]
        P = np.zeros((A.size, 3))
        P[:, axis] = sign * dims[axis] / 2
        P[:, u] = A.ravel() * dims[u] / 2
        P[:, v] = B.ravel() * dims[v] / 2
        W = P @ R.T + centre
        W = W[W[:, 2] > GROUND_HEIGHT]
        out[f"{'+' if sign > 0 else '-'}{'xyz'[axis]}"] = float(np.mean([occupancy.contains_points(w[None]) for w in W]))
    return out


def main(argv: list[str] | None = None) -> int:
    import importlib.util
    from pathlib import Path

    from manip import MotionGenerator
    from manip.sim import FixedCuboid, Franka, World

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] + " Run alone, it refreshes the map of "
                                     "the flagship's scene once and prints how much of each obstacle's faces it holds.")
    parser.add_argument("--seed", type=int, default=0, help="Seed of the obstacle layout (as pick_and_place.py's).")
    parser.add_argument("--resolution", type=float, default=0.02, help="Cell edge of the map [m].")
    args = parser.parse_args(argv)
    spec = importlib.util.spec_from_file_location("pick_and_place_example", Path(__file__).with_name("pick_and_place.py"))
    flagship = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = flagship
    spec.loader.exec_module(flagship)
    world = World()
    world.scene.add_default_ground_plane()
    boxes = flagship.obstacle_boxes(args.seed)
    for name, c, dims, yaw in boxes:
        world.scene.add(FixedCuboid(f"/World/{name}", name=name, position=c, size=1.0, scale=dims,
                                    orientation=quat.from_axis_angle([0, 0, 1], yaw)))
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    rig = CameraRig()
    world.reset()
    mg = MotionGenerator("franka")
    t0 = time.perf_counter()
    for cam in rig.cameras:   # refresh() at another resolution: the same steps
        p, o = cam.get_world_pose()
        depth = cam.get_depth().copy()
        X = _points(depth, cam.get_intrinsics_matrix(), Pose(p, o))
        depth[X[..., 2] < GROUND_HEIGHT] = np.inf
        mg.update_world_from_depth(depth, cam.get_intrinsics_matrix(), Pose(p, o), q=franka.get_joint_positions(),
                                   resolution=args.resolution)
    occupancy = mg.world.get("camera")
    print(f"{occupancy.num_cells} cells of {args.resolution} m ({occupancy.num_boxes} boxes) from {len(rig.cameras)} "
          f"cameras in {time.perf_counter() - t0:.2f} s (rendering included)")
    for name, c, dims, yaw in boxes:
        cover = face_coverage(occupancy, c, dims, yaw)
        print(f"  {name:6s} faces held: " + ", ".join(f"{k} {v:.0%}" for k, v in cover.items()))
    return 0 if occupancy.num_cells else 1


if __name__ == "__main__":
    sys.exit(main())
