"""Generate robots/franka/franka.xml (MuJoCo MJCF) from the example-robot-data Panda URDF.

MuJoCo's own URDF import fuses fixed joints (panda_link8, panda_hand, panda_hand_tcp vanish)
and cannot read the .dae visual meshes, so the MJCF is written here instead: the kinematic
tree, joint axes and limits, inertials and collision geometry are read from the URDF; what
the URDF does not say (drive gains, armature, contact parameters, the home keyframe) is set
by the constants below.

Usage (from the repository root)::

    .venv/bin/python robots/tools/make_franka_mjcf.py            # writes robots/franka/franka.xml
    .venv/bin/python robots/tools/make_franka_mjcf.py --check    # exit 1 if the file is stale

The collision STL meshes must already be in robots/franka/assets/ (copied from
example-robot-data's panda_description/meshes/collision/).
"""

from __future__ import annotations

import argparse
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

ROBOTS = Path(__file__).resolve().parents[1]
OUT = ROBOTS / "franka" / "franka.xml"

ARM_JOINTS = [f"panda_joint{i}" for i in range(1, 8)]
FINGER_JOINTS = ["panda_finger_joint1", "panda_finger_joint2"]
HOME_ARM = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785]
HOME_FINGERS = [0.04, 0.04]

# Drives: MuJoCo `position` actuators, tau = kp (q_target - q) - kv qdot, clamped to the
# URDF effort. kv is integrated implicitly with the implicit / implicitfast integrators.
ARM_KP = [6000.0, 6000.0, 5000.0, 5000.0, 3000.0, 3000.0, 3000.0]   # [N m / rad]
ARM_KV = [80.0, 80.0, 60.0, 60.0, 30.0, 30.0, 30.0]                 # [N m s / rad]
ARM_ARMATURE = 0.1       # [kg m^2] reflected rotor inertia (not in the URDF)
ARM_DAMPING = 0.0        # [N m s / rad] passive joint damping (the drive's kv does the work)
FINGER_KP = 1500.0       # [N / m]
FINGER_KV = 10.0         # [N s / m]
FINGER_FORCE = 70.0      # [N] per finger: the grip force once a finger stalls on an object
FINGER_ARMATURE = 0.01   # [kg]
FINGER_DAMPING = 0.0     # [N s / m]
FINGER_FRICTION = "1.2 0.02 0.0001"   # sliding, torsional [m], rolling [m]


def _rpy_to_quat(rpy: list[float]) -> np.ndarray:
    """URDF roll-pitch-yaw (R = Rz(y) Ry(p) Rx(r)) to a (w, x, y, z) quaternion."""
    r, p, y = (0.5 * a for a in rpy)
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array([
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ])


def _f(values) -> str:
    """Format numbers compactly for XML (-0 printed as 0)."""
    out = []
    for v in np.atleast_1d(np.asarray(values, dtype=float)):
        s = f"{0.0 if abs(v) < 1e-12 else v:.12g}"
        out.append("0" if s == "-0" else s)
    return " ".join(out)


