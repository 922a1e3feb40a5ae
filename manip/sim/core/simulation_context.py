"""`SimulationContext`: the simulation loop of Isaac Sim's core API on MuJoCo (`World` adds
the scene and the tasks).

Time: `physics_dt` (default 1/60 s, as Isaac) is the step seen by callbacks and tasks;
MuJoCo integrates each physics step in `ceil(physics_dt / substep_dt)` equal substeps of
at most `substep_dt` (default 0.002 s, i.e. 9 substeps of 1.85 ms at 60 Hz), which is what
keeps a grasped cube stable and stiff drives accurate; more while a free body moves fast
(`manip.sim.core.substeps`: no body travels more than 2 mm between contact checks). `step(render=True)` runs
max(1, round(rendering_dt / physics_dt)) physics steps then renders; `render=False` runs one.
As in Isaac (`SimulationContext.initialize_physics`), `reset()` stops, plays and takes one
warm-up `step(render=True)` without physics callbacks, so `current_time_step_index` is 1
right after a reset (with the default dts) and the world is playing.

Callback names follow Isaac: a duplicate name or removing an unknown one logs an error
(`carb.log_error`) and changes nothing (`manip.sim.core.simulation_callbacks`). The `*_async` methods are coroutines doing the same
as the plain ones, for Isaac's extension workflow (`asyncio.run(world.reset_async())`).

Solver options (`manip.sim.scenes.compiler`): `implicitfast`, elliptic cones, gravity -9.81 m/s^2
along z (`get_physics_context()`); the same script gives the same trajectory (nothing is random).

Observers (`add_observer`, e.g. the viewer) follow every instance (`WorldObserver`).

Joint limits hold after every physics step (see `manip.sim.articulations.articulation`). MuJoCo's own
warnings become Python ones after every physics step (`manip.sim.core.mujoco_warnings`): an
unstable step raises `SimulationInstabilityError` naming the joint or actuator, with the drive
targets set to the current joint positions and the efforts to 0, so that the world can go on
(call `reset()` to restart from the default states); milder ones are `SimulationWarning`s.
"""

from __future__ import annotations

import logging
import math
import weakref
from pathlib import Path
from typing import ClassVar

import mujoco
import numpy as np

from manip.errors import InvalidInputError
from manip.sim.articulations.articulation_core import ArticulationCore
from manip.sim.core import recording as rec
from manip.sim.core import substeps
from manip.sim.core.callbacks import TimelineEvent
from manip.sim.core.mujoco_warnings import SimulationInstabilityError, SimulationWarning, WarningMonitor  # noqa: F401 (re-exported)
from manip.sim.core.observers import WorldObserver
from manip.sim.core.physics_context import PhysicsContext
from manip.sim.core.simulation_callbacks import SimulationCallbacks
from manip.sim.scenes.compiler import compile_stage
from manip.sim.scenes.robot_overlaps import check_robot_overlaps
from manip.sim.scenes.stage import ReferencePrim, SimHandle, SimulationError, get_current_stage
from manip.validation import non_negative, positive, vec

logger = logging.getLogger(__name__)

DEFAULT_DT = 1.0 / 60.0
DEFAULT_GRAVITY = (0.0, 0.0, -9.81)  # [m/s^2]


