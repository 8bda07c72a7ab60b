"""Spray paths on a part's surface: a plane-slicing raster as a pipeline of small stages.

Like ROS-Industrial noether's plane slicer and its modifiers, :func:`surface_raster` is the
composition of stages that each take and return plain data (usable on their own):

1. :func:`target_faces` -- the faces to paint: those facing the gun side ``view`` (part frame,
   default +z: the gun is above the part, looking down -z);
2. :func:`smoothed_normals` -- per-vertex normals of those faces, averaged over a radius (a
   coarse mesh still gives a smooth path), interpolated inside each face;
3. :func:`slice_surface` -- cut the target faces with parallel planes ``spacing`` apart, normal
   to the cross direction ``c = view x direction``, centred on the part, so that the bands
   ``spacing`` wide around the passes cover it; along each cut, the surface point closest to
   the gun (largest height along ``view``) every ``step``, and where the cut leaves the part
   (holes, gaps, the edges);
4. :func:`pass_poses` -- the gun poses of a pass: tip ``standoff`` along the smoothed normal,
   gun axis (tool +z) pointing at the surface, tool x along the direction of travel turned by
   ``spin`` about the gun axis; passes alternate direction (boustrophedon);
5. :func:`extend_pass` -- ``overspray`` past each edge of the part, spray on, straight along the
   travel direction, so the gun is at speed over the whole part; gaps narrower than twice the
   overspray are crossed with the spray on, wider ones with it off;
6. :func:`link_passes` -- turnarounds between passes (a U turn with zero curvature at its ends,
   spray off), a straight
   approach (lead-in) before the first pass and a retract (lead-out) after the last, spray off.

The result is a :class:`~ik7r.painting.Path` in the robot's base frame whose ``spray`` flags
say where the gun is on: trajectory IK, events and interpolation use it unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .parts import Part
from .paths import DEFAULT_STEP, Path

__all__ = ["SurfacePass", "PoseRun", "target_faces", "smoothed_normals", "slice_surface", "pass_poses",
           "extend_pass", "link_passes", "surface_raster", "smooth_geometry", "sprayed_length",
           "DEFAULT_SURFACE_SPACING", "DEFAULT_STANDOFF", "DEFAULT_OVERSPRAY", "DEFAULT_APPROACH"]

#: Defaults in mm (converted to the part's unit): distance between passes, gun standoff,
#: overspray past the part's edges, length of the approach and retract.
DEFAULT_SURFACE_SPACING = 60.0
DEFAULT_STANDOFF = 200.0
DEFAULT_OVERSPRAY = 60.0
DEFAULT_APPROACH = 150.0


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0)


def _axes(direction, view) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(travel d, cross c, view v), orthonormal, from a direction and a view axis (part frame)."""
    v = _unit(np.asarray(view, dtype=float))
    d = np.asarray(direction, dtype=float)
    if d.shape != (3,) or v.shape != (3,) or not np.all(np.isfinite(np.r_[d, v])):
        raise ValueError(f"direction and view must be 3 finite numbers each; got {d!r} and {view!r}")
    d = d - (d @ v) * v
    if np.linalg.norm(d) < 1e-9 or np.linalg.norm(v) < 1e-9:
        raise ValueError(f"the pass direction {np.asarray(direction).tolist()} must not be parallel "
                         f"to the view axis {np.asarray(view).tolist()} (nor zero)")
    d = _unit(d)
    return d, np.cross(v, d), v


# ----------------------------------------------------------------------------- stages 1-2
def target_faces(part: Part, view=(0.0, 0.0, 1.0), *, min_cos: float = 0.05) -> np.ndarray:
    """Faces to paint ``(F,)`` bool: unit normal . ``view`` > ``min_cos`` (they face the gun)."""
    return part.face_normals @ _unit(np.asarray(view, dtype=float)) > min_cos


