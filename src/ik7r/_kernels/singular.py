"""Where a pose and a robot lie relative to the singular sets, from the robot's parameters and the
line of virtual wrist centres (``p``, ``a``: frame 7's origin and axis in the base frame).

Small predicates the scans share: the fold of a (nearly) 45 deg twist (``u_fold``,
``fold_snap``), the line's distance from axis 1 (``line_to_axis1``, ``axis1_distance``,
``shoulder_offset``, ``range_offset``), whether the whole turn of joint 1 is scanned there
(``turn_scanned``), where it crosses a lateral offset's cylinder and how far from it it runs
(``cylinder_crossings``, ``cylinder_offset``), whether an arm is near the shoulder set or has
its elbow near stretched (``near_shoulder``, ``near_stretch``), whether the model's straight
wrist is a circle (``straight_circle``), and how much further than the published models it
deviates (``deviation_widening``).
"""

from __future__ import annotations

import math

from . import params as L
from .constants import (
    FOLD_SNAP,
    FOLD_WINDOW,
    SHOULDER_DEVIATING,
    SHOULDER_EFFECT_REF,
    SHOULDER_EXACT_NEAR,
    SHOULDER_SCAN_DEVIATING,
    STRETCH_DEVIATING,
)
from .jit import njit


@njit
def fold_snap(K):
    """How close (rad) to theta5 = pi a wrist is tried at pi exactly first: FOLD_SNAP on the
    idealised model, FOLD_WINDOW on a deviating one (whose polish starts off the fold)."""
    return FOLD_SNAP if K[L.DEVIATION] == 0.0 else FOLD_WINDOW


@njit
def straight_circle(K):
    """Whether the model as written keeps axes 4 and 7 on one line at the straight wrist (its
    wrist deviates from the mirror by no more than NEGLIGIBLE of the tolerances:
    ``Family.wrist_effect`` 0), so that a straight wrist leaves only ``s4 q4 + s7 q7`` defined, a
    circle of solutions: every family member, and a model that deviates in its arm alone (twists
    written as 1.5708 rad). Only where the wrist itself deviates does the circle break into
    isolated solutions (:func:`ik7r._kernels.reduced.straight_family`)."""
    return K[L.WRIST_EFFECT] == 0.0


@njit
def turn_scanned(p, a, K):
    """Whether :func:`scan_shoulder` tracks the exact model over the whole turn of q1 for the
    line of virtual centres ``p - t a`` (:func:`_shoulder_turn`) without lateral offset (with a
    small one: :func:`small_lateral_turn`): its closest approach to axis 1 within SHOULDER_EXACT_NEAR
    (:func:`shoulder_offset`) at a d near the range, or that approach taken into the range so
    near (:func:`range_offset`)."""
    if K[L.B] != 0.0 or K[L.DEVIATION] == 0.0 or a[0] * a[0] + a[1] * a[1] < 1e-24:
        return False
    t, _ = line_to_axis1(p, a)
    d = t - K[L.D7]
    return ((d_near_range(d, K) and shoulder_offset(p, a, K) <= SHOULDER_EXACT_NEAR)
            or range_offset(p, a, K) <= SHOULDER_EXACT_NEAR)


@njit
def small_lateral_turn(p, a, K):
    """Whether a deviating model's lateral offset is as small as the deviation's reach
    (``abs(b)`` within SHOULDER_SCAN_DEVIATING of the size) with the line of virtual centres
    ``p - t a`` within SHOULDER_EXACT_NEAR of the cylinder of radius ``abs(b)`` (the measure of
    :func:`shoulder_offset`, :func:`_relative_offset`, from the cylinder instead of the axis) at
    a d in range: the regime of the shoulder set without lateral offset, where
    :func:`scan_shoulder` tracks the exact model over the whole turn of q1 as well."""
    b = K[L.B]
    if b == 0.0 or K[L.DEVIATION] == 0.0 or a[0] * a[0] + a[1] * a[1] < 1e-24:
        return False
    t, r = line_to_axis1(p, a)
    d = t - K[L.D7]
    return (abs(b) <= SHOULDER_SCAN_DEVIATING * K[L.SCALE] and d_near_range(d, K)
            and _relative_offset(abs(r - abs(b)), t, K) <= SHOULDER_EXACT_NEAR)


