"""Build a robot's MuJoCo model (MJCF) from its URDF, SRDF and robot.yaml.

MuJoCo's own URDF compiler reads the kinematic tree, joint axes, inertials and collision
geometry. Before it, the URDF is trimmed to the robot below `base_link`, mimic couplings
are dropped (each finger gets its own actuator) and every massless, geometry-less fixed
link (a tool frame such as `tool0` or `panda_hand_tcp`) is fused into its parent and kept
as a site; fixed links with mass or geometry stay bodies. After it (on the `MjSpec`):
the planner's joint limits, a site for `ee_link` and `tcp_link`, one position actuator per
arm joint and per gripper joint, the SRDF's disabled pairs as contact excludes, and a
"home" keyframe (default configuration, fingers open).

Drive gains come from the yaml's `sim:` section; without them each arm joint gets a
critically damped drive of DEFAULT_DRIVE_HZ on its inertia at home (the joint-space
inertia matrix diagonal plus armature): kp = w^2 I, kv = 2 w I, w = 2 pi f. Meshes other
than STL (e.g. COLLADA .dae) become the binary STL of their convex hull (loaded with coal).
"""

from __future__ import annotations

import logging
import math
import struct
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import coal
import mujoco
import numpy as np
from scipy.spatial import ConvexHull

from manip import package_uri
from manip.errors import RobotConfigError
from manip.robot_config import RobotConfig

logger = logging.getLogger(__name__)

DEFAULT_DRIVE_HZ = 8.0       # [Hz] natural frequency of the default arm drives
DEFAULT_ARMATURE = 0.1       # [kg m^2] reflected rotor inertia of an arm joint (not in URDFs)
DEFAULT_FINGER_KP = 1500.0   # [N/m]
DEFAULT_FINGER_KV = 10.0     # [N s/m]
DEFAULT_FINGER_FORCE = 70.0  # [N]
DEFAULT_FINGER_ARMATURE = 0.01  # [kg]


def _origin(el: ET.Element | None) -> np.ndarray:
    """4x4 transform of a URDF <origin> (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    T = np.eye(4)
    if el is None:
        return T
    x = [float(v) for v in el.get("xyz", "0 0 0").split()]
    r, p, y = (float(v) for v in el.get("rpy", "0 0 0").split())
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    T[:3, :3] = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                 [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                 [-sp, cp * sr, cp * cr]]
    T[:3, 3] = x
    return T


def _set_origin(el: ET.Element, T: np.ndarray) -> None:
    """Write T into an <origin> child of `el` (xyz + rpy)."""
    o = el.find("origin")
    if o is None:
        o = ET.SubElement(el, "origin")
    R = T[:3, :3]
    pitch = math.asin(-max(-1.0, min(1.0, R[2, 0])))
    if abs(math.cos(pitch)) > 1e-9:
        roll, yaw = math.atan2(R[2, 1], R[2, 2]), math.atan2(R[1, 0], R[0, 0])
    else:  # gimbal lock: put everything into yaw
        roll, yaw = 0.0, math.atan2(-R[0, 1], R[1, 1])
    o.set("xyz", " ".join(repr(float(v)) for v in T[:3, 3]))
    o.set("rpy", " ".join(repr(float(v)) for v in (roll, pitch, yaw)))


def _quat(R: np.ndarray) -> np.ndarray:
    q = np.empty(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(R, dtype=float).ravel())
    return q


@dataclass
class _Prepared:
    xml: str
    meshes: dict[str, Path] = field(default_factory=dict)   # asset file name -> source file
    sites: list[tuple[str, str, np.ndarray]] = field(default_factory=list)  # (name, body, T_body_site)
    body_of_link: dict[str, str] = field(default_factory=dict)


def _mass(link: ET.Element) -> float:
    """The link's URDF mass [kg] (0 without an <inertial>)."""
    m = link.find("inertial/mass")
    return 0.0 if m is None else float(m.get("value", "0"))


def _f(values) -> str:
    """Numbers for XML at full precision (12 significant digits; -0 printed as 0)."""
    out = []
    for v in np.atleast_1d(np.asarray(values, dtype=float)):
        t = f"{0.0 if abs(v) < 1e-15 else v:.12g}"
        out.append("0" if t == "-0" else t)
    return " ".join(out)


