"""Ported listing: clearing the world and the stage.

From the tutorial 'Nvidia Isaac Sim代码编程 入门教程 2024(7) (Auromix)' (seed file 002_628dc57bd19cb1e9.txt, lines 139-143).
Changed: only the imports (omni.isaac... / isaacsim... -> manip.sim, carb -> manip.sim.carb,
the cuRobo wrapper -> manip.TutorialMotionGen) and headless=True; the code is the tutorial's.
"""

# Clear the world [recommend]
world.clear()
# Clear the stage
from manip.sim import clear_stage
clear_stage()