@njit
def cylinder_crossings(p, a, K):
    """The virtual offsets d at which the line of virtual centres ``p - t a`` crosses the
    cylinder of radius abs(b) about axis 1 (an arm with a lateral offset b: its shoulder set,
    where the two shoulder branches meet): a quadratic in t, (d1, d2), NaN for none (no
    crossing, no lateral offset, or ``a`` along axis 1)."""
    b = K[L.B]
    qa = a[0] * a[0] + a[1] * a[1]
    if b == 0.0 or qa < 1e-24:
        return math.nan, math.nan
    qb = -2.0 * (p[0] * a[0] + p[1] * a[1])
    qc = p[0] * p[0] + p[1] * p[1] - b * b
    disc = qb * qb - 4.0 * qa * qc
    if disc < 0.0:
        return math.nan, math.nan
    q = -0.5 * (qb + math.copysign(math.sqrt(disc), qb))  # (the two roots without cancellation)
    return q / qa - K[L.D7], (qc / q if q != 0.0 else math.nan) - K[L.D7]


@njit
def cylinder_offset(d, p, a, K):
    """The line of virtual centres' distance at ``d`` from the lateral offset's cylinder (radius
    abs(b) about axis 1), in the measure of :func:`shoulder_offset` (:func:`_relative_offset`)."""
    t = K[L.D7] + d
    return _relative_offset(abs(axis1_distance(t, p, a) - abs(K[L.B])), t, K)


@njit
def d_near_range(d, K):
    """Whether ``d`` is within 2 % of the robot's range of d (the shoulder scans' window: a
    deviating model's solutions there may come from a nominal d just beyond the range). Each
    end is widened by 2 % of its own magnitude: with negative wrist offsets (``d5 = d6 < 0``, a
    robot written in mirrored frames) the range is negative, and ``0.98 DMIN .. 1.02 DMAX``
    narrowed it instead (a rounded member's shoulder set, its line of centres 0.019 mm from axis
    1 at d = -74.7 in [-89.0, -73.6], was not scanned: three sources missed). On a model that
    deviates further than the published ones the 2 % widen with its reach
    (:func:`deviation_widening`): near axis 1 the arm's plane meets the line of virtual centres
    at a grazing angle, and the deviation moves that d by many times itself (a 44.3 deg member
    deviating 0.31 mm: the line met every plane at d = 50.0, 3 % below the range, 51.5; its
    source at q5 = -0.165)."""
    margin = 0.02 * deviation_widening(K)
    return K[L.DMIN] - margin * abs(K[L.DMIN]) <= d <= K[L.DMAX] + margin * abs(K[L.DMAX])


@njit
def line_to_axis1(p, a):
    """The line of virtual centres ``p - t a`` (``a`` not along axis 1) at its closest to axis 1:
    (t there, the distance)."""
    axy2 = a[0] * a[0] + a[1] * a[1]
    t = (p[0] * a[0] + p[1] * a[1]) / axy2
    return t, axis1_distance(t, p, a)


@njit
def axis1_distance(t, p, a):
    """The distance of the line's point ``p - t a`` from axis 1."""
    rx = p[0] - t * a[0]
    ry = p[1] - t * a[1]
    return math.sqrt(rx * rx + ry * ry)


@njit
def shoulder_offset(p, a, K):
    """The line of virtual centres' distance from axis 1 (``a`` not along it) relative to the
    larger of the robot's size and the distance d of its closest point from the wrist: how far
    a deviating model's virtual centre moves is the deviation's lengths plus d times its angles,
    and near the fully bent wrist of a 45 deg twist d reaches 1,000 sizes and more; and over how
    much further the model deviates than those the windows were measured on
    (:func:`_relative_offset`)."""
    t, r = line_to_axis1(p, a)
    return _relative_offset(r, t, K)


