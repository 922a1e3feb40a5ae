"""`World`: the simulation loop of Isaac Sim's core API on MuJoCo.

Time: `physics_dt` (default 1/60 s, as Isaac) is the step seen by callbacks and tasks;
MuJoCo integrates each physics step in `ceil(physics_dt / substep_dt)` equal substeps of
at most `substep_dt` (default 0.002 s, i.e. 9 substeps of 1.85 ms at 60 Hz), which is what
keeps a grasped cube stable and stiff drives accurate. `step(render=True)` runs
max(1, round(rendering_dt / physics_dt)) physics steps then renders; `render=False` runs one.

Solver options: the `implicitfast` integrator (implicit drive damping), elliptic friction
cones and gravity -9.81 m/s^2 along z. The same script gives the same trajectory run after
run (MuJoCo is deterministic on one machine; nothing here is random).
"""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import Any, Callable

import mujoco
import numpy as np

from manip.errors import InvalidInputError, UnknownNameError
from manip.sim import recording as rec
from manip.sim.scene import Scene
from manip.sim.stage import ReferencePrim, SimHandle, SimulationError, StageEvent, get_current_stage

logger = logging.getLogger(__name__)

DEFAULT_DT = 1.0 / 60.0


class TimelineEvent:
    """What a timeline callback receives: `type` is "PLAY", "PAUSE" or "STOP"."""

    def __init__(self, type: str):
        self.type = type

    def __repr__(self) -> str:
        return f"TimelineEvent({self.type!r})"


def _dt(value, what: str) -> float:
    v = float(value)
    if not math.isfinite(v) or v <= 0:
        raise InvalidInputError(f"{what} must be a positive number of seconds; got {value!r}")
    return v


