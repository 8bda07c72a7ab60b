"""Robot files: the TOML format, the built-in robots, and :func:`load_robot`.

The TOML format (angles in degrees, lengths in ``unit``)::

    name = "paper"
    unit = "mm"                       # length unit of dh, base and tool
    description = "..."               # optional

    [dh]                              # Craig's modified DH, one entry per joint 1..7
    a            = [0, 0, 1000, 0, 0, 0, 0]       # a_{i-1}
    alpha        = [0, 90, 0, 90, -35, 70, -35]   # alpha_{i-1}, deg
    d            = [0, 0, 0, 900, 80, 80, 100]    # d_i
    theta_offset = [0, 0, 0, 0, 0, 0, 0]          # optional, deg: theta_i = sign_i q_i + offset_i
    sign         = [1, 1, 1, 1, 1, 1, 1]          # optional

    [coupling]                        # optional: q6 = multiplier * q5 + offset (deg)
    multiplier = -1.0
    offset = 0.0

    [limits]                          # independent joints q1 q2 q3 q4 q5 q7
    lower = [-70, -80, -70, -360, -180, -360]     # deg
    upper = [70, 135, 70, 360, 180, 360]
    velocity = [...]                  # optional, deg/s
    acceleration = [...]              # optional, deg/s^2

    [base]                            # optional: world <- frame 0
    xyz = [0, 0, 0]
    rpy = [0, 0, 0]                   # deg, URDF convention (fixed axes X-Y-Z)

    [tool]                            # optional: frame 7 <- tool (TCP)
    xyz = [0, 0, 0]
    rpy = [0, 0, 0]

    joint_names = ["joint_1", ..., "joint_7"]   # optional
"""

from __future__ import annotations

import math
import os
import sys
from importlib import resources
from pathlib import Path

import numpy as np

from .._typing import RobotSource
from ..errors import FamilyError, RobotFileError
from ..geometry.rotations import rpy_to_matrix, transform
from ..limits import MAX_ROBOT_FILE_BYTES
from ..textio import decode_text, read_text_file
from ..units import unit_scale
from .model import DEFAULT_JOINT_NAMES, Robot

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["load_robot", "robot_from_toml", "robot_in_unit", "BUILTIN_ROBOTS"]

#: Names of the robots shipped with ik7r (``ik7r.load_robot(name)``).
BUILTIN_ROBOTS = {"paper": "paper.toml", "irb5400": "irb5400.toml"}



def load_robot(path: RobotSource = None, *, base: str | None = None, tip: str | None = None,
               max_bytes: int = MAX_ROBOT_FILE_BYTES) -> Robot:
    """Load a robot.

    Parameters
    ----------
    path : str or Path, optional
        ``None`` for the paper's robot; a built-in name (``"paper"``, ``"irb5400"``); or a
        ``.toml`` or ``.urdf`` file.
    base, tip : str, optional
        URDF only: the links the chain runs from and to (default: the root, and the deepest
        leaf).
    max_bytes : int
        Largest file accepted (default :data:`ik7r.limits.MAX_ROBOT_FILE_BYTES`, 64 MiB).

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    RobotFileError
        The file is malformed, too big, unreadable or not UTF-8 (a ``ValueError`` naming the
        file and the problem).
    ValueError
        ``path`` is not a name or a path.
    FamilyError
        The chain is not of the family (a ``ValueError`` naming the joint).
    """
    if path is None:
        path = "paper"
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if not isinstance(path, (str, os.PathLike)):
        raise ValueError(f"robot must be a built-in name ({', '.join(BUILTIN_ROBOTS)}) or the path of a "
                         f".toml or .urdf file; got {type(path).__name__} {path!r}")
    if isinstance(path, str) and path in BUILTIN_ROBOTS:
        data = resources.files("ik7r.robot").joinpath("data").joinpath(BUILTIN_ROBOTS[path])
        text = data.read_text(encoding="utf-8")
        return robot_from_toml(text, source=f"built-in robot {path!r}")
    p = Path(path)
    if str(path) == "" or "\x00" in str(path):
        raise ValueError(f"not a robot name or file: {str(path)!r}")
    if p.suffix.lower() == ".urdf":
        from .urdf import robot_from_urdf

        if not p.is_file():
            raise FileNotFoundError(f"no such robot file: {p}")
        return robot_from_urdf(p, base=base, tip=tip, max_bytes=max_bytes)
    if base is not None or tip is not None:
        raise ValueError("base= and tip= apply to URDF files only")
    if p.suffix.lower() != ".toml":
        if not p.exists():
            raise FileNotFoundError(
                f"no such robot file or built-in robot: {path} (built-in: {', '.join(BUILTIN_ROBOTS)})")
        raise RobotFileError(f"{p}: unknown robot file type {p.suffix!r}; expected .toml or .urdf")
    if not p.is_file():
        raise FileNotFoundError(f"no such robot file: {p}")
    return robot_from_toml(read_text_file(p, max_bytes, "robot file"), source=str(p))


