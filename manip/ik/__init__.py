"""Inverse kinematics: damped least squares (Levenberg-Marquardt) with joint limits and restarts.

- `IKSolver` (`manip.ik.solver`): `solve` (one goal), `solve_batch` (a batched Pose, in
  NumPy, `manip.ik.batch`) and `solve_many` (several distinct solutions of one goal).
- Results (`manip.ik.result`): `IKResult`, `BatchIKResult`, `IKSolutions`, and `IKStatus`
  whose `hint` says what to change.
- `manip.ik.kernels`: the compiled (numba) descent and the rotation logarithm.
- `manip.ik.position`: position-only IK (`solve_position`: a frame's origin to a point, any
  orientation), for Isaac's `compute_inverse_kinematics` without a target orientation.
"""

from __future__ import annotations

from manip.ik.result import BatchIKResult, IKResult, IKSolutions, IKStatus
from manip.ik.solver import IKSolver
from manip.ik.result import ValidityFn

__all__ = ["BatchIKResult", "IKResult", "IKSolutions", "IKSolver", "IKStatus", "ValidityFn"]
