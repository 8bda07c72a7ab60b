"""Film thickness: the growth rate of a gun integrated over a timed trajectory, per mesh vertex.

``T(s) = integral over the sprayed time of q_s(s; gun pose at t) dt`` (um), with ``q_s`` the
projection formula of :mod:`ik7r.painting.spray`, nothing where the part hides ``s`` from the
gun tip (a depth buffer of the part seen from the tip, per pose) or faces away.

The input is generic (:class:`GunPoses`): instants ``t``, the gun pose ``T_part_tool`` at each,
and whether each interval between instants is sprayed. :func:`gun_poses` makes it from a timed
:class:`~ik7r.painting.Trajectory` (forward kinematics of the interpolated joints) and its path
(the spray flags); :func:`poses_from_samples` from any poses.

**Time-step rule** (:func:`film_step`, :func:`gun_poses`). The integral is a trapezoidal sum
over the instants. Between consecutive instants the spray pattern may move at most ``h`` on
the surface, measured at the pattern's centre at the reference standoff (``tip + h0 z``) and,
for a fan (double-beta), at its ends ``reach`` away along tool x and y. ``h`` is the largest
of ``width / 2, width / 4, ...`` (width = sigma, radius or min(a, b)) for which the same sum
over one straight stroke reproduces the closed-form stroke profile within
:data:`STEP_ACCURACY` (0.2 %) of its peak at every distance from the stroke and every phase of
the samples -- checked numerically for the gun at hand, so the 0.5 % of peak the film
promises holds with margin for the overlap of strokes. Gaussian guns pass at ``sigma / 2``
(the sum's error is ``2 exp(-2 pi^2 sigma^2 / h^2)``, 1e-17 there); beta patterns with small
exponents (edges like a square root) need finer steps, found by the same check. Instants also
fall exactly on every spray switch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..geometry.rotations import invert
from .spray import Gun, plane_rate, stroke_profile

__all__ = ["GunPoses", "poses_from_samples", "gun_poses", "film_step", "film_thickness", "part_film",
           "FilmStats", "film_stats", "ripple", "gaussian_ripple", "STEP_ACCURACY", "DEFAULT_RESOLUTION"]

#: Largest error of the time sum over one straight stroke, relative to the stroke's peak.
STEP_ACCURACY = 2e-3
#: Pixels per side of the per-pose depth buffer (occlusion).
DEFAULT_RESOLUTION = 256


@dataclass(frozen=True, eq=False)
class GunPoses:
    """Gun poses over time, the input of the film integration.

    Attributes
    ----------
    t : ndarray, shape (M,)
        Instants (s), increasing.
    T_part_tool : ndarray, shape (M, 4, 4)
        The gun (tool) pose in the part frame at each instant.
    sprayed : ndarray, shape (M - 1,), bool
        Whether the gun is on between instants ``i`` and ``i + 1``.
    """

    t: np.ndarray
    T_part_tool: np.ndarray
    sprayed: np.ndarray

    @property
    def weights(self) -> np.ndarray:
        """Trapezoidal time weights ``(M,)`` (s): half of each adjacent sprayed interval."""
        dt = np.diff(self.t) * self.sprayed
        w = np.zeros(len(self.t))
        w[:-1] += 0.5 * dt
        w[1:] += 0.5 * dt
        return w

    @property
    def spray_time(self) -> float:
        """Total time the gun is on (s)."""
        return float(np.sum(np.diff(self.t) * self.sprayed))


def poses_from_samples(t, T_part_tool, sprayed=None) -> GunPoses:
    """:class:`GunPoses` from instants ``t`` (M,), poses (M, 4, 4) and interval flags (M-1,)
    (default all on), validated."""
    t = np.asarray(t, dtype=float)
    T = np.asarray(T_part_tool, dtype=float)
    if t.ndim != 1 or len(t) < 2 or T.shape != (len(t), 4, 4):
        raise ValueError(f"need t (M,) with M >= 2 and T_part_tool (M, 4, 4); got {t.shape} and {T.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(T))) or np.any(np.diff(t) <= 0):
        raise ValueError("t must be finite and increasing, the poses finite")
    s = np.ones(len(t) - 1, dtype=bool) if sprayed is None else np.asarray(sprayed, dtype=bool)
    if s.shape != (len(t) - 1,):
        raise ValueError(f"sprayed must have shape ({len(t) - 1},); got {s.shape}")
    return GunPoses(t, T, s)


def film_step(gun: Gun, accuracy: float = STEP_ACCURACY) -> float:
    """The largest footprint move ``h`` between instants (gun's unit) for which the trapezoidal
    time sum over a straight stroke is within ``accuracy`` of the stroke's peak (module
    docstring); ``width / 256`` at the finest."""
    rng = np.random.default_rng(0)
    y = np.linspace(0.0, gun.reach, 121)
    ref = stroke_profile(gun, y, 1.0)
    peak = float(ref.max())
    # along the travel (tool x) the pattern reaches b for a fan, the reach otherwise
    along = gun.params["b"] if gun.model == "double-beta" else gun.reach
    h = gun.width / 2.0
    while h > gun.width / 256.0:
        worst = 0.0
        for phase in rng.uniform(0.0, 1.0, 6):
            x = np.arange(-along - h, along + 2 * h, h) + phase * h
            s = plane_rate(gun, x[None, :], y[:, None]).sum(axis=1) * h
            worst = max(worst, float(np.abs(s - ref).max()) / peak)
        if worst <= accuracy:
            return h
        h /= 2.0
    return h


def _u_of_t(trajectory, t: np.ndarray) -> np.ndarray:
    """Path parameter at times ``t``: linear between the trajectory's rows."""
    return np.interp(t, trajectory.t, trajectory.u)


