"""Joint-space interpolation of a solved path: the joint path, its timing, the dense limit check.

A timed trajectory is the composition ``q(t) = Q(u(t))`` of

1. **the joint path** ``Q(u)`` (:class:`JointPath`): one spline per joint in the path parameter
   ``u`` through the IK samples, quintic by default (cubic on request), split into pieces at
   the path's stops (sharp corners: there ``Q`` is only continuous and the robot is at rest).
   Between samples the joints are interpolated, not solved: the tool leaves the path a little.
   The deviation depends on ``u`` only, not on the timing; it is checked at seven points in
   every interval (and at every output row), and where it exceeds ``tolerance`` the interval
   gets a new IK sample at its middle, solved on the same branch;
2. **a timing** ``u(t)``: :class:`Timing` (constant speed with smooth ramps, rest to rest
   between stops, over a given duration) or :class:`ProfileTiming` (a speed profile on a grid
   of ``u`` with constant path acceleration per grid interval: the time-optimal profile of
   :mod:`ik7r.painting.topp`).

So ``dq = Q'(u) udot`` and ``ddq = Q''(u) udot^2 + Q'(u) uddot`` exactly, and a uniform time
scaling by ``k`` divides speeds by ``k`` and accelerations by ``k^2`` exactly.
:func:`dense_peaks` finds the peak joint speeds and accelerations over every interval of the
joint path and of the timing (both sides of every breakpoint, eight points inside every
interval, then a bounded search around the largest), and the output rows include the peak
instants, so the CSV and the figures show the peaks the report states.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:
    from .._typing import ArrayLike
    from ..robot.model import Robot
    from .events import PathEvent

import math
from dataclasses import dataclass, field

import numpy as np

from ..geometry.rotations import invert
from ..limits import check_work, limit, rows_estimate
from ..units import METRES_PER_UNIT, unit_scale
from .trajectory import DEFAULT_MAX_STEP, PathSolution, track

__all__ = ["Timing", "ProfileTiming", "JointPath", "Trajectory", "interpolate", "dense_peaks",
           "default_tolerance", "DEFAULT_RAMP", "DEFAULT_RATE"]

#: Default duration of each speed ramp (s) of :class:`Timing`.
DEFAULT_RAMP = 1.0
#: Default rate of the output rows (Hz).
DEFAULT_RATE = 100.0
#: Default deviation tolerance, in mm (converted to the robot's length unit).
DEFAULT_TOLERANCE_MM = 0.01
#: Smallest deviation tolerance accepted, in mm: 0.1 um, a hundred times below the default and far
#: below any robot's repeatability. Each factor of 64 below the default doubles the joint samples
#: of a quintic fit (its error falls as the sixth power of the spacing), all solved by IK, so a
#: tolerance such as 1e-13 mm would ask for minutes of work that no robot can use.
MIN_TOLERANCE_MM = 1e-4
_CHECK_FRACTIONS = np.arange(1, 8) / 8.0


def default_tolerance(unit: str) -> float:
    """0.01 mm in ``unit`` (``mm``, ``cm``, ``m`` or ``in``)."""
    if unit not in METRES_PER_UNIT:
        raise ValueError(f"unknown length unit {unit!r}; give tolerance= explicitly "
                         f"(known units: {sorted(METRES_PER_UNIT)})")
    return DEFAULT_TOLERANCE_MM * unit_scale("mm", unit)


def mm_in(unit: str) -> float:
    """One millimetre in ``unit``."""
    return default_tolerance(unit) / DEFAULT_TOLERANCE_MM


# ----------------------------------------------------------------------------- timings
def _ramp_u(x):
    """Distance covered in a ramp, per ``V tau``, after a fraction ``x`` of it."""
    return x ** 3 - 0.5 * x ** 4


def _ramp_x(r):
    """Inverse of :func:`_ramp_u` on [0, 1] (r in [0, 1/2]), by bisection then Newton."""
    lo, hi = np.zeros_like(r), np.ones_like(r)
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        low = _ramp_u(mid) < r
        lo = np.where(low, mid, lo)
        hi = np.where(low, hi, mid)
    x = 0.5 * (lo + hi)
    for _ in range(3):
        d = 3 * x ** 2 - 2 * x ** 3
        x = np.where(d > 1e-300, x - (_ramp_u(x) - r) / np.where(d > 1e-300, d, 1.0), x)
    return np.clip(x, 0.0, 1.0)


@dataclass(frozen=True)
class Timing:
    """Rest-to-rest timing of the path parameter over ``duration``: ``u(t)``.

    Between consecutive stops (``0``, the interior ``stops``, ``length``) the path runs rest to
    rest: constant speed ``speed`` (the same for every piece) between two ramps in which the
    speed goes smoothly (``3x^2 - 2x^3``) from and to zero, so the path acceleration is
    continuous and zero at the stops. Each ramp lasts ``ramp`` seconds, or less on a piece too
    short for it. Without stops: ``speed = length / (duration - ramp)``.
    """

    length: float
    duration: float
    ramp: float
    stops: tuple = ()
    # derived in __post_init__: per piece (bounds, L, tau, D, t0, V), and the cruise speed
    _pieces: tuple = field(init=False, repr=False, compare=False)
    _speed: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("length", "duration", "ramp"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a positive number; got {v!r}")
        if self.ramp > 0.5 * self.duration + 1e-12:
            raise ValueError(f"ramp ({self.ramp} s) must be at most half the duration ({self.duration} s)")
        st = tuple(float(s) for s in self.stops)
        if any(not 0 < s < self.length for s in st) or any(b <= a for a, b in zip(st, st[1:])):
            raise ValueError(f"stops must increase strictly inside (0, {self.length}); got {st}")
        object.__setattr__(self, "stops", st)
        bounds = np.array((0.0,) + st + (self.length,))
        L = np.diff(bounds)
        if st:
            # common cruise speed V: duration = sum(L_k / V + min(ramp, L_k / V))
            def total(V):
                return float(np.sum(L / V + np.minimum(self.ramp, L / V)))

            lo, hi = 1e-300, 1.0
            while total(hi) > self.duration:
                hi *= 2.0
            lo = hi / 2.0
            while total(lo) < self.duration:
                lo /= 2.0
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if total(mid) > self.duration else (lo, mid)
            V = 0.5 * (lo + hi)
            tau = np.minimum(self.ramp, L / V)
            D = L / V + tau
            D *= self.duration / D.sum()
        else:
            V = self.length / (self.duration - self.ramp)
            tau, D = np.array([self.ramp]), np.array([self.duration])
        object.__setattr__(self, "_pieces", (bounds, L, tau, D, np.concatenate([[0.0], np.cumsum(D)]),
                                              L / (D - tau)))
        object.__setattr__(self, "_speed", float(V))

    @property
    def speed(self) -> float:
        """Path speed between the ramps (length unit per s)."""
        return self._speed

    def breakpoints(self) -> np.ndarray:
        """Times where the path acceleration may change its formula (stops, ramp ends)."""
        bounds, L, tau, D, t0, V = self._pieces
        return np.unique(np.concatenate([t0, t0[:-1] + tau, t0[1:] - tau]))

    def _piece_t(self, t):
        bounds, L, tau, D, t0, V = self._pieces
        k = np.clip(np.searchsorted(t0, t, side="right") - 1, 0, len(L) - 1)
        return k, t - t0[k], bounds[k], L[k], tau[k], D[k], V[k]

    def derivatives(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``u``, ``udot``, ``uddot`` at times ``t`` (clipped to [0, duration])."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        k, tl, u0, L, tau, D, V = self._piece_t(t)
        xs = np.clip(tl / tau, 0.0, 1.0)
        xe = np.clip((D - tl) / tau, 0.0, 1.0)
        start, end = tl < tau, tl > D - tau
        u = np.where(start, V * tau * _ramp_u(xs),
                     np.where(end, L - V * tau * _ramp_u(xe), 0.5 * V * tau + V * (tl - tau)))
        ud = np.where(start, V * (3 * xs ** 2 - 2 * xs ** 3),
                      np.where(end, V * (3 * xe ** 2 - 2 * xe ** 3), V))
        udd = np.where(start, V * (6 * xs - 6 * xs ** 2) / tau,
                       np.where(end, -V * (6 * xe - 6 * xe ** 2) / tau, 0.0))
        return u0 + np.minimum(u, L), ud, udd

    def u_of_t(self, t: ArrayLike) -> np.ndarray:
        """Path parameter at times ``t`` (clipped to [0, duration])."""
        return self.derivatives(t)[0]

    def t_of_u(self, u: ArrayLike) -> np.ndarray:
        """Times at path parameters ``u`` (clipped to [0, length])."""
        bounds, L, tau, D, t0, V = self._pieces
        u = np.clip(np.asarray(u, dtype=float), 0.0, self.length)
        k = np.clip(np.searchsorted(bounds, u, side="right") - 1, 0, len(L) - 1)
        ul = u - bounds[k]
        Vk, tk, Lk, Dk = V[k], tau[k], L[k], D[k]
        u1 = 0.5 * Vk * tk
        start = tk * _ramp_x(np.clip(ul / (Vk * tk), 0.0, 0.5))
        mid = tk + (ul - u1) / Vk
        end = Dk - tk * _ramp_x(np.clip((Lk - ul) / (Vk * tk), 0.0, 0.5))
        return t0[k] + np.where(ul < u1, start, np.where(ul > Lk - u1, end, mid))

    def scaled(self, k: float) -> Timing:
        """The same motion ``k`` times slower."""
        return Timing(self.length, self.duration * k, self.ramp * k, self.stops)


@dataclass(frozen=True, eq=False)
class ProfileTiming:
    """A speed profile on a grid of the path parameter: ``x = udot^2`` at ``grid`` (N + 1,),
    constant path acceleration in every grid interval (so ``x`` is linear in ``u`` there).
    The time-optimal timing of :func:`ik7r.painting.topp.topp` has this form."""

    grid: np.ndarray
    x: np.ndarray
    #: derived in __post_init__: the time at every grid point, the path acceleration per interval
    times: np.ndarray = field(init=False, repr=False)
    accel: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        from .topp import profile_times

        s = np.array(self.grid, dtype=float)
        x = np.maximum(np.array(self.x, dtype=float), 0.0)
        if s.ndim != 1 or x.shape != s.shape or len(s) < 2 or np.any(np.diff(s) <= 0):
            raise ValueError("grid must increase strictly and x must have its shape")
        t = profile_times(s, x)
        a = np.diff(x) / (2.0 * np.diff(s))
        for arr in (s, x, t, a):
            arr.setflags(write=False)
        object.__setattr__(self, "grid", s)
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "accel", a)

    @property
    def length(self) -> float:
        return float(self.grid[-1] - self.grid[0])

    @property
    def duration(self) -> float:
        return float(self.times[-1])

    @property
    def speed(self) -> float:
        """The highest path speed (length unit per s)."""
        return float(np.sqrt(self.x.max()))

    def breakpoints(self) -> np.ndarray:
        return self.times

    def derivatives(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        i = np.clip(np.searchsorted(self.times, t, side="right") - 1, 0, len(self.accel) - 1)
        tau = t - self.times[i]
        v0 = np.sqrt(self.x[i])
        a = self.accel[i]
        u = np.minimum(self.grid[i] + v0 * tau + 0.5 * a * tau ** 2, self.grid[i + 1])
        ud = np.maximum(v0 + a * tau, 0.0)
        return u, ud, a

    def u_of_t(self, t) -> np.ndarray:
        return self.derivatives(t)[0]

    def t_of_u(self, u) -> np.ndarray:
        u = np.clip(np.asarray(u, dtype=float), self.grid[0], self.grid[-1])
        i = np.clip(np.searchsorted(self.grid, u, side="right") - 1, 0, len(self.accel) - 1)
        du = u - self.grid[i]
        v0 = np.sqrt(self.x[i])
        v1 = np.sqrt(np.maximum(self.x[i] + 2.0 * self.accel[i] * du, 0.0))
        den = v0 + v1
        return self.times[i] + np.where(den > 0, 2.0 * du / np.where(den > 0, den, 1.0), 0.0)

    def scaled(self, k: float) -> ProfileTiming:
        return ProfileTiming(self.grid, self.x / k ** 2)


# ----------------------------------------------------------------------------- the joint path
def _fit(u, q, kind: str):
    from scipy.interpolate import make_interp_spline

    n = len(u)
    k = 5 if kind == "quintic" else 3
    k = min(k, n - 1 if (n - 1) % 2 == 1 else n - 2)
    return make_interp_spline(u, q, k=max(k, 1), axis=0)


@dataclass(frozen=True, eq=False)
class JointPath:
    """``Q(u)``: the joints (rad) as splines of the path parameter through IK samples.

    Attributes
    ----------
    knot_u : ndarray, shape (K,)
    knot_q : ndarray, shape (K, 6)
        The IK samples.
    stops : tuple of float
        Path parameters where the spline is split (sharp corners; ``Q`` is continuous there).
    kind : str
        ``"quintic"`` or ``"cubic"``.
    """

    knot_u: np.ndarray
    knot_q: np.ndarray
    stops: tuple
    kind: str
    # derived in __post_init__: the pieces' bounds, splines and their derivatives
    _bounds: np.ndarray = field(init=False, repr=False)
    _pieces: list = field(init=False, repr=False)
    _derivs: list = field(init=False, repr=False)

    def __post_init__(self) -> None:
        bounds = np.concatenate([[self.knot_u[0]], self.stops, [self.knot_u[-1]]])
        idx = np.searchsorted(self.knot_u, bounds)
        if not np.allclose(self.knot_u[idx], bounds, rtol=0, atol=1e-9 * max(1.0, self.knot_u[-1])):
            raise ValueError("every stop must be an IK sample")
        pieces = [_fit(self.knot_u[a:b + 1], self.knot_q[a:b + 1], self.kind)
                  for a, b in zip(idx[:-1], idx[1:])]
        object.__setattr__(self, "_bounds", bounds)
        object.__setattr__(self, "_pieces", pieces)
        object.__setattr__(self, "_derivs", [[p.derivative(n) if n else p for n in range(min(3, p.k + 1))]
                                             for p in pieces])

    def evaluate(self, u, order: int = 0, side: Literal["left", "right"] = "right") -> np.ndarray:
        """``Q``, ``Q'`` or ``Q''`` (order 0, 1, 2) at ``u`` (M,) -> (M, 6); at a stop the piece
        on ``side``."""
        u = np.atleast_1d(np.asarray(u, dtype=float))
        k = np.searchsorted(self._bounds, u, side=side) - 1
        k = np.clip(k, 0, len(self._pieces) - 1)
        out = np.empty((len(u), self.knot_q.shape[1]))
        for j in np.unique(k):
            m = k == j
            d = self._derivs[j]
            out[m] = d[order](u[m]) if order < len(d) else 0.0
        return out


def _deviation(robot, path, jp: JointPath, u):
    """Position (length unit) and angle (rad) deviations of the interpolated tool at ``u``."""
    T = invert(robot.base) @ robot.fk(jp.evaluate(u))
    P, R = path.at(u)
    dp = np.linalg.norm(T[:, :3, 3] - P, axis=1)
    c = (np.einsum("nij,nij->n", T[:, :3, :3], R) - 1.0) / 2.0
    return dp, np.arccos(np.clip(c, -1.0, 1.0))


def _interior(k: np.ndarray) -> np.ndarray:
    """Check points inside every interval of ``k`` (flat)."""
    return (k[:-1, None] + _CHECK_FRACTIONS[None, :] * np.diff(k)[:, None]).reshape(-1)


def _enough_knots(robot, path, ku, kq, stops, need, max_step):
    """Add IK samples (bisecting the longest intervals, on the same branch) to every piece between
    stops that has fewer than ``need`` samples, so that each gets a spline of full degree."""
    bounds = np.concatenate([[ku[0]], stops, [ku[-1]]])
    for _ in range(need):
        idx = np.searchsorted(ku, bounds)
        short = [(a, b) for a, b in zip(idx[:-1], idx[1:]) if b - a + 1 < need]
        if not short:
            break
        new_u, new_q = [], []
        for a, b in short:
            i = a + int(np.argmax(np.diff(ku[a:b + 1])))
            um = 0.5 * (ku[i] + ku[i + 1])
            qm, _ = track(robot, path, kq[i], ku[i], um, max_step=max_step)
            if qm is None:
                return ku, kq
            new_u.append(um)
            new_q.append(qm)
        ku = np.concatenate([ku, new_u])
        kq = np.concatenate([kq, np.array(new_q)])
        order = np.argsort(ku, kind="stable")
        ku, kq = ku[order], kq[order]
    return ku, kq


def fit_joint_path(robot, path, ku, kq, stops, kind, tol, *, extra_u=None, max_rounds: int = 10,
                   max_step: float = DEFAULT_MAX_STEP) -> JointPath:
    """Fit :class:`JointPath` and add IK samples at the middle of intervals where the tool
    leaves the path by more than ``tol`` (at the check points and at ``extra_u``)."""
    ku, kq = _enough_knots(robot, path, np.asarray(ku, dtype=float), np.asarray(kq, dtype=float), stops,
                           6 if kind == "quintic" else 4, max_step)
    stuck: set[float] = set()
    jp = JointPath(ku, kq, tuple(stops), kind)
    for rnd in range(max_rounds + 1):
        uc = _interior(ku) if extra_u is None else np.concatenate([_interior(ku), extra_u])
        dev, _ = _deviation(robot, path, jp, uc)
        bad = np.zeros(len(ku) - 1, dtype=bool)
        bad[np.clip(np.searchsorted(ku, uc[dev > tol], side="right") - 1, 0, len(ku) - 2)] = True
        if stuck:
            bad &= ~np.isin(ku[:-1], list(stuck))
        if not np.any(bad) or rnd == max_rounds:
            break
        new_u, new_q = [], []
        for i in np.flatnonzero(bad):
            um = 0.5 * (ku[i] + ku[i + 1])
            qm = None
            if ku[i] < um < ku[i + 1]:
                qm, _ = track(robot, path, kq[i], ku[i], um, max_step=max_step)
            if qm is None:
                stuck.add(float(ku[i]))
                continue
            new_u.append(um)
            new_q.append(qm)
        if not new_u:
            break
        ku = np.concatenate([ku, new_u])
        kq = np.concatenate([kq, np.array(new_q)])
        order = np.argsort(ku, kind="stable")
        ku, kq = ku[order], kq[order]
        jp = JointPath(ku, kq, tuple(stops), kind)
    return jp


# ----------------------------------------------------------------------------- evaluation, peaks
def joint_motion(jp: JointPath, timing, t) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``u``, ``q``, ``dq``, ``ddq`` at times ``t`` of ``q(t) = Q(u(t))``."""
    u, ud, udd = timing.derivatives(np.atleast_1d(np.asarray(t, dtype=float)))
    d0, d1, d2 = (jp.evaluate(u, n) for n in range(3))
    return u, d0, d1 * ud[:, None], d2 * (ud ** 2)[:, None] + d1 * np.broadcast_to(udd, ud.shape)[:, None]


