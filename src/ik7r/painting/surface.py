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
    """Unit vertex normals ``(V, 3)`` of the ``faces`` (mask; default all), averaged with
    Gaussian weights (sigma = radius / 2) over the vertices within ``radius`` (default twice
    the median edge length). Vertices of no selected face get 0."""
    from scipy.sparse import csr_matrix
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
    if radius > 0 and len(used) > 1:
        tree = cKDTree(part.vertices[used])
        D = tree.sparse_distance_matrix(tree, radius, output_type="coo_matrix")
        w = np.exp(-2.0 * (D.data / radius) ** 2)
        W = csr_matrix((w, (D.row, D.col)), shape=(len(used), len(used))).tolil()
        W.setdiag(1.0)  # each vertex itself (distance 0 may not be stored)
        W = W.tocsr()
        acc[used] = W @ _unit(acc[used])
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
        covered = []
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
    ``spray`` (N,) bool.
    """

    positions: np.ndarray
    rotations: np.ndarray
    spray: np.ndarray


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


def _bridge(p0, R0, p1, R1, step: float, *, min_inner: int = 1):
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
    on each side and crossed spray off in between."""
    if not (math.isfinite(overspray) and overspray >= 0):
        raise ValueError(f"overspray must be a length >= 0; got {overspray!r}")
    P, R, S = [], [], []

    def add(p, r, on):
        P.append(np.asarray(p).reshape(-1, 3))
        R.append(np.asarray(r).reshape(-1, 3, 3))
        S.append(np.full(len(P[-1]), bool(on)))

    first = runs[0]
    if overspray > 0:
        p, r = _straight(first.positions[0], first.rotations[0], overspray, step, spin, backwards=True)
        add(p[::-1], r[::-1], True)
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
                pa, ra = (_straight(run.positions[-1], run.rotations[-1], overspray, step, spin)
                          if overspray > 0 else none)
                pb, rb = (_straight(nxt.positions[0], nxt.rotations[0], overspray, step, spin, backwards=True)
                          if overspray > 0 else none)
                add(pa, ra, True)
                ea = (pa[-1], ra[-1]) if len(pa) else (run.positions[-1], run.rotations[-1])
                sb = (pb[-1], rb[-1]) if len(pb) else (nxt.positions[0], nxt.rotations[0])
                add(*_bridge(*ea, *sb, step), False)
                add(pb[::-1], rb[::-1], True)
    last = runs[-1]
    if overspray > 0:
        add(*_straight(last.positions[-1], last.rotations[-1], overspray, step, spin), True)
    return PoseRun(np.concatenate(P), np.concatenate(R), np.concatenate(S))


def _turn(p0, R0, p1, R1, step: float, spin: float):
    """Interior poses of a U turn from (p0, R0) to (p1, R1): a quintic Hermite curve leaving along
    the first travel direction and arriving along the second with zero curvature at both ends
    (tangent length twice the gap: the loop reaches half the gap past the ends), so the tool's
    turn about its axis starts and ends at rest; gun axis blended with a smootherstep, tool x
    along the curve."""
    gap = float(np.linalg.norm(p1 - p0))
    L = 2.0 * gap
    m0, m1 = L * _travel(R0, spin), L * _travel(R1, spin)
    length = 1.6 * gap + 1e-12  # about the curve's length (a half circle is pi/2 gap)
    m = max(4, int(math.ceil(length / step - 1e-9)))
    t = np.linspace(0.0, 1.0, m + 1)[1:-1, None]
    t2, t3, t4, t5 = t ** 2, t ** 3, t ** 4, t ** 5
    h0, h1 = 1 - 10 * t3 + 15 * t4 - 6 * t5, t - 6 * t3 + 8 * t4 - 3 * t5
    h2, h3 = 10 * t3 - 15 * t4 + 6 * t5, -4 * t3 + 7 * t4 - 3 * t5
    pos = h0 * p0 + h1 * m0 + h2 * p1 + h3 * m1
    d0, d1 = -30 * t2 + 60 * t3 - 30 * t4, 1 - 18 * t2 + 32 * t3 - 15 * t4
    d2, d3 = 30 * t2 - 60 * t3 + 30 * t4, -12 * t2 + 28 * t3 - 15 * t4
    tangent = d0 * p0 + d1 * m0 + d2 * p1 + d3 * m1
    w = h2  # smootherstep 10t^3 - 15t^4 + 6t^5: the axis turns from rest to rest
    z = (1 - w) * R0[:, 2] + w * R1[:, 2]
    return pos, _frames(z, tangent, spin)


