"""Plots where people look rather than read (matplotlib, PNG; no viser needed).

`plot_joint_trajectory` draws a trajectory's joint positions, velocities, accelerations
and jerks against time, one panel per quantity and one line per joint, with each joint's
limits drawn as dashed lines of the same colour. `plot_benchmark_distributions` draws the
planning-time and motion-time distributions per planner of `benchmarks/mbm.py` results.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from manip.errors import InvalidInputError
from manip.trajectory import Trajectory

logger = logging.getLogger(__name__)

_QUANTITIES = (("positions", "position [rad]"), ("velocities", "velocity [rad/s]"),
               ("accelerations", "acceleration [rad/s²]"), ("jerks", "jerk [rad/s³]"))


def _figure(figsize: tuple[float, float]):
    """A matplotlib Figure drawn with Agg (no pyplot, no global backend change, no display)."""
    from matplotlib.figure import Figure

    return Figure(figsize=figsize)


def robot_limits(robot: Any) -> dict[str, np.ndarray]:
    """The limits to draw, from anything with `lower_limits`, `upper_limits`,
    `velocity_limits`, `acceleration_limits`, `jerk_limits` (a MotionGenerator, a RobotConfig)."""
    return {"lower": np.asarray(robot.lower_limits), "upper": np.asarray(robot.upper_limits),
            "velocity": np.asarray(robot.velocity_limits), "acceleration": np.asarray(robot.acceleration_limits),
            "jerk": np.asarray(robot.jerk_limits)}


def plot_joint_trajectory(trajectory: Trajectory | Sequence[Trajectory], path: str | Path, *,
                          limits: Mapping[str, np.ndarray] | None = None, title: str = "") -> Path:
    """Write a PNG of joint position, velocity, acceleration and jerk against time.

    Args:
        trajectory: one trajectory, or several played one after the other (e.g. the
            motions of a pick-and-place episode; their times are chained).
        path: output PNG file.
        limits: per-quantity limits, each (dof,): "lower", "upper" [rad] (positions),
            "velocity" [rad/s], "acceleration" [rad/s^2], "jerk" [rad/s^3] (symmetric);
            missing keys are not drawn.
        title: figure title.

    Returns:
        The path written.

    Raises:
        InvalidInputError: no trajectory, trajectories with different joints, or limits of
            the wrong size.
    """
    trajs = [trajectory] if isinstance(trajectory, Trajectory) else list(trajectory)
    if not trajs or not all(isinstance(t, Trajectory) for t in trajs):
        raise InvalidInputError("plot_joint_trajectory needs a Trajectory or a non-empty list of them")
    names = trajs[0].joint_names
    if any(t.joint_names != names for t in trajs):
        raise InvalidInputError("the trajectories to plot must have the same joints")
    limits = dict(limits or {})
    for key, value in limits.items():
        if key not in ("lower", "upper", "velocity", "acceleration", "jerk"):
            raise InvalidInputError(f"unknown limit '{key}'; valid: lower, upper, velocity, acceleration, jerk")
        if np.shape(value) != (len(names),):
            raise InvalidInputError(f"limits['{key}'] must have {len(names)} entries (one per joint)")
    times, offset = [], 0.0
    for t in trajs:
        times.append(t.times + offset)
        offset += t.duration
    time_all = np.concatenate(times)
    import matplotlib

    fig = _figure((10, 11))
    axes = fig.subplots(4, 1, sharex=True)
    colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    bounds = {"positions": ("lower", "upper"), "velocities": ("velocity",), "accelerations": ("acceleration",),
              "jerks": ("jerk",)}
    for ax, (attr, label) in zip(axes, _QUANTITIES):
        values = np.concatenate([getattr(t, attr) for t in trajs])
        for j, name in enumerate(names):
            c = colors[j % len(colors)]
            ax.plot(time_all, values[:, j], color=c, lw=1.2, label=name)
            for key in bounds[attr]:
                if key in limits:
                    lim = float(limits[key][j])
                    for v in ((lim,) if attr == "positions" else (lim, -lim)):
                        ax.axhline(v, color=c, lw=0.8, ls="--", alpha=0.6)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    for boundary in np.cumsum([t.duration for t in trajs])[:-1]:
        for ax in axes:
            ax.axvline(boundary, color="k", lw=0.5, alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=7, ncol=min(len(names), 4))
    axes[-1].set_xlabel("time [s]")
    return _save(fig, path, title or "joint trajectory (dashed: limits)")


def plot_benchmark_distributions(samples: Mapping[str, Mapping[str, Sequence[float]]], path: str | Path, *,
                                 title: str = "") -> Path:
    """Write a PNG of planning-time and motion-time distributions per planner.

    Args:
        samples: {planner: {"planning_time": [s, ...], "motion_time": [s, ...]}} over the
            solved problems.
        path: output PNG file.
        title: figure title.

    Returns:
        The path written.

    Raises:
        InvalidInputError: no planner, or a planner without both lists.
    """
    if not samples:
        raise InvalidInputError("plot_benchmark_distributions needs at least one planner's samples")
    for planner, s in samples.items():
        missing = {"planning_time", "motion_time"} - set(s)
        if missing:
            raise InvalidInputError(f"planner '{planner}': missing {sorted(missing)}")
    fig = _figure((11, 4.5))
    axes = fig.subplots(1, 2)
    planners = list(samples)
    for ax, key, label, log in ((axes[0], "planning_time", "planning time [s]", True),
                                (axes[1], "motion_time", "motion time [s]", False)):
        data = [np.asarray(samples[p][key], dtype=float) for p in planners]
        data = [d[np.isfinite(d)] for d in data]
        if all(d.size > 1 for d in data):
            ax.violinplot(data, showmedians=True)
        ax.boxplot([d if d.size else np.array([np.nan]) for d in data], widths=0.15, showfliers=False)
        ax.set_xticks(range(1, len(planners) + 1),
                      [f"{p}\n(n={d.size})" for p, d in zip(planners, data)])
        if log:
            ax.set_yscale("log")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, axis="y")
    return _save(fig, path, title or "MotionBenchMaker: distributions over solved problems")


def _save(fig, path: str | Path, title: str) -> Path:
    """Title, lay out and write `fig` as a PNG at `path`; the path written."""
    fig.suptitle(title)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=90)
    logger.info("wrote %s", path)
    return path
