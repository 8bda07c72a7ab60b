"""Compiled kernel of the complete solver: every solution of one pose, certified.

1. Sample the residual polynomial G(d) of :mod:`ik7r._kernels.poly` at Chebyshev points over the
   whole range of the virtual offset d (theta5 over [-pi, pi]) and isolate all its real
   roots (no root can be missed; tangential roots and clusters come back as candidates).
2. At each root, solve the two conditions that are linear in (cos psi, sin psi) for each
   shoulder branch, which gives theta1, theta2, theta3 exactly; theta5 = +-theta5(d); the wrist
   gives theta4 and theta7 from the orientation.
3. Verify every candidate on the exact forward kinematics; polish it with Newton-Raphson when
   it misses (the nominal model differs from the exact one, or a root sits at a tangency);
   drop it when it cannot be made exact. Remove duplicates.

``solve_into`` is that sequence, read top to bottom; the stages live in their own modules,
each importing only those above it in this table:

============ =============================================================================
module       what it holds
============ =============================================================================
constants    every tolerance, window and grid, and the layout of the pose's work array
singular     where the pose lies relative to the singular sets (small predicates)
answers      what is exact and what is one solution: accept, add, the output's passes
joints       a candidate's six joints from the arm's angles and the wrist
reduced      the exact model's reduced residual and its scans (deviating models)
held         the exact model's least error in q1 with the wrist held fully bent (deviating)
candidates   each arm branch at a root, its wrists, verified
gaps         the bend, shoulder and fold gaps the scans search
scans        the scans beside the polynomial: undecided brackets, shoulder set, fold
complete     the root isolation's roots and near misses, and ``solve_into``
============ =============================================================================
"""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .answers import floor_shoulder, merge_folded
from .candidates import solutions_at, wrist_and_accept
from .constants import (
    CW_FOUND,
    CW_REF,
    CW_SHOULDER,
    DEVIATING_ENDS,
    FOLD_NEAR,
    FOLD_SPAN,
    MAT_CW,
    MAT_MEMO_N,
    MAT_PSI,
    MAT_R07,
    MAT_T07,
    NBRACKETS,
    NEAR_GRID,
    NEAR_RATIO,
    NEAR_RATIO_END,
    NEAR_RATIO_FOLD_END,
    NEAR_RATIO_GRID,
    NEAR_RATIO_ROOTSIDE,
    NMATS,
    ROOT_CAP,
    W_A,
    W_BCOEF,
    W_BHI,
    W_BLO,
    W_BSURE,
    W_CAST,
    W_FOUND,
    W_ISO,
    W_MATS,
    W_NB,
    W_NFAM,
    W_NRSCAN,
    W_NSDIP,
    W_NSTR,
    W_P,
    W_ROOTS,
    W_TH,
    WORK_SIZE,
    wrap,
)
from .jit import njit
from .joints import arm_from_psi, psi_candidates
from .poly import (
    ISOLATE_WORK,
    REFINE_GRID,
    bend_row_on_axis,
    degree_power,
    isolate,
    least_abs,
    linear_system,
    newton_on_bracket,
    off_zero,
    refine,
    residual_of,
)
from .reduced import dips_to_zero, other_wrists, partners
from .scans import gap_near_misses, lateral_crossings, scan_fold, scan_shoulder, scan_theta5
from .singular import fold_snap, u_fold
from .wrist import d_of_theta5, theta5_cs_of_d


@njit
def frame07(Td, K, T07):
    """Frame 0 <- 7 of a world <- tool target: ``BASE^-1 Td TOOL^-1``."""
    for i in range(4):
        m0 = 0.0
        m1 = 0.0
        m2 = 0.0
        m3 = 0.0
        for k in range(4):
            b = K[L.BASE_INV + 4 * i + k]
            m0 += b * Td[k, 0]
            m1 += b * Td[k, 1]
            m2 += b * Td[k, 2]
            m3 += b * Td[k, 3]
        for j in range(4):
            T07[i, j] = (m0 * K[L.TOOL_INV + j] + m1 * K[L.TOOL_INV + 4 + j]
                         + m2 * K[L.TOOL_INV + 8 + j] + m3 * K[L.TOOL_INV + 12 + j])


