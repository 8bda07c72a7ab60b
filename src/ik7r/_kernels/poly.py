"""The residual polynomial of the virtual-wrist formulation, and certified real-root isolation.

For a pose (frame 0 <- 7: position ``p``, approach ``a``) and a virtual offset ``d`` the
virtual centre is ``P = p - (d7 + d) a`` and ``L = d4 + d``. A solution needs an arm placing
P at distance L along axis 4 (the arm-plane unknowns are theta1 and psi = theta2 + theta3)
with axis 4 at the bend angle ``phi(d)`` from ``a``: ``u . a = cos(phi) = 2 KW^2 / d^2 - 1``.
With ``rho = +-sqrt(Px^2 + Py^2 - b^2)`` fixing theta1, both remaining conditions are linear in
``(cos psi, sin psi)`` (see :func:`linear_system`); eliminating psi through
``cos^2 + sin^2 = 1`` leaves ``F(d, rho) = N1^2 + N2^2 - Det^2 = 0``, a polynomial in d and rho.

* zero shoulder, elbow and lateral offsets: F is even in rho, a polynomial of degree 8 in d
  (``G = F``); both shoulder branches share each root.
* otherwise ``G(d) = F(d, rho) F(d, -rho)`` is a polynomial of degree 16 in d.

Every solution's d is a real root of G in ``[KW, KW / cos(2 beta)]``; G has at most 8 (16) of
them, each giving at most 4 (2) solutions: at most 32 solutions per pose. G is sampled at
Chebyshev points (exact for a polynomial of that degree), converted to the Bernstein basis,
and its real roots are isolated by subdivision with Descartes' rule of signs: an interval
whose Bernstein coefficients all share a sign (beyond their rounding bound) holds no root;
one with exactly one sign change holds exactly one. Intervals that stay undecided down to
``WMIN`` (tangential roots, clusters) are all returned as candidates. No root can be missed:
the only intervals discarded are those proved root-free.
"""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .bernstein import bernstein_tables  # noqa: F401 (re-exported: its home until the compiled module)
from .jit import njit

WMIN = 1e-12  # smallest interval width of the subdivision, in units of the search interval
ZERO_WIDTH = 1e-5  # an interval zero within rounding is split further while wider than this
#: Samplings of :func:`isolate` after which an interval no wider than ZERO_WIDTH that its own
#: samples leave undecided is handed on undecided as well, not split down to WMIN: where the
#: residual stays within a few roundings of zero over a stretch (an exact member with the elbow
#: nearly stretched next to a 45 deg fold) every rounding wiggle was split to WMIN, 8,883
#: samplings and 8.6 ms for one pose (now 1,098 and 0.9 ms). Over 6,400 poses of eight robots
#: none took more than 795 (median 1 to 11).
ISOLATE_BUDGET = 1024
REFINE_GRID = 32  # grid of an undecided bracket: sign changes and local minima of |f|
MAX_DEGREE = 16
#: Size of the work array :func:`isolate` needs (degree up to MAX_DEGREE, a stack of 64).
ISOLATE_WORK = 64 * (MAX_DEGREE + 5) + 4 * (MAX_DEGREE + 1)


@njit
def linear_system(d, rho, p, a, K):
    """Coefficients of the two conditions linear in ``(cos psi, sin psi)`` at offset ``d`` on the
    shoulder branch ``rho`` (real, or complex when ``Px^2 + Py^2 < b^2``)::

        a11 cos + a12 sin = m     (elbow: |E - shoulder| = a2)
        a21 cos + a22 sin = c     (bend: u . a = cos(phi)), multiplied by r^2 d^2
    """
    a2 = K[L.A2]
    a3 = K[L.A3]
    e1 = K[L.EPS1]
    e3 = K[L.EPS3]
    kw = K[L.KW]
    t = K[L.D7] + d
    px = p[0] - t * a[0]
    py = p[1] - t * a[1]
    pz = p[2] - t * a[2]
    Ld = K[L.D4] + d
    r2 = px * px + py * py
    q = px * a[0] + py * a[1]
    w = py * a[0] - px * a[1]
    xx = rho - K[L.A1]
    xy = e1 * (pz - K[L.D1])
    m = 0.5 * (xx * xx + xy * xy + a3 * a3 + Ld * Ld - a2 * a2)
    a11 = a3 * xx - e3 * Ld * xy
    a12 = a3 * xy + e3 * Ld * xx
    a21 = -e1 * e3 * a[2] * r2 * d * d
    a22 = e3 * (rho * q - e1 * K[L.B] * w) * d * d
    c = (2.0 * kw * kw - d * d) * r2
    return a11, a12, m, a21, a22, c


