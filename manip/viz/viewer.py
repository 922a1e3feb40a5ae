"""`Viewer`: a MotionGenerator's robot, world and plans in the browser (viser).

    viewer = Viewer(mg)          # starts the server, prints the URL
    viewer.show_plan(result)     # play/pause, time slider, tool path
    viewer.wait()                # keep serving until Ctrl-C

Shown: the robot's URDF visual meshes at a configuration, every obstacle of the planner's
world (attached objects in their own colour), a planned trajectory with its tool path and
tool frames, an IK target gizmo (release it: the robot plans to it and the status shows
in the GUI), and the collision spheres on demand (a GUI checkbox). Scene node names are
listed by `node_names()`; `server.scene.get_handle_by_name(name)` gives each node.

Over SSH: run the script on the remote machine, then `ssh -L 8080:localhost:8080 host`
on the laptop and open http://localhost:8080.
"""

from __future__ import annotations

import logging
import threading
import time

import numpy as np
from manip.errors import InvalidInputError
from manip.motion_generator import MotionGenerator
from manip.planning.result import PlanResult
from manip.pose import Pose
from manip.trajectory import Trajectory
from manip.viz.interact import TargetGizmo
from manip.viz.obstacles import AttachedDrawing, WorldDrawing
from manip.viz.playback import TrajectoryPlayback
from manip.viz.robot import RobotMeshes
from manip.viz.server import start_server
from manip.viz.spheres import SphereDrawing

logger = logging.getLogger(__name__)

