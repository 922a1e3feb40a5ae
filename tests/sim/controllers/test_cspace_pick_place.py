"""Isaac's generic PickPlaceController (the manipulators extension's), driving a given c-space
controller: its signatures (by keyword, by position, subclassed), phases and errors."""

from __future__ import annotations

import numpy as np
import pytest

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim import BaseController, PickPlaceController


class Recorder(BaseController):
    """A c-space controller that records the end-effector targets it is given."""

    def __init__(self):
        super().__init__("recorder")
        self.targets, self.resets = [], 0

    def forward(self, target_end_effector_position, target_end_effector_orientation=None):
        self.targets.append((np.array(target_end_effector_position), np.array(target_end_effector_orientation)))
        return ArticulationAction(joint_positions=np.zeros(9))

    def reset(self):
        self.resets += 1


class Gripper:
    def forward(self, action):
        return ArticulationAction(joint_positions=np.full(9, 1.0 if action == "close" else 2.0))


def run(controller, calls):
    actions = []
    for _ in range(calls):
        actions.append(controller.forward(picking_position=[0.4, 0.1, 0.03], placing_position=[-0.3, -0.3, 0.05],
                                          current_joint_positions=np.zeros(9)))
        if controller.is_done():
            break
    return actions


@pytest.mark.parametrize("make", [
    lambda c, g: PickPlaceController(name="pp", cspace_controller=c, gripper=g, events_dt=[0.5] * 10),
    lambda c, g: PickPlaceController("pp", c, g, 0.3, [0.5] * 10),   # Isaac's positional order
])
def test_the_phases_drive_the_cspace_controller_and_the_gripper(make):
    cspace, gripper = Recorder(), Gripper()
    controller = make(cspace, gripper)
    actions = run(controller, 100)
    assert controller.is_done() and len(actions) == 20        # 10 phases of 2 calls
    heights = [t[0][2] for t in cspace.targets]
    assert heights[0] == pytest.approx(0.3)                   # h1 above the pick position
    np.testing.assert_allclose(cspace.targets[0][0][:2], [0.4, 0.1])
    np.testing.assert_allclose(cspace.targets[0][1], [0, 0, 1, 0])   # Isaac's default orientation
    assert min(heights) == pytest.approx(0.03)                # down to the pick height
    assert cspace.targets[-1][0] == pytest.approx([-0.3, -0.3, 0.3])  # ends at h1 above the place position
    assert np.all(actions[6].joint_positions == 1.0) and np.all(actions[14].joint_positions == 2.0)  # close, open
    assert np.all(np.isnan(actions[4].joint_positions))       # phase 2: wait
    controller.reset()
    assert cspace.resets == 1 and controller.get_current_event() == 0 and not controller.is_done()


def test_a_subclass_as_in_isaacs_new_manipulator_tutorial():
    class MyPickPlace(PickPlaceController):
        def __init__(self, name, gripper, cspace):
            super().__init__(name=name, cspace_controller=cspace, gripper=gripper, events_dt=[1.0] * 10,
                             end_effector_initial_height=0.6)

    cspace = Recorder()
    controller = MyPickPlace("mine", Gripper(), cspace)
    run(controller, 20)
    assert controller.is_done() and cspace.targets[0][0][2] == pytest.approx(0.6)
    assert controller.failure is None


def test_bad_arguments_say_what_is_wrong():
    with pytest.raises(InvalidInputError, match="gripper must have forward"):
        PickPlaceController(name="pp", cspace_controller=Recorder(), gripper=object())
    with pytest.raises(InvalidInputError, match="events_dt must be 10 numbers"):
        PickPlaceController(name="pp", cspace_controller=Recorder(), gripper=Gripper(), events_dt=[0.1] * 9)
    with pytest.raises(InvalidInputError, match="needs gripper and robot_articulation"):
        PickPlaceController(name="pp")