@njit
def residual_F(d, rho, p, a, K):
    """``F = N1^2 + N2^2 - Det^2`` of :func:`linear_system` (zero exactly at solutions), and
    a bound on the magnitude of its terms (its rounding error is a few ulps of that bound)."""
    a11, a12, m, a21, a22, c = linear_system(d, rho, p, a, K)
    return eliminate_psi(a11, a12, m, a21, a22, c)


@njit
def residual_fixed_theta1(d, p, a, K):
    """F for the continuum case (axis 7 on axis 1, ``a = +-z``): theta1 is free, P' stays on
    axis 1 (rho = 0) and the bend condition reads ``-eps1 eps3 az cos(psi) = cos(phi)``."""
    a11, a12, m, a21, a22, c = linear_system(d, 0.0, p, a, K)
    a21, a22, c = bend_row_on_axis(d, a, K)
    return eliminate_psi(a11, a12, m, a21, a22, c)


@njit
def bend_row_on_axis(d, a, K):
    """The bend condition's row when P' is on axis 1 and ``a = +-z``, multiplied by d^2."""
    kw = K[L.KW]
    return -K[L.EPS1] * K[L.EPS3] * a[2] * d * d, 0.0, 2.0 * kw * kw - d * d


@njit
def eliminate_psi(a11, a12, m, a21, a22, c):
    """``N1^2 + N2^2 - Det^2`` of the 2 x 2 system, and the magnitude of its terms."""
    det = a11 * a22 - a12 * a21
    n1 = m * a22 - a12 * c
    n2 = a11 * c - a21 * m
    mag1 = abs(m * a22) + abs(a12 * c)
    mag2 = abs(a11 * c) + abs(a21 * m)
    mag3 = abs(a11 * a22) + abs(a12 * a21)
    return n1 * n1 + n2 * n2 - det * det, mag1 * mag1 + mag2 * mag2 + mag3 * mag3


@njit
def residual_G(d, p, a, K):
    """The residual polynomial G(d) (see the module docstring) and a bound on the magnitude
    of the terms it is computed from."""
    s2 = _rho_squared(d, p, a, K)
    if K[L.PRODUCT] == 0.0:
        return residual_F(d, math.sqrt(max(s2, 0.0)), p, a, K)
    if s2 >= 0.0:
        return _residual_F_pair(d, s2, p, a, K)
    return _residual_G_imaginary(d, math.sqrt(-s2), p, a, K)


@njit
def _rho_squared(d, p, a, K):
    """``rho^2 = Px^2 + Py^2 - b^2`` of the virtual centre at offset ``d``."""
    t = K[L.D7] + d
    px = p[0] - t * a[0]
    py = p[1] - t * a[1]
    return px * px + py * py - K[L.B] * K[L.B]


@njit
def _residual_F_pair(d, s2, p, a, K):
    """``G = F(d, s) F(d, -s)`` with ``s = sqrt(s2)``, ``s2 >= 0``, and its magnitude (no
    branches on the pose: a loop of it can be SIMD)."""
    s = math.sqrt(max(s2, 0.0))
    fp, mp = residual_F(d, s, p, a, K)
    fm, mm = residual_F(d, -s, p, a, K)
    return fp * fm, abs(fp) * mm + abs(fm) * mp + mp * mm * 1e-16


@njit
def _residual_G_imaginary(d, s, p, a, K):
    """:func:`residual_G` when ``Px^2 + Py^2 < b^2``: ``rho = i s`` and ``G = |F(d, i s)|^2``
    (the only place with complex arithmetic)."""
    f, mf = residual_F(d, complex(0.0, s), p, a, K)
    return f.real * f.real + f.imag * f.imag, 2.0 * abs(f) * mf + mf * mf * 1e-16