def _full_precision(xml: str, model: mujoco.MjModel) -> str:
    """MjSpec.to_xml writes 6 significant digits; rewrite the frames that set the kinematics
    (body, inertial and site placements, masses, joint ranges) from the compiled model at full precision."""
    root = ET.fromstring(xml)
    for el in root.iter("body"):
        if el.get("name"):
            b = model.body(el.get("name"))
            el.set("pos", _f(b.pos))
            el.set("quat", _f(b.quat))
            inertial = el.find("inertial")
            if inertial is not None:
                inertial.attrib.pop("fullinertia", None)
                inertial.set("pos", _f(b.ipos))
                inertial.set("quat", _f(b.iquat))
                inertial.set("mass", _f(b.mass))
                inertial.set("diaginertia", _f(b.inertia))
    for el in root.iter("site"):
        s = model.site(el.get("name"))
        el.set("pos", _f(s.pos))
        el.set("quat", _f(s.quat))
    for el in root.iter("joint"):
        if el.get("range") is not None:
            el.set("range", _f(model.joint(el.get("name")).range))
    for el in root.findall("size"):  # nkey: would conflict when the model is attached into a scene
        root.remove(el)
    ET.indent(root, "  ")
    return ET.tostring(root, encoding="unicode") + "\n"


def _resolve_mesh(uri: str, config: RobotConfig) -> Path:
    return package_uri.resolve(uri, config.urdf_path)


def _prepare(config: RobotConfig) -> _Prepared:
    """Trim, fuse and rewrite the URDF for MuJoCo's compiler (see the module docstring)."""
    root = ET.parse(config.urdf_path).getroot()
    links = {el.get("name"): el for el in root.findall("link")}
    joints = list(root.findall("joint"))
    if config.base_link not in links:
        raise RobotConfigError(f"{config.urdf_path}: no link '{config.base_link}'")
    # keep only the subtree below base_link
    children: dict[str, list[ET.Element]] = {}
    for j in joints:
        children.setdefault(j.find("parent").get("link"), []).append(j)
    keep, stack = {config.base_link}, [config.base_link]
    while stack:
        for j in children.get(stack.pop(), []):
            keep.add(j.find("child").get("link"))
            stack.append(j.find("child").get("link"))
    for el in list(root):
        if el.tag == "link" and el.get("name") not in keep:
            root.remove(el)
        elif el.tag == "joint" and (el.find("child").get("link") not in keep
                                    or el.find("parent").get("link") not in keep):
            root.remove(el)
        elif el.tag not in ("link", "joint", "material"):
            root.remove(el)   # transmissions, gazebo plugins, ...
    prep = _Prepared("")
    # fuse massless, geometry-less fixed links into their parents (sites)
    changed = True
    while changed:
        changed = False
        for j in root.findall("joint"):
            child = j.find("child").get("link")
            link = root.find(f"link[@name='{child}']")
            if j.get("type") != "fixed" or link.find("collision") is not None or _mass(link) > 0.0:
                continue
            parent = j.find("parent").get("link")
            T = _origin(j.find("origin"))
            prep.sites.append((child, parent, T))
            for k in root.findall("joint"):
                if k.find("parent").get("link") == child:
                    k.find("parent").set("link", parent)
                    _set_origin(k, T @ _origin(k.find("origin")))
            # sites recorded on the fused link move to its parent
            prep.sites = [(n, parent, T @ Ts) if b == child else (n, b, Ts) for n, b, Ts in prep.sites]
            root.remove(j)
            root.remove(link)
            changed = True
            break
    for j in root.findall("joint"):
        for m in j.findall("mimic"):
            j.remove(m)
    for link in root.findall("link"):
        for v in link.findall("visual"):
            link.remove(v)
        for mesh in link.iter("mesh"):
            src = _resolve_mesh(mesh.get("filename"), config)
            name = src.stem   # the source file's name, made unique
            while name + ".stl" in prep.meshes and prep.meshes[name + ".stl"] != src:
                name += "_"
            prep.meshes[name + ".stl"] = src
            mesh.set("filename", name + ".stl")
    ET.SubElement(root, "mujoco").append(ET.Element(
        "compiler", fusestatic="false", discardvisual="true", strippath="false", balanceinertia="true"))
    prep.xml = ET.tostring(root, encoding="unicode")
    prep.body_of_link = {el.get("name"): el.get("name") for el in root.findall("link")}
    for name, body, _ in prep.sites:
        prep.body_of_link[name] = body
    return prep