def link_passes(passes: list[PoseRun], *, step: float, approach: float, spin: float = 0.0) -> PoseRun:
    """Join the passes: a U turn between consecutive passes (spray off), a straight approach of
    ``approach`` before the first and a retract after the last (spray off)."""
    if not (math.isfinite(approach) and approach >= 0):
        raise ValueError(f"approach must be a length >= 0; got {approach!r}")
    P, R, S = [], [], []

    def add(p, r, on):
        if len(p):
            P.append(np.asarray(p).reshape(-1, 3))
            R.append(np.asarray(r).reshape(-1, 3, 3))
            S.append(np.full(len(P[-1]), bool(on)) if np.ndim(on) == 0 else np.asarray(on, dtype=bool))

    a = passes[0]
    if approach > 0:
        p, r = _straight(a.positions[0], a.rotations[0], approach, step, spin, backwards=True)
        add(p[::-1], r[::-1], False)
    for k, ps in enumerate(passes):
        add(ps.positions, ps.rotations, ps.spray)
        if k + 1 < len(passes):
            nxt = passes[k + 1]
            add(*_turn(ps.positions[-1], ps.rotations[-1], nxt.positions[0], nxt.rotations[0], step, spin),
                False)
    z = passes[-1]
    if approach > 0:
        add(*_straight(z.positions[-1], z.rotations[-1], approach, step, spin), False)
    return PoseRun(np.concatenate(P), np.concatenate(R), np.concatenate(S))


def _dedupe(run: PoseRun, tol: float) -> PoseRun:
    """Drop samples coinciding with the previous one (their spray flags are or-ed)."""
    d = np.linalg.norm(np.diff(run.positions, axis=0), axis=1)
    ang = np.linalg.norm(run.rotations[1:] - run.rotations[:-1], axis=(1, 2))
    dup = np.flatnonzero((d <= tol) & (ang <= 1e-9))
    spray = run.spray.copy()
    spray[dup] |= spray[dup + 1]
    keep = np.ones(len(spray), dtype=bool)
    keep[dup + 1] = False
    return PoseRun(run.positions[keep], run.rotations[keep], spray[keep])


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
    geometry = smooth_geometry(base.u, base.positions, base.rotations)
    return Path(base.positions, base.rotations, base.u, geometry, name, run.spray)


def smooth_geometry(u, positions, rotations):
    """``u (M,) -> (positions (M, 3), rotations (M, 3, 3))`` through the samples: a cubic spline of
    the positions and a rotation spline (scipy's, continuous angular acceleration), so that the
    joints can follow the path between samples without corners (linear pieces would turn by a
    finite angle at every sample of a curve)."""
    from scipy.interpolate import CubicSpline
    from scipy.spatial.transform import Rotation, RotationSpline

    u = np.asarray(u, dtype=float)
    pos = CubicSpline(u, np.asarray(positions, dtype=float), axis=0)
    rot = RotationSpline(u, Rotation.from_matrix(np.asarray(rotations, dtype=float)))

    def geometry(x):
        x = np.atleast_1d(np.asarray(x, dtype=float))
        return pos(x), rot(x).as_matrix().reshape(-1, 3, 3)

    return geometry


def sprayed_length(path: Path) -> float:
    """Length of the path's positions over the sprayed segments (length unit)."""
    seg = np.linalg.norm(np.diff(path.positions, axis=0), axis=1)
    return float(seg[path.spray[:-1] & path.spray[1:]].sum())
