"""Sensors of the World (Isaac's `omni.isaac.sensor`): `Camera` (`manip.sim.sensors.camera`)."""

from __future__ import annotations

from manip.sim.sensors.camera import Camera

__all__ = ["Camera"]