@njit
def _roots(kind, p, a, K, Bm, bnorm, roots, ws):
    """Every real root of the residual ``kind`` (:func:`ik7r._kernels.poly.residual_of`) over the
    search interval of d (into ``roots``), ascending; -1 when it vanishes identically (a
    continuum). ``ws``: the pose's work array."""
    lo, hi = _interval(K)
    nc = Bm.shape[0]
    blo = ws[W_BLO:W_BLO + NBRACKETS]
    bhi = ws[W_BHI:W_BHI + NBRACKETS]
    bsure = ws[W_BSURE:W_BSURE + NBRACKETS]
    bcoef = ws[W_BCOEF:W_BCOEF + NBRACKETS * nc].reshape((NBRACKETS, nc))
    nb = isolate(kind, lo, hi, p, a, K, Bm, bnorm, blo, bhi, bsure, bcoef,
                 ws[W_ISO:W_ISO + ISOLATE_WORK])
    ws[W_NB] = max(nb, 0)
    if nb < 0:
        return -1
    count = 0
    found = ws[W_FOUND:W_FOUND + REFINE_GRID + 2]
    w = ws[W_CAST:W_CAST + nc]
    for k in range(nb):
        if bsure[k] == 1.0:  # exactly one root, and the interpolant on its bracket
            found[0] = newton_on_bracket(kind, blo[k], bhi[k], bcoef[k], p, a, K, w)
            m = 1
        else:
            m = refine(kind, blo[k], bhi[k], p, a, K, found)
        for i in range(m):
            # u -> d; for a model that deviates from the idealised one a root just outside
            # the range stays where it is (its arm exists there; theta5 is clamped to 0 or pi)
            u = found[i]
            if K[L.DEVIATION] == 0.0:
                u = min(1.0, max(u_fold(K), u))
            if abs(u) < 1e-12:
                continue  # the folded wrist of a 45 deg twist (d at infinity): see solve_all
            if count == roots.shape[0]:
                raise RuntimeError("ik7r: more candidate roots than ROOT_CAP; none is dropped "
                                   "silently: please report the pose")
            roots[count] = K[L.KW] / u
            count += 1
    if K[L.DEVIATION] > 0.0:
        count = _near_misses(kind, lo, hi, p, a, K, roots, count)
    return count