def _numbers(table: dict, key: str, n: int, where: str, required: bool = True):
    if key not in table:
        if required:
            raise RobotFileError(f"{where}: missing '{key}' ({n} numbers)")
        return None
    val = table[key]
    if (not isinstance(val, list) or len(val) != n
            or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in val)):
        raise RobotFileError(f"{where}: '{key}' must be a list of {n} numbers; got {_short(val)}")
    try:
        arr = np.array(val, dtype=float)
    except OverflowError:  # a TOML integer beyond the floats
        arr = np.array([math.inf])
    if not np.all(np.isfinite(arr)):
        raise RobotFileError(f"{where}: '{key}' must be finite; got {_short(val)}")
    return arr


def _pose(table, where: str) -> np.ndarray:
    _table_keys(table, where, {"xyz", "rpy"})
    xyz = _numbers(table, "xyz", 3, where, required=False)
    rpy = _numbers(table, "rpy", 3, where, required=False)
    R = rpy_to_matrix(np.radians(rpy)) if rpy is not None else np.eye(3)
    return transform(R, xyz if xyz is not None else np.zeros(3))


def _table_keys(table, where: str, known: set[str]) -> None:
    """``table`` must be a TOML table holding only ``known`` keys."""
    if not isinstance(table, dict):
        raise RobotFileError(f"{where}: must be a table ({', '.join(sorted(known))}); "
                             f"got {type(table).__name__} {_short(table)}")
    unknown = set(table) - known
    if unknown:
        raise RobotFileError(f"{where}: unknown keys {sorted(unknown)}; expected {sorted(known)}")


def _short(x) -> str:
    text = repr(x)
    return text if len(text) <= 60 else text[:57] + "..."


