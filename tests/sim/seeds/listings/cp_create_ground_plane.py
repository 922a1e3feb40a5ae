"""Ported listing: create_ground_plane.py.

From the tutorial 'Nvidia Isaac Sim代码编程 入门教程 2024(7) (Auromix)' (seed file 002_628dc57bd19cb1e9.txt, lines 122-129).
Changed: only the imports (omni.isaac... / isaacsim... -> manip.sim, carb -> manip.sim.carb,
the cuRobo wrapper -> manip.TutorialMotionGen) and headless=True; the code is the tutorial's.
"""

# create_ground_plane.py
from manip.sim import World


# Instantiate World class
world = World()
# Add a ground plane to stage and register it in the scene
world.scene.add_default_ground_plane()