def _check_times(jp: JointPath, timing, per: int = 8) -> tuple[np.ndarray, np.ndarray]:
    D = timing.duration
    T = np.unique(np.clip(np.concatenate([timing.breakpoints(), timing.t_of_u(jp.knot_u), [0.0, D]]), 0.0, D))
    eps = 1e-9 * max(1.0, D)
    inner = (T[:-1, None] + (np.arange(1, per) / per)[None, :] * np.diff(T)[:, None]).reshape(-1)
    return np.unique(np.clip(np.concatenate([T, T - eps, T + eps, inner]), 0.0, D)), T


def dense_peaks(jp: JointPath, timing, per: int = 8):
    """Peak ``|dq|`` and ``|ddq|`` per joint over the whole trajectory.

    Evaluated at every breakpoint of the timing and every IK sample's time (both sides),
    ``per - 1`` points inside every interval between them, then refined by a bounded search
    in the interval of each joint's largest value.

    Returns
    -------
    v_peak, v_time, a_peak, a_time : ndarray, shape (6,) each
    """
    from scipy.optimize import minimize_scalar

    tc, T = _check_times(jp, timing, per)
    _, _, dq, ddq = joint_motion(jp, timing, tc)
    out = []
    for which, vals in ((2, np.abs(dq)), (3, np.abs(ddq))):
        peak, when = vals.max(axis=0), tc[vals.argmax(axis=0)]
        for j in range(vals.shape[1]):
            k = int(np.clip(np.searchsorted(T, when[j], side="right") - 1, 0, len(T) - 2))
            a, b = T[k], T[k + 1]
            w = (b - a) / per
            lo, hi = max(a, when[j] - w), min(b, when[j] + w)
            if hi - lo <= 1e-12:
                continue

            def f(t, j=j, which=which):
                return -abs(joint_motion(jp, timing, [t])[which][0, j])

            r = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-9 * max(1.0, b)})
            if -r.fun > peak[j]:
                peak[j], when[j] = -r.fun, r.x
        out += [peak, when]
    return tuple(out)


