"""manip.control: reactive control, differential inverse kinematics as a QP per step (mink).

`ReactiveController.step(q, target, dt)` moves the arm's end-effector frame towards a
target that may move at every step, within the joint position and velocity limits, and
keeps the robot `safety_margin` away from the world's obstacles and from itself. It needs
no simulator; `manip.sim.RMPFlowController` wraps it under Isaac Sim's name.

- `manip.control.controller`: `ReactiveController`.
- `manip.control.tasks`: the weighted tasks (`TaskWeights`).
- `manip.control.collision`: the collision-avoidance limit (`CollisionLimit`).
- `manip.control.model`: the controller's MuJoCo model of the robot and obstacles.
- `manip.control.obstacles`: planner shapes as MuJoCo geoms.
- `manip.control.targets`: accepted target forms.
- `manip.control.solvers`: the QP solve (qpsolvers; DAQP by default).
- `manip.control.results`: `StepResult`, `StepStatus`.
- `manip.control.progress`: stall detection (`StepStatus.STALLED`).
"""

from __future__ import annotations

from manip.control.controller import ReactiveController
from manip.control.model import UnknownFrameError
from manip.control.results import StepResult, StepStatus
from manip.control.solvers import DEFAULT_SOLVER
from manip.control.tasks import TaskWeights

__all__ = ["DEFAULT_SOLVER", "ReactiveController", "StepResult", "StepStatus", "TaskWeights", "UnknownFrameError"]
