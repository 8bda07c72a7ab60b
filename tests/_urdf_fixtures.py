"""Test helpers: family robots built from DH tables, and URDFs written for them with the joint
frames placed in different ways. Independent of ik7r.robot.urdf (the code under test)."""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np

from ik7r.geometry.rotations import invert, matrix_to_rpy, rpy_to_matrix, transform
from ik7r.robot.model import Robot

SHARED_IRB5400 = Path(__file__).resolve().parents[2] / "shared" / "robots" / "abb_irb5400.urdf"

#: How the URDF places each joint frame on its axis line (the axis lines are the same).
STYLES = ("dh", "world", "x", "negx", "random")


def rodrigues(u, angle) -> np.ndarray:
    """Rotation (3, 3) about the unit vector ``u`` by ``angle`` (rad)."""
    K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * K @ K


def align(a, u) -> np.ndarray:
    """A rotation taking the unit vector ``a`` to the unit vector ``u``."""
    v = np.cross(a, u)
    s, c = float(np.linalg.norm(v)), float(a @ u)
    if s < 1e-12:
        if c > 0:
            return np.eye(3)
        p = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
        return rodrigues(p / np.linalg.norm(p), math.pi)
    return rodrigues(v / s, math.atan2(s, c))


def random_transform(rng, reach=0.5) -> np.ndarray:
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    return transform(R, rng.uniform(-reach, reach, 3))


def family_robot(name, *, a1, a2, a3, d1, d2, d3, d4, beta_deg, d5, d6, d7, eps1=1, eps3=1, sign=None,
                 offsets=None, coupling=(-1.0, 0.0), base=None, tool=None, limit=2.5) -> Robot:
    """A family member from its DH numbers (metres); offset 6 is set so that theta6 = -theta5."""
    b = math.radians(beta_deg)
    sign = np.ones(7) if sign is None else np.array(sign, dtype=float)
    off = np.zeros(7) if offsets is None else np.array(offsets, dtype=float)
    m, c = coupling
    off[5] = -off[4] - sign[5] * c
    dh = np.array([[0, 0, d1, off[0]], [a1, eps1 * math.pi / 2, d2, off[1]], [a2, 0, d3, off[2]],
                   [a3, eps3 * math.pi / 2, d4, off[3]], [0, -b, d5, off[4]], [0, 2 * b, d6, off[5]],
                   [0, -b, d7, off[6]]], dtype=float)
    return Robot(name=name, dh=dh, unit="m", lower=np.full(6, -limit), upper=np.full(6, limit),
                 velocity=np.array([2.0, 2.0, 2.0, 3.0, 3.0, 4.0]), coupling=coupling, joint_sign=sign,
                 base=np.eye(4) if base is None else base, tool=np.eye(4) if tool is None else tool,
                 joint_names=tuple(f"j{k}" for k in range(1, 8)))


def deviating_robot(rng, *, wrist_offset, twist_error, negative_a2=None, negative_beta=None,
                    frames=True) -> Robot:
    """A family member (mm) that deviates from the mirror: wrist offsets a4 .. a6 and d5 - d6 up
    to ``wrist_offset``, every twist but alpha0 up to ``twist_error`` (rad) off; beta, the upper
    arm, alpha1 and alpha3 of random signs (or beta < 0 and a2 < 0 as asked), random joint signs
    and theta offsets with the coupling keeping theta6 = -theta5, and (``frames``) a random base
    and tool within 500 mm."""
    beta = rng.choice([-1.0, 1.0]) * math.radians(rng.uniform(15.0, 44.0))
    e1, e3, sa2 = rng.choice([-1.0, 1.0], 3)
    if negative_beta is not None:
        beta = -abs(beta) if negative_beta else abs(beta)
    if negative_a2 is not None:
        sa2 = -1.0 if negative_a2 else 1.0
    dw = rng.uniform(60.0, 150.0)
    dh = np.array([[0.0, 0.0, rng.uniform(0, 800), 0.0],
                   [rng.uniform(0, 300), e1 * math.pi / 2, rng.uniform(-150, 150), 0.0],
                   [sa2 * rng.uniform(700, 1400), 0.0, rng.uniform(-150, 150), 0.0],
                   [rng.uniform(-250, 250), e3 * math.pi / 2, rng.uniform(700, 1400), 0.0],
                   [0.0, -beta, dw, 0.0], [0.0, 2 * beta, dw, 0.0], [0.0, -beta, rng.uniform(50, 200), 0.0]])
    dh[4:7, 0] = rng.uniform(-wrist_offset, wrist_offset, 3)
    dh[5, 2] += rng.uniform(-wrist_offset, wrist_offset)
    dh[1:, 1] += rng.uniform(-twist_error, twist_error, 6)
    dh[:, 3] = rng.uniform(-np.pi, np.pi, 7)
    sign = rng.choice([-1.0, 1.0], 7)
    coupling = (-sign[4] * sign[5], -(dh[4, 3] + dh[5, 3]) * sign[5])
    base, tool = np.eye(4), np.eye(4)
    if frames:
        base, tool = random_transform(rng), random_transform(rng)
        base[:3, 3] *= 1000.0
        tool[:3, 3] *= 1000.0
    return Robot(name="deviating", dh=dh, joint_sign=sign, coupling=coupling, base=base, tool=tool)


