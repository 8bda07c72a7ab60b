"""The gap functions the scans search: scalar, continuous on an arm branch, zero at a solution.

The bend gap in theta5 (``bend_gap``: the bend the arm's frame asks for, minus theta5), the
shoulder gap in theta1 (``shoulder_gap``, where the line of virtual centres passes near axis 1),
and the fold gap near the fully bent wrist of a (nearly) 45 deg twist (``fold_gap``, in
``sw = sin(theta5 / 2)`` scaled, finite where the virtual centre runs off to infinity); ``gap``
picks one by its kind, ``gap_root`` and ``gap_min`` refine a sign change and a dip, and
``branch_end`` finds where an arm branch stops reaching.
"""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .arm import arm_cs, arm_params, arm_reach, elbow_cosine, inside_cylinder, shoulder_angle
from .constants import (
    DIP_EARLY,
    FOLD_AXIS_CLAMP,
    FOLD_AXIS_NEAR,
    FOLD_BELOW,
    FOLD_SPAN,
    LATERAL_ROUNDING,
    LATERAL_SHOULDER_DEVIATING,
    REACH_SLACK_DEVIATING,
    SCAN_TINY,
)
from .jit import njit
from .poly import brent_next, brent_start, brent_take, illinois_step, secant_point
from .singular import d_near_range, deviation_widening, u_fold
from .wrist import theta5_cs_of_d


@njit
def _bend_centre(t5, p, a, K, t1_hint=0.0, in_plane=False):
    """The virtual centre of the wrist bent by ``t5`` >= 0 (as :func:`bend_gap` takes it, with
    ``t1_hint``, ``in_plane``): (x, d, px, py, pz, ok), ``x = sin(beta) sin(t5 / 2)``, ``d`` the
    virtual offset; ok is False at the fold of a 45 deg twist (the centre is at infinity)."""
    x = K[L.SB] * math.sin(0.5 * t5)
    h = 1.0 - 2.0 * x * x  # cos(phi / 2)
    if h < 1e-9:
        return x, 0.0, 0.0, 0.0, 0.0, False
    d = K[L.KW] / h
    t = K[L.D7] + d
    px = p[0] - t * a[0]
    py = p[1] - t * a[1]
    if in_plane:
        ch, sh = math.cos(t1_hint), math.sin(t1_hint)
        rho = ch * px + sh * py
        px, py = rho * ch, rho * sh
    return x, d, px, py, p[2] - t * a[2], True


@njit
def bend_gap(t5, p, a, front, elbow, K, th, t1_hint=0.0, in_plane=False, slack=1e-12, inside=-1.0):
    """The bend gap at wrist angle ``t5`` >= 0 on the arm branch (``front``, ``elbow``: +-1):
    the angle between axis 4 of the arm that places the virtual centre of that bend and the
    tool's approach ``a``, minus the wrist's bend ``phi(t5)``; zero exactly at solutions.
    Unlike the residual polynomial it is computed from t5 itself, with angles from atan2: it
    stays accurate (to rounding of the angles) where d is flat in t5 (straight or fully bent
    wrist) and where two roots of the polynomial merge within its rounding. Writes the arm's
    DH cosines and sines into ``th`` (as :func:`arm_from_psi`). Returns (gap, ok); ok is False
    where the branch does not reach. ``t1_hint``: theta1 when the virtual centre is on axis 1;
    ``th[6]`` gets t5. ``in_plane``: theta1 is ``t1_hint`` (the virtual centre is taken in
    that arm plane: near axis 1 its direction from the axis is rounding noise). ``slack``:
    how far the arm may miss the centre (:func:`ik7r._kernels.arm.arm_ik`; the arm's cosines and
    sines come from :func:`ik7r._kernels.arm.arm_cs`, without a trigonometric call). ``inside``:
    a virtual centre inside the lateral offset's cylinder by no more than this is taken onto it
    (:func:`ik7r._kernels.arm.arm_reach`)."""
    x, d, px, py, pz, ok = _bend_centre(t5, p, a, K, t1_hint, in_plane)
    if not ok:
        return 0.0, False  # the fold of a 45 deg twist: the virtual centre is at infinity
    c1, s1, c2, s2, c3, s3, ok = arm_cs(px, py, pz, K[L.D4] + d, front, elbow, t1_hint, K, slack, inside)
    if not ok:
        return 0.0, False
    th[0], th[1], th[2], th[3], th[4], th[5], th[6] = c1, c2, c3, s1, s2, s3, t5
    cp = c2 * c3 - s2 * s3  # psi = theta2 + theta3
    sp = s2 * c3 + c2 * s3
    e3 = K[L.EPS3]
    zx = e3 * c1 * sp  # axis 4 (frame 0)
    zy = e3 * s1 * sp
    zz = -K[L.EPS1] * e3 * cp
    cx = zy * a[2] - zz * a[1]
    cy = zz * a[0] - zx * a[2]
    cz = zx * a[1] - zy * a[0]
    gamma = math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), zx * a[0] + zy * a[1] + zz * a[2])
    return gamma - 4.0 * math.asin(x), True


