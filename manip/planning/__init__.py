"""Path planning: results, sampling-based search, shortcutting and path optimisation."""

from __future__ import annotations

from manip.planning.result import PlanResult, PlanStatus

__all__ = ["PlanResult", "PlanStatus"]
