"""Robot programs from a timed trajectory: an ABB RAPID module and the same program as JSON.

The program's targets are the trajectory's IK samples (``knot_q``: exact solutions of path
poses, so every target lies on the path), in path order, each reached at its planned time.

RAPID (:func:`write_rapid`): one ``CONST jointtarget`` per target with the six axes in degrees
(axes 1-6 are the independent joints ``[q1, q2, q3, q4, q5, q7]`` as the robot file names and
signs them; the coupled joint 6 is not an axis of its own; external axes ``9E9``), a
``MoveAbsJ`` per target with ``\\T`` set to the planned segment time (so the controller follows
the planned timing; the speed data is then ignored), zone data ``fine`` where the robot stops
(start, end, corners) and a small zone (``zpath``: the ``zone`` given, or 1 mm) elsewhere, and
``SetDO <signal>, 1/0`` after the target where the spray switches on/off. ``main`` moves to
the first target (untimed, at ``v100``, the gun off), then calls the procedures ``path_1``,
``path_2``, ... of at most ``moves_per_proc`` moves each, and switches the gun off at the end.
"""

from __future__ import annotations

import json
import math
import os
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path as FilePath

import numpy as np

from .interpolate import mm_in

__all__ = ["Program", "make_program", "rapid_text", "write_rapid", "program_dict", "write_program_json",
           "DEFAULT_SIGNAL", "DEFAULT_MOVES_PER_PROC"]

#: Default digital output that switches the gun.
DEFAULT_SIGNAL = "doGunOn"
#: Most moves per RAPID procedure.
DEFAULT_MOVES_PER_PROC = 1000
_IDENT = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,31}$")


@dataclass(frozen=True, eq=False)
class Program:
    """A joint program: targets, times, spray state, zones.

    Attributes
    ----------
    q : ndarray, shape (K, 6)
        Targets ``[q1, q2, q3, q4, q5, q7]`` (rad).
    t : ndarray, shape (K,)
        Planned time of each target (s); ``t[0] = 0``, ``t[-1]`` the duration.
    positions : ndarray, shape (K, 3)
        The path point of each target (base frame, robot length unit).
    spray : ndarray of bool, shape (K - 1,)
        Gun on while moving from target ``k`` to ``k + 1``.
    stop : ndarray of bool, shape (K,)
        The robot is at rest at the target (zone ``fine``).
    zone_mm : float
        Zone radius of the other targets (mm).
    robot, unit, signal : str
    commanded_speed : float or None
    """

    q: np.ndarray
    t: np.ndarray
    positions: np.ndarray
    spray: np.ndarray
    stop: np.ndarray
    zone_mm: float
    robot: str
    unit: str
    signal: str
    commanded_speed: float | None = None

    @property
    def duration(self) -> float:
        return float(self.t[-1])


def make_program(robot, path, trajectory, *, signal: str = DEFAULT_SIGNAL,
                 zone: float | None = None) -> Program:
    """The program of ``trajectory`` (its IK samples as targets) along ``path``.

    ``zone`` (robot length unit, default 1 mm) is the zone radius of the targets the robot
    passes without stopping.
    """
    if not _IDENT.match(signal):
        raise ValueError(f"signal must be a RAPID identifier (a letter, then letters, digits or _; at most "
                         f"32); got {signal!r}")
    zone_mm = 1.0 if zone is None else float(zone) / mm_in(robot.unit)
    if not (math.isfinite(zone_mm) and zone_mm > 0):
        raise ValueError(f"zone must be a positive length; got {zone!r}")
    ku = np.asarray(trajectory.knot_u)
    mid = 0.5 * (ku[:-1] + ku[1:])
    stop = np.zeros(len(ku), dtype=bool)
    stop[[0, -1]] = True
    if trajectory.stops:
        stop |= np.isin(ku, trajectory.stops)
    pos, _ = path.at(ku)
    return Program(np.array(trajectory.knot_q), np.array(trajectory.knot_t), pos, path.sprayed(mid), stop,
                   zone_mm, robot.name, robot.unit, signal, trajectory.commanded_speed)


def _num(x: float) -> str:
    return f"{x:.6f}".rstrip("0").rstrip(".") if abs(x) >= 5e-7 else "0"


