"""Timing a solved path for painting: the process speed where the gun is on, time-optimal elsewhere.

:func:`time_path` turns a :class:`~ik7r.painting.PathSolution` into a checked
:class:`~ik7r.painting.Trajectory` in one of two modes:

``speed=V`` (the process mode)
    On spray-on stretches the gun tip moves at ``V`` (the path's speed ``udot`` is capped at
    ``V / |dp/du|``); everywhere else (turnarounds, approach, retract, gaps) the path runs as
    fast as the joint speed and acceleration limits allow: the time-optimal profile of
    :func:`ik7r.painting.topp.topp` under the caps, rest to rest, with stops at corners.
    Where holding ``V`` would itself break a limit (``|q'| V > v_max`` or
    ``|q'' V^2 + q' uddot| > a_max`` on the commanded profile) the events say where, which
    joint and by how much: :class:`CommandedSpeedTooHigh` (blocking: the call raises
    :class:`PathNotFeasible`) or, with ``slow_down=True``, :class:`SlowDown` warnings and a
    profile slowed just there.
``duration=D`` (for paths without a commanded speed)
    Constant path speed with smooth ramps (:class:`~ik7r.painting.Timing`), rest to rest
    between the stops at corners; ``rescale=True`` stretches it uniformly until the dense check
    passes.

Either way the limits are verified after any scaling by :func:`~ik7r.painting.interpolate.dense_peaks`
over every interval (the time-optimal profile is computed with the limits times
``margin`` and tightened if the dense check still finds an excess), and the rows include the
peak instants.
"""

from __future__ import annotations

import math

import numpy as np

from .corners import DEFAULT_CORNER_ANGLE, find_corners
from .events import (
    AccelerationLimit,
    CommandedSpeedTooHigh,
    CornerStop,
    DeviationExceeded,
    JointLimit,
    PathNotFeasible,
    SlowDown,
    SpeedLimit,
    TimeScaled,
)
from .interpolate import (
    DEFAULT_RAMP,
    DEFAULT_RATE,
    MIN_TOLERANCE_MM,
    JointPath,
    ProfileTiming,
    Timing,
    Trajectory,
    _deviation,
    _interior,
    default_tolerance,
    dense_peaks,
    fit_joint_path,
    joint_motion,
    mm_in,
    output_times,
)
from .topp import TOPPInfeasible, topp
from .trajectory import DEFAULT_MAX_STEP, PathSolution

__all__ = ["time_path", "SPEED_TOLERANCE", "DEFAULT_MARGIN"]

#: Relative gun-speed tolerance on spray-on stretches outside the ramps.
SPEED_TOLERANCE = 0.01
#: Fraction of the joint limits the time-optimal profile is computed for (the dense check then
#: verifies the full limits; a speed reduction of at most 1 - sqrt(margin) on a spray-on stretch
#: stays inside the speed tolerance).
DEFAULT_MARGIN = 0.995
#: Grid points per IK-sample interval of the time-optimal profile.
DEFAULT_GRID = 4
#: Largest distance between the profile's grid points (mm).
GRID_SPACING_MM = 1.0


def _stops_of(solution: PathSolution, corner_angle: float, unit: str):
    path = solution.path
    idx, turn = find_corners(path, corner_angle)
    events = [CornerStop(int(i), float(a), bool(path.spray[i]), _pos(path, path.u[i]), unit)
              for i, a in zip(idx, turn)]
    return tuple(float(path.u[i]) for i in idx), events


def _grid(jp: JointPath, per: int, h: float) -> np.ndarray:
    """``per`` points per IK-sample interval, more where that leaves them farther than ``h``."""
    ku = jp.knot_u
    n = np.maximum(per, np.ceil(np.diff(ku) / h - 1e-9).astype(int))
    return np.concatenate([ku[i] + np.arange(n[i]) / n[i] * (ku[i + 1] - ku[i]) for i in range(len(n))]
                          + [ku[-1:]])


def _tip_rate(path, s: np.ndarray) -> np.ndarray:
    """``|dp/du|`` at ``s`` (the larger one-sided value at a sample)."""
    h = 1e-6 * max(1.0, float(path.u[-1]))
    p0, _ = path.at(s)
    pa, _ = path.at(np.minimum(s + h, path.u[-1]))
    pb, _ = path.at(np.maximum(s - h, 0.0))
    ra = np.linalg.norm(pa - p0, axis=1) / np.maximum(np.minimum(s + h, path.u[-1]) - s, 1e-300)
    rb = np.linalg.norm(p0 - pb, axis=1) / np.maximum(s - np.maximum(s - h, 0.0), 1e-300)
    ra[s >= path.u[-1]] = 0.0
    rb[s <= 0.0] = 0.0
    return np.maximum(ra, rb)