@njit
def residual_of(kind, u, p, a, K):
    """The residual in the search variable ``u = KW / d = cos(phi / 2)`` (value, term magnitude):
    kind 0 is :func:`residual_G`, 1 is :func:`residual_fixed_theta1`; 2 and 3 are the factors
    ``F(d, rho)`` and ``F(d, -rho)`` of G for robots with offsets (one shoulder branch each; NaN
    where rho is not real), whose near misses the product can hide (see
    :func:`ik7r._kernels.complete._near_misses`).

    ``u^n G(KW / u)`` is a polynomial of the same degree n in u, and u runs over the bounded
    interval ``[cos(2 beta), 1]`` for every wrist twist up to 45 deg (where d is unbounded).
    """
    u = off_zero(u)
    d = K[L.KW] / u
    if kind == 0:
        v, m = residual_G(d, p, a, K)
    elif kind == 1:
        v, m = residual_fixed_theta1(d, p, a, K)
    else:
        s2 = _rho_squared(d, p, a, K)
        if s2 < 0.0:
            return math.nan, math.nan
        v, m = residual_F(d, (1.0 if kind == 2 else -1.0) * math.sqrt(s2), p, a, K)
    scale = degree_power(u, K)
    return v * scale, m * scale


@njit
def off_zero(u):
    """``u`` moved to at least 1e-6 from zero (d beyond 1e6 KW: the value is rounding noise
    there anyway)."""
    return math.copysign(max(abs(u), 1e-6), u)


@njit
def degree_power(u, K):
    """``u^n`` for the degree n (8 or 16) of the residual."""
    u2 = u * u
    u4 = u2 * u2
    u8 = u4 * u4
    return u8 * u8 if K[L.NCHEB] > 8.0 else u8


@njit(vector=True)
def _residual_at_nodes(d0, d1, p, a, K, nodes, vals, mags):
    """:func:`residual_of` (kind 0) at the points ``nodes`` (in [-1, 1]) of [d0, d1], as
    SIMD loops. A magnitude with its sign bit set marks a value they could not give (complex
    shoulder branches: see :func:`_residual_G_imaginary`)."""
    mid = 0.5 * (d0 + d1)
    half = 0.5 * (d1 - d0)
    if K[L.PRODUCT] == 0.0:
        for j in range(nodes.shape[0]):
            u = off_zero(mid + half * nodes[j])
            d = K[L.KW] / u
            v, m = residual_F(d, math.sqrt(max(_rho_squared(d, p, a, K), 0.0)), p, a, K)
            scale = degree_power(u, K)
            vals[j] = v * scale
            mags[j] = m * scale
    else:
        for j in range(nodes.shape[0]):
            u = off_zero(mid + half * nodes[j])
            d = K[L.KW] / u
            s2 = _rho_squared(d, p, a, K)
            v, m = _residual_F_pair(d, s2, p, a, K)
            scale = degree_power(u, K)
            vals[j] = v * scale
            mags[j] = math.copysign(m * scale, s2)


#: Chebyshev-Lobatto points ``cos(pi j / n)`` of the two degrees the residual has (8, 16)
_NODES8 = np.cos(np.pi * np.arange(9) / 8)
_NODES16 = np.cos(np.pi * np.arange(17) / 16)


def _to_power(n: int) -> np.ndarray:
    """Matrix (n + 1, n + 1) taking Bernstein coefficients on [0, 1] to power-basis ones:
    ``c_k = C(n, k) sum_i (-1)^(k - i) C(k, i) b_i`` (integers, exact in floating point)."""
    P = np.zeros((n + 1, n + 1))
    for k in range(n + 1):
        for i in range(k + 1):
            P[k, i] = math.comb(n, k) * (-1) ** (k - i) * math.comb(k, i)
    return P


#: Bernstein -> power basis of the two degrees the residual has
_TO_POWER8 = _to_power(8)
_TO_POWER16 = _to_power(16)


