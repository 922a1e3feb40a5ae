"""Constraints on the configuration kept over the whole continuous motion of a plan.

`Constraint` (`base`: the interface a new constraint implements), `OrientationConstraint`,
`PositionConstraint`, `RelativePoseConstraint` (two links' relative pose, e.g. two hands); `certify_constraints` (the certificate between samples) and
`project` (onto the allowed set) are what the planner builds on them.
"""

from __future__ import annotations

from manip.constraints.base import Constraint
from manip.constraints.certify import ConstraintCertificate, certify_constraints, segments_hold, trajectory_deviation
from manip.constraints.orientation import OrientationConstraint
from manip.constraints.position import PositionConstraint
from manip.constraints.projection import project, satisfied
from manip.constraints.relative import RelativePoseConstraint

__all__ = [
    "Constraint",
    "ConstraintCertificate",
    "OrientationConstraint",
    "PositionConstraint",
    "RelativePoseConstraint",
    "certify_constraints",
    "project",
    "satisfied",
    "segments_hold",
    "trajectory_deviation",
]
