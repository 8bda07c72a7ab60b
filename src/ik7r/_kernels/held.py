"""The exact model's least error over the turn of q1 with the wrist held fully bent, for robots
that deviate from the idealised family.

At the fully bent wrist of a 45 deg twist with the approach along axis 1, axes 1, 4 and 7 are
(nearly) parallel and the Jacobian loses two ranks: one for the fold (a bend there is taken up
by joints 4 and 7 to first order) and one for the turn about axis 1. The reduced residual of
:mod:`.reduced` (q1 held, the five other joints fitted) is not defined there: the fitted point
slides along the fold, and ``det [J_other | e]`` vanishes along the whole fold whatever the
error. With joint 5 held at the fold as well, the four other joints are determined, and the
least error over them is a function of q1 alone whose dips hold the exact solutions beside the
fold (``held_fold_turn``).
"""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .answers import accept, apart
from .constants import (
    HELD_CELLS,
    HELD_DIP,
    HELD_NEAR,
    HELD_SAME,
    HELD_SEEN,
    HELD_SETTLE,
    HELD_SIDE_FAR,
    HELD_SIDE_NEAR,
    HELD_SLOPE,
    HELD_STEPS,
    HELD_SUB_DIP,
    TWO_PI,
    wrap,
)
from .fk import fk_user, polish_into, residual
from .jit import njit
from .poly import brent_next, brent_start, brent_take

#: The joints fitted with q1 and q5 held (bit ``i``: joint ``i + 1``, see :func:`polish`): q2,
#: q3, q4 and q7.
HELD_MOVING = 0b101110


@njit
def held_error(x, v, Td, K, T, J, e, dq, ZO):
    """The least error of the pose ``Td`` with q1 at ``v`` and q5 held at ``x[4]``: q2, q3, q4
    and q7 fitted by Gauss-Newton from ``x`` (in place, HELD_STEPS at most, stopping below
    HELD_SETTLE rad); the error is the position's over the robot's size or the rotation's (rad),
    the larger. ``T`` (4, 4), ``J`` (6, 6), ``e``, ``dq`` (6,) and ``ZO`` (7, 6) are work arrays."""
    x[0] = v
    polish_into(x, Td, K, HELD_STEPS, T, J, e, dq, ZO, True, 0, HELD_SETTLE, HELD_MOVING)
    fk_user(x, K, T)
    dp, dr = residual(T, Td)
    err = max(dp / K[L.SCALE], dr)
    return err if err < 1e300 else math.inf  # (NaN: no fit)


