"""Path planning: joint-space polylines from a start to goal configurations (no timing).

- `goals`: the order in which a plan tries goal configurations.
- `search`: the straight line, else RRT-Connect (`rrt_connect`), and the repair of a path's
  segments that fail a stricter check.
- `shortcut`: shortening a valid path; `restarts`: a shorter way round a detour.
- `smoothing`: optional clearance smoothing of a shortened path.
- `linear`: a straight tool-space line (approach, retreat) through dense IK.
"""
