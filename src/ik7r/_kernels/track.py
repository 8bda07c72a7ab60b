"""Compiled kernel of warm-started path IK: each pose from the previous solution.

A Newton step on the full forward kinematics continues the previous solution; it is taken
only when it verifies (FK within the robot's tolerances), keeps the configuration's
indicators, stays within the joint limits when asked, and moves no joint more than
``max_step``. Otherwise the pose goes to the complete solver and the solution with the
indicators nearest the previous one is taken. Either way every returned row is exact.
"""

from __future__ import annotations

import numpy as np

from . import params as L
from .complete import solve_into
from .constants import WORK_SIZE, wrap
from .fk import polish_into
from .jit import njit
from .select import matches, select

TRACK_ITERATIONS = 6


@njit
def _within(q, K):
    for j in range(6):
        if q[j] < K[L.LIMITS + j] or q[j] > K[L.LIMITS + 6 + j]:
            return False
    return True


@njit(allocates=True)
def track_path(Ts, K, Bm, bnorm, arm, elbow, wrist, seed, has_seed, within_limits, max_step,
               ok_in, q_out, ok_out, tracked_out):
    """Solve the poses ``Ts`` (N, 4, 4) in order, each from the previous solution.

    Rows are continuous (not wrapped): a joint that turns past pi keeps turning. ``ok_out[i]``
    is False when pose i is bad (``ok_in``) or has no solution with the indicators (within the
    limits when asked); ``tracked_out[i]`` is True when the warm start was enough. Returns
    the number of poses that needed the complete solver.
    """
    n = Ts.shape[0]
    prev = np.empty(6)
    vel = np.zeros(6)  # last step, to predict the next solution (linear extrapolation)
    q = np.empty(6)
    T_ = np.empty((4, 4))
    J_ = np.empty((6, 6))
    e_ = np.empty(6)
    dq_ = np.empty(6)
    keep = np.empty(6)
    zo_ = np.empty((7, 6))
    sols = np.empty((L.MAX_SOLUTIONS, 6))
    ws = np.empty(WORK_SIZE)  # the solver's scratch, once for the path (not once per pose)
    filt = 4 * arm + 2 * elbow + wrist
    have_prev = has_seed
    for j in range(6):
        prev[j] = seed[j]
    full = 0
    for i in range(n):
        ok_out[i] = False
        tracked_out[i] = False
        for j in range(6):
            q_out[i, j] = np.nan
        if not ok_in[i]:
            continue
        done = False
        if have_prev:
            for j in range(6):
                q[j] = prev[j] + vel[j]
            exact = polish_into(q, Ts[i], K, TRACK_ITERATIONS, T_, J_, e_, dq_, zo_)
            if exact and matches(q, arm, elbow, wrist):
                step = 0.0
                for j in range(6):
                    step = max(step, abs(q[j] - prev[j]))
                if step <= max_step and (not within_limits or _within(q, K)):
                    done = True
                    tracked_out[i] = True
        if not done:
            full += 1
            m = solve_into(Ts[i], K, Bm, bnorm, prev, have_prev, sols, filt, ws)
            if select(sols, m, arm, elbow, wrist, prev, within_limits, K, q):
                if have_prev and not within_limits:
                    for j in range(6):  # continue the previous turn of every joint
                        keep[j] = q[j]
                        q[j] = prev[j] + wrap(q[j] - prev[j])
                    # the shifted joints are verified too (a far turn rounds them); when they
                    # miss, the exact wrapped solution is kept
                    if not polish_into(q, Ts[i], K, 0, T_, J_, e_, dq_, zo_):
                        for j in range(6):
                            q[j] = keep[j]
                done = True
        if done:
            ok_out[i] = True
            for j in range(6):
                q_out[i, j] = q[j]
                vel[j] = q[j] - prev[j] if (have_prev and tracked_out[i]) else 0.0
                prev[j] = q[j]
            have_prev = True
    return full
