"""The candidates of one root: each arm branch at the virtual offset ``d``, its wrist, verified.

``solutions_at`` places the virtual centre at ``d`` on the line of centres and takes every arm
branch that reaches it; ``wrist_and_accept`` gives each its wrist (both bends, the snaps to a
straight or fully bent wrist, the straight-wrist family of a deviating model) and accepts it
(:mod:`.answers`).
"""

from __future__ import annotations

import math

from . import params as L
from .answers import accept, on_shoulder_set, straight_damped, straight_split
from .arm import inside_cylinder
from .constants import (
    FOLD_WINDOW,
    LATERAL_ROUNDING,
    LATERAL_SHOULDER_DEVIATING,
    MAT_PSI,
    MAT_Q,
    NEAR_SINGULAR,
    STRAIGHT_DEVIATING,
    STRAIGHT_SHOULDER,
    STRETCH_STRAIGHT,
    W_Q6,
    W_QQ,
    W_TH,
    wrap,
)
from .fk import user_angle
from .jit import njit
from .joints import (
    arm_frame,
    arm_from_psi,
    arm_may_match,
    filter_margin,
    may_match,
    psi_candidates,
    with_wrist,
)
from .poly import linear_system
from .reduced import straight_family
from .singular import fold_snap, near_shoulder, near_stretch, straight_circle
from .wrist import theta5_cs_of_d, theta5_of_bend


