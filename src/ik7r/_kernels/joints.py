"""A candidate's six joints from the arm's cosines and sines and the wrist.

From a root (the virtual offset ``d`` and the arm's plane ``psi``) the arm's angles
(``psi_candidates``, ``arm_from_psi``), the configuration filter of ``solve_config``
(``filter_margin``, ``may_match``), the arm's frame and the wrist's target (``arm_frame``), and
the wrist's joints for a bend (``with_wrist``, ``with_fold_wrist``, ``other_wrist``).
"""

from __future__ import annotations

import math

from . import params as L
from .answers import theta5
from .constants import FILTER_MARGIN, FILTER_MARGIN_DEVIATING, MAT_M, MAT_Q, MAT_WR, W_Q6
from .fk import dh_angle, dh_step_cs, user_angle
from .jit import njit
from .wrist import wrist_ik_cs, wrist_rotation_cs, wrist_t7, wrist_target


@njit
def psi_candidates(a11, a12, m, a21, a22, c, out, tol=1e-4):
    """(cos psi, sin psi) solving the 2 x 2 system on the unit circle: 0, 1 or 2 of them
    (the Cramer solution is accepted ``tol`` off the circle, then projected onto it)."""
    det = a11 * a22 - a12 * a21
    s1 = abs(a11) + abs(a12)
    s2 = abs(a21) + abs(a22)
    if abs(det) > 1e-9 * s1 * s2:
        cp = (m * a22 - a12 * c) / det
        sp = (a11 * c - a21 * m) / det
        nrm = math.sqrt(cp * cp + sp * sp)
        if abs(nrm - 1.0) > tol:
            return 0
        out[0, 0] = cp / nrm
        out[0, 1] = sp / nrm
        return 1
    # rows (nearly) parallel: intersect the elbow row's line with the unit circle (the
    # candidates are verified on the forward kinematics afterwards)
    if s1 > 0.0:
        u, v, w = a11 / s1, a12 / s1, m / s1
    elif s2 > 0.0:
        u, v, w = a21 / s2, a22 / s2, c / s2
    else:
        return 0
    nn = u * u + v * v
    disc = nn - w * w
    if disc < -1e-9 * nn:
        return 0
    root = math.sqrt(max(disc, 0.0))
    k = 0
    for sgn in (1.0, -1.0):
        cp = (u * w - sgn * v * root) / nn
        sp = (v * w + sgn * u * root) / nn
        out[k, 0] = cp
        out[k, 1] = sp
        k += 1
        if root == 0.0:
            break
    return k


@njit
def arm_from_psi(d, rho, cp, sp, pz, c1, s1, K, th):
    """Cosines and sines of DH theta1..3 (into ``th``: c1, c2, c3, s1, s2, s3) from those of
    theta1 (the shoulder branch) and of psi = theta2 + theta3 (no trigonometric call: the
    angles themselves are needed only for accepted candidates)."""
    a3 = K[L.A3]
    e1 = K[L.EPS1]
    e3 = K[L.EPS3]
    Ld = K[L.D4] + d
    xx = rho - K[L.A1]
    xy = e1 * (pz - K[L.D1])
    ex = xx - a3 * cp - Ld * e3 * sp
    ey = xy - a3 * sp + Ld * e3 * cp
    n = math.sqrt(ex * ex + ey * ey)
    c2, s2 = (ex / n, ey / n) if n > 0.0 else (1.0, 0.0)  # as atan2(0, 0) = 0
    th[0] = c1
    th[1] = c2
    th[2] = cp * c2 + sp * s2  # theta3 = psi - theta2
    th[3] = s1
    th[4] = s2
    th[5] = sp * c2 - cp * s2


@njit
def filter_margin(K):
    """FILTER_MARGIN, or FILTER_MARGIN_DEVIATING for a model that deviates from the idealised one."""
    return FILTER_MARGIN if K[L.DEVIATION] == 0.0 else FILTER_MARGIN_DEVIATING


@njit
def may_match(i, c, s, indicator, margin, K):
    """Whether joint ``i`` (0-based) at the DH angle of cosine ``c`` and sine ``s`` may have the
    indicator (1: user angle in [-pi/2, pi/2), where its cosine is positive) once polished:
    True when it is within about ``margin`` (rad) of a boundary."""
    # cos(user angle) = cos(theta - theta_offset) whatever the joint's sign
    cq = c * K[L.OFFSET_TRIG + 2 * i] + s * K[L.OFFSET_TRIG + 2 * i + 1]
    if abs(cq) < margin:
        return True
    return (cq > 0.0) == (indicator == 1)


@njit
def _angle(th, i):
    """DH theta_(i+1) from its cosine and sine in ``th`` (see :func:`arm_from_psi`)."""
    return math.atan2(th[3 + i], th[i])


@njit
def arm_may_match(th, filt, margin, K):
    """Whether the arm of ``th`` (DH cosines and sines of theta1..3, see :func:`arm_from_psi`)
    may have the Arm and Elbow indicators of ``filt`` (see :func:`solve_config`) once polished."""
    return (may_match(0, th[0], th[3], filt >> 2, margin, K)
            and may_match(2, th[2], th[5], (filt >> 1) & 1, margin, K))


