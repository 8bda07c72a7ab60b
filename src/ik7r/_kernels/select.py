"""Compiled kernels that pick solutions: indicators, joint limits and multi-turn joints,
nearest to a seed; and the batch drivers built on :func:`ik7r._kernels.complete.solve_all`."""

from __future__ import annotations

import math

import numpy as np

from ..geometry import configs
from ..robot.family import MAX_JOINT_ANGLE
from . import params as L
from .complete import solve_into
from .constants import DUP_TOL, WORK_SIZE, wrap
from .jit import njit, shared
from .validate import validate_pose

HALF_PI = 0.5 * math.pi
SINGULAR_WRIST = 1e-9  # |q5| below this: both Wrist indicators name the pose
#: pi - |q5| below this: both Wrist indicators name the pose. Beside the fully bent wrist its two
#: solutions +-(pi - eps), 2 eps apart, are one solution below DUP_TOL (ik7r._kernels.complete),
#: which then stands for both.
FOLDED_WRIST = 0.5 * DUP_TOL
#: q1 or q3 within this (rad) of an indicator boundary (+-pi/2): both indicators name the
#: solution. It is the rounding of the solve where a boundary is singular (the stretched elbow of
#: a robot without elbow offset: the FK is flat there, a joint error e moves the tool by about
#: reach * e^2, 1e-9 of it for e = 1e-6 ... and two elbow solutions merge into one).
BOUNDARY_TOL = 1e-6

# the one indicator rule and the one numbering (ik7r.geometry.configs), compiled into the kernels
arm_elbow_wrist = shared(configs.arm_elbow_wrist)
number_of = shared(configs.number_of)


@njit
def _on_boundary(x):
    """Whether joint angle ``x`` (q1 or q3) is within BOUNDARY_TOL of an indicator boundary +-pi/2."""
    return abs(abs(wrap(x)) - HALF_PI) <= BOUNDARY_TOL


@njit
def matches(q, arm, elbow, wrist):
    """True when ``q`` has the indicators (arm, elbow, wrist) by the one rule
    (:func:`ik7r.geometry.configs.arm_elbow_wrist`), except that a solution on a boundary between
    configurations belongs to both: q1 or q3 within BOUNDARY_TOL of +-pi/2, a straight
    (q5 = 0) or fully bent (q5 within FOLDED_WRIST of pi) wrist (its two wrist solutions are one)."""
    a, e, w = arm_elbow_wrist(q[0], q[2], q[4])
    if not ((a == arm or _on_boundary(q[0])) and (e == elbow or _on_boundary(q[2]))):
        return False
    q5 = wrap(q[4])
    if abs(q5) < SINGULAR_WRIST or math.pi - abs(q5) < FOLDED_WRIST:
        return True
    return w == wrist


#: Solutions this close (rad) outside a joint limit count as inside, and are set onto it: the
#: 2 pi shifts of the multi-turn expansion round by a few ulps (4e-15 rad moves a tool at the
#: largest extent the family admits by under half its position tolerance).
LIMIT_SLACK = 4e-15
TWO_PI = 2.0 * math.pi


@njit
def turn_range(x, lo, hi):
    """``(k0, k1)``: the turns k with ``x + 2 pi k`` inside ``[lo, hi]`` (none when k1 < k0)."""
    k0 = math.ceil((lo - LIMIT_SLACK - x) / TWO_PI)
    k1 = math.floor((hi + LIMIT_SLACK - x) / TWO_PI)
    return k0, k1


@njit
def shifted(x, k, lo, hi):
    """``x + 2 pi k`` set onto the limits it is within LIMIT_SLACK of."""
    return min(hi, max(lo, x + TWO_PI * k))


@njit
def count_within_limits(sols, n, K):
    """How many rows :func:`expand_within_limits` writes for ``sols[:n]`` (the sum over the
    solutions of the product of each joint's number of turns inside the limits)."""
    lo = K[L.LIMITS:L.LIMITS + 6]
    hi = K[L.LIMITS + 6:L.LIMITS + 12]
    total = 0
    for s in range(n):
        prod = 1
        for j in range(6):
            k0, k1 = turn_range(sols[s, j], lo[j], hi[j])
            prod *= max(0, k1 - k0 + 1)
        total += prod
    return total


@njit(allocates=True)
def expand_within_limits(sols, n, K, out):
    """Every solution of ``sols[:n]`` shifted by multiples of 2 pi per joint into the joint
    limits (multi-turn joints give several) into ``out``, which must have
    :func:`count_within_limits` rows (the caller sizes it); returns the number written, or -1
    when ``out`` is too small (nothing is dropped silently)."""
    lo = K[L.LIMITS:L.LIMITS + 6]
    hi = K[L.LIMITS + 6:L.LIMITS + 12]
    count = 0
    first = np.empty(6, np.int64)
    nturn = np.empty(6, np.int64)
    for s in range(n):
        total = 1
        for j in range(6):
            k0, k1 = turn_range(sols[s, j], lo[j], hi[j])
            first[j] = k0
            nturn[j] = max(0, k1 - k0 + 1)
            total *= nturn[j]
        if count + total > out.shape[0]:
            return -1
        for t in range(total):
            r = t
            for j in range(6):
                out[count, j] = shifted(sols[s, j], first[j] + r % nturn[j], lo[j], hi[j])
                r //= nturn[j]
            count += 1
    return count