@njit(allocates=True)
def _near_misses(kind, lo, hi, p, a, K, roots, count):
    """Extra candidates for a model that deviates from the idealised one: local minima of
    |residual| that come close to zero without crossing it. A pair of nearby roots of the
    idealised residual can vanish (turn complex) under the deviation while the exact model
    keeps its two solutions there; Newton's polish from the minimum finds them.

    For robots with offsets ``G = F(d, rho) F(d, -rho)`` is a product over the two shoulder
    branches, and a near miss of one factor (the two exact solutions of one branch next to the
    elbow stretch or the shoulder set) often lies within a grid cell of a simple root of the
    other, where ``G`` changes sign and shows no minimum: the factors are searched too (a
    factor's minimum within a quarter of a cell of one found before is that one). A grid
    minimum is held to NEAR_RATIO on the grid or, within NEAR_RATIO_GRID there, at its refined
    minimum: the grid reads a narrow dip between its points too high. A cell beside a root's
    cell that the grid reads as the descent to that root may hold a near miss of its own (a
    cluster): where the grid value between them is within NEAR_RATIO_ROOTSIDE of its terms, that
    cell's least ``|f|`` is a candidate when it lies below half the grid value (:func:`_root_side`)."""
    m = NEAR_GRID
    nk = 3 if kind == 0 and K[L.PRODUCT] != 0.0 else 1
    fs = np.empty((nk, m + 1))
    ms = np.empty((nk, m + 1))
    for i in range(m + 1):
        u = lo + (hi - lo) * i / m
        if nk == 1:
            fs[0, i], ms[0, i] = residual_of(kind, u, p, a, K)
            continue
        fs[1, i], ms[1, i] = residual_of(2, u, p, a, K)
        fs[2, i], ms[2, i] = residual_of(3, u, p, a, K)
        if math.isnan(fs[1, i]):  # (rho imaginary: G is |F(d, rho)|^2)
            fs[0, i], ms[0, i] = residual_of(0, u, p, a, K)
        else:  # G from its factors, as residual_G has it (scaled by u^16 once)
            sc = degree_power(off_zero(u), K)
            fs[0, i] = fs[1, i] * fs[2, i] / sc
            ms[0, i] = (abs(fs[1, i]) * ms[2, i] + abs(fs[2, i]) * ms[1, i]
                        + ms[1, i] * ms[2, i] * 1e-16) / sc
    h = 0.5 * (hi - lo) / m
    n0 = count
    for k in range(nk):
        kd = kind if k == 0 else k + 1  # kinds 2 and 3: the factors (see residual_of)
        n1 = count
        for i in range(0 if k > 0 else 1, m + 1 if k > 0 else m):
            # (a factor's minimum may lie at an end of the range: a near miss at the fold or
            # the straight wrist, whose exact solutions then lie just inside)
            fa = abs(fs[k, i])
            il = max(i - 1, 0)
            ir = min(i + 1, m)
            if (fa <= abs(fs[k, il]) and fa <= abs(fs[k, ir]) and fs[k, il] * fs[k, i] > 0.0
                    and fs[k, i] * fs[k, ir] > 0.0 and (fa < NEAR_RATIO * ms[k, i] or (
                        fa < NEAR_RATIO_GRID * ms[k, i] and dips_to_zero(fs[k, il], fs[k, i], fs[k, ir])))):
                u = least_abs(kd, lo + (hi - lo) * il / m, lo + (hi - lo) * ir / m, p, a, K)
                fu, mu = residual_of(kd, u, p, a, K)
                if not (fa < NEAR_RATIO * ms[k, i] or abs(fu) < NEAR_RATIO * mu):
                    continue  # clear of zero on the grid and at its refined minimum
                if k > 0:
                    end = NEAR_RATIO_FOLD_END if i == 0 and u_fold(K) >= FOLD_NEAR else NEAR_RATIO_END
                    if fu * fs[k, i] <= 0.0 or not (0 < i < m or abs(fu) < end * mu):
                        continue  # two real roots (the certified search has them), or an end clear of zero
            else:
                side = _root_side(fs[k], ms[k], i, m)
                if side < 0:
                    continue
                u = least_abs(kd, lo + (hi - lo) * min(i, side) / m, lo + (hi - lo) * max(i, side) / m,
                              p, a, K)
                fu, mu = residual_of(kd, u, p, a, K)
                if not (fu * fs[k, i] > 0.0 and abs(fu) < 0.5 * fa and abs(fu) < NEAR_RATIO * mu):
                    continue  # the cell descends to the grid point: no dip of its own
            seen = False
            for j in range(n0, n1):  # (the minima found before, and their neighbours)
                seen = seen or abs(K[L.KW] / roots[j] - u) < 0.5 * h
            if seen:
                continue
            for v in (u, u - h, u + h):  # the minimum and starts on either side of it
                if abs(v) > 1e-12:
                    if count == roots.shape[0]:
                        raise RuntimeError("ik7r: more candidate roots than ROOT_CAP; none is "
                                           "dropped silently: please report the pose")
                    roots[count] = K[L.KW] / v
                    count += 1
    return count


@njit
def _root_side(f, mag, i, m):
    """The neighbour of grid point ``i`` whose cell may hide a near miss beside a root: ``i``'s
    other neighbour has the other sign (a root's cell), this one the sign of ``f[i]`` and a
    larger magnitude, and ``|f[i]|`` is within NEAR_RATIO_ROOTSIDE of its terms ``mag[i]``; -1
    when there is none (or ``i`` is an end of the grid). The grid reads such a cell as the
    residual's descent to the root, while a cluster's near miss may lie inside it."""
    if i <= 0 or i >= m or not abs(f[i]) < NEAR_RATIO_ROOTSIDE * mag[i]:
        return -1
    for j in (i - 1, i + 1):
        o = 2 * i - j
        if f[j] * f[i] > 0.0 and f[i] * f[o] < 0.0 and abs(f[j]) > abs(f[i]):
            return j
    return -1


