"""Joint-space interpolation of a solved path: timing, spline, limits, Cartesian deviation.

1. **Timing.** The path parameter ``u`` (arc length) is run rest to rest over the duration:
   constant speed, with smooth ramps of ``ramp`` seconds at both ends (the speed follows
   ``3x^2 - 2x^3``, so the path acceleration is continuous and zero at both ends).
2. **Spline.** One spline per joint through the IK samples at their times: quintic by default
   (continuous accelerations and jerks; zero velocity and acceleration at both ends), or cubic
   (zero velocity at both ends).
3. **Deviation.** Between samples the joints are interpolated, not solved: the tool leaves the
   path a little. The deviation (position of the tool at time ``t`` from the path point at
   ``t``) is checked at three points in every interval and at every output row; where it
   exceeds ``tolerance`` the interval gets a new IK sample at its middle (solved on the same
   branch), and the spline is fitted again, for up to ``max_rounds`` rounds.
4. **Limits.** Joint speeds and accelerations are checked against the robot's limits at the
   check points, the samples and the output rows; the time is stretched uniformly
   (``rescale=True``: speeds scale by ``1/k``, accelerations by ``1/k^2``) or the excess is
   reported.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .._typing import ArrayLike
    from ..robot.model import Robot
    from .events import PathEvent

import math
from dataclasses import dataclass, field

import numpy as np

from ..geometry.rotations import invert
from ..units import METRES_PER_UNIT, unit_scale
from .events import (
    AccelerationLimit,
    DeviationExceeded,
    JointLimit,
    PathNotFeasible,
    SpeedLimit,
    TimeScaled,
)
from .trajectory import DEFAULT_MAX_STEP, PathSolution, track

__all__ = ["Timing", "Trajectory", "interpolate", "default_tolerance", "DEFAULT_RAMP", "DEFAULT_RATE"]

#: Default duration of each speed ramp (s).
DEFAULT_RAMP = 1.0
#: Default rate of the output rows (Hz).
DEFAULT_RATE = 100.0
#: Default deviation tolerance, in mm (converted to the robot's length unit).
DEFAULT_TOLERANCE_MM = 0.01
_CHECK_FRACTIONS = np.arange(1, 8) / 8.0


def default_tolerance(unit: str) -> float:
    """0.01 mm in ``unit`` (``mm``, ``cm``, ``m`` or ``in``)."""
    if unit not in METRES_PER_UNIT:
        raise ValueError(f"unknown length unit {unit!r}; give tolerance= explicitly "
                         f"(known units: {sorted(METRES_PER_UNIT)})")
    return DEFAULT_TOLERANCE_MM * unit_scale("mm", unit)


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
    """Rest-to-rest timing of the path parameter: ``u(t)`` for ``t`` in ``[0, duration]``.

    Constant speed ``speed = length / (duration - ramp)`` between two ramps of ``ramp``
    seconds in which the speed goes smoothly (``3x^2 - 2x^3``) from and to zero.
    """

    length: float
    duration: float
    ramp: float

    def __post_init__(self) -> None:
        for name in ("length", "duration", "ramp"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a positive number; got {v!r}")
        if self.ramp > 0.5 * self.duration + 1e-12:
            raise ValueError(f"ramp ({self.ramp} s) must be at most half the duration ({self.duration} s)")

    @property
    def speed(self) -> float:
        """Path speed between the ramps (length unit per s)."""
        return self.length / (self.duration - self.ramp)

    def u_of_t(self, t: ArrayLike) -> np.ndarray:
        """Path parameter at times ``t`` (clipped to [0, duration])."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        V, tau, D = self.speed, self.ramp, self.duration
        start = V * tau * _ramp_u(t / tau)
        mid = 0.5 * V * tau + V * (t - tau)
        end = self.length - V * tau * _ramp_u((D - t) / tau)
        return np.where(t < tau, start, np.where(t > D - tau, end, mid))

    def t_of_u(self, u: ArrayLike) -> np.ndarray:
        """Times at path parameters ``u`` (clipped to [0, length])."""
        u = np.clip(np.asarray(u, dtype=float), 0.0, self.length)
        V, tau, D = self.speed, self.ramp, self.duration
        u1 = 0.5 * V * tau
        start = tau * _ramp_x(np.clip(u / (V * tau), 0.0, 0.5))
        mid = tau + (u - u1) / V
        end = D - tau * _ramp_x(np.clip((self.length - u) / (V * tau), 0.0, 0.5))
        return np.where(u < u1, start, np.where(u > self.length - u1, end, mid))

    def scaled(self, k: float) -> Timing:
        """The same motion ``k`` times slower."""
        return Timing(self.length, self.duration * k, self.ramp * k)


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A timed joint trajectory along a path, sampled at a fixed rate.

    Attributes
    ----------
    t : ndarray, shape (M,)
        Times (s), from 0 to ``duration``.
    q, dq, ddq : ndarray, shape (M, 6)
        Joints ``[q1, q2, q3, q4, q5, q7]`` (rad), their velocities (rad/s) and accelerations
        (rad/s^2). ``q6 = robot.coupling[0] * q5 + robot.coupling[1]``.
    positions : ndarray, shape (M, 3)
        The path point (tool position in the base frame, robot length unit) at each time.
    u : ndarray, shape (M,)
        Path parameter at each time.
    duration : float
        s (after any rescaling).
    timing : Timing
    knot_t, knot_u : ndarray, shape (K,)
        Times and path parameters of the IK samples the spline passes through (the path's
        samples plus those added by densification).
    knot_q : ndarray, shape (K, 6)
        The IK samples (rad).
    max_deviation : float
        Largest distance (length unit) of the tool from the path point at the same time, over
        the check points and the rows.
    max_angle_deviation : float
        Largest angle (rad) between the tool's orientation and the path's, over the same points.
    tolerance : float
        The deviation tolerance (length unit).
    speed_ratio, acceleration_ratio : ndarray, shape (6,)
        Peak ``|dq|`` / velocity limit and peak ``|ddq|`` / acceleration limit per joint (NaN when the
        robot has no such limits).
    kind : str
        ``"quintic"`` or ``"cubic"``.
    """

    t: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    ddq: np.ndarray
    positions: np.ndarray
    u: np.ndarray
    duration: float
    timing: Timing
    knot_t: np.ndarray
    knot_u: np.ndarray
    knot_q: np.ndarray
    max_deviation: float
    max_angle_deviation: float
    tolerance: float
    speed_ratio: np.ndarray
    acceleration_ratio: np.ndarray
    kind: str
    spline: object = field(repr=False, default=None)

    def evaluate(self, t: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Joints, velocities and accelerations ``(M, 6)`` each at times ``t`` (M,) (s)."""
        t = np.clip(np.atleast_1d(np.asarray(t, dtype=float)), 0.0, self.duration)
        s = self.spline
        return s(t), s.derivative(1)(t), s.derivative(2)(t)