def output_times(duration: float, rate: float, extra=()) -> np.ndarray:
    """Rows every ``1 / rate`` s from 0, ``duration`` last, and the ``extra`` instants (at most
    ``ik7r.limits.MAX_TRAJECTORY_ROWS``, estimated before allocating)."""
    check_work(f"trajectory rows ({duration:.6g} s at {rate:g} Hz)", rows_estimate(duration, rate),
               limit("MAX_TRAJECTORY_ROWS"), "--max-rows, or fewer rows with --rate")
    n = int(math.floor(duration * rate + 1e-9)) + 1
    t = np.arange(n) / rate
    if duration - t[-1] > 1e-9:
        t = np.append(t, duration)
    else:
        t[-1] = duration
    extra = np.asarray(extra, dtype=float)
    if extra.size:
        extra = extra[np.min(np.abs(extra[:, None] - t[None, :]), axis=1) > 1e-9]
        t = np.unique(np.concatenate([t, extra]))
    return t


# ----------------------------------------------------------------------------- the result
@dataclass(frozen=True, eq=False)
class Trajectory:
    """A timed joint trajectory along a path, sampled at a fixed rate plus the peak instants.

    Attributes
    ----------
    t : ndarray, shape (M,)
        Times (s), from 0 to ``duration``: every ``1 / rate`` s, and the instants of every
        joint's peak speed and acceleration.
    q, dq, ddq : ndarray, shape (M, 6)
        Joints ``[q1, q2, q3, q4, q5, q7]`` (rad), their velocities (rad/s) and accelerations
        (rad/s^2). ``q6 = robot.coupling[0] * q5 + robot.coupling[1]``.
    positions : ndarray, shape (M, 3)
        The path point (tool position in the base frame, robot length unit) at each time.
    u : ndarray, shape (M,)
        Path parameter at each time.
    duration : float
        s (after any rescaling).
    timing : Timing or ProfileTiming
        ``u(t)``.
    knot_t, knot_u : ndarray, shape (K,)
        Times and path parameters of the IK samples (the path's samples plus those added).
    knot_q : ndarray, shape (K, 6)
        The IK samples (rad).
    max_deviation : float
        Largest distance (length unit) of the tool from the path point at the same ``u``, over
        the check points and the rows.
    max_angle_deviation : float
        Largest angle (rad) between the tool's orientation and the path's, over the same points.
    tolerance : float
        The deviation tolerance (length unit).
    speed_ratio, acceleration_ratio : ndarray, shape (6,)
        Peak ``|dq|`` / velocity limit and peak ``|ddq|`` / acceleration limit per joint, from the
        dense check (NaN when the robot has no such limits).
    kind : str
        ``"quintic"`` or ``"cubic"``.
    joint_path : JointPath
    speed_peak, speed_peak_t, acceleration_peak, acceleration_peak_t : ndarray, shape (6,)
        The dense check's peaks (rad/s, rad/s^2) and their times (s); each is a row of ``t``.
    spray : ndarray of bool, shape (M,)
        Gun on at each row.
    gun_speed : ndarray, shape (M,)
        Speed of the tool (length unit per s) at each row, from forward kinematics of the joints.
    commanded_speed : float or None
        The commanded gun speed on spray-on stretches (None: timed by duration).
    stops : tuple of float
        Path parameters where the robot stops (corners).
    ramps : ndarray, shape (R, 2)
        ``u`` ranges of spray-on stretches below the commanded speed at a stretch's ends.
    """

    t: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    ddq: np.ndarray
    positions: np.ndarray
    u: np.ndarray
    duration: float
    timing: Timing | ProfileTiming
    knot_t: np.ndarray
    knot_u: np.ndarray
    knot_q: np.ndarray
    max_deviation: float
    max_angle_deviation: float
    tolerance: float
    speed_ratio: np.ndarray
    acceleration_ratio: np.ndarray
    kind: str
    joint_path: JointPath = field(repr=False)
    speed_peak: np.ndarray = field(repr=False)
    speed_peak_t: np.ndarray = field(repr=False)
    acceleration_peak: np.ndarray = field(repr=False)
    acceleration_peak_t: np.ndarray = field(repr=False)
    spray: np.ndarray = field(repr=False)
    gun_speed: np.ndarray = field(repr=False)
    commanded_speed: float | None = None
    stops: tuple = ()
    ramps: np.ndarray = field(repr=False, default_factory=lambda: np.zeros((0, 2)))

    def evaluate(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Joints, velocities and accelerations ``(M, 6)`` each at times ``t`` (M,) (s)."""
        t = np.clip(np.atleast_1d(np.asarray(t, dtype=float)), 0.0, self.duration)
        _, q, dq, ddq = joint_motion(self.joint_path, self.timing, t)
        return q, dq, ddq


def interpolate(robot: Robot, solution: PathSolution, duration: float = 20.0, *, ramp: float = DEFAULT_RAMP,
                kind: str = "quintic", tolerance: float | None = None, rate: float = DEFAULT_RATE,
                rescale: bool = False, max_rounds: int = 10, max_step: float = DEFAULT_MAX_STEP,
                corner_angle: float | None = None) -> tuple[Trajectory, list[PathEvent]]:
    """A trajectory through the IK samples of ``solution`` over ``duration`` (constant speed,
    ramps, stops at sharp corners): :func:`ik7r.painting.time_path` with ``duration``.

    ``rescale=True`` stretches the time uniformly until the dense check finds every joint
    within its speed and acceleration limits (a :class:`TimeScaled` event); otherwise any
    excess is reported (:class:`SpeedLimit`, :class:`AccelerationLimit`).

    Returns
    -------
    trajectory : Trajectory
    events : list of PathEvent
    """
    from .timing import time_path

    return time_path(robot, solution, duration=duration, ramp=ramp, kind=kind, tolerance=tolerance, rate=rate,
                     rescale=rescale, max_rounds=max_rounds, max_step=max_step, corner_angle=corner_angle)
