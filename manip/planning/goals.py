"""The order in which a plan tries the goal configurations of a pose or a goal set.

Goals are ranked by the motion they allow: the time-optimal rest-to-rest duration from the
start under the call's limits (a lower bound of any motion to that goal), and among the goals
within `TIME_BAND` of the fastest, the shortest straight line in joint space first.
"""

from __future__ import annotations

import numpy as np

from manip.limits import JointLimits
from manip.timing.bounds import rest_to_rest_time

#: Goals whose lower-bound duration is within this fraction of the fastest one's are ranked by
#: their joint-space distance from the start instead (shortest first). 0.05 against 0 (the
#: fastest first), MotionBenchMaker pose goals, whole plans, 8/scene twice (problems 0-7 with
#: the robot's limits, 8-15 with cuRobo's; ~50 each): path length -1.3 / -1.5 %, motion time
#: +0.2 / -0.7 %; 0.02: path -1.2 / -0.3 %, motion +0.05 / +0.2 %; 0.10: path -1.8 / -2.0 %,
#: motion +0.7 / +0.1 %. (Among the ~13 IK solutions of a pose, the shortest is 3 % shorter
#: than the fastest one on average, and its bound 0.3 % longer.) With the IK solutions also
#: offered moved along their self-motion towards the start (`IKSolver.solve_many(toward_seed=True)`),
#: 0.10 against 0.05, 8/scene three times (problems 0-7, 8-15 with cuRobo's limits, 16-23): path
#: -1.0 / -0.7 / -0.8 %, motion time +0.25 / +0.6 / +0.5 %.
TIME_BAND = 0.10


def order_goals(start: np.ndarray, configs: np.ndarray, limits: JointLimits) -> np.ndarray:
    """Indices of `configs` (G, dof) in the order a plan tries them (see the module docstring).

    Args:
        start: (dof,) start configuration [rad].
        configs: (G, dof) goal configurations [rad].
        limits: the call's limits (`PlanContext.scaled_limits`).

    Returns:
        (G,) a permutation of range(G).
    """
    bounds = np.array([rest_to_rest_time(start, q, limits) for q in configs])
    lengths = np.linalg.norm(configs - start, axis=1)
    near = bounds <= bounds.min() * (1.0 + TIME_BAND)
    # near goals first, by length; then the others, by their bound (stable: ties keep IK order)
    key = np.where(near, 0.0, 1.0)
    return np.lexsort((np.arange(len(configs)), np.where(near, lengths, bounds), key))