class SimulationContext(SimulationCallbacks):
    """The simulation (one per process, as Isaac's): stage compilation, timeline, stepping,
    callbacks (`SimulationCallbacks`), camera and video. `World` adds the scene and the tasks.

    A second construction returns the existing instance; differing arguments are ignored
    with a warning (use `set_simulation_dt`, or `clear_instance()` first).

    Args:
        physics_dt: physics step [s] (default 1/60).
        rendering_dt: render interval [s] (default = physics_dt).
        stage_units_in_meters: must be 1.0 (SI units only).
        substep_dt: largest MuJoCo integration step [s] (default 0.002).
        gravity: (3,) [m/s^2] (default (0, 0, -9.81)).
        sim_params: Isaac's physics settings: "gravity" is used (the argument takes
            precedence); other keys (PhysX/GPU settings) are ignored with a warning.
        backend, device: "numpy" and None/"cpu" only (MuJoCo runs on the CPU).
        physics_prim_path, set_defaults: the PhysicsContext's prim path; ignored.

    Raises:
        InvalidInputError: stage units other than metres, another backend or device, a
            non-positive dt, a bad gravity.
    """

    _instance: SimulationContext | None = None
    _initialized = False  # per instance: True once __init__ has run (the singleton is initialised once)
    _observers: ClassVar[list[WorldObserver]] = []  # shared by every World of the process

    def __new__(cls, *args, **kwargs):
        inst = SimulationContext._instance  # one per process, a World included (as in Isaac)
        if inst is None:
            inst = SimulationContext._instance = super().__new__(cls)  # `_initialized` is False until __init__ ends
        elif not isinstance(inst, cls):
            raise SimulationError(f"a {type(inst).__name__} exists (one simulation per process): call "
                                  f"{type(inst).__name__}.clear_instance() before creating a {cls.__name__}")
        return inst

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
        *,
        substep_dt: float = 0.002,
        gravity=None,
    ):
        if self._initialized:
            if physics_dt is not None or rendering_dt is not None:
                logger.warning(
                    "%s already exists (physics_dt=%s, rendering_dt=%s); the new arguments are ignored. "
                    "Use set_simulation_dt() or %s.clear_instance() first.", type(self).__name__,
                    self._physics_dt, self._rendering_dt, type(self).__name__,
                )
            return
        try:
            if stage_units_in_meters is not None and float(stage_units_in_meters) != 1.0:
                raise InvalidInputError(
                    f"stage_units_in_meters must be 1.0; got {stage_units_in_meters!r}: manip.sim works in metres "
                    "(there is no USD stage to scale; give lengths in m)")
            if backend != "numpy":
                raise InvalidInputError(
                    f"backend must be 'numpy'; got {backend!r}: manip.sim runs MuJoCo on the CPU and returns NumPy "
                    "arrays (Isaac's 'torch'/'warp' backends and GPU pipelines have no equivalent here)")
            if device is not None and str(device).lower() != "cpu":
                raise InvalidInputError(
                    f"device must be None or 'cpu'; got {device!r}: manip.sim runs MuJoCo on the CPU (no GPU physics)")
            if sim_params is not None and "gravity" in sim_params and gravity is None:
                gravity = sim_params["gravity"]
            ignored = sorted(set(sim_params or {}) - {"gravity"})
            if ignored:
                logger.warning("sim_params %s are PhysX settings manip.sim does not mirror; they are ignored "
                               "(only 'gravity' is used; give physics_dt/rendering_dt as arguments)", ignored)
            self._physics_dt = positive(physics_dt if physics_dt is not None else DEFAULT_DT, "physics_dt", "s")
            self._rendering_dt = positive(rendering_dt if rendering_dt is not None else self._physics_dt,
                                          "rendering_dt", "s")
            self._substep_dt = positive(substep_dt, "substep_dt", "s")
            g = vec(gravity if gravity is not None else DEFAULT_GRAVITY, 3, "gravity")
        except Exception:
            SimulationContext._instance = None
            raise
        self._physics_context = PhysicsContext(self, g, physics_prim_path)
        self._physics_off = False  # set_simulation_dt(physics_dt=0): steps only render
        self._stage = get_current_stage()
        self._sim: SimHandle | None = None
        self._cores: list[ArticulationCore] = []  # of the compiled model
        self._warnings = WarningMonitor()  # MuJoCo's warnings, each reported once
        self._compiled_version = -1
        self._playing = False
        self._stopped = True
        self._time = 0.0
        self._time_origin = 0.0
        self._index = 0
        self._init_callbacks()
        self._camera_view = rec.CameraView()
        self._recorder: rec.Recorder | None = None
        self._warned_dirty = False
        self._init_components()
        self._initialized = True

    def _init_components(self) -> None:
        """Create what a subclass adds (the World: scene and tasks); called once, by `__init__`."""

    # ------------------------------------------------------------------ instance
    @classmethod
    def instance(cls) -> SimulationContext | None:
        """The instance of this process (a World is the SimulationContext too, as in Isaac),
        or None; `World.instance()` is None while the instance is a plain SimulationContext."""
        inst = SimulationContext._instance
        return inst if isinstance(inst, cls) else None

    @classmethod
    def clear_instance(cls) -> None:
        """Forget the instance (`SimulationContext.clear_instance()` clears a World too):
        stop recording, clean up (a World: its tasks), unbind objects, empty the stage."""
        w = SimulationContext._instance
        if w is not None and getattr(w, "_initialized", False):
            w._forget()
        SimulationContext._instance = None

    def _forget(self) -> None:
        self.stop_recording()
        self._clear_components()
        self._unbind_all()
        self._stage.clear()
        self._notify("on_world_cleared")

    def _clear_components(self) -> None:
        """Clean up what a subclass added (the World: its tasks); called by `clear_instance`."""

    @classmethod
    def add_observer(cls, observer: WorldObserver) -> None:
        """Let `observer` follow every World (see `WorldObserver`); added once."""
        if observer not in cls._observers:
            cls._observers.append(observer)

    @classmethod
    def remove_observer(cls, observer: WorldObserver) -> None:
        """Stop notifying `observer` (nothing happens if it was not added)."""
        if observer in cls._observers:
            cls._observers.remove(observer)

    def _notify(self, event: str) -> None:
        for observer in list(self._observers):
            getattr(observer, event)(self)

    # ------------------------------------------------------------------ properties
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

    def get_physics_context(self) -> PhysicsContext:
        return self._physics_context  # gravity and the step; PhysX's other settings kept, unused

    def get_physics_dt(self) -> float:
        return 0.0 if self._physics_off else self._physics_dt

    def get_rendering_dt(self) -> float:
        return self._rendering_dt

    def set_simulation_dt(self, physics_dt: float | None = None, rendering_dt: float | None = None) -> None:
        """Change the physics step and/or render interval [s] (takes effect immediately;
        `current_time` goes on from where it is). As in Isaac, `physics_dt=0`: physics does not
        simulate (steps only render) until a positive physics_dt is set again; `rendering_dt=0`:
        `step(render=True)` runs one physics step.

        Raises:
            InvalidInputError: a negative or non-finite dt (nothing changes then).
        """
        v = non_negative(physics_dt, "physics_dt", "s") if physics_dt is not None else None
        off = v == 0.0 if v is not None else self._physics_off
        new_physics = v if v else self._physics_dt
        new_rendering = non_negative(rendering_dt, "rendering_dt") if rendering_dt is not None else self._rendering_dt
        # current_time = time_origin + index * physics_dt (no accumulated rounding); keep it continuous.
        self._time_origin = self._time - self._index * new_physics
        self._physics_dt, self._rendering_dt = new_physics, new_rendering
        self._physics_off = off
        if self._sim is not None:
            self._sim.model.opt.timestep = self._physics_dt / self.physics_substeps
            for core in self._cores:
                core.stiffen_limits()

    # ------------------------------------------------------------------ compilation
    def _needs_compile(self) -> bool:
        return self._sim is None or self._compiled_version != self._stage.version

    def _unbind_all(self) -> None:
        for prim in self._stage.prims():
            if hasattr(prim, "unbind_simulation"):
                prim.unbind_simulation()
            if isinstance(prim, ReferencePrim):
                prim.core = None
        for w in self._stage.wrappers():
            w.unbind_simulation()
        self._sim = None
        self._cores = []
        self._stage.sim = None
        self._warnings.unwatch()  # the old data must go with its model (see `unwatch`)

    def _compile(self) -> None:
        """Compile the stage, then bind to the new model: each object, each referenced
        model (a new `ArticulationCore`), then the wrappers (articulations, views)."""
        self.stop_recording()
        self._unbind_all()
        sim = compile_stage(self._stage, timestep=self._physics_dt / self.physics_substeps, gravity=self._physics_context.gravity)
        model = sim.model
        cores = []
        for prim in self._stage.prims():
            if isinstance(prim, ReferencePrim):
                prim.core = ArticulationCore(prim, sim)
                cores.append(prim.core)
            else:
                prim.bind_simulation(sim)
        self._cores = cores
        sim.robot_cores = weakref.WeakSet(cores)  # weak: a core holds the handle (no cycle keeps the model)
        self._warnings.watch(sim.data)
        for w in self._stage.wrappers():
            w.bind_simulation(sim)
        self._sim = sim
        self._stage.sim = sim
        self._compiled_version = self._stage.version
        self._warned_dirty = False
        self._stage.notify_changed("COMPILED", "/")
        self._compiled_version = self._stage.version
        logger.info("compiled the stage: %d bodies, %d DoF, %d actuators, %d substeps of %.4f s",
                    model.nbody, model.nv, model.nu, self.physics_substeps, model.opt.timestep)
        self._notify("on_world_compiled")

    def _reset_physics_state(self) -> None:
        """Back to the compiled initial state (qpos0, mocap at their build pose, targets = qpos0)."""
        sim = self._sim
        mujoco.mj_resetData(sim.model, sim.data)
        self._warnings.reset()
        for core in self._cores:
            core.reset_drive_targets()
        sim.mark_stale()

    # ------------------------------------------------------------------ timeline
    def reset(self, soft: bool = False) -> None:
        """Stop, compile the stage if it changed (else restore the compiled initial state),
        play and take one warm-up step (Isaac's `initialize_physics`).

        As in Isaac, the warm-up is one `step(render=True)` worth of physics (max(1,
        rendering_dt / physics_dt) physics steps) without physics callbacks, so right after
        a reset `current_time_step_index` is 1 (default dts) and the world is playing.
        Physics callbacks are kept. `soft=True` on a compiled world does nothing here (the
        World restores its objects' default states).
        """
        if soft and self._sim is not None:
            return
        if soft:
            logger.warning("reset(soft=True) before the first reset: doing a full reset")
        self.initialize_physics()
        self._notify("on_world_rendered")

    def initialize_physics(self) -> None:
        """`reset()`'s work (Isaac: "it does one step internally to propagate all physics handles")."""
        self._restart_physics()
        self._play_and_warm_up()

    def _restart_physics(self) -> None:
        """Stop, then compile the stage if it changed, else restore the compiled initial state."""
        self.stop()
        if self._needs_compile():
            self._compile()
        else:
            self._reset_physics_state()
        self._forward()  # robots placed inside each other raise here, before any step
        check_robot_overlaps(self._sim.model, self._sim.data, self._cores)

    def _forward(self) -> None:
        """Bring the derived quantities (poses, velocities...) up to date with the state."""
        mujoco.mj_forward(self._sim.model, self._sim.data)
        self._sim.kinematics_stale = False

    def _play_and_warm_up(self) -> None:
        """Play from time 0, then the physics of one `step(render=True)`, callbacks not called."""
        self._time = 0.0
        self._time_origin = 0.0
        self._index = 0
        self.play()
        for _ in range(self._steps_per_render()):
            self._advance()
        self._forward()

    def _steps_per_render(self) -> int:
        return max(1, round(self._rendering_dt / self._physics_dt))

    def is_simulating(self) -> bool:
        """Whether a compiled model exists (Isaac: a physics simulation view exists)."""
        return self._sim is not None

    @property
    def physics_sim_view(self) -> SimHandle | None:
        """The compiled model and data (Isaac's physics simulation view); None before the first reset."""
        return self._sim

    def play(self) -> None:
        """Start (or resume) the simulation; compiles the stage if never compiled. After a
        `stop()`, physics starts from the compiled initial state (and what was set while stopped)."""
        if self._sim is None:
            self._compile()
        self._playing = True
        self._stopped = False
        self._fire_timeline("PLAY")

    def pause(self) -> None:
        """Pause: `step()` still renders and runs task pre_steps, physics does not advance."""
        self._playing = False
        self._fire_timeline("PAUSE")

    def stop(self) -> None:
        """Stop: time and step index go back to 0 and, as Isaac's Stop, the objects and robots
        go back to the compiled initial state (poses read while stopped are those); what is set
        while stopped is where the next `play()` starts."""
        was = not self._stopped
        self._playing = False
        self._stopped = True
        self._time = 0.0
        self._time_origin = 0.0
        self._index = 0
        if was and self._sim is not None:
            self._reset_physics_state()
        if was:
            self._fire_timeline("STOP")

    def is_playing(self) -> bool:
        return self._playing

    def is_stopped(self) -> bool:
        return self._stopped

    async def reset_async(self, soft: bool = False) -> None:
        """`reset()`, awaitable (Isaac's extension workflow; `asyncio.run(world.reset_async())`)."""
        self.reset(soft)

    async def play_async(self) -> None:
        """`play()`, awaitable."""
        self.play()

    async def pause_async(self) -> None:
        """`pause()`, awaitable."""
        self.pause()

    async def stop_async(self) -> None:
        """`stop()`, awaitable."""
        self.stop()

    async def render_async(self) -> None:
        """`render()`, awaitable."""
        self.render()

    async def initialize_simulation_context_async(self) -> None:
        """Nothing to wait for: ready once constructed (Isaac sets up its USD stage here)."""

    def _fire_timeline(self, kind: str) -> None:
        self._timeline_callbacks.call(TimelineEvent(kind, {"currentTime": self.current_time}))

    # ------------------------------------------------------------------ stepping
    def step(self, render: bool = True, step_sim: bool = True, update_fabric: bool = False) -> None:
        """Physics (if playing): max(1, rendering_dt / physics_dt) physics steps with
        render=True, one with render=False; then render (`update_fabric`: no Fabric here).

        Physics callbacks run before each physics step with `step_size = physics_dt`.
        """
        if self._playing and step_sim and not self._physics_off:
            if self._compiled_version != self._stage.version and not self._warned_dirty:
                logger.warning("the stage changed since the last world.reset(); new prims appear after a reset")
                self._warned_dirty = True
            n = self._steps_per_render() if render else 1
            for _ in range(n):
                self._physics_step()
        if render:
            self.render()

    def _physics_step(self) -> None:
        self._physics_callbacks.call(self._physics_dt)
        self._advance()

    def _advance(self) -> None:
        """One physics step of the model (no callbacks); time and step index advance. Then the
        joint limits are enforced and MuJoCo's warnings of the step reported (see the module
        docstring).

        Raises:
            SimulationInstabilityError: MuJoCo found the step numerically unstable.
        """
        sim = self._sim
        substeps.step(sim, self._physics_dt, self.physics_substeps)
        sim.kinematics_stale = True
        self._index += 1
        self._time = self._time_origin + self._index * self._physics_dt
        fatal = self._warnings.check(sim.model, sim.data, self._time)
        for core in self._cores:
            core.enforce_limits()
        for hook in sim.after_step:
            hook()
        if fatal is not None:
            for core in self._cores:  # MuJoCo reset the state, or ignored the controls
                core.reset_drive_targets()
            sim.mark_stale()
            raise SimulationInstabilityError(fatal)

    def render(self) -> None:
        """Capture a video frame if recording, update the viewer if one is open, and run the
        render callbacks."""
        if self._sim is None:
            return
        if self._recorder is not None:
            self._sim.ensure_kinematics()
            self._recorder.maybe_capture(self._sim.data, self._time, self._camera_view)
        self._notify("on_world_rendered")
        self._render_callbacks.call(TimelineEvent("RENDER", {"dt": self._rendering_dt}))

    # ------------------------------------------------------------------ camera and video
    def set_camera_view(self, eye, target) -> None:
        """Point the viewer's and the recording's camera from `eye` (3,) at `target` (3,) [m]."""
        self._camera_view = rec.CameraView.from_eye_target(eye, target)
        self._notify("on_camera_changed")

    def get_camera_view(self) -> rec.CameraView:
        return self._camera_view

    def start_recording(self, path: str | Path, camera: str | rec.CameraView | None = None, *, width: int = 640,
                        height: int = 480, fps: float = 30.0) -> None:
        """Write an MP4 of a camera view, a frame every 1/fps of simulated time on render.

        Offscreen (EGL or OSMesa, `manip.sim.core.recording`), after `reset()`; a recompile ends it.

        Args:
            path: output file (.mp4).
            camera: name of a model camera, a CameraView, or None for the World's view
                (`set_camera_view`).
            width, height, fps: frame size [px]; frames per second of simulated time.

        Raises:
            OffscreenRenderingError: no offscreen GL backend or no imageio-ffmpeg.
            SimulationError: before the first reset, or already recording.
        """
        if self._sim is None:
            raise SimulationError("start_recording: call world.reset() first (the model is not compiled)")
        if self._recorder is not None:
            raise SimulationError(f"already recording to {self._recorder.path}; call stop_recording() first")
        rec.check_camera(self._sim.model, camera)
        self._recorder = rec.Recorder(self._sim.model, path, camera, width=width, height=height, fps=fps)
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

    def render_image(self, width: int = 640, height: int = 480, *,
                     camera: str | rec.CameraView | None = None) -> np.ndarray:
        """One offscreen RGB image (height, width, 3) uint8 of the current state [px], from a
        model camera's name, a CameraView, or the World's view (None)."""
        if self._sim is None:
            raise SimulationError("render_image: call world.reset() first")
        return rec.render_image(self._sim, width, height, camera, self._camera_view)