@njit
def _continuum(p, a, R07, Td, K, Bm, bnorm, hint, has_hint, out, count, filt, ws, mats):
    """Axis 7 on axis 1 (P' on axis 1 for every d): theta1 is free. Take it from the hint
    (else 0) and solve the remaining 1-D problem with the same certified root isolation."""
    roots = ws[W_ROOTS:W_ROOTS + ROOT_CAP]
    nr = _roots(1, p, a, K, Bm, bnorm, roots, ws)
    th1 = K[L.SIGN] * hint[0] + K[L.THETA_OFFSET1] if has_hint else K[L.THETA_OFFSET1]
    c1, s1 = math.cos(th1), math.sin(th1)
    psi = mats[MAT_PSI]
    th = ws[W_TH:W_TH + 6]
    for k in range(max(nr, 0)):
        d = roots[k]
        t5, c5, s5 = theta5_cs_of_d(d, K)
        pz = p[2] - (K[L.D7] + d) * a[2]
        a11, a12, m, a21, a22, c = linear_system(d, 0.0, p, a, K)
        a21, a22, c = bend_row_on_axis(d, a, K)
        for k2 in range(psi_candidates(a11, a12, m, a21, a22, c, psi)):
            arm_from_psi(d, 0.0, psi[k2, 0], psi[k2, 1], pz, c1, s1, K, th)
            count = wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                      mats)
    return count


@njit
def _interval(K):
    """The search interval of ``u = KW / d = cos(phi / 2)``: the whole theta5 range (u = 1 at
    the straight wrist, cos(2 beta) fully bent), padded by rounding; for a fold (nearly) at
    infinity (cos(2 beta) < FOLD_NEAR) it starts FOLD_SPAN above the fold."""
    lo = u_fold(K)
    pad = 1e-9 * (1.0 - lo)
    if K[L.DEVIATION] > 0.0:
        # the exact model's solutions near the ends of the range may come from nominal roots
        # just outside it (kept there, then polished on the exact model)
        pad = 0.02 * (1.0 - lo)
    if lo < FOLD_NEAR:
        return lo + FOLD_SPAN, 1.0 + pad  # the fold's neighbourhood is :func:`scan_fold`'s
    return lo - pad, 1.0 + pad


@njit(allocates=True)
def solve_all(Td, K, Bm, bnorm, hint, has_hint, out):
    """Every exact solution of the world <- tool target ``Td`` (4, 4) into ``out`` (M, 6).

    Returns the number of solutions (angles wrapped to (-pi, pi], no duplicates). ``hint``
    (6,) chooses the free joints at singular poses when ``has_hint``.
    """
    return solve_into(Td, K, Bm, bnorm, hint, has_hint, out, -1, np.empty(WORK_SIZE))


@njit(allocates=True)
def solve_config(Td, K, Bm, bnorm, hint, has_hint, arm, elbow, wrist, out):
    """:func:`solve_all` for one configuration: every exact solution that has the indicators
    (arm, elbow, wrist), and possibly others. The root search is the same; only candidates
    whose arm and wrist clearly (beyond a margin) have other indicators are not verified,
    which skips most of the forward kinematics checks."""
    return solve_into(Td, K, Bm, bnorm, hint, has_hint, out, 4 * arm + 2 * elbow + wrist,
                      np.empty(WORK_SIZE))


