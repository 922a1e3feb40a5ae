"""Inverse kinematics: damped least squares (Levenberg-Marquardt) with joint limits and restarts.

- `IKSolver` (`manip.ik.solver`): `solve` (one goal), `solve_batch` (a batched Pose, in
  NumPy, `manip.ik.batch`) and `solve_many` (several distinct solutions of one goal).
- `manip.ik.goalset`: cuRobo's `solve_goalset` / `solve_batch_goalset` (one pose of a set
  reached, `goalset_index` says which), `GoalsetIKResult`.
- Results (`manip.ik.result`): `IKResult`, `BatchIKResult`, `IKSolutions`, and `IKStatus`
  whose `hint` says what to change.
- `manip.ik.kernels`: the compiled (numba) descent and the rotation logarithm.
- `manip.ik.position`: position-only IK (`solve_position`: a frame's origin to a point, any
  orientation), for Isaac's `compute_inverse_kinematics` without a target orientation.
"""

from __future__ import annotations

from manip.ik.goalset import GoalsetIKResult
from manip.ik.result import BatchIKResult, IKResult, IKSolutions, IKStatus, ValidityFn
from manip.ik.solver import IKSolver

__all__ = ["BatchIKResult", "GoalsetIKResult", "IKResult", "IKSolutions", "IKSolver", "IKStatus", "ValidityFn"]