def _fit(t, q, kind: str):
    from scipy.interpolate import make_interp_spline

    z = np.zeros(q.shape[1])
    if kind == "quintic":
        return make_interp_spline(t, q, k=5, bc_type=([(1, z), (2, z)], [(1, z), (2, z)]), axis=0)
    return make_interp_spline(t, q, k=3, bc_type=([(1, z)], [(1, z)]), axis=0)


def _interior(kt: np.ndarray) -> np.ndarray:
    """Check times inside every interval of the knot times ``kt`` (flat)."""
    return (kt[:-1, None] + _CHECK_FRACTIONS[None, :] * np.diff(kt)[:, None]).reshape(-1)


def _rows(duration: float, rate: float) -> np.ndarray:
    """Output times: every ``1 / rate`` s from 0, and ``duration`` itself last."""
    n = int(math.floor(duration * rate + 1e-9)) + 1
    t = np.arange(n) / rate
    if duration - t[-1] > 1e-9:
        t = np.append(t, duration)
    else:
        t[-1] = duration
    return t


def _deviation(robot, path, timing, spline, t):
    """Position (length unit) and angle (rad) deviations of the splined tool at times ``t``."""
    flat = t.reshape(-1)
    T = invert(robot.base) @ robot.fk(spline(flat))
    P, R = path.at(timing.u_of_t(flat))
    dp = np.linalg.norm(T[:, :3, 3] - P, axis=1)
    c = (np.einsum("nij,nij->n", T[:, :3, :3], R) - 1.0) / 2.0
    da = np.arccos(np.clip(c, -1.0, 1.0))
    return dp.reshape(t.shape), da.reshape(t.shape)