@njit
def solve_into(Td, K, Bm, bnorm, hint, has_hint, out, filt, ws):
    """:func:`solve_all` (``filt`` -1) or :func:`solve_config` (``filt`` = 4 arm + 2 elbow +
    wrist) with the caller's work array ``ws`` (WORK_SIZE,): every scratch array of the pose,
    so that a batch allocates once."""
    mats = ws[W_MATS:W_MATS + NMATS * 16].reshape((NMATS, 4, 4))
    T07 = mats[MAT_T07]
    frame07(Td, K, T07)
    p = ws[W_P:W_P + 3]
    a = ws[W_A:W_A + 3]
    R07 = mats[MAT_R07, :3, :3]
    for i in range(3):
        p[i] = T07[i, 3]
        a[i] = T07[i, 2]
        for j in range(3):
            R07[i, j] = T07[i, j]
    na = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    for i in range(3):
        a[i] /= na
    roots = ws[W_ROOTS:W_ROOTS + ROOT_CAP]
    ws[W_NFAM] = 0.0
    ws[W_NRSCAN] = 0.0
    ws[W_NSDIP] = 0.0
    ws[W_NSTR] = 0.0
    mats[MAT_MEMO_N, 0, 0] = 0.0
    mats[MAT_CW].reshape(16)[CW_REF] = wrap(hint[0]) if has_hint else 0.0
    mats[MAT_CW].reshape(16)[CW_FOUND] = 0.0
    mats[MAT_CW].reshape(16)[CW_SHOULDER] = 0.0
    nr = _roots(0, p, a, K, Bm, bnorm, roots, ws)
    count = 0
    if nr < 0:
        return _continuum(p, a, R07, Td, K, Bm, bnorm, hint, has_hint, out, count, filt, ws, mats)
    last = -1e300
    folded = False
    # theta5 grows with d: the roots within fold_snap of theta5 = pi lie beyond this d
    d_fold = d_of_theta5(math.pi - fold_snap(K), K) if u_fold(K) > 1e-9 else math.inf
    for k in range(nr):
        d = roots[k]
        if d == last:
            continue  # the same root twice (clamped to an end of the range)
        last = d
        if not folded and d > d_fold:
            # near theta5 = pi the residual is flat: try the folded wrist's own d first
            folded = True
            count = solutions_at(K[L.DMAX], p, a, R07, Td, K, hint, has_hint, out, count, filt,
                                  ws, mats)
        count = solutions_at(d, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
    # brackets the polynomial left undecided (clusters of roots within its rounding): scan
    # them in theta5 with the bend gap, which resolves what the polynomial cannot
    sb2 = 2.0 * K[L.SB] * K[L.SB]
    for k in range(int(ws[W_NB])):
        if ws[W_BSURE + k] == 0.0:
            ta = 2.0 * math.asin(math.sqrt(min(1.0, max(0.0, (1.0 - ws[W_BHI + k]) / sb2))))
            tb = 2.0 * math.asin(math.sqrt(min(1.0, max(0.0, (1.0 - ws[W_BLO + k]) / sb2))))
            count = scan_theta5(ta, tb, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                 mats)
    if K[L.DEVIATION] > 0.0:
        # a model that deviates from the idealised one: near a singular wrist its exact solutions
        # may come from nominal near-misses the polynomial decides as root-free or as one root
        near0 = False
        nearpi = False
        for k in range(nr):
            t5k = theta5_cs_of_d(roots[k], K)[0]
            near0 = near0 or t5k < DEVIATING_ENDS
            nearpi = nearpi or math.pi - t5k < DEVIATING_ENDS
        if near0:
            count = scan_theta5(0.0, DEVIATING_ENDS, p, a, R07, Td, K, hint, has_hint, out, count,
                                 filt, ws, mats)
        if nearpi and u_fold(K) >= FOLD_NEAR:
            count = scan_theta5(math.pi - DEVIATING_ENDS, math.pi, p, a, R07, Td, K, hint, has_hint,
                                 out, count, filt, ws, mats)
    if u_fold(K) < FOLD_NEAR:
        # the fully bent wrist of a (nearly) 45 deg twist: the polynomial starts FOLD_SPAN above it
        count = scan_fold(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
        folded = True
    count = scan_shoulder(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
    if K[L.DEVIATION] > 0.0:
        count = gap_near_misses(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
        count = lateral_crossings(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
        count = partners(Td, K, out, count, ws, mats)
        count = other_wrists(R07, Td, K, out, count, ws, mats)
    if folded:
        count = merge_folded(out, count)
    if mats[MAT_CW].reshape(16)[CW_SHOULDER] != 0.0:
        count = floor_shoulder(out, count, Td, K, mats)
    return count
