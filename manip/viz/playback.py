"""Trajectory playback in the browser: play/pause, a time slider, and the tool path.

`TrajectoryPlayback` owns the "Plan" GUI folder (a play/pause button, a time slider
[s], a loop checkbox) and the plan's scene nodes: `/plan/tool_path`, the tool frame's
path drawn as line segments, and `/plan/frames`, tool frames (axes) at evenly spaced
times. Moving the slider, by hand or by the playback thread, poses the robot at
`trajectory.at_time(t)` through the `set_configuration` callback.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.trajectory import Trajectory

logger = logging.getLogger(__name__)

#: Tool path colour [0-255].
PATH_COLOR = (40, 120, 255)
#: Samples of the drawn tool path per second of motion (at least 2 in all).
PATH_SAMPLES_PER_SECOND = 60
#: Playback refresh rate [Hz].
PLAYBACK_RATE = 30.0


class TrajectoryPlayback:
    """Plays one trajectory on the robot, with GUI controls and the tool path in the scene.

    Args:
        server: the viser server (its `gui` and `scene`).
        trajectory: the motion to play.
        set_configuration: called with q (dof,) [rad] whenever the playback time changes.
        tool_pose: `(Q (N, dof)) -> Pose` (batch of N) of the tool frame, base frame.
        num_frames: tool frames drawn along the path (>= 2).
    """

    def __init__(self, server: Any, trajectory: Trajectory, set_configuration: Callable[[np.ndarray], None],
                 tool_pose: Callable[[np.ndarray], Pose], *, num_frames: int = 8):
        if not isinstance(trajectory, Trajectory):
            raise InvalidInputError(f"trajectory must be a manip Trajectory; got {type(trajectory).__name__}")
        if int(num_frames) < 2:
            raise InvalidInputError(f"num_frames must be >= 2; got {num_frames}")
        self.trajectory = trajectory
        self._set_configuration = set_configuration
        self._stop = threading.Event()
        self._playing = threading.Event()
        duration = trajectory.duration
        n = max(2, int(np.ceil(duration * PATH_SAMPLES_PER_SECOND)) + 1)
        tool = tool_pose(trajectory.at_time(np.linspace(0.0, duration, n))[0])
        pts = np.asarray(tool.position)
        self.tool_path = pts
        scene = server.scene
        self.handles: dict[str, Any] = {
            "/plan/tool_path": scene.add_line_segments(
                "/plan/tool_path", np.stack([pts[:-1], pts[1:]], axis=1), PATH_COLOR, thickness=0.004),
        }
        frames = tool_pose(trajectory.at_time(np.linspace(0.0, duration, int(num_frames)))[0])
        self.frame_positions = np.asarray(frames.position)
        self.handles["/plan/frames"] = scene.add_batched_axes(
            "/plan/frames", np.asarray(frames.quaternion), self.frame_positions, axes_length=0.05, axes_radius=0.003)
        gui = server.gui
        self.folder = gui.add_folder("Plan")
        with self.folder:
            self.play_button = gui.add_button("Play / pause")
            step = max(duration / 1000.0, 1e-3)
            self.time_slider = gui.add_slider("time [s]", min=0.0, max=max(duration, step), step=step,
                                              initial_value=0.0)
            self.loop_checkbox = gui.add_checkbox("loop", initial_value=True)
        self.time_slider.on_update(lambda _event: self.seek(self.time_slider.value))
        self.play_button.on_click(lambda _event: self.toggle())
        self._thread = threading.Thread(target=self._run, name="manip-viz-playback", daemon=True)
        self._thread.start()
        self.seek(0.0)

    @property
    def playing(self) -> bool:
        """Whether the trajectory is playing."""
        return self._playing.is_set()

    def seek(self, t: float) -> np.ndarray:
        """Pose the robot at time t [s] (clamped to [0, duration]); returns q (dof,)."""
        t = float(np.clip(t, 0.0, self.trajectory.duration))
        q = self.trajectory.at_time(t)[0]
        self._set_configuration(q)
        return q

    def play(self) -> None:
        """Start playing from the slider's time (from 0 when at the end)."""
        if self.time_slider.value >= self.trajectory.duration:
            self.time_slider.value = 0.0
        self._playing.set()

    def pause(self) -> None:
        """Stop at the current time."""
        self._playing.clear()

    def toggle(self) -> None:
        """Play when paused, pause when playing."""
        if self.playing:
            self.pause()
        else:
            self.play()

    def _run(self) -> None:
        last = time.perf_counter()
        while not self._stop.wait(1.0 / PLAYBACK_RATE):
            now = time.perf_counter()
            if self._playing.is_set():
                t = self.time_slider.value + (now - last)
                if t >= self.trajectory.duration:
                    if self.loop_checkbox.value:
                        t = 0.0
                    else:
                        t = self.trajectory.duration
                        self._playing.clear()
                self.time_slider.value = t  # its callback poses the robot
            last = now

    def remove(self) -> None:
        """Stop the playback thread and remove the GUI controls and scene nodes."""
        self._stop.set()
        self._thread.join()
        for h in self.handles.values():
            h.remove()
        self.handles.clear()
        self.folder.remove()
