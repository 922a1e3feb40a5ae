"""Objects and materials: coloured shapes and their visual materials, physics materials with
different frictions on a ramp, a visual marker, bounding boxes. Only the imports differ from
Isaac Sim 4.x."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import DynamicCuboid, FixedCuboid, VisualSphere, DynamicSphere
from manip.sim import PhysicsMaterial
from manip.sim import PreviewSurface
from manip.sim import euler_angles_to_quat

world = World(stage_units_in_meters=1.0)
world.scene.add_default_ground_plane()
slope = np.deg2rad(15.0)
ramp_orientation = euler_angles_to_quat(np.array([0.0, slope, 0.0]))
ramp = world.scene.add(
    FixedCuboid(
        prim_path="/World/ramp",
        name="ramp",
        position=np.array([0.0, 0.0, 0.4]),
        orientation=ramp_orientation,
        scale=np.array([2.0, 1.2, 0.05]),
        size=1.0,
        color=np.array([0.6, 0.6, 0.6]),
    )
)
ice = PhysicsMaterial(prim_path="/World/Physics_Materials/ice", static_friction=0.02, dynamic_friction=0.02)
rubber = PhysicsMaterial(prim_path="/World/Physics_Materials/rubber", static_friction=0.9, dynamic_friction=0.9)
normal = np.array([np.sin(slope), 0.0, np.cos(slope)])
blocks = {}
for name, material, y in (("ice_block", ice, -0.3), ("rubber_block", rubber, 0.3)):
    blocks[name] = world.scene.add(
        DynamicCuboid(
            prim_path=f"/World/{name}",
            name=name,
            position=np.array([0.0, y, 0.4]) + normal * (0.025 + 0.05),
            orientation=ramp_orientation,
            size=0.1,
            color=np.array([0.1, 0.4, 0.9]) if name == "ice_block" else np.array([0.9, 0.2, 0.1]),
            physics_material=material,
        )
    )
marker = world.scene.add(
    VisualSphere(prim_path="/World/marker", name="marker", position=np.array([0.5, 0.0, 0.8]), radius=0.03,
                 color=np.array([0.0, 1.0, 0.0]))
)
ball = world.scene.add(DynamicSphere(prim_path="/World/ball", name="ball", position=np.array([1.5, 1.0, 0.3]),
                                     radius=0.04))
world.reset()

colors = {name: block.get_applied_visual_material().get_color() for name, block in blocks.items()}
gold = PreviewSurface(prim_path="/World/Looks/gold", color=np.array([1.0, 0.8, 0.1]), metallic=1.0)
ball.apply_visual_material(gold)
ball_color = ball.get_applied_visual_material().get_color()
marker.set_visibility(False)

start = {name: block.get_world_pose()[0] for name, block in blocks.items()}
for _ in range(60):
    world.step(render=True)
slid = {name: float(np.linalg.norm(block.get_world_pose()[0] - start[name])) for name, block in blocks.items()}
ramp_box = world.scene.compute_object_AABB("ramp")
ball_height = float(ball.get_world_pose()[0][2])
print("colours", colors, "slid", slid, "ramp bounds", ramp_box)
simulation_app.close()
