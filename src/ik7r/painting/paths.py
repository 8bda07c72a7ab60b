"""Tool paths for painting: a raster (boustrophedon) over a rectangle, or samples loaded from CSV.

A :class:`Path` is a sequence of tool (gun tip) poses in the robot's **base frame** (frame 0)
together with a path parameter ``u`` (the arc length of the positions, plus the rotation angle
times a radius where the orientation changes), which :mod:`ik7r.painting.interpolate` maps to
time. ``Path.at(u)`` gives the pose anywhere along the path: exactly for a raster, by linear
interpolation of positions and spherical interpolation of rotations between loaded samples.

Frames: ``T_base_workpiece`` places the workpiece in the base frame; a raster lies in the
workpiece's x-y plane, the surface normal is the workpiece's +z (towards the gun), and the gun
orientation is given in the workpiece frame (default :data:`GUN_DOWN`: gun x along the
workpiece x, gun y and z opposite to the workpiece's, the paper's Simulation 3).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .._typing import ArrayLike

import csv
import math
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path as FilePath

import numpy as np

from ..geometry.checks import check_transforms
from ..geometry.rotations import quat_to_matrix, relative_rotvec, rpy_to_matrix, transform
from ..limits import MAX_PATH_FILE_BYTES, MAX_PATH_SAMPLES, check_work
from ..textio import decode_text, read_bytes_limited

__all__ = [
    "Path",
    "GUN_DOWN",
    "DEFAULT_ORIGIN",
    "DEFAULT_SIZE",
    "DEFAULT_SPACING",
    "DEFAULT_STEP",
    "raster_path",
    "path_from_poses",
    "load_path_csv",
    "workpiece_frame",
]

#: Gun orientation in the workpiece frame for the paper's Simulation 3: x along the workpiece x,
#: y and z opposite to the workpiece's (the gun points into the surface).
GUN_DOWN = np.diag([1.0, -1.0, -1.0])

#: Centre of the default raster rectangle in the base frame of the paper robot (mm). See
#: the README, "Off-line painting programs": configuration 1 reaches the default raster (with its
#: turns) everywhere
#: within the Table 4 limits, with theta5 between 44 and 58 deg (far from the wrist
#: singularities at 0 and 180 deg), every joint at least 30 deg inside its limits, and the
#: Jacobian's condition number (positions in m) between 4.9 and 5.6.
DEFAULT_ORIGIN = (1100.0, 0.0, 200.0)
#: Size of the default rectangle (mm): along the workpiece x (the passes), along its y.
DEFAULT_SIZE = (600.0, 800.0)
#: Default distance between passes (mm).
DEFAULT_SPACING = 100.0
#: Default largest distance between path samples (mm).
DEFAULT_STEP = 5.0


#: The default ``spray`` of :class:`Path` (a marker, replaced by on at every sample).
_SPRAY_ON = np.ones(0, dtype=bool)


@dataclass(frozen=True, eq=False)
class Path:
    """Tool poses along a path, in the robot's base frame (immutable).

    Parameters
    ----------
    positions : ndarray, shape (N, 3)
        Tool (gun tip) positions in the base frame (robot length unit).
    rotations : ndarray, shape (N, 3, 3)
        Tool orientations in the base frame.
    u : ndarray, shape (N,)
        Path parameter, strictly increasing from 0 (length unit): the arc length of the
        positions, with rotation angle times ``rotation_radius`` added where the orientation
        turns. Time along the path is a function of ``u``.
    geometry : callable, optional
        ``u (M,) -> (positions (M, 3), rotations (M, 3, 3))``, the exact path between the
        samples. ``None``: linear positions and spherical (slerp) rotations between samples.
    name : str
        What the path is (for reports and plots).
    spray : ndarray of bool, shape (N,), optional
        The spray state at each sample (``True``: gun on). A segment between samples ``i`` and
        ``i + 1`` is sprayed when both ends are on (:meth:`sprayed`), so a switch happens at a
        sample: the last sample of a pass and the first of the next are on, the turn between
        them is off. Default: on everywhere.
    """

    positions: np.ndarray
    rotations: np.ndarray
    u: np.ndarray
    geometry: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]] | None = field(default=None, repr=False)
    name: str = "path"
    spray: np.ndarray = field(default_factory=lambda: _SPRAY_ON)

    def __post_init__(self) -> None:
        P = np.array(self.positions, dtype=float)
        if P.ndim != 2 or P.shape[1] != 3 or P.shape[0] < 2:
            raise ValueError(f"positions must have shape (N, 3) with N >= 2; got {P.shape}")
        R = np.array(self.rotations, dtype=float)
        if R.shape != (P.shape[0], 3, 3):
            raise ValueError(f"rotations must have shape ({P.shape[0]}, 3, 3); got {R.shape}")
        if not np.all(np.isfinite(P)):
            bad = int(np.flatnonzero(~np.all(np.isfinite(P), axis=1))[0])
            raise ValueError(f"positions must be finite; sample {bad} is {P[bad].tolist()}")
        R = check_transforms(transform(R, P), "path pose")[:, :3, :3]
        u = np.array(self.u, dtype=float)
        if u.shape != (P.shape[0],) or not np.all(np.isfinite(u)):
            raise ValueError(f"u must be {P.shape[0]} finite numbers; got shape {u.shape}")
        du = np.diff(u)
        if np.any(du <= 0):
            i = int(np.flatnonzero(du <= 0)[0])
            raise ValueError(f"the path parameter u must increase; samples {i} and {i + 1} have "
                             f"u = {u[i]:.9g} and {u[i + 1]:.9g} (coincident samples?)")
        if self.spray is None or self.spray is _SPRAY_ON:
            spray = np.ones(P.shape[0], dtype=bool)
        else:
            spray = np.array(self.spray)
            if spray.shape != (P.shape[0],) or spray.dtype.kind not in "biu" or not np.all(
                    (spray == 0) | (spray == 1)):
                raise ValueError(f"spray must be {P.shape[0]} flags (bool, or 0 and 1); got "
                                 f"shape {spray.shape}, dtype {spray.dtype}")
            spray = spray.astype(bool)
        for arr in (P, R, u, spray):
            arr.setflags(write=False)
        object.__setattr__(self, "spray", spray)
        object.__setattr__(self, "positions", P)
        object.__setattr__(self, "rotations", R)
        object.__setattr__(self, "u", u)

    def __len__(self) -> int:
        return self.positions.shape[0]

    @property
    def transforms(self) -> np.ndarray:
        """Base <- tool poses ``(N, 4, 4)``."""
        return transform(self.rotations, self.positions)

    @property
    def arc_length(self) -> np.ndarray:
        """Cumulative length of the positions ``(N,)`` (robot length unit), 0 at the start."""
        return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(self.positions, axis=0), axis=1))])

    @property
    def length(self) -> float:
        """Total length of the positions (robot length unit)."""
        return float(self.arc_length[-1])

    def sprayed(self, u: ArrayLike) -> np.ndarray:
        """Whether the gun is on at path parameters ``u`` (M,): bool ``(M,)``.

        On inside a segment whose two end samples are on, and at an on sample itself.
        """
        u = np.atleast_1d(np.asarray(u, dtype=float))
        i = np.clip(np.searchsorted(self.u, u, side="right") - 1, 0, len(self.u) - 2)
        at_sample = np.isclose(u, self.u[i], rtol=0.0, atol=1e-12 * max(1.0, self.u[-1]))
        at_next = np.isclose(u, self.u[i + 1], rtol=0.0, atol=1e-12 * max(1.0, self.u[-1]))
        inside = self.spray[i] & self.spray[i + 1]
        return np.where(at_sample, self.spray[i], np.where(at_next, self.spray[i + 1], inside))

    def at(self, u: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Poses at path parameters ``u`` (M,) in ``[0, u[-1]]``.

        Returns
        -------
        positions : ndarray, shape (M, 3)
        rotations : ndarray, shape (M, 3, 3)
        """
        x = np.atleast_1d(np.asarray(u, dtype=float))
        if not np.all(np.isfinite(x)) or x.size and (x.min() < -1e-9 or x.max() > self.u[-1] + 1e-9):
            raise ValueError(f"u must lie in [0, {self.u[-1]:.9g}]; got [{x.min():.9g}, {x.max():.9g}]")
        x = np.clip(x, 0.0, self.u[-1])
        if self.geometry is not None:
            return self.geometry(x)
        return _interpolate_samples(self.positions, self.rotations, self.u, x)