@njit
def shoulder_gap(t1, p, a, elbow, K, th, slack=1e-12):
    """The bend gap as a function of theta1 (DH) on the elbow branch ``elbow`` (+-1), for a robot
    without lateral offset: the virtual centre is where the line ``p - t a`` meets the arm's
    plane at theta1, which fixes d and so theta5. Near the shoulder singular set (that line
    passes close to axis 1) theta1 swings fast with d, and the residual polynomial's roots
    there merge within its rounding; in theta1 they stay apart. Returns (gap, ok); ``slack`` as
    :func:`bend_gap` takes it."""
    t5, front, ok = _shoulder_bend(t1, p, a, K)
    if not ok:
        return 0.0, False
    return bend_gap(t5, p, a, front, elbow, K, th, t1, True, slack)


@njit
def _shoulder_bend(t1, p, a, K):
    """The wrist angle and shoulder branch :func:`shoulder_gap` takes at theta1 = ``t1``:
    (t5, front, ok); ok is False where the arm's plane misses the line of virtual centres in
    the range of d."""
    c1 = math.cos(t1)
    s1 = math.sin(t1)
    an = -s1 * a[0] + c1 * a[1]
    if abs(an) < 1e-12:
        return 0.0, 0.0, False
    d = (-s1 * p[0] + c1 * p[1]) / an - K[L.D7]
    if not (K[L.DMIN] <= d <= K[L.DMAX]):
        if K[L.DEVIATION] == 0.0 or not d_near_range(d, K):
            return 0.0, 0.0, False
        d = min(K[L.DMAX], max(K[L.DMIN], d))
    t5 = theta5_cs_of_d(d, K)[0]
    t = K[L.D7] + d
    rho = c1 * (p[0] - t * a[0]) + s1 * (p[1] - t * a[1])
    return t5, 1.0 if rho >= 0.0 else -1.0, True


@njit
def shoulder_side(t1, p, a, K):
    """The shoulder branch :func:`shoulder_gap` takes at theta1 = ``t1`` (the side of axis 1 the
    virtual centre is on, +-1) and whether it is defined there: (front, ok). It switches where
    the arm's plane meets the line of virtual centres on axis 1, and the gap jumps there."""
    _, front, ok = _shoulder_bend(t1, p, a, K)
    return front, ok


@njit
def shoulder_switch(t_in, t_out, p, a, K):
    """The point between ``t_in`` and ``t_out`` (in either order) where the shoulder branch of
    :func:`shoulder_side` changes from the one at ``t_in``: bisection to the last bit; returns
    the last point found on ``t_in``'s side."""
    side = shoulder_side(t_in, p, a, K)[0]
    for _ in range(60):
        tm = 0.5 * (t_in + t_out)
        if tm == t_in or tm == t_out:
            break
        front, ok = shoulder_side(tm, p, a, K)
        if ok and front == side:
            t_in = tm
        else:
            t_out = tm
    return t_in


