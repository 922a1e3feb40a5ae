"""Ported listing: standalone My controller: a custom differential controller.

From the tutorial 'Isaac Sim教程08 独立代码编程 (Herman Ye, Auromix)' (seed file 000_7a433f4238e67386.txt, lines 801-925).
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
# 引入控制器的基类
from manip.sim import BaseController
# 引入日志相关,Carbonite含有Omniverse的日志系统
from manip.sim import carb
# 引入numpy
import numpy as np


class MyController(BaseController):
    def __init__(self):
        super().__init__(name="my_cool_controller")
        # 双轮模型的开环控制器
        self._wheel_radius = 0.03
        self._wheel_base = 0.1125
        return

    def forward(self, command):
        # 具体的控制器实现
        joint_velocities = [0.0, 0.0]
        joint_velocities[0] = (
            (2 * command[0]) - (command[1] * self._wheel_base)) / (2 * self._wheel_radius)
        joint_velocities[1] = (
            (2 * command[0]) + (command[1] * self._wheel_base)) / (2 * self._wheel_radius)
        # 返还ArticulationAction对象
        return ArticulationAction(joint_velocities=joint_velocities)


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
        # 自定义机器人控制器
        self._my_controller = MyController()

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
        # 自定义速度指令的格式为[前进速度,角速度]
        my_velocity_control_command = [0.5, np.pi / 4]
        # 应用自定义控制器计算出的动作
        self._jetbot.apply_action(self._my_controller.forward(
            command=my_velocity_control_command))

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
