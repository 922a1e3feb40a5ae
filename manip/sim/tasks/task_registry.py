"""`TaskRegistry`: the World's tasks by name, and which of them have built their scene."""

from __future__ import annotations

from typing import Any

from manip.errors import InvalidInputError, UnknownNameError


class TaskRegistry:
    """Tasks (`BaseTask` or alike) in the order they were added."""

    def __init__(self) -> None:
        self._tasks: dict[str, Any] = {}
        self._set_up: set[str] = set()

    def add(self, task) -> None:
        """Register `task` under `task.name`.

        Raises:
            InvalidInputError: a task of that name exists.
        """
        if task.name in self._tasks:
            raise InvalidInputError(f"a task named {task.name!r} already exists; tasks: {sorted(self._tasks)}")
        self._tasks[task.name] = task

    def get(self, name: str):
        """The task named `name`.

        Raises:
            UnknownNameError: no such task (the message lists them).
        """
        if name not in self._tasks:
            raise UnknownNameError("task", name, sorted(self._tasks))
        return self._tasks[name]

    def as_dict(self) -> dict:
        return dict(self._tasks)

    def scenes_built(self) -> bool:
        """Whether there are tasks and every one has set up its scene."""
        return bool(self._tasks) and all(n in self._set_up for n in self._tasks)

    def set_up_scenes(self, scene) -> None:
        """`set_up_scene(scene)` of each task that has not done it yet."""
        for name, task in list(self._tasks.items()):
            if name not in self._set_up:
                task.set_up_scene(scene)
                self._set_up.add(name)

    def pre_step(self, time_step_index: int, simulation_time: float) -> None:
        """`pre_step` of each task whose scene is set up."""
        for name, task in list(self._tasks.items()):
            if name in self._set_up:
                task.pre_step(time_step_index, simulation_time)

    def post_reset(self) -> None:
        for task in list(self._tasks.values()):
            task.post_reset()

    def cleanup(self) -> None:
        """`cleanup()` of every task (they stay registered)."""
        for task in list(self._tasks.values()):
            task.cleanup()

    def clear(self) -> None:
        """Forget every task."""
        self._tasks.clear()
        self._set_up.clear()

    def observations(self, task_name: str | None = None) -> dict:
        """One task's observations, or all tasks' merged into one dict."""
        if task_name is not None:
            return self.get(task_name).get_observations()
        out: dict = {}
        for task in self._tasks.values():
            out.update(task.get_observations())
        return out

    def metrics(self, task_name: str | None = None) -> dict:
        """One task's metrics, or all tasks' merged into one dict."""
        if task_name is not None:
            return self.get(task_name).calculate_metrics()
        out: dict = {}
        for task in self._tasks.values():
            out.update(task.calculate_metrics() or {})
        return out

    def is_done(self, task_name: str | None = None) -> bool:
        """Whether the task (or, with None, every task; True without tasks, as Isaac's `all([])`) is done."""
        if task_name is not None:
            return bool(self.get(task_name).is_done())
        return all(t.is_done() for t in self._tasks.values())
