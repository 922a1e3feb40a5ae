"""Prims with a pose: transforms, Visual/Fixed/Dynamic shapes and the ground plane.

This module gathers the object classes; each lives with its concept:

- `XFormPrim` (`manip.sim.prims.xform_prim`): a pose, new or wrapping a body of a referenced model;
- `GeometryPrim`, `PhysicsMaterial` (`manip.sim.prims.geometry_prim`): one geom, its friction;
- `RigidPrim` (`manip.sim.prims.rigid_prim`): velocities and mass of a free body;
- `VisualCuboid` ... `DynamicCone` (`manip.sim.objects.shapes`): the 15 shapes;
- `GroundPlane` (`manip.sim.objects.ground_plane`).

Objects have no parent transform: `/World` is the identity, so the local pose equals the
world pose.
"""

from __future__ import annotations

from manip.sim.prims.geometry_prim import GeometryPrim, PhysicsMaterial
from manip.sim.objects.ground_plane import GroundPlane
from manip.sim.prims.rigid_prim import RigidPrim
from manip.sim.objects.shapes import (
    DynamicCapsule,
    DynamicCone,
    DynamicCuboid,
    DynamicCylinder,
    DynamicSphere,
    FixedCapsule,
    FixedCone,
    FixedCuboid,
    FixedCylinder,
    FixedSphere,
    VisualCapsule,
    VisualCone,
    VisualCuboid,
    VisualCylinder,
    VisualSphere,
)
from manip.sim.prims.xform_prim import XFormPrim

__all__ = [
    "DynamicCapsule", "DynamicCone", "DynamicCuboid", "DynamicCylinder", "DynamicSphere",
    "FixedCapsule", "FixedCone", "FixedCuboid", "FixedCylinder", "FixedSphere",
    "GeometryPrim", "GroundPlane", "PhysicsMaterial", "RigidPrim",
    "VisualCapsule", "VisualCone", "VisualCuboid", "VisualCylinder", "VisualSphere",
    "XFormPrim",
]
