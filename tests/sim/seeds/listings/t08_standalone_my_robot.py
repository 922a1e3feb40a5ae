"""Ported listing: standalone My Robot: the Jetbot, random wheel velocities.

From the tutorial 'Isaac Sim教程08 独立代码编程 (Herman Ye, Auromix)' (seed file 000_7a433f4238e67386.txt, lines 686-797).
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
# 引入nuclues中的函数来获取assets路径
from manip.sim import get_assets_root_path
# 引入omni.isaac.core.utils.stage中的函数来添加机器人模型引用
from manip.sim import add_reference_to_stage
# 引入omni.isaac.core.robots中的Robot类
from manip.sim import Robot
# 引入关节控制种类相关类
from manip.sim import ArticulationAction
# 引入日志相关,Carbonite含有Omniverse的日志系统
from manip.sim import carb
# 引入numpy
import numpy as np


class HelloRobot():
    def __init__(self):
        self.setup_scene()
        return

    def setup_scene(self):
        # 创建世界实例
        self._world = World()
        # 添加默认的地面
        self._world.scene.add_default_ground_plane()
        # 获取Nucleus服务器上的Isaac资产文件夹的路径
        assets_root_path = get_assets_root_path()
        # 打印错误信息
        if assets_root_path is None:
            carb.log_error("Could not find nucleus server with /Isaac folder")
        # 打印Isaac资产文件夹的路径
        carb.log_info("Assets root path: " + assets_root_path)
        # 拼接机器人模型的路径
        asset_path = assets_root_path + "/Isaac/Robots/Jetbot/jetbot.usd"
        # 打印机器人模型的路径
        carb.log_info("Asset path: " + asset_path)
        # 将机器人模型添加到Stage中并指定它的Stage路径
        add_reference_to_stage(usd_path=asset_path,
                               prim_path="/World/Fancy_Robot")

        # 将机器人prim root 封装成Robot类的实例并添加到世界中
        # 注意:此步不会重复添加prim到Stage,因为在第一次添加后,该prim已经存在于Stage中
        jetbot_robot = self._world.scene.add(
            Robot(prim_path="/World/Fancy_Robot", name="fancy_robot"))

        # 打印机器人的自由度,但在第一次重置之前,关节信息无法获取,它将输出none
        print("Num of degrees of freedom before first reset: " +
              str(jetbot_robot.num_dof))

        # 添加资源后建议进行重置
        self._world.reset()

        # 获取指定名称的prim,此处为机器人
        self._jetbot = self._world.scene.get_object("fancy_robot")
        # 获取机器人的关节隐式PD控制器,可用于设置PD控制器的参数,应用动作,切换控制模式等
        self._jetbot_articulation_controller = self._jetbot.get_articulation_controller()

        # 添加一个仿真物理步进回调函数,以便在每次执行物理步骤时发送控制动作
        self._world.add_physics_callback(
            "sending_actions", callback_fn=self.send_robot_actions)

        # 在第一次重置后,关节信息将可用,此时将打印关节信息,它将输出2
        print("Num of degrees of freedom after first reset: " +
              str(self._jetbot.num_dof))
        # 获取关节的位置
        print("Joint Positions after first reset: " +
              str(self._jetbot.get_joint_positions()))

    def send_robot_actions(self, step_size):
        # 控制器的apply_action 方法接受 ArticulationAction 类型的参数,其中包含关节位置,关节力矩和关节速度
        # 对于轮子通常指定速度控制,此处随机生成两个轮子的速度数组乘上系数作为速度控制输入
        # self._jetbot_articulation_controller.apply_action()的另一个相同的方法是self._jetbot.apply_action()
        wheel_velocities = 5 * np.random.rand(2)
        self._jetbot_articulation_controller.apply_action(ArticulationAction(joint_positions=None,
                                                                             joint_efforts=None,
                                                                             joint_velocities=wheel_velocities))
        # 打印日志
        print("send_robot_actions method called")
        print("step_size: " + str(step_size))
        print("joint_positions: " +
              str(self._jetbot.get_joint_positions()))
        print("joint_velocities: " + str(wheel_velocities))

    def run(self, steps_to_simulate=2000):
        for i in range(steps_to_simulate):
            # 同步执行仿真物理步进和显示渲染步进
            self._world.step(render=True)

    def close(self):
        # 关闭仿真器
        simulation_app.close()


def main():
    # 创建HelloRobot实例
    hello_robot = HelloRobot()
    # 运行仿真
    hello_robot.run()
    # 关闭仿真器
    hello_robot.close()


if __name__ == "__main__":
    main()
