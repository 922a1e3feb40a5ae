"""Articulations: `Articulation` (Isaac's SingleArticulation), its `ArticulationView`, the compiled model's view of it (`articulation_core`) and the DOF properties."""
