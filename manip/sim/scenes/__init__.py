"""The stage and the scene: prims on the stage (`stage`), compiled to one MuJoCo model (`mjcf_builder`, `compiler`); `Scene` (objects by name, the planner's view of them)."""
