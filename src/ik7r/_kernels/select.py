"""Compiled kernels that pick solutions: indicators, joint limits and multi-turn joints,
nearest to a seed; and the batch drivers built on :func:`ik7r._kernels.complete.solve_all`."""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .complete import WORK_SIZE, solve_all, solve_config, solve_into, wrap
from .jit import njit
from .validate import validate_pose

HALF_PI = 0.5 * math.pi
SINGULAR_WRIST = 1e-9  # |q5| (or |q5| - pi) below this: both Wrist indicators name the pose
#: q1 or q3 within this (rad) of an indicator boundary (+-pi/2): both indicators name the
#: solution. It is the rounding of the solve where a boundary is singular (the stretched elbow of
#: a robot without elbow offset: the FK is flat there, a joint error e moves the tool by about
#: reach * e^2, 1e-9 of it for e = 1e-6 ... and two elbow solutions merge into one).
BOUNDARY_TOL = 1e-6


@njit
def _side(x, want):
    """Whether the wrapped angle ``x`` may have the indicator ``want`` (1: in [-pi/2, pi/2)):
    True for either indicator within BOUNDARY_TOL of +-pi/2."""
    if abs(abs(x) - HALF_PI) <= BOUNDARY_TOL:
        return True
    return (1 if -HALF_PI <= x < HALF_PI else 0) == want


@njit
def matches(q, arm, elbow, wrist):
    """True when ``q`` has the indicators (arm, elbow, wrist). A solution on a boundary between
    configurations belongs to both: q1 or q3 within BOUNDARY_TOL of +-pi/2, a straight
    (q5 = 0) or fully bent (q5 = pi) wrist (its two wrist solutions are one)."""
    if not (_side(wrap(q[0]), arm) and _side(wrap(q[2]), elbow)):
        return False
    q5 = wrap(q[4])
    if abs(q5) < SINGULAR_WRIST or math.pi - abs(q5) < SINGULAR_WRIST:
        return True
    w = 1 if 0.0 <= q5 < math.pi else 0
    return w == wrist


@njit(allocates=True)
def expand_within_limits(sols, n, K, out):
    """Every solution of ``sols[:n]`` shifted by multiples of 2 pi per joint into the joint
    limits (multi-turn joints give several); returns how many were written to ``out``."""
    lo = K[L.LIMITS:L.LIMITS + 6]
    hi = K[L.LIMITS + 6:L.LIMITS + 12]
    count = 0
    first = np.empty(6, np.int64)
    nturn = np.empty(6, np.int64)
    idx = np.empty(6, np.int64)
    for s in range(n):
        total = 1
        for j in range(6):
            k0 = math.ceil((lo[j] - sols[s, j]) / (2 * math.pi) - 1e-12)
            k1 = math.floor((hi[j] - sols[s, j]) / (2 * math.pi) + 1e-12)
            first[j] = k0
            nturn[j] = max(0, k1 - k0 + 1)
            total *= nturn[j]
        for t in range(total):
            r = t
            for j in range(6):
                idx[j] = r % nturn[j]
                r //= nturn[j]
            if count >= out.shape[0]:
                return count
            for j in range(6):
                v = sols[s, j] + 2 * math.pi * (first[j] + idx[j])
                out[count, j] = min(hi[j], max(lo[j], v))
            count += 1
    return count


@njit
def nearest(sols, n, seed, wrapped):
    """Index of the solution of ``sols[:n]`` nearest ``seed`` (sum of squared joint
    differences, wrapped to (-pi, pi] when ``wrapped``); ties go to the first."""
    best = -1
    bestd = np.inf
    for s in range(n):
        dist = 0.0
        for j in range(6):
            dj = sols[s, j] - seed[j]
            if wrapped:
                dj = wrap(dj)
            dist += dj * dj
        if dist < bestd - 1e-12:
            bestd = dist
            best = s
    return best


@njit(allocates=True)
def select(sols, n, arm, elbow, wrist, seed, within_limits, K, q_out):
    """Pick the solution with the indicators nearest ``seed``; False when there is none."""
    pool = np.empty((sols.shape[0] * 16 if within_limits else sols.shape[0], 6))
    m = 0
    for s in range(n):
        if matches(sols[s], arm, elbow, wrist):
            pool[m] = sols[s]
            m += 1
    if within_limits:
        expanded = np.empty((pool.shape[0], 6))
        m = expand_within_limits(pool, m, K, expanded)
        pool = expanded
    k = nearest(pool, m, seed, not within_limits)
    if k < 0:
        return False
    q_out[:] = pool[k]
    return True


# ---------------------------------------------------------------------- fused entry points
# One compiled call per public call: the Python side only allocates and raises.


@njit
def np_wrap(x):
    """``numpy``'s :func:`ik7r.geometry.rotations.wrap_angle` of one angle, bit for bit (fmod based)."""
    two_pi = 2.0 * math.pi
    y = np.fmod(x + math.pi, two_pi)
    if y != 0.0:
        if y < 0.0:
            y += two_pi
    else:
        y = 0.0
    if y <= 0.0:
        y += two_pi
    return y - math.pi


@njit
def config_number(q):
    """Configuration number 1..8 of ``q`` (6,), as :func:`ik7r.geometry.configs.config_number`."""
    q1 = np_wrap(q[0])
    q3 = np_wrap(q[2])
    q5 = np_wrap(q[4])
    arm = 1 if -HALF_PI <= q1 < HALF_PI else 0
    elbow = 1 if -HALF_PI <= q3 < HALF_PI else 0
    wrist = 1 if 0.0 <= q5 < math.pi else 0
    return 1 + 4 * (1 - arm) + 2 * (1 - elbow) + (1 - wrist)


