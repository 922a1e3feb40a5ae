"""`Trajectory` (samples every `dt` [s], exact in between when it carries a profile) and `sample_times`.

The simulator bridge methods delegate to `manip.sim_bridge` (duck-typed, simulator-free).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from manip import curobo_names
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim_bridge import joint_indices_for, trajectory_to_actions
from manip.trajectory.profiles import PiecewiseJerkProfile, readonly
from manip.trajectory.spline import PathProfile
from manip.validation import as_real_array, non_negative, positive, sample_count

# Relative tolerance used to decide that two times are "the same" (sample grids).
_TIME_EPS = 1e-9


def sample_times(duration: float, dt: float) -> np.ndarray:
    """The sample grid of a trajectory: 0, dt, 2 dt, ..., ending exactly at `duration`.

    If `duration` is not a multiple of `dt` (within 1e-9 relative), the last step is
    shorter than `dt`.

    Args:
        duration: total time [s], >= 0.
        dt: sample period [s], > 0.

    Returns:
        (T,) times [s], T >= 1.
    """
    dt = positive(dt, "dt", "s")
    duration = non_negative(duration, "duration", "s")
    sample_count(duration, dt, "dt")
    n = int(np.ceil(duration / dt - _TIME_EPS))
    times = np.arange(n + 1, dtype=float) * dt
    times[-1] = duration
    return times


def _as_matrix(values: Any, name: str, shape: tuple[int, int]) -> np.ndarray:
    a = np.array(values, dtype=float)
    if a.shape != shape:
        raise InvalidInputError(f"Trajectory.{name} must have shape {shape} (T, dof); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"Trajectory.{name} has non-finite entries")
    return readonly(a)


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A timed joint-space trajectory sampled every `dt`, starting at t = 0.

    Arrays are read-only copies. `times[-1] == duration`; all steps equal `dt` except
    possibly the last, which may be shorter.

    Args:
        times: (T,) sample times [s], starting at 0, increasing.
        positions: (T, dof) joint positions [rad].
        velocities: (T, dof) joint velocities [rad/s].
        accelerations: (T, dof) joint accelerations [rad/s^2].
        jerks: (T, dof) joint jerks [rad/s^3] (right-continuous values of the profile:
            at a sample that falls on a jerk switch, the jerk that starts there; 0 at the
            final sample, where the motion has ended).
        dt: sample period [s].
        joint_names: (dof,) names of the joints, in column order.
        profile: the exact motion the samples were taken from (a `PiecewiseJerkProfile`
            from `time_parameterize`, or a `PathProfile` from `time_parameterize_dense`),
            or None for a trajectory known only by its samples.
    """

    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray
    jerks: np.ndarray
    dt: float
    joint_names: tuple[str, ...]
    profile: PiecewiseJerkProfile | PathProfile | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        times = np.array(self.times, dtype=float)
        if times.ndim != 1 or times.size < 1:
            raise InvalidInputError(f"Trajectory.times must have shape (T,), T >= 1; got {times.shape}")
        if not np.all(np.isfinite(times)):
            raise InvalidInputError("Trajectory.times has non-finite entries")
        dt = positive(self.dt, "Trajectory.dt", "s")
        if times[0] != 0.0:
            raise InvalidInputError(f"Trajectory.times must start at 0; got {times[0]}")
        steps = np.diff(times)
        if np.any(steps <= 0):
            raise InvalidInputError("Trajectory.times must be strictly increasing")
        tol = _TIME_EPS * max(1.0, float(times[-1])) + 1e-12
        if steps.size and (np.any(np.abs(steps[:-1] - dt) > tol) or steps[-1] > dt + tol):
            raise InvalidInputError(
                f"Trajectory.times must be spaced by dt = {dt} s (the last step may be shorter); "
                f"got steps in [{steps.min()}, {steps.max()}]"
            )
        names = tuple(str(n) for n in self.joint_names)
        pos = np.array(self.positions, dtype=float)
        if pos.ndim != 2 or pos.shape[0] != times.size:
            raise InvalidInputError(
                f"Trajectory.positions must have shape (T, dof) = ({times.size}, dof); got {pos.shape}"
            )
        shape = (times.size, pos.shape[1])
        if len(names) != shape[1]:
            raise InvalidInputError(
                f"Trajectory.joint_names has {len(names)} names for {shape[1]} joints: {names}"
            )
        if len(set(names)) != len(names):
            raise InvalidInputError(f"Trajectory.joint_names has duplicates: {names}")
        object.__setattr__(self, "times", readonly(times))
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "joint_names", names)
        for name in ("positions", "velocities", "accelerations", "jerks"):
            object.__setattr__(self, name, _as_matrix(getattr(self, name), name, shape))
        if self.profile is not None:
            if not isinstance(self.profile, (PiecewiseJerkProfile, PathProfile)) or self.profile.dof != shape[1]:
                raise InvalidInputError(
                    f"Trajectory.profile must be a PiecewiseJerkProfile or PathProfile with {shape[1]} joints"
                )
            if abs(self.profile.duration - times[-1]) > tol:
                raise InvalidInputError(
                    f"Trajectory.profile lasts {self.profile.duration} s but the samples end at {times[-1]} s"
                )

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_profile(
        cls, profile: PiecewiseJerkProfile | PathProfile, dt: float, joint_names: Sequence[str]
    ) -> Trajectory:
        """Sample an exact profile every `dt` (last sample at its end).

        Args:
            profile: the motion.
            dt: sample period [s].
            joint_names: (dof,) joint names.
        """
        times = sample_times(profile.duration, dt)
        q, qd, qdd, qddd = profile.evaluate(times)
        return cls(times, q, qd, qdd, qddd, dt, tuple(joint_names), profile)

    # ------------------------------------------------------------------ properties
    @property
    def duration(self) -> float:
        """Total time [s] (= times[-1])."""
        return float(self.times[-1])

    @property
    def dof(self) -> int:
        """Number of joints."""
        return int(self.positions.shape[1])

    @property
    def num_samples(self) -> int:
        """Number of samples T."""
        return int(self.times.size)

    @property
    def start(self) -> np.ndarray:
        """(dof,) first configuration [rad]."""
        return self.positions[0]

    @property
    def goal(self) -> np.ndarray:
        """(dof,) last configuration [rad]."""
        return self.positions[-1]

    # ------------------------------------------------------------------ evaluation
    def at_time(self, t: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Joint state at time `t`, clamped to [0, duration].

        Exact (from the trajectory's profile) when the trajectory has one;
        otherwise positions are cubic Hermite interpolated from the sampled positions and
        velocities, and velocities/accelerations linearly interpolated.

        Args:
            t: scalar or (N,) times [s]; values outside [0, duration] are clamped (the
                robot is at rest at both ends, so this is the physical state).

        Returns:
            (q, qd, qdd): each (dof,) for scalar `t`, else (N, dof), in [rad], [rad/s],
            [rad/s^2].
        """
        try:
            t_arr = as_real_array(t, "t")
        except InvalidInputError as exc:
            text = repr(t) if len(repr(t)) <= 80 else repr(t)[:80] + "..."
            raise InvalidInputError(f"at_time: t must be a time [s] or an (N,) array of times, real numbers; got "
                                    f"{text} ({type(t).__name__})") from exc
        if t_arr.ndim > 1:
            raise InvalidInputError(f"at_time: t must be a time [s] or an (N,) array of times; got an array of "
                                    f"shape {t_arr.shape}")
        if not np.all(np.isfinite(t_arr)):
            raise InvalidInputError(f"at_time: t must be finite times [s]; got {t}")
        if self.profile is not None:
            q, qd, qdd, _ = self.profile.evaluate(t_arr)
            return q, qd, qdd
        return self._interpolate(t_arr)

    def _interpolate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        scalar = t.ndim == 0
        ts = np.clip(np.atleast_1d(t), 0.0, self.duration)
        if self.times.size == 1:
            reps = (ts.size, 1)
            out = tuple(np.tile(a[0], reps) for a in (self.positions, self.velocities, self.accelerations))
        else:
            i = np.clip(np.searchsorted(self.times, ts, side="right") - 1, 0, self.times.size - 2)
            h = (self.times[i + 1] - self.times[i])[:, None]
            s = ((ts - self.times[i])[:, None]) / h
            p0, p1 = self.positions[i], self.positions[i + 1]
            m0, m1 = self.velocities[i] * h, self.velocities[i + 1] * h
            h00 = 2 * s**3 - 3 * s**2 + 1
            h10 = s**3 - 2 * s**2 + s
            h01 = -2 * s**3 + 3 * s**2
            h11 = s**3 - s**2
            q = h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1
            qd = (1 - s) * self.velocities[i] + s * self.velocities[i + 1]
            qdd = (1 - s) * self.accelerations[i] + s * self.accelerations[i + 1]
            out = (q, qd, qdd)
        if scalar:
            return tuple(o[0] for o in out)  # type: ignore[return-value]
        return out  # type: ignore[return-value]

    def resample(self, dt: float) -> Trajectory:
        """The same motion sampled every `dt` [s] (same duration; last step may be shorter).

        Exact when the trajectory has a profile; otherwise interpolated as in `at_time`
        (jerks then come from finite differences of the interpolated accelerations).
        """
        if self.profile is not None:
            return Trajectory.from_profile(self.profile, dt, self.joint_names)
        times = sample_times(self.duration, dt)
        q, qd, qdd = self._interpolate(times)
        jerk = np.zeros_like(qdd)
        if times.size > 1:
            jerk[:-1] = np.diff(qdd, axis=0) / np.diff(times)[:, None]
        return Trajectory(times, q, qd, qdd, jerk, dt, self.joint_names, None)

    # ------------------------------------------------------------------ quality measures
    def path_length(self) -> float:
        """Sum of joint-space Euclidean step lengths between samples [rad]."""
        return float(np.linalg.norm(np.diff(self.positions, axis=0), axis=1).sum())

    def _extreme(self, key: str, samples: np.ndarray) -> np.ndarray:
        if self.profile is not None:
            return self.profile.extrema()[key]
        return np.abs(samples).max(axis=0)

    def max_abs_velocity(self) -> np.ndarray:
        """(dof,) largest |velocity| [rad/s] (exact over the profile when present, else over samples)."""
        return self._extreme("max_abs_velocity", self.velocities)

    def max_abs_acceleration(self) -> np.ndarray:
        """(dof,) largest |acceleration| [rad/s^2] (exact over the profile when present)."""
        return self._extreme("max_abs_acceleration", self.accelerations)

    def max_abs_jerk(self) -> np.ndarray:
        """(dof,) largest |jerk| [rad/s^3] (exact over the profile when present)."""
        return self._extreme("max_abs_jerk", self.jerks)

    def position_range(self) -> tuple[np.ndarray, np.ndarray]:
        """((dof,), (dof,)) smallest and largest position of each joint [rad] (exact over the profile when present)."""
        if self.profile is not None:
            e = self.profile.extrema()
            return e["position_min"], e["position_max"]
        return self.positions.min(axis=0), self.positions.max(axis=0)

    # ------------------------------------------------------------------ simulator bridge
    def joint_indices_for(self, robot: Any) -> np.ndarray:
        """(dof,) indices of `joint_names` among a robot's DoFs (`manip.sim_bridge.joint_indices_for`)."""
        return joint_indices_for(self, robot)

    def to_articulation_actions(self, robot: Any, physics_dt: float | None = None, *,
                                prefix: str | None = None) -> list[ArticulationAction]:
        """One `ArticulationAction` per step after t = 0 (`manip.sim_bridge.trajectory_to_actions`);
        a multi-arm robot's trajectory gives each simulated arm its own joints' actions (`prefix`:
        which arm; default the one the robot's name names, `manip.sim_bridge.robot_columns`)."""
        return trajectory_to_actions(self, robot, physics_dt, prefix=prefix)

    def __repr__(self) -> str:
        return (
            f"Trajectory(duration={self.duration:.4f} s, samples={self.num_samples}, dt={self.dt:.6g} s, "
            f"joints={list(self.joint_names)})"
        )

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's JointState names (position, ...) say where manip has them
        if name.startswith("__"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.TRAJECTORY, name)
