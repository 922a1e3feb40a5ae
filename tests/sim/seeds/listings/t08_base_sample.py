"""Ported listing: base_example.py: Isaac's BaseSample, annotated.

From the tutorial 'Isaac Sim教程08 独立代码编程 (Herman Ye, Auromix)' (seed file 000_7a433f4238e67386.txt, lines 162-345).
Changed: only the imports (omni.isaac... / isaacsim... -> manip.sim, carb -> manip.sim.carb,
the cuRobo wrapper -> manip.TutorialMotionGen) and headless=True; the code is the tutorial's.
"""

# Copyright (c) 2018-2023, NVIDIA CORPORATION. All rights reserved.
#
# NVIDIA CORPORATION and its licensors retain all intellectual property
# and proprietary rights in and to this software, related documentation
# and any modifications thereto. Any use, reproduction, disclosure or
# distribution of this software and related documentation without an express
# license agreement from NVIDIA CORPORATION is strictly prohibited.
#

# 引入垃圾回收
import gc
# 引入抽象基类装饰器,以确保子类重写了父类中的抽象方法而不是直接继承父类的抽象方法
from abc import abstractmethod
# 引入World类
from manip.sim import World
# 引入Scene类
from manip.sim import Scene
# 引入创建和更新舞台Stage的异步方法
from manip.sim import create_new_stage_async, update_stage_async


class BaseSample(object):
    def __init__(self) -> None:
        # 初始化变量
        self._world = None
        self._current_tasks = None
        # 初始化世界设置
        self._world_settings = {"physics_dt": 1.0 / 60.0,
                                "stage_units_in_meters": 1.0, "rendering_dt": 1.0 / 60.0}
        # self._logging_info = ""
        return

    # 获取世界实例的方法
    def get_world(self):
        return self._world

    # 设置世界参数
    # 若该方法被调用且传入了参数,则更新世界对应的参数设置
    def set_world_settings(self, physics_dt=None, stage_units_in_meters=None, rendering_dt=None):

        if physics_dt is not None:
            self._world_settings["physics_dt"] = physics_dt
        if stage_units_in_meters is not None:
            self._world_settings["stage_units_in_meters"] = stage_units_in_meters
        if rendering_dt is not None:
            self._world_settings["rendering_dt"] = rendering_dt
        return

    # 当按下Load时调用的函数
    # 这是加载世界的异步方法
    async def load_world_async(self):
        """Function called when clicking load buttton"""
        # 检查是否已经实例化了世界
        if World.instance() is None:
            # 若没有实例化,则异步等待创建一个新的舞台Stage
            await create_new_stage_async()
            # 将self._world_settings字典中的参数键值对解包为关键字参数并用于创建世界实例
            self._world = World(**self._world_settings)
            # 初始化世界的仿真上下文
            await self._world.initialize_simulation_context_async()
            # 设置场景
            self.setup_scene()
        else:
            # 若已经实例化了世界,则直接获取世界实例
            self._world = World.instance()
        # 获取当前世界中的任务
        # Warning@HermanYe: 所有任务都应该在reset之前添加
        self._current_tasks = self._world.get_current_tasks()

        # 将舞台Stage重置为其初始状态,并将场景Scene中包含的每个对象重置为其默认状态
        await self._world.reset_async()
        # 将世界暂停
        await self._world.pause_async()
        # 在load世界的首次reset后,调用setup_post_load方法
        await self.setup_post_load()
        # 若存在任务,则将物理回调函数添加到世界中
        if len(self._current_tasks) > 0:
            # 在每次物理步进前调用的回调函数(回调名称,具体的回调函数)
            # self._world.step_async将会调用物理步进前应调用的所有函数
            self._world.add_physics_callback(
                "tasks_step", self._world.step_async)
        return

    # 当按下Reset时调用的函数
    # 这是重置世界的异步方法
    async def reset_async(self):
        """Function called when clicking reset buttton"""
        # 若世界中已经存在任务且已经构建了场景
        if self._world.is_tasks_scene_built() and len(self._current_tasks) > 0:
            # 移除名为tasks_step的回调函数
            self._world.remove_physics_callback("tasks_step")
        # 开始世界的Play
        await self._world.play_async()
        # 更新舞台Stage
        await update_stage_async()
        # 调用setup_pre_reset方法来完成重置之前需要的操作
        await self.setup_pre_reset()
        # 重置世界
        await self._world.reset_async()
        # 暂停世界
        await self._world.pause_async()
        # 调用setup_post_reset方法来完成重置之后需要的操作
        await self.setup_post_reset()
        # 若世界中已经存在任务且已经构建了场景
        if self._world.is_tasks_scene_built() and len(self._current_tasks) > 0:
            # 重新添加名为tasks_step的回调函数
            self._world.add_physics_callback(
                "tasks_step", self._world.step_async)
        return

    @abstractmethod
    def setup_scene(self, scene: Scene) -> None:
        """used to setup anything in the world, adding tasks happen here for instance.

        Args:
            scene (Scene): [description]
        """
        return

    @abstractmethod
    async def setup_post_load(self):
        """called after first reset of the world when pressing load,
        intializing provate variables happen here.
        """
        return

    @abstractmethod
    async def setup_pre_reset(self):
        """called in reset button before resetting the world
        to remove a physics callback for instance or a controller reset
        """
        return

    @abstractmethod
    async def setup_post_reset(self):
        """called in reset button after resetting the world which includes one step with rendering"""
        return

    @abstractmethod
    async def setup_post_clear(self):
        """called after clicking clear button
        or after creating a new stage and clearing the instance of the world with its callbacks
        """
        return

    # def log_info(self, info):
    #     self._logging_info += str(info) + "\n"
    #     return

    # 清理世界的方法
    def _world_cleanup(self):
        # 停止世界
        self._world.stop()
        # 清除所有的回调函数
        self._world.clear_all_callbacks()
        # 清除所有的当前任务
        self._current_tasks = None
        # 其他清理操作
        self.world_cleanup()
        return

    # 其他清理操作
    def world_cleanup(self):
        """Function called when extension shutdowns and starts again, (hot reloading feature)"""
        return

    # 异步清理
    async def clear_async(self):
        """Function called when clicking clear buttton"""
        # 创建一个新的舞台Stage
        await create_new_stage_async()
        # 若世界实例不为空
        if self._world is not None:
            # 清理世界
            self._world_cleanup()
            # 清除世界实例
            self._world.clear_instance()
            # 清除代表世界的变量
            self._world = None
            # 垃圾回收
            gc.collect()
        # 调用setup_post_clear方法来完成清理之后需要的操作
        await self.setup_post_clear()
        return