def rapid_text(program: Program, *, module: str = "ik7rPaint", tool: str = "tool0",
               moves_per_proc: int = DEFAULT_MOVES_PER_PROC) -> str:
    """The RAPID module of ``program`` (see the module docstring)."""
    for name, v in (("module", module), ("tool", tool)):
        if not _IDENT.match(v):
            raise ValueError(f"{name} must be a RAPID identifier; got {v!r}")
    if moves_per_proc < 1:
        raise ValueError(f"moves_per_proc must be at least 1; got {moves_per_proc}")
    deg = np.degrees(program.q)
    # times rounded once, so that the \T of consecutive moves add up to the rounded duration
    t_r = np.round(program.t, 6)
    dt = np.diff(t_r)
    z = program.zone_mm
    lines = [f"MODULE {module}",
             f"  ! written by ik7r for robot {program.robot}: {len(deg)} targets, planned duration "
             f"{_num(t_r[-1])} s",
             "  ! axes 1-6 = independent joints [q1, q2, q3, q4, q5, q7] (deg) as the robot file names "
             "and signs them;",
             "  ! joint 6 is coupled to joint 5 (not an axis); external axes unused (9E9)",
             f"  ! {program.signal} = 1 while the gun sprays; \\T = planned segment time (s)",
             f"  CONST zonedata zpath := [FALSE, {_num(z)}, {_num(1.5 * z)}, {_num(1.5 * z)}, "
             f"{_num(0.15 * z)}, {_num(1.5 * z)}, {_num(0.15 * z)}];"]
    for k, row in enumerate(deg):
        lines.append(f"  CONST jointtarget jt{k} := [[{', '.join(_num(v) for v in row)}], "
                     "[9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];")
    n_moves = len(deg) - 1
    procs = [list(range(1 + i, min(1 + i + moves_per_proc, len(deg))))
             for i in range(0, n_moves, moves_per_proc)]
    sig = program.signal
    lines += ["", "  PROC main()", f"    SetDO {sig}, 0;",
              f"    MoveAbsJ jt0, v100, fine, {tool};  ! to the start (not timed)"]
    if program.spray[0]:
        lines.append(f"    SetDO {sig}, 1;")
    lines += [f"    path_{i + 1};" for i in range(len(procs))]
    lines += [f"    SetDO {sig}, 0;", "  ENDPROC"]
    for i, ks in enumerate(procs):
        lines += ["", f"  PROC path_{i + 1}()"]
        for k in ks:
            zone = "fine" if program.stop[k] else "zpath"
            lines.append(f"    MoveAbsJ jt{k}, v1000 \\T:={_num(dt[k - 1])}, {zone}, {tool};")
            if k < n_moves and program.spray[k] != program.spray[k - 1]:
                lines.append(f"    SetDO {sig}, {int(program.spray[k])};")
        lines.append("  ENDPROC")
    lines.append("ENDMODULE")
    return "\n".join(lines) + "\n"


def program_dict(program: Program) -> dict:
    """The program as plain data (JSON-ready)."""
    return {
        "format": "ik7r-program", "version": 1, "robot": program.robot, "unit": program.unit,
        "joints": ["q1", "q2", "q3", "q4", "q5", "q7"], "signal": program.signal,
        "duration": program.duration, "commanded_speed": program.commanded_speed, "zone_mm": program.zone_mm,
        "targets": [
            {"index": k, "t": float(program.t[k]), "dt": float(program.t[k] - program.t[k - 1]) if k else 0.0,
             "q_rad": [float(v) for v in program.q[k]], "q_deg": [float(v) for v in np.degrees(program.q[k])],
             "position": [float(v) for v in program.positions[k]],
             "spray_after": bool(program.spray[k]) if k < len(program.spray) else False,
             "zone": "fine" if program.stop[k] else "zpath"}
            for k in range(len(program.t))],
    }


def _write_atomic(file, text: str) -> FilePath:
    fp = FilePath(file)
    fd, tmp = tempfile.mkstemp(prefix=f".{fp.name}.", dir=fp.parent if str(fp.parent) else ".")
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, fp)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return fp


def write_rapid(program: Program, file, **options) -> FilePath:
    """Write :func:`rapid_text` to ``file`` (written to a temporary file, then renamed)."""
    fp = FilePath(file)
    options.setdefault("module", re.sub(r"[^A-Za-z0-9_]", "_", fp.stem)[:32] if _IDENT.match(
        re.sub(r"[^A-Za-z0-9_]", "_", fp.stem)[:32] or "") else "ik7rPaint")
    return _write_atomic(fp, rapid_text(program, **options))


def write_program_json(program: Program, file) -> FilePath:
    """Write :func:`program_dict` as JSON (written to a temporary file, then renamed)."""
    return _write_atomic(file, json.dumps(program_dict(program), indent=1) + "\n")
