"""Sharp corners of sampled paths: find them, or blend them within a zone (RAPID's zone data).

A path loaded from samples runs linearly between them, so every sample where the direction
changes is a corner. Where it turns by more than :data:`DEFAULT_CORNER_ANGLE` the robot must
either stop there (the timing stops at :func:`find_corners`) or leave the path within a zone
around the corner: :func:`blend_corners` replaces the corner by the circular arc tangent to
both sides at distance ``d = min(zone, 0.45 x the distance to the next corner)`` from it (the
arc stays inside the zone; RAPID's ``zN`` blends within N mm the same way). The orientation
turns (slerp) from the pose at the arc's start to the one at its end. The blended path keeps
exact geometry (``Path.at`` on the lines and arcs), so the trajectory follows the arc.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..geometry.rotations import relative_rotvec
from .paths import Path

if TYPE_CHECKING:
    from .._typing import ArrayLike

__all__ = ["find_corners", "blend_corners", "DEFAULT_CORNER_ANGLE"]

#: Turn (rad) of a sampled path's direction at a sample above which it is a corner.
DEFAULT_CORNER_ANGLE = math.radians(2.0)


def _tangents(path: Path, rotation_radius: float) -> np.ndarray:
    """Unit tangents of the segments in (position, rotation_radius x rotation vector) (N-1, 6)."""
    dp = np.diff(path.positions, axis=0)
    R = path.rotations
    rv = np.einsum("nij,nj->ni", R[:-1], relative_rotvec(R[:-1], R[1:]))
    d = np.concatenate([dp, rotation_radius * rv], axis=1)
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def find_corners(path: Path, angle: float = DEFAULT_CORNER_ANGLE, *,
                 rotation_radius: float = 100.0) -> tuple[np.ndarray, np.ndarray]:
    """Interior samples where a sampled path (``path.geometry is None``) turns by more than
    ``angle`` (rad): ``(indices (C,), turn angles (C,) rad)``. A path with exact geometry
    (a raster, a blended path) has none."""
    if path.geometry is not None or len(path) < 3:
        return np.zeros(0, dtype=int), np.zeros(0)
    tg = _tangents(path, rotation_radius)
    turn = np.arccos(np.clip(np.einsum("ni,ni->n", tg[:-1], tg[1:]), -1.0, 1.0))
    idx = np.flatnonzero(turn > angle) + 1
    return idx, turn[idx - 1]


def blend_corners(path: Path, zone: float, angle: float = DEFAULT_CORNER_ANGLE, *,
                  rotation_radius: float = 100.0, step: float | None = None) -> Path:
    """``path`` with every corner (:func:`find_corners`) replaced by a tangent circular arc
    within ``zone`` (length unit) of it.

    Parameters
    ----------
    path : Path
        A sampled path (with exact geometry: returned unchanged).
    zone : float
        Zone radius (> 0): the arc starts and ends this far from the corner along the path
        (less where the next corner or the path's end is near: 0.45 of that distance).
    angle : float
        Corner threshold (rad).
    rotation_radius : float
        Weight of orientation changes in ``u`` (as :func:`path_from_poses`).
    step : float, optional
        Largest distance between samples on an arc (default: the zone / 4).

    Returns
    -------
    Path
        Exact geometry; samples: the original ones outside the zones, plus the arcs' samples;
        spray flags carried over (a segment is sprayed when it was; an arc when its corner is).
    """
    if not (math.isfinite(zone) and zone > 0):
        raise ValueError(f"zone must be a positive length; got {zone!r}")
    idx, _ = find_corners(path, angle, rotation_radius=rotation_radius)
    if idx.size == 0:
        return path
    step = zone / 4.0 if step is None else float(step)
    P, R, spray = path.positions, path.rotations, path.spray
    s = path.arc_length
    ends = np.concatenate([[0.0], s[idx], [s[-1]]])
    gaps = np.diff(ends)
    dz = np.minimum(zone, 0.45 * np.minimum(gaps[:-1], gaps[1:]))  # per corner
    from scipy.spatial.transform import Rotation, Slerp

    def at_s(x):
        u = float(np.interp(x, s, path.u))
        pos, rot = path.at([u])
        return pos[0], rot[0], bool(path.sprayed([u])[0])

    # pieces: ("line", p0, p1, R0, R1, flag) or ("arc", centre, e1, e2, r, phi, R0, R1, flag), with
    # the spray flag of the piece's first sample
    pieces: list[tuple[Any, ...]] = []
    cur = (P[0], R[0], bool(spray[0]))
    i = 1
    for c, k in enumerate(idx):
        s_in, s_out = s[k] - dz[c], s[k] + dz[c]
        while i < k and s[i] < s_in - 1e-12 * max(1.0, s[-1]):
            pieces.append(("line", cur[0], P[i], cur[1], R[i], cur[2]))
            cur = (P[i], R[i], bool(spray[i]))
            i += 1
        pin, Rin, _ = at_s(s_in)
        pout, Rout, f_out = at_s(s_out)
        a = (P[k] - pin) / np.linalg.norm(P[k] - pin)
        b = (pout - P[k]) / np.linalg.norm(pout - P[k])
        phi = math.acos(float(np.clip(a @ b, -1.0, 1.0)))
        i = int(np.searchsorted(s, s_out + 1e-12 * max(1.0, s[-1]), side="left"))
        if phi < 1e-9 or phi > math.pi - 1e-6:  # no turn, or a reversal: nothing to blend
            pieces.append(("line", cur[0], P[k], cur[1], R[k], cur[2]))
            cur = (P[k], R[k], bool(spray[k]))
            i = k + 1
            continue
        d = min(np.linalg.norm(P[k] - pin), np.linalg.norm(pout - P[k]))
        pin, pout = P[k] - d * a, P[k] + d * b
        pieces.append(("line", cur[0], pin, cur[1], Rin, cur[2]))
        r = d / math.tan(phi / 2)
        n = b - (a @ b) * a  # towards the inside of the corner, normal to the incoming segment
        n /= np.linalg.norm(n)
        centre = pin + r * n
        pieces.append(("arc", centre, -n, a, r, phi, Rin, Rout, bool(spray[k])))
        cur = (pout, Rout, f_out)
    while i < len(P):
        pieces.append(("line", cur[0], P[i], cur[1], R[i], cur[2]))
        cur = (P[i], R[i], bool(spray[i]))
        i += 1
    pieces = [p for p in pieces if not (p[0] == "line" and np.linalg.norm(p[2] - p[1]) < 1e-12
                                        and np.allclose(p[3], p[4]))]
    lengths, rots = [], []
    for p in pieces:
        if p[0] == "line":
            L = float(np.linalg.norm(p[2] - p[1]))
            th = float(np.linalg.norm(relative_rotvec(p[3][None], p[4][None])[0]))
        else:
            L = p[4] * p[5]
            th = float(np.linalg.norm(relative_rotvec(p[6][None], p[7][None])[0]))
        lengths.append(math.hypot(L, rotation_radius * th))
        rots.append(Rotation.from_matrix(np.stack([p[3], p[4]] if p[0] == "line" else [p[6], p[7]])))
    u0 = np.concatenate([[0.0], np.cumsum(lengths)])
    slerps = [Slerp([0.0, 1.0], r) for r in rots]

    def geometry(u):
        u = np.atleast_1d(np.asarray(u, dtype=float))
        k = np.clip(np.searchsorted(u0, u, side="right") - 1, 0, len(pieces) - 1)
        f = np.clip((u - u0[k]) / np.asarray(lengths)[k], 0.0, 1.0)
        pos = np.empty((len(u), 3))
        rot = np.empty((len(u), 3, 3))
        for j in np.unique(k):
            m = k == j
            p = pieces[j]
            if p[0] == "line":
                pos[m] = p[1] + f[m, None] * (p[2] - p[1])
            else:
                centre, e1, e2, r, phi = p[1], p[2], p[3], p[4], p[5]
                ang = f[m] * phi
                pos[m] = centre + r * (np.cos(ang)[:, None] * e1 + np.sin(ang)[:, None] * e2)
            rot[m] = slerps[j](f[m]).as_matrix()
        return pos, rot

    us: list[ArrayLike] = []
    flags: list[ArrayLike] = []
    for j, p in enumerate(pieces):
        if p[0] == "line":
            n = 1
        else:
            n = max(4, int(math.ceil(p[4] * p[5] / step)))
        us.append(u0[j] + np.arange(n) / n * lengths[j])
        flags.append(np.full(n, p[-1]))
    us.append([u0[-1]])
    flags.append([bool(spray[-1])])
    u = np.concatenate(us)
    fl = np.concatenate(flags).astype(bool)
    pos, rot = geometry(u)
    return Path(pos, rot, u, geometry, f"{path.name}, corners blended within {zone:g}", fl)