def _interpolate_samples(P, R, u_samples, u):
    from scipy.spatial.transform import Rotation

    i = np.clip(np.searchsorted(u_samples, u, side="right") - 1, 0, len(u_samples) - 2)
    f = (u - u_samples[i]) / (u_samples[i + 1] - u_samples[i])
    pos = P[i] + f[:, None] * (P[i + 1] - P[i])
    rv = relative_rotvec(R[i], R[i + 1]) * f[:, None]
    rot = R[i] @ Rotation.from_rotvec(rv).as_matrix().reshape(-1, 3, 3)
    return pos, rot


def path_from_poses(T_base_tool: ArrayLike, *, rotation_radius: float = 100.0, name: str = "path") -> Path:
    """A :class:`Path` through the poses ``T_base_tool`` (N, 4, 4) (linear/slerp in between).

    ``rotation_radius`` (length unit per rad, default 100, meant for mm) weights orientation
    changes in the path parameter: ``du = sqrt(|dp|^2 + (rotation_radius * dtheta)^2)``, so
    that a pure change of orientation also takes time. Consecutive poses must differ.
    """
    T = check_transforms(T_base_tool, "path pose")
    if T.ndim != 3:
        raise ValueError(f"T_base_tool must have shape (N, 4, 4); got {T.shape}")
    if not (math.isfinite(rotation_radius) and rotation_radius >= 0):
        raise ValueError(f"rotation_radius must be a finite number >= 0; got {rotation_radius}")
    P, R = T[:, :3, 3], T[:, :3, :3]
    if len(T) < 2:
        raise ValueError(f"a path needs at least 2 poses; got {len(T)}")
    dp = np.linalg.norm(np.diff(P, axis=0), axis=1)
    dth = np.linalg.norm(relative_rotvec(R[:-1], R[1:]), axis=1)
    u = np.concatenate([[0.0], np.cumsum(np.hypot(dp, rotation_radius * dth))])
    return Path(P, R, u, None, name)