def smoothed_normals(part: Part, faces=None, radius: float | None = None) -> np.ndarray:
    """Unit vertex normals ``(V, 3)`` of the ``faces`` (mask; default all), smoothed over
    ``radius`` (default twice the median edge length). Vertices of no selected face get 0.

    At each vertex, the normal is the value at the vertex of a local linear regression of the
    normals of the faces whose centroids lie within ``radius`` (Gaussian weights, sigma =
    radius / 2, times the face areas), over the vertex's tangent plane: inside the part that is
    the weighted mean of the normals around the vertex, and at the part's border, where the
    faces lie on one side only, it is not biased towards the inside (a mean there is the normal
    of a point about radius / 3 inside, which turns the gun too late and then all at once as the
    pass reaches the edge). A normal that changes linearly over the surface (a sphere, to first
    order) is reproduced, a flat part's exactly; where fewer than three faces or faces in a line
    are in reach, the weighted mean.
    """
    from scipy.spatial import cKDTree

    F = part.faces if faces is None else part.faces[np.asarray(faces, dtype=bool)]
    tri = part.vertices[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])  # area-weighted
    acc = np.zeros_like(part.vertices)
    for k in range(3):
        np.add.at(acc, F[:, k], n)
    if radius is None:
        edges = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2)
        radius = 2.0 * float(np.median(edges)) if edges.size else 0.0
    used = np.flatnonzero(np.linalg.norm(acc, axis=1) > 0)
    if radius > 0 and len(used) > 0:
        Vu = part.vertices[used]
        centres = tri.mean(axis=1)
        area = 0.5 * np.linalg.norm(n, axis=1)
        nf = _unit(n)
        D = cKDTree(Vu).sparse_distance_matrix(cKDTree(centres), radius, output_type="coo_matrix")
        row, col = D.row, D.col
        w = np.exp(-2.0 * (D.data / radius) ** 2) * area[col]
        # tangent frame of each vertex (from its own faces' normal)
        n0 = _unit(acc[used])
        helper = np.where(np.abs(n0[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        e1 = _unit(np.cross(n0, helper))
        e2 = np.cross(n0, e1)
        dx = centres[col] - Vu[row]
        phi = np.column_stack([np.ones(len(row)), np.sum(dx * e1[row], axis=1) / radius,
                               np.sum(dx * e2[row], axis=1) / radius])
        M = np.zeros((len(used), 3, 3))
        rhs = np.zeros((len(used), 3, 3))
        np.add.at(M, row, w[:, None, None] * phi[:, :, None] * phi[:, None, :])
        np.add.at(rhs, row, w[:, None, None] * phi[:, :, None] * nf[col][:, None, :])
        count = np.bincount(row, minlength=len(used))
        mean = np.divide(rhs[:, 0], M[:, 0, 0, None], out=np.zeros((len(used), 3)),
                         where=M[:, 0, 0, None] > 0)
        scale = np.maximum(M[:, 0, 0], 1e-300)
        regular = (count >= 3) & (np.linalg.det(M) / scale ** 3 > 1e-6)
        fit = np.zeros((len(used), 3))
        if np.any(regular):
            fit[regular] = np.linalg.solve(M[regular], rhs[regular])[:, 0]
        est = np.where(regular[:, None], fit, mean)
        ok = np.linalg.norm(est, axis=1) > 0
        acc[used[ok]] = est[ok]
    return _unit(acc)


# ----------------------------------------------------------------------------- stage 3
@dataclass(frozen=True, eq=False)
class SurfacePass:
    """One cut of the surface: samples of the surface along the travel direction.

    Attributes
    ----------
    offset : float
        Position of the cutting plane along the cross direction (part frame, length unit).
    s : ndarray, shape (N,)
        Coordinate of each sample along the travel direction ``d`` (increasing).
    points : ndarray, shape (N, 3)
        Surface points (part frame).
    normals : ndarray, shape (N, 3)
        Smoothed unit normals there (towards the gun side).
    covered : ndarray, shape (K, 2)
        ``[s_start, s_end]`` of each stretch where the cut is on the part (gaps between them).
    run : ndarray, shape (N,), int
        Index of the stretch each sample belongs to.
    """

    offset: float
    s: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    covered: np.ndarray
    run: np.ndarray


def _cut(V, F, N, c, h):
    """Segments of the plane ``x . c = h`` with the faces: endpoints and normals (K, 2, 3) each."""
    dist = V @ c - h
    dist = np.where(dist == 0.0, 1e-12 * max(1.0, abs(h)), dist)
    df = dist[F]
    pos = df > 0
    cross = pos.any(axis=1) & ~pos.all(axis=1)
    F, df, pos = F[cross], df[cross], pos[cross]
    if len(F) == 0:
        return np.empty((0, 2, 3)), np.empty((0, 2, 3))
    # the lone vertex (the one whose side differs from the other two) and its two edges
    lone = np.where(pos.sum(axis=1) == 1, np.argmax(pos, axis=1), np.argmin(pos, axis=1))
    rows = np.arange(len(F))
    a = F[rows, lone]
    da = df[rows, lone]
    P, Nn = [], []
    for k in (1, 2):
        other = (lone + k) % 3
        b, db = F[rows, other], df[rows, other]
        f = (da / (da - db))[:, None]
        P.append(V[a] + f * (V[b] - V[a]))
        Nn.append(N[a] + f * (N[b] - N[a]))
    return np.stack(P, axis=1), np.stack(Nn, axis=1)


def slice_surface(part: Part, faces, normals, *, spacing: float, direction=(1.0, 0.0, 0.0),
                  view=(0.0, 0.0, 1.0), step: float = DEFAULT_STEP) -> list[SurfacePass]:
    """Cut the ``faces`` (mask) with planes ``spacing`` apart; one :class:`SurfacePass` per
    plane that meets them, ordered along the cross direction ``view x direction``.

    ``n = ceil(W / spacing)`` planes, centred on the faces' extent ``W`` across, so the bands
    ``spacing`` wide centred on the passes cover the part. Along each cut the samples are at
    most ``step`` apart, with one at each end of every stretch on the part.
    """
    for name, val in (("spacing", spacing), ("step", step)):
        if not (math.isfinite(val) and val > 0):
            raise ValueError(f"{name} must be a positive length; got {val!r}")
    d, c, v = _axes(direction, view)
    mask = np.asarray(faces, dtype=bool)
    F = part.faces[mask]
    if len(F) == 0:
        raise ValueError(f"{part.name}: no face faces the gun side {np.asarray(view).tolist()} (part frame)")
    V = part.vertices
    used = np.unique(F)
    across = V[used] @ c
    lo, hi = float(across.min()), float(across.max())
    n = max(1, int(math.ceil((hi - lo) / spacing - 1e-9)))
    offsets = 0.5 * (lo + hi) + (np.arange(n) - (n - 1) / 2) * spacing
    eps = 1e-9 * max(1.0, float(np.ptp(V[used], axis=0).max()))
    passes = []
    for h in offsets:
        P, Nn = _cut(V, F, normals, c, h)
        if len(P) == 0:
            continue
        s_seg = P @ d  # (K, 2)
        order = np.argsort(s_seg, axis=1)
        P = np.take_along_axis(P, order[:, :, None], axis=1)
        Nn = np.take_along_axis(Nn, order[:, :, None], axis=1)
        s_seg = np.take_along_axis(s_seg, order, axis=1)
        keep = s_seg[:, 1] - s_seg[:, 0] > eps
        P, Nn, s_seg = P[keep], Nn[keep], s_seg[keep]
        if len(P) == 0:
            continue
        # stretches: union of the segments' s-intervals
        idx = np.argsort(s_seg[:, 0])
        covered: list[list[float]] = []
        for a, b in s_seg[idx]:
            if covered and a <= covered[-1][1] + 10 * eps:
                covered[-1][1] = max(covered[-1][1], b)
            else:
                covered.append([a, b])
        s_all, run_all = [], []
        for k, (a, b) in enumerate(covered):
            m = max(1, int(math.ceil((b - a) / step - 1e-9)))
            s_all.append(np.linspace(a, b, m + 1))
            run_all.append(np.full(m + 1, k))
        s = np.concatenate(s_all)
        run = np.concatenate(run_all)
        # the covering segment closest to the gun at each s (largest height along v)
        sc = np.clip(s[:, None], s_seg[None, :, 0], s_seg[None, :, 1])
        inside = np.abs(sc - s[:, None]) <= 10 * eps
        f = (sc - s_seg[None, :, 0]) / (s_seg[None, :, 1] - s_seg[None, :, 0])
        pts = P[None, :, 0] + f[..., None] * (P[None, :, 1] - P[None, :, 0])
        height = np.where(inside, pts @ v, -np.inf)
        best = np.argmax(height, axis=1)
        rows = np.arange(len(s))
        points = pts[rows, best]
        fb = f[rows, best][:, None]
        nrm = _unit(Nn[best, 0] + fb * (Nn[best, 1] - Nn[best, 0]))
        flip = nrm @ v < 0
        nrm[flip] = -nrm[flip]
        passes.append(SurfacePass(float(h), s, points, nrm, np.array(covered), run))
    if not passes:
        raise ValueError(f"{part.name}: no cutting plane meets the faces to paint")
    return passes


# ----------------------------------------------------------------------------- stages 4-6
@dataclass(frozen=True, eq=False)
class PoseRun:
    """Gun poses in the part frame with their spray flags (a piece of the final path).

    ``positions`` (N, 3), ``rotations`` (N, 3, 3) (columns: tool x, y, z in the part frame),
    ``spray`` (N,) bool; ``joins`` (N, 3), optional: at the samples where the path is straight
    with a fixed orientation to second order (the ends of the U turns, approach and retract),
    the unit direction of travel, NaN elsewhere (:func:`smooth_geometry` splits the path there).
    """

    positions: np.ndarray
    rotations: np.ndarray
    spray: np.ndarray
    joins: np.ndarray | None = None


def _frames(z, x, spin: float) -> np.ndarray:
    """Rotations (N, 3, 3) with tool z = ``z``, tool x = ``x`` made orthogonal to z, then both
    turned by ``spin`` (rad) about z."""
    z = _unit(z)
    x = _unit(x - np.sum(x * z, axis=1, keepdims=True) * z)
    y = np.cross(z, x)
    cs, sn = math.cos(spin), math.sin(spin)
    x, y = cs * x + sn * y, -sn * x + cs * y
    return np.stack([x, y, z], axis=2)


def pass_poses(sp: SurfacePass, *, standoff: float, forward: bool, direction=(1.0, 0.0, 0.0),
               view=(0.0, 0.0, 1.0), spin: float = 0.0) -> list[PoseRun]:
    """Gun poses over each stretch of a pass (spray on), in travel order.

    Tip at ``standoff`` along the smoothed normal; tool +z = -normal; tool x along the travel
    (``+direction`` when ``forward``, else ``-direction``, along the cut: ``c x normal``),
    turned by ``spin`` (rad) about the gun axis.
    """
    d, c, v = _axes(direction, view)
    sign = 1.0 if forward else -1.0
    runs = []
    for k in range(len(sp.covered)):
        sel = np.flatnonzero(sp.run == k)
        if not forward:
            sel = sel[::-1]
        nrm = sp.normals[sel]
        travel = sign * np.cross(np.broadcast_to(c, nrm.shape), nrm)
        R = _frames(-nrm, travel, spin)
        runs.append(PoseRun(sp.points[sel] + standoff * nrm, R, np.ones(len(sel), dtype=bool)))
    return runs if forward else runs[::-1]


def _travel(R: np.ndarray, spin: float) -> np.ndarray:
    """Travel direction (the unspun tool x) of rotations ``R`` (..., 3, 3)."""
    cs, sn = math.cos(spin), math.sin(spin)
    return cs * R[..., :, 0] - sn * R[..., :, 1]


def _straight(p0, R0, length: float, step: float, spin: float, backwards: bool = False):
    """Poses along a straight line of ``length`` from (p0, R0) along its travel direction
    (against it when ``backwards``), constant orientation; first sample p0 (excluded: p0 is
    the caller's)."""
    m = max(1, int(math.ceil(length / step - 1e-9)))
    f = np.linspace(0.0, length, m + 1)[1:]
    t = _travel(R0, spin) * (-1.0 if backwards else 1.0)
    return p0 + f[:, None] * t, np.broadcast_to(R0, (m, 3, 3)).copy()


#: Samples at the end of a pass over which its direction, curvature and turn rate are estimated.
_END_FIT = 7


def _end_rates(positions, rotations, spin: float):
    """At the last sample of a run of poses: unit tangent ``t``, curvature vector ``k``
    (``d2p/ds2``) and body turn rate ``w`` (``dR/ds = R [w]x``, rad per length), from a
    quadratic least-squares fit over the last :data:`_END_FIT` samples in arc length. A run of
    fewer than three samples: the tool's travel direction, no curvature, no turn."""
    from scipy.spatial.transform import Rotation

    P, R = positions[-_END_FIT:], rotations[-_END_FIT:]
    if len(P) < 3:
        t = _travel(R[-1], spin)
        if len(P) == 2 and np.linalg.norm(P[1] - P[0]) > 0:
            t = _unit(P[1] - P[0])
        return t, np.zeros(3), np.zeros(3)
    seg = np.linalg.norm(np.diff(P, axis=0), axis=1)
    sa = np.concatenate([[0.0], np.cumsum(seg)])
    sa = sa - sa[-1]  # <= 0, 0 at the end
    A = np.column_stack([sa, 0.5 * sa ** 2])
    cp, *_ = np.linalg.lstsq(A, P - P[-1], rcond=None)
    rv = Rotation.from_matrix(np.einsum("ji,njk->nik", R[-1], R)).as_rotvec()
    cr, *_ = np.linalg.lstsq(A, rv, rcond=None)
    t = _unit(cp[0])
    k = cp[1] - (cp[1] @ t) * t  # curvature is normal to the tangent
    return t, k, cr[0]


def _ease_out(p0, R0, t, k, w, length: float, step: float):
    """Poses along ``length`` of arc from (p0, R0), leaving along ``t`` with curvature ``k``
    and body turn rate ``w`` that fade as ``(1 - s/length)^2``: at the far end the path is
    straight and the orientation fixed, with the first derivatives of both zero (a U turn joins
    there smoothly); first sample p0 excluded. A pass on a curved surface thus runs on without
    a jump of its curvature or of the gun's turn rate where the part ends."""
    from scipy.spatial.transform import Rotation

    m = max(1, int(math.ceil(length / step - 1e-9)))
    s = np.linspace(0.0, length, m + 1)[1:, None]
    L = length
    B = L / 3.0 * (1.0 - (1.0 - s / L) ** 3)  # integral of (1 - s/L)^2
    C = L / 3.0 * (s - L / 4.0 * (1.0 - (1.0 - s / L) ** 4))  # integral of B
    pos = p0 + s * t + C * k
    rot = R0 @ Rotation.from_rotvec(B * w).as_matrix().reshape(-1, 3, 3)
    return pos, rot, _unit(t + B[-1] * k)


def _extension(run: PoseRun, length: float, step: float, spin: float, *, at_start: bool):
    """``length`` of overspray past the last sample of ``run`` (past the first, ``at_start``,
    returned in travel order): see :func:`_ease_out`. Returns positions, rotations and the
    direction of travel at the far end."""
    P, R = (run.positions[::-1], run.rotations[::-1]) if at_start else (run.positions, run.rotations)
    t, k, w = _end_rates(P, R, spin)
    if at_start and len(P) < 3:  # the tool's travel direction, reversed
        t = -t if len(P) < 2 or np.linalg.norm(P[1] - P[0]) == 0 else t
    p, r, t_end = _ease_out(P[-1], R[-1], t, k, w, length, step)
    return (p[::-1], r[::-1], -t_end) if at_start else (p, r, t_end)


def _bridge(p0, R0, p1, R1, step: float, *, min_inner: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Poses strictly between (p0, R0) and (p1, R1): linear positions, slerped rotations, at
    most ``step`` apart, at least ``min_inner`` of them."""
    from scipy.spatial.transform import Rotation, Slerp

    L = float(np.linalg.norm(p1 - p0))
    m = max(min_inner + 1, int(math.ceil(L / step - 1e-9)))
    f = np.linspace(0.0, 1.0, m + 1)[1:-1]
    slerp = Slerp([0.0, 1.0], Rotation.from_matrix(np.stack([R0, R1])))
    return p0 + f[:, None] * (p1 - p0), slerp(f).as_matrix().reshape(-1, 3, 3)


def extend_pass(runs: list[PoseRun], *, overspray: float, step: float, spin: float = 0.0) -> PoseRun:
    """One pass from its stretches: ``overspray`` before the first and after the last (spray
    on), gaps of at most ``2 overspray`` crossed spray on, wider ones extended by ``overspray``
    on each side and crossed spray off in between.

    An extension leaves the part along the pass with the pass's curvature and turn rate fading
    to zero (:func:`_ease_out`; on a flat part: a straight line at a fixed orientation), so the
    gun reaches the end of the overspray moving straight at a fixed orientation; the pass's
    ``joins`` give the direction of travel at both ends."""
    if not (math.isfinite(overspray) and overspray >= 0):
        raise ValueError(f"overspray must be a length >= 0; got {overspray!r}")
    P, R, S = [], [], []

    def add(p, r, on):
        P.append(np.asarray(p).reshape(-1, 3))
        R.append(np.asarray(r).reshape(-1, 3, 3))
        S.append(np.full(len(P[-1]), bool(on)))

    first, last = runs[0], runs[-1]
    t_first, _, _ = _end_rates(first.positions[::-1], first.rotations[::-1], spin)
    t_first = -t_first if len(first.positions) >= 2 else _travel(first.rotations[0], spin)
    t_last, _, _ = _end_rates(last.positions, last.rotations, spin)
    if overspray > 0:
        p, r, t_first = _extension(first, overspray, step, spin, at_start=True)
        add(p, r, True)
    for k, run in enumerate(runs):
        add(run.positions, run.rotations, True)
        if k + 1 < len(runs):
            nxt = runs[k + 1]
            gap = float(np.linalg.norm(nxt.positions[0] - run.positions[-1]))
            if gap <= 2 * overspray:
                add(*_bridge(run.positions[-1], run.rotations[-1], nxt.positions[0], nxt.rotations[0],
                             step, min_inner=0), True)
            else:
                none = (np.empty((0, 3)), np.empty((0, 3, 3)))
                pa, ra = (_extension(run, overspray, step, spin, at_start=False)[:2]
                          if overspray > 0 else none)
                pb, rb = (_extension(nxt, overspray, step, spin, at_start=True)[:2]
                          if overspray > 0 else none)
                add(pa, ra, True)
                ea = (pa[-1], ra[-1]) if len(pa) else (run.positions[-1], run.rotations[-1])
                sb = (pb[0], rb[0]) if len(pb) else (nxt.positions[0], nxt.rotations[0])
                add(*_bridge(*ea, *sb, step), False)
                add(pb, rb, True)
    if overspray > 0:
        p, r, t_last = _extension(last, overspray, step, spin, at_start=False)
        add(p, r, True)
    pos = np.concatenate(P)
    joins = np.full(pos.shape, np.nan)
    joins[0], joins[-1] = t_first, t_last
    return PoseRun(pos, np.concatenate(R), np.concatenate(S), joins)


def _septic(t):
    """The septic Hermite basis on [0, 1] for end values and tangents, zero second and third
    derivatives at both ends: ``(h0, h1, h2, h3)`` and their derivatives."""
    def tangent(t):  # t - 20 t^4 + 45 t^5 - 36 t^6 + 10 t^7: slope 1 at 0, flat to third order at 1
        return t - 20 * t ** 4 + 45 * t ** 5 - 36 * t ** 6 + 10 * t ** 7, \
            1 - 80 * t ** 3 + 225 * t ** 4 - 216 * t ** 5 + 70 * t ** 6

    step = 35 * t ** 4 - 84 * t ** 5 + 70 * t ** 6 - 20 * t ** 7
    dstep = 140 * t ** 3 - 420 * t ** 4 + 420 * t ** 5 - 140 * t ** 6
    h1, d1 = tangent(t)
    g, dg = tangent(1.0 - t)
    return (1 - step, h1, step, -g), (-dstep, d1, dstep, dg)


def _turn(p0, R0, p1, R1, step: float, spin: float, t0=None, t1=None) -> tuple[np.ndarray, np.ndarray]:
    """Interior poses of a U turn from (p0, R0) to (p1, R1): a septic Hermite curve leaving along
    the first travel direction ``t0`` and arriving along the second ``t1`` (default the tools'
    travel directions) with zero curvature and zero rate of curvature at both ends (tangent
    length twice the gap), so the tool's turn about its axis starts and ends at rest with no
    jump of its angular acceleration; gun axis blended with the same septic step (at rest to
    third order at both ends); tool x along the curve (see below)."""
    gap = float(np.linalg.norm(p1 - p0))
    L = 2.0 * gap
    t0 = _travel(R0, spin) if t0 is None else t0
    t1 = _travel(R1, spin) if t1 is None else t1
    m0, m1 = L * t0, L * t1
    length = 2.0 * gap + 1e-12  # about the curve's length
    m = max(4, int(math.ceil(length / step - 1e-9)))
    t = np.linspace(0.0, 1.0, m + 1)[1:-1, None]
    (h0, h1, h2, h3), (d0, d1, d2, d3) = _septic(t)
    pos = h0 * p0 + h1 * m0 + h2 * p1 + h3 * m1
    tangent = _unit(d0 * p0 + d1 * m0 + d2 * p1 + d3 * m1)
    z = (1 - h2) * R0[:, 2] + h2 * R1[:, 2]
    # tool x along the curve, plus the ends' own offsets from it faded with the same step (on a
    # curved part the tool's x, normal to the cut, is not exactly the tip's direction of travel)
    x = tangent + (1 - h2) * (_travel(R0, spin) - t0) + h2 * (_travel(R1, spin) - t1)
    return pos, _frames(z, x, spin)


def link_passes(passes: list[PoseRun], *, step: float, approach: float, spin: float = 0.0) -> PoseRun:
    """Join the passes: a U turn between consecutive passes (spray off), a straight approach of
    ``approach`` before the first and a retract after the last (spray off). The ends of the
    turns, approach and retract are ``joins`` (see :class:`PoseRun`)."""
    if not (math.isfinite(approach) and approach >= 0):
        raise ValueError(f"approach must be a length >= 0; got {approach!r}")
    P, R, S, J = [], [], [], []

    def add(p, r, on, joins=None):
        if len(p):
            P.append(np.asarray(p).reshape(-1, 3))
            R.append(np.asarray(r).reshape(-1, 3, 3))
            S.append(np.full(len(P[-1]), bool(on)) if np.ndim(on) == 0 else np.asarray(on, dtype=bool))
            J.append(np.full((len(P[-1]), 3), np.nan) if joins is None else np.asarray(joins, dtype=float))

    def ends(ps):
        j = np.full((len(ps.positions), 3), np.nan) if ps.joins is None else ps.joins
        t0 = j[0] if np.all(np.isfinite(j[0])) else _travel(ps.rotations[0], spin)
        t1 = j[-1] if np.all(np.isfinite(j[-1])) else _travel(ps.rotations[-1], spin)
        return j, t0, t1

    a = passes[0]
    _, ta, _ = ends(a)
    if approach > 0:
        p = a.positions[0] - np.linspace(0.0, approach, max(1, int(math.ceil(approach / step - 1e-9))) + 1)[
            1:, None] * ta
        jn = np.full((len(p), 3), np.nan)
        jn[-1] = ta
        add(p[::-1], np.broadcast_to(a.rotations[0], (len(p), 3, 3)), False, jn[::-1])
    for k, ps in enumerate(passes):
        j, _, t_out = ends(ps)
        j = j.copy()
        j[0], j[-1] = ends(ps)[1], t_out
        if k == 0 and approach > 0:
            j[0] = np.nan  # the approach runs on straight: no join at the pass's start
        if k == len(passes) - 1 and approach > 0:
            j[-1] = np.nan
        add(ps.positions, ps.rotations, ps.spray, j)
        if k + 1 < len(passes):
            nxt = passes[k + 1]
            add(*_turn(ps.positions[-1], ps.rotations[-1], nxt.positions[0], nxt.rotations[0], step, spin,
                       t_out, ends(nxt)[1]), False)
    z = passes[-1]
    if approach > 0:
        _, _, tz = ends(z)
        p = z.positions[-1] + np.linspace(0.0, approach, max(1, int(math.ceil(approach / step - 1e-9))) + 1)[
            1:, None] * tz
        jn = np.full((len(p), 3), np.nan)
        jn[-1] = tz
        add(p, np.broadcast_to(z.rotations[-1], (len(p), 3, 3)), False, jn)
    return PoseRun(np.concatenate(P), np.concatenate(R), np.concatenate(S), np.concatenate(J))


def _dedupe(run: PoseRun, tol: float) -> PoseRun:
    """Drop samples coinciding with the previous one (their spray flags are or-ed, a join kept)."""
    d = np.linalg.norm(np.diff(run.positions, axis=0), axis=1)
    ang = np.linalg.norm(run.rotations[1:] - run.rotations[:-1], axis=(1, 2))
    dup = np.flatnonzero((d <= tol) & (ang <= 1e-9))
    spray = run.spray.copy()
    spray[dup] |= spray[dup + 1]
    joins = None
    if run.joins is not None:
        joins = run.joins.copy()
        take = dup[~np.all(np.isfinite(joins[dup]), axis=1)]
        joins[take] = joins[take + 1]
    keep = np.ones(len(spray), dtype=bool)
    keep[dup + 1] = False
    return PoseRun(run.positions[keep], run.rotations[keep], spray[keep],
                   None if joins is None else joins[keep])


def surface_raster(part: Part, *, spacing: float, standoff: float, overspray: float, approach: float,
                   direction=(1.0, 0.0, 0.0), view=(0.0, 0.0, 1.0), spin: float = 0.0,
                   step: float = DEFAULT_STEP, smoothing: float | None = None,
                   rotation_radius: float = 100.0) -> Path:
    """A plane-slicing raster over ``part`` (stages 1-6 of the module docstring), in the base frame.

    Parameters
    ----------
    part : Part
    spacing, standoff, overspray, approach : float
        Distance between passes (> 0), gun tip to surface along the normal, overrun past the
        part's edges, approach/retract length (>= 0), in the part's unit.
    direction, view : (3,) float
        Pass direction and the side the gun sprays from, in the part frame.
    spin : float
        Tool x turned by this angle (rad) about the gun axis from the direction of travel.
    step : float
        Largest distance between samples along the surface.
    smoothing : float, optional
        Normal smoothing radius (default twice the median edge length).
    rotation_radius : float
        Length per radian of orientation change in the path parameter (see
        :func:`~ik7r.painting.path_from_poses`).
    """
    for name, val in (("standoff", standoff), ("approach", approach)):
        if not (math.isfinite(val) and val >= 0):
            raise ValueError(f"{name} must be a length >= 0; got {val!r}")
    faces = target_faces(part, view)
    normals = smoothed_normals(part, faces, smoothing)
    cuts = slice_surface(part, faces, normals, spacing=spacing, direction=direction, view=view, step=step)
    passes = [extend_pass(pass_poses(sp, standoff=standoff, forward=k % 2 == 0, direction=direction,
                                     view=view, spin=spin), overspray=overspray, step=step, spin=spin)
              for k, sp in enumerate(cuts)]
    run = _dedupe(link_passes(passes, step=step, approach=approach, spin=spin),
                  1e-9 * max(1.0, float(np.ptp(part.vertices, axis=0).max())))
    T = part.T_base_part
    pos = run.positions @ T[:3, :3].T + T[:3, 3]
    rot = np.einsum("ij,njk->nik", T[:3, :3], run.rotations)
    from ..geometry.rotations import transform
    from .paths import path_from_poses

    base = path_from_poses(transform(rot, pos), rotation_radius=rotation_radius)
    name = (f"{part.name}: {len(cuts)} passes {spacing:g} {part.unit} apart, standoff {standoff:g}, "
            f"overspray {overspray:g}, spin {math.degrees(spin):g} deg")
    joins = None if run.joins is None else run.joins @ T[:3, :3].T
    geometry = smooth_geometry(base.u, base.positions, base.rotations, joins)
    return Path(base.positions, base.rotations, base.u, geometry, name, run.spray)


def _piece(u, positions, rotations, t_start, t_end):
    """Quintic splines of the positions and of the rotation vectors about the middle sample
    through one piece's samples; at an end with a direction of travel ``t`` (not NaN) the
    first derivative of the position is ``t``, the second zero and the orientation at rest to
    second order (so a straight stretch at a fixed orientation is reproduced exactly), at
    the others the third and fourth derivatives are zero."""
    from scipy.interpolate import make_interp_spline
    from scipy.spatial.transform import Rotation

    R_ref = rotations[len(rotations) // 2]
    rv = Rotation.from_matrix(np.einsum("ji,njk->nik", R_ref, rotations)).as_rotvec()
    zero = np.zeros(3)

    def bc(t):
        if t is not None and np.all(np.isfinite(t)):
            return [(1, t), (2, zero)], [(1, zero), (2, zero)]
        return [(3, zero), (4, zero)], [(3, zero), (4, zero)]

    (pa, ra), (pb, rb) = bc(t_start), bc(t_end)
    if len(u) < 3 and (pa[0][0] != 1 or pb[0][0] != 1):  # too few samples for free ends: linear
        pos = make_interp_spline(u, positions, k=1, axis=0)
        rot = make_interp_spline(u, rv, k=1, axis=0)
    else:
        pos = make_interp_spline(u, positions, k=5, bc_type=(pa, pb), axis=0)
        rot = make_interp_spline(u, rv, k=5, bc_type=(ra, rb), axis=0)
    return pos, rot, R_ref


def smooth_geometry(u, positions, rotations, joins=None):
    """``u (M,) -> (positions (M, 3), rotations (M, 3, 3))`` through the samples, so that the
    joints can follow the path between samples without corners (linear pieces would turn by a
    finite angle at every sample of a curve).

    The path is split at its ``joins`` (``(N, 3)``: the unit direction of travel where the
    path is straight at a fixed orientation, NaN elsewhere; default none): each piece is a
    quintic spline of the positions and of the rotation vectors (about the piece's middle
    sample), which at the joins moves along the direction given, with no curvature and no
    turn to second order. A straight pass at a fixed orientation is thus reproduced exactly,
    and what happens in a U turn does not ring into the passes (one spline through the whole
    path would spread a turn's curvature over the passes next to it, decaying by a constant
    factor per sample). Without joins: one cubic spline of the positions and scipy's rotation
    spline.
    """
    from scipy.interpolate import CubicSpline
    from scipy.spatial.transform import Rotation, RotationSpline

    u = np.asarray(u, dtype=float)
    positions = np.asarray(positions, dtype=float)
    rotations = np.asarray(rotations, dtype=float)
    if joins is None:
        pos = CubicSpline(u, positions, axis=0)
        rs = RotationSpline(u, Rotation.from_matrix(rotations))

        def geometry(x):
            x = np.atleast_1d(np.asarray(x, dtype=float))
            return pos(x), rs(x).as_matrix().reshape(-1, 3, 3)

        return geometry
    joins = np.asarray(joins, dtype=float)
    at = np.flatnonzero(np.all(np.isfinite(joins), axis=1))
    cuts = np.unique(np.concatenate([[0], at[(at > 0) & (at < len(u) - 1)], [len(u) - 1]]))
    pieces = []
    for i0, i1 in zip(cuts[:-1], cuts[1:]):
        sl = slice(i0, i1 + 1)
        pieces.append(_piece(u[sl], positions[sl], rotations[sl], joins[i0], joins[i1]))
    bounds = u[cuts]

    def geometry(x):
        x = np.atleast_1d(np.asarray(x, dtype=float))
        k = np.clip(np.searchsorted(bounds, x, side="right") - 1, 0, len(pieces) - 1)
        P = np.empty((len(x), 3))
        R = np.empty((len(x), 3, 3))
        for j in np.unique(k):
            m = k == j
            pos, rot, R_ref = pieces[j]
            P[m] = pos(x[m])
            R[m] = R_ref @ Rotation.from_rotvec(rot(x[m])).as_matrix().reshape(-1, 3, 3)
        return P, R

    return geometry


def sprayed_length(path: Path) -> float:
    """Length of the path's positions over the sprayed segments (length unit)."""
    seg = np.linalg.norm(np.diff(path.positions, axis=0), axis=1)
    return float(seg[path.spray[:-1] & path.spray[1:]].sum())
