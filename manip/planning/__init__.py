"""Planning: options, per-call context, validity, path search, shortcutting, the trajectory
optimiser, timing-and-validation, and the results they return."""

from __future__ import annotations

from manip.planning.grasp_plan import GraspPlan
from manip.planning.options import PlanOptions
from manip.planning.result import PlanResult, PlanStatus

__all__ = ["GraspPlan", "PlanOptions", "PlanResult", "PlanStatus"]
