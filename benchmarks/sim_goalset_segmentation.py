"""Round seven (isaac-audit-7): goal-set IK against solve_batch of the same goals, and the Camera's
segmentation annotators' cost per get_current_frame (medians of 7 calls)."""

import math
import time

import numpy as np

from manip import MotionGenerator, Pose
from manip import quaternion as quat
from manip.sim import Camera, DynamicCuboid, Franka, World, add_update_semantics

mg = MotionGenerator("franka")
ik = mg.ik_solver
rng = np.random.default_rng(3)
DOWN = [0, 1, 0, 0]
sets = [Pose.stack([Pose([rng.uniform(0.3, 0.6), rng.uniform(-0.3, 0.3), rng.uniform(0.1, 0.5)], DOWN) for _ in range(4)])
        for _ in range(8)]
flat = Pose(np.concatenate([s.position for s in sets]), np.concatenate([s.quaternion for s in sets]))
ik.solve_batch(flat); ik.solve_batch_goalset(sets)
def med(f, n=7):
    t = []
    for _ in range(n):
        t0 = time.perf_counter(); f(); t.append(time.perf_counter() - t0)
    return float(np.median(t))
a = med(lambda: ik.solve_batch(flat)); b = med(lambda: ik.solve_batch_goalset(sets))
print(f"IK 8 sets x 4 poses: solve_batch(32) {a*1e3:.1f} ms, solve_batch_goalset {b*1e3:.1f} ms, ratio {b/a:.3f}")

w = World(); w.scene.add_default_ground_plane(); w.scene.add(Franka("/World/Franka", name="franka"))
c = w.scene.add(DynamicCuboid("/World/Cube", name="cube", position=[0.5, 0.1, 0.05], size=0.1)); add_update_semantics(c.prim, "cube")
cam = Camera("/World/camera", position=[0.4, 0, 1.5], orientation=quat.from_axis_angle(np.array([0, 1.0, 0]), math.pi / 2), resolution=(320, 240))
w.reset(); cam.initialize(); cam.get_current_frame()
p = med(lambda: cam.get_current_frame())
cam.add_semantic_segmentation_to_frame(); cam.get_current_frame()
s = med(lambda: cam.get_current_frame())
cam.add_instance_id_segmentation_to_frame(); cam.get_current_frame()
si = med(lambda: cam.get_current_frame())
print(f"Camera 320x240 get_current_frame: plain {p*1e3:.1f} ms, +semantic {s*1e3:.1f} ms (x{s/p:.2f}), +instance id {si*1e3:.1f} ms (x{si/p:.2f})")