def _t_of_u(trajectory, u: np.ndarray) -> np.ndarray:
    return np.interp(u, trajectory.u, trajectory.t)


def gun_poses(robot, trajectory, path, T_base_part, gun: Gun, *, step: float | None = None) -> GunPoses:
    """Gun poses in the part frame along a timed trajectory, at the step rule's instants.

    The pose at an instant is the forward kinematics of the trajectory's interpolated joints
    (``trajectory.evaluate``) in the part frame; the spray state is the path's at the
    trajectory's path parameter. ``step`` (robot unit): the footprint move per instant
    (default :func:`film_step`).
    """
    g = gun.in_unit(robot.unit)
    h = film_step(g) if step is None else float(step)
    if not (math.isfinite(h) and h > 0):
        raise ValueError(f"step must be a positive length; got {step!r}")
    T_part_base = invert(T_base_part) @ invert(robot.base)
    # instants: the trajectory's rows and every spray switch
    sw = np.flatnonzero(np.diff(path.spray.astype(int)) != 0)
    switch_u = np.unique(np.concatenate([path.u[sw], path.u[sw + 1]]))
    t0 = np.unique(np.concatenate([trajectory.t, _t_of_u(trajectory, switch_u)]))

    def poses(t):
        return T_part_base @ robot.fk(trajectory.evaluate(t)[0])

    T0 = poses(t0)
    c0 = T0[:, :3, 3] + g.standoff * T0[:, :3, 2]
    move = np.linalg.norm(np.diff(c0, axis=0), axis=1)
    if g.model == "double-beta":
        for k in (0, 1):
            ck = c0 + g.reach * T0[:, :3, k]
            move = np.maximum(move, np.linalg.norm(np.diff(ck, axis=0), axis=1))
    # between consecutive spray switches, instants at equal footprint moves of at most h
    s_cum = np.concatenate([[0.0], np.cumsum(move)])
    cuts = np.unique(np.concatenate([[t0[0], t0[-1]], _t_of_u(trajectory, switch_u)]))
    pieces = []
    for ta, tb in zip(cuts[:-1], cuts[1:]):
        sa, sb = np.interp([ta, tb], t0, s_cum)
        on = bool(path.sprayed(np.clip(_u_of_t(trajectory, np.array([0.5 * (ta + tb)])), 0.0, path.u[-1]))[0])
        n = max(1, int(math.ceil((sb - sa) / h - 1e-9))) if on else 1
        # monotone in s; where the footprint does not move, spread evenly in time instead
        ts = np.interp(np.linspace(sa, sb, n + 1), s_cum, t0) if sb > sa else np.linspace(ta, tb, n + 1)
        ts[0], ts[-1] = ta, tb
        pieces.append(ts[:-1])
    t = np.unique(np.concatenate(pieces + [t0[-1:]]))
    T = poses(t)
    mid = 0.5 * (t[1:] + t[:-1])
    sprayed = path.sprayed(np.clip(_u_of_t(trajectory, mid), 0.0, path.u[-1]))
    return GunPoses(t, T, sprayed)


def film_thickness(vertices, normals, faces, poses: GunPoses, gun: Gun, *, occlusion: bool = True,
                   resolution: int = DEFAULT_RESOLUTION) -> np.ndarray:
    """Film thickness (um) at points ``vertices`` (V, 3) with unit ``normals`` (V, 3) (part
    frame, the gun's length unit), occluded by the triangles ``faces`` (F, 3) of ``vertices``.

    ``occlusion=False`` skips the depth buffer (every point facing the gun gets paint).
    """
    from .._kernels import film_kernel

    V = np.ascontiguousarray(vertices, dtype=float)
    N = np.ascontiguousarray(normals, dtype=float)
    F = np.ascontiguousarray(faces, dtype=np.int64)
    if V.ndim != 2 or V.shape[1] != 3 or N.shape != V.shape:
        raise ValueError(f"vertices and normals must have the same shape (V, 3); got {V.shape}, {N.shape}")
    if F.ndim != 2 or F.shape[1] != 3 or (F.size and (F.min() < 0 or F.max() >= len(V))):
        raise ValueError(f"faces must be (F, 3) indices of the vertices; got shape {F.shape}")
    if not (isinstance(resolution, (int, np.integer)) and 8 <= resolution <= 4096):
        raise ValueError(f"resolution must be an integer in [8, 4096]; got {resolution!r}")
    T_tool_part = np.ascontiguousarray(invert(poses.T_part_tool))
    w = np.ascontiguousarray(poses.weights)
    cone = gun.reach / gun.standoff * (1.0 + 1e-9)
    res = int(resolution)
    out = np.zeros(len(V))
    film_kernel(V, N, F, T_tool_part, w, gun.kernel_params(), cone, bool(occlusion), res,
                np.empty(res * res), np.empty((len(V), 3)), np.empty(len(V), dtype=np.int8), out)
    return out