@njit
def gap_reaches(t, p, a, front, elbow, K, th):
    """Whether the arm branch of :func:`gap` reaches at ``t`` (its ``ok``, the same to the last
    bit), at a fraction of its cost for the bend gaps (no angle of the arm, no gap): the
    bisections for the ends of arm branches in :func:`_scan_piece` ask only this."""
    if abs(front) == 2.0 or front == 3.0 or abs(front) >= 5.0:
        return gap(t, p, a, front, elbow, K, th)[1]
    t5, t1, in_plane = t, 0.0, front == 0.0
    if in_plane:
        t1 = t
        t5, front, ok = _shoulder_bend(t1, p, a, K)
        if not ok:
            return False
    x, d, px, py, pz, ok = _bend_centre(t5, p, a, K, t1, in_plane)
    return ok and arm_reach(px, py, pz, K[L.D4] + d, front, t1, K)[4]


@njit
def reach_excess(t5, p, a, front, K):
    """How far the elbow of the shoulder branch ``front`` (+-1) is beyond its reach at wrist
    angle ``t5`` >= 0: ``|c| - 1`` with ``c`` the elbow's cosine before its clamp
    (:func:`ik7r._kernels.arm.elbow_cosine`), negative where both elbow branches are defined;
    smooth in t5 (inf at the fold of a 45 deg twist). Its dips between grid points where the
    branch does not reach are the branch's islands (:func:`ik7r._kernels.scans.gap_near_misses`)."""
    x, d, px, py, pz, ok = _bend_centre(t5, p, a, K)
    if not ok:
        return np.inf
    return abs(elbow_cosine(px, py, pz, K[L.D4] + d, front, 0.0, K)[3]) - 1.0


@njit
def reach_slack(K):
    """How far (in the elbow's cosine) the nominal arm may miss the centre where the exact
    model's may still reach it: REACH_SLACK_DEVIATING, widened with the deviation
    (:func:`ik7r._kernels.singular.deviation_widening`)."""
    return REACH_SLACK_DEVIATING * deviation_widening(K)


@njit
def reach_end(t_in, t_out, slack, p, a, front, K):
    """Where the elbow of the shoulder branch ``front`` (+-1) passes ``slack`` beyond its reach
    (:func:`reach_excess`) between ``t_in``, within it, and ``t_out``: ``t_out`` itself where it
    is within it there too; else Illinois steps to the last bits, the point returned on the
    inside."""
    f0 = reach_excess(t_in, p, a, front, K) - slack
    f1 = reach_excess(t_out, p, a, front, K) - slack
    if not f1 > 0.0:
        return t_out
    if not f0 < 0.0:
        return t_in
    side = 0
    for _ in range(200):
        t = secant_point(t_in, t_out, f0, f1)  # (the midpoint where f1 is inf: the fold)
        f = reach_excess(t, p, a, front, K) - slack
        if f == 0.0:
            return t
        t_in, t_out, f0, f1, side, done = illinois_step(t_in, t_out, f0, f1, side, t, f)
        if done:
            break
    return t_in


@njit
def gap(t, p, a, front, elbow, K, th):
    """The bend gap of :func:`bend_gap` at theta5 = ``t`` on the branch (front, elbow), with
    ``front`` 0 that of :func:`shoulder_gap` at theta1 = ``t`` on the elbow branch, with
    ``front`` +-2 the fold gap of :func:`fold_gap` at ``sw = t`` on the branch (front / 2, elbow),
    with ``front`` 3 that of :func:`_fold_axis_gap` at theta1 = ``t``; with ``front`` +-4 not a
    gap but :func:`reach_excess` of the shoulder branch front / 4 (for :func:`gap_min`'s search
    of an island; ``elbow`` unused); with ``front`` +-5 the bend gap of the shoulder branch
    front / 5 with a virtual centre inside the lateral offset's cylinder by no more than
    LATERAL_SHOULDER_DEVIATING of the size taken onto it (both branches merged there: a deviating
    model's solutions beside the cylinder, :func:`ik7r._kernels.scans.lateral_inside`); with
    ``front`` +-6 that of the shoulder branch front / 6 whose arm may miss the centre by
    REACH_SLACK_DEVIATING (widened with the deviation) in the elbow's cosine, the nearest arm
    taken there (beyond the elbow's stretch: :func:`ik7r._kernels.scans.gap_near_misses`)."""
    if abs(front) == 5.0:
        return bend_gap(t, p, a, 0.2 * front, elbow, K, th, 0.0, False, 1e-12,
                        LATERAL_SHOULDER_DEVIATING * K[L.SCALE])
    if abs(front) == 2.0:
        return fold_gap(t, p, a, 0.5 * front, elbow, K, th)
    if front == 3.0:
        return _fold_axis_gap(t, p, a, elbow, K, th)
    if abs(front) == 4.0:
        return reach_excess(t, p, a, 0.25 * front, K), True
    if abs(front) == 6.0:
        return bend_gap(t, p, a, front / 6.0, elbow, K, th, 0.0, False, reach_slack(K))
    if front != 0.0:
        return bend_gap(t, p, a, front, elbow, K, th)
    return shoulder_gap(t, p, a, elbow, K, th)


