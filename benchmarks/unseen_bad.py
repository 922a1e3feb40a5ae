"""Inputs users get wrong, for `benchmarks/unseen.py bad`: each must raise a clear error naming
what was wrong, or give a failed result with a status and a message; never a success."""

from __future__ import annotations

import traceback

import numpy as np

from manip import MotionGenerator, OrientationConstraint, Pose

TCP = "panda_hand_tcp"

def bad_inputs() -> list[tuple[str, object]]:
    """(label, call) pairs of inputs users get wrong; each call must raise a ManipError (or a
    ValueError/KeyError/TypeError naming the argument) or return a failed result, but those
    labelled "valid: ", unusual inputs that mean something (a zero-length capsule is a sphere),
    which must succeed."""
    from manip import PositionConstraint, RelativePoseConstraint, WorldConfig

    fr = MotionGenerator("franka")
    q0 = fr.default_joint_positions
    ur = MotionGenerator("ur5")
    u0 = ur.default_joint_positions
    duo = MotionGenerator("dual_franka")
    d0 = duo.default_joint_positions
    down = [0, 1, 0, 0]
    far = Pose([3.0, 0.0, 0.3], down)
    cases = [
        ("ur5: a 7-joint start", lambda: ur.plan_joints(np.r_[u0, 0.0], u0)),
        ("ur5: a Franka link", lambda: ur.plan_pose(u0, Pose([0.4, 0, 0.3], down), link="panda_hand")),
        ("xarm7: NaN goal", lambda: MotionGenerator("xarm7").plan_joints(np.zeros(7), np.full(7, np.nan))),
        ("kinova: goal 0.5 rad past a limit", lambda: _kin_past_limit()),
        ("franka: goal out of reach (3 m)", lambda: fr.plan_pose(q0, far)),
        ("ur5: goal out of reach (3 m)", lambda: ur.plan_pose(u0, far)),
        ("franka: Pose.from_list non-unit quaternion", lambda: fr.plan_pose(q0, Pose.from_list([0.4, 0, 0.3, 0, 2, 0, 0]))),
        ("franka: zero quaternion", lambda: fr.plan_pose(q0, Pose([0.4, 0, 0.3], [0, 0, 0, 0]))),
        ("franka: 2-d position", lambda: fr.plan_pose(q0, Pose([0.4, 0], down))),
        ("franka: goal a list of 7 numbers", lambda: fr.plan_pose(q0, [0.4, 0, 0.3, 0, 1, 0, 0])),
        ("franka: start in a box", lambda: _in_box(fr, q0)),
        ("franka: robot inside a 10 km box", lambda: _absurd_box(q0)),
        ("world: negative dims", lambda: WorldConfig.from_dict({"cuboid": {"b": {"dims": [-1, 1, 1], "pose": [0, 0, 0, 1, 0, 0, 0]}}})),
        ("world: zero radius sphere", lambda: WorldConfig.from_dict({"sphere": {"s": {"radius": 0.0, "position": [1, 0, 0]}}})),
        ("world: NaN pose", lambda: WorldConfig.from_dict({"cuboid": {"b": {"dims": [1, 1, 1], "pose": [np.nan, 0, 0, 1, 0, 0, 0]}}})),
        ("valid: world: capsule base == tip", lambda: WorldConfig.from_dict({"capsule": {"c": {"radius": 0.1, "base": [1, 0, 0], "tip": [1, 0, 0]}}})),
        ("world: missing mesh file", lambda: WorldConfig.from_dict({"mesh": {"m": {"file_path": "/nonexistent.stl", "pose": [1, 0, 0, 1, 0, 0, 0]}}})),
        ("world: unknown kind", lambda: WorldConfig.from_dict({"cube": {"b": {"dims": [1, 1, 1]}}})),
        ("robot inside a 1e9 m cuboid", lambda: MotionGenerator("franka", {"cuboid": {"b": {"dims": [1e9] * 3, "pose": [0, 0, 0, 1, 0, 0, 0]}}}).plan_joints(q0, q0 + 0.1)),
        ("valid: a 1e9 m floor below the base", lambda: MotionGenerator("franka", {"cuboid": {"f": {"dims": [1e9, 1e9, 1.0], "pose": [0, 0, -0.5, 1, 0, 0, 0]}}}).plan_joints(q0, q0 + 0.3)),
        ("OrientationConstraint zero axis", lambda: OrientationConstraint(axis=(0, 0, 0), direction=(0, 0, -1), tolerance=0.1)),
        ("OrientationConstraint negative tolerance", lambda: OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=-0.1)),
        ("OrientationConstraint tolerance 10 rad", lambda: OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=10)),
        ("OrientationConstraint unknown link", lambda: fr.plan_joints(q0, q0 + 0.1, constraints=(OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=0.5, link="gripper"),))),
        ("PositionConstraint lower > upper", lambda: PositionConstraint(lower=(1, 0, 0), upper=(0, 1, 1))),
        ("valid: constraints not a tuple", lambda: fr.plan_joints(q0, q0 + 0.1, constraints=OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=3.0))),
        ("RelativePoseConstraint one link twice", lambda: duo.plan_joints(d0, d0, constraints=(RelativePoseConstraint("left_panda_hand", "left_panda_hand"),))),
        ("RelativePoseConstraint unknown link", lambda: duo.plan_joints(d0, d0 + 0.05, constraints=(RelativePoseConstraint("left_panda_hand", "panda_hand"),))),
        ("plan_grasp unknown object", lambda: fr.plan_grasp(q0, Pose.stack([Pose([0.5, 0, 0.1], down)]), "nothing")),
        ("plan_grasp negative approach", lambda: _grasp(fr, q0, approach=-0.1)),
        ("valid: plan_grasp a single Pose", lambda: _grasp(fr, q0, single=True)),
        ("plan_grasp a list of Poses", lambda: _grasp(fr, q0, as_list=True)),
        ("plan_place with nothing attached", lambda: fr.plan_place(q0, Pose.stack([Pose([0.5, 0, 0.1])]))),
        ("attach_object unknown name", lambda: fr.attach_object("nothing", q=q0)),
        ("valid: detach_object with nothing attached", lambda: fr.detach_object(q0)),
        ("a finger inside panda_link5 as the goal", lambda: fr.plan_joints(q0, [-0.7005, 0.9538, 1.6255, -1.1995, 1.0952, -0.0043, 2.5645])),
        ("valid: plan_poses on one arm", lambda: fr.plan_poses(q0, {"panda_hand": Pose([0.4, 0, 0.3], down)})),
        ("plan_poses two links of one arm", lambda: duo.plan_poses(d0, {"left_panda_hand": Pose([0.4, 0.2, 0.3], down), "left_panda_link7": Pose([0.4, 0.2, 0.4], down)})),
        ("dual_franka: a 7-joint start", lambda: duo.plan_joints(q0, q0)),
        ("plan_batch 3 starts, 2 goals", lambda: fr.plan_batch(np.stack([q0] * 3), np.stack([q0] * 2))),
        ("time_budget 0", lambda: fr.plan_joints(q0, q0 + 0.1, time_budget=0.0)),
        ("time_budget -1", lambda: fr.plan_joints(q0, q0 + 0.1, time_budget=-1.0)),
        ("velocity_scale 0", lambda: fr.plan_joints(q0, q0 + 0.1, velocity_scale=0.0)),
        ("velocity_scale 2", lambda: fr.plan_joints(q0, q0 + 0.1, velocity_scale=2.0)),
        ("valid: dt 10 s", lambda: fr.plan_joints(q0, q0 + 0.1, dt=10.0)),
        ("duration shorter than feasible", lambda: fr.plan_joints(q0, q0 + 1.0, duration=0.01)),
        ("ik a list", lambda: fr.ik([0.4, 0, 0.3, 1, 0, 0, 0])),
        ("unknown robot", lambda: MotionGenerator("panda_arm")),
        ("world a string", lambda: MotionGenerator("franka", "table.yaml")),
        ("batch: unknown robot", lambda: _batch_unknown_robot()),
        ("linear to an out-of-reach goal", lambda: fr.plan_pose(q0, far, linear=True)),
        ("goalset empty", lambda: fr.plan_goalset(q0, Pose.stack([]))),
        ("tutorial: non-unit xyzw quaternion", lambda: _tutorial().ik([0.4, 0, 0.3, 0, 0, 0, 2])),
        ("tutorial: ragged ik_batch", lambda: _tutorial().ik_batch([[0.4, 0, 0.3, 1, 0, 0, 0], [0.4, 0, 0.3]])),
        ("tutorial: a 6-value pose", lambda: _tutorial().motion_generate(list(q0), goal_end_effector_pose=[0.4, 0, 0.3, 0, 1, 0])),
        ("tutorial: both goals", lambda: _tutorial().motion_generate(list(q0), [0.4, 0, 0.3, 1, 0, 0, 0], list(q0))),
        ("tutorial: an 8-value start", lambda: _tutorial().motion_generate(list(q0) + [0.04], goal_joint_angles=list(q0))),
        ("tutorial: set_constraint of 3", lambda: _tutorial().set_constraint([1, 1, 1])),
        ("tutorial: goal out of reach", lambda: _tutorial().motion_generate(list(q0), [3.0, 0, 0.3, 1, 0, 0, 0])),
    ]
    return cases


