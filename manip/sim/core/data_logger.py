"""`DataLogger` (`World.get_data_logger()`): Isaac's per-step data recording, pure Python as Isaac's.

`add_data_frame_logging_func(fn)` sets `fn(tasks, scene) -> dict`; once `start()`ed, every
`World.step()` appends a `DataFrame(current_time_step, current_time, data=fn(...))` after its
physics; `save(path)` writes Isaac's JSON ({"Isaac Sim Data": [frame dicts]}) and `load(path)`
reads it back (paused). The data must be JSON-serialisable to be saved (`.tolist()` arrays, as
Isaac's example does).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

from manip.errors import InvalidInputError
from manip.sim.scenes.stage import SimulationError


class DataFrame:
    """The data logged at one step: `current_time_step` (index), `current_time` [s], `data` (dict)."""

    def __init__(self, current_time_step: int, current_time: float, data: dict):
        self.current_time_step = current_time_step
        self.current_time = current_time
        self.data = data

    def get_dict(self) -> dict:
        return {"current_time": self.current_time, "current_time_step": self.current_time_step, "data": self.data}

    def __str__(self) -> str:
        return str(self.get_dict())

    @classmethod
    def init_from_dict(cls, dict_representation: dict) -> DataFrame:
        return cls(dict_representation["current_time_step"], dict_representation["current_time"],
                   dict_representation["data"])


class DataLogger:
    """Collects one `DataFrame` per `World.step()` while started (Isaac's `DataLogger`)."""

    def __init__(self) -> None:
        self._pause = True
        self._data_frames: list[DataFrame] = []
        self._func: Callable[..., dict] | None = None

    def add_data_frame_logging_func(self, func: Callable[..., dict]) -> None:
        """`func(tasks=..., scene=...) -> dict`, called at every step while started."""
        if not callable(func):
            raise InvalidInputError(f"the data frame logging function must be callable; got {func!r}")
        self._func = func

    def start(self) -> None:
        self._pause = False

    def pause(self) -> None:
        self._pause = True

    def is_started(self) -> bool:
        return not self._pause

    def reset(self) -> None:
        """Forget the frames and pause."""
        self._pause = True
        self._data_frames = []

    def add_data(self, data: dict, current_time_step: int, current_time: float) -> None:
        """Append a frame (nothing while paused)."""
        if not self._pause:
            self._data_frames.append(DataFrame(current_time_step, current_time, data))

    def log_step(self, tasks: dict, scene: Any, current_time_step: int, current_time: float) -> None:
        """The World's call after a step: one frame from the logging function, while started.

        Raises:
            SimulationError: started without a logging function (as Isaac's).
        """
        if self._pause:
            return
        if self._func is None:
            raise SimulationError("the data logger is started without a logging function: call "
                                  "add_data_frame_logging_func(fn) first, fn(tasks, scene) -> dict")
        self.add_data(self._func(tasks=tasks, scene=scene), current_time_step, current_time)

    def get_num_of_data_frames(self) -> int:
        return len(self._data_frames)

    def get_data_frame(self, data_frame_index: int) -> DataFrame:
        return self._data_frames[data_frame_index]

    def save(self, log_path: str | Path) -> None:
        """Write the frames as Isaac's JSON."""
        with open(log_path, "w") as f:
            json.dump({"Isaac Sim Data": [frame.get_dict() for frame in self._data_frames]}, f)

    def load(self, log_path: str | Path) -> None:
        """Read frames saved by `save` (or Isaac); the logger is paused."""
        with open(log_path) as f:
            frames = json.load(f)["Isaac Sim Data"]
        self._pause = True
        self._data_frames = [DataFrame.init_from_dict(d) for d in frames]