def reference_robots() -> dict[str, Robot]:
    """Family members with other wrist angles, offsets, signs, couplings, bases and tools."""
    return {
        "beta30_offsets": family_robot(
            "beta30_offsets", a1=0.25, a2=1.1, a3=-0.15, d1=0.5, d2=0.06, d3=0.04, d4=1.2, beta_deg=30,
            d5=0.09, d6=0.09, d7=0.12, sign=[1, -1, 1, 1, -1, -1, -1],
            offsets=[0.3, -0.5, 0.2, 1.0, 0.4, 0, -0.7],
            base=transform(rpy_to_matrix([0.1, -0.2, 0.5]), [0.3, -0.1, 0.2]),
            tool=transform(rpy_to_matrix([0.5, 0.2, -1.0]), [0.01, 0.02, 0.15])),
        "beta45_unequal": family_robot(
            "beta45_unequal", a1=0.2, a2=0.9, a3=0.1, d1=0.4, d2=0.0, d3=-0.05, d4=1.0, beta_deg=45,
            d5=0.08, d6=0.0805, d7=0.1, eps1=-1, sign=[-1, 1, 1, -1, 1, -1, 1],
            offsets=[0, 0.5, -0.2, 0, 0.4, 0, 0.3], coupling=(1.0, 0.2), tool=transform(None, [0, 0, 0.2])),
        "beta40_irb_like": family_robot(
            "beta40_irb_like", a1=0.3, a2=1.2, a3=0.186, d1=0.66, d2=0, d3=0, d4=1.41, beta_deg=40,
            d5=0.07, d6=0.0703, d7=0.08, eps1=-1, eps3=-1, offsets=[0, -math.pi / 2, 0, math.pi / 2, 0, 0, 0],
            base=transform(rpy_to_matrix([0, 0, 0.7]), [1.0, 2.0, 0.0])),
        "paper_zero_offsets": family_robot(
            "paper_zero_offsets", a1=0, a2=1.0, a3=0, d1=0, d2=0, d3=0, d4=0.9, beta_deg=35, d5=0.08,
            d6=0.08, d7=0.1, limit=1.2),
    }


def _fmt(v) -> str:
    return " ".join(repr(float(x)) for x in v)


def _origin(T) -> str:
    return f'<origin xyz="{_fmt(T[:3, 3])}" rpy="{_fmt(matrix_to_rpy(T[:3, :3]))}"/>'


