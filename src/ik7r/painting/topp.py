"""Time-optimal path parameterisation (TOPP) under joint speed and acceleration limits.

Given a joint path ``q(s)`` on a grid ``s_0 < ... < s_N`` of its parameter, find the fastest
``x(s) = sdot^2`` with, per grid interval, a constant path acceleration ``a_i = sddot``
(``x_{i+1} = x_i + 2 (s_{i+1} - s_i) a_i``) such that

* joint speeds ``|q'(s) sdot| <= v_max`` at every grid point,
* joint accelerations ``|q''(s) x + q'(s) a_i| <= a_max`` at *both ends* of every interval
  (toppra's "interpolation" discretisation), and
* ``x <= cap`` at every grid point (a commanded path speed, 0 at a stop).

This is the reachability analysis of TOPP-RA (Pham and Pham, IEEE T-RO 2018, the algorithm of
the ``toppra`` package, which the tests use as the reference): a backward pass computes, for
every grid point, the interval of ``x`` from which the end state can still be reached; a
forward pass then takes the largest admissible ``x`` at each next point. The two-variable
linear programs of the backward pass are solved in closed form: with ``y = x_{i+1}`` every
acceleration row reads ``lo <= c x + d y <= hi``, so ``y`` lies between lower and upper lines
in ``x``, and the projection onto ``x`` is the set where every lower line stays below every
upper line (one linear inequality per pair). The limits hold at the grid points; between them
the caller checks densely (:mod:`ik7r.painting.interpolate`).
"""

from __future__ import annotations

import numpy as np

from ..errors import Ik7rError

__all__ = ["topp", "TOPPInfeasible", "profile_times"]


class TOPPInfeasible(Ik7rError, ValueError):
    """No admissible speed profile: the path cannot be followed within the limits from the
    given start state to the given end state (``index`` is the grid point where it fails)."""

    def __init__(self, index: int, message: str):
        self.index = int(index)
        super().__init__(message)


def _rows(ds, dq0, ddq0, dq1, ddq1, amax):
    """Acceleration rows ``lo <= c x + d y <= hi`` per interval: ``(c, d, hi)`` of shape (N, 2J)."""
    h = 2.0 * ds[:, None]
    c = np.concatenate([ddq0 - dq0 / h, -dq1 / h], axis=1)
    d = np.concatenate([dq0 / h, ddq1 + dq1 / h], axis=1)
    hi = np.broadcast_to(np.concatenate([amax, amax]), c.shape)
    return c, d, hi


def _lines(c, d, hi, scale):
    """Lower and upper lines ``y >= mL x + bL``, ``y <= mU x + bU`` of the rows with ``d != 0``
    (others: ``bL = -inf``, ``bU = +inf``, ``m = 0``), and the bound on ``x`` of rows with
    ``d = 0`` (``|c| x <= hi``)."""
    ok = np.abs(d) > 1e-12 * scale
    dd = np.where(ok, d, 1.0)
    m = np.where(ok, -c / dd, 0.0)
    lo_over = np.where(d > 0, -hi, hi) / dd
    hi_over = np.where(d > 0, hi, -hi) / dd
    bL = np.where(ok, lo_over, -np.inf)
    bU = np.where(ok, hi_over, np.inf)
    ac = np.abs(c)
    x_only = np.where(~ok & (ac > 0), hi / np.where(ac > 0, ac, 1.0), np.inf).min(axis=1)
    return m, bL, bU, x_only


