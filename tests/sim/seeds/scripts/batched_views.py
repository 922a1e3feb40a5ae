"""Batched views: a row of cubes handled through one RigidPrimView (poses, velocities,
forces, contact forces, gravity) and a Franka through an ArticulationView (joint state,
Jacobians, mass matrix). Only the imports differ from Isaac Sim 4.x."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import DynamicCuboid
from manip.sim import RigidPrimView
from manip.sim import ArticulationView
from manip.sim import Franka

world = World(stage_units_in_meters=1.0)
world.scene.add_default_ground_plane()
num_cubes = 4
for i in range(num_cubes):
    world.scene.add(
        DynamicCuboid(
            prim_path=f"/World/Cube_{i}",
            name=f"cube_{i}",
            position=np.array([0.6, -0.3 + 0.2 * i, 0.5]),
            size=0.05,
            mass=0.1,
            color=np.array([0.2 * i, 0.5, 1.0 - 0.2 * i]),
        )
    )
cubes = RigidPrimView(
    prim_paths_expr="/World/Cube_[0-9]+",
    name="cubes_view",
    track_contact_forces=True,
    contact_filter_prim_paths_expr=["/World/defaultGroundPlane"],
)
world.scene.add(cubes)
world.scene.add(Franka(prim_path="/World/Franka", name="franka"))
franka_view = ArticulationView(prim_paths_expr="/World/Franka", name="franka_view")
world.scene.add(franka_view)
world.reset()

# let the cubes land, then read them all at once
for _ in range(90):
    world.step(render=False)
positions, orientations = cubes.get_world_poses()
landed_heights = positions[:, 2].copy()
ground_forces = cubes.get_net_contact_forces(dt=world.get_physics_dt())

# push the first two cubes sideways every step for half a second; float the last one
cubes.disable_gravities(indices=[3])
cubes.set_velocities(np.array([[0.0, 0.0, 0.2, 0.0, 0.0, 0.0]]), indices=[3])
for _ in range(30):
    cubes.apply_forces(np.array([[0.5, 0.0, 0.0], [0.5, 0.0, 0.0]]), indices=[0, 1])
    world.step(render=False)
after, _ = cubes.get_world_poses()

# the Franka through its view
franka_view.set_joint_positions(np.array([[0.0, -0.5, 0.0, -2.2, 0.0, 1.8, 0.8, 0.04, 0.04]]))
jacobians = franka_view.get_jacobians()
mass_matrices = franka_view.get_mass_matrices()
joint_positions = franka_view.get_joint_positions()
print("landed at", landed_heights, "ground forces", ground_forces[:, 2])
print("moved", after - positions, "jacobians", jacobians.shape, "mass matrices", mass_matrices.shape)
simulation_app.close()