@njit
def gap_root(t0, t1, g0, g1, p, a, front, elbow, K, th):
    """The root of the bend gap bracketed by [t0, t1] (``g0``, ``g1`` of opposite signs): the
    Illinois steps of :func:`ik7r._kernels.poly.illinois_step`, to the last bits."""
    side = 0
    for _ in range(200):
        t = secant_point(t0, t1, g0, g1)
        g, ok = gap(t, p, a, front, elbow, K, th)
        if not ok or g == 0.0:
            return t
        t0, t1, g0, g1, side, done = illinois_step(t0, t1, g0, g1, side, t, g)
        if done:
            break
    return t0 if abs(g0) < abs(g1) else t1


@njit
def gap_min(t0, t1, p, a, front, elbow, K, th, floor=0.0, toward=0.0):
    """The least |bend gap| in [t0, t1] (Brent's minimiser); (t, |gap|, gap, ok) with the gap
    and its ``ok`` at t (|gap| is inf where not ok). ``floor`` > 0: stop once the bracket is
    below DIP_EARLY of [t0, t1] with the least |gap| so far at or above ``floor`` (the minimum
    is then only known to be about that high). ``toward`` +-1: the least ``toward * gap``
    instead, up to the first point where it is negative (where a dip's bottom is a root,
    whether the gap crosses zero twice there: a point between the two roots). (The value at
    the least point is kept from the search, not evaluated again; ``th`` holds the arm of the
    last point evaluated.)"""
    st, t = brent_start(t0, t1)
    early = DIP_EARLY * (t1 - t0)
    fx = 0.0
    okx = False
    for _ in range(200):
        f, ok = gap(t, p, a, front, elbow, K, th)
        if ok and toward * f < 0.0:
            return t, abs(f), f, ok
        st = brent_take(st, t, (abs(f) if toward == 0.0 else toward * f) if ok else np.inf)
        if st[2] == t:
            fx, okx = f, ok
        if floor > 0.0 and st[1] - st[0] < early and st[5] >= floor:
            break
        st, t, done = brent_next(st)
        if done:
            break
    return st[2], abs(fx) if okx else np.inf, fx, okx


@njit
def branch_end(t_in, t_out, p, a, front, elbow, K, th):
    """The end of the arm branch (``front``, ``elbow``) between ``t_in``, where its gap is
    defined, and ``t_out``, where it is not: bisection to the last bit (:func:`gap_reaches`);
    returns the last point found on the defined side."""
    for _ in range(60):
        tm = 0.5 * (t_in + t_out)
        if tm == t_in or tm == t_out:
            break
        if gap_reaches(tm, p, a, front, elbow, K, th):
            t_in = tm
        else:
            t_out = tm
    return t_in


@njit
def tiny_piece(ta, tb):
    """Whether [ta, tb] is narrower than SCAN_TINY (relative to 1 + |ta|): not gridded."""
    return tb - ta <= SCAN_TINY * (1.0 + abs(ta))