@njit
def _bernstein(kind, d0, d1, p, a, K, Bmat, bnorm, b, vals, mags):
    """Bernstein coefficients ``b`` of the residual ``kind`` on [d0, d1], sampled at the
    Chebyshev points of that interval (into ``vals``, their term magnitudes into ``mags``);
    returns (rounding bound of b, 1.0 if some sample is nonzero beyond its own rounding else
    0.0)."""
    n = Bmat.shape[0] - 1
    nodes = _NODES8 if n == 8 else _NODES16  # the degree is 8 or 16
    if kind == 0:
        _residual_at_nodes(d0, d1, p, a, K, nodes, vals, mags)
    for j in range(n + 1):
        if kind != 0 or math.copysign(1.0, mags[j]) < 0.0:
            vals[j], mags[j] = residual_of(kind, 0.5 * (d0 + d1) + 0.5 * (d1 - d0) * nodes[j],
                                           p, a, K)
    magmax = 0.0
    big = 0.0  # 0 when every sample is zero within its own rounding (a continuum), else 1
    for j in range(n + 1):
        magmax = max(magmax, mags[j])
        if abs(vals[j]) > 64.0 * 2.220446049250313e-16 * mags[j]:
            big = 1.0
    for i in range(n + 1):
        s = 0.0
        for j in range(n + 1):
            s += Bmat[i, j] * vals[j]
        b[i] = s
    # each value errs by at most ~16 ulps of its term magnitude; the conversion multiplies the
    # errors by at most bnorm
    if not (magmax < 1e300):
        return np.inf, big
    return 64.0 * 2.220446049250313e-16 * bnorm * magmax, big


@njit
def _emit(blo, bhi, bsure, count, x0, x1, sure):
    """Append the bracket [x0, x1] (brackets come in ascending order). Undecided brackets
    that touch the previous undecided one are merged with it; when the storage is full the
    last bracket is extended instead (and marked undecided): nothing is ever dropped."""
    if count > 0 and not sure and bsure[count - 1] == 0.0 and x0 - bhi[count - 1] <= 1e-12 * (abs(x0) + 1.0):
        bhi[count - 1] = x1
        return count
    if count == blo.shape[0]:
        bhi[count - 1] = x1
        bsure[count - 1] = 0.0
        return count
    blo[count] = x0
    bhi[count] = x1
    bsure[count] = 1.0 if sure else 0.0
    return count + 1


@njit
def isolate(kind, d0, d1, p, a, K, Bmat, bnorm, blo, bhi, bsure, bcoef, work):
    """Brackets of every real root of the residual ``kind`` on [d0, d1].

    The residual is a polynomial of degree n (``Bmat`` is (n+1, n+1)): its interpolant at n+1
    Chebyshev points is exact. Intervals are subdivided (de Casteljau) and, where the rounding
    bound of the Bernstein coefficients leaves an interval undecided, re-sampled on that
    interval (the bound is then local). An interval whose coefficients all exceed the bound
    with one sign is root-free; one with exactly one sign change holds exactly one root
    (Descartes' rule of signs). Writes brackets ``[blo, bhi]`` (ascending, in d) and returns
    their number; ``bsure`` is 0.0 (else 1.0) for brackets no longer than ``WMIN`` that stayed
    undecided (a tangential root or a cluster); ``bcoef[k]`` (n + 1,) holds the Bernstein
    coefficients of a sure bracket on it (for :func:`newton_on_bracket`). Returns -1 when the residual is
    zero within rounding everywhere (a continuum of solutions). Only intervals proved
    root-free are discarded. ``work``: at least ISOLATE_WORK floats (``bsure`` too is floats:
    1.0 for sure).
    """
    n = Bmat.shape[0] - 1
    nb = n + 1
    stack = work[:64 * nb].reshape((64, nb))
    noise = work[64 * nb:64 * (nb + 1)]
    fresh = work[64 * (nb + 1):64 * (nb + 2)]  # 1.0 where sampled on the interval itself
    lo = work[64 * (nb + 2):64 * (nb + 3)]
    hi = work[64 * (nb + 3):64 * (nb + 4)]
    rest = 64 * (nb + 4)
    b = work[rest:rest + nb]
    tmp = work[rest + nb:rest + 2 * nb]
    vals = work[rest + 2 * nb:rest + 3 * nb]
    mags = work[rest + 3 * nb:rest + 4 * nb]
    noise[0], big = _bernstein(kind, d0, d1, p, a, K, Bmat, bnorm, b, vals, mags)
    sampled = 1
    if big == 0.0:
        return -1  # zero within rounding at every sample: a continuum
    for i in range(nb):
        stack[0, i] = b[i]
    fresh[0] = 1.0
    lo[0] = 0.0
    hi[0] = 1.0
    top = 1
    count = 0
    width = d1 - d0
    while top > 0:
        top -= 1
        t0 = lo[top]
        t1 = hi[top]
        bb = stack[top]
        nz = noise[top]
        npos = 0
        nneg = 0
        for i in range(nb):
            npos += bb[i] > nz
            nneg += bb[i] < -nz
        if npos == nb or nneg == nb:
            continue  # proved root-free
        if npos + nneg < nb and fresh[top] == 0.0 and t1 - t0 > WMIN:
            # undecided by the inherited bound: sample this interval afresh
            noise[top], _ = _bernstein(kind, d0 + width * t0, d0 + width * t1, p, a, K, Bmat,
                                       bnorm, b, vals, mags)
            sampled += 1
            for i in range(nb):
                stack[top, i] = b[i]
            fresh[top] = 1.0
            top += 1
            continue
        if (npos + nneg == 0 or npos + nneg < nb and sampled > ISOLATE_BUDGET) and t1 - t0 <= ZERO_WIDTH:
            # zero within rounding over the whole (freshly sampled) interval, or past the
            # budget undecided by its own samples: nothing more is decided here cheaply; hand
            # it to refine() as one undecided bracket
            count = _emit(blo, bhi, bsure, count, d0 + width * t0, d0 + width * t1, False)
            continue
        sure = False
        if npos + nneg == nb:
            var = 0
            for i in range(nb - 1):
                if (bb[i] > 0.0) != (bb[i + 1] > 0.0):
                    var += 1
            sure = var == 1  # exactly one root (Descartes' rule of signs)
        if sure or t1 - t0 <= WMIN or top + 2 > 64:
            count = _emit(blo, bhi, bsure, count, d0 + width * t0, d0 + width * t1, sure)
            if sure and bsure[count - 1] == 1.0:
                for i in range(nb):
                    bcoef[count - 1, i] = bb[i]
            continue
        # de Casteljau subdivision at the midpoint, in place: the right half replaces this
        # interval (row top), the left half goes above it, so that it is handled first
        # (ascending roots)
        for i in range(nb):
            tmp[i] = bb[i]
        left = stack[top + 1]
        for r in range(nb):
            left[r] = tmp[0]
            bb[nb - 1 - r] = tmp[nb - 1 - r]
            for i in range(nb - 1 - r):
                tmp[i] = 0.5 * (tmp[i] + tmp[i + 1])
        tm = 0.5 * (t0 + t1)
        fresh[top] = 0.0
        lo[top] = tm
        noise[top + 1] = nz
        fresh[top + 1] = 0.0
        lo[top + 1] = t0
        hi[top + 1] = tm
        top += 2
    return count


