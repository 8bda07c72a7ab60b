"""URDF robots: read a serial chain into the family's modified DH parameters, and write one.

Reading (:func:`robot_from_urdf`) works on the axis lines, not on the URDF's joint frames, so
any placement of the joint frames (DH-style z axes, ABB-style x axes, fixed joints anywhere)
gives the same robot:

1. Take the serial chain from the ``base`` link (default: the root) to the ``tip`` link
   (default: the deepest leaf). Its revolute and continuous joints are the seven joints of the
   robot; exactly one of them, the sixth, must be a ``<mimic>`` of the fifth. Fixed joints are
   folded in, prismatic, planar and floating joints are out of the family.
2. Evaluate the chain in its zero posture (independent joints 0, the mimic joint at its
   offset) and find every joint axis as a line (point, direction) in the ``base`` link frame.
3. Build Craig's modified DH frames on these lines: ``z_i`` along axis i (``joint_sign`` -1
   where ``z_i`` points against the URDF axis), ``x_i`` along the common normal of axes i and
   i + 1, frame 0 on axis 1 nearest the base link origin, frame 7 on axis 7 nearest the tip
   link origin. Whatever is left at the ends becomes the robot's ``base`` and ``tool``.
4. Check the table against the family (:func:`ik7r.robot.family.family_of`) and check the result by
   comparing its forward kinematics with the URDF's own chain of transforms.

Lengths stay in metres (``unit = "m"``).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import overload

import numpy as np

from .._typing import ArrayLike, PathLike
from ..errors import FamilyError, RobotFileError
from ..geometry.rotations import dh_transform, invert, rpy_to_matrix, transform
from ..limits import MAX_ROBOT_FILE_BYTES
from ..textio import read_bytes_limited
from .family import ANGLE_TOL
from .model import Robot

__all__ = [
    "robot_from_urdf",
    "robot_from_urdf_string",
    "UrdfChain",
    "read_chain",
    "PARALLEL_TOL",
    "FK_CHECK_TOL",
]

#: Axes closer to parallel than this (rad) are taken as exactly parallel. Treating them so
#: moves the chain by at most this times its reach (3e-13 m on a 3 m robot).
PARALLEL_TOL = 1e-13
#: A common normal farther than this many times the chain's size from the joints means two
#: axes are so nearly parallel that the normal's place is lost in the rounding of the lines:
#: they are written as parallel, and the chain is rejected when that misses it by more than
#: ``FK_CHECK_TOL`` (then it cannot be written in modified DH parameters without losing precision).
FAR_NORMAL = 10.0
#: After conversion the DH model's forward kinematics must match the URDF chain within this
#: (rotation entries; positions relative to the chain's size plus 1 m), checked at load time.
FK_CHECK_TOL = 1e-12

_MOVING = ("revolute", "continuous")
_KNOWN_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")


# ---------------------------------------------------------------------------- parsing
@dataclass(frozen=True)
class UrdfJoint:
    """One ``<joint>`` of a URDF (lengths in metres, angles in rad)."""

    name: str
    type: str
    parent: str
    child: str
    origin: np.ndarray  # (4, 4) parent link <- joint frame at zero joint value
    axis: np.ndarray  # (3,) unit vector in the joint frame
    lower: float | None = None
    upper: float | None = None
    velocity: float | None = None
    mimic: tuple[str, float, float] | None = None  # (joint, multiplier, offset)


@dataclass(frozen=True)
class UrdfChain:
    """The serial chain of a URDF from ``base`` to ``tip`` (see :func:`read_chain`)."""

    name: str
    base: str
    tip: str
    joints: tuple[UrdfJoint, ...]  # every joint from base to tip, fixed ones included
    source: str = "<string>"
    moving: tuple[int, ...] = field(default=())  # indices into joints of the moving joints

    def transforms(self, q_moving: ArrayLike) -> np.ndarray:
        """Base link <- tip link transform for values of the moving joints.

        Parameters
        ----------
        q_moving : array_like, shape (..., n_moving)
            Values of the moving joints in chain order (rad); mimic joints are given too.

        Returns
        -------
        T_base_tip : ndarray, shape (..., 4, 4)
        """
        q = np.asarray(q_moving, dtype=float)
        T = np.broadcast_to(np.eye(4), q.shape[:-1] + (4, 4)).copy()
        k = 0
        for j in self.joints:
            T = T @ j.origin
            if j.type in _MOVING:
                T = T @ _axis_rotation(j.axis, q[..., k])
                k += 1
        return T


def _axis_rotation(axis: np.ndarray, angle) -> np.ndarray:
    """Rotation about the unit ``axis`` by ``angle`` (...,) as (..., 4, 4) (Rodrigues)."""
    angle = np.asarray(angle, dtype=float)
    x, y, z = axis
    K = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    s, c = np.sin(angle)[..., None, None], np.cos(angle)[..., None, None]
    R = np.eye(3) + s * K + (1.0 - c) * (K @ K)
    T = np.zeros(angle.shape + (4, 4))
    T[..., :3, :3] = R
    T[..., 3, 3] = 1.0
    return T


def _floats(text: str | None, n: int, what: str, default) -> np.ndarray:
    if text is None:
        return np.array(default, dtype=float)
    parts = text.split()
    try:
        vals = np.array([float(p) for p in parts])
    except ValueError:
        vals = np.array([])
    if len(parts) != n or vals.size != n or not np.all(np.isfinite(vals)):
        raise RobotFileError(f"{what} must be {n} finite numbers; got {text!r}")
    return vals


@overload
def _float_attr(el: ET.Element, key: str, what: str, default: float) -> float: ...
@overload
def _float_attr(el: ET.Element, key: str, what: str, default: None) -> float | None: ...
def _float_attr(el: ET.Element, key: str, what: str, default: float | None) -> float | None:
    val = el.get(key)
    if val is None:
        return default
    try:
        x = float(val)
    except ValueError:
        x = math.nan
    if not math.isfinite(x):
        raise RobotFileError(f"{what}: '{key}' must be a finite number; got {val!r}")
    return x


def _few(names: list[str], k: int = 8) -> str:
    """At most ``k`` names for a message."""
    shown = ", ".join(repr(n) for n in names[:k])
    return f"[{shown}{f', ... ({len(names)} in all)' if len(names) > k else ''}]"


def _parse_joint(el: ET.Element, source: str) -> UrdfJoint:
    name = el.get("name")
    if not name:
        raise RobotFileError(f"{source}: a <joint> has no name")
    where = f"{source}: joint {name!r}"
    jtype = el.get("type")
    if jtype not in _KNOWN_TYPES:
        raise RobotFileError(f"{where}: unknown type {jtype!r}; expected one of {', '.join(_KNOWN_TYPES)}")
    links: list[str] = []
    for tag in ("parent", "child"):
        sub = el.find(tag)
        link = None if sub is None else sub.get("link")
        if not link:
            raise RobotFileError(f"{where}: missing <{tag} link=...>")
        links.append(link)
    org = el.find("origin")
    xyz = _floats(None if org is None else org.get("xyz"), 3, f"{where}: <origin xyz>", (0, 0, 0))
    rpy = _floats(None if org is None else org.get("rpy"), 3, f"{where}: <origin rpy>", (0, 0, 0))
    origin = transform(rpy_to_matrix(rpy), xyz)
    ax = el.find("axis")
    axis = _floats(None if ax is None else ax.get("xyz"), 3, f"{where}: <axis xyz>", (1, 0, 0))
    big = float(np.abs(axis).max())
    if jtype != "fixed" and not big >= 1e-9:
        raise RobotFileError(f"{where}: the axis must not be zero; got {axis.tolist()}")
    if big > 0:  # scaled first: 1e200 components must not overflow the norm
        axis = axis / big
        axis = axis / np.linalg.norm(axis)
    else:
        axis = np.array([1.0, 0.0, 0.0])
    lower = upper = velocity = None
    lim = el.find("limit")
    if jtype == "revolute" and lim is None:
        raise RobotFileError(f"{where}: a revolute joint needs <limit lower=... upper=... velocity=...>")
    if lim is not None:
        velocity = _float_attr(lim, "velocity", f"{where} <limit>", None)
        if jtype == "revolute":
            lower = _float_attr(lim, "lower", f"{where} <limit>", 0.0)
            upper = _float_attr(lim, "upper", f"{where} <limit>", 0.0)
            if lower > upper:
                raise RobotFileError(f"{where}: lower limit {lower:g} exceeds upper limit {upper:g}")
    mimic = None
    mel = el.find("mimic")
    if mel is not None and jtype != "fixed":
        target = mel.get("joint")
        if not target:
            raise RobotFileError(f"{where}: <mimic> needs joint=...")
        mimic = (target,
                 _float_attr(mel, "multiplier", f"{where} <mimic>", 1.0),
                 _float_attr(mel, "offset", f"{where} <mimic>", 0.0))
    return UrdfJoint(name=name, type=jtype, parent=links[0], child=links[1], origin=origin, axis=axis,
                     lower=lower, upper=upper, velocity=velocity, mimic=mimic)


def _depths(links: list[str], parent_joint: dict[str, UrdfJoint]) -> dict[str, int]:
    """Number of joints above each link, in time linear in the number of links (a loop in the
    parent relation is an error naming a link on it)."""
    depth: dict[str, int] = {}
    for start in links:
        if start in depth:
            continue
        trail, on_trail, link = [], set(), start
        while link not in depth and link in parent_joint:
            if link in on_trail:
                raise RobotFileError(f"the joints form a loop through link {link!r}")
            on_trail.add(link)
            trail.append(link)
            link = parent_joint[link].parent
        d = depth.get(link, 0)
        if link not in depth:
            depth[link] = 0
        for ln in reversed(trail):
            d += 1
            depth[ln] = d
    return depth


def _path_to_root(link: str, parent_joint: dict[str, UrdfJoint]) -> list[UrdfJoint]:
    """The joints from the root down to ``link`` (the parent relation has no loop)."""
    path = []
    while link in parent_joint:
        j = parent_joint[link]
        path.append(j)
        link = j.parent
    return path[::-1]


def _below(links: list[str], parent_joint: dict[str, UrdfJoint], base: str) -> dict[str, bool]:
    """Whether each link is ``base`` or below it (linear time, memoised)."""
    below: dict[str, bool] = {base: True}
    for start in links:
        trail, link = [], start
        while link not in below:
            trail.append(link)
            if link not in parent_joint:
                below[link] = False
                break
            link = parent_joint[link].parent
        value = below[link]
        for ln in trail:
            below[ln] = value
    return below


def read_chain(text: str | bytes, *, base: str | None = None, tip: str | None = None,
               source: str = "<string>") -> UrdfChain:
    """Parse URDF text and take its serial chain from ``base`` to ``tip``.

    Parameters
    ----------
    text : str or bytes
        The URDF (XML).
    base, tip : str, optional
        Link names. Default: the root link, and the deepest leaf (most joints from the root;
        the first in the file on a tie).
    source : str
        Name of the file, for messages.

    Raises
    ------
    RobotFileError
        Malformed XML, or links and joints that do not form a tree, or unknown links.
    """
    if isinstance(text, str):
        text = text.removeprefix("\ufeff")
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise RobotFileError(f"{source}: not valid XML: {exc}") from exc
    except (ValueError, LookupError) as exc:  # an encoding Python does not know, a NUL in text
        raise RobotFileError(f"{source}: not valid XML: {exc}") from exc
    if root.tag != "robot":
        raise RobotFileError(f"{source}: the root element must be <robot>; got <{root.tag}>")
    named = [el.get("name") for el in root.findall("link")]
    links = [n for n in named if n]
    if len(links) != len(named):
        raise RobotFileError(f"{source}: a <link> has no name")
    link_set = set(links)
    if len(link_set) != len(links):
        dup = sorted(n for n, k in Counter(links).items() if k > 1)
        raise RobotFileError(f"{source}: duplicate link names {_few(dup)}")
    joints = [_parse_joint(el, source) for el in root.findall("joint")]
    names = [j.name for j in joints]
    if len(set(names)) != len(names):
        dup = sorted(n for n, k in Counter(names).items() if k > 1)
        raise RobotFileError(f"{source}: duplicate joint names {_few(dup)}")
    parent_joint: dict[str, UrdfJoint] = {}
    for j in joints:
        for ln in (j.parent, j.child):
            if ln not in link_set:
                raise RobotFileError(
                    f"{source}: joint {j.name!r} refers to link {ln!r}, which is not defined")
        if j.child in parent_joint:
            raise RobotFileError(f"{source}: link {j.child!r} is the child of two joints "
                                 f"({parent_joint[j.child].name!r} and {j.name!r}); a URDF must be a tree")
        parent_joint[j.child] = j
    if not links:
        raise RobotFileError(f"{source}: no <link> elements")
    roots = [n for n in links if n not in parent_joint]
    if len(roots) != 1:
        raise RobotFileError(f"{source}: a URDF must have exactly one root link; got {_few(roots)}")
    try:
        depth = _depths(links, parent_joint)
    except RobotFileError as exc:
        raise RobotFileError(f"{source}: {exc}") from exc
    for key, val in (("base", base), ("tip", tip)):
        if val is not None and val not in link_set:
            raise RobotFileError(f"{source}: {key} link {val!r} is not defined; links are {_few(links)}")
    base_link = roots[0] if base is None else base
    if tip is None:
        parents = {j.parent for j in joints}
        below = _below(links, parent_joint, base_link)
        leaves = [n for n in links if n not in parents and n != base_link and below[n]]
        if not leaves:
            raise RobotFileError(f"{source}: no link below base link {base_link!r}")
        tip_link = max(leaves, key=lambda n: depth[n])  # first of the deepest
    else:
        tip_link = tip
    full = _path_to_root(tip_link, parent_joint)
    start = next((k for k, j in enumerate(full) if j.parent == base_link), None)
    if start is None:
        raise RobotFileError(f"{source}: tip link {tip_link!r} is not below base link {base_link!r}")
    chain = tuple(full[start:])
    moving = tuple(k for k, j in enumerate(chain) if j.type in _MOVING)
    return UrdfChain(name=root.get("name") or "robot", base=base_link, tip=tip_link, joints=chain,
                     source=source, moving=moving)


# ---------------------------------------------------------------------------- conversion
def _check_chain_family(chain: UrdfChain) -> tuple[list[UrdfJoint], float, float]:
    """Joint types, count and the mimic coupling; returns the 7 moving joints and (m, c)."""
    src = chain.source
    for j in chain.joints:
        if j.type in ("prismatic", "planar", "floating"):
            raise FamilyError(f"{src}: joint {j.name!r} is {j.type}; ik7r's family has revolute joints only")
    moving = [chain.joints[k] for k in chain.moving]
    names = [j.name for j in moving]
    mimics = [j for j in moving if j.mimic is not None]
    if len(moving) != 7:
        raise FamilyError(
            f"{src}: the chain {chain.base} -> {chain.tip} has {len(moving)} revolute joints {names}; "
            "ik7r's family has 7 (6 independent joints and joint 6 mimicking joint 5); "
            "choose the chain with base= and tip=")
    if not mimics:
        raise FamilyError(f"{src}: no <mimic> joint in the chain {names}; the sixth joint "
                          f"({names[5]!r}) must mimic the fifth ({names[4]!r})")
    for j in mimics:
        if j is not moving[5]:
            raise FamilyError(f"{src}: joint {j.name!r} is a mimic joint, but only the sixth revolute joint "
                              f"({names[5]!r}) may be coupled (to the fifth, {names[4]!r})")
    coupling = moving[5].mimic
    if coupling is None:  # (the checks above found it)
        raise FamilyError(f"{src}: joint {names[5]!r} must mimic {names[4]!r}")
    target, m, c = coupling
    if target != names[4]:
        raise FamilyError(f"{src}: joint {names[5]!r} mimics {target!r}; it must mimic the fifth revolute "
                          f"joint of the chain, {names[4]!r}")
    return moving, m, c


def _normal(u1, u2):
    """``u1 x u2``, computed as ``u1 x (u2 - u1)``: the same vector, but with its relative
    precision kept on nearly parallel axes (``u1 x u2`` there is a difference of nearly equal
    products, off by 1e-16 absolute, which at 1e-8 rad turns the normal by 1e-8 rad)."""
    return np.cross(u1, u2 - u1)


def _foot(p1, u1, p2, u2):
    """Parameters (t1, t2) of the feet of the common normal of two non-parallel lines.

    With ``n = u1 x u2`` and ``w = p2 - p1``: ``t1 = (w x u2) . n / |n|^2`` and
    ``t2 = (w x u1) . n / |n|^2``, each factor computed directly (see :func:`_normal`). On
    nearly parallel axes the feet are ill-conditioned in the lines (they move by
    ``a delta / alpha^2`` for a turn ``delta`` of an axis): they must be exact for the lines as
    given. (The form with ``1 - (u1 . u2)^2`` kept five digits of its denominator at 5e-6 rad,
    and the frames built on its feet missed the chain by 1e-12 of its size.)
    """
    n = _normal(u1, u2)
    nn = float(n @ n)
    w = p2 - p1
    return float(np.cross(w, u2) @ n) / nn, float(np.cross(w, u1) @ n) / nn


def _unit(v):
    return v / np.linalg.norm(v)


def _frame(x, z, o) -> np.ndarray:
    return transform(np.column_stack([x, np.cross(z, x), z]), o)


def _perp_unit(v, z, fallback):
    """Unit part of ``v`` perpendicular to unit ``z`` (``fallback`` when ``v`` is along ``z``)."""
    for w in (v, fallback):
        p = w - (w @ z) * z
        n = np.linalg.norm(p)
        if n > 1e-6:
            return p / n
    raise AssertionError("no direction perpendicular to z")  # pragma: no cover


def _tidy(v: float, tol: float) -> float:
    """``v`` rounded to 12 significant digits (or to 0) when that moves it by at most ``tol``
    (float noise: 1.1999999999999997 -> 1.2, 7e-17 -> 0), else ``v``."""
    if abs(v) <= tol:
        return 0.0
    c = float(f"{v:.12g}")
    return c if abs(c - v) <= tol else v


def _sign(x: float, default: float) -> float:
    return default if x == 0.0 else math.copysign(1.0, x)


def _preferred_sign(axis: np.ndarray) -> float:
    """+1, or -1 for an axis written pointing the negative way (its largest component negative)."""
    k = int(np.argmax(np.abs(axis)))
    return -1.0 if axis[k] < 0 else 1.0


def _forearm_sign(points: np.ndarray, u: np.ndarray, default: float) -> float:
    """+1 when the wrist (the normal of axes 4-5) lies ahead of the elbow (the normal of axes
    3-4) along the URDF direction of axis 4, else -1 (``default`` when undecided)."""
    t = []
    for k in (2, 4):
        if np.linalg.norm(_normal(u[3], u[k])) <= PARALLEL_TOL:
            return default
        t.append(_foot(points[3], u[3], points[k], u[k])[0])
    return _sign(t[1] - t[0], default)


def _joint_signs(points: np.ndarray, u: np.ndarray, pref: np.ndarray, m: float) -> np.ndarray:
    """Directions of the DH z axes: ``z_i = s_i u_i``.

    ``s1`` and ``s2`` follow the URDF axes (-1 for an axis written pointing the negative way),
    ``s4`` makes ``z4`` point from the elbow to the wrist (forearm ``d4 > 0`` as in the paper);
    the family fixes the others: axis 3 parallel (not antiparallel) to axis 2, acute angles
    between axes 4-5 and 6-7, and ``s6 = -s5 sign(m)`` so that the coupling is a mirror in DH
    angles. Between the two choices of ``s2`` the one matching more URDF directions is taken.
    """
    s4 = _forearm_sign(points, u, pref[3])
    best: np.ndarray | None = None
    best_cost: int | None = None
    for s2 in (pref[1], -pref[1]):
        s = np.array([pref[0], s2, 0.0, s4, 0.0, 0.0, 0.0])
        s[2] = _sign(float(u[2] @ u[1]) * s2, pref[2])
        s[4] = _sign(float(u[4] @ u[3]) * s4, pref[4])
        s[5] = -s[4] * _sign(m, 1.0)
        s[6] = _sign(float(u[6] @ u[5]) * s[5], pref[6])
        cost = int(np.sum(s[:3] != pref[:3]))
        if best is None or best_cost is None or cost < best_cost:
            best, best_cost = s, cost
    assert best is not None  # the loop runs twice
    return best


def _dh_from_lines(points: np.ndarray, dirs: np.ndarray, sign: np.ndarray, T_base_tip: np.ndarray,
                   size: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[tuple[int, float, float]]]:
    """Modified DH frames on the axis lines (zero posture, base link coordinates).

    Returns ``(dh (7, 4) with the zero-posture angles in the offset column, base, tool, far)``,
    ``far`` listing ``(i, sin, distance)`` for each pair of axes i, i + 1 (from 0) so nearly
    parallel that their common normal lies beyond ``FAR_NORMAL`` times the size (they are
    written as parallel; the caller's check of the forward kinematics decides).
    """
    far: list[tuple[int, float, float]] = []
    z = [sign[i] * dirs[i] for i in range(7)]
    # frame 0 on axis 1, nearest the base link origin; x0 along the base link's x
    o_prev = points[0] - (points[0] @ z[0]) * z[0]
    x_prev = _perp_unit(np.array([1.0, 0.0, 0.0]), z[0], np.array([0.0, 1.0, 0.0]))
    frames = [(x_prev, z[0], o_prev)]
    # wrist normals: x4 = -(z4 x z5), x5 = +(z5 x z6), x6 = -(z6 x z7) give twists (-b, 2b, -b), b > 0
    wrist_sigma = {3: -1.0, 4: 1.0, 5: -1.0}
    for i in range(7):
        if i == 6:  # frame 7 on axis 7, nearest the tip origin; x7 along the tip's x
            tip_o = T_base_tip[:3, 3]
            o = points[6] + ((tip_o - points[6]) @ z[6]) * z[6]
            x = _perp_unit(T_base_tip[:3, 0], z[6], T_base_tip[:3, 1])
            frames.append((x, z[6], o))
            break
        cross = _normal(z[i], z[i + 1])
        sin = float(np.linalg.norm(cross))
        parallel = sin <= PARALLEL_TOL
        if not parallel:
            t1, t2 = _foot(points[i], z[i], points[i + 1], z[i + 1])
            near = max(abs(t1), abs(t2))
            if near > FAR_NORMAL * size:
                far.append((i, sin, near))
                parallel = True
        if parallel:
            # parallel, or so nearly that the common normal's place is lost in the rounding of
            # the lines (see _foot): frame i where the previous normal meets axis i (d_i = 0),
            # x_i towards the nearest point of axis i + 1 (the check below bounds the error)
            o = points[i] + ((o_prev - points[i]) @ z[i]) * z[i]
            gap = points[i + 1] + ((o - points[i + 1]) @ z[i + 1]) * z[i + 1] - o
            gap = gap - (gap @ z[i]) * z[i]
            x = _unit(gap) if np.linalg.norm(gap) > 1e-12 * size else x_prev
        else:
            o = points[i] + t1 * z[i]
            n = cross / sin
            if i in wrist_sigma:
                x = wrist_sigma[i] * n
            else:
                a = float((points[i + 1] + t2 * z[i + 1] - o) @ n)
                if abs(a) > 1e-9 * size:
                    x = n if a > 0 else -n
                else:  # intersecting: the direction nearest the previous x
                    x = n if n @ x_prev >= 0 else -n
        frames.append((x, z[i], o))
        o_prev, x_prev = o, x
    dh = np.zeros((7, 4))
    for i in range(1, 8):
        xp, zp, op = frames[i - 1]
        x, zi, o = frames[i]
        step = o - op
        a = float(step @ xp)
        d = float(step @ zi)
        alpha = math.atan2(float(_normal(zp, zi) @ xp), float(zp @ zi))
        theta = math.atan2(float(np.cross(xp, x) @ zi), float(xp @ x))
        dh[i - 1] = (_tidy(a, 1e-15 * size), _tidy(alpha, 1e-15), _tidy(d, 1e-15 * size), _tidy(theta, 1e-15))
    dh[0, :2] = 0.0  # frame 0 is on axis 1 with z0 = z1 by construction (this only drops float noise)
    base = _frame(*frames[0])
    tool = invert(_frame(*frames[7])) @ T_base_tip
    for T in (base, tool):  # float noise: exact zeros, an exact bottom row
        T[:3, :3][np.abs(T[:3, :3]) < 1e-15] = 0.0
        T[:3, 3][np.abs(T[:3, 3]) < 1e-15 * size] = 0.0
        T[3] = (0.0, 0.0, 0.0, 1.0)
    return dh, base, tool, far


#: Largest coordinate (in the file's unit) of a joint origin in the zero posture that the loader
#: computes with: beyond it a squared length overflows float64. (The family refuses lengths far
#: smaller, by name, when they cannot be solved to the tolerance.)
MAX_COORDINATE = 1e150


def robot_from_chain(chain: UrdfChain) -> Robot:
    """The :class:`~ik7r.robot.model.Robot` of a URDF chain (see the module docstring)."""
    src = chain.source
    moving, m, c = _check_chain_family(chain)
    names = tuple(j.name for j in moving)
    q0 = np.zeros(7)
    q0[5] = c
    # zero posture: the axis lines in base link coordinates
    T = np.eye(4)
    point_list: list[np.ndarray] = []
    dir_list: list[np.ndarray] = []
    k = 0
    for j in chain.joints:
        T = T @ j.origin
        if j.type in _MOVING:
            point_list.append(T[:3, 3].copy())
            dir_list.append(_unit(T[:3, :3] @ j.axis))
            T = T @ _axis_rotation(j.axis, q0[k])
            k += 1
    T_base_tip = T
    points, dirs = np.array(point_list), np.array(dir_list)
    far = float(np.abs(np.vstack([points, T_base_tip[:3, 3]])).max())
    if not far <= MAX_COORDINATE:
        raise FamilyError(f"{src}: a joint origin lies {far:.6g} from the base (in the file's unit); the "
                          f"chain's lengths must be within MAX_COORDINATE = {MAX_COORDINATE:g}, beyond which "
                          "their squares overflow float arithmetic (and far fewer can be solved to the "
                          "tolerance: see the family's magnitude check)")
    size = float(np.sum(np.linalg.norm(np.diff(np.vstack([points, T_base_tip[:3, 3]]), axis=0), axis=1)))
    size = max(size, 1e-9)
    pref = np.array([_preferred_sign(j.axis) for j in moving])
    sign = _joint_signs(points, dirs, pref, m)
    z5, z6 = sign[4] * dirs[4], sign[5] * dirs[5]
    if float(z5 @ z6) < -math.sin(ANGLE_TOL):
        raise FamilyError(
            f"{src}: joint {names[5]!r} mimics {names[4]!r} with multiplier {m:g}, which with these axis "
            f"directions turns the wrist the same way as joint {names[4]!r} instead of mirroring it; a "
            f"mirror wrist needs multiplier {-m:g}")
    dh, base, tool, far_normals = _dh_from_lines(points, dirs, sign, T_base_tip, size)
    dh[5, 3] -= sign[5] * c  # theta6 = s6 q6 + offset6, and q6 = c in the zero posture
    lower = np.array([-math.pi if j.lower is None else j.lower for j in moving])
    upper = np.array([math.pi if j.upper is None else j.upper for j in moving])
    vel = np.array([0.0 if j.velocity is None else j.velocity for j in moving])
    keep = [0, 1, 2, 3, 4, 6]
    velocity = vel[keep] if np.all(vel[keep] > 0) else None
    try:
        robot = Robot(
            name=chain.name, dh=dh, unit="m", lower=lower[keep], upper=upper[keep], velocity=velocity,
            coupling=(m, c), joint_sign=sign, base=base, tool=tool, joint_names=names,
            description=f"from URDF {Path(src).name}, chain {chain.base} -> {chain.tip}",
        )
    except FamilyError as exc:
        raise FamilyError(f"{src}: {exc}") from exc
    except ValueError as exc:
        raise RobotFileError(f"{src}: {exc}") from exc
    _check_fk(robot, chain, size, names, far_normals)
    return robot


def dh_fk(robot: Robot, q) -> np.ndarray:
    """Forward kinematics of ``robot`` in NumPy (``(..., 6)`` rad -> ``(..., 4, 4)``); the same
    model as :meth:`Robot.fk`, used to check conversions without the compiled kernels."""
    q = np.asarray(q, dtype=float)
    m, c = robot.coupling
    q7 = np.concatenate([q[..., :5], (m * q[..., 4] + c)[..., None], q[..., 5:6]], axis=-1)
    theta = robot.joint_sign * q7 + robot.dh[:, 3]
    A = dh_transform(robot.dh[:, 0], robot.dh[:, 1], theta, robot.dh[:, 2])
    T = np.broadcast_to(robot.base, q.shape[:-1] + (4, 4)).copy()
    for i in range(7):
        T = T @ A[..., i, :, :]
    return T @ robot.tool


def _check_fk(robot: Robot, chain: UrdfChain, size: float, names: tuple[str, ...],
              far_normals: list[tuple[int, float, float]]) -> None:
    rng = np.random.default_rng(0)
    q = rng.uniform(-math.pi, math.pi, (16, 6))
    m, c = robot.coupling
    q7 = np.concatenate([q[:, :5], (m * q[:, 4] + c)[:, None], q[:, 5:]], axis=1)
    err = np.abs(dh_fk(robot, q) - chain.transforms(q7))
    err[:, :3, 3] /= size + 1.0
    worst = float(err.max())
    if worst <= FK_CHECK_TOL:
        return
    if far_normals:
        i, sin, near = far_normals[0]
        raise FamilyError(
            f"{chain.source}: the axes of joints {names[i]!r} and {names[i + 1]!r} are almost but not "
            f"exactly parallel ({math.degrees(math.asin(min(sin, 1.0))):.3g} deg): their common normal "
            f"lies {near:.3g} m away, and written as parallel they miss the chain by {worst:.3g} relative "
            f"to its size, so the chain cannot be written exactly in modified DH parameters; make them "
            f"parallel (ik7r takes axes within {PARALLEL_TOL:g} rad as parallel)")
    raise FamilyError(f"{chain.source}: the chain could not be written exactly in modified DH parameters "
                      f"(forward kinematics differ by {worst:.3g} relative to its size)")


def robot_from_urdf_string(text: str | bytes, *, base: str | None = None, tip: str | None = None,
                           source: str = "<string>") -> Robot:
    """:func:`robot_from_urdf` for URDF text."""
    return robot_from_chain(read_chain(text, base=base, tip=tip, source=source))


def robot_from_urdf(path: PathLike, *, base: str | None = None, tip: str | None = None,
                    max_bytes: int = MAX_ROBOT_FILE_BYTES) -> Robot:
    """Load a robot from a URDF file.

    Parameters
    ----------
    path : str or Path
        The ``.urdf`` file.
    base, tip : str, optional
        Links the chain runs from and to (default: the root link and the deepest leaf).
    max_bytes : int
        Largest file accepted (default :data:`ik7r.limits.MAX_ROBOT_FILE_BYTES`).

    Returns
    -------
    Robot
        Lengths in metres; the independent joints are the chain's revolute (and continuous)
        joints that are not mimic joints, in chain order; joint limits from ``<limit>``
        (continuous joints: [-pi, pi]); velocity limits when every independent joint has one.

    Raises
    ------
    RobotFileError
        Malformed file (a ``ValueError``).
    FamilyError
        The chain is not of the family (a ``ValueError`` naming the joint).
    """
    p = Path(path)
    # bytes, so that the XML declaration's encoding is honoured
    return robot_from_urdf_string(read_bytes_limited(p, max_bytes, "robot file"), base=base, tip=tip,
                                  source=str(p))