@njit
def fold_gap(sw, p, a, front, elbow, K, th, t1_in=0.0, in_plane=False, reach=0.0):
    """The fold gap at ``u = cos(2 beta) + sw^2`` (``sw^2 = 2 sin^2(beta) sin^2(eps / 2)``, eps =
    pi - theta5: ``sw >= 0`` grows with the distance from the fully bent wrist) on the arm
    branch (``front``, ``elbow``: +-1); zero exactly at solutions. Finite at the fold, where the
    virtual centre ``P = O - (KW / u) a`` (``O = p - d7 a``, the centre of joint 6) is at
    infinity for a 45 deg twist and the bend gap cannot be evaluated.

    The arm that places P at distance ``L = d4 + KW / u`` along axis 4 is computed in coordinates
    scaled by u (``u P`` and ``u L`` stay finite), with the elbow's angles from half-angle forms
    whose small terms are computed as such (``|X|^2 - |v|^2`` expanded, its leading terms cancelled
    by hand): it stays accurate to rounding as u goes to 0, where the two elbow branches keep
    distinct theta2 and theta3. For that arm, the wrist's condition (axis 4 at the bend ``phi(u)``
    from the approach ``a``) is equivalent to ``|O - O4| = 2 |KW|`` (the mirror wrist puts O4 and O
    symmetric about the bisector of axes 4 and 7), a distance of points that both stay finite:
    the gap is ``|O - O4| / (2 |KW|) - 1``. Writes DH cosines and sines of theta1..3 into
    ``th[:6]`` (as :func:`arm_from_psi`), theta5 (DH, in [0, pi]) into ``th[6]`` and O4 (frame 0)
    into ``th[7:10]``. Returns (gap, ok); ok is False where the branch does not reach.
    ``in_plane``: theta1 is ``t1_in`` and the scaled virtual centre is taken in that arm plane
    (``front`` unused; see :func:`_fold_axis_gap`). ``reach`` > 0: where the elbow falls short of
    the centre by up to that much, the arm with the elbow stretched toward it."""
    ok, _, half, psi0, gamma, t20, t1, ox, oy, oz = _fold_arm(sw, p, a, front, K, t1_in, in_plane, reach)
    if not ok:
        return 0.0, False
    return _fold_branch(elbow, half, psi0, gamma, t20, math.cos(t1), math.sin(t1), ox, oy, oz,
                        sw, K, th)


@njit
def fold_gap_pair(sw, p, a, front, K, th):
    """:func:`fold_gap` at ``sw`` on both elbow branches of the shoulder branch ``front`` (+-1):
    (gap, ok) of elbow +1, then of elbow -1, from one evaluation of the part they share (the
    centre, theta1, the elbow's half angle: about a third of a gap's transcendental calls), then
    how far the elbow falls short of the centre (robot units; negative where it reaches, infinite
    where not computed). ``th`` holds the arm of elbow -1."""
    ok, short, half, psi0, gamma, t20, t1, ox, oy, oz = _fold_arm(sw, p, a, front, K, 0.0, False, 0.0)
    if not ok:
        return 0.0, False, 0.0, False, short
    c1, s1 = math.cos(t1), math.sin(t1)
    gp, okp = _fold_branch(1.0, half, psi0, gamma, t20, c1, s1, ox, oy, oz, sw, K, th)
    gm, okm = _fold_branch(-1.0, half, psi0, gamma, t20, c1, s1, ox, oy, oz, sw, K, th)
    return gp, okp, gm, okm, short


@njit
def fold_shortfall(sw, p, a, front, K):
    """How far the elbow of the fold gap's shoulder branch ``front`` (+-1) falls short of the
    centre at ``sw`` (robot units; negative where it reaches; infinite where the branch is not
    defined at all, the centre within the lateral offset of axis 1): ``fold_gap_pair``'s fifth
    value, without the elbow branches."""
    return _fold_arm(sw, p, a, front, K, 0.0, False, 0.0)[1]