def workpiece_frame(origin: ArrayLike = DEFAULT_ORIGIN, rpy: ArrayLike = (0.0, 0.0, 0.0)) -> np.ndarray:
    """``T_base_workpiece`` (4, 4) from a position (length unit) and URDF roll-pitch-yaw (rad)."""
    origin = np.asarray(origin, dtype=float)
    rpy = np.asarray(rpy, dtype=float)
    if origin.shape != (3,) or rpy.shape != (3,) or not np.all(np.isfinite(np.r_[origin, rpy])):
        raise ValueError(f"origin and rpy must be 3 finite numbers each; got {origin!r} and {rpy!r}")
    return transform(rpy_to_matrix(rpy), origin)


# ----------------------------------------------------------------------------- raster
def _positive(name: str, value: float, allow_zero: bool = False) -> float:
    v = float(value)
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise ValueError(f"{name} must be a finite number {'>=' if allow_zero else '>'} 0; got {value!r}")
    return v


def raster_path(
    T_base_workpiece=None,
    *,
    size=DEFAULT_SIZE,
    spacing: float = DEFAULT_SPACING,
    margin: float = 0.0,
    standoff: float = 0.0,
    step: float = DEFAULT_STEP,
    R_workpiece_gun=GUN_DOWN,
    max_samples: int = MAX_PATH_SAMPLES,
) -> Path:
    """A raster (boustrophedon) over a rectangle in the workpiece's x-y plane.

    The rectangle ``[-w/2, w/2] x [-h/2, h/2]`` is centred on the workpiece origin. Passes run
    along the workpiece x, alternating direction, from ``-w/2 - margin`` to ``w/2 + margin``;
    ``n = ceil(h / spacing) + 1`` passes cover ``y`` from ``-h/2`` to ``h/2`` evenly (so the
    actual spacing ``h / (n - 1)`` is at most ``spacing``). Consecutive passes are joined by
    half circles of diameter the actual spacing, outside the rectangle and its margins, so the
    path is tangent-continuous. The gun tip runs at ``standoff`` above the surface (along the
    workpiece +z) with the constant orientation ``R_workpiece_gun``.

    Parameters
    ----------
    T_base_workpiece : array_like, shape (4, 4), optional
        The workpiece frame in the base frame (default: :data:`DEFAULT_ORIGIN`, axes of the base).
    size : (float, float)
        ``(w, h)``: the rectangle's size along the workpiece x and y (length unit).
    spacing, margin, standoff : float
        Largest distance between passes (> 0), overrun of each pass beyond the rectangle (>= 0),
        gun-tip distance from the surface (>= 0), in the length unit.
    step : float
        Largest distance between samples (> 0); every pass and turn end is a sample.
    R_workpiece_gun : array_like, shape (3, 3)
        Gun orientation in the workpiece frame (default :data:`GUN_DOWN`, the paper's).
    max_samples : int
        Most passes and samples (default :data:`ik7r.limits.MAX_PATH_SAMPLES`), estimated before
        anything is allocated (:class:`ik7r.limits.WorkLimitError` above).

    Returns
    -------
    Path
        Exact geometry between samples (``Path.at``); ``u`` is the arc length; spray on along
        the passes (margins included), off in the turns.
    """
    T_bw = workpiece_frame() if T_base_workpiece is None else check_transforms(T_base_workpiece,
                                                                             "T_base_workpiece")
    if T_bw.shape != (4, 4):
        raise ValueError(f"T_base_workpiece must have shape (4, 4); got {T_bw.shape}")
    size = np.asarray(size, dtype=float)
    if size.shape != (2,):
        raise ValueError(f"size must be (width, height); got {size.tolist()}")
    w = _positive("size[0] (width)", size[0])
    h = _positive("size[1] (height)", size[1], allow_zero=True)
    spacing = _positive("spacing", spacing)
    margin = _positive("margin", margin, allow_zero=True)
    standoff = _positive("standoff", standoff, allow_zero=True)
    step = _positive("step", step)
    R_wg = check_transforms(transform(np.asarray(R_workpiece_gun, dtype=float)), "R_workpiece_gun")[:3, :3]

    # estimated before allocating: passes, and samples of the passes and turns
    passes = math.ceil(h / spacing - 1e-9) + 1 if h > 0 else 1
    check_work(f"raster passes (height {h:g} / spacing {spacing:g})", passes, max_samples,
               "--max-samples, or a larger --spacing")
    samples = passes * ((w + 2 * margin) / step + 2) + (passes - 1) * (
        math.pi * h / max(passes - 1, 1) / 2 / step + 2)  # a float: inf for absurd sizes
    check_work(f"raster path samples (step {step:g})", samples, max_samples,
               "--max-samples, or a larger --step")
    n = int(passes)
    gap = h / (n - 1) if n > 1 else 0.0
    x_end = w / 2 + margin
    # segments: lines (kind 0) and half circles (kind 1), in workpiece coordinates (z = standoff)
    kinds, starts, dirs, centres, signs, lengths = [], [], [], [], [], []
    for k in range(n):
        y = -h / 2 + k * gap
        d = 1.0 if k % 2 == 0 else -1.0
        kinds.append(0)
        starts.append((-d * x_end, y))
        dirs.append((d, 0.0))
        centres.append((0.0, 0.0))
        signs.append(0.0)
        lengths.append(2 * x_end)
        if k < n - 1:
            # half circle from (d x_end, y) to (d x_end, y + gap), bulging along +d x
            kinds.append(1)
            starts.append((d * x_end, y))
            dirs.append((d, 0.0))
            centres.append((d * x_end, y + gap / 2))
            signs.append(d)
            lengths.append(math.pi * gap / 2)
    kinds_a = np.array(kinds)
    starts_a, dirs_a, centres_a = np.array(starts), np.array(dirs), np.array(centres)
    signs_a, lengths_a = np.array(signs), np.array(lengths)
    seg_start = np.concatenate([[0.0], np.cumsum(lengths_a)])
    total = float(seg_start[-1])
    R_bg = T_bw[:3, :3] @ R_wg

    def geometry(u: np.ndarray):
        s = np.searchsorted(seg_start, u, side="right") - 1
        s = np.clip(s, 0, len(lengths_a) - 1)
        loc = u - seg_start[s]
        xy = starts_a[s] + dirs_a[s] * loc[:, None]  # lines
        arc = kinds_a[s] == 1
        if np.any(arc):
            # half circle: centre + r (d sin(phi), -cos(phi)), phi from 0 to pi (d = pass direction)
            r = gap / 2
            d = signs_a[s[arc]]
            phi = loc[arc] / r
            xy[arc] = centres_a[s[arc]] + r * np.stack([d * np.sin(phi), -np.cos(phi)], axis=1)
        p_w = np.column_stack([xy, np.full(len(u), standoff)])
        pos = p_w @ T_bw[:3, :3].T + T_bw[:3, 3]
        rot = np.broadcast_to(R_bg, (len(u), 3, 3)).copy()
        return pos, rot

    counts = [max(1, int(math.ceil(lengths_a[i] / step - 1e-9))) for i in range(len(lengths_a))]
    u = np.concatenate([np.linspace(seg_start[i], seg_start[i + 1], counts[i] + 1)[:-1]
                        for i in range(len(lengths_a))] + [[total]])
    # spray: on along the passes (margins included), off inside the turns; a turn's first sample
    # is its pass's last, so it is on
    spray = np.concatenate([np.ones(c, dtype=bool) if kinds[i] == 0
                            else np.r_[True, np.zeros(c - 1, dtype=bool)] for i, c in enumerate(counts)]
                           + [[True]])
    pos, rot = geometry(u)
    name = (f"raster {w:g} x {h:g}, {n} passes {gap:g} apart, margin {margin:g}, standoff {standoff:g}"
            if n > 1 else f"line {w:g}, margin {margin:g}, standoff {standoff:g}")
    return Path(pos, rot, u, geometry, name, spray)