def _stl_bytes(path: Path) -> bytes:
    """The mesh file as MuJoCo can read it: STL as it is; anything else (COLLADA, ...) loaded
    with coal and written as the binary STL of its convex hull, the shape MuJoCo collides
    with anyway (the model's visuals then show hulls for those links)."""
    if path.suffix.lower() == ".stl":
        return path.read_bytes()
    bvh = coal.MeshLoader().load(str(path), np.ones(3))
    V = np.array(bvh.vertices(), dtype=float).reshape(-1, 3)
    hull = ConvexHull(V)
    F = hull.simplices.copy()
    centre = V[hull.vertices].mean(axis=0)
    for k, (a, b, c) in enumerate(F):  # outward winding
        if np.cross(V[b] - V[a], V[c] - V[a]) @ (V[a] - centre) < 0:
            F[k] = (a, c, b)
    out = [b"\0" * 80, struct.pack("<I", len(F))]
    for a, b, c in F:
        n = np.cross(V[b] - V[a], V[c] - V[a])
        n = n / (np.linalg.norm(n) or 1.0)
        out.append(struct.pack("<12fH", *n, *V[a], *V[b], *V[c], 0))
    return b"".join(out)


def _sim_list(sim: dict, key: str, n: int, default) -> np.ndarray:
    v = sim.get(key, default)
    a = np.broadcast_to(np.asarray(v, dtype=float), (n,)).copy() if np.ndim(v) == 0 else np.asarray(v, dtype=float)
    if a.shape != (n,):
        raise RobotConfigError(f"sim: '{key}' must be one value or {n}; got {v!r}")
    return a


