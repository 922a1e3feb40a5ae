"""Tasks: `BaseTask` and `PickPlace` (`base_task`), the World's task registry, `FollowTarget`, `Stacking`."""