# ----------------------------------------------------------------------------- CSV
def _cut(row) -> str:
    text = repr(row)
    return text if len(text) <= 100 else text[:97] + "..."


_QUAT = ("qw", "qx", "qy", "qz")
_RPY = ("roll", "pitch", "yaw")
_SPRAY_WORDS = {"1": True, "0": False, "true": True, "false": False, "on": True, "off": False}


def load_path_csv(
    file,
    T_base_workpiece=None,
    *,
    default_rotation=GUN_DOWN,
    rotation_radius: float = 100.0,
    max_bytes: int = MAX_PATH_FILE_BYTES,
    max_samples: int = MAX_PATH_SAMPLES,
) -> Path:
    """A path from a CSV file of tool poses in a workpiece frame.

    The file has a header row naming its columns: ``x, y, z`` (required; robot length unit),
    and optionally an orientation as a unit quaternion ``qw, qx, qy, qz`` or as URDF
    roll-pitch-yaw ``roll, pitch, yaw`` in **degrees** (not both). Without orientation columns
    every pose has ``default_rotation`` (in the workpiece frame; default :data:`GUN_DOWN`).
    An optional ``spray`` column (``1``/``0``, ``true``/``false``, ``on``/``off``) gives the
    gun state per sample (:attr:`Path.spray`); without it the gun is on throughout.
    Other columns are ignored (a column named twice is an error); blank lines and lines
    starting with ``#`` are skipped. The file is UTF-8 (a byte-order mark is accepted).

    Parameters
    ----------
    file : str or Path
    T_base_workpiece : array_like, shape (4, 4), optional
        The workpiece frame in the base frame (default: the base frame itself).
    default_rotation : array_like, shape (3, 3)
    rotation_radius : float
        See :func:`path_from_poses`.
    max_bytes, max_samples : int
        Largest file and most rows accepted (:mod:`ik7r.limits`).

    Raises
    ------
    FileNotFoundError
    ValueError
        Malformed file, not UTF-8, too big: the message names the file, the line and the problem.
    """
    fp = FilePath(file)
    if not fp.is_file():
        raise FileNotFoundError(f"no such path file: {fp}")
    T_bw = np.eye(4) if T_base_workpiece is None else check_transforms(T_base_workpiece, "T_base_workpiece")
    text = decode_text(read_bytes_limited(fp, max_bytes, "path file", ValueError), str(fp), "path file",
                       ValueError)
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    if "\x00" in text:
        raise ValueError(f"{fp}: the path file holds NUL bytes; expected CSV text")
    lines = [(i + 1, line) for i, line in enumerate(text.split("\n"))
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise ValueError(f"{fp}: empty file; expected a header row x,y,z[,qw,qx,qy,qz | ,roll,pitch,yaw]")
    check_work(f"rows in {fp}", len(lines) - 1, max_samples, "--max-samples")
    try:
        rows = list(csv.reader([line for _, line in lines]))
    except csv.Error as exc:
        raise ValueError(f"{fp}: not CSV: {exc}") from exc
    header = [c.strip().lower() for c in rows[0]]
    missing = [c for c in ("x", "y", "z") if c not in header]
    if missing:
        raise ValueError(f"{fp}: the header row {_cut(rows[0])} lacks columns {missing}; expected x,y,z "
                         f"and optionally qw,qx,qy,qz or roll,pitch,yaw (deg)")
    dup = sorted(c for c, k in Counter(header).items() if c and k > 1)
    if dup:
        raise ValueError(f"{fp}, line {lines[0][0]}: duplicate columns {dup} in the header")
    has_q = any(c in header for c in _QUAT)
    has_r = any(c in header for c in _RPY)
    if has_q and has_r:
        raise ValueError(f"{fp}: give the orientation either as qw,qx,qy,qz or as roll,pitch,yaw, not both")
    need = ["x", "y", "z"] + (list(_QUAT) if has_q else list(_RPY) if has_r else [])
    for c in need:
        if c not in header:
            raise ValueError(f"{fp}: column {c!r} is missing (header {_cut(rows[0])})")
    cols = [header.index(c) for c in need]
    data = np.empty((len(rows) - 1, len(need)))
    for r, (row, (lineno, _)) in enumerate(zip(rows[1:], lines[1:])):
        try:
            data[r] = [float(row[c]) for c in cols]
        except (IndexError, ValueError) as exc:
            raise ValueError(f"{fp}, line {lineno}: expected numbers in columns {need}; "
                             f"got {_cut(row)}") from exc
        if not np.all(np.isfinite(data[r])):
            raise ValueError(f"{fp}, line {lineno}: values must be finite; got {_cut(row)}")
    if len(data) < 2:
        raise ValueError(f"{fp}: a path needs at least 2 rows; got {len(data)}")
    if has_q:
        norm = np.linalg.norm(data[:, 3:7], axis=1)
        bad = np.flatnonzero(np.abs(norm - 1) > 1e-3)
        if bad.size:
            lineno = lines[1 + int(bad[0])][0]
            raise ValueError(f"{fp}, line {lineno}: quaternion (qw, qx, qy, qz) must have unit norm "
                             f"(within 1e-3); got norm {norm[bad[0]]:.6g}")
        R_w = quat_to_matrix(data[:, 3:7])
    elif has_r:
        R_w = rpy_to_matrix(np.radians(data[:, 3:6]))
    else:
        R0 = check_transforms(transform(np.asarray(default_rotation, dtype=float)),
                              "default_rotation")[:3, :3]
        R_w = np.broadcast_to(R0, (len(data), 3, 3))
    spray = None
    if "spray" in header:
        col = header.index("spray")
        spray = np.empty(len(data), dtype=bool)
        for r, (row, (lineno, _)) in enumerate(zip(rows[1:], lines[1:])):
            word = row[col].strip().lower() if col < len(row) else ""
            if word not in _SPRAY_WORDS:
                raise ValueError(f"{fp}, line {lineno}: column 'spray' must be 1/0, true/false or on/off; "
                                 f"got {word!r}")
            spray[r] = _SPRAY_WORDS[word]
    T_base_tool = T_bw @ transform(R_w, data[:, :3])
    steps = np.linalg.norm(np.diff(T_base_tool[:, :3, 3], axis=0), axis=1)
    if not (np.all(np.isfinite(T_base_tool)) and np.isfinite(steps.sum())):
        raise ValueError(f"{fp}: coordinates too large (the path's length overflows); expected lengths "
                         "in the robot's unit")
    try:
        p = path_from_poses(T_base_tool, rotation_radius=rotation_radius, name=fp.name)
    except ValueError as exc:
        raise ValueError(f"{fp}: {exc}") from exc
    return p if spray is None else Path(p.positions, p.rotations, p.u, None, p.name, spray)
