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
#: their joint-space distance from the start instead (shortest first; BENCHMARKS.md, "Constants").
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
