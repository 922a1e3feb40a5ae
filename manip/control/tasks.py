"""The controller's weighted tasks (mink): end-effector frame, posture, damping.

Each step minimises, over the joint displacement dq of the step,

    || W (J_frame dq + gain * e_frame) ||^2   (W = diag(position x3, orientation x3))
  + posture^2 * || dq + (q - q_rest) ||^2
  + damping^2 * || dq ||^2

(mink's `FrameTask`, `PostureTask` and `DampingTask`, whose costs multiply the residuals as
the weights do here; e_frame is the frame's pose error as a twist). Setting `orientation_weight = 0` (or giving a position-only target) lets the
orientation float. The frame task's Levenberg-Marquardt damping
(`frame_lm_damping * |e|^2` on the diagonal) keeps the step short when the target is
out of reach, where the Jacobian is nearly singular.
"""

from __future__ import annotations

from dataclasses import dataclass

import mink
import mujoco
import numpy as np

from manip.errors import InvalidInputError
from manip.validation import non_negative, positive


@dataclass(frozen=True)
class TaskWeights:
    """Weights of the controller's tasks (all >= 0; position + orientation > 0).

    Attributes:
        position: weight of the frame's position error [1/m] (default 1).
        orientation: weight of the frame's orientation error [1/rad] (default 0.5; 0 =
            position only).
        posture: weight pulling the arm towards its rest configuration (default 1e-2:
            resolves the redundancy without pulling the frame off the target).
        damping: weight of the joint displacement itself (default 1e-3: smooths steps near
            singularities).
        frame_gain: fraction of the frame error corrected per step, (0, 1] (default 1).
        frame_lm_damping: Levenberg-Marquardt damping of the frame task (default 1e-2).
    """

    position: float = 1.0
    orientation: float = 0.5
    posture: float = 1e-2
    damping: float = 1e-3
    frame_gain: float = 1.0
    frame_lm_damping: float = 1e-2

    def __post_init__(self) -> None:
        for name in ("position", "orientation", "posture", "damping", "frame_lm_damping"):
            object.__setattr__(self, name, non_negative(getattr(self, name), f"{name} weight"))
        g = positive(self.frame_gain, "frame_gain")
        if g > 1.0:
            raise InvalidInputError(f"frame_gain must be in (0, 1]; got {self.frame_gain!r}")
        object.__setattr__(self, "frame_gain", g)
        if self.position + self.orientation <= 0:
            raise InvalidInputError("position and orientation weights are both 0: the frame task would do nothing")


class Tasks:
    """The controller's tasks: mink's `FrameTask` for the end effector, and the posture and
    damping terms.

    The posture and damping terms are mink's `PostureTask` (J = I, e = q - q_rest) and
    `DampingTask` (J = I, e = 0), whose objectives are diagonal: they are added in closed
    form (w^2 I and w^2 e), which gives the same QP as the mink tasks (tested) in a few
    microseconds instead of tens.

    Args:
        model: the controller's MuJoCo model (hinge and slide joints only).
        frame_type, frame_id: the controlled frame ("site" or "body", id).
        rest: (nv,) the rest configuration of the posture term (model order).
        weights: the task weights.
    """

    def __init__(self, model: mujoco.MjModel, frame_type: str, frame_id: int, rest: np.ndarray, weights: TaskWeights):
        self.frame_type, self.frame_id = frame_type, frame_id
        self.frame = mink.FrameTask(frame_id, frame_type, position_cost=weights.position,
                                    orientation_cost=weights.orientation, gain=weights.frame_gain,
                                    lm_damping=weights.frame_lm_damping)
        self.rest = np.asarray(rest, dtype=float).copy()
        self.weights = weights
        self._position_only = False

    def set_weights(self, weights: TaskWeights) -> None:
        self.weights = weights
        self.frame.set_position_cost(weights.position)
        self.frame.set_orientation_cost(0.0 if self._position_only else weights.orientation)
        self.frame.gain = weights.frame_gain
        self.frame.lm_damping = weights.frame_lm_damping

    def set_rest(self, rest: np.ndarray) -> None:
        self.rest = np.asarray(rest, dtype=float).copy()

    def set_target(self, target: mink.SE3, position_only: bool) -> None:
        """The frame's target (base frame); `position_only` zeroes the orientation weight
        for this target."""
        if position_only != self._position_only:
            self._position_only = position_only
            self.frame.set_orientation_cost(0.0 if position_only else self.weights.orientation)
        self.frame.set_target(target)

    def objective(self, configuration: mink.Configuration, regularisation: float) -> tuple[np.ndarray, np.ndarray]:
        """(H, c) of the QP over dq: 1/2 dq' H dq + c' dq."""
        W, e, mu = self.frame.compute_qp_residual(configuration)
        H = W.T @ W
        c = -(e @ W)
        wp2 = self.weights.posture ** 2
        wd2 = self.weights.damping ** 2
        H.flat[:: H.shape[0] + 1] += mu + wp2 + wd2 + regularisation
        if wp2 > 0.0:
            c += wp2 * (configuration.data.qpos - self.rest)
        return H, c