def _densify(robot, path, timing, ku, kq, t_out, tol, kind, max_rounds, max_step):
    """Add IK samples at the middle of intervals where the splined tool leaves the path by more
    than ``tol`` (at the check points or the rows ``t_out``); returns (ku, kq, spline)."""
    stuck_u: set[float] = set()  # left ends of intervals that cannot be split further
    for rnd in range(max_rounds + 1):
        kt = timing.t_of_u(ku)
        spline = _fit(kt, kq, kind)
        tc = np.concatenate([_interior(kt), t_out])
        dev, _ = _deviation(robot, path, timing, spline, tc)
        bad = np.zeros(len(ku) - 1, dtype=bool)
        over = tc[dev > tol]
        bad[np.clip(np.searchsorted(kt, over, side="right") - 1, 0, len(ku) - 2)] = True
        if stuck_u:
            bad &= ~np.isin(ku[:-1], list(stuck_u))
        if not np.any(bad) or rnd == max_rounds:
            break
        new_u, new_q = [], []
        for i in np.flatnonzero(bad):
            um = 0.5 * (ku[i] + ku[i + 1])
            qm = None
            if ku[i] < um < ku[i + 1]:
                qm, _ = track(robot, path, kq[i], ku[i], um, max_step=max_step)
            if qm is None:  # too short, or (never on a feasible solution) the branch is lost
                stuck_u.add(float(ku[i]))
                continue
            new_u.append(um)
            new_q.append(qm)
        if not new_u:
            break
        ku = np.concatenate([ku, new_u])
        kq = np.concatenate([kq, np.array(new_q)])
        order = np.argsort(ku, kind="stable")
        ku, kq = ku[order], kq[order]
    return ku, kq, spline