@njit
def secant_point(x0, x1, f0, f1):
    """The secant's zero between ``x0`` and ``x1`` (values ``f0``, ``f1`` of opposite signs), or
    their midpoint where rounding puts it outside."""
    x = (x0 * f1 - x1 * f0) / (f1 - f0)
    if not (min(x0, x1) < x < max(x0, x1)):
        x = 0.5 * (x0 + x1)
    return x


@njit
def illinois_step(x0, x1, f0, f1, side, x, fx):
    """One step of the Illinois (safeguarded secant) method: the bracket [x0, x1] with values
    ``f0``, ``f1`` of opposite signs shrunk to the new point ``x`` (value ``fx``, nonzero), the
    value kept at the end that stays twice in a row halved. ``side``: which end moved last
    (0 at the start). Returns (x0, x1, f0, f1, side, done); done when the bracket is down to
    the last bits. Every root finder on a bracket uses it (:func:`_illinois`,
    :func:`ik7r._kernels.gaps.gap_root`)."""
    if (fx > 0.0) == (f1 > 0.0):
        x1, f1 = x, fx
        if side == -1:
            f0 *= 0.5
        side = -1
    else:
        x0, f0 = x, fx
        if side == 1:
            f1 *= 0.5
        side = 1
    done = abs(x1 - x0) <= 4e-16 * max(abs(x0), abs(x1)) + 1e-300
    return x0, x1, f0, f1, side, done


@njit
def _illinois(kind, x0, x1, f0, f1, p, a, K):
    """The root of the residual ``kind`` bracketed by [x0, x1] (``f0``, ``f1`` of opposite signs)."""
    side = 0
    for _ in range(200):
        x = secant_point(x0, x1, f0, f1)
        fx = residual_of(kind, x, p, a, K)[0]
        if fx == 0.0:
            return x
        x0, x1, f0, f1, side, done = illinois_step(x0, x1, f0, f1, side, x, fx)
        if done:
            break
    return x0 if abs(f0) < abs(f1) else x1