def chain_urdf(ref: Robot, style: str, rng, *, extra_fixed=False, world_T_base=None) -> str:
    """A URDF of the robot ``ref`` (unit m): root ``world``, then ``base_link`` at
    ``world_T_base`` (identity by default), joints placed on the axis lines of ``ref`` in its
    zero posture as ``style`` says, fixed links between joints when ``extra_fixed``, the tip link
    ``flange`` at ``ref``'s tool, and a side branch ``camera`` on ``link_3``."""
    F = ref.frames(np.zeros(6))  # world frames at q = 0: base, 1..7, tool (q6 = coupling offset)
    m, c = ref.coupling
    B = np.eye(4) if world_T_base is None else world_T_base
    links = ["world", "base_link"]
    joints = [("world-base_link", "fixed", "world", "base_link", B, None)]
    parent, J_prev = "base_link", B
    names = ref.joint_names
    for i in range(7):
        u = ref.joint_sign[i] * F[i + 1][:3, 2]
        p = F[i + 1][:3, 3]
        shift = 0.0 if style == "dh" else rng.uniform(-0.2, 0.2)
        if style == "dh":
            R, ax = F[i + 1][:3, :3], np.array([0.0, 0.0, ref.joint_sign[i]])
        elif style == "world":  # ABB style: every joint frame parallel to the base
            R, ax = np.eye(3), u
        elif style in ("x", "negx"):  # ABB style: the joint axis is the frame's x (or -x)
            ax = np.array([1.0 if style == "x" else -1.0, 0.0, 0.0])
            R = rodrigues(u, rng.uniform(-3, 3)) @ align(ax, u)
        else:
            ax = rng.normal(size=3)
            ax /= np.linalg.norm(ax)
            R = rodrigues(u, rng.uniform(-3, 3)) @ align(ax, u)
        J = transform(R, p + shift * u)
        if extra_fixed and i in (1, 3, 4, 6):
            G = random_transform(rng)
            links.append(f"mid_{i}")
            joints.append((f"fixed_{i}", "fixed", parent, f"mid_{i}", invert(J_prev) @ G, None))
            parent, J_prev = f"mid_{i}", G
        T_parent_joint = invert(J_prev) @ J
        if i == 5:  # the zero posture has joint 6 at the mimic offset c; its origin is at value 0
            T_parent_joint = T_parent_joint @ transform(rodrigues(ax / np.linalg.norm(ax), -c), None)
        k = i if i < 5 else 5
        lim = (-6.0, 6.0) if i == 5 else (ref.lower[k], ref.upper[k])
        extra = {"axis": ax, "limit": lim, "velocity": 1.0 if i == 5 else ref.velocity[k],
                 "mimic": (names[4], m, c) if i == 5 else None}
        links.append(f"link_{i + 1}")
        joints.append((names[i], "revolute", parent, f"link_{i + 1}", T_parent_joint, extra))
        parent, J_prev = f"link_{i + 1}", J
    links += ["flange", "camera"]
    joints.append(("flange_joint", "fixed", parent, "flange", invert(J_prev) @ F[8], None))
    joints.append(("camera_joint", "fixed", "link_3", "camera", transform(None, [0.1, 0.2, 0.3]), None))
    out = ['<?xml version="1.0"?>', f'<robot name="{ref.name}">']
    out += [f'  <link name="{ln}"/>' for ln in links]
    for name, typ, par, chi, T, extra in joints:
        out += [f'  <joint name="{name}" type="{typ}">', f'    <parent link="{par}"/>',
                f'    <child link="{chi}"/>', f"    {_origin(T)}"]
        if extra is not None:
            lo, hi = extra["limit"]
            out.append(f'    <axis xyz="{_fmt(extra["axis"])}"/>')
            out.append(f'    <limit lower="{float(lo)!r}" upper="{float(hi)!r}" '
                       f'velocity="{float(extra["velocity"])!r}" effort="10"/>')
            if extra["mimic"]:
                j, mm, cc = extra["mimic"]
                out.append(f'    <mimic joint="{j}" multiplier="{float(mm)!r}" offset="{float(cc)!r}"/>')
        out.append("  </joint>")
    out.append("</robot>")
    return "\n".join(out) + "\n"


def yourdfpy_fk(urdf_text: str, names, q, frame_to: str, frame_from: str, *, scene_graph=False) -> np.ndarray:
    """``frame_from <- frame_to`` transforms (N, 4, 4) of a URDF read by yourdfpy, for joints ``q``
    (N, 6) of the independent joints ``names`` (mimic joints follow their joint).

    By default the chain is multiplied out here from yourdfpy's parsed joints (origin, axis,
    mimic). ``scene_graph=True`` asks yourdfpy's own forward kinematics instead; it is only good
    to about 1e-8, because its trimesh scene graph drops transforms within 1e-8 of the identity
    (trimesh/scene/transforms.py), such as the IRB 5400's tool0, 4.9e-12 rad from a right angle.
    """
    import yourdfpy

    model = yourdfpy.URDF.load(io.StringIO(urdf_text), load_meshes=False, build_collision_scene_graph=False)
    out = []
    by_child = {j.child: j for j in model.robot.joints}
    path, link = [], frame_to
    while link != frame_from:
        j = by_child[link]
        path.append(j)
        link = j.parent
    path.reverse()
    for qq in np.atleast_2d(q):
        cfg = dict(zip(names, qq))
        if scene_graph:
            model.update_cfg(cfg)
            out.append(model.get_transform(frame_to, frame_from))
            continue
        T = np.eye(4)
        for j in path:
            T = T @ (np.eye(4) if j.origin is None else j.origin)
            if j.type in ("revolute", "continuous"):
                if j.mimic is not None:
                    mult = 1.0 if j.mimic.multiplier is None else j.mimic.multiplier
                    value = mult * cfg[j.mimic.joint] + (j.mimic.offset or 0.0)
                else:
                    value = cfg[j.name]
                axis = np.asarray(j.axis, dtype=float)
                T = T @ transform(rodrigues(axis / np.linalg.norm(axis), value), None)
        out.append(T)
    return np.array(out)
