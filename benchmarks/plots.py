"""Plots of `benchmarks/mbm.py` runs: planning-time and motion-time distributions per planner.

    python benchmarks/mbm.py ... --plot mbm.png           # after planning
    python benchmarks/mbm.py --from-json run.json --plot mbm.png

Each box/violin is one planner (with its run label, e.g. "manip (before)") over the
problems it solved with a verified trajectory; planning time on a log scale.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from manip.viz.plots import plot_benchmark_distributions


def samples_by_planner(runs: Iterable[Mapping[str, Any]]) -> dict[str, dict[str, list[float]]]:
    """{planner (label): {"planning_time": [s], "motion_time": [s]}} over verified runs."""
    out: dict[str, dict[str, list[float]]] = {}
    for r in runs:
        name = r["planner"] + (f" ({r['label']})" if r.get("label") else "")
        s = out.setdefault(name, {"planning_time": [], "motion_time": []})
        if r["verified"]:
            s["planning_time"].append(float(r["plan_time_s"]))
            s["motion_time"].append(float(r["motion_time_s"]))
    return out


def plot_mbm(runs: Iterable[Mapping[str, Any]], path: str | Path, title: str = "") -> Path:
    """Write the distributions of `runs` (as in mbm.py's JSON "runs") to a PNG; prints where."""
    samples = samples_by_planner(runs)
    if not samples:
        raise SystemExit("--plot: no runs to plot (a --from-json report must have been saved with its runs)")
    out = plot_benchmark_distributions(samples, path, title=title)
    print(f"wrote {out}")
    return out
