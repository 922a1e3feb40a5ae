"""Ported listing: the cube-info physics callback (marked DO NOT EXECUTE for Isaac 4.0).

From the tutorial 'Nvidia Isaac Sim代码编程 入门教程 2024(7) (Auromix)' (seed file 002_628dc57bd19cb1e9.txt, lines 227-238).
Changed: only the imports (omni.isaac... / isaacsim... -> manip.sim, carb -> manip.sim.carb,
the cuRobo wrapper -> manip.TutorialMotionGen) and headless=True; the code is the tutorial's.
"""

# WARNING: DO NOT EXECUTE!
# All physics callbacks must take step_size as an argument
def print_target_cube_info(step_size):
    position, orientation = cube.get_world_pose()
    print(f"Position={position}")
    print(f"Orientation={orientation}")
    linear_velocity = cube.get_linear_velocity()
    print(f"Linear velocity={linear_velocity}")


# Add callback to world, callback will be called every physics step
world.add_physics_callback(callback_name="print_target_cube_info_callback", callback_fn=print_target_cube_info)