@njit
def wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Complete DH theta1..3 with the wrist bent by ``t5`` >= 0 (its cosine ``c5`` and sine
    ``s5``); accept every exact solution (with ``filt`` >= 0, only those that may have its
    indicators: see :func:`solve_config`)."""
    margin = filter_margin(K)
    if filt >= 0 and not arm_may_match(th, filt, margin, K):
        return count
    arm_frame(th, R07, K, ws, mats)
    Q = mats[MAT_Q, :3, :3]
    q = ws[W_Q6:W_Q6 + 6]
    qq = ws[W_QQ:W_QQ + 6]  # q completed with a wrist solution
    if not straight_circle(K) and t5 < STRAIGHT_SHOULDER:  # (the wrist deviates: no circle)
        shoulder = near_shoulder(th, K)
        stretched = near_stretch(th, K)
        window = STRAIGHT_SHOULDER if shoulder or stretched else STRAIGHT_DEVIATING
        # (the bend of the arm's own target: a root clamped to the end of the range is not enough)
        bent = theta5_of_bend(Q, K)
        if t5 < window and bent < window:
            # (the elbow at its stretch and the wrist straight as well: the split from starts)
            splits = stretched and max(t5, bent) < STRETCH_STRAIGHT
            count = straight_family(q, Q, Td, K, out, count, ws, mats, shoulder, splits)
    t4_hint = K[L.SIGN + 3] * hint[3] + K[L.THETA_OFFSET4]
    if t5 < FOLD_WINDOW:
        # straight wrist: one member of the theta4 + theta7 family
        for i in range(6):
            qq[i] = q[i]
        qq[4] = user_angle(4, 0.0, K)
        straight_split(qq, Q, K, hint, has_hint)
        count, exact = accept(qq, Td, K, out, count, mats, True)
        if exact:
            return count
        if straight_circle(K):
            for i in range(6):  # (the snap again: accept's failed polish moved it)
                qq[i] = q[i]
            qq[4] = user_angle(4, 0.0, K)
            straight_split(qq, Q, K, hint, has_hint)
            # (on the shoulder set; with a lateral offset anywhere: the arm from the double
            # root lay 2e-6 rad off, and only nearly straight shadows came back. Without one,
            # over the paper robot's and the offset members' 9,000 poses of edges.py, the paths
            # below gave the same solutions, and this polish cost the paper robot's nearly
            # straight poses a quarter of their time. Always on a model whose arm deviates:
            # its nominal arm misses the pose by the deviation, and accept does not polish a
            # snap of a deviating model)
            shoulder = on_shoulder_set(qq, K)
            if (shoulder or K[L.B] != 0.0 or K[L.DEVIATION] > 0.0) and straight_damped(
                    qq, Td, K, hint, has_hint, mats, shoulder):
                count, exact = accept(qq, Td, K, out, count, mats, True)
                if exact:
                    return count
        # nearly straight: theta5 from the bend itself (d is flat in theta5 at zero)
        t5 = theta5_of_bend(Q, K)
        if t5 == 0.0:
            return count
        c5, s5 = math.cos(t5), math.sin(t5)
    if math.pi - t5 < fold_snap(K):
        # fully bent wrist: the two wrist solutions merge into one, at theta5 = pi exactly
        count, exact = accept(with_wrist(q, Q, math.pi, -1.0, 0.0, t4_hint, K, mats, qq), Td,
                               K, out, count, mats, True)
        if exact:
            return count
    # a model that is not exactly the idealised one (rounded published numbers): a start on
    # the singular fold or straight wrist would stall Newton's polish; start just inside
    t5_alt = -1.0
    if K[L.DEVIATION] > 0.0:
        if math.pi - t5 < NEAR_SINGULAR:
            t5_alt = math.pi - NEAR_SINGULAR
        elif t5 < NEAR_SINGULAR:
            t5_alt = NEAR_SINGULAR
    for sgn in (1.0, -1.0):
        if filt >= 0 and margin < t5 < math.pi - margin:
            q5 = wrap(user_angle(4, sgn * t5, K))
            if (1 if 0.0 <= q5 < math.pi else 0) != (filt & 1):
                continue
        count, _ = accept(with_wrist(q, Q, sgn * t5, c5, sgn * s5, t4_hint, K, mats, qq), Td,
                           K, out, count, mats)
        if t5_alt > 0.0:  # (both signs polish from one singular point: also start off it)
            alt = sgn * t5_alt
            count, _ = accept(with_wrist(q, Q, alt, math.cos(alt), math.sin(alt), t4_hint, K,
                                           mats, qq), Td, K, out, count, mats, False, False)
    return count


@njit
def solutions_at(d, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Every exact solution whose virtual offset is the root ``d``."""
    t = K[L.D7] + d
    px = p[0] - t * a[0]
    py = p[1] - t * a[1]
    pz = p[2] - t * a[2]
    r2 = px * px + py * py
    b = K[L.B]
    scale = K[L.SCALE]
    psi = mats[MAT_PSI]
    th = ws[W_TH:W_TH + 6]
    t5, c5, s5 = theta5_cs_of_d(d, K)
    if r2 <= (1e-9 * scale) ** 2 and b == 0.0:
        # P' on axis 1 (shoulder singularity): psi from the elbow condition alone, theta1 from
        # the bend condition u . a = eps3 (sin psi (c1 ax + s1 ay) - eps1 cos psi az)
        kw = K[L.KW]
        cphi = 2.0 * kw * kw / (d * d) - 1.0
        axy = math.hypot(a[0], a[1])
        t1h = K[L.SIGN] * hint[0] + K[L.THETA_OFFSET1]
        a11, a12, m, a21, a22, c = linear_system(d, 0.0, p, a, K)
        for k in range(psi_candidates(a11, a12, m, 0.0, 0.0, 0.0, psi)):
            cp = psi[k, 0]
            sp = psi[k, 1]
            if abs(sp) * axy < 1e-12:
                arm_from_psi(d, 0.0, cp, sp, pz, math.cos(t1h), math.sin(t1h), K, th)
                count = wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                          mats)
                continue
            target = (cphi * K[L.EPS3] + K[L.EPS1] * cp * a[2]) / (sp * axy)
            if abs(target) > 1.0 + 1e-9:
                continue
            base = math.atan2(a[1], a[0])
            dev = math.acos(max(-1.0, min(1.0, target)))
            for sg in (1.0, -1.0):
                t1 = base + sg * dev
                arm_from_psi(d, 0.0, cp, sp, pz, math.cos(t1), math.sin(t1), K, th)
                count = wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                          mats)
        return count
    s2 = r2 - b * b
    # inside the cylinder of radius abs(b) about axis 1 the arm has no shoulder branch; on it (the
    # shoulder set of an arm with a lateral offset) its two branches meet. Within the rounding
    # of the root (LATERAL_ROUNDING) or, on a deviating model, within LATERAL_SHOULDER_DEVIATING
    # (its exact solutions lie beside the cylinder), the centre is taken onto it: one merged branch
    slack = (LATERAL_ROUNDING if K[L.DEVIATION] == 0.0 else LATERAL_SHOULDER_DEVIATING) * scale
    if inside_cylinder(s2, r2, b, slack):
        return count
    s = math.sqrt(max(s2, 0.0))
    bp = -K[L.EPS1] * b
    margin = filter_margin(K)
    for sgn in (1.0, -1.0):
        rho = sgn * s
        x1 = rho * px + bp * py  # theta1 = atan2(y1, x1)
        y1 = rho * py - bp * px
        n1 = math.sqrt(x1 * x1 + y1 * y1)
        c1, s1 = (x1 / n1, y1 / n1) if n1 > 0.0 else (1.0, 0.0)
        if filt >= 0 and not may_match(0, c1, s1, filt >> 2, margin, K):
            if s == 0.0:
                break
            continue  # this shoulder branch clearly has the other arm indicator
        a11, a12, m, a21, a22, c = linear_system(d, rho, p, a, K)
        n = psi_candidates(a11, a12, m, a21, a22, c, psi, 1e-4 if K[L.DEVIATION] == 0.0 else 2e-2)
        for k in range(n):
            arm_from_psi(d, rho, psi[k, 0], psi[k, 1], pz, c1, s1, K, th)
            count = wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                      mats)
        if s == 0.0:
            break
    return count