def _origin(el: ET.Element | None) -> tuple[list[float], list[float]]:
    if el is None:
        return [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    xyz = [float(v) for v in el.get("xyz", "0 0 0").split()]
    rpy = [float(v) for v in el.get("rpy", "0 0 0").split()]
    return xyz, rpy


def _pose_attrs(xyz: list[float], rpy: list[float]) -> str:
    s = ""
    if any(abs(v) > 0 for v in xyz):
        s += f' pos="{_f(xyz)}"'
    if any(abs(v) > 0 for v in rpy):
        s += f' quat="{_f(_rpy_to_quat(rpy))}"'
    return s


def _inertial(link: ET.Element) -> str:
    inert = link.find("inertial")
    mass = float(inert.find("mass").get("value"))
    xyz, rpy = _origin(inert.find("origin"))
    i = inert.find("inertia")
    full = [float(i.get(k)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")]
    pose = _pose_attrs(xyz, rpy) or ' pos="0 0 0"'
    return f'<inertial{pose} mass="{_f(mass)}" fullinertia="{_f(full)}"/>'


def generate(urdf_path: Path, srdf_path: Path) -> str:
    """Return the MJCF text for the Panda described by the URDF and SRDF."""
    urdf = ET.parse(urdf_path).getroot()
    links = {l.get("name"): l for l in urdf.findall("link")}
    joints = {j.get("name"): j for j in urdf.findall("joint")}
    child_joint = {j.find("child").get("link"): j for j in joints.values()}

    def joint_of(link: str) -> ET.Element:
        return child_joint[link]

    L: list[str] = []
    ind = "  "

    def arm_body(i: int, depth: int) -> None:
        name = f"panda_link{i}"
        link = links[name]
        pad = ind * depth
        if i == 0:
            L.append(f'{pad}<body name="{name}" childclass="panda">')
        else:
            j = joint_of(name)
            xyz, rpy = _origin(j.find("origin"))
            L.append(f'{pad}<body name="{name}"{_pose_attrs(xyz, rpy)}>')
            lim = j.find("limit")
            axis = j.find("axis").get("xyz")
            L.append(f'{pad}{ind}<joint name="{j.get("name")}" axis="{axis}" '
                     f'range="{lim.get("lower")} {lim.get("upper")}" '
                     f'actuatorfrcrange="{-float(lim.get("effort")):g} {float(lim.get("effort")):g}"/>')
        L.append(f"{pad}{ind}{_inertial(link)}")
        L.append(f'{pad}{ind}<geom class="link" mesh="link{i}" name="{name}_collision"/>')
        if i < 7:
            arm_body(i + 1, depth + 1)
        else:
            hand(depth + 1)
        L.append(f"{pad}</body>")

    def hand(depth: int) -> None:
        pad = ind * depth
        # panda_link8 (fixed, massless) and panda_hand (fixed) fused into one body by hand.
        j8 = joints["panda_joint8"]
        jh = joints["panda_hand_joint"]
        xyz8, rpy8 = _origin(j8.find("origin"))
        xyzh, rpyh = _origin(jh.find("origin"))
        if any(rpy8) or any(xyzh):
            raise RuntimeError("expected panda_joint8 to be a pure translation and panda_hand_joint a pure rotation")
        L.append(f"{pad}<!-- panda_link8 ({_f(xyz8)} from panda_link7) fused: the hand frame is "
                 f"panda_link8 rotated by rpy {_f(rpyh)} -->")
        L.append(f'{pad}<body name="panda_hand"{_pose_attrs(xyz8, rpyh)}>')
        L.append(f"{pad}{ind}{_inertial(links['panda_hand'])}")
        L.append(f'{pad}{ind}<geom class="link" mesh="hand" name="panda_hand_collision"/>')
        L.append(f'{pad}{ind}<site name="panda_hand" size="0.005" rgba="1 0 0 1" group="4"/>')
        jt = joints["panda_hand_tcp_joint"]
        xyzt, rpyt = _origin(jt.find("origin"))
        L.append(f'{pad}{ind}<site name="panda_hand_tcp"{_pose_attrs(xyzt, rpyt)} size="0.005" '
                 f'rgba="0 1 0 1" group="4"/>')
        for fj, link_name, side in (("panda_finger_joint1", "panda_leftfinger", "left"),
                                    ("panda_finger_joint2", "panda_rightfinger", "right")):
            j = joints[fj]
            xyz, rpy = _origin(j.find("origin"))
            lim = j.find("limit")
            L.append(f'{pad}{ind}<body name="{link_name}"{_pose_attrs(xyz, rpy)}>')
            L.append(f'{pad}{ind * 2}<joint name="{fj}" class="finger" axis="{j.find("axis").get("xyz")}" '
                     f'range="{lim.get("lower")} {lim.get("upper")}"/>')
            link = links[link_name]
            L.append(f"{pad}{ind * 2}{_inertial(link)}")
            vis = link.find("visual")
            _, vrpy = _origin(vis.find("origin"))
            L.append(f'{pad}{ind * 2}<geom class="finger_visual" mesh="finger"{_pose_attrs([0, 0, 0], vrpy)}/>')
            names = ["mount", "sledge", "diagonal", "pad"]   # URDF comment order
            for n, col in zip(names, link.findall("collision")):
                cxyz, crpy = _origin(col.find("origin"))
                size = [0.5 * float(v) for v in col.find("geometry/box").get("size").split()]
                cls = "finger_pad" if n == "pad" else "finger_collision"
                L.append(f'{pad}{ind * 2}<geom name="{link_name}_{n}" class="{cls}" type="box" '
                         f'size="{_f(size)}"{_pose_attrs(cxyz, crpy)}/>')
            L.append(f"{pad}{ind}</body>")
        L.append(f"{pad}</body>")

    arm_body(0, 2)

    srdf = ET.parse(srdf_path).getroot()
    excludes = []
    bodies = {f"panda_link{i}" for i in range(8)} | {"panda_hand", "panda_leftfinger", "panda_rightfinger"}
    for dc in srdf.findall("disable_collisions"):
        a, b = dc.get("link1"), dc.get("link2")
        if a in bodies and b in bodies:
            excludes.append(tuple(sorted((a, b))))
    excludes = sorted(set(excludes))

    arm_acts = []
    for name, kp, kv in zip(ARM_JOINTS, ARM_KP, ARM_KV):
        eff = float(joints[name].find("limit").get("effort"))
        arm_acts.append(f'    <position name="{name}" joint="{name}" kp="{_f(kp)}" kv="{_f(kv)}" '
                        f'forcerange="{-eff:g} {eff:g}" inheritrange="1"/>')
    fing_acts = [f'    <position name="{n}" joint="{n}" class="finger" inheritrange="1"/>' for n in FINGER_JOINTS]

    home_q = HOME_ARM + HOME_FINGERS
    head = f"""<!--
  Franka Emika Panda for MuJoCo, generated by robots/tools/make_franka_mjcf.py from the
  example-robot-data URDF (kinematics, limits, inertials, collision meshes and finger boxes)
  and SRDF (disabled self-collision pairs -> <exclude>). Do not edit by hand: change the
  generator and rerun it.

  Names: bodies = URDF links (panda_link0..7, panda_hand, panda_leftfinger, panda_rightfinger;
  panda_link8 is fused into panda_hand), joints = URDF joints, sites panda_hand (hand frame)
  and panda_hand_tcp (0.1034 m along the hand z axis). One position actuator per joint,
  named after its joint: tau = kp (target - q) - kv qdot, clamped to the URDF effort.
  The fingers are independent (no equality): each has its own actuator.
  Tuned for timestep <= 0.002 s; stable with the Euler and implicitfast integrators
  (implicitfast recommended). No <option>, floor or light here: the World supplies them.
-->
<mujoco model="franka">
  <compiler angle="radian" meshdir="assets" autolimits="true"/>

  <default>
    <default class="panda">
      <joint armature="{ARM_ARMATURE:g}" damping="{ARM_DAMPING:g}"/>
      <geom contype="1" conaffinity="1" condim="3" friction="1 0.005 0.0001"/>
      <default class="link">
        <geom type="mesh" group="2" material="panda_white"/>
      </default>
      <default class="finger">
        <joint type="slide" armature="{FINGER_ARMATURE:g}" damping="{FINGER_DAMPING:g}"/>
        <position kp="{_f(FINGER_KP)}" kv="{_f(FINGER_KV)}" forcerange="{-FINGER_FORCE:g} {FINGER_FORCE:g}"/>
      </default>
      <default class="finger_visual">
        <geom type="mesh" contype="0" conaffinity="0" group="2" material="panda_white"/>
      </default>
      <default class="finger_collision">
        <geom type="box" group="3" rgba="0.3 0.3 0.3 1"/>
      </default>
      <default class="finger_pad">
        <geom type="box" group="3" rgba="0.1 0.1 0.1 1" condim="6" priority="1"
              friction="{FINGER_FRICTION}" solref="0.005 1" solimp="0.97 0.995 0.001 0.5 2"/>
      </default>
    </default>
  </default>

  <asset>
    <material name="panda_white" rgba="0.95 0.95 0.95 1"/>
"""
    L_assets = [f'    <mesh name="{m}" file="{m}.stl"/>' for m in
                [f"link{i}" for i in range(8)] + ["hand", "finger"]]
    body_text = "\n".join(L)
    ex = "\n".join(f'    <exclude body1="{a}" body2="{b}"/>' for a, b in excludes)
    key_ctrl = home_q
    return (
        head + "\n".join(L_assets) + "\n  </asset>\n\n  <worldbody>\n" + body_text + "\n  </worldbody>\n\n"
        "  <!-- SRDF disabled collision pairs -->\n  <contact>\n" + ex + "\n  </contact>\n\n"
        '  <actuator>\n' + "\n".join(arm_acts) + "\n" + "\n".join(fing_acts) + "\n  </actuator>\n\n"
        f'  <keyframe>\n    <key name="home" qpos="{_f(home_q)}" ctrl="{_f(key_ctrl)}"/>\n  </keyframe>\n'
        "</mujoco>\n"
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only check that franka.xml is up to date")
    args = parser.parse_args()
    sys.path.insert(0, str(ROBOTS.parent))
    from manip.robot_config import load_robot_config

    cfg = load_robot_config("franka")
    text = generate(cfg.urdf_path, cfg.srdf_path)
    if args.check:
        current = OUT.read_text() if OUT.exists() else ""
        if current != text:
            print(f"{OUT} is stale: rerun {Path(__file__).name}")
            return 1
        print(f"{OUT} is up to date")
        return 0
    OUT.write_text(text)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