@njit
def range_offset(p, a, K):
    """:func:`shoulder_offset` at the line's closest approach to axis 1 taken into the range of
    d (its end nearest the closest approach, where that lies beyond it): the line may pass near
    axis 1 at an end of the range while its closest approach lies beyond the 2 % of
    :func:`d_near_range` (a member deviating 0.34 mm, the closest approach 0.65 mm from axis 1 at
    2.2 mm of d beyond the range, 0.82 mm at its end: its source was missed, the whole turn not
    tracked)."""
    t, _ = line_to_axis1(p, a)
    tc = K[L.D7] + min(K[L.DMAX], max(K[L.DMIN], t - K[L.D7]))
    return _relative_offset(axis1_distance(tc, p, a), tc, K)


@njit
def _relative_offset(r, t, K):
    """A distance ``r`` of the line of virtual centres at ``t`` (from axis 1, or from the lateral
    offset's cylinder) in the measure of the deviating models' shoulder windows: over the larger
    of the size and the line's d there, and over how much further than SHOULDER_EFFECT_REF of the
    size the deviation reaches (``deviation_effect`` tolerances; at least 1)."""
    return r / (max(K[L.SCALE], abs(t - K[L.D7])) * deviation_widening(K))


@njit
def deviation_widening(K):
    """How much further than SHOULDER_EFFECT_REF of the size the model's deviation reaches
    (its ``deviation_effect`` tolerances; at least 1): the factor by which the windows measured
    on the published models widen on a model that deviates further."""
    return max(1.0, K[L.DEVIATION_EFFECT] * K[L.POS_TOL] / (K[L.SCALE] * SHOULDER_EFFECT_REF))


@njit
def u_fold(K):
    """``u = KW / d`` of the fully bent wrist (theta5 = pi): ``cos(2 beta)``."""
    return 1.0 - 2.0 * K[L.SB] * K[L.SB]


@njit
def near_shoulder(th, K):
    """Whether the arm of DH cosines and sines ``th`` (see :func:`arm_from_psi`) places the
    straight wrist's virtual centre within SHOULDER_DEVIATING of the robot's size from axis 1
    (its distance in the arm plane, ``a1`` plus the reach of joints 2 and 3)."""
    c2, c3, s2, s3 = th[1], th[2], th[4], th[5]
    Ld = K[L.D4] + K[L.KW]
    e3 = K[L.EPS3]
    x2 = K[L.A2] + K[L.A3] * c3 + e3 * Ld * s3
    y2 = K[L.A3] * s3 - e3 * Ld * c3
    return abs(K[L.A1] + c2 * x2 - s2 * y2) < SHOULDER_DEVIATING * K[L.SCALE]


@njit
def near_stretch(th, K, within=STRETCH_DEVIATING):
    """Whether the arm of DH cosines and sines ``th`` (see :func:`arm_from_psi`) has its elbow
    ``within`` (default STRETCH_DEVIATING) of stretched or folded for the straight wrist's virtual centre: the
    sine of ``theta3 - atan2(eps3 L, a3)``, ``L = d4 + KW`` (the elbow's angle from the line of
    the upper arm, :func:`ik7r._kernels.arm.arm_cs`)."""
    return elbow_stretched(th[2], th[5], K, within)


@njit
def elbow_stretched(c3, s3, K, within):
    """Whether the elbow of DH cosine ``c3`` and sine ``s3`` of theta3 is ``within`` of stretched
    or folded (the sine of its angle from there: see :func:`near_stretch`)."""
    Ld = K[L.D4] + K[L.KW]
    a3 = K[L.A3]
    return abs(s3 * a3 - c3 * K[L.EPS3] * Ld) < within * math.hypot(a3, Ld)

