"""A robot's pose can be read and set before the first reset (issue 32, item 1): Isaac's
"Adding Multiple Robots" moves a Franka in `set_up_scene`, right after `scene.add`."""

from __future__ import annotations

import numpy as np

from manip.sim import BaseTask, Franka, RigidPrim, World, XFormPrim


def test_a_franka_pose_is_read_and_set_before_the_first_reset():
    world = World()
    franka = world.scene.add(Franka(prim_path="/World/Franka", name="franka"))
    p, q = franka.get_world_pose()  # was TypeError: None
    np.testing.assert_array_equal(p, [0, 0, 0])
    np.testing.assert_array_equal(q, [1, 0, 0, 0])
    franka.set_world_pose(position=[1.0, 0.0, 0.0])  # was SimulationError: not compiled yet
    np.testing.assert_array_equal(franka.get_world_pose()[0], [1.0, 0.0, 0.0])
    franka.set_default_state(position=[1.0, 0.0, 0.0])  # what the tutorial does too
    world.reset()
    np.testing.assert_allclose(franka.get_world_pose()[0], [1.0, 0.0, 0.0], atol=1e-12)
    sim = world.physics_sim_view
    link0 = sim.data.xpos[sim.model.body("/World/Franka/panda_link0").id]
    np.testing.assert_allclose(link0, [1.0, 0.0, 0.0], atol=1e-9)  # the simulated robot is there


def test_without_a_new_default_state_a_reset_restores_the_construction_pose_as_isaac():
    world = World()
    franka = world.scene.add(Franka(prim_path="/World/Franka", name="franka", position=[0.0, 0.5, 0.0]))
    franka.set_world_pose(position=[2.0, 0.0, 0.0])
    world.reset()
    np.testing.assert_allclose(franka.get_world_pose()[0], [0.0, 0.5, 0.0], atol=1e-12)


def test_a_task_moving_its_robots_in_set_up_scene():
    class TwoFrankas(BaseTask):
        def set_up_scene(self, scene):
            super().set_up_scene(scene)
            self.a = scene.add(Franka(prim_path="/World/A", name="a"))
            self.b = scene.add(Franka(prim_path="/World/B", name="b"))
            p, _ = self.b.get_world_pose()
            self.b.set_world_pose(position=p + np.array([0.0, 1.0, 0.0]))
            self.b.set_default_state(position=p + np.array([0.0, 1.0, 0.0]))

    world = World()
    task = TwoFrankas(name="two")
    world.add_task(task)
    world.reset()
    for _ in range(30):
        world.step(render=False)
    np.testing.assert_allclose(task.b.get_world_pose()[0], [0.0, 1.0, 0.0], atol=1e-12)
    hand_a, hand_b = (task.a.end_effector.get_world_pose()[0], task.b.end_effector.get_world_pose()[0])
    np.testing.assert_allclose(hand_b - hand_a, [0.0, 1.0, 0.0], atol=1e-3)  # same arm, one metre apart


def test_a_link_pose_before_the_first_reset_is_where_the_reset_puts_it():
    world = World()
    world.scene.add(Franka(prim_path="/World/Franka", name="franka", position=[0.3, -0.2, 0.1]))
    hand = world.scene.add(RigidPrim("/World/Franka/panda_hand", name="hand"))
    tcp = XFormPrim("/World/Franka/panda_hand_tcp", name="tcp")  # a site
    before = hand.get_world_pose()
    before_tcp = tcp.get_world_pose()
    np.testing.assert_array_equal(hand.get_linear_velocity(), np.zeros(3))
    world.reset()
    after = hand.get_world_pose()
    np.testing.assert_allclose(before[0], after[0], atol=1e-6)
    np.testing.assert_allclose(np.abs(before[1] @ after[1]), 1.0, atol=1e-9)
    np.testing.assert_allclose(before_tcp[0], tcp.get_world_pose()[0], atol=1e-6)