@njit
def fold_short_min(t0, t1, p, a, front, K, sign=1.0):
    """The least ``sign`` times the shortfall (:func:`fold_shortfall`) of the shoulder branch
    ``front`` in [t0, t1] (Brent's minimiser; ``sign`` -1: the greatest shortfall; a point
    where the branch is not defined counts as infinitely high): (sw, shortfall there)."""
    st, t = brent_start(t0, t1)
    for _ in range(200):
        short = fold_shortfall(t, p, a, front, K)
        st = brent_take(st, t, sign * short if math.isfinite(short) else math.inf)
        st, t, done = brent_next(st)
        if done:
            break
    return st[2], sign * st[5]


@njit
def fold_meetings(p, a, K):
    """Where the fold gap's two shoulder branches meet: ``sw`` (:func:`fold_gap`) of the (at
    most two) u at which the scaled virtual centre ``u O - KW a`` lies at the lateral offset's
    distance from axis 1 (``|u O_xy - KW a_xy|^2 = (u b)^2``, a quadratic in u; the branches
    are not defined on one side, and are one arm at the point). NaN for none; both NaN without
    a lateral offset (the centre on axis 1 is :func:`fold_near_axis`'s)."""
    b = K[L.B]
    if b == 0.0:
        return np.nan, np.nan
    d7 = K[L.D7]
    kw = K[L.KW]
    ox = p[0] - d7 * a[0]
    oy = p[1] - d7 * a[1]
    qa = ox * ox + oy * oy - b * b
    qb = -2.0 * kw * (ox * a[0] + oy * a[1])
    qc = kw * kw * (a[0] * a[0] + a[1] * a[1])
    disc = qb * qb - 4.0 * qa * qc
    if disc < 0.0 or (qa == 0.0 and qb == 0.0):
        return np.nan, np.nan
    q = -0.5 * (qb + math.copysign(math.sqrt(disc), qb))  # (the two roots without cancellation)
    u1 = q / qa if qa != 0.0 else np.nan
    u2 = qc / q if q != 0.0 else np.nan
    uf = u_fold(K)
    return (math.copysign(math.sqrt(abs(u1 - uf)), u1 - uf),
            math.copysign(math.sqrt(abs(u2 - uf)), u2 - uf))