_TUTORIAL: list = []


def _tutorial():
    """The Isaac tutorial's wrapper as its scripts build it (one, reused)."""
    from manip import TutorialMotionGen

    if not _TUTORIAL:
        t = TutorialMotionGen("franka.yml")
        t.init_motion_gen()
        _TUTORIAL.append(t)
    return _TUTORIAL[0]


def _kin_past_limit():
    mg = MotionGenerator("kinova")
    g = mg.default_joint_positions.copy()
    k = int(np.argmin(mg.upper_limits))
    g[k] = mg.upper_limits[k] + 0.5
    return mg.plan_joints(mg.default_joint_positions, g)


def _in_box(mg, q):
    from manip import Cuboid

    mg.update_world({})
    mg.add_obstacle(Cuboid("box", [0.3, 0.3, 0.3], mg.fk(q)))
    try:
        return mg.plan_joints(q, q + 0.1)
    finally:
        mg.update_world({})


def _absurd_box(q):
    mg = MotionGenerator("franka", {"cuboid": {"b": {"dims": [1e4, 1e4, 1e4], "pose": [0, 0, 0, 1, 0, 0, 0]}}})
    return mg.plan_joints(q, q + 0.1)


def _grasp(mg, q, approach=0.1, single=False, as_list=False):
    from manip import Cuboid

    mg.update_world({})
    mg.add_obstacle(Cuboid("cube", [0.05, 0.05, 0.05], Pose([0.5, 0, 0.025])))
    g = [Pose([0.5, 0, 0.03], [0, 1, 0, 0])]
    grasps = g[0] if single else (g if as_list else Pose.stack(g))
    try:
        return mg.plan_grasp(q, grasps, "cube", approach=approach, link=TCP)
    finally:
        mg.update_world({})


