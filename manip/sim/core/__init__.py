"""The engine: `SimulationApp`, `SimulationContext` and `World` (time stepping, callbacks), Isaac's `carb` logging, offscreen rendering (`gl_backend`, `recording`)."""
