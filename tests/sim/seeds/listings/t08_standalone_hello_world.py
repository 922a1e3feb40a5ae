"""Ported listing: standalone Hello World: the falling cube.

From the tutorial 'Isaac Sim教程08 独立代码编程 (Herman Ye, Auromix)' (seed file 000_7a433f4238e67386.txt, lines 637-682).
Changed: only the imports (omni.isaac... / isaacsim... -> manip.sim, carb -> manip.sim.carb,
the cuRobo wrapper -> manip.TutorialMotionGen) and headless=True; the code is the tutorial's.
"""

# 在其他任何引入前,必须先引入仿真器类
from manip.sim import SimulationApp
# 构建仿真器实例
# 设置Headless模式(TODO)
simulation_app = SimulationApp({"headless": True})

# 引入World类
from manip.sim import World
# 引入DynamicCuboid类,用于创建立方体
from manip.sim import DynamicCuboid
# 引入numpy
import numpy as np

# 创建世界实例
world = World()
# 添加默认的地面
world.scene.add_default_ground_plane()
# 添加一个立方体
fancy_cube = world.scene.add(
    DynamicCuboid(
        prim_path="/World/random_cube",
        name="fancy_cube",
        position=np.array([0, 0, 1.0]),
        scale=np.array([0.5015, 0.5015, 0.5015]),
        color=np.array([0, 0, 1.0]),
    ))
# 添加资源后建议进行重置
world.reset()

# 主循环
steps_to_simulate = 2000
for i in range(steps_to_simulate):
    # 获取指定的prim在世界坐标系下的位姿
    position, orientation = fancy_cube.get_world_pose()
    # 获取指定的prim的线速度
    linear_velocity = fancy_cube.get_linear_velocity()
    # 打印信息
    print("Cube position is : " + str(position))
    print("Cube's orientation is : " + str(orientation))
    print("Cube's linear velocity is : " + str(linear_velocity))

    # 同步执行仿真物理步进和显示渲染步进
    world.step(render=True)

# 关闭仿真器
simulation_app.close()