@njit
def _fold_arm(sw, p, a, front, K, t1_in, in_plane, reach):
    """The part of :func:`fold_gap` its two elbow branches share: (ok, short, half, psi0, gamma,
    t20, t1, ox, oy, oz): how far the elbow falls short of the centre (robot units; negative
    where it reaches, infinite where that is not computed), half the elbow's angle, psi = theta2
    + theta3 and theta2 before the elbow's sign (``psi0 + 2 elbow half``, ``t20 - elbow
    gamma``), theta1 (DH) and O, the centre of joint 6. Short by no more than ``reach``: the
    elbow stretched (half 0) toward the centre."""
    u = u_fold(K) + sw * abs(sw)  # (sw < 0: u below the fold, scanned for deviating models)
    kw = K[L.KW]
    a1, a2, a3, b, e1, e3, scale = arm_params(K)
    d1 = K[L.D1]
    d4 = K[L.D4]
    d7 = K[L.D7]
    ox = p[0] - d7 * a[0]
    oy = p[1] - d7 * a[1]
    oz = p[2] - d7 * a[2]
    hx = u * ox - kw * a[0]  # u P
    hy = u * oy - kw * a[1]
    hz = u * oz - kw * a[2]
    lh = u * d4 + kw  # u L
    bp = -e1 * b
    if in_plane:
        t1 = t1_in
        rho = math.cos(t1) * hx + math.sin(t1) * hy  # u rho (signed: the branch is theta1's)
    else:
        r2 = hx * hx + hy * hy
        if r2 <= (1e-13 * scale * u) ** 2 + (1e-13 * kw) ** 2:
            # the scaled virtual centre (nearly) on axis 1: _fold_axis_gap's
            return False, math.inf, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        disc = r2 - (u * b) ** 2
        if inside_cylinder(disc, r2, u * b, abs(u) * LATERAL_ROUNDING * scale):
            return False, math.inf, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0  # (inside the cylinder)
        rho = front * math.sqrt(max(disc, 0.0))  # u rho
        t1 = shoulder_angle(rho, hx, hy, u * bp)
    xx = rho - u * a1  # u X: the centre in the arm plane, from the shoulder
    xy = e1 * (hz - u * d1)
    nx = math.hypot(xx, xy)
    nv = math.hypot(u * a3, lh)  # u |v|, v = (a3, -eps3 L)
    if nx == 0.0 or nv == 0.0:
        return False, math.inf, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # |X|^2 - |v|^2 = D / u with the terms of order 1 / u^2 cancelled exactly
    dd = (u * (ox * ox + oy * oy + oz * oz - b * b + a1 * a1 + d1 * d1 - a3 * a3 - d4 * d4)
          - 2.0 * kw * (ox * a[0] + oy * a[1] + oz * a[2] + d4) - 2.0 * (a1 * rho + d1 * hz))
    su = 1.0 if u >= 0.0 else -1.0  # (u < 0: the scaled vectors point the other way)
    dt = su * dd / (nx + nv)  # |X| - |v|
    s2 = a2 * a2 - dt * dt
    short = abs(dt) - a2
    if u != 0.0:
        # the triangle's other side: the elbow folded back beyond itself (a2 > |X| + |v|, where
        # the forearm's virtual length d4 + d passes zero: a negative d4), which s2 does not see
        # (the half angle below would clamp at 90 deg, both elbows one arm that misses the
        # centre); the shortfall is the nearer side's, so that the fold scan's search for holes
        # between grid points that reach (_fold_splits) sees it come near
        short = max(short, a2 - (nx + nv) / abs(u))
    if nx + nv < a2 * abs(u):
        if short > 1e-12 * a2 and not short <= reach:
            return False, short, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    elif s2 < -1e-12 * a2 * a2:
        if not short <= reach:
            return False, short, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0  # the elbow does not reach
        s2 = 0.0
    root = math.sqrt(max(s2, 0.0) / (nx * nv))
    half = math.asin(min(1.0, 0.5 * abs(u) * root))  # half the angle between X and R(psi) v
    psi0 = math.atan2(xy, xx) - math.atan2(-e3 * lh, u * a3)
    # theta2: the angle at the shoulder between X and the upper arm (its sine from the law of
    # sines, both finite as u goes to 0)
    gamma = math.atan2(nv * root * math.cos(half) / a2, (su * dd + abs(u) * a2 * a2) / (2.0 * a2 * nx))
    t20 = math.atan2(su * xy, su * xx)  # (a2 > 0: ik7r.robot.family.frame_dh)
    return True, short, half, psi0, gamma, t20, t1, ox, oy, oz


@njit
def _fold_branch(elbow, half, psi0, gamma, t20, c1, s1, ox, oy, oz, sw, K, th):
    """The elbow branch ``elbow`` of :func:`fold_gap` from its shared part (:func:`_fold_arm`;
    ``c1``, ``s1``: theta1's cosine and sine): the arm into ``th``, the gap."""
    a1, a2, a3, b, e1, e3, scale = arm_params(K)
    d1 = K[L.D1]
    d4 = K[L.D4]
    bp = -e1 * b
    psi = psi0 + 2.0 * elbow * half
    t2 = t20 - elbow * gamma
    c2, s2_ = math.cos(t2), math.sin(t2)
    cp, sp = math.cos(psi), math.sin(psi)
    th[0], th[1], th[2] = c1, c2, cp * c2 + sp * s2_
    th[3], th[4], th[5] = s1, s2_, sp * c2 - cp * s2_
    th[6] = math.pi - fold_eps(sw, K)
    # O4 = E + R(psi) (a3, -eps3 d4) in the arm plane, then in frame 0
    x4 = a2 * c2 + a3 * cp + e3 * d4 * sp
    y4 = a2 * s2_ + a3 * sp - e3 * d4 * cp
    r4 = x4 + a1
    th[7] = r4 * c1 - bp * s1
    th[8] = r4 * s1 + bp * c1
    th[9] = e1 * y4 + d1
    dx = ox - th[7]
    dy = oy - th[8]
    dz = oz - th[9]
    return math.sqrt(dx * dx + dy * dy + dz * dz) / (2.0 * abs(K[L.KW])) - 1.0, True