def _interval(alpha, beta):
    """The set of ``x`` with ``alpha x <= beta`` for every pair (last axis): (lo, hi)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        r = beta / alpha
    up = np.where(alpha > 0, r, np.inf).min(axis=-1)
    low = np.where(alpha < 0, r, -np.inf).max(axis=-1)
    bad = np.any((alpha == 0) & (beta < 0), axis=-1)
    return np.where(bad, np.inf, low), np.where(bad, -np.inf, up)


def topp(s, dq0, ddq0, dq1, ddq1, vmax, amax, cap=None, *, x_start: float = 0.0,
         x_end: float = 0.0) -> np.ndarray:
    """The time-optimal ``x = sdot^2`` at the grid points.

    Parameters
    ----------
    s : ndarray, shape (N + 1,)
        Grid of the path parameter, increasing.
    dq0, ddq0 : ndarray, shape (N, J)
        ``q'`` and ``q''`` at the start of every interval (on the interval's own side: the path
        may have corners at grid points).
    dq1, ddq1 : ndarray, shape (N, J)
        ``q'`` and ``q''`` at the end of every interval.
    vmax, amax : ndarray, shape (J,)
        Joint speed and acceleration limits (> 0).
    cap : ndarray, shape (N + 1,), optional
        Upper bounds on ``x`` (``inf``: none; 0: a stop).
    x_start, x_end : float
        ``x`` at both ends (0: at rest).

    Returns
    -------
    x : ndarray, shape (N + 1,)

    Raises
    ------
    TOPPInfeasible
        The end state cannot be reached within the limits.
    """
    s = np.asarray(s, dtype=float)
    ds = np.diff(s)
    n = len(ds)
    vmax = np.asarray(vmax, dtype=float)
    amax = np.asarray(amax, dtype=float)
    # speed limits at the grid points, both sides
    with np.errstate(divide="ignore"):
        v0 = np.min((vmax / np.abs(dq0)) ** 2, axis=1)
        v1 = np.min((vmax / np.abs(dq1)) ** 2, axis=1)
    xb = np.full(n + 1, np.inf)
    xb[:-1] = np.minimum(xb[:-1], v0)
    xb[1:] = np.minimum(xb[1:], v1)
    if cap is not None:
        xb = np.minimum(xb, np.asarray(cap, dtype=float))
    c, d, hi = _rows(ds, dq0, ddq0, dq1, ddq1, amax)
    scale = float(np.max(np.abs(d))) if d.size else 1.0
    m, bL, bU, x_only = _lines(c, d, hi, scale)
    # pairs of rows (independent of the next reachable set): mL_p x - mU_q x <= bU_q - bL_p
    alpha = (m[:, :, None] - m[:, None, :]).reshape(n, -1)
    with np.errstate(invalid="ignore"):
        beta = (bU[:, None, :] - bL[:, :, None]).reshape(n, -1)
    beta = np.where(np.isnan(beta), np.inf, beta)
    A, B = _interval(alpha, beta)
    A = np.maximum(A, 0.0)
    B = np.minimum(np.minimum(B, x_only), xb[:-1])
    finite_bL = np.isfinite(bL)
    finite_bU = np.isfinite(bU)

    kmin = np.empty(n + 1)
    kmax = np.empty(n + 1)
    tol = 1e-9
    if x_end > xb[n] * (1 + tol) + tol:
        raise TOPPInfeasible(n, f"the end speed^2 {x_end:g} exceeds the bound {xb[n]:g} at the end")
    kmin[n] = kmax[n] = x_end
    for i in range(n - 1, -1, -1):
        lo_k, hi_k = kmin[i + 1], kmax[i + 1]
        # kmin <= U_q(x):  -mU_q x <= bU_q - kmin ; L_p(x) <= kmax:  mL_p x <= kmax - bL_p
        al = np.concatenate([-m[i][finite_bU[i]], m[i][finite_bL[i]]])
        be = np.concatenate([bU[i][finite_bU[i]] - lo_k, hi_k - bL[i][finite_bL[i]]])
        lo, up = _interval(al[None], be[None])
        lo = max(float(lo[0]), A[i])
        up = min(float(up[0]), B[i])
        if up < lo:
            if lo - up <= tol * max(1.0, abs(lo)):
                up = lo
            else:
                raise TOPPInfeasible(i, f"no admissible speed at grid point {i} (s = {s[i]:.6g})")
        kmin[i], kmax[i] = lo, up
    if not kmin[0] - tol * max(1.0, kmin[0]) <= x_start <= kmax[0] * (1 + tol) + tol:
        raise TOPPInfeasible(0, f"the start speed^2 {x_start:g} is outside the reachable "
                                f"[{kmin[0]:g}, {kmax[0]:g}]")
    x = np.empty(n + 1)
    x[0] = x_start
    for i in range(n):
        xi = x[i]
        sel = finite_bU[i]
        y = min(kmax[i + 1], float(np.min(m[i][sel] * xi + bU[i][sel])) if np.any(sel) else np.inf)
        selL = finite_bL[i]
        y_lo = max(kmin[i + 1], float(np.max(m[i][selL] * xi + bL[i][selL])) if np.any(selL) else -np.inf)
        x[i + 1] = max(y, y_lo, 0.0)
    x[n] = x_end
    return x


def profile_times(s, x) -> np.ndarray:
    """Times at the grid points of the profile ``x = sdot^2`` (constant ``sddot`` per interval):
    ``dt = 2 ds / (sqrt(x_i) + sqrt(x_{i+1}))``."""
    v = np.sqrt(np.maximum(np.asarray(x, dtype=float), 0.0))
    den = v[:-1] + v[1:]
    if np.any(den <= 0):
        i = int(np.flatnonzero(den <= 0)[0])
        raise TOPPInfeasible(i, f"the speed is zero at both ends of grid interval {i}")
    return np.concatenate([[0.0], np.cumsum(2.0 * np.diff(s) / den)])