@njit(allocates=True)
def refine(kind, d0, d1, p, a, K, out):
    """Roots of the residual ``kind`` at d (the true residual, not its interpolant) in an
    undecided bracket [d0, d1] (a sure one goes to :func:`newton_on_bracket`).

    Sign changes on a grid of the bracket are refined to full precision; without any, the grid
    point of least ``|f|`` (a tangential root) is returned, refined to the least ``|f|``.
    Writes to ``out``, returns the count (at least 1)."""
    m = REFINE_GRID
    xs = np.empty(m + 1)
    fs = np.empty(m + 1)
    for i in range(m + 1):
        xs[i] = d0 + (d1 - d0) * i / m
        fs[i] = residual_of(kind, xs[i], p, a, K)[0]
    count = 0
    for i in range(m + 1):
        if count >= out.shape[0]:
            break
        if fs[i] == 0.0:
            out[count] = xs[i]
            count += 1
        elif i < m and fs[i] * fs[i + 1] < 0.0:
            out[count] = _illinois(kind, xs[i], xs[i + 1], fs[i], fs[i + 1], p, a, K)
            count += 1
        elif (fs[i] != 0.0 and (i == 0 or abs(fs[i]) <= abs(fs[i - 1]))
              and (i == m or abs(fs[i]) <= abs(fs[i + 1]))):
            # a local minimum of |f| without a sign change: a tangential root or a near miss
            # (a candidate; the forward kinematics decides)
            out[count] = least_abs(kind, xs[max(0, i - 1)], xs[min(m, i + 1)], p, a, K)
            count += 1
    return count


@njit
def newton_on_bracket(kind, d0, d1, bb, p, a, K, w):
    """The one root in [d0, d1] of a bracket whose interpolant ``bb`` (Bernstein coefficients
    with one sign change) is known: Newton's method on the interpolant (safeguarded by
    bisection) gives a start within rounding of the root, which Newton steps on the true
    residual (with the interpolant's slope) finish in one or two evaluations. Falls back to
    the safeguarded secant on the whole bracket when those steps misbehave. ``w``: work array
    of the size of ``bb``."""
    n = bb.shape[0] - 1
    up = bb[n] > bb[0]  # the interpolant rises through its root
    s = 0.5
    for i in range(n):  # start where the control polygon crosses zero
        if (bb[i] > 0.0) != (bb[i + 1] > 0.0):
            s = (i + bb[i] / (bb[i] - bb[i + 1])) / n
            break
    # power-basis coefficients on [0, 1]: a start for the true residual needs no more
    # accuracy than this conversion keeps
    P = _TO_POWER8 if n == 8 else _TO_POWER16  # the degree is 8 or 16
    for k in range(n + 1):
        c = 0.0
        for i in range(n + 1):  # (the whole row: a fixed trip count, P is lower triangular)
            c += P[k, i] * bb[i]
        w[k] = c
    s_lo = 0.0
    s_hi = 1.0
    slope = 0.0
    for _ in range(60):
        v = w[n]
        slope = 0.0
        for k in range(n - 1, -1, -1):
            slope = slope * s + v
            v = v * s + w[k]
        if v == 0.0:
            break
        if (v > 0.0) == up:
            s_hi = s
        else:
            s_lo = s
        step = v / slope if slope != 0.0 else 1.0
        s_new = s - step
        if not (s_lo < s_new < s_hi):
            s_new = 0.5 * (s_lo + s_hi)
            if s_hi - s_lo <= 1e-15:
                break
        elif abs(step) <= 1e-8:
            s = s_new  # converging quadratically: this step leaves an error of order step^2
            break
        s = s_new
    width = d1 - d0
    x = d0 + width * s
    slope_x = slope / width
    if slope_x != 0.0 and math.isfinite(slope_x):
        for _ in range(4):
            f = residual_of(kind, x, p, a, K)[0]
            if f == 0.0:
                return x
            step = f / slope_x
            x_new = x - step
            if not (d0 <= x_new <= d1):
                break
            if abs(step) <= 1e-10 * (abs(x) + abs(width)):
                # the start was within 1e-10 of the root: one Newton step (quadratic, with
                # the interpolant's slope) leaves only rounding; the candidate it gives is
                # verified on the forward kinematics anyway
                return x_new
            x = x_new
    f0 = residual_of(kind, d0, p, a, K)[0]
    f1 = residual_of(kind, d1, p, a, K)[0]
    if f0 * f1 < 0.0:
        return _illinois(kind, d0, d1, f0, f1, p, a, K)
    return x