@njit
def nearest_within_limits(q, seed, K, out):
    """The multi-turn equivalent of ``q`` inside the limits nearest ``seed`` (joint by joint:
    the distance is a sum over joints) into ``out``; False when some joint has no turn inside."""
    for j in range(6):
        lo = K[L.LIMITS + j]
        hi = K[L.LIMITS + 6 + j]
        k0, k1 = turn_range(q[j], lo, hi)
        if k1 < k0:
            return False
        k = min(k1, max(k0, math.floor((seed[j] - q[j]) / TWO_PI + 0.5)))
        out[j] = shifted(q[j], k, lo, hi)
    return True


@njit
def reduced_seed(seed, out):
    """``seed`` with every joint beyond MAX_JOINT_ANGLE (``ik7r.robot.family``) reduced modulo 2 pi
    to (-pi, pi] into ``out`` (seeds are periodic; such a value lies outside every joint's
    limits, so no turn is lost)."""
    for j in range(6):
        x = seed[j]
        out[j] = x if abs(x) <= MAX_JOINT_ANGLE else wrap(x)


@njit(allocates=True)
def select(sols, n, arm, elbow, wrist, seed, within_limits, K, q_out):
    """Pick the solution with the indicators nearest ``seed`` (wrapped distance; with
    ``within_limits`` the nearest multi-turn equivalent inside the limits, not wrapped);
    False when there is none."""
    best = -1.0
    cand = np.empty(6)
    found = False
    for s in range(n):
        if not matches(sols[s], arm, elbow, wrist):
            continue
        if within_limits:
            if not nearest_within_limits(sols[s], seed, K, cand):
                continue
        else:
            for j in range(6):
                cand[j] = sols[s, j]
        dist = 0.0
        for j in range(6):
            dj = cand[j] - seed[j]
            if not within_limits:
                dj = wrap(dj)
            dist += dj * dj
        if not found or dist < best - 1e-12:
            best = dist
            found = True
            for j in range(6):
                q_out[j] = cand[j]
    return found


# ---------------------------------------------------------------------- fused entry points
# One compiled call per public call: the Python side only allocates and raises.


@njit
def config_number(q):
    """Configuration number 1..8 of one solution ``q`` (6,): the one rule and numbering of
    :mod:`ik7r.geometry.configs` (what :func:`ik7r.geometry.configs.config_number` gives for arrays)."""
    arm, elbow, wrist = arm_elbow_wrist(q[0], q[2], q[4])
    return number_of(arm, elbow, wrist)


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
def ik_all_one(T, tol, K, Bm, bnorm, hint, has_hint, within_limits, sols, out):
    """Validate one pose ``T`` (4, 4), solve it and sort the solutions into ``sols``
    (MAX_SOLUTIONS rows, wrapped); with ``within_limits`` instead every multi-turn equivalent
    inside the limits, sorted, into ``out`` when it has room for them all (``sols`` unsorted).

    Returns ``(n, total)``: the number of solutions (-1 when ``T`` is not a valid pose, -2 when
    the hint is not finite: the caller says why) and, with ``within_limits``, the number of
    equivalents inside the limits (written to ``out`` only when ``total <= len(out)``; else the
    caller sizes an output and expands ``sols`` itself). A hint beyond MAX_JOINT_ANGLE is
    reduced (see :func:`reduced_seed`)."""
    clean = np.empty((4, 4))
    if validate_pose(T, tol, clean, np.empty((3, 3))) != 0:
        return -1, 0
    if has_hint and not _finite6(hint):
        return -2, 0
    h = np.empty(6)
    reduced_seed(hint, h)
    # solve_into, not its wrapper solve_all: each compiled caller level links and re-optimises
    # the whole solver below it, so a wrapper in between is a second compile of everything
    n = solve_into(clean, K, Bm, bnorm, h, has_hint, sols, -1, np.empty(WORK_SIZE))
    if not within_limits:
        sort_solutions(sols, n)
        return n, 0
    total = count_within_limits(sols, n, K)
    if total <= out.shape[0]:
        expand_within_limits(sols, n, K, out)
        sort_solutions(out, total)
    return n, total


@njit(allocates=True)
def ik_one(T, tol, K, Bm, bnorm, arm, elbow, wrist, hint, has_hint, within_limits, sols, q_out):
    """Validate one pose, solve it and pick the solution with the indicators nearest ``hint``.

    Returns ``(n, found)``: the number of solutions of the pose (left in ``sols``; -1 when
    ``T`` is not a valid pose, -2 when the hint is not finite) and whether one with the
    indicators was written to ``q_out``. A hint beyond MAX_JOINT_ANGLE is reduced (see
    :func:`reduced_seed`)."""
    clean = np.empty((4, 4))
    if validate_pose(T, tol, clean, np.empty((3, 3))) != 0:
        return -1, False
    if has_hint and not _finite6(hint):
        return -2, False
    h = np.empty(6)
    reduced_seed(hint, h)
    ws = np.empty(WORK_SIZE)  # solve_into directly (see ik_all_one)
    n = solve_into(clean, K, Bm, bnorm, h, has_hint, sols, 4 * arm + 2 * elbow + wrist, ws)
    found = select(sols[:max(1, n)], n, arm, elbow, wrist, h, within_limits, K, q_out)
    if not found:  # the whole solution set, for the caller's message
        n = solve_into(clean, K, Bm, bnorm, h, has_hint, sols, -1, ws)
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