@njit
def _before(a, ca, b, cb):
    """Strictly before in the order (configuration, q1, q2, q3, q4, q5, q7)."""
    if ca != cb:
        return ca < cb
    for j in range(6):
        if a[j] != b[j]:
            return a[j] < b[j]
    return False


@njit(allocates=True)
def sort_solutions(sols, n):
    """Sort ``sols[:n]`` in place by configuration number, then joints (a stable insertion
    sort: the order of ``np.lexsort`` on those keys)."""
    conf = np.empty(n, np.int64)
    for s in range(n):
        conf[s] = config_number(sols[s])
    row = np.empty(6)
    for s in range(1, n):
        c = conf[s]
        for j in range(6):
            row[j] = sols[s, j]
        k = s
        while k > 0 and _before(row, c, sols[k - 1], conf[k - 1]):
            for j in range(6):
                sols[k, j] = sols[k - 1, j]
            conf[k] = conf[k - 1]
            k -= 1
        for j in range(6):
            sols[k, j] = row[j]
        conf[k] = c


@njit
def _finite6(x):
    for j in range(6):
        if not math.isfinite(x[j]):
            return False
    return True


@njit(allocates=True)
def ik_all_one(T, tol, K, Bm, bnorm, hint, has_hint, within_limits, out):
    """Validate one pose ``T`` (4, 4), solve it and sort the solutions into ``out``.

    Returns the number of solutions, -1 when ``T`` is not a valid pose or -2 when the hint
    is not finite (the caller says why). With ``within_limits`` every multi-turn equivalent
    inside the limits is written (``out`` needs ``64 * MAX_SOLUTIONS`` rows)."""
    clean = np.empty((4, 4))
    if validate_pose(T, tol, clean, np.empty((3, 3))) != 0:
        return -1
    if has_hint and not _finite6(hint):
        return -2
    sols = np.empty((L.MAX_SOLUTIONS, 6))
    n = solve_all(clean, K, Bm, bnorm, hint, has_hint, sols)
    if within_limits:
        n = expand_within_limits(sols, n, K, out[:max(1, n) * 64])
    else:
        for s in range(n):
            for j in range(6):
                out[s, j] = sols[s, j]
    sort_solutions(out, n)
    return n


@njit(allocates=True)
def ik_one(T, tol, K, Bm, bnorm, arm, elbow, wrist, hint, has_hint, within_limits, sols, q_out):
    """Validate one pose, solve it and pick the solution with the indicators nearest ``hint``.

    Returns ``(n, found)``: the number of solutions of the pose (left in ``sols``; -1 when
    ``T`` is not a valid pose, -2 when the hint is not finite) and whether one with the
    indicators was written to ``q_out``."""
    clean = np.empty((4, 4))
    if validate_pose(T, tol, clean, np.empty((3, 3))) != 0:
        return -1, False
    if has_hint and not _finite6(hint):
        return -2, False
    n = solve_config(clean, K, Bm, bnorm, hint, has_hint, arm, elbow, wrist, sols)
    found = select(sols[:max(1, n)], n, arm, elbow, wrist, hint, within_limits, K, q_out)
    if not found:  # the whole solution set, for the caller's message
        n = solve_all(clean, K, Bm, bnorm, hint, has_hint, sols)
    return n, found


@njit(allocates=True)
def config_rows(Ts, K, Bm, bnorm, arm, elbow, wrist, seeds, has_seed, within_limits,
                ok_in, q_out, ok_out):
    """One configuration for every pose of ``Ts`` (N, 4, 4) whose ``ok_in`` is True; rows
    without a solution get NaN. ``seeds`` is (N, 6) or (1, 6) (the same seed for every row)."""
    sols = np.empty((L.MAX_SOLUTIONS, 6))
    ws = np.empty(WORK_SIZE)
    per_row = seeds.shape[0] > 1
    filt = 4 * arm + 2 * elbow + wrist
    for i in range(Ts.shape[0]):
        seed = seeds[i] if per_row else seeds[0]
        ok = False
        if ok_in[i]:
            n = solve_into(Ts[i], K, Bm, bnorm, seed, has_seed, sols, filt, ws)
            ok = select(sols, n, arm, elbow, wrist, seed, within_limits, K, q_out[i])
        ok_out[i] = ok
        if not ok:
            for j in range(6):
                q_out[i, j] = np.nan


@njit(allocates=True)
def all_rows(Ts, K, Bm, bnorm, ok_in, out, counts):
    """Every solution of every pose of ``Ts`` (N, 4, 4) into ``out`` (N, W, 6), NaN after the
    ``counts[i]`` valid rows; poses whose ``ok_in`` is False have none."""
    sols = np.empty((L.MAX_SOLUTIONS, 6))
    ws = np.empty(WORK_SIZE)
    hint = np.zeros(6)
    width = out.shape[1]
    for i in range(Ts.shape[0]):
        n = 0
        if ok_in[i]:
            n = solve_into(Ts[i], K, Bm, bnorm, hint, False, sols, -1, ws)
        n = min(n, width)
        counts[i] = n
        for s in range(n):
            for j in range(6):
                out[i, s, j] = sols[s, j]
        for s in range(n, width):
            for j in range(6):
                out[i, s, j] = np.nan