#: Golden-section fraction of Brent's minimiser, and its relative tolerance (in units of the
#: bracket: values at a smooth minimum are flat to rounding closer than about sqrt(eps))
_CGOLD = 0.5 * (3.0 - math.sqrt(5.0))
_BRENT_TOL = 1e-9


@njit
def brent_start(lo, hi):
    """The state of Brent's minimiser (golden section with parabolic steps) on [lo, hi], and the
    first point to evaluate. The state is ``(a, b, x, w, v, fx, fw, fv, d, e, tol)``; evaluate
    ``f`` at the point returned and pass it to :func:`brent_take`, then ask :func:`brent_next`
    for the next point until it says done: ``x`` (state[2]) is then the least point found,
    ``fx`` (state[5]) its value. Every minimiser of a bracket uses it (:func:`least_abs`,
    :func:`ik7r._kernels.gaps.gap_min`): about 10 to 40 values where plain golden section
    took 100 or more. ``lo`` and ``hi`` may come in either order (a scan toward smaller values
    gives them so; its stopping test, taken as given, stopped at the first point)."""
    if hi < lo:
        lo, hi = hi, lo
    x = lo + _CGOLD * (hi - lo)
    inf = math.inf
    tol = _BRENT_TOL * (hi - lo) + 4.4e-16 * max(abs(lo), abs(hi)) + 1e-300  # (not below float spacing)
    return (lo, hi, x, x, x, inf, inf, inf, 0.0, 0.0, tol), x


@njit
def brent_next(st):
    """The next point of Brent's minimiser in state ``st`` (see :func:`brent_start`): returns
    (state, point, done)."""
    a, b, x, w, v, fx, fw, fv, d, e, tol = st
    m = 0.5 * (a + b)
    t2 = 2.0 * tol
    if abs(x - m) <= t2 - 0.5 * (b - a):
        return st, x, True
    p = 0.0
    q = 0.0
    r = 0.0
    # try a parabola through x, w, v (not through a point where f is undefined: +inf would give
    # nan, which the tests below reject as well, but with a warning in pure Python)
    if abs(e) > tol and fw < math.inf and fv < math.inf:
        r = (x - w) * (fx - fv)
        q = (x - v) * (fx - fw)
        p = (x - v) * q - (x - w) * r
        q = 2.0 * (q - r)
        if q > 0.0:
            p = -p
        else:
            q = -q
        r = e
        e = d
    if abs(p) < abs(0.5 * q * r) and p > q * (a - x) and p < q * (b - x):
        d = p / q
        u = x + d
        if u - a < t2 or b - u < t2:
            d = tol if x < m else -tol
    else:  # a golden-section step into the larger part
        e = b - x if x < m else a - x
        d = _CGOLD * e
    u = x + (d if abs(d) >= tol else (tol if d > 0.0 else -tol))
    return (a, b, x, w, v, fx, fw, fv, d, e, tol), u, False


@njit
def brent_take(st, u, fu):
    """Brent's minimiser's state ``st`` with the value ``fu`` at the point ``u`` it asked for
    (``+inf`` where the function is not defined; a NaN counts as that, else it would stop the
    search at the first point: no value compares below it)."""
    a, b, x, w, v, fx, fw, fv, d, e, tol = st
    if not fu <= math.inf:
        fu = math.inf
    if fx == math.inf and u == x and fw == math.inf:  # the first value
        return (a, b, x, x, x, fu, fu, fu, d, e, tol)
    if fu <= fx:
        if u < x:
            b = x
        else:
            a = x
        v, fv = w, fw
        w, fw = x, fx
        x, fx = u, fu
    else:
        if u < x:
            a = u
        else:
            b = u
        if fu <= fw or w == x:
            v, fv = w, fw
            w, fw = u, fu
        elif fu <= fv or v == x or v == w:
            v, fv = u, fu
    return (a, b, x, w, v, fx, fw, fv, d, e, tol)


@njit
def least_abs(kind, lo, hi, p, a, K):
    """The least ``|f|`` of the residual ``kind`` in [lo, hi] (Brent's minimiser)."""
    st, u = brent_start(lo, hi)
    for _ in range(200):
        st = brent_take(st, u, abs(residual_of(kind, u, p, a, K)[0]))
        st, u, done = brent_next(st)
        if done:
            break
    return st[2]