@njit
def arm_frame(th, R07, K, ws, mats):
    """The arm of ``th`` (DH cosines and sines of theta1..3) made into frame 3 (``mats[MAT_M]``),
    the wrist's target rotation for the flange ``R07`` (``mats[MAT_Q]``, 3 x 3) and the arm's user
    angles (``q1..q3`` of ``ws[W_Q6:W_Q6 + 6]``)."""
    _arm_target(th, R07, K, mats[MAT_M], mats[MAT_Q, :3, :3])
    q = ws[W_Q6:W_Q6 + 6]
    for i in range(3):
        q[i] = user_angle(i, _angle(th, i), K)


@njit
def _arm_target(th, R07, K, M, Q):
    """Frame 3 of the arm of ``th`` (DH cosines and sines of theta1..3) into ``M`` (4, 4) and
    the wrist's target rotation for the flange ``R07`` into ``Q`` (3, 3)."""
    for i in range(4):
        for j in range(4):
            M[i, j] = 1.0 if i == j else 0.0
    for i in range(3):
        dh_step_cs(M, K, L.NDH, L.TRIG + 14, i, th[i], th[3 + i])
    wrist_target(M[:3, :3], R07, K, Q)


@njit
def other_wrist(q, R07, K, th, M, Q, W, qq):
    """Make ``qq`` the arm of ``q`` (user joints 1 to 3) with the other wrist for the flange
    ``R07``: DH theta5 of the other sign, theta4 (the nearest to ``q``'s) and theta7 from the
    arm's wrist target. On the idealised model each arm comes with both; on a deviating one the
    exact solution lies about the deviation from it. ``th`` (6,), ``M`` (4, 4), ``Q`` and ``W``
    (3, 3) are work arrays."""
    arm_with_wrist(q, -theta5(q, K), R07, K, th, M, Q, W, qq)


@njit
def arm_with_wrist(q, t5, R07, K, th, M, Q, W, qq):
    """Make ``qq`` (may be ``q``) the arm of ``q`` (user joints 1 to 3) with the wrist of DH
    theta5 ``t5`` for the flange ``R07``: theta4 and theta7 from the arm's wrist target.
    ``th`` (6,), ``M`` (4, 4), ``Q`` and ``W`` (3, 3) are work arrays."""
    for i in range(3):
        t = dh_angle(q, K, i)
        th[i] = math.cos(t)
        th[3 + i] = math.sin(t)
    _arm_target(th, R07, K, M, Q)
    t4, t7 = wrist_ik_cs(Q, math.cos(t5), math.sin(t5), K[L.SIGN + 3] * q[3] + K[L.THETA_OFFSET4], K, W)
    _completed(q, t4, t5, t7, K, qq)


@njit
def with_wrist(q, Q, t5, c5, s5, t4_hint, K, mats, qq):
    """``qq``: a copy of ``q`` (arm joints set) completed with the wrist for DH angle ``t5``
    (cosine ``c5``, sine ``s5``; :func:`set_wrist`)."""
    set_wrist(q, Q, t5, c5, s5, t4_hint, K, mats, qq)
    return qq


@njit
def set_wrist(q, Q, t5, c5, s5, t4_hint, K, mats, qq):
    """Set ``qq`` to a copy of ``q`` (arm joints set) completed with the wrist for DH angle
    ``t5`` (cosine ``c5``, sine ``s5``). Returns nothing (see :func:`with_fold_wrist`)."""
    t4, t7 = wrist_ik_cs(Q, c5, s5, t4_hint, K, mats[MAT_WR, :3, :3])
    _completed(q, t4, t5, t7, K, qq)


@njit
def _completed(q, t4, t5, t7, K, qq):
    """Make ``qq`` a copy of ``q`` (arm joints set) with the wrist's DH angles ``t4``, ``t5``,
    ``t7`` as user angles."""
    for i in range(6):
        qq[i] = q[i]
    qq[3] = user_angle(3, t4, K)
    qq[4] = user_angle(4, t5, K)
    qq[5] = user_angle(6, t7, K)


@njit
def with_fold_wrist(q, Q, t5, c5, s5, az, K, mats, qq):
    """Set ``qq`` to a copy of ``q`` (arm joints set) completed with the wrist for DH angle
    ``t5`` (cosine ``c5``, sine ``s5``), theta4 from the azimuth ``az`` of O - O4 about axis 4
    (O - O4 = dw (z5 + z6) lies at azimuth theta4 + mu(theta5) in frame 4 at theta4 = 0).
    Returns nothing: a kernel that counts references (``allocates``) would release an array
    it was given back."""
    sb = K[L.SB]
    dwsb = K[L.DW] * sb
    mu = math.atan2(dwsb * math.sqrt(1.0 - sb * sb) * (1.0 - c5), dwsb * s5)
    t4 = az - mu
    c4, s4 = math.cos(t4), math.sin(t4)
    W = mats[MAT_WR, :3, :3]
    wrist_rotation_cs(c5, s5, K, W)
    t7 = wrist_t7(Q, c4, s4, W)
    _completed(q, t4, t5, t7, K, qq)