def part_film(part, poses: GunPoses, gun: Gun, **options) -> np.ndarray:
    """:func:`film_thickness` at the vertices of a :class:`~ik7r.painting.parts.Part` (its
    area-weighted vertex normals; the gun converted to the part's unit)."""
    return film_thickness(part.vertices, part.vertex_normals, part.faces, poses, gun.in_unit(part.unit),
                          **options)


# ----------------------------------------------------------------------------- statistics
@dataclass(frozen=True)
class FilmStats:
    """Film statistics over the painted area (area-weighted over its vertices).

    ``mean``, ``std``, ``minimum``, ``maximum`` (um); ``uniformity`` = std / mean; ``area``
    (unit^2) of the painted faces; ``volume`` (um * unit^2) of film on them; ``within`` the
    share of the painted area within ``target +- tolerance`` (None without a target).
    """

    mean: float
    std: float
    minimum: float
    maximum: float
    uniformity: float
    area: float
    volume: float
    target: float | None = None
    tolerance: float | None = None
    within: float | None = None

    def lines(self, unit: str) -> list[str]:
        out = [f"film over the painted area ({self.area:.6g} {unit}^2): mean {self.mean:.2f} um, "
               f"std/mean {100 * self.uniformity:.1f} %, min {self.minimum:.2f} um, "
               f"max {self.maximum:.2f} um"]
        if self.target is not None and self.tolerance is not None and self.within is not None:
            out.append(f"within {self.target:g} +- {self.tolerance:g} um: {100 * self.within:.1f} % "
                       f"of the area")
        return out


def film_stats(part, thickness, faces=None, *, target: float | None = None,
               tolerance: float | None = None) -> FilmStats:
    """:class:`FilmStats` of ``thickness`` (V,) over the ``faces`` (mask, default all)."""
    T = np.asarray(thickness, dtype=float)
    mask = np.ones(len(part.faces), dtype=bool) if faces is None else np.asarray(faces, dtype=bool)
    A = part.vertex_areas(mask)
    total = float(A.sum())
    if not total > 0:
        raise ValueError("no painted area")
    mean = float(np.sum(A * T) / total)
    std = float(math.sqrt(max(np.sum(A * (T - mean) ** 2) / total, 0.0)))
    used = A > 0
    within = None
    if target is not None:
        tol = 0.1 * target if tolerance is None else float(tolerance)
        within = float(np.sum(A[np.abs(T - target) <= tol]) / total)
        tolerance = tol
    return FilmStats(mean, std, float(T[used].min()), float(T[used].max()),
                     std / mean if mean > 0 else math.inf,
                     total, float(np.sum(A * T)), target, tolerance, within)


# ----------------------------------------------------------------------------- planning
def gaussian_ripple(sigma: float, spacing: float) -> float:
    """The approximate ripple (relative amplitude) of Gaussian strokes ``spacing`` apart,
    ``2 exp(-2 pi^2 sigma^2 / spacing^2)`` (the first Fourier term)."""
    return 2.0 * math.exp(-2.0 * math.pi ** 2 * sigma ** 2 / spacing ** 2)


def ripple(gun: Gun, spacing: float) -> float:
    """Ripple of the film of infinitely many parallel strokes ``spacing`` apart (same unit as
    the gun) on a plane at the reference standoff: its relative amplitude ``(max - min) / (2
    mean)`` over one period of the sum of the closed-form stroke profiles (for a Gaussian gun
    about :func:`gaussian_ripple`)."""
    if not (math.isfinite(spacing) and spacing > 0):
        raise ValueError(f"spacing must be a positive length; got {spacing!r}")
    y = np.linspace(0.0, spacing, 201)
    k = np.arange(-int(math.ceil(gun.reach / spacing)) - 2, int(math.ceil(gun.reach / spacing)) + 3)
    total = stroke_profile(gun, y[:, None] - k[None, :] * spacing, 1.0).sum(axis=1)
    return float((total.max() - total.min()) / (2.0 * total.mean()))
