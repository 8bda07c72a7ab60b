"""Compiled kernels that pick solutions: indicators, joint limits and multi-turn joints,
nearest to a seed; and the batch drivers built on :func:`ik7r._complete.solve_all`."""

from __future__ import annotations

import math

import numpy as np

from . import _layout as L
from ._complete import solve_all, wrap
from ._jit import njit

HALF_PI = 0.5 * math.pi
SINGULAR_WRIST = 1e-9  # |q5| (or |q5| - pi) below this: both Wrist indicators name the pose


@njit
def matches(q, arm, elbow, wrist):
    """True when ``q`` has the indicators (arm, elbow, wrist); a straight (q5 = 0) or fully
    bent (q5 = pi) wrist matches both Wrist values (its two wrist solutions are one)."""
    q1 = wrap(q[0])
    q3 = wrap(q[2])
    q5 = wrap(q[4])
    a = 1 if -HALF_PI <= q1 < HALF_PI else 0
    e = 1 if -HALF_PI <= q3 < HALF_PI else 0
    if a != arm or e != elbow:
        return False
    if abs(q5) < SINGULAR_WRIST or math.pi - abs(q5) < SINGULAR_WRIST:
        return True
    w = 1 if 0.0 <= q5 < math.pi else 0
    return w == wrist


@njit
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


@njit
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


@njit
def solve_config_batch(Ts, K, Bm, bnorm, arm, elbow, wrist, seeds, has_seed,
                       within_limits, ok_in, q_out, ok_out):
    """One configuration for every pose of ``Ts`` (N, 4, 4); rows with ``ok_in`` False are
    skipped. ``seeds`` (N, 6) chooses among solutions sharing the indicators."""
    sols = np.empty((L.MAX_SOLUTIONS, 6))
    for i in range(Ts.shape[0]):
        ok_out[i] = False
        if not ok_in[i]:
            continue
        n = solve_all(Ts[i], K, Bm, bnorm, seeds[i], has_seed, sols)
        ok_out[i] = select(sols, n, arm, elbow, wrist, seeds[i], within_limits, K, q_out[i])