@njit(allocates=True)
def held_fold_turn(start, m, Td, K, out, count, mats, seen, arm):
    """Every exact solution beside the fully bent wrist that the least error with q5 held
    (:func:`held_error`) dips to over the whole turn of q1: tracked from ``start`` (user
    angles: ``start[0]`` the first grid point's q1, ``start[4]`` the fold) on ``m`` cells; each
    grid point below HELD_DIP and lower than both neighbours is a dip, the two cells beside it
    are searched again on HELD_CELLS cells (two dips can share a cell), each dip of those below
    HELD_SUB_DIP is taken to its bottom by Brent's minimiser, and a bottom below HELD_NEAR is polished
    with joint 5 free (:func:`ik7r._kernels.answers.accept`) from the wrist HELD_SIDE_NEAR and
    HELD_SIDE_FAR to either side of the fold: a pair of solutions lies there, on one side of it
    or on both. ``seen`` (HELD_SEEN + 1, 6): the fits at the dips an earlier turn of the pose
    searched (rows 1.., their count in ``seen[0, 0]``); a dip whose fit is within HELD_SAME of
    one is that dip and is not searched again (the turns from both elbows' arms often track one
    curve). Returns the new count, and whether the first point's fit stayed within ``arm`` (rad)
    of the start's arm (q2, q3): where it did not, nothing was tracked."""
    T = np.empty((4, 4))
    J = np.empty((6, 6))
    ZO = np.empty((7, 6))
    e = np.empty(6)
    dq = np.empty(6)
    x = np.empty(6)
    qs = np.empty((m + 2, 6))
    gs = np.empty(m + 2)
    sub_q = np.empty((HELD_CELLS + 1, 6))
    sub_g = np.empty(HELD_CELLS + 1)
    qc = np.empty(6)
    h = TWO_PI / m
    for i in range(6):
        x[i] = start[i]
    held_error(x, start[0], Td, K, T, J, e, dq, ZO)
    if abs(wrap(x[1] - start[1])) > arm or abs(wrap(x[2] - start[2])) > arm:
        return count, False
    # (one cell past the turn: a dip at its start has both neighbours)
    _held_scan(x, start[0], h, qs, gs, Td, K, T, J, e, dq, ZO)
    for k in range(1, m + 1):
        if not (gs[k] < HELD_DIP and gs[k] <= gs[k - 1] and gs[k] <= gs[k + 1]):
            continue
        if _seen_dip(qs[k], seen):
            continue
        # the two cells beside the dip on a finer grid
        v0 = qs[k - 1, 0]
        hs = 2.0 * h / HELD_CELLS
        _held_scan(qs[k - 1], v0, hs, sub_q, sub_g, Td, K, T, J, e, dq, ZO)
        for s in range(1, HELD_CELLS):
            if not (sub_g[s] < HELD_SUB_DIP and sub_g[s] <= sub_g[s - 1]
                    and sub_g[s] <= sub_g[s + 1]):
                continue
            for i in range(6):
                x[i] = sub_q[s, i]
            slope = max(sub_g[s - 1] - sub_g[s], sub_g[s + 1] - sub_g[s]) / hs
            g = _bottom(x, v0 + (s - 1) * hs, v0 + (s + 1) * hs, HELD_SLOPE * slope, Td, K, T, J,
                        e, dq, ZO)
            if not g < HELD_NEAR:
                continue
            for side in (-HELD_SIDE_FAR, -HELD_SIDE_NEAR, HELD_SIDE_NEAR, HELD_SIDE_FAR):
                for i in range(6):
                    qc[i] = x[i]
                qc[4] += side
                count, _ = accept(qc, Td, K, out, count, mats, False, False)
    return count, True


@njit
def _seen_dip(q, seen):
    """Whether the fit ``q`` at a dip is within HELD_SAME of one in ``seen`` (see
    :func:`held_fold_turn`); if not, it is added there (while there is room)."""
    n = int(seen[0, 0])
    for s in range(1, n + 1):
        if apart(q, seen[s]) < HELD_SAME:
            return True
    if n < HELD_SEEN:
        for i in range(6):
            seen[n + 1, i] = q[i]
        seen[0, 0] = n + 1
    return False


@njit
def _held_scan(start, v0, h, qs, gs, Td, K, T, J, e, dq, ZO):
    """:func:`held_error` at q1 = ``v0 + k h`` for each row ``k`` of ``qs`` (the fits, out) and
    ``gs`` (the errors, out), each point fitted from the extrapolation of the two before it
    (the first from ``start``, the second from the first)."""
    x = qs[0]
    for i in range(6):
        x[i] = start[i]
    gs[0] = held_error(x, v0, Td, K, T, J, e, dq, ZO)
    for k in range(1, len(gs)):
        x = qs[k]
        for i in range(6):
            x[i] = 2.0 * qs[k - 1, i] - qs[k - 2, i] if k > 1 else qs[0, i]
        x[4] = start[4]
        gs[k] = held_error(x, v0 + k * h, Td, K, T, J, e, dq, ZO)


@njit
def _bottom(x, lo, hi, lip, Td, K, T, J, e, dq, ZO):
    """The least :func:`held_error` over q1 in [lo, hi] (a dip of a grid) by Brent's minimiser
    (:func:`ik7r._kernels.poly.brent_start`), each point fitted from the last; ``x`` (in: a fit
    inside the bracket) ends fitted at the bottom. Returns the least error there, or as soon as
    the least value found less ``lip`` (a bound on the error's slope) times the bracket's width
    stays above HELD_NEAR, that value: no bottom below HELD_NEAR is left in it."""
    st, u = brent_start(lo, hi)
    for _ in range(200):
        st = brent_take(st, u, held_error(x, u, Td, K, T, J, e, dq, ZO))
        if st[5] - lip * (st[1] - st[0]) > HELD_NEAR:
            return st[5]
        st, u, done = brent_next(st)
        if done:
            break
    return held_error(x, st[2], Td, K, T, J, e, dq, ZO)