class World:
    """The simulation (one per process, as Isaac's): stage compilation, stepping, callbacks,
    tasks and the scene.

    A second `World(...)` returns the existing instance; differing arguments are ignored
    with a warning (use `set_simulation_dt`, or `World.clear_instance()` first).

    Args:
        physics_dt: physics step [s] (default 1/60).
        rendering_dt: render interval [s] (default = physics_dt).
        stage_units_in_meters: must be 1.0 (SI units only).
        substep_dt: largest MuJoCo integration step [s] (default 0.002).
        gravity: (3,) [m/s^2].
        physics_prim_path, sim_params, set_defaults, backend, device: accepted for Isaac
            scripts and ignored (backend must be "numpy").
    """

    _instance: World | None = None

    def __new__(cls, *args, **kwargs):
        if cls._instance is None:
            inst = super().__new__(cls)
            inst._initialized = False
            cls._instance = inst
        return cls._instance

    def __init__(
        self,
        physics_dt: float | None = None,
        rendering_dt: float | None = None,
        stage_units_in_meters: float | None = None,
        physics_prim_path: str = "/physicsScene",
        sim_params: dict | None = None,
        set_defaults: bool = True,
        backend: str = "numpy",
        device: str | None = None,
        substep_dt: float = 0.002,
        gravity=(0.0, 0.0, -9.81),
    ):
        if self._initialized:
            if physics_dt is not None or rendering_dt is not None:
                logger.warning(
                    "World already exists (physics_dt=%s, rendering_dt=%s); the new arguments are ignored. "
                    "Use set_simulation_dt() or World.clear_instance() first.",
                    self._physics_dt, self._rendering_dt,
                )
            return
        try:
            if stage_units_in_meters is not None and float(stage_units_in_meters) != 1.0:
                raise InvalidInputError("manip.sim works in metres: stage_units_in_meters must be 1.0")
            if backend not in ("numpy", "torch") or backend == "torch":
                if backend != "numpy":
                    raise InvalidInputError(f"backend must be 'numpy'; got {backend!r}")
            self._physics_dt = _dt(physics_dt if physics_dt is not None else DEFAULT_DT, "physics_dt")
            self._rendering_dt = _dt(rendering_dt if rendering_dt is not None else self._physics_dt, "rendering_dt")
            self._substep_dt = _dt(substep_dt, "substep_dt")
            g = np.asarray(gravity, dtype=float)
            if g.shape != (3,) or not np.all(np.isfinite(g)):
                raise InvalidInputError(f"gravity must be 3 finite numbers; got {gravity!r}")
        except Exception:
            type(self)._instance = None
            raise
        self._gravity = g
        self._stage = get_current_stage()
        self._scene = Scene(self)
        self._sim: SimHandle | None = None
        self._compiled_version = -1
        self._playing = False
        self._stopped = True
        self._time = 0.0
        self._index = 0
        self._last_pre_step_index = -1
        self._physics_callbacks: dict[str, Callable] = {}
        self._timeline_callbacks: dict[str, Callable] = {}
        self._render_callbacks: dict[str, Callable] = {}
        self._tasks: dict[str, Any] = {}
        self._tasks_set_up: set[str] = set()
        self._camera_view = rec.CameraView()
        self._recorder: rec.Recorder | None = None
        self._warned_dirty = False
        self._restart_pending = False
        self._initialized = True

    # ------------------------------------------------------------------ instance
    @classmethod
    def instance(cls) -> World | None:
        """The World of this process, or None."""
        return cls._instance

    @classmethod
    def clear_instance(cls) -> None:
        """Forget the World: stop recording, unbind objects, empty the stage."""
        w = cls._instance
        if w is not None and getattr(w, "_initialized", False):
            w.stop_recording()
            for task in list(w._tasks.values()):
                task.cleanup()
            w._unbind_all()
            w._stage.clear()
            from manip.sim import app as _app

            _app._world_cleared(w)
        cls._instance = None

    # ------------------------------------------------------------------ properties
    @property
    def scene(self) -> Scene:
        return self._scene

    @property
    def stage(self):
        return self._stage

    @property
    def model(self) -> mujoco.MjModel | None:
        """The compiled MuJoCo model (None before the first reset): an escape hatch."""
        return None if self._sim is None else self._sim.model

    @property
    def data(self) -> mujoco.MjData | None:
        """The MuJoCo data (None before the first reset): an escape hatch."""
        return None if self._sim is None else self._sim.data

    @property
    def current_time(self) -> float:
        """Simulated time since the last reset/stop [s]."""
        return self._time

    @property
    def current_time_step_index(self) -> int:
        """Physics steps since the last reset/stop."""
        return self._index

    @property
    def physics_substeps(self) -> int:
        """MuJoCo steps per physics step."""
        return max(1, math.ceil(self._physics_dt / self._substep_dt - 1e-9))

    def get_physics_dt(self) -> float:
        return self._physics_dt

    def get_rendering_dt(self) -> float:
        return self._rendering_dt

    def set_simulation_dt(self, physics_dt: float | None = None, rendering_dt: float | None = None) -> None:
        """Change the physics step and/or render interval [s] (takes effect immediately)."""
        if physics_dt is not None:
            self._physics_dt = _dt(physics_dt, "physics_dt")
        if rendering_dt is not None:
            self._rendering_dt = _dt(rendering_dt, "rendering_dt")
        if self._sim is not None:
            self._sim.model.opt.timestep = self._physics_dt / self.physics_substeps

    # ------------------------------------------------------------------ compilation
    def _needs_compile(self) -> bool:
        return self._sim is None or self._compiled_version != self._stage.version

    def _unbind_all(self) -> None:
        for prim in self._stage.prims():
            if hasattr(prim, "_unbind"):
                prim._unbind()
            if isinstance(prim, ReferencePrim):
                prim.core = None
        for w in self._stage.wrappers():
            w._unbind()
        self._sim = None
        self._stage.sim = None

    def _compile(self) -> None:
        self.stop_recording()
        self._unbind_all()
        spec = mujoco.MjSpec()
        spec.modelname = "manip_world"
        spec.option.timestep = self._physics_dt / self.physics_substeps
        spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
        spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
        spec.option.gravity = self._gravity.tolist()
        spec.visual.global_.offwidth = 1920
        spec.visual.global_.offheight = 1080
        spec.visual.headlight.ambient = [0.3, 0.3, 0.3]
        spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]
        spec.worldbody.add_light(name="__manip_key_light", pos=[0.0, 0.0, 3.0], dir=[0.0, 0.0, -1.0],
                                 type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, diffuse=[0.6, 0.6, 0.6],
                                 castshadow=True)
        for prim in self._stage.prims():
            prim._build(spec)
        try:
            model = spec.compile()
        except ValueError as exc:
            raise SimulationError(f"the stage does not compile into a MuJoCo model: {exc}") from exc
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
        sim = SimHandle(model, data)
        for prim in self._stage.prims():
            prim._bind(sim)
        for w in self._stage.wrappers():
            w._bind(sim)
        self._sim = sim
        self._stage.sim = sim
        self._compiled_version = self._stage.version
        self._warned_dirty = False
        self._stage._changed("COMPILED", "/")
        self._compiled_version = self._stage.version
        logger.info("compiled the stage: %d bodies, %d DoF, %d actuators, %d substeps of %.4f s",
                    model.nbody, model.nv, model.nu, self.physics_substeps, model.opt.timestep)
        from manip.sim import app as _app

        _app._world_compiled(self)

    def _reset_physics_state(self) -> None:
        """Back to the compiled initial state (qpos0, mocap at their build pose, targets = qpos0)."""
        sim = self._sim
        mujoco.mj_resetData(sim.model, sim.data)
        for prim in self._stage.prims():
            if isinstance(prim, ReferencePrim) and prim.core is not None:
                c = prim.core
                c.pos_target = sim.data.qpos[c.qadr].copy()
                c.vel_target = np.zeros(c.n)
                c.efforts = np.zeros(c.n)
                c.write_targets()
        sim.mark_stale()

    # ------------------------------------------------------------------ timeline
    def reset(self, soft: bool = False) -> None:
        """Build task scenes (once per task), compile the stage if it changed, restore every
        scene object's default state, call each task's `post_reset()` and play.

        Time and step index go back to 0; physics callbacks are kept.
        """
        for name, task in list(self._tasks.items()):
            if name not in self._tasks_set_up:
                task.set_up_scene(self._scene)
                self._tasks_set_up.add(name)
        self.stop()
        if self._needs_compile():
            self._compile()
        else:
            self._reset_physics_state()
        self._scene.post_reset()
        mujoco.mj_forward(self._sim.model, self._sim.data)
        self._sim.kinematics_stale = False
        for task in list(self._tasks.values()):
            task.post_reset()
        self._time = 0.0
        self._index = 0
        self._last_pre_step_index = -1
        self._restart_pending = False
        self.play()
        from manip.sim import app as _app

        _app._world_rendered(self)

    def play(self) -> None:
        """Start (or resume) the simulation; compiles the stage if never compiled. After a
        `stop()`, physics restarts from the compiled initial state."""
        if self._sim is None:
            self._compile()
        elif self._restart_pending:
            self._reset_physics_state()
        self._restart_pending = False
        self._playing = True
        self._stopped = False
        self._fire_timeline("PLAY")

    def pause(self) -> None:
        """Pause: `step()` still renders and runs task pre_steps, physics does not advance."""
        self._playing = False
        self._fire_timeline("PAUSE")

    def stop(self) -> None:
        """Stop: time and step index go back to 0; the next `play()` restarts physics."""
        was = not self._stopped
        self._playing = False
        self._stopped = True
        self._time = 0.0
        self._index = 0
        self._last_pre_step_index = -1
        self._restart_pending = self._sim is not None
        if was:
            self._fire_timeline("STOP")

    def is_playing(self) -> bool:
        return self._playing

    def is_stopped(self) -> bool:
        return self._stopped

    async def reset_async(self, soft: bool = False) -> None:
        self.reset(soft)

    async def play_async(self) -> None:
        self.play()

    async def pause_async(self) -> None:
        self.pause()

    async def stop_async(self) -> None:
        self.stop()

    def _fire_timeline(self, kind: str) -> None:
        ev = TimelineEvent(kind)
        for fn in list(self._timeline_callbacks.values()):
            fn(ev)

    # ------------------------------------------------------------------ stepping
    def step(self, render: bool = True, step_sim: bool = True) -> None:
        """Run the tasks' `pre_step`, then physics (if playing): max(1, rendering_dt /
        physics_dt) physics steps with render=True, one with render=False; then render.

        Physics callbacks run before each physics step with `step_size = physics_dt`.
        """
        self.step_async()
        if self._playing and step_sim:
            if self._compiled_version != self._stage.version and not self._warned_dirty:
                logger.warning("the stage changed since the last world.reset(); new prims appear after a reset")
                self._warned_dirty = True
            n = max(1, int(round(self._rendering_dt / self._physics_dt))) if render else 1
            for _ in range(n):
                self._physics_step()
        if render:
            self.render()

    def step_async(self, step_size: float | None = None) -> None:
        """Run each task's `pre_step(step_index, time)` once for the current physics step
        (Isaac's name; what the BaseSample's "tasks_step" physics callback calls)."""
        if self._last_pre_step_index == self._index:
            return
        self._last_pre_step_index = self._index
        for name, task in list(self._tasks.items()):
            if name in self._tasks_set_up:
                task.pre_step(self._index, self._time)

    def _physics_step(self) -> None:
        dt = self._physics_dt
        for fn in list(self._physics_callbacks.values()):
            fn(dt)
        sim = self._sim
        mujoco.mj_step(sim.model, sim.data, nstep=self.physics_substeps)
        sim.kinematics_stale = True
        self._index += 1
        self._time = self._index * dt

    def render(self) -> None:
        """Capture a video frame if recording, update the viewer if one is open, and run the
        render callbacks."""
        if self._sim is None:
            return
        if self._recorder is not None:
            self._sim.ensure_kinematics()
            self._recorder.maybe_capture(self._sim.data, self._time, self._camera_view)
        from manip.sim import app as _app

        _app._world_rendered(self)
        for fn in list(self._render_callbacks.values()):
            fn(TimelineEvent("RENDER"))

    # ------------------------------------------------------------------ callbacks
    def _add_cb(self, table: dict, kind: str, name: str, fn: Callable) -> None:
        if not callable(fn):
            raise InvalidInputError(f"{kind} callback {name!r} must be callable; got {fn!r}")
        if name in table:
            raise InvalidInputError(
                f"a {kind} callback named {name!r} already exists; remove it first or use another name "
                f"(existing: {sorted(table)})"
            )
        table[name] = fn

    def add_physics_callback(self, callback_name: str, callback_fn: Callable[[float], None]) -> None:
        """Call `callback_fn(step_size)` before every physics step (step_size = physics_dt [s]).

        Raises:
            InvalidInputError: the name is taken.
        """
        self._add_cb(self._physics_callbacks, "physics", callback_name, callback_fn)

    def remove_physics_callback(self, callback_name: str) -> None:
        if callback_name not in self._physics_callbacks:
            raise UnknownNameError("physics callback", callback_name, sorted(self._physics_callbacks))
        del self._physics_callbacks[callback_name]

    def physics_callback_exists(self, callback_name: str) -> bool:
        return callback_name in self._physics_callbacks

    def add_timeline_callback(self, callback_name: str, callback_fn: Callable[[TimelineEvent], None]) -> None:
        """Call `callback_fn(event)` on play/pause/stop (`event.type`: "PLAY", "PAUSE", "STOP")."""
        self._add_cb(self._timeline_callbacks, "timeline", callback_name, callback_fn)

    def remove_timeline_callback(self, callback_name: str) -> None:
        if callback_name not in self._timeline_callbacks:
            raise UnknownNameError("timeline callback", callback_name, sorted(self._timeline_callbacks))
        del self._timeline_callbacks[callback_name]

    def timeline_callback_exists(self, callback_name: str) -> bool:
        return callback_name in self._timeline_callbacks

    def add_stage_callback(self, callback_name: str, callback_fn: Callable[[StageEvent], None]) -> None:
        """Call `callback_fn(event)` when the stage changes (`event.type`: "PRIM_ADDED",
        "PRIM_REMOVED", "PRIM_CHANGED", "CLEARED", "COMPILED"; `event.path`)."""
        self._add_cb(self._stage._callbacks, "stage", callback_name, callback_fn)

    def remove_stage_callback(self, callback_name: str) -> None:
        if callback_name not in self._stage._callbacks:
            raise UnknownNameError("stage callback", callback_name, sorted(self._stage._callbacks))
        del self._stage._callbacks[callback_name]

    def stage_callback_exists(self, callback_name: str) -> bool:
        return callback_name in self._stage._callbacks

    def add_render_callback(self, callback_name: str, callback_fn: Callable) -> None:
        """Call `callback_fn(event)` after every render."""
        self._add_cb(self._render_callbacks, "render", callback_name, callback_fn)

    def remove_render_callback(self, callback_name: str) -> None:
        if callback_name not in self._render_callbacks:
            raise UnknownNameError("render callback", callback_name, sorted(self._render_callbacks))
        del self._render_callbacks[callback_name]

    def clear_all_callbacks(self) -> None:
        """Remove every physics, timeline, stage and render callback."""
        self._physics_callbacks.clear()
        self._timeline_callbacks.clear()
        self._stage._callbacks.clear()
        self._render_callbacks.clear()

    # ------------------------------------------------------------------ tasks
    def add_task(self, task) -> None:
        """Register a task; its scene is set up at the next `reset()`.

        Raises:
            InvalidInputError: a task of that name exists.
        """
        if task.name in self._tasks:
            raise InvalidInputError(f"a task named {task.name!r} already exists; tasks: {sorted(self._tasks)}")
        self._tasks[task.name] = task

    def get_task(self, name: str):
        """The task named `name`.

        Raises:
            UnknownNameError: no such task (the message lists them).
        """
        if name not in self._tasks:
            raise UnknownNameError("task", name, sorted(self._tasks))
        return self._tasks[name]

    def get_current_tasks(self) -> dict:
        return dict(self._tasks)

    def is_tasks_scene_built(self) -> bool:
        return bool(self._tasks) and all(n in self._tasks_set_up for n in self._tasks)

    def get_observations(self, task_name: str | None = None) -> dict:
        """One task's observations, or all tasks' merged into one dict."""
        if task_name is not None:
            return self.get_task(task_name).get_observations()
        out: dict = {}
        for task in self._tasks.values():
            out.update(task.get_observations())
        return out

    def calculate_metrics(self, task_name: str | None = None) -> dict:
        if task_name is not None:
            return self.get_task(task_name).calculate_metrics()
        out: dict = {}
        for task in self._tasks.values():
            out.update(task.calculate_metrics() or {})
        return out

    def is_done(self, task_name: str | None = None) -> bool:
        """Whether the task (or every task) is done."""
        if task_name is not None:
            return bool(self.get_task(task_name).is_done())
        return bool(self._tasks) and all(t.is_done() for t in self._tasks.values())

    def clear(self) -> None:
        """Remove every scene object (and its prim) and every task; the stage is emptied."""
        self.stop_recording()
        for task in list(self._tasks.values()):
            task.cleanup()
        self._tasks.clear()
        self._tasks_set_up.clear()
        self._scene.clear(registry_only=True)
        self._unbind_all()
        self._stage.clear()
        self._compiled_version = -1
        self.stop()

    # ------------------------------------------------------------------ camera and video
    def set_camera_view(self, eye, target) -> None:
        """Point the viewer's and the recording's camera from `eye` (3,) at `target` (3,) [m]."""
        self._camera_view = rec.CameraView.from_eye_target(eye, target)
        from manip.sim import app as _app

        _app._camera_changed(self)

    def get_camera_view(self) -> rec.CameraView:
        return self._camera_view

    def start_recording(self, path: str | Path, camera: str | rec.CameraView | None = None, width: int = 640,
                        height: int = 480, fps: float = 30.0) -> None:
        """Write an MP4 of a camera view, a frame every 1/fps of simulated time on render.

        Offscreen: works without a display when EGL or OSMesa is installed (see
        `manip.sim.recording`). The model must be compiled (call after `reset()`); a recompile
        (reset after adding prims) ends the recording.

        Args:
            path: output file (.mp4).
            camera: name of a model camera, a CameraView, or None for the World's view
                (`set_camera_view`).
            width, height: frame size [px].
            fps: frames per second of simulated time.

        Raises:
            OffscreenRenderingError: no offscreen GL backend or no imageio-ffmpeg.
            SimulationError: before the first reset, or already recording.
        """
        if self._sim is None:
            raise SimulationError("start_recording: call world.reset() first (the model is not compiled)")
        if self._recorder is not None:
            raise SimulationError(f"already recording to {self._recorder.path}; call stop_recording() first")
        if isinstance(camera, str) and mujoco.mj_name2id(self._sim.model, mujoco.mjtObj.mjOBJ_CAMERA, camera) < 0:
            cams = [self._sim.model.camera(i).name for i in range(self._sim.model.ncam)]
            raise UnknownNameError("camera", camera, cams)
        self._recorder = rec.Recorder(self._sim.model, path, camera, width, height, fps)
        self._recorder.capture(self._sim.data, self._camera_view)

    def stop_recording(self) -> Path | None:
        """Finish the MP4; returns its path (None if not recording)."""
        r = self._recorder
        if r is None:
            return None
        self._recorder = None
        r.close()
        return r.path

    def is_recording(self) -> bool:
        return self._recorder is not None

    def render_image(self, width: int = 640, height: int = 480, camera: str | rec.CameraView | None = None) -> np.ndarray:
        """One offscreen RGB image (height, width, 3) uint8 of the current state."""
        if self._sim is None:
            raise SimulationError("render_image: call world.reset() first")
        r = rec.make_renderer(self._sim.model, width, height)
        try:
            self._sim.ensure_kinematics()
            if isinstance(camera, str):
                r.update_scene(self._sim.data, camera=camera)
            else:
                cam = mujoco.MjvCamera()
                (camera or self._camera_view).apply(cam)
                r.update_scene(self._sim.data, camera=cam)
            return r.render().copy()
        finally:
            r.close()
