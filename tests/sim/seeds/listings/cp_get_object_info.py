"""Ported listing: get_object_info.py.

From the tutorial 'Nvidia Isaac Sim代码编程 入门教程 2024(7) (Auromix)' (seed file 002_628dc57bd19cb1e9.txt, lines 200-220).
Changed: only the imports (omni.isaac... / isaacsim... -> manip.sim, carb -> manip.sim.carb,
the cuRobo wrapper -> manip.TutorialMotionGen) and headless=True; the code is the tutorial's.
"""

# get_object_info.py
from manip.sim import World

# Instantiate World class
world = World()
# Get the DynamicCuboid instance from the scene
cube = world.scene.get_object("target_cuboid")
print(cube)
# Get the world pose of the object
position, orientation = cube.get_world_pose()
print(f"Position(x,y,z)={position}")
print(f"Orientation(qw,qx,qy,qz)={orientation}")
# Get the linear and angular velocities of the object
# DynamicCuboid is subclass of RigidPrim, which has the dynamic related methods
linear_velocity = cube.get_linear_velocity()
angular_velocity = cube.get_angular_velocity()
mass = cube.get_mass()

print(f"Linear velocity={linear_velocity}")
print(f"Angular velocity={angular_velocity}")
print(f"Mass={mass}")