def robot_from_toml(text: str, source: str = "<string>") -> Robot:
    """Build a :class:`Robot` from the text of a TOML robot file (see the module docstring).

    Raises
    ------
    RobotFileError
        Not TOML, nested too deeply, a missing or unknown key in any table, a value of the
        wrong type or length (the message starts with ``source`` and names the table and key).
    FamilyError
        The table is outside the family.
    """
    if isinstance(text, bytes):
        text = decode_text(text, source, "robot file")
    if not isinstance(text, str):
        raise RobotFileError(f"{source}: TOML text expected; got {type(text).__name__}")
    text = text.removeprefix("\ufeff")  # a byte-order mark
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RobotFileError(f"{source}: not valid TOML: {exc}") from exc
    except RecursionError:
        raise RobotFileError(f"{source}: not a robot file: arrays or tables nested too deeply") from None
    known = {"name", "unit", "description", "dh", "coupling", "limits", "base", "tool", "joint_names"}
    unknown = set(data) - known
    if unknown:
        raise RobotFileError(f"{source}: unknown keys {sorted(unknown)}; expected {sorted(known)}")
    for key in ("name", "unit"):
        if not isinstance(data.get(key), str):
            raise RobotFileError(f"{source}: '{key}' must be a string")
    if "description" in data and not isinstance(data["description"], str):
        raise RobotFileError(f"{source}: 'description' must be a string")
    for key in ("dh", "limits"):
        if key not in data:
            raise RobotFileError(f"{source}: missing table [{key}]")
    dh_t = data["dh"]
    where = f"{source} [dh]"
    _table_keys(dh_t, where, {"a", "alpha", "d", "theta_offset", "sign"})
    a = _numbers(dh_t, "a", 7, where)
    alpha = _numbers(dh_t, "alpha", 7, where)
    d = _numbers(dh_t, "d", 7, where)
    off = _numbers(dh_t, "theta_offset", 7, where, required=False)
    sign = _numbers(dh_t, "sign", 7, where, required=False)
    lim = data["limits"]
    where = f"{source} [limits]"
    _table_keys(lim, where, {"lower", "upper", "velocity", "acceleration"})
    lower = _numbers(lim, "lower", 6, where)
    upper = _numbers(lim, "upper", 6, where)
    vel = _numbers(lim, "velocity", 6, where, required=False)
    acc = _numbers(lim, "acceleration", 6, where, required=False)
    coup = data.get("coupling", {})
    _table_keys(coup, f"{source} [coupling]", {"multiplier", "offset"})
    mult = coup.get("multiplier", -1.0)
    coff = coup.get("offset", 0.0)
    if not all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
               for x in (mult, coff)):
        raise RobotFileError(f"{source} [coupling]: multiplier and offset must be finite numbers; "
                             f"got {_short(mult)} and {_short(coff)}")
    names = data.get("joint_names", list(DEFAULT_JOINT_NAMES))
    if not (isinstance(names, list) and len(names) == 7 and all(isinstance(n, str) for n in names)):
        raise RobotFileError(f"{source}: 'joint_names' must be a list of 7 strings")
    # angles in degrees are periodic: reduced modulo 360 exactly (IEEE remainder) before the
    # conversion to radians, so an offset of 1e6 deg keeps its full precision
    alpha = _reduced_degrees(alpha)
    off = _reduced_degrees(off) if off is not None else np.zeros(7)
    coff = _reduced_degrees(np.array([float(coff)]))[0]
    dh = np.stack([a, np.radians(alpha), d, np.radians(off)], 1)
    try:
        return Robot(
            name=data["name"], dh=dh, unit=data["unit"], lower=np.radians(lower),
            upper=np.radians(upper),
            velocity=None if vel is None else np.radians(vel),
            acceleration=None if acc is None else np.radians(acc),
            coupling=(float(mult), math.radians(coff)),
            joint_sign=sign if sign is not None else np.ones(7),
            base=_pose(data.get("base", {}), f"{source} [base]"),
            tool=_pose(data.get("tool", {}), f"{source} [tool]"),
            joint_names=tuple(names), description=str(data.get("description", "")),
        )
    except FamilyError as exc:
        raise FamilyError(f"{source}: {exc}") from exc
    except RobotFileError:
        raise
    except ValueError as exc:
        raise RobotFileError(f"{source}: {exc}") from exc


def _reduced_degrees(x: np.ndarray) -> np.ndarray:
    """Angles (deg) reduced to [-180, 180] exactly (the IEEE remainder of a float is exact)."""
    return np.array([math.remainder(float(v), 360.0) if 180.0 < abs(v) < math.inf else float(v) for v in x])


def robot_in_unit(robot: Robot, unit: str) -> Robot:
    """A copy of ``robot`` with its lengths (DH a and d, base and tool translations) in ``unit``.

    Parameters
    ----------
    robot : Robot
    unit : str
        One of :data:`ik7r.units.METRES_PER_UNIT` (``"m"``, ``"cm"``, ``"mm"``, ``"in"``);
        ``robot.unit`` must be too.

    Returns
    -------
    Robot
        Same joints and limits; its forward kinematics is the original one with positions scaled.
    """
    k = unit_scale(robot.unit, unit)
    if unit == robot.unit:
        return robot

    def scaled(x):  # x * k without the float noise of the product (1.4083 * 1000 = 1408.3)
        y = np.asarray(x, dtype=float) * k
        tidy = np.array([float(f"{v:.12g}") for v in y.reshape(-1)]).reshape(y.shape)
        return np.where(np.abs(tidy - y) <= 4 * np.finfo(float).eps * np.abs(y), tidy, y)

    dh = np.array(robot.dh)
    dh[:, 0], dh[:, 2] = scaled(dh[:, 0]), scaled(dh[:, 2])
    base, tool = np.array(robot.base), np.array(robot.tool)
    base[:3, 3], tool[:3, 3] = scaled(base[:3, 3]), scaled(tool[:3, 3])
    return robot.replace(dh=dh, base=base, tool=tool, unit=unit)