def _stretches(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges ``[a, b]`` (inclusive) of the runs of True in ``mask``."""
    m = np.concatenate([[False], mask, [False]]).astype(int)
    d = np.diff(m)
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1))


def _pos(path, u: float) -> tuple:
    return tuple(float(v) for v in path.at([u])[0][0])


def _commanded_check(robot, path, jp, s, on, cap, speed, unit, per):
    """Joint speeds and accelerations of the commanded profile on the spray-on grid points:
    the stretches (per joint) where a limit is exceeded, as events."""
    d1 = jp.evaluate(s, 1)
    d2 = jp.evaluate(s, 2)
    x = np.where(on, cap, 0.0)
    x = np.where(np.isfinite(x), x, 0.0)
    a = np.gradient(x, s) / 2.0
    v_ratio = np.abs(d1) * np.sqrt(x)[:, None] / robot.velocity
    a_ratio = np.abs(d2 * x[:, None] + d1 * a[:, None]) / robot.acceleration
    # a short run of acceleration excess at the end of its spray-on stretch (up to three IK-sample
    # intervals: where the spline meets the curvature of a turn) is a ramp: the profile slows down
    # before it, off the part when the stretch has an overspray margin
    first = np.zeros(len(s), dtype=bool)
    last = np.zeros(len(s), dtype=bool)
    for a, b in _stretches(on):
        first[a], last[b] = True, True
    events, bad_any = [], np.zeros(len(s), dtype=bool)
    for quantity, ratio, root in (("speed", v_ratio, 1.0), ("acceleration", a_ratio, 0.5)):
        for j in range(6):
            bad = on & (ratio[:, j] > 1.0)
            for i0, i1 in _stretches(bad):
                if quantity == "acceleration" and (first[i0] or last[i1]) and i1 - i0 < 3 * per:
                    continue
                bad_any[i0:i1 + 1] = True
                r = float(ratio[i0:i1 + 1, j].max())
                events.append(CommandedSpeedTooHigh(j, quantity, r, float(s[i0]), float(s[i1]), float(speed),
                                                    float(speed / r ** root), _pos(path, s[i0]), unit))
    events.sort(key=lambda e: (e.u0, e.joint))
    return events, bad_any, np.maximum(v_ratio, np.sqrt(a_ratio))


def time_path(robot, solution: PathSolution, *, speed: float | None = None,
              duration: float | None = None, slow_down: bool = False, rescale: bool = False,
              ramp: float = DEFAULT_RAMP, kind: str = "quintic", tolerance: float | None = None,
              rate: float = DEFAULT_RATE, max_rounds: int = 10,
              max_step: float = DEFAULT_MAX_STEP, corner_angle: float | None = None,
              margin: float = DEFAULT_MARGIN, grid: int = DEFAULT_GRID):
    """A timed, checked joint trajectory through the IK samples of ``solution``.

    Parameters
    ----------
    robot : Robot
        The robot the solution was computed for (same tool and base).
    solution : PathSolution
        From :func:`ik7r.painting.solve_path`; must be ``feasible``. Its path's ``spray`` flags
        say where the gun is on.
    speed : float, optional
        Commanded gun (tool-tip) speed on spray-on stretches (length unit per s). Needs the
        robot's velocity and acceleration limits.
    duration : float, optional
        Time for the whole path (s) when no speed is commanded (default 20).
    slow_down : bool
        ``speed`` mode: where ``speed`` would break a limit, slow the stroke there (reported as
        :class:`SlowDown`) instead of raising.
    rescale : bool
        ``duration`` mode: stretch the time uniformly so that no limit is exceeded.
    ramp : float
        ``duration`` mode: duration of each speed ramp (s).
    kind : {"quintic", "cubic"}
        Joint spline in the path parameter.
    tolerance : float, optional
        Largest deviation of the tool from the path (length unit; default 0.01 mm, at least
        ``MIN_TOLERANCE_MM`` = 1e-4 mm).
    rate : float
        Output rows per second (Hz); the peak instants are rows too.
    max_rounds, max_step
        Densification rounds; see :func:`ik7r.painting.solve_path`.
    corner_angle : float, optional
        Turn (rad) at a sample of a sampled path above which the robot stops there (default
        2 deg; blend corners beforehand with :func:`ik7r.painting.blend_corners`).
    margin : float
        ``speed`` mode: fraction of the limits the time-optimal profile is computed for.
    grid : int
        ``speed`` mode: profile grid points per IK-sample interval.

    Returns
    -------
    trajectory : Trajectory
    events : list of PathEvent

    Raises
    ------
    PathNotFeasible
        The solution is not feasible, or (``speed`` mode, no ``slow_down``) the commanded speed
        breaks a limit on a spray-on stretch, or the path cannot be followed within the limits.
    """
    if not isinstance(solution, PathSolution):
        raise ValueError(f"solution must be a PathSolution; got {type(solution).__name__}")
    if not solution.feasible:
        raise PathNotFeasible(solution.events, solution)
    if kind not in ("quintic", "cubic"):
        raise ValueError(f"kind must be 'quintic' or 'cubic'; got {kind!r}")
    if speed is not None and duration is not None:
        raise ValueError("give either speed (the process mode) or duration, not both")
    if speed is None and duration is None:
        duration = 20.0
    for name, v in (("speed", speed), ("duration", duration), ("ramp", ramp), ("rate", rate)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a positive number; got {v!r}")
    if not (0 < margin <= 1):
        raise ValueError(f"margin must be in (0, 1]; got {margin!r}")
    tol = default_tolerance(robot.unit) if tolerance is None else float(tolerance)
    if not (math.isfinite(tol) and tol > 0):
        raise ValueError(f"tolerance must be a positive length; got {tolerance!r}")
    tol_min = MIN_TOLERANCE_MM * mm_in(robot.unit)
    if tol < tol_min:
        raise ValueError(f"tolerance must be at least {tol_min:g} {robot.unit} (0.1 um; the joint "
                         f"samples double for every factor of 64 below the default 0.01 mm); "
                         f"got {tolerance!r}")
    if speed is not None and (robot.velocity is None or robot.acceleration is None):
        raise ValueError(f"a commanded speed needs the joint velocity and acceleration limits; robot "
                         f"{robot.name} has {'none' if robot.velocity is None else 'no acceleration limits'}"
                         f" (time it by duration instead)")
    path = solution.path
    unit = robot.unit
    stops, events = _stops_of(solution, DEFAULT_CORNER_ANGLE if corner_angle is None else corner_angle, unit)
    jp = fit_joint_path(robot, path, path.u, np.array(solution.q), stops, kind, tol, max_rounds=max_rounds,
                        max_step=max_step)

    def timed(jp):
        if speed is None:
            return _duration_timing(robot, path, jp, duration, ramp, stops, rescale), [], np.zeros((0, 2))
        return _speed_timing(robot, path, jp, speed, slow_down, margin, grid, unit, solution)

    (timing, scaled_from), more, ramps = timed(jp)
    for _ in range(3):  # rows fall at new path points: check the deviation there too
        u_rows = timing.u_of_t(output_times(timing.duration, rate))
        dev, _ = _deviation(robot, path, jp, u_rows)
        if dev.max() <= tol:
            break
        jp = fit_joint_path(robot, path, jp.knot_u, jp.knot_q, stops, kind, tol, extra_u=u_rows,
                            max_rounds=max_rounds, max_step=max_step)
        (timing, scaled_from), more, ramps = timed(jp)
    if scaled_from is not None:
        events.append(TimeScaled(scaled_from, timing.duration))
    events += more

    # ---- the dense check, the rows (peak instants included), the final checks
    vlim, alim = robot.velocity, robot.acceleration
    v_pk, v_t, a_pk, a_t = dense_peaks(jp, timing)
    v_ratio = v_pk / vlim if vlim is not None else np.full(6, np.nan)
    a_ratio = a_pk / alim if alim is not None else np.full(6, np.nan)
    for j in range(6):
        if vlim is not None and v_ratio[j] > 1.0 + 1e-6:
            events.append(SpeedLimit(j, float(v_pk[j]), float(vlim[j]), float(v_t[j])))
        if alim is not None and a_ratio[j] > 1.0 + 1e-6:
            events.append(AccelerationLimit(j, float(a_pk[j]), float(alim[j]), float(a_t[j])))
    t_out = output_times(timing.duration, rate, np.concatenate([v_t, a_t]))
    u_out, q, dq, ddq = joint_motion(jp, timing, t_out)
    positions, _ = path.at(u_out)
    u_all = np.concatenate([_interior(jp.knot_u), u_out])
    dev, ang = _deviation(robot, path, jp, u_all)
    imax = int(np.argmax(dev))
    if dev[imax] > tol:
        events.append(DeviationExceeded(float(dev[imax]), tol, float(timing.t_of_u(u_all[imax])), unit))
    q_chk = jp.evaluate(u_all)
    for j in range(6):
        for side, lim in (("hi", robot.upper[j]), ("lo", robot.lower[j])):
            over = q_chk[:, j] - lim if side == "hi" else lim - q_chk[:, j]
            i = int(np.argmax(over))
            if over[i] > 1e-9:
                events.append(JointLimit(j, float(q_chk[i, j]), float(lim),
                                         time=float(timing.t_of_u(u_all[i]))))
    J = robot.jacobian(q)
    gun = np.linalg.norm(np.einsum("mij,mj->mi", J[:, :3, :], dq), axis=1)
    traj = Trajectory(
        t=t_out, q=q, dq=dq, ddq=ddq, positions=positions, u=u_out, duration=timing.duration,
        timing=timing, knot_t=timing.t_of_u(jp.knot_u), knot_u=jp.knot_u, knot_q=jp.knot_q,
        max_deviation=float(dev.max()), max_angle_deviation=float(ang.max()), tolerance=tol,
        speed_ratio=v_ratio, acceleration_ratio=a_ratio, kind=kind, joint_path=jp,
        speed_peak=v_pk, speed_peak_t=v_t, acceleration_peak=a_pk, acceleration_peak_t=a_t,
        spray=path.sprayed(u_out), gun_speed=gun, commanded_speed=None if speed is None else float(speed),
        stops=tuple(stops), ramps=np.asarray(ramps, dtype=float).reshape(-1, 2),
    )
    for arr in (traj.t, traj.q, traj.dq, traj.ddq, traj.positions, traj.u, traj.knot_t, traj.knot_u,
                traj.knot_q, traj.spray, traj.gun_speed, traj.ramps):
        arr.setflags(write=False)
    return traj, events


def _duration_timing(robot, path, jp, duration, ramp, stops, rescale):
    timing = Timing(float(path.u[-1]), float(duration), min(float(ramp), 0.5 * float(duration)), stops)
    if not rescale or robot.velocity is None:
        return timing, None
    v_pk, _, a_pk, _ = dense_peaks(jp, timing)
    k = float(np.max(v_pk / robot.velocity))
    if robot.acceleration is not None:
        k = max(k, math.sqrt(float(np.max(a_pk / robot.acceleration))))
    if k <= 1.0:
        return timing, None
    # speeds scale by 1/k and accelerations by 1/k^2 exactly (q(t) = Q(u(t / k)))
    return timing.scaled(k * (1.0 + 1e-9)), float(duration)


def _speed_timing(robot, path, jp, speed, slow_down, margin, per, unit, solution):
    s = _grid(jp, per, GRID_SPACING_MM * mm_in(unit))
    on = path.sprayed(s)
    rate = _tip_rate(path, s)
    cap = np.where(on, (speed / np.maximum(rate, 1e-300)) ** 2, np.inf)
    stop_mask = np.isin(s, jp.stops)
    cap[stop_mask] = 0.0
    check, bad, need = _commanded_check(robot, path, jp, s, on & ~stop_mask, cap, speed, unit, per)
    if check and not slow_down:
        raise PathNotFeasible(list(solution.events) + check, solution)
    # interval-wise derivatives, on each interval's own side of a stop
    lo_side = np.concatenate([s[:-1], [s[-1]]])
    d1r, d2r = jp.evaluate(lo_side, 1, "right"), jp.evaluate(lo_side, 2, "right")
    d1l, d2l = jp.evaluate(s, 1, "left"), jp.evaluate(s, 2, "left")
    f = margin
    for _ in range(6):
        try:
            x = topp(s, d1r[:-1], d2r[:-1], d1l[1:], d2l[1:], robot.velocity * f, robot.acceleration * f, cap)
        except TOPPInfeasible as exc:
            raise TOPPInfeasible(exc.index, f"the path cannot be timed within the joint limits: {exc} "
                                            f"(at {_pos(path, s[exc.index])} {unit})") from exc
        timing = ProfileTiming(s, x)
        v_pk, _, a_pk, _ = dense_peaks(jp, timing)
        r = max(float(np.max(v_pk / robot.velocity)), float(np.max(a_pk / robot.acceleration)))
        if r <= 1.0:
            break
        f *= 0.99 / r
    events = []
    # ---- where the gun is slower than commanded on spray-on stretches: ramps and slow-downs
    actual = np.sqrt(x) * rate
    slow = on & (actual < (1.0 - SPEED_TOLERANCE) * speed)  # a stop (speed 0) is slow
    ramps = []
    for a, b in _stretches(slow):
        # a ramp: the slow run touches the end of a spray-on stretch or holds a stop, and holds no
        # point where the commanded speed breaks a limit
        touches = ((a == 0 or not on[a - 1]) or (b == len(s) - 1 or not on[b + 1])
                   or bool(np.any(stop_mask[a:b + 1])))
        if touches and not np.any(bad[a:b + 1]):
            # from the last grid point at speed to the first one at speed again (the speed
            # changes linearly in x between grid points)
            ramps.append((float(s[max(a - 1, 0)]), float(s[min(b + 1, len(s) - 1)])))
            continue
        if np.any(bad[a:b + 1]):
            k = a + int(np.argmax(np.max(need[a:b + 1], axis=1)))
            j = int(np.argmax(need[k]))
        else:
            j = int(np.argmax(np.max(need[a:b + 1], axis=0)))
        events.append(SlowDown(j, float(s[a]), float(s[b]), float(speed), float(actual[a:b + 1].min()),
                               _pos(path, s[a]), unit))
    return (timing, None), events, ramps