class Viewer:
    """A browser view of a MotionGenerator: robot, world, plans, IK target, spheres.

    Args:
        mg: the motion generator whose robot, world and planner are shown.
        host: interface to serve on ("127.0.0.1": this machine only, reach it over SSH
            with port forwarding; "0.0.0.0": every interface).
        port: TCP port (the next free one if taken; `port` property says which).
        verbose: let viser print the URL and connection messages.
        gizmo: show the draggable IK target.
        grid: draw a ground grid at z = 0.
        q: (dof,) configuration to show first [rad] (default: the robot's default).

    Raises:
        InvalidInputError: `mg` is not a MotionGenerator, bad port or configuration.
    """

    def __init__(self, mg: MotionGenerator, *, host: str = "127.0.0.1", port: int = 8080, verbose: bool = True,
                 gizmo: bool = True, grid: bool = True, q: np.ndarray | None = None):
        if not isinstance(mg, MotionGenerator):
            raise InvalidInputError(f"Viewer needs a MotionGenerator; got {type(mg).__name__}")
        self.mg = mg
        self.server = start_server(host, port, verbose=verbose, grid=grid)
        scene = self.server.scene
        self._lock = threading.RLock()
        self.robot = RobotMeshes(scene, mg.kinematics)
        self.world = WorldDrawing(scene)
        self.attached = AttachedDrawing(scene, mg.fk)
        self.spheres = SphereDrawing(scene, mg.checker.spheres)
        self.playback: TrajectoryPlayback | None = None
        self.last_result: PlanResult | None = None
        cfg = mg.kinematics.config
        self.tool_link = cfg.tcp_link or cfg.ee_link
        gui = self.server.gui
        self.status = gui.add_markdown("**manip** viewer")
        self.spheres_checkbox = gui.add_checkbox("collision spheres", initial_value=False)
        self.spheres_checkbox.on_update(lambda _event: self.show_spheres(self.spheres_checkbox.value))
        self.configuration = np.array(mg.default_joint_positions if q is None else q, dtype=float)
        self.update_world()
        self.set_configuration(self.configuration)
        self.gizmo = TargetGizmo(scene, mg.fk(self.configuration), self.plan_to) if gizmo else None
        logger.info("manip viewer at %s", self.url)

    # ------------------------------------------------------------------ server
    @property
    def port(self) -> int:
        """The TCP port served."""
        return int(self.server.get_port())

    @property
    def url(self) -> str:
        """The page's address on the serving machine."""
        return f"http://localhost:{self.port}"

    def node_names(self) -> list[str]:
        """Names of the scene nodes the viewer drew (robot, world, attached, plan, spheres, gizmo)."""
        names = list(self.robot.handles) + list(self.world.handles) + list(self.attached.handles)
        if self.playback is not None:
            names += list(self.playback.handles)
        if self.spheres.handle is not None:
            names.append(self.spheres.name)
        if self.gizmo is not None:
            names.append(self.gizmo.name)
        return names

    def wait(self, timeout: float | None = None) -> None:
        """Keep serving until Ctrl-C, or for `timeout` seconds."""
        end = None if timeout is None else time.monotonic() + float(timeout)
        try:
            while end is None or time.monotonic() < end:
                time.sleep(0.1)
        except KeyboardInterrupt:
            pass

    def close(self) -> None:
        """Stop the playback and the server."""
        if self.playback is not None:
            self.playback.remove()
            self.playback = None
        self.server.stop()

    # ------------------------------------------------------------------ content
    def set_configuration(self, q: np.ndarray) -> None:
        """Show the robot (and attached objects, and shown spheres) at q (dof,) [rad]."""
        q = self.mg.kinematics.check_q(q, "q")
        if q.ndim != 1:
            raise InvalidInputError(f"q must have shape ({self.mg.robot_dof},); got {q.shape}")
        with self._lock:
            self.robot.set_configuration(q)
            self.attached.update(q)
            self.spheres.update(q)
            self.configuration = np.array(q, dtype=float)

    def update_world(self) -> None:
        """Redraw the planner's world and attached objects (call after editing the world)."""
        with self._lock:
            self.world.set_world(self.mg.world)
            self.attached.set_objects(self.mg.checker.attached_objects, self.configuration)

    def show_spheres(self, visible: bool = True) -> None:
        """Show or hide the collision spheres (at the current configuration)."""
        with self._lock:
            if visible:
                self.spheres.show(self.configuration)
            else:
                self.spheres.hide()
        if self.spheres_checkbox.value != bool(visible):
            self.spheres_checkbox.value = bool(visible)

    def _tool_poses(self, Q: np.ndarray) -> Pose:
        return self.mg.fk(Q, self.tool_link)

    def show_plan(self, plan: PlanResult | Trajectory, *, play: bool = True) -> TrajectoryPlayback | None:
        """Show a plan: its status, and, when it has a trajectory, playback and tool path.

        Args:
            plan: a PlanResult (its status is shown; failures show no motion) or a Trajectory.
            play: start playing at once.

        Returns:
            The playback (GUI and scene nodes of the motion), or None for a failed plan.
        """
        if isinstance(plan, PlanResult):
            self.last_result = plan
            hint = "" if plan.success else f"  \n{plan.status.hint}"
            self.status.content = (f"**{plan.status.name}** {plan.message}{hint}  \n"
                                   f"planning {plan.plan_time * 1e3:.0f} ms"
                                   + (f", motion {plan.trajectory.duration:.2f} s" if plan.trajectory else ""))
            trajectory = plan.trajectory if plan.success else None
        elif isinstance(plan, Trajectory):
            trajectory = plan
        else:
            raise InvalidInputError(f"show_plan needs a PlanResult or a Trajectory; got {type(plan).__name__}")
        with self._lock:
            if self.playback is not None:
                self.playback.remove()
                self.playback = None
            if trajectory is None:
                return None
            if trajectory.dof != self.mg.robot_dof:
                raise InvalidInputError(f"the trajectory has {trajectory.dof} joints; the robot {self.mg.robot_dof}")
            self.playback = TrajectoryPlayback(self.server, trajectory, self.set_configuration, self._tool_poses)
        if play:
            self.playback.play()
        return self.playback

    def plan_to(self, goal: Pose) -> PlanResult:
        """Plan from the shown configuration to a pose of the end-effector and show the result.

        What the IK gizmo calls on release. The robot is first put at rest where it is shown.
        """
        if self.playback is not None:
            self.playback.pause()
        start = self.configuration.copy()
        self.status.content = "planning..."
        result = self.mg.plan_pose(start, goal)
        self.show_plan(result)
        return result