def interpolate(robot: Robot, solution: PathSolution, duration: float = 20.0, *, ramp: float = DEFAULT_RAMP,
                kind: str = "quintic", tolerance: float | None = None, rate: float = DEFAULT_RATE,
                rescale: bool = False, max_rounds: int = 10,
                max_step: float = DEFAULT_MAX_STEP) -> tuple[Trajectory, list[PathEvent]]:
    """A timed, smooth joint trajectory through the IK samples of ``solution``.

    Parameters
    ----------
    robot : Robot
        The robot the solution was computed for (same tool and base).
    solution : PathSolution
        From :func:`ik7r.painting.solve_path`; must be ``feasible``.
    duration : float
        Time for the whole path (s), before any rescaling.
    ramp : float
        Duration of the speed ramps at both ends (s); at most half the duration (larger values
        are reduced to it).
    kind : {"quintic", "cubic"}
        Spline through the samples.
    tolerance : float, optional
        Largest allowed deviation of the tool from the path (length unit); default 0.01 mm.
    rate : float
        Output rows per second (Hz); the last row is at ``duration`` exactly.
    rescale : bool
        Stretch the time uniformly so that no speed or acceleration limit is exceeded (a
        :class:`TimeScaled` event), instead of reporting :class:`SpeedLimit` /
        :class:`AccelerationLimit` events.
    max_rounds : int
        Most densification rounds.
    max_step : float
        See :func:`ik7r.painting.solve_path` (used when solving added samples).

    Returns
    -------
    trajectory : Trajectory
    events : list of PathEvent
        Limit excesses, time scaling, deviation above tolerance (all non-blocking).

    Raises
    ------
    PathNotFeasible
        The solution has unreachable samples or branch changes.
    """
    if not isinstance(solution, PathSolution):
        raise ValueError(f"solution must be a PathSolution; got {type(solution).__name__}")
    if not solution.feasible:
        raise PathNotFeasible(solution.events, solution)
    if kind not in ("quintic", "cubic"):
        raise ValueError(f"kind must be 'quintic' or 'cubic'; got {kind!r}")
    for name, v in (("duration", duration), ("ramp", ramp), ("rate", rate)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a positive number; got {v!r}")
    tol = default_tolerance(robot.unit) if tolerance is None else float(tolerance)
    if not (math.isfinite(tol) and tol > 0):
        raise ValueError(f"tolerance must be a positive length; got {tolerance!r}")
    path = solution.path
    timing = Timing(float(path.u[-1]), float(duration), min(float(ramp), 0.5 * float(duration)))
    unit = robot.unit
    events = []

    # ---- densify until the deviation is within tolerance at the check points and the rows
    t_out = _rows(timing.duration, rate)
    ku, kq, spline = _densify(robot, path, timing, path.u.copy(), np.array(solution.q), t_out, tol, kind,
                              max_rounds, max_step)

    # ---- limits, and uniform time scaling
    vlim, alim = robot.velocity, robot.acceleration

    def peaks(spline, ku):
        kt = timing.t_of_u(ku)
        t_chk = np.concatenate([kt, _interior(kt), t_out])
        dq_c = spline.derivative(1)(t_chk)
        ddq_c = spline.derivative(2)(t_chk)
        v = np.abs(dq_c).max(axis=0) / vlim if vlim is not None else np.full(6, np.nan)
        a = np.abs(ddq_c).max(axis=0) / alim if alim is not None else np.full(6, np.nan)
        return v, a, t_chk, dq_c, ddq_c

    v_ratio, a_ratio, t_chk, dq_c, ddq_c = peaks(spline, ku)
    k = max(np.nanmax(np.r_[v_ratio, 0.0]), math.sqrt(np.nanmax(np.r_[a_ratio, 0.0])))
    if rescale and k > 1.0:
        before = timing.duration
        timing = timing.scaled(k * (1.0 + 1e-9))
        events.append(TimeScaled(before, timing.duration))
        t_out = _rows(timing.duration, rate)
        # the rows now fall elsewhere on the path: check (and densify) again
        ku, kq, spline = _densify(robot, path, timing, ku, kq, t_out, tol, kind, max_rounds, max_step)
        v_ratio, a_ratio, t_chk, dq_c, ddq_c = peaks(spline, ku)
    for j in range(6):  # after rescaling only a new sample could push a peak past its limit
        if vlim is not None and v_ratio[j] > 1.0 + 1e-6:
            i = int(np.argmax(np.abs(dq_c[:, j])))
            events.append(SpeedLimit(j, float(abs(dq_c[i, j])), float(vlim[j]), float(t_chk[i])))
        if alim is not None and a_ratio[j] > 1.0 + 1e-6:
            i = int(np.argmax(np.abs(ddq_c[:, j])))
            events.append(AccelerationLimit(j, float(abs(ddq_c[i, j])), float(alim[j]), float(t_chk[i])))

    # ---- output rows and the final checks
    q = spline(t_out)
    dq = spline.derivative(1)(t_out)
    ddq = spline.derivative(2)(t_out)
    u_out = timing.u_of_t(t_out)
    positions, _ = path.at(u_out)
    t_all = np.concatenate([_interior(timing.t_of_u(ku)), t_out])
    dev, ang = _deviation(robot, path, timing, spline, t_all)
    imax = int(np.argmax(dev))
    if dev[imax] > tol:
        events.append(DeviationExceeded(float(dev[imax]), tol, float(t_all[imax]), unit))
    q_chk = spline(t_all)
    for j in range(6):
        for side, lim in (("hi", robot.upper[j]), ("lo", robot.lower[j])):
            over = q_chk[:, j] - lim if side == "hi" else lim - q_chk[:, j]
            i = int(np.argmax(over))
            if over[i] > 1e-9:
                events.append(JointLimit(j, float(q_chk[i, j]), float(lim), time=float(t_all[i])))
    traj = Trajectory(
        t=t_out, q=q, dq=dq, ddq=ddq, positions=positions, u=u_out, duration=timing.duration,
        timing=timing, knot_t=timing.t_of_u(ku), knot_u=ku, knot_q=kq, max_deviation=float(dev.max()),
        max_angle_deviation=float(ang.max()), tolerance=tol, speed_ratio=v_ratio,
        acceleration_ratio=a_ratio, kind=kind, spline=spline,
    )
    for arr in (traj.t, traj.q, traj.dq, traj.ddq, traj.positions, traj.u, traj.knot_t, traj.knot_u,
                traj.knot_q):
        arr.setflags(write=False)
    return traj, events
