"""manip's own planner adapter for the benchmark driver (peers live in `benchmarks.peers`)."""
