"""Compiled kernel of the arm (joints 1 to 3): place axis 4's point at distance ``L`` from
the x3 axis on a given point (the paper's Appendix 1, generalised to OPW-style offsets).

The arm is ``R perp R parallel R``: DH rows ``(0, 0, d1)``, ``(a1, eps1 90 deg, d2)``,
``(a2, 0, d3)``, ``(a3, eps3 90 deg, d4)``. In frame 1 the arm is planar: the point reached is
``(a1 + Xx, -eps1 b, eps1 Xy)`` with ``b = d2 + d3`` the lateral offset and
``X = RotZ(theta2) [a2 + a3 c3 + eps3 L s3,  a3 s3 - eps3 L c3]``.
"""

from __future__ import annotations

import math

from . import params as L
from .constants import LATERAL_ROUNDING
from .jit import njit


@njit
def arm_params(K):
    """The arm's numbers from the kernel parameters ``K``: (a1, a2, a3, b, eps1, eps3, scale)."""
    return K[L.A1], K[L.A2], K[L.A3], K[L.B], K[L.EPS1], K[L.EPS3], K[L.SCALE]


@njit
def shoulder_angle(rho, px, py, bp):
    """DH theta1 of the arm plane that holds ``(px, py)`` at ``rho`` (signed: the shoulder
    branch) along the plane and ``bp = -eps1 b`` (the lateral offset) across it."""
    return math.atan2(rho * py - bp * px, rho * px + bp * py)


@njit
def inside_cylinder(disc, r2, b, slack):
    """Whether a point at squared distance ``r2`` from axis 1 (``disc = r2 - b^2``) lies inside the
    cylinder of radius abs(``b``) about it by more than ``slack`` (a distance): there the arm has
    no shoulder branch; on it the two branches meet (:func:`shoulder_angle`). The test is on the
    distance: ``disc`` is about 2 abs(b) times it, and a squared slack would drop a root's
    rounding (LATERAL_ROUNDING)."""
    return disc < 0.0 and math.sqrt(r2) < abs(b) - slack


@njit
def elbow_cosine(px, py, pz, Ld, front, t1_hint, K):
    """The triangle of :func:`arm_ik` for the point, before any clamp: (rho, xx, xy, c,
    disc) with ``rho`` the signed distance of the point from axis 1 in the arm plane, ``(xx,
    xy)`` the point in the plane from axis 2, ``c`` the cosine the elbow's arc cosine is taken
    of (beyond +-1 where the elbow cannot reach: smooth in the point, so a scan can see it come
    near the reach between grid points where it is beyond) and ``disc`` the squared distance
    of the point from the cylinder of the lateral offset around axis 1 (negative inside)."""
    a1, a2, a3, b, e1, e3, scale = arm_params(K)
    r2 = px * px + py * py
    disc = r2 - b * b
    rho = front * math.sqrt(max(0.0, disc))
    if not r2 > (1e-13 * scale) ** 2:
        rho = front * (px * math.cos(t1_hint) + py * math.sin(t1_hint))
    xx = rho - a1
    xy = e1 * (pz - K[L.D1])
    m = (xx * xx + xy * xy - a2 * a2 - a3 * a3 - Ld * Ld) / (2.0 * a2)
    return rho, xx, xy, m / math.hypot(a3, Ld), disc


@njit
def arm_reach(px, py, pz, Ld, front, t1_hint, K, slack=1e-12, inside=-1.0):
    """Whether :func:`arm_ik` reaches the point (its ``ok``), without its angles: (rho, xx, xy,
    c, ok) as :func:`elbow_cosine` gives them, with ``c`` clamped to [-1, 1]; ``ok`` is False
    where it was beyond 1 by more than ``slack``, or the point is inside the lateral offset's
    cylinder by more than rounding (LATERAL_ROUNDING of the size), or by more than ``inside``
    (a distance) if that is given (>= 0): a point inside by less is taken onto the cylinder, the
    two shoulder branches merged there. The angles' trigonometric calls are left out: a scan that
    only looks for where an arm branch ends calls this alone."""
    rho, xx, xy, c, disc = elbow_cosine(px, py, pz, Ld, front, t1_hint, K)
    b = K[L.B]
    within = inside if inside >= 0.0 else LATERAL_ROUNDING * K[L.SCALE]
    ok = not inside_cylinder(disc, max(disc + b * b, 0.0), b, within)
    if abs(c) > 1.0:
        if abs(c) > 1.0 + slack:
            ok = False
        c = max(-1.0, min(1.0, c))
    return rho, xx, xy, c, ok