def build_mjcf(config: RobotConfig) -> tuple[str, dict[str, bytes]]:
    """The MJCF text of a robot and its mesh assets.

    Args:
        config: the robot configuration (URDF, SRDF pairs, limits, gripper, `sim:` section).

    Returns:
        (MJCF text with meshdir "assets", {asset file name: STL bytes}).

    Raises:
        RobotConfigError: missing meshes or links, malformed `sim:` entries.
    """
    prep = _prepare(config)
    assets = {name: _stl_bytes(src) for name, src in prep.meshes.items()}
    spec = mujoco.MjSpec.from_string(prep.xml, assets=assets)
    spec.modelname = config.name
    spec.compiler.meshdir = "assets"
    sim = dict(config.raw.get("sim", {}) or {})
    n = config.dof
    gravcomp = bool(sim.get("gravity_compensation", False))
    for b in spec.bodies:
        if b.name != "world":
            b.gravcomp = 1.0 if gravcomp else 0.0
    for g in spec.geoms:
        g.contype, g.conaffinity, g.group = 1, 1, 2
        g.rgba = [0.8, 0.8, 0.82, 1.0]
        g.friction = [1.0, 0.005, 0.0001]
    # sites: fused frames, and ee / tcp links that are bodies
    for name, body, T in prep.sites:
        s = spec.body(body).add_site(name=name, pos=T[:3, 3], quat=_quat(T[:3, :3]), size=[0.005] * 3, group=4)
        s.rgba = [1, 0, 0, 1]
    for link in (config.ee_link, config.tcp_link):
        if link and link not in {s[0] for s in prep.sites}:
            if spec.body(link) is None:
                raise RobotConfigError(f"{config.name}: link '{link}' is not in the MJCF")
            spec.body(link).add_site(name=link, size=[0.005] * 3, group=4, rgba=[1, 0, 0, 1])
    armature = _sim_list(sim, "armature", n, DEFAULT_ARMATURE)
    for i, jn in enumerate(config.arm_joints):
        j = spec.joint(jn)
        j.range = [float(config.lower_limits[i]), float(config.upper_limits[i])]
        j.limited = mujoco.mjtLimited.mjLIMITED_TRUE
        j.armature = float(armature[i])
        j.damping = [0.0, 0.0, 0.0]
    gripper = config.gripper
    if gripper is not None:
        fc = sim.get("finger_contact", {}) or {}
        finger_bodies = {spec.joint(jn).parent.name for jn in gripper.joints}
        for g in spec.geoms:
            if g.parent.name in finger_bodies:
                if "friction" in fc:
                    g.friction = [float(v) for v in fc["friction"]]
                if "condim" in fc:
                    g.condim = int(fc["condim"])
                if "solref" in fc:
                    g.solref = [float(v) for v in fc["solref"]]
                if "solimp" in fc:
                    g.solimp = [float(v) for v in fc["solimp"]]
                g.priority = int(fc.get("priority", 0))
        for jn in gripper.joints:
            spec.joint(jn).armature = float(sim.get("finger_armature", DEFAULT_FINGER_ARMATURE))
            spec.joint(jn).damping = [0.0, 0.0, 0.0]
    # drive gains: the yaml's, else critically damped on the inertia at home
    model = spec.compile()
    data = mujoco.MjData(model)
    qpos = model.qpos0.copy()
    for i, jn in enumerate(config.arm_joints):
        qpos[model.joint(jn).qposadr[0]] = config.default_joint_positions[i]
    data.qpos[:] = qpos
    mujoco.mj_forward(model, data)
    inertia = np.empty(n)   # diagonal of the joint-space inertia matrix (M e_i)_i
    for i, jn in enumerate(config.arm_joints):
        e, Me = np.zeros(model.nv), np.zeros(model.nv)
        e[model.joint(jn).dofadr[0]] = 1.0
        mujoco.mj_mulM(model, data, Me, e)
        inertia[i] = Me[model.joint(jn).dofadr[0]]
    w = 2.0 * math.pi * DEFAULT_DRIVE_HZ
    kp = _sim_list(sim, "kp", n, 0.0) if "kp" in sim else w * w * inertia
    kv = _sim_list(sim, "kv", n, 0.0) if "kv" in sim else 2.0 * w * inertia
    tree = ET.parse(config.urdf_path).getroot()
    effort = {j.get("name"): float(j.find("limit").get("effort")) for j in tree.findall("joint")
              if j.find("limit") is not None and j.find("limit").get("effort") is not None}
    for i, jn in enumerate(config.arm_joints):
        a = spec.add_actuator(name=jn, target=jn, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        a.set_to_position(kp=float(kp[i]), kv=float(kv[i]))
        a.inheritrange = 1.0
        if effort.get(jn):
            a.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            a.forcerange = [-effort[jn], effort[jn]]
    if gripper is not None:
        fkp = float(sim.get("finger_kp", DEFAULT_FINGER_KP))
        fkv = float(sim.get("finger_kv", DEFAULT_FINGER_KV))
        force = float(sim.get("finger_force", DEFAULT_FINGER_FORCE))
        for jn in gripper.joints:
            a = spec.add_actuator(name=jn, target=jn, trntype=mujoco.mjtTrn.mjTRN_JOINT)
            a.set_to_position(kp=fkp, kv=fkv)
            a.inheritrange = 1.0
            a.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            a.forcerange = [-force, force]
    # SRDF / yaml disabled pairs between bodies of the model
    excludes = sorted({tuple(sorted((prep.body_of_link[a], prep.body_of_link[b])))
                       for a, b in config.disabled_collision_pairs
                       if a in prep.body_of_link and b in prep.body_of_link})
    for a, b in excludes:
        if a != b:
            spec.add_exclude(bodyname1=a, bodyname2=b)
    home = qpos.copy()
    if gripper is not None:
        for jn, v in zip(gripper.joints, gripper.open_positions):
            home[model.joint(jn).qposadr[0]] = v
    ctrl = [home[model.joint(jn).qposadr[0]] for jn in list(config.arm_joints) + list(gripper.joints if gripper else [])]
    spec.add_key(name="home", qpos=home.tolist(), ctrl=ctrl)
    final = spec.compile()
    header = (f"<!-- {config.name} for MuJoCo, generated by robots/tools/make_mjcf.py (manip.sim.scenes.mjcf_builder)\n"
              f"  from {config.urdf_path.name}{' and ' + config.srdf_path.name if config.srdf_path else ''}"
              " and robot.yaml. Do not edit by hand: change the yaml or the builder and rerun it.\n"
              "  Bodies = URDF links (massless fixed links fused into sites), joints = URDF joints, one\n"
              "  position actuator per joint named after it; contact excludes = disabled collision pairs. -->\n")
    return header + _full_precision(spec.to_xml(), final), assets


def write_mjcf(config: RobotConfig, out: Path | None = None) -> Path:
    """Build the MJCF of `config` and write it (default `config.folder / config.mjcf`) with
    its meshes in `assets/` beside it; return the MJCF path."""
    out = Path(out) if out is not None else config.mjcf_path
    if out is None:
        raise RobotConfigError(f"{config.name}: no 'mjcf' file named in robot.yaml and no output path given")
    text, assets = build_mjcf(config)
    (out.parent / "assets").mkdir(parents=True, exist_ok=True)
    for name, data in assets.items():
        (out.parent / "assets" / name).write_bytes(data)
    out.write_text(text)
    return out
