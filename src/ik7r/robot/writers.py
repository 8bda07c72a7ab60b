"""Writing robots: TOML robot files and URDF with the ``<mimic>`` joint.

The readers (:mod:`.files`, :mod:`.urdf`) build :class:`~ik7r.robot.model.Robot` values; the
writers only read a robot's fields, so the model can offer ``Robot.to_toml`` and
``Robot.to_urdf`` without an import cycle.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry.rotations import dh_transform, matrix_to_rpy
from ..units import METRES_PER_UNIT

__all__ = ["robot_to_toml", "robot_to_urdf"]


def _number(v) -> str:
    v = float(v)
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


def _toml_list(values) -> str:
    return "[" + ", ".join(_number(v) for v in values) + "]"


def robot_to_toml(robot) -> str:
    """The TOML text of ``robot`` (round-trips through :func:`robot_from_toml` exactly)."""
    def esc(s: str) -> str:
        return s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")

    lines = [f'name = "{esc(robot.name)}"', f'unit = "{esc(robot.unit)}"']
    if robot.description:
        lines.append(f'description = "{esc(robot.description)}"')
    lines.append("joint_names = [" + ", ".join(f'"{esc(n)}"' for n in robot.joint_names) + "]")
    lines += ["", "[dh]", f"a = {_toml_list(robot.dh[:, 0])}",
              f"alpha = {_toml_list(np.degrees(robot.dh[:, 1]))}",
              f"d = {_toml_list(robot.dh[:, 2])}",
              f"theta_offset = {_toml_list(np.degrees(robot.dh[:, 3]))}",
              f"sign = {_toml_list(robot.joint_sign)}"]
    lines += ["", "[coupling]", f"multiplier = {float(robot.coupling[0])!r}",
              f"offset = {math.degrees(robot.coupling[1])!r}"]
    lines += ["", "[limits]", f"lower = {_toml_list(np.degrees(robot.lower))}",
              f"upper = {_toml_list(np.degrees(robot.upper))}"]
    if robot.velocity is not None:
        lines.append(f"velocity = {_toml_list(np.degrees(robot.velocity))}")
    if robot.acceleration is not None:
        lines.append(f"acceleration = {_toml_list(np.degrees(robot.acceleration))}")
    for key in ("base", "tool"):
        T = getattr(robot, key)
        if not np.array_equal(T, np.eye(4)):
            lines += ["", f"[{key}]", f"xyz = {_toml_list(T[:3, 3])}",
                      f"rpy = {_toml_list(np.degrees(matrix_to_rpy(T[:3, :3])))}"]
    return "\n".join(lines) + "\n"


def _urdf_numbers(values) -> str:
    return " ".join(repr(float(v)) if v != 0 else "0" for v in values)


def _origin(T: np.ndarray, scale: float) -> str:
    rpy = matrix_to_rpy(T[:3, :3])
    return f'<origin xyz="{_urdf_numbers(T[:3, 3] * scale)}" rpy="{_urdf_numbers(rpy)}"/>'


def robot_to_urdf(robot) -> str:
    """The URDF text of ``robot`` (lengths converted to metres).

    Links ``base_link`` (the robot's world frame), ``link_0`` ... ``link_7`` (the DH frames)
    and ``tool0`` (the TCP); fixed joints ``base_link-link_0`` (``robot.base``) and
    ``link_7-tool0`` (``robot.tool``); the sixth revolute joint carries ``<mimic>`` with the
    robot's coupling. Joint limits and velocities are written (velocity 0 when the robot has
    none; effort is not modelled and written as 0); acceleration limits are not part of URDF.
    Loading the result with :func:`robot_from_urdf` gives the same forward kinematics.
    """
    if robot.unit not in METRES_PER_UNIT:
        raise ValueError(f"cannot write a URDF for a robot in unit {robot.unit!r}; "
                         f"known units: {', '.join(METRES_PER_UNIT)}")
    scale = METRES_PER_UNIT[robot.unit]

    def esc(s: str) -> str:
        return (s.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")
                .replace(">", "&gt;").replace("--", "- -"))

    names = list(robot.joint_names)
    fixed_base, fixed_tool = "base_link-link_0", "link_7-tool0"
    while fixed_base in names or fixed_tool in names:
        fixed_base, fixed_tool = fixed_base + "_fixed", fixed_tool + "_fixed"
    m, c = robot.coupling
    lower = list(robot.lower[:5]) + [None] + [robot.lower[5]]
    upper = list(robot.upper[:5]) + [None] + [robot.upper[5]]
    ends = (m * robot.lower[4] + c, m * robot.upper[4] + c)
    lower[5], upper[5] = min(ends), max(ends)
    vel = [0.0] * 7 if robot.velocity is None else list(robot.velocity[:5]) + [0.0, robot.velocity[5]]
    if robot.velocity is not None:
        vel[5] = abs(m) * robot.velocity[4]
    lines = [
        '<?xml version="1.0"?>',
        f"<!-- Written by ik7r from robot {esc(robot.name)} (unit {esc(robot.unit)}; "
        "lengths here in metres).",
        "     Link i is the modified DH frame i; joint 6 mimics joint 5. -->",
        f'<robot name="{esc(robot.name)}">',
    ]
    lines += [f'  <link name="{ln}"/>' for ln in ["base_link"] + [f"link_{i}" for i in range(8)] + ["tool0"]]
    lines += [f'  <joint name="{esc(fixed_base)}" type="fixed">', '    <parent link="base_link"/>',
              '    <child link="link_0"/>', f"    {_origin(robot.base, scale)}", "  </joint>"]
    for i in range(7):
        a, alpha, d, off = robot.dh[i]
        # RotX(alpha) TransX(a) RotZ(sign q + off) TransZ(d) = [origin at q = 0] RotZ(sign q)
        T = dh_transform(a, alpha, off, d)
        lines += [f'  <joint name="{esc(names[i])}" type="revolute">', f'    <parent link="link_{i}"/>',
                  f'    <child link="link_{i + 1}"/>', f"    {_origin(T, scale)}",
                  f'    <axis xyz="0 0 {int(robot.joint_sign[i])}"/>',
                  f'    <limit lower="{float(lower[i])!r}" upper="{float(upper[i])!r}" '
                  f'velocity="{float(vel[i])!r}" effort="0"/>']
        if i == 5:
            lines.append(f'    <mimic joint="{esc(names[4])}" multiplier="{float(m)!r}" '
                         f'offset="{float(c)!r}"/>')
        lines.append("  </joint>")
    lines += [f'  <joint name="{esc(fixed_tool)}" type="fixed">', '    <parent link="link_7"/>',
              '    <child link="tool0"/>', f"    {_origin(robot.tool, scale)}", "  </joint>", "</robot>"]
    return "\n".join(lines) + "\n"