def _batch_unknown_robot():
    from manip.batch import Problem, plan_many

    return plan_many([Problem({}, np.zeros(6), np.zeros(6), robot="ur7")], workers=1)


def run_bad(args) -> list[dict]:
    from manip import ManipError

    rows = []
    for label, call in bad_inputs():
        row = {"part": "bad", "robot": "", "goal": label}
        try:
            r = call()
        except ManipError as exc:
            row.update(status="ManipError", kind=type(exc).__name__, message=str(exc)[:240])
        except (ValueError, KeyError, TypeError) as exc:
            row.update(status="other error", kind=type(exc).__name__, message=str(exc)[:240])
        except Exception as exc:  # noqa: BLE001 - a finding
            row.update(status="UNCLEAR", kind=type(exc).__name__, message=str(exc)[:240],
                       trace=traceback.format_exc()[-600:])
        else:
            valid = label.startswith("valid: ")
            if r is None and label.startswith("tutorial"):   # the tutorial API's failure (the reason is logged)
                row.update(status="failed result", kind="None (reason logged)", message="")
            elif hasattr(r, "status") and hasattr(r, "success"):
                status = ("accepted" if valid else "SILENT SUCCESS") if r.success else "failed result"
                row.update(status=status, kind=r.status.name, message=(r.message or "")[:240], success=bool(r.success))
            else:
                row.update(status="accepted" if valid else "RETURNED", kind=type(r).__name__, message=repr(r)[:120])
        if label.startswith("valid: ") and row["status"] != "accepted":
            row["status"] = "VALID INPUT REFUSED"
        rows.append(row)
        print(f"{label:<45} {row['status']:<14} {row['kind']:<28} {row['message'][:150]}", flush=True)
    return rows

