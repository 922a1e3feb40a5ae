"""Prims with a pose: `XFormPrim`, `RigidPrim`, `GeometryPrim` and the batched views (`RigidPrimView`, `XFormPrimView`)."""