@njit
def fold_eps(sw, K):
    """``eps = pi - theta5`` (>= 0) of the wrist at ``u = cos(2 beta) + sw^2``: ``sw =
    sqrt(2) |sin(beta)| sin(eps / 2)`` (u is quadratic in eps, sw linear); 0 for ``sw < 0``
    (theta5 clamped to pi)."""
    return 2.0 * math.asin(min(1.0, max(sw, 0.0) / (math.sqrt(2.0) * abs(K[L.SB]))))


@njit
def _fold_span_u(K):
    """The span of ``u - cos(2 beta)`` the fold scan covers (see :func:`scan_fold`)."""
    lo = -FOLD_BELOW * (1.0 - u_fold(K)) if K[L.DEVIATION] > 0.0 else 0.0
    return lo, FOLD_SPAN * (1.0 + 1e-3) ** 2


@njit
def fold_near_axis(p, a, K):
    """Whether the scaled virtual centre ``u P = u O - KW a`` (O the centre of joint 6) of the
    fully bent wrist (u = cos(2 beta)) lies within FOLD_AXIS_NEAR (relative to ``KW + |u|
    scale``), widened with the deviation (:func:`deviation_widening`), of axis 1: the approach
    (nearly) parallel to axis 1, where theta1 of the fold gap's arm swings next to the fold (and
    at the fold itself, with a vertical approach, is fixed not by the direction of P but by the
    position of O4). A model's deviation turns its approach by about its size over the wrist's
    offset: members deviating as far as the loader accepts had solutions there with the approach
    0.019 .. 0.025 rad from axis 1, twice the nominal margin."""
    u = u_fold(K)
    d7 = K[L.D7]
    hx = u * (p[0] - d7 * a[0]) - K[L.KW] * a[0]
    hy = u * (p[1] - d7 * a[1]) - K[L.KW] * a[1]
    near = FOLD_AXIS_NEAR * deviation_widening(K)
    return math.hypot(hx, hy) <= near * (abs(K[L.KW]) + abs(u) * K[L.SCALE])


@njit
def fold_axis_sw(t1, p, a, K):
    """``sw`` (:func:`fold_gap`) of the u at which the scaled virtual centre ``u O - KW a`` lies in
    the arm plane at theta1 (DH; the plane's offset scaled by u too): the plane condition is
    linear in u. Returns (sw, ok); ok is False outside the fold span."""
    c1 = math.cos(t1)
    s1 = math.sin(t1)
    d7 = K[L.D7]
    an = -s1 * a[0] + c1 * a[1]
    on = -s1 * (p[0] - d7 * a[0]) + c1 * (p[1] - d7 * a[1]) + K[L.EPS1] * K[L.B]
    u = 0.0
    if an != 0.0:
        if on == 0.0:
            return 0.0, False
        u = K[L.KW] * an / on
    du = u - u_fold(K)
    lo, hi = _fold_span_u(K)
    if lo == 0.0 and -FOLD_AXIS_CLAMP <= du < 0.0:
        # just beyond the fold (u is kw an / on, an the approach's rounding when it is along axis
        # 1): the fold itself, where the solutions of a pose made there lie
        du = 0.0
    if not lo <= du <= hi:
        return 0.0, False
    return (math.sqrt(du) if du >= 0.0 else -math.sqrt(-du)), True


@njit
def _fold_axis_gap(t1, p, a, elbow, K, th):
    """The fold gap (:func:`fold_gap`) as a function of theta1 (DH) on the elbow branch
    ``elbow``: u from the plane condition (:func:`fold_axis_sw`), the arm in that plane. Where
    the approach is (nearly) parallel to axis 1 the scaled virtual centre is (nearly) on it near
    the fold, and theta1 of the fold gap's arm swings fast with u (at the fold itself a vertical
    approach leaves theta1 to the position of O4: the pose's solutions there form no branch of
    u at all); in theta1 they stay apart. Returns (gap, ok)."""
    sw, ok = fold_axis_sw(t1, p, a, K)
    if not ok:
        return 0.0, False
    return fold_gap(sw, p, a, 1.0, elbow, K, th, t1, True)