@njit
def arm_cs(px, py, pz, Ld, front, elbow, t1_hint, K, slack=1e-12, inside=-1.0):
    """The cosines and sines of :func:`arm_ik`'s angles, from the same triangle without a
    trigonometric call: (c1, s1, c2, s2, c3, s3, ok). The scans evaluate the bend gap, which
    needs only these, hundreds of times a pose. ``inside``: as :func:`arm_reach` takes it."""
    a1, a2, a3, b, e1, e3, scale = arm_params(K)
    rho, xx, xy, c, ok = arm_reach(px, py, pz, Ld, front, t1_hint, K, slack, inside)
    if _off_axis1(px, py, K):
        # theta1 = atan2(v, u) (:func:`shoulder_angle`); |(u, v)| > 0 here
        bp = -e1 * b
        u = rho * px + bp * py
        v = rho * py - bp * px
        n = math.sqrt(u * u + v * v)
        c1 = u / n
        s1 = v / n
    else:
        c1 = math.cos(t1_hint)
        s1 = math.sin(t1_hint)
    # theta3 = atan2(eps3 L, a3) + elbow acos(c)
    R = math.hypot(a3, Ld)
    cf, sf = (a3 / R, e3 * Ld / R) if R > 0.0 else (1.0, 0.0)
    sa = elbow * math.sqrt(max(0.0, (1.0 - c) * (1.0 + c)))
    c3 = cf * c - sf * sa
    s3 = sf * c + cf * sa
    # theta2 = atan2(xy, xx) - atan2(y2, x2)
    x2 = a2 + a3 * c3 + e3 * Ld * s3
    y2 = a3 * s3 - e3 * Ld * c3
    n = math.hypot(xx, xy)
    cx, sx = (xx / n, xy / n) if n > 0.0 else (1.0, 0.0)
    n = math.hypot(x2, y2)
    cy, sy = (x2 / n, y2 / n) if n > 0.0 else (1.0, 0.0)
    return c1, s1, cx * cy + sx * sy, sx * cy - cx * sy, c3, s3, ok


@njit
def arm_ik(px, py, pz, Ld, front, elbow, t1_hint, K, slack=1e-12):
    """DH angles (theta1, theta2, theta3) placing the point at distance ``Ld`` along axis 4
    on ``(px, py, pz)`` (frame 0), each in (-pi, pi]. ``front`` (+-1) picks the shoulder branch
    (+1 reaches forward of the shoulder), ``elbow`` (+-1) the elbow branch. On axis 1 (shoulder
    singularity, zero lateral offset) theta1 is ``t1_hint``. Returns ``ok = False`` when the
    point is out of reach (by more than rounding: the elbow's cosine beyond 1 by more than
    ``slack``; the angles are then of the nearest arm)."""
    c1, s1, c2, s2, c3, s3, ok = arm_cs(px, py, pz, Ld, front, elbow, t1_hint, K, slack)
    t1 = math.atan2(s1, c1) if _off_axis1(px, py, K) else t1_hint
    return t1, math.atan2(s2, c2), math.atan2(s3, c3), ok


@njit
def _off_axis1(px, py, K):
    """Whether ``(px, py)`` is off axis 1 by more than rounding (else theta1 is the hint's)."""
    return px * px + py * py > (1e-13 * K[L.SCALE]) ** 2
