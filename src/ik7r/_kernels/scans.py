"""The scans that find what the residual polynomial leaves undecided, or cannot see.

``scan_theta5`` over brackets the root isolation could not decide, ``scan_shoulder`` in theta1
near the shoulder singular set (on deviating models the exact model's reduced residual over
the whole turn and around the nominal gap's dips), ``scan_fold`` next to the fully bent wrist of
a (nearly) 45 deg twist, and ``gap_near_misses`` (deviating models: the nominal gaps' dips that
miss zero by about the deviation). Each sign change or deep dip becomes a candidate
(``_gap_candidate``) verified by :mod:`.candidates`.
"""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .answers import accept, apart
from .candidates import solutions_at, wrist_and_accept
from .constants import (
    CLOSED_TOL,
    DIP_FLOOR,
    DIP_NEAR,
    FOLD_BELOW,
    FOLD_BELOW_CELLS,
    FOLD_END_NEAR,
    FOLD_MEET_SNAP,
    FOLD_NEAR,
    FOLD_REACH_DIP,
    FOLD_REACH_ISLAND,
    FOLD_REACH_SLACK,
    FOLD_SPAN,
    FOLD_SPLIT_PIECES,
    FOLD_TOUCH,
    FOLD_WINDOW,
    GAP_NEAR_CELLS,
    GAP_NEAR_DEPTH,
    GAP_NEAR_END,
    GAP_NEAR_GRID,
    HELD_ARM,
    HELD_SEEN,
    LATERAL_SHOULDER_DEVIATING,
    MAT_M,
    MAT_Q,
    NEAR_SINGULAR,
    NTH,
    REACH_PEAK,
    REACH_SLACK_CELLS,
    REDUCED_GRID,
    SCAN_GRID,
    SCAN_NEAR,
    SCAN_NEAR_DEVIATING,
    SCAN_NEST,
    SCAN_NEST_FOLD_AXIS,
    SCAN_PIECES,
    SHOULDER_CELLS,
    SHOULDER_DIP,
    SHOULDER_DIP_SAME,
    SHOULDER_DIPS,
    SHOULDER_EXACT_FAR,
    SHOULDER_EXACT_NEAR,
    SHOULDER_NEAR,
    SHOULDER_NEAR_FOLD,
    SHOULDER_REACH,
    SHOULDER_SCAN_DEVIATING,
    SHOULDER_SWITCH_NEAR,
    SHOULDER_TURN_BEND,
    SHOULDER_TURN_SLACK,
    SHOULDER_VALLEY_END,
    TWO_PI,
    W_LEAST,
    W_NSDIP,
    W_PAIR,
    W_Q6,
    W_QQ,
    W_SCAN,
    W_SDIP,
    W_SEND,
    W_SHORT,
    W_SPLIT,
    W_SUB,
    W_TEND,
    W_TH,
    wrap,
)
from .fk import user_angle
from .gaps import (
    bend_gap,
    branch_end,
    fold_axis_sw,
    fold_eps,
    fold_gap,
    fold_gap_pair,
    fold_meetings,
    fold_near_axis,
    fold_short_min,
    gap,
    gap_min,
    gap_reaches,
    gap_root,
    reach_end,
    reach_excess,
    reach_slack,
    shoulder_gap,
    shoulder_side,
    shoulder_switch,
    tiny_piece,
)
from .held import held_fold_turn
from .jit import njit
from .joints import arm_frame, arm_may_match, filter_margin, set_wrist, with_fold_wrist, with_wrist
from .reduced import reduced_scan, rescan_jumps, settle_start, turn_tracked
from .singular import (
    cylinder_crossings,
    cylinder_offset,
    d_near_range,
    deviation_widening,
    fold_snap,
    line_to_axis1,
    shoulder_offset,
    small_lateral_turn,
    turn_scanned,
    u_fold,
)
from .wrist import theta5_cs_of_d, theta5_cs_of_u


@njit
def scan_theta5(ta, tb, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats, front1=1.0,
                 cells=SCAN_GRID):
    """Every solution with theta5 in [ta, tb] (an interval the residual polynomial left
    undecided: its values there are within their rounding of zero), from the bend gap of each
    of the four arm branches (:func:`bend_gap`) on a grid: sign changes refined to the last
    bits, dips of |gap| (tangential roots, or two roots in one cell) refined by Brent's minimiser
    and split at the dip. Where a branch ends inside a cell (the elbow stretches) the end is
    found by bisection and the piece between it and the grid is scanned on a grid of its own.
    Each candidate is completed with the wrist and verified on the forward kinematics.
    ``front1`` 2: the same scan of the fold gap (:func:`scan_fold`). ``cells``: the first grid's
    (the pieces it adds have SCAN_GRID)."""
    paired = abs(front1) == 2.0 and not tiny_piece(ta, tb)
    for front in (front1, -front1):
        nsplit = 0
        if paired:
            # the fold gap's two elbow branches share most of their arm: their first grids at once
            th = ws[W_TH:W_TH + NTH]
            row = _short_row(front)
            for i in range(cells + 1):
                gp, okp, gm, okm, short = fold_gap_pair(ta + (tb - ta) * i / cells, p, a, 0.5 * front, K,
                                                        th)
                ws[W_PAIR + i] = gp if okp else np.nan
                ws[W_PAIR + SCAN_GRID + 1 + i] = gm if okm else np.nan
                ws[row + i] = short
            count, nsplit = _fold_splits(ta, tb, cells, front, p, a, R07, Td, K, hint, has_hint,
                                         out, count, filt, ws, mats)
        for elbow in (1.0, -1.0):
            count = _scan_pieces(ta, tb, front, elbow, p, a, R07, Td, K, hint, has_hint, out, count,
                                 filt, ws, mats, cells, (0 if elbow > 0.0 else 1) if paired else -1,
                                 nsplit)
    return count


@njit
def _scan_pieces(ta, tb, front, elbow, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats,
                 cells, given, nsplit=0):
    """:func:`_scan_piece` over [ta, tb] on the branch (front, elbow) (``cells``; its values from
    row ``given`` of W_PAIR if >= 0), then over the ``nsplit`` pieces of ``ws[W_SPLIT]``
    (:func:`_fold_splits`) and every piece these append."""
    sub = ws[W_SUB:W_SUB + 2 * (SCAN_PIECES + nsplit)]
    sub[0] = ta
    sub[1] = tb
    for k in range(2 * nsplit):
        sub[2 + k] = ws[W_SPLIT + k]
    npieces = 1 + nsplit
    j = 0
    while j < npieces:
        count, npieces = _scan_piece(sub[2 * j], sub[2 * j + 1], sub, npieces, front, elbow, p, a,
                                     R07, Td, K, hint, has_hint, out, count, filt, ws, mats,
                                     cells if j == 0 else SCAN_GRID, given if j == 0 else -1)
        j += 1
    return count


@njit
def _fold_splits(ta, tb, cells, front, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Pieces the fold scan's first grid (``cells`` over [ta, tb]) adds on the shoulder branch
    ``front`` (+-2) where a branch's reach changes between two grid points unseen (into
    ``ws[W_SPLIT]``), and the candidates it finds there. From the grid's shortfalls
    (``ws[W_SHORT]``):

    * where the two shoulder branches meet (:func:`fold_meetings`, in closed form) inside a
      cell, the cell's two sides: the branches are not defined on one side of the point, and
      born there as one arm, so a branch may reach from there to an elbow stretched before the
      next grid point (an exact 45 deg member with a 169 mm lateral offset: for 8e-6 in sw, the
      source there), or hold a piece between the point and a grid point where it reaches;
    * where the least-reaching grid point's shortfall is within FOLD_REACH_DIP of the size of
      zero, the greatest shortfall over its two cells (Brent; over the one toward the other
      grid point that reaches where a neighbour does not: an exact 45 deg member's island 5.9e-4
      wide in sw held the last grid point before the branch's end, the hole before it unseen,
      the source at the island's start): above zero, the branch has a
      hole there (the elbow stretched at both its sides, unseen by the grid), and the pieces
      from the grid points to the hole's sides are added, the sides candidates (as branch
      ends, FOLD_END_NEAR); within FOLD_TOUCH of the size below zero, the elbow touches the
      stretch there (a source made with the elbow stretched is often such a point: six of
      the seven exact members' misses that led here), and the point is a candidate;
    * where a least shortfall is above zero but within FOLD_REACH_DIP of the size, the least
      over its two cells (Brent), kept with the least of the grid for :func:`_fold_beyond_reach`
      (``ws[W_LEAST]``: the least and its sw, per shoulder branch); below zero, the island of
      reach is a piece too. A neighbour across a meeting of the branches is not compared (the
      shortfall jumps there), and its cell is searched up to the meeting (an exact 45 deg
      member: an island 1.6e-3 wide in sw in the cell before one, the source at its end);
    * where a grid point falls short by less than FOLD_REACH_DIP of the size next to one that
      reaches (the branch's end between them), the least shortfall over its other cell (Brent);
      below zero, that island is a piece (an exact 45 deg member in mirrored frames: an island
      1e-3 wide in sw between points short by 66 and 0.21 mm, four solutions on it).

    Returns (count, the number of pieces)."""
    row = _short_row(front)
    split = ws[W_SPLIT:W_SPLIT + 2 * FOLD_SPLIT_PIECES]
    th = ws[W_TH:W_TH + NTH]
    h = (tb - ta) / cells
    near = FOLD_REACH_DIP * K[L.SCALE]
    n = 0
    m1, m2 = fold_meetings(p, a, K)
    for m in (m1, m2):
        i = int(math.floor((m - ta) / h)) if ta < m < tb else -1
        if 0 <= i < cells and ta + h * i < m < ta + h * (i + 1) and n + 2 <= FOLD_SPLIT_PIECES:
            split[2 * n], split[2 * n + 1] = ta + h * i, m
            split[2 * n + 2], split[2 * n + 3] = m, ta + h * (i + 1)
            n += 2
    least = math.inf
    at = 0.0
    for i in range(cells + 1):
        s = ws[row + i]
        lo = ws[row + i - 1] if i > 0 else s
        hi = ws[row + i + 1] if i < cells else s
        t_lo = ta + h * max(i - 1, 0)
        t_hi = ta + h * min(i + 1, cells)
        t = ta + h * i
        if (-near < s <= 0.0 and (lo <= s or hi <= s) and (lo <= s or lo > 0.0)
                and (hi <= s or hi > 0.0) and n + 2 <= FOLD_SPLIT_PIECES):
            # (a neighbour that does not reach, the branch's end beyond it: the other cell only)
            if lo > 0.0:
                t_lo = t
            if hi > 0.0:
                t_hi = t
            tm, sm = fold_short_min(t_lo, t_hi, p, a, 0.5 * front, K, -1.0)
            e0 = e1 = tm
            if sm > 0.0:  # (a hole: each side's piece from the grid to the stretched elbow)
                e0 = branch_end(t_lo, tm, p, a, front, 1.0, K, th)
                e1 = branch_end(t_hi, tm, p, a, front, 1.0, K, th)
                split[2 * n], split[2 * n + 1] = t_lo, e0
                split[2 * n + 2], split[2 * n + 3] = e1, t_hi
                n += 2
            if sm > -FOLD_TOUCH * K[L.SCALE]:
                for e in (e0, e1):
                    for elbow in (1.0, -1.0):
                        g, ok = gap(e, p, a, front, elbow, K, th)
                        if ok and abs(g) < FOLD_END_NEAR:
                            count = _gap_candidate(e, p, a, front, elbow, R07, Td, K, hint, has_hint,
                                                   out, count, filt, ws, mats)
                    if e1 == e0:
                        break
        elif 0.0 < s < math.inf:
            # (where the shoulder branches meet in a neighbouring cell the shortfall jumps: that
            # neighbour is not compared, and its cell is searched up to the meeting)
            for mm in (m1, m2):
                if t_lo < mm < t:
                    lo, t_lo = s, mm
                if t < mm < t_hi:
                    hi, t_hi = s, mm
            if s < near and s <= lo and s <= hi and lo > 0.0 and hi > 0.0:
                t, s = fold_short_min(t_lo, t_hi, p, a, 0.5 * front, K)
                if s <= 0.0 and n < FOLD_SPLIT_PIECES:  # (an island: its piece)
                    split[2 * n] = branch_end(t, t_lo, p, a, front, 1.0, K, th)
                    split[2 * n + 1] = branch_end(t, t_hi, p, a, front, 1.0, K, th)
                    n += 1
            elif s < near and (hi <= 0.0 < lo or lo <= 0.0 < hi) and n < FOLD_SPLIT_PIECES:
                # (just short beside a neighbour that reaches, the branch's end between them: the
                # cell on the other side may hold an island, which neither neighbour sees)
                t_far = t_lo if hi <= 0.0 else t_hi
                tm, sm = fold_short_min(min(t_far, t), max(t_far, t), p, a, 0.5 * front, K)
                if sm <= 0.0:
                    split[2 * n] = branch_end(tm, t_far, p, a, front, 1.0, K, th)
                    split[2 * n + 1] = branch_end(tm, t, p, a, front, 1.0, K, th)
                    if split[2 * n] > split[2 * n + 1]:
                        split[2 * n], split[2 * n + 1] = split[2 * n + 1], split[2 * n]
                    n += 1
            if s < least:
                least = s
                at = t
    k = _least_slot(front)
    ws[k] = least
    ws[k + 1] = at
    return count, n


@njit
def _least_slot(front):
    """Where in the work array :func:`_fold_splits` keeps the least shortfall of the shoulder
    branch ``front`` and its sw (read by :func:`_fold_beyond_reach`)."""
    return W_LEAST + (0 if front > 0.0 else 2)


@njit
def lateral_crossings(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """A deviating model with a lateral offset b: candidates where the line of virtual centres
    crosses the cylinder of radius abs(b) about axis 1 (:func:`cylinder_crossings`; the arm's
    shoulder set, its two shoulder branches merged there), at each d in range. Inside the
    cylinder the idealised residual is a sum of squares (its shoulder branch imaginary): an
    exact solution whose idealised centre falls just inside it leaves no root and, beside the
    crossing, often no near miss either (a rounded member's source 3.5e-4 mm inside, its
    polynomial's near misses 0.8 .. 1.8 farther in d; nothing was answered)."""
    for d in cylinder_crossings(p, a, K):
        if d_near_range(d, K):
            count = solutions_at(min(K[L.DMAX], max(K[L.DMIN], d)), p, a, R07, Td, K, hint, has_hint,
                                 out, count, filt, ws, mats)
    count = _lateral_inside(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
    return _cylinder_exact(p, a, R07, Td, K, hint, out, count, ws, mats)


@njit
def _cylinder_exact(p, a, R07, Td, K, hint, out, count, ws, mats):
    """Beside the lateral offset's cylinder, on a model that deviates from the idealised one:
    every exact solution near the merged shoulder branch in q1 (see below), where the
    line of virtual centres passes within SHOULDER_EXACT_FAR of the cylinder (the measure of
    :func:`shoulder_offset`) at a crossing taken into the range of d, or where it crosses
    nowhere so near, at its closest approach to axis 1 taken into the range. (The scans follow
    the exact model's curves in q1, whatever d their points have: a source at the straight
    wrist's end of the range was found from the closest approach 7 mm of d away; the closest
    approach beside a crossing found nothing the crossings did not, on 14 missed sources.)

    There the shoulder branches' theta1 moves by about ``sqrt(2 e / abs(b))`` for a centre moved
    by ``e``: the deviation (a tenth of a millimetre) moves the exact solutions 0.1 to 0.2 rad
    from the nominal ones, and the nominal gap, whose two branches have gaps of opposite signs
    that meet at the cylinder, leaves no root or near miss to start from (members with b = -40
    and 63 mm, the line 0.28 and 0.10 mm outside the cylinder, a wrist nearly fully bent: two of
    three and two of six solutions missed). As in :func:`_shoulder_exact`, the exact model's
    reduced residual in q1 is tracked (:func:`_q1_scans`, both wrist signs) from the nominal arm
    with the centre taken onto the cylinder (:func:`_cylinder_arm`), each way from their middle
    to beyond either branch by SHOULDER_REACH, or by ``sqrt(2 e / abs(b))`` (at most pi) where
    that is larger, ``e`` how far the deviation may move the centre there (its
    ``deviation_effect`` tolerances, times ``d / size`` beyond the size, as
    :func:`shoulder_offset` measures): a 45 deg member's source at d = 9.9e5 lay 0.85 rad from
    the nearer middle. (Where the offset is as small as the
    deviation's reach, :func:`small_lateral_turn`, the whole turn is tracked by
    :func:`scan_shoulder` instead.)"""
    if K[L.B] == 0.0 or a[0] * a[0] + a[1] * a[1] < 1e-24 or small_lateral_turn(p, a, K):
        return count
    d1, d2 = cylinder_crossings(p, a, K)
    t, _ = line_to_axis1(p, a)
    th = ws[W_TH:W_TH + NTH]
    done = math.nan
    for k in range(3):
        d = d1 if k == 0 else d2 if k == 1 else t - K[L.D7]
        if k == 2 and math.isfinite(done):
            break  # (the closest approach only where no crossing was scanned)
        if not math.isfinite(d):
            continue
        d = min(K[L.DMAX], max(K[L.DMIN], d))
        if d == done or cylinder_offset(d, p, a, K) > SHOULDER_EXACT_FAR:
            continue
        done = d
        t5 = theta5_cs_of_d(d, K)[0]
        # how far the deviation may move the virtual centre there (the measure of shoulder_offset)
        moved = K[L.DEVIATION_EFFECT] * K[L.POS_TOL] * max(1.0, abs(d) / K[L.SCALE])
        for elbow in (1.0, -1.0):
            t1a, t1b, ok = _cylinder_arm(t5, p, a, elbow, K, th)
            if not ok:
                continue
            half = 0.5 * abs(wrap(t1a - t1b))
            mid = t1b + 0.5 * wrap(t1a - t1b)
            reach = half + min(math.pi, max(SHOULDER_REACH, math.sqrt(2.0 * moved / abs(K[L.B]))))
            cells = int(math.ceil(SHOULDER_CELLS * reach / SHOULDER_REACH))
            arm_frame(th, R07, K, ws, mats)
            q1 = ws[W_Q6]
            count = _q1_scans(th, wrap(user_angle(0, mid - reach, K) - q1),
                              wrap(user_angle(0, mid + reach, K) - q1), cells, Td, K, hint, out, count,
                              ws, mats)
    return count


@njit
def _cylinder_arm(t5, p, a, elbow, K, th):
    """The start of :func:`_cylinder_exact` on the elbow branch ``elbow`` at wrist angle ``t5``:
    ``th`` the nominal arm with a centre inside the cylinder taken onto it (``gap``'s front 5:
    shoulder branch 1, or -1 where 1 does not reach), and theta1 of both shoulder branches (one
    twice where only one reaches). Where neither reaches (the elbow at its stretch beside the
    cylinder, within the deviation of the exact model's reach), the nearest arm of branch 1 when
    it misses by less than SHOULDER_TURN_SLACK in the elbow's cosine, as for the whole turn
    (a 45 deg member's only solution, 0.19 mm inside the cylinder, its nominal branch ending at
    theta5 = 0.515 and the source at 0.507: nothing answered). Returns ``(t1a, t1b, ok)``."""
    _, ok_b = gap(t5, p, a, -5.0, elbow, K, th)
    t1b = math.atan2(th[3], th[0])
    _, ok_a = gap(t5, p, a, 5.0, elbow, K, th)
    t1a = math.atan2(th[3], th[0])
    if ok_a:
        return t1a, t1a if not ok_b else t1b, True
    if ok_b:
        gap(t5, p, a, -5.0, elbow, K, th)
        return t1b, t1b, True
    _, ok = bend_gap(t5, p, a, 1.0, elbow, K, th, 0.0, False, SHOULDER_TURN_SLACK,
                     LATERAL_SHOULDER_DEVIATING * K[L.SCALE])
    t1a = math.atan2(th[3], th[0])
    return t1a, t1a, ok


@njit
def _lateral_inside(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """The candidates of :func:`lateral_crossings` between the crossings, where the line of
    virtual centres runs inside the cylinder: there the idealised arm has no branch and the
    residual no root, yet the exact model may have a solution whose idealised centre lies
    inside by about the deviation (members 0.027 and 0.038 mm off the family, the centre 0.07 and
    0.013 mm inside, a wrist nearly straight or bent 0.38 rad: nothing answered, the idealised
    arm's near misses 0.06 and 0.012 mm off the pose). The bend gap with the centre taken onto
    the cylinder (``gap``'s front 5) on a grid of GAP_NEAR_CELLS over the stretch of theta5
    inside: each sign change (refined) and each grid minimum of ``|gap|`` below GAP_NEAR_GRID
    that Brent's minimiser takes below GAP_NEAR_DEPTH is completed with the wrist and polished
    on the exact model. Where the merged branch ends within a cell, its end stands for the grid
    point beyond (:func:`_merged_side`): a root or a dip beside the end was missed (a member's
    source beside the elbow's reach, another's beside the merge's depth: nothing answered)."""
    d1, d2 = cylinder_crossings(p, a, K)
    if not (math.isfinite(d1) and math.isfinite(d2)):
        return count
    lo = max(min(d1, d2), K[L.DMIN])
    hi = min(max(d1, d2), K[L.DMAX])
    if not lo < hi:
        return count
    ta = theta5_cs_of_d(lo, K)[0]
    tb = theta5_cs_of_d(hi, K)[0]
    if ta > tb:  # (negative wrist offsets: d runs from KW = DMAX down as theta5 grows)
        ta, tb = tb, ta
    if u_fold(K) < FOLD_NEAR:  # (the fold span is the fold gap's, as in gap_near_misses)
        tb = min(tb, theta5_cs_of_u(u_fold(K) + FOLD_SPAN, K)[0])
    if not ta < tb:
        return count
    m = GAP_NEAR_CELLS
    gs = ws[W_SCAN:W_SCAN + m + 1]
    th = ws[W_TH:W_TH + NTH]
    h = (tb - ta) / m
    for elbow in (1.0, -1.0):
        for i in range(m + 1):
            g, ok = gap(ta + h * i, p, a, 5.0, elbow, K, th)
            gs[i] = g if ok else np.nan
        for i in range(m + 1):
            g1 = gs[i]
            if not math.isfinite(g1):
                continue
            ti = ta + h * i
            # its neighbours (where the branch ends in the cell between, that end), mirrored at
            # the grid's ends for the dip's test
            tl, gl, tr, gr = ti, np.nan, ti, np.nan
            if i > 0:
                tl, gl = _merged_side(ti, ta + h * (i - 1), gs[i - 1], elbow, p, a, K, th)
            if i < m:
                tr, gr = _merged_side(ti, ta + h * (i + 1), gs[i + 1], elbow, p, a, K, th)
            if i == 0:
                gl = gr
            if i == m:
                gr = gl
            root = False
            if i < m and g1 * gr < 0.0:  # (NaN fails the comparisons)
                count = _root_between(ti, g1, tr, gr, p, a, 5.0, elbow, R07, Td, K, hint, has_hint,
                                      out, count, filt, ws, mats)
                root = True
            if i > 0 and not math.isfinite(gs[i - 1]) and g1 * gl < 0.0:  # (a cell with an end)
                count = _root_between(tl, gl, ti, g1, p, a, 5.0, elbow, R07, Td, K, hint, has_hint,
                                      out, count, filt, ws, mats)
                root = True
            if not root and _grid_dip(gl, g1, gr):
                tm, fm, _, okm = gap_min(tl, tr, p, a, 5.0, elbow, K, th)
                if okm and fm < GAP_NEAR_DEPTH:
                    count = _gap_candidate(tm, p, a, 5.0, elbow, R07, Td, K, hint, has_hint, out,
                                           count, filt, ws, mats)
    return count


@njit
def _merged_side(ti, tj, gj, elbow, p, a, K, th):
    """The neighbour of a grid point ``ti`` of :func:`_lateral_inside`, where its merged branch
    (front 5) is defined, toward the grid point ``tj`` (its gap ``gj``): ``(tj, gj)``, or where
    the branch ends between them (``gj`` NaN: the elbow's reach, or the centre deeper inside
    the cylinder than the merge takes) that end (:func:`branch_end`) and its gap."""
    if math.isfinite(gj):
        return tj, gj
    t_end = branch_end(ti, tj, p, a, 5.0, elbow, K, th)
    g_end, ok = gap(t_end, p, a, 5.0, elbow, K, th)
    return t_end, (g_end if ok else np.nan)


@njit
def gap_near_misses(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Extra candidates for a model that deviates from the idealised one: the near misses of
    each of the four arm branches' bend gaps (:func:`bend_gap`) over the whole theta5 range.
    A tangency of one branch's gap that the deviation turns into a pair of exact solutions is a
    near miss of one factor of the residual polynomial, but the factor of one shoulder branch
    is the product over its two elbow branches, and where the other elbow branch has a simple
    root less than a cell away the factor changes sign and shows no minimum (:func:`_near_misses`
    looks no deeper than the shoulder branches). Over theta5 in [0, pi] (up to the fold span
    where the fully bent wrist is nearly folded back), each grid minimum of ``|gap|`` below
    GAP_NEAR_GRID (rad) whose cells keep one sign is refined by Brent's minimiser (every one: beside
    the elbow stretch a dip is a V that no parabola through three grid values shows) and, when it
    comes below GAP_NEAR_DEPTH without crossing zero, completed with the wrist and polished
    on the exact model (its partner: :func:`partners`). Next to an end of the branch (the elbow
    stretched), a grid point below GAP_NEAR_END whose ``|gap|`` falls toward the end has no
    defined neighbour there: the end is bisected for (:func:`branch_end`) and the part between it
    and the point minimised the same way; a branch's islands that hold no more than one grid
    point are found from its elbow's reach (:func:`_islands`). Sign changes are the
    polynomial's, except where the exact model reaches further than the nominal one: beyond a
    branch's end (:func:`_beyond_the_stretch`) and over a cell at either end of which the
    elbow is within REACH_SLACK_DEVIATING of its stretch (:func:`_slack_roots`; a member
    deviating like the published models had its elbow within 1e-4 of the stretch over 0.4 rad
    of theta5, beyond it by at most 3e-6 over 0.06 of them, and a pair of exact solutions
    there, on both elbows, where the nominal gap changes sign across that hole)."""
    m = GAP_NEAR_CELLS
    gs = ws[W_SCAN:W_SCAN + m + 1]
    es = ws[W_SCAN + m + 1:W_SCAN + 2 * m + 2]  # (the elbow's excess on the grid: _islands)
    th = ws[W_TH:W_TH + NTH]
    top = math.pi
    if u_fold(K) < FOLD_NEAR:  # (the fold span is the fold gap's: see :func:`scan_fold`)
        top = theta5_cs_of_u(u_fold(K) + FOLD_SPAN, K)[0]
    for front in (1.0, -1.0):
        count = _islands(top, p, a, front, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
        for elbow in (1.0, -1.0):
            for i in range(m + 1):
                g, ok = bend_gap(top * i / m, p, a, front, elbow, K, th)
                gs[i] = g if ok else np.nan
            for i in range(m + 1):
                # (at an end of the range, the straight or fully bent wrist, the one neighbour
                # is taken twice: a minimum there is refined over its one cell)
                g0, g1, g2 = gs[max(i - 1, 1 - i)], gs[i], gs[min(i + 1, 2 * m - 1 - i)]
                if 0 < i < m and math.isfinite(g1) and math.isfinite(g0) != math.isfinite(g2):
                    # the branch ends in the cell beside: a near miss between the end and this
                    # point (the elbow nearly stretched) has no grid point of its own
                    out_i = i - 1 if math.isfinite(g2) else i + 1
                    g_in = g2 if math.isfinite(g2) else g0
                    count = _beyond_the_stretch(top * i / m, top * out_i / m, g1, p, a, front, elbow,
                                                R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
                    if g1 * g_in > 0.0 and abs(g1) <= abs(g_in):
                        t_e = branch_end(top * i / m, top * out_i / m, p, a, front, elbow, K, th)
                        # (far from zero at the grid point, the gap may still reach it at the
                        # end: it is as steep as a square root there; a rounded member's
                        # -0.6 a cell from an end of -2e-5 hid a pair of solutions)
                        near_end = abs(g1) < GAP_NEAR_END
                        if not near_end:
                            g_e, ok_e = bend_gap(t_e, p, a, front, elbow, K, th)
                            near_end = ok_e and abs(g_e) < GAP_NEAR_DEPTH
                        if near_end:
                            tm, fm, gm, okm = gap_min(min(t_e, top * i / m),
                                                       max(t_e, top * i / m), p, a, front, elbow,
                                                       K, th)
                            if okm and fm < GAP_NEAR_DEPTH and gm * g1 > 0.0:
                                count = _gap_candidate(tm, p, a, front, elbow, R07, Td, K, hint,
                                                       has_hint, out, count, filt, ws, mats)
                    continue
                if (i < m and math.isfinite(g1) and math.isfinite(gs[i + 1])
                        and _near_the_stretch(es, i, K)):
                    # the elbow within the slack of its stretch at a cell end, the branch defined
                    # at both: the exact model may reach where the nominal one does not inside
                    count = _slack_roots(top * i / m, top * (i + 1) / m, g1, p, a, front, elbow,
                                         R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
                if not _grid_dip(g0, g1, g2):
                    continue
                tm, fm, gm, okm = gap_min(top * max(i - 1, 0) / m, top * min(i + 1, m) / m, p,
                                           a, front, elbow, K, th)
                if okm and fm < GAP_NEAR_DEPTH and gm * g1 > 0.0:
                    count = _gap_candidate(tm, p, a, front, elbow, R07, Td, K, hint, has_hint, out,
                                           count, filt, ws, mats)
    return count


@njit
def _beyond_the_stretch(t_in, t_out, g_in, p, a, front, elbow, R07, Td, K, hint, has_hint, out,
                        count, filt, ws, mats):
    """The roots of the bend gap just beyond the end of the arm branch (``front``, ``elbow``)
    between ``t_in`` (gap ``g_in``) and ``t_out``, where the elbow stretches: the exact model
    reaches further than the nominal one, so the gap of the nominal arm allowed to miss by
    REACH_SLACK_DEVIATING in the elbow's cosine is searched up to where that slack ends
    (:func:`reach_end`; :func:`_slack_roots`). A member deviating like the published models had
    its source 0.034 rad in theta5 beyond a branch's end, where the gap came from +0.29: its
    nominal arm short by 3e-5 in the elbow's cosine there, and nothing was tried."""
    t_s = reach_end(t_in, t_out, reach_slack(K), p, a, front, K)
    return _slack_roots(t_in, t_s, g_in, p, a, front, elbow, R07, Td, K, hint, has_hint, out,
                        count, filt, ws, mats)


@njit
def _near_the_stretch(es, i, K):
    """Whether the cell [i, i + 1] of the near misses' grid may hold a stretch of theta5 where the
    exact model's elbow reaches and the nominal one's does not (``es``: the elbow's excess over
    its reach on the grid, negative where it reaches, :func:`reach_excess`): at either end the
    excess within the slack of the stretch (:func:`reach_slack`), or either end a grid maximum
    of it within REACH_PEAK (the hole between grid points can be far deeper than the grid shows:
    a maximum of -1.6e-3 on the grid, +6.3e-3 0.1 rad beside it)."""
    m = len(es) - 1
    if max(es[i], es[i + 1]) > -reach_slack(K):
        return True
    for j in (i, i + 1):
        if 0 < j < m and es[j] >= es[j - 1] and es[j] >= es[j + 1] and es[j] > -REACH_PEAK:
            return True
    return False


@njit
def _slack_roots(ta, tb, ga, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count, filt,
                 ws, mats):
    """Each sign change of the gap of the nominal arm allowed to miss by REACH_SLACK_DEVIATING in
    the elbow's cosine (:func:`ik7r._kernels.gaps.gap`, front +-6: the nearest arm) over [ta,
    tb] on REACH_SLACK_CELLS cells (``ga``: its value at ``ta``, nan if undefined), its root a
    candidate. The cells are needed: the reach need not be monotone there (beside the lateral
    offset's cylinder a member's elbow came back within reach 0.04 rad beyond a branch's end,
    and the gap is undefined where the centre is inside the cylinder)."""
    th = ws[W_TH:W_TH + NTH]
    for k in range(1, REACH_SLACK_CELLS + 1):
        t = ta + (tb - ta) * k / REACH_SLACK_CELLS
        g, ok = gap(t, p, a, 6.0 * front, elbow, K, th)
        if not ok:
            ga = math.nan
            continue
        if ga * g <= 0.0:
            t_r = gap_root(t - (tb - ta) / REACH_SLACK_CELLS, t, ga, g, p, a, 6.0 * front, elbow, K,
                           th) if g != 0.0 else t
            count = _gap_candidate(t_r, p, a, 6.0 * front, elbow, R07, Td, K, hint, has_hint, out,
                                   count, filt, ws, mats)
        ga = g
    return count


@njit
def _grid_dip(g0, g1, g2):
    """Whether the grid value ``g1`` of a gap, between ``g0`` and ``g2`` of its sign, is a least
    ``|gap|`` below GAP_NEAR_GRID: a near miss for :func:`gap_near_misses` and
    :func:`_lateral_inside` to minimise (NaN, a branch end, fails the comparisons)."""
    return (abs(g1) < GAP_NEAR_GRID and g0 * g1 > 0.0 and g1 * g2 > 0.0
            and abs(g1) <= abs(g0) and abs(g1) <= abs(g2))


@njit
def _islands(top, p, a, front, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """The near misses of :func:`gap_near_misses` on the islands of the shoulder branch
    ``front`` (+-1) that its grid does not see: stretches of theta5 where the elbow reaches with
    no more than one grid point in them, between points where it does not (seen: [1.157, 1.215]
    against cells of 0.26 rad, with the deviating model's solutions at its end, the elbow
    stretched). One grid point that reaches between two that do not, and a grid minimum of the
    elbow's excess beyond its reach (:func:`reach_excess`, smooth) between two more that dips
    inside the reach (Brent's minimiser, stopped at the first point inside), are bisected for
    the island's ends (:func:`branch_end`); each half of the island, each elbow, is then
    minimised for ``|gap|`` as a grid point beside a branch end is, and a minimum below
    GAP_NEAR_DEPTH is a candidate. (An island within one cell whose excess keeps falling to a
    grid point beyond is not seen; neither is one the lateral offset's cylinder alone makes.)"""
    m = GAP_NEAR_CELLS
    es = ws[W_SCAN + m + 1:W_SCAN + 2 * m + 2]  # (the first m + 1: the gaps' grid)
    th = ws[W_TH:W_TH + NTH]
    for i in range(m + 1):
        es[i] = reach_excess(top * i / m, p, a, front, K)
    for i in range(m + 1):
        # (at an end of the range the one neighbour is taken twice, as in gap_near_misses)
        j0, j2 = max(i - 1, 1 - i), min(i + 1, 2 * m - 1 - i)
        e0, e1, e2 = es[j0], es[i], es[j2]
        if not (e0 > 0.0 and e2 > 0.0):
            continue
        t0, t1 = top * max(i - 1, 0) / m, top * min(i + 1, m) / m
        ti = top * i / m
        if e1 > 0.0:
            if not (e1 <= e0 and e1 <= e2 and math.isfinite(e1)):
                continue
            # (the first point inside the reach, else the least excess: not reached below)
            ti = gap_min(t0, t1, p, a, 4.0 * front, 1.0, K, th, 0.0, 1.0)[0]
        if not gap_reaches(ti, p, a, front, 1.0, K, th):
            continue
        lo = 0.0 if i == 0 and e1 <= 0.0 else branch_end(ti, t0, p, a, front, 1.0, K, th)
        hi = top if i == m and e1 <= 0.0 else branch_end(ti, t1, p, a, front, 1.0, K, th)
        mid = 0.5 * (lo + hi)
        for elbow in (1.0, -1.0):
            for ta, tb in ((lo, mid), (mid, hi)):
                tm, fm, _, okm = gap_min(ta, tb, p, a, front, elbow, K, th)
                if okm and fm < GAP_NEAR_DEPTH:
                    count = _gap_candidate(tm, p, a, front, elbow, R07, Td, K, hint, has_hint,
                                           out, count, filt, ws, mats)
    return count


@njit
def _scan_piece(ta, tb, sub, npieces, front, elbow, p, a, R07, Td, K, hint, has_hint, out,
                count, filt, ws, mats, cells=SCAN_GRID, given=-1):
    """One grid of :func:`scan_theta5` over [ta, tb] on one arm branch; the pieces next to
    branch ends and around dips it finds are appended to ``sub`` (while there is room: a piece
    is two cells of the one that found it, so they nest). In the fold scan of a deviating model
    a branch's end is itself a candidate (see FOLD_END_NEAR). ``cells``: the grid's (at most
    SCAN_GRID). ``given`` >= 0: the grid's values are row ``given`` of the work block W_PAIR
    (:func:`scan_theta5` evaluated them, both elbows at once). Returns (count, npieces)."""
    m = cells
    gs = ws[W_SCAN:W_SCAN + m + 1]
    th = ws[W_TH:W_TH + NTH]
    near = SCAN_NEAR if K[L.DEVIATION] == 0.0 else SCAN_NEAR_DEVIATING
    if tiny_piece(ta, tb):
        # a piece this narrow (an undecided bracket of the polynomial at its width limit) holds
        # roots within SCAN_TINY of each other, which its grid would not tell apart from rounding
        # (every grid point could look like a dip): its sign change, else its least |gap|
        g0, ok0 = gap(ta, p, a, front, elbow, K, th)
        g1, ok1 = gap(tb, p, a, front, elbow, K, th)
        if ok0 and ok1 and g0 * g1 < 0.0:
            t = gap_root(ta, tb, g0, g1, p, a, front, elbow, K, th)
        else:
            t, fm, _, _ = gap_min(ta, tb, p, a, front, elbow, K, th)
            if not fm < near:
                return count, npieces
        return _gap_candidate(t, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count, filt,
                              ws, mats), npieces
    for i in range(m + 1):
        if given >= 0:
            gs[i] = ws[W_PAIR + given * (SCAN_GRID + 1) + i]
        else:
            g, ok = gap(ta + (tb - ta) * i / m, p, a, front, elbow, K, th)
            gs[i] = g if ok else np.nan
    first = ta == sub[0] and tb == sub[1]
    for i in range(m + 1):
        gi = gs[i]
        ti = ta + (tb - ta) * i / m
        if front == 0.0 and first and i > 0:
            # the shoulder gap jumps where its shoulder branch switches (the virtual centre
            # crosses axis 1): a cell that holds a switch, with the gap near zero at one of
            # its ends, is scanned as two pieces, one each side (an exact 45 deg member's pair
            # 3e-3 apart beside one, on a plateau of the other branch's gap that Brent's
            # minimiser took for the whole cell)
            if (2 * npieces + 2 <= len(sub)
                    and (abs(gi) < SHOULDER_SWITCH_NEAR or abs(gs[i - 1]) < SHOULDER_SWITCH_NEAR)):
                t_prev = ta + (tb - ta) * (i - 1) / m
                s0, ok0 = shoulder_side(t_prev, p, a, K)
                s1, ok1 = shoulder_side(ti, p, a, K)
                if ok0 and ok1 and s0 != s1:
                    t_sw = shoulder_switch(t_prev, ti, p, a, K)
                    sub[2 * npieces], sub[2 * npieces + 1] = t_prev, t_sw
                    sub[2 * npieces + 2], sub[2 * npieces + 3] = t_sw, ti
                    npieces += 2
        if i < m and math.isfinite(gi) != math.isfinite(gs[i + 1]) and 2 * npieces < len(sub):
            # the branch ends in this cell: bisect for the end, then scan the defined part
            t_in = branch_end(ti if math.isfinite(gi) else ta + (tb - ta) * (i + 1) / m,
                               ta + (tb - ta) * (i + 1) / m if math.isfinite(gi) else ti,
                               p, a, front, elbow, K, th)
            edge = ti if math.isfinite(gi) else ta + (tb - ta) * (i + 1) / m
            if abs(front) == 2.0:
                g_end, ok_end = gap(t_in, p, a, front, elbow, K, th)
                if ok_end and abs(g_end) < FOLD_END_NEAR:
                    count = _gap_candidate(t_in, p, a, front, elbow, R07, Td, K, hint, has_hint,
                                           out, count, filt, ws, mats)
            sub[2 * npieces] = min(t_in, edge)
            sub[2 * npieces + 1] = max(t_in, edge)
            npieces += 1
        if not math.isfinite(gi):
            continue
        if abs(front) == 2.0 and i == 0 and gi != 0.0 and abs(gi) < near:
            # the fold scan's start is the fully bent wrist itself, where the fold gap of a pose
            # made there vanishes: a candidate whatever the cell beside it holds
            count = _gap_candidate(ti, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count,
                                   filt, ws, mats)
        t = ti
        have = gi == 0.0  # (theta1 may be negative: a flag, not a sentinel value)
        if not have and i < m and math.isfinite(gs[i + 1]) and gi * gs[i + 1] < 0.0:
            t = gap_root(ti, ta + (tb - ta) * (i + 1) / m, gi, gs[i + 1], p, a, front, elbow, K, th)
            have = True
            if front == 0.0 and K[L.DEVIATION] > 0.0 and ta == sub[0] and tb == sub[1]:
                # (a root's exact solutions move as far as a dip's, and may come as a pair)
                count = _shoulder_exact(t, elbow, p, a, R07, Td, K, hint, out, count, ws, mats)
        elif (not have and (i == 0 or not math.isfinite(gs[i - 1]) or abs(gi) < abs(gs[i - 1]))
              and (i == m or not math.isfinite(gs[i + 1]) or abs(gi) <= abs(gs[i + 1]))):
            # a dip of |gap|: a tangential root, or two roots within one grid cell
            lo_i = max(0, i - 1)
            hi_i = min(m, i + 1)
            t_lo = ta + (tb - ta) * lo_i / m
            t_hi = ta + (tb - ta) * hi_i / m
            # (the gaps in theta1, front 0 and 3, are minimised to the end: see DIP_FLOOR)
            tm, fm, gm, okm = gap_min(t_lo, t_hi, p, a, front, elbow, K, th,
                                       DIP_FLOOR if front != 0.0 and front != 3.0 else 0.0)
            nest = SCAN_NEST_FOLD_AXIS if front == 3.0 else SCAN_NEST
            nests = fm < near and 2 * npieces < len(sub) and t_hi - t_lo >= nest * (sub[1] - sub[0])
            split = okm and gm * gi < 0.0
            if split:
                for t_end, g_end in ((t_lo, gs[lo_i]), (t_hi, gs[hi_i])):
                    if math.isfinite(g_end) and g_end * gm < 0.0:
                        count = _root_between(t_end, g_end, tm, gm, p, a, front, elbow, R07, Td,
                                              K, hint, has_hint, out, count, filt, ws, mats)
            if okm and fm < SCAN_NEAR and (split or not nests):
                # the bottom is a root, but the gap has the grid's sign on either side of it: it
                # has a partner in these cells, which no finer grid will scan, unless it is a
                # tangency (a shoulder-set pair 3e-3 rad apart with 1.7e-7 between them, where
                # the least |gap| was the one whose side has the grid's sign). Past the signed
                # gap's extremum, the side away from this root holds the partner. Where the
                # split above ran, the bottom's sign was its rounding's, and the far side's
                # bracket may have closed on this root again (an exact 45 deg member's
                # shoulder-set pair 3.6e-3 apart lost its second so, on every grid): the same.
                tx, _, gx, okx = gap_min(t_lo, t_hi, p, a, front, elbow, K, th, 0.0,
                                         1.0 if gi > 0.0 else -1.0)
                t_end, g_end = (t_hi, gs[hi_i]) if tm < tx else (t_lo, gs[lo_i])
                if okx and gx * gi < 0.0 and math.isfinite(g_end) and g_end * gx < 0.0:
                    count = _root_between(t_end, g_end, tx, gx, p, a, front, elbow, R07, Td, K,
                                          hint, has_hint, out, count, filt, ws, mats)
            if fm < near:  # (also when split: at a tangency the bottom itself is the root)
                t = tm
                have = True
            if (front == 0.0 and K[L.DEVIATION] > 0.0 and fm < SHOULDER_DIP and ta == sub[0]
                    and tb == sub[1]):
                count = _shoulder_exact(tm, elbow, p, a, R07, Td, K, hint, out, count, ws, mats)
            if nests:
                # a dip that reaches (nearly) zero may hide more than one root: scan it again
                # on a grid of its own
                sub[2 * npieces] = t_lo
                sub[2 * npieces + 1] = t_hi
                npieces += 1
        if have:
            count = _gap_candidate(t, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count,
                                   filt, ws, mats)
    return count, npieces


@njit
def scan_shoulder(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Near the shoulder singular set (no lateral offset; the line of virtual centres
    ``p - t a`` passes within SHOULDER_NEAR of the robot's size from axis 1, at a d in range;
    SHOULDER_NEAR_FOLD where that d lies in the fold scan's span; on a deviating model within
    SHOULDER_SCAN_DEVIATING, see :func:`shoulder_offset`):
    every solution from the bend gap in theta1 (:func:`shoulder_gap`) on a grid over the whole
    turn, both elbow branches. A deviating model whose lateral offset is as small as the
    deviation's reach (:func:`small_lateral_turn`; a member with b = -2 mm and wrist offsets of
    0.11 mm missed sources there) has the exact model tracked over the whole turn of q1
    (:func:`_shoulder_turn`, which starts from the arm the gap in theta1 gives as if b were 0;
    the tracking is on the model as written)."""
    if K[L.B] != 0.0:
        if small_lateral_turn(p, a, K):
            for elbow in (1.0, -1.0):
                count = _shoulder_turn(elbow, p, a, R07, Td, K, hint, out, count, ws, mats)
        return count
    if a[0] * a[0] + a[1] * a[1] < 1e-24:
        return count  # a along axis 1: P' is at one distance from it for every d
    t, r = line_to_axis1(p, a)
    d = t - K[L.D7]
    if K[L.DEVIATION] == 0.0:
        near = SHOULDER_NEAR
        if u_fold(K) < FOLD_NEAR and d > 0.0 and K[L.KW] < (u_fold(K) + FOLD_SPAN) * d:
            near = SHOULDER_NEAR_FOLD  # (the closest approach in the fold scan's span)
        if r > near * K[L.SCALE]:
            return count
    elif shoulder_offset(p, a, K) > SHOULDER_SCAN_DEVIATING:
        return count
    if not d_near_range(d, K) and not turn_scanned(p, a, K):
        return count  # (a deviating model whose line passes near axis 1 at an end of the range: on)
    return _scan_turn(0.0, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)


@njit
def _scan_turn(front, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Every root of a gap in theta1 (``front`` 0: :func:`shoulder_gap`, 3: :func:`_fold_axis_gap`)
    on a grid over the whole turn (:func:`_scan_piece`, nested pieces), both elbow branches.

    Where a deviating model's line of virtual centres passes within SHOULDER_EXACT_NEAR of axis
    1 (``turn``) the exact model is tracked over the whole turn (:func:`_shoulder_turn`) and only
    the nominal gap's first grid is scanned: its roots and dips start the dip-centred scans of
    :func:`_shoulder_exact`, while the nested pieces would refine nominal roots whose exact
    solutions those scans find anyway (the same solution sets over 12,000 near-shoulder poses
    of four deviating robots without them; they were 600 of such a pose's 830 gap values)."""
    sub = ws[W_SUB:W_SUB + 2 * SCAN_PIECES]
    turn = front == 0.0 and turn_scanned(p, a, K)
    for elbow in (1.0, -1.0):
        sub[0] = -math.pi
        sub[1] = math.pi
        npieces = 1
        j = 0
        while j < npieces:
            count, npieces = _scan_piece(sub[2 * j], sub[2 * j + 1], sub, npieces, front, elbow,
                                         p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
            j += 1
            if turn:
                break  # (the first grid only: see above)
        if turn:
            count = _shoulder_turn(elbow, p, a, R07, Td, K, hint, out, count, ws, mats)
    return count


@njit
def _shoulder_turn(elbow, p, a, R07, Td, K, hint, out, count, ws, mats, front=0.0):
    """Where the line of virtual centres passes within SHOULDER_EXACT_NEAR of axis 1
    (:func:`shoulder_offset`), on a model that deviates from the idealised one: every exact
    solution on the elbow branch ``elbow`` over the whole turn of q1. There the deviation moves the virtual
    centre by as much as its distance from axis 1 or more, so the exact solutions lie anywhere
    in theta1, not only near the nominal gap's dips (an IRB 5400 pose with the line 1.1e-5 of
    the size from axis 1 has one 1.2 rad from the nearest dip). The exact model's reduced
    residual in q1 (:func:`_reduced_at`) is tracked over the turn on REDUCED_GRID cells, one
    closed curve per wrist sign, from the nominal arm and wrist at the first grid point the
    branch reaches, or where none does, from the nearest arm of the first that misses by less
    than SHOULDER_TURN_SLACK; the dip-centred scans of :func:`_shoulder_exact` (finer,
    SHOULDER_REACH each way) still resolve the close pairs beside the dips. Then again from
    the nominal arm half a turn on (see TURN_TRACKED): the centre near axis 1 is reached in
    front and over the back, each a curve of its own in q1, and a turn from one arm need not
    come onto the other's; a wrist sign whose start a whole turn of the pose already passes
    through is not tracked again.

    ``front`` 3: the same at the fully bent wrist of a (nearly) 45 deg twist with the approach
    along axis 1 (:func:`scan_fold`), from the arm of the fold gap in theta1 (its virtual centre
    at infinity along axis 1 leaves the nominal arm's theta1 free there, as on the shoulder
    set: a member deviating 0.15 mm had a pair of solutions 5e-5 rad apart in q1 where that gap
    is 0.3 and more from zero on either elbow)."""
    th = ws[W_TH:W_TH + NTH]
    k = _turn_arm(0, REDUCED_GRID, p, a, front, elbow, K, th)
    if k < 0:
        return count
    arm_frame(th, R07, K, ws, mats)
    count = _q1_scans(th, TWO_PI, 0.0, REDUCED_GRID, Td, K, hint, out, count, ws, mats)
    if _turn_arm(k + REDUCED_GRID // 2, 1, p, a, front, elbow, K, th) < 0:
        return count
    arm_frame(th, R07, K, ws, mats)
    return _q1_scans(th, TWO_PI, 0.0, REDUCED_GRID, Td, K, hint, out, count, ws, mats, True)


@njit
def _turn_arm(k_from, n, p, a, front, elbow, K, th, fold=False):
    """The first of the ``n`` grid points from ``k_from`` on (REDUCED_GRID over the whole turn of
    theta1) whose nominal arm on the elbow branch ``elbow`` reaches the centre, or where none
    does, the first that misses by less than SHOULDER_TURN_SLACK, widened with the deviation's
    reach (:func:`deviation_widening`; its arm into ``th``); -1 where none. ``front`` 3: the arm
    of the fold gap in theta1 (:func:`ik7r._kernels.gaps.gap`), where it reaches with the wrist
    short of fully bent (no slack), or ``fold``: at the fold itself as well."""
    for slack in (1e-12, SHOULDER_TURN_SLACK * deviation_widening(K)):
        for i in range(n):
            k = (k_from + i) % REDUCED_GRID
            t1 = K[L.SIGN] * (-math.pi + TWO_PI * k / REDUCED_GRID) + K[L.THETA_OFFSET1]
            if front == 3.0:
                _, ok = gap(t1, p, a, 3.0, elbow, K, th)
                ok = ok and (fold or th[6] < math.pi)
            else:
                _, ok = shoulder_gap(t1, p, a, elbow, K, th, slack)
            if ok:
                return k
        if front == 3.0:
            break
    return -1


@njit
def _q1_scans(th, span_a, span_b, cells, Td, K, hint, out, count, ws, mats, untracked=False):
    """The exact model's reduced residual in q1 (:func:`reduced_scan`) tracked from the
    nominal arm of ``th`` (made into ``ws`` and ``mats`` by :func:`arm_frame`) with its wrist of
    either sign, from its q1 over ``span_a`` and then ``span_b`` (rad, user q1; 0: no scan), on
    ``cells`` cells each. A scan shorter than the whole turn that ends inside its valley with roots
    that may go on (:func:`_valley_goes_on`) goes on by its span again, up to SHOULDER_VALLEY_END
    from its start. Where the whole turns of the two wrist signs end on one curve, the turn is
    tracked again, each scan keeping its wrist's sign (see TURN_START_ROUNDS): the branch the
    two left was otherwise seen by the dip-centred scans alone. After each whole turn the cells
    where it jumped off a root's valley or left the fully bent wrist are scanned again
    (:func:`ik7r._kernels.reduced.rescan_jumps`). ``untracked`` (a whole turn): a wrist sign whose
    start, taken to its least-squares point, a whole turn of the pose passes through already
    (:func:`ik7r._kernels.reduced.turn_tracked`) is not scanned, and a scan stops where it
    joins such a turn, and is then tracked from its start the other way round until it joins
    one too (nor is the turn tracked again where both end on one curve)."""
    Q = mats[MAT_Q, :3, :3]
    q = ws[W_Q6:W_Q6 + 6]
    qq = ws[W_QQ:W_QQ + 6]
    t5 = max(th[6], SHOULDER_TURN_BEND)
    t4_hint = K[L.SIGN + 3] * hint[3] + K[L.THETA_OFFSET4]
    v0 = q[0]
    turn = span_b == 0.0 and abs(abs(span_a) - TWO_PI) < 1e-12
    end = ws[W_TEND:W_TEND + 6]
    one_curve = False
    for sgn in (1.0, -1.0):
        for span in (span_a, span_b):
            if span == 0.0:
                continue
            # (the start into qq: reduced_scan reads it once, before it adds anything)
            with_wrist(q, Q, sgn * t5, math.cos(t5), sgn * math.sin(t5), t4_hint, K, mats, qq)
            if untracked and turn_tracked(qq, v0, Td, K, ws):
                continue
            count = reduced_scan(qq, 0, v0, v0 + span, cells, Td, K, out, count, ws, mats, False,
                                 untracked)
            if turn:
                if sgn > 0.0:
                    for i in range(6):
                        end[i] = ws[W_SEND + i]
                else:
                    one_curve = apart(end, ws[W_SEND:W_SEND + 6]) < CLOSED_TOL
                count = rescan_jumps(0, Td, K, out, count, ws, mats)
                if untracked and abs(ws[W_SEND] - (v0 + span)) > 1e-9:
                    # it stopped where it joined a scanned turn: its curve behind the start is
                    # tracked the other way round, from the same start, until it joins one too
                    # (the start settled as before; no whole turn of the memo passed through it
                    # then, and the forward scan that joined is kept in none)
                    with_wrist(q, Q, sgn * t5, math.cos(t5), sgn * math.sin(t5), t4_hint, K, mats,
                               qq)
                    settle_start(qq, v0, Td, K)
                    count = reduced_scan(qq, 0, v0, v0 - span, cells, Td, K, out, count, ws, mats,
                                         False, True)
                    count = rescan_jumps(0, Td, K, out, count, ws, mats)
                continue
            v = v0 + span
            while (abs(v - v0) + abs(span) <= SHOULDER_VALLEY_END + 1e-12
                   and _valley_goes_on(ws[W_SEND + 6], ws[W_SEND + 7], ws[W_SEND + 8])):
                for i in range(6):
                    qq[i] = ws[W_SEND + i]
                count = reduced_scan(qq, 0, v, v + span, cells, Td, K, out, count, ws, mats)
                v += span
    if turn and one_curve and not untracked:
        # both wrist signs ended on one curve: the turn again, each scan keeping its wrist's sign
        # from a start taken to its least-squares point (see TURN_START_ROUNDS)
        for sgn in (1.0, -1.0):
            with_wrist(q, Q, sgn * t5, math.cos(t5), sgn * math.sin(t5), t4_hint, K, mats, qq)
            count = reduced_scan(qq, 0, v0, v0 + span_a, cells, Td, K, out, count, ws, mats, True)
            count = rescan_jumps(0, Td, K, out, count, ws, mats)
    return count


@njit
def _valley_goes_on(e_end, r_before, r_end):
    """Whether a dip-centred scan in q1 that ends with the error's norm ``e_end`` and the
    residual ``r_before``, ``r_end`` at its last two points ends inside the dip's valley with
    roots that may go on beyond it: ``e_end`` below DIP_NEAR, and the residual crossed zero over
    the last cell or fell to less than half toward it. (``|e|`` alone goes on for a scan in five
    of the IRB 5400's near-shoulder poses, and found nothing more there.)"""
    if not (e_end < DIP_NEAR and math.isfinite(r_before) and math.isfinite(r_end)):
        return False
    return r_before * r_end <= 0.0 or abs(r_end) < 0.5 * abs(r_before)


@njit
def _shoulder_exact(t1, elbow, p, a, R07, Td, K, hint, out, count, ws, mats):
    """Near the shoulder set, on a model that deviates from the idealised one: every exact
    solution next to the dip at theta1 = ``t1`` (DH) of the nominal shoulder gap on the elbow
    branch ``elbow``, within SHOULDER_REACH of it. There the deviation moves the virtual
    centre, a fraction of a millimetre from axis 1, by a good part of its distance from it, so
    the exact model's
    solutions lie 0.1 rad and more from the nominal ones in theta1 and come in pairs where the
    nominal gap has only a dip (the idealised roots are complex). With theta1 fixed the five
    other joints are regular, so they are the zeros of the exact model's reduced residual in q1
    (:func:`_reduced_at`), tracked from the nominal arm and wrist at the dip (both wrist signs)
    SHOULDER_REACH either way (:func:`reduced_scan`). Only where the line of virtual
    centres passes within SHOULDER_EXACT_FAR of axis 1 (:func:`shoulder_offset`), beyond
    SHOULDER_EXACT_NEAR with the reach shrinking as its distance grows: further out the
    nominal candidates and their polish find these solutions (within SHOULDER_EXACT_NEAR the
    whole turn is scanned as well: :func:`_shoulder_turn`)."""
    r = shoulder_offset(p, a, K)  # (a is not along axis 1: scan_shoulder checked)
    if r > SHOULDER_EXACT_FAR:
        return count
    if _dip_scanned(t1, elbow, ws):
        return count
    reach = SHOULDER_REACH if r <= SHOULDER_EXACT_NEAR else SHOULDER_REACH * SHOULDER_EXACT_NEAR / r
    cells = max(2, int(math.ceil(SHOULDER_CELLS * reach / SHOULDER_REACH)))
    th = ws[W_TH:W_TH + NTH]
    _, ok = shoulder_gap(t1, p, a, elbow, K, th)
    if not ok:
        return count
    arm_frame(th, R07, K, ws, mats)
    q1 = ws[W_Q6]
    return _q1_scans(th, wrap(user_angle(0, t1 - reach, K) - q1), wrap(user_angle(0, t1 + reach, K) - q1),
                     cells, Td, K, hint, out, count, ws, mats)


@njit
def _dip_scanned(t1, elbow, ws):
    """Whether :func:`_shoulder_exact` has scanned the dip at theta1 = ``t1`` (DH) on the elbow
    branch ``elbow`` in this pose already (within SHOULDER_DIP_SAME); if not, it is remembered
    (while there is room for it: SHOULDER_DIPS)."""
    n = int(ws[W_NSDIP])
    for k in range(n):
        if ws[W_SDIP + 2 * k + 1] == elbow and abs(wrap(t1 - ws[W_SDIP + 2 * k])) < SHOULDER_DIP_SAME:
            return True
    if n < SHOULDER_DIPS:
        ws[W_SDIP + 2 * n] = t1
        ws[W_SDIP + 2 * n + 1] = elbow
        ws[W_NSDIP] = n + 1
    return False


#: The end of the fold scan's span in sw (a little past where the polynomial search begins)
FOLD_SCAN_TOP = math.sqrt(FOLD_SPAN) * (1.0 + 1e-3)


@njit
def _short_row(front):
    """Where in the work array the fold scan's first grid keeps the shortfalls of the shoulder
    branch ``front`` (``fold_gap_pair``'s fifth value: how far the elbow falls short)."""
    return W_SHORT + (0 if front > 0.0 else SCAN_GRID + 1)


@njit
def _fold_azimuth(th, p, a, R07, K, ws, mats):
    """The fold gap's arm ``th`` made into frame 3 (``mats[MAT_M]``, with the wrist's target
    ``mats[MAT_Q]`` and the arm's user joints in ``ws[W_Q6:W_Q6 + 3]``: :func:`arm_frame`), and
    the azimuth of O - O4 (O the centre of joint 6) about axis 4, in frame 3 turned by alpha3
    (frame 4 at theta4 = 0), from which :func:`with_fold_wrist` takes theta4."""
    arm_frame(th, R07, K, ws, mats)
    M = mats[MAT_M]
    d7 = K[L.D7]
    vx = p[0] - d7 * a[0] - th[7]
    vy = p[1] - d7 * a[1] - th[8]
    vz = p[2] - d7 * a[2] - th[9]
    x3 = M[0, 0] * vx + M[1, 0] * vy + M[2, 0] * vz
    y3 = M[0, 1] * vx + M[1, 1] * vy + M[2, 1] * vz
    z3 = M[0, 2] * vx + M[1, 2] * vy + M[2, 2] * vz
    return math.atan2(K[L.NOMINAL_TRIG + 6] * y3 + K[L.NOMINAL_TRIG + 7] * z3, x3)


@njit(allocates=True)
def _fold_beyond_reach(p, a, R07, Td, K, out, count, ws, mats):
    """Solutions beside the fully bent wrist where the nominal arm falls just short (a 45 deg
    twist: the virtual centre goes to infinity at the fold). On a deviating model the wrist's
    deviation moves the exact solutions beyond the nominal arm's reach (the rounded 45 deg robot
    with the elbow stretched: the nominal elbow 0.016 to 0.07 mm short of the fold gap's
    centre); on the idealised one the arm may reach over an island narrower than a cell of the
    fold scan's grid (an exact member with a lateral offset, short by 2.8e-4 mm at a grid point).
    Where a shoulder branch's elbow falls short by no more than FOLD_REACH_SLACK times the
    deviation, or FOLD_REACH_ISLAND of the size, at a point of the fold scan's first grid or at
    the least between two of them (:func:`_fold_splits` left it in ``ws[W_LEAST]``), or reaches
    there over an island the grid does not see, the model's reduced residual in q5
    (:func:`reduced_scan`) is followed from the arm there with the elbow stretched toward the
    centre, each wrist, to the fold and back to the span's end."""
    th = ws[W_TH:W_TH + NTH]
    top = FOLD_SCAN_TOP
    slack = max(FOLD_REACH_SLACK * K[L.DEVIATION], FOLD_REACH_ISLAND * K[L.SCALE])
    for front in (1.0, -1.0):
        k = _least_slot(front)
        least = ws[k]
        at = ws[k + 1]
        if not least <= slack:
            continue
        _, ok = fold_gap(at, p, a, front, 1.0, K, th, 0.0, False, slack)
        if not ok:
            continue
        az = _fold_azimuth(th, p, a, R07, K, ws, mats)
        Q = mats[MAT_Q, :3, :3].copy()
        q = ws[W_Q6:W_Q6 + 6].copy()
        start = np.empty(6)
        eps = fold_eps(at, K)
        rest = fold_eps(top, K) - eps
        for sgn in (1.0, -1.0):
            for v in (eps, -rest):  # (theta5 to the fold, then back to the span's end)
                if v == 0.0:
                    continue
                with_fold_wrist(q, Q, sgn * (math.pi - eps), -math.cos(eps), sgn * math.sin(eps), az,
                                K, mats, start)
                # (from two cells behind the start: the scan sees no dip in its first cell, and
                # the stretched arm's own pair of roots, one per elbow, may lie either side of it)
                step = K[L.SIGN + 4] * sgn * v
                count = reduced_scan(start, 4, start[4] - 2.0 * step / REDUCED_GRID, start[4] + step,
                                     REDUCED_GRID, Td, K, out, count, ws, mats)
    return count


@njit
def _fold_candidate(sw, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count, filt, ws, mats,
                    t1=0.0, in_plane=False):
    """Complete the root ``sw`` of the fold gap on the branch (front, elbow) with the wrist and
    accept what is exact: theta5 = +-(pi - eps) (and pi itself when eps < FOLD_WINDOW); theta4
    from the position of O (the centre of joint 6) about axis 4, which stays defined where the
    orientation leaves only theta7 - theta4 (axis 7 folded back parallel to axis 4), then theta7
    from the orientation. ``t1``, ``in_plane``: the arm in that plane (:func:`_fold_axis_gap`)."""
    th = ws[W_TH:W_TH + NTH]
    _, ok = fold_gap(sw, p, a, front, elbow, K, th, t1, in_plane)
    if not ok and not in_plane:
        # a root where the shoulder branches meet (the lateral offset's cylinder): its bracket
        # may end just inside, where no branch is defined; the meeting itself, in closed form
        for m in fold_meetings(p, a, K):
            if not ok and abs(m - sw) < FOLD_MEET_SNAP:
                sw = m
                _, ok = fold_gap(sw, p, a, front, elbow, K, th, t1, in_plane)
    if not ok:
        return count
    if filt >= 0 and not arm_may_match(th, filt, filter_margin(K), K):
        return count
    az = _fold_azimuth(th, p, a, R07, K, ws, mats)
    Q = mats[MAT_Q, :3, :3]
    q = ws[W_Q6:W_Q6 + 6]
    qq = ws[W_QQ:W_QQ + 6]
    eps = fold_eps(sw, K)
    if eps < fold_snap(K):
        with_fold_wrist(q, Q, math.pi, -1.0, 0.0, az, K, mats, qq)
        count, exact = accept(qq, Td, K, out, count, mats, True)
        # (done unless the polish left this arm: with the approach along axis 1 the fold has
        # solutions of its own, which a start beside them may slide to)
        if exact and max(abs(wrap(qq[0] - q[0])), abs(wrap(qq[1] - q[1])),
                         abs(wrap(qq[2] - q[2]))) < FOLD_WINDOW:
            return count
    for sgn in (1.0, -1.0):
        t5 = sgn * (math.pi - eps)
        with_fold_wrist(q, Q, t5, -math.cos(eps), sgn * math.sin(eps), az, K, mats, qq)
        count, _ = accept(qq, Td, K, out, count, mats)
        if K[L.DEVIATION] > 0.0 and eps < NEAR_SINGULAR:  # (start off the singular fold too)
            alt = sgn * (math.pi - NEAR_SINGULAR)
            with_fold_wrist(q, Q, alt, math.cos(alt), math.sin(alt), az, K, mats, qq)
            count, _ = accept(qq, Td, K, out, count, mats, False, False)
    return count


@njit
def scan_fold(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Every solution within FOLD_SPAN (in u) of the fully bent wrist, for robots whose fold is
    (nearly) at infinity (``cos(2 beta)`` below FOLD_NEAR): the fold gap (:func:`fold_gap`) of each
    of the four arm branches scanned as the bend gap is (:func:`_scan_piece`), in ``sw =
    sqrt(u - cos(2 beta))`` (proportional to sin((pi - theta5) / 2): solutions close to the fold
    stay apart on the grid) from the fold (0) to just past where the polynomial search begins.
    With the approach along axis 1 (:func:`fold_near_axis`) the fold gap in theta1 too, and on a
    deviating model the exact model over the whole turn of q1 (:func:`_shoulder_turn`), and
    with the wrist held at the fold (:func:`_held_turn`)."""
    if K[L.DEVIATION] > 0.0:
        # the exact model's solutions at the fold may come from nominal roots beyond it (u below
        # cos(2 beta), theta5 clamped to pi): near a fold at infinity a twist 1e-4 rad off moves
        # the virtual centre by d 1e-4, and it may come back from the other side (u < 0)
        count = scan_theta5(-math.sqrt(FOLD_BELOW * (1.0 - u_fold(K))), 0.0, p, a, R07, Td, K,
                             hint, has_hint, out, count, filt, ws, mats, 2.0, FOLD_BELOW_CELLS)
    count = scan_theta5(0.0, FOLD_SCAN_TOP, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws,
                         mats, 2.0)
    count = _fold_beyond_reach(p, a, R07, Td, K, out, count, ws, mats)  # (the least, W_LEAST)
    if fold_near_axis(p, a, K):
        # the approach (nearly) along axis 1: the fold gap in theta1 as well, and on a finer grid
        # next to the fold (two roots there can be within 1e-4 in sw, one cell of the grid above)
        count = _scan_turn(3.0, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
        count = scan_theta5(0.0, 1e-2 * math.sqrt(FOLD_SPAN), p, a, R07, Td, K, hint, has_hint,
                             out, count, filt, ws, mats, 2.0)
        if K[L.DEVIATION] > 0.0:
            # the exact model over the whole turn of q1, as on the shoulder set
            for elbow in (1.0, -1.0):
                count = _shoulder_turn(elbow, p, a, R07, Td, K, hint, out, count, ws, mats, 3.0)
            count = _held_turns(p, a, R07, Td, K, hint, out, count, ws, mats)
    return count


@njit(allocates=True)
def _held_turns(p, a, R07, Td, K, hint, out, count, ws, mats):
    """At the fully bent wrist with the approach along axis 1, on a deviating model: the exact
    model's least error over the whole turn of q1 with joint 5 held at the fold
    (:func:`ik7r._kernels.held.held_fold_turn`), from the fold gap's arm on either elbow branch
    (:func:`_turn_arm`) at the first grid point where the fit stays on that arm (elsewhere the
    arm's curve may not be there, and a turn from it tracks the other arm's: a member with
    mirrored frames had its source on the arm the turn from its own arm's first point left),
    or where it stays nowhere, at the first where the arm reaches.
    The second turn does not search the dips the first searched. There axes 1, 4 and 7 are
    (nearly) parallel and the reduced
    residual of the whole turn (:func:`_shoulder_turn`), q1 held and the five others fitted,
    slides along the fold: a member deviating as far as the loader accepts had a pair of
    solutions 1.4e-4 rad apart in q1, 7e-4 and 7e-3 rad to either side of the fold, where the
    residual of the turn was 1e-10 .. 1e-6 and changed sign wherever its wrist crossed the fold.
    The start may be the fold gap's arm at the fold itself (where that alone reaches, the joint
    held there anyway: another such member's only solution lay there, its approach 4e-4 rad
    from axis 1, axis 4 27 mm from it, and nothing was answered)."""
    th = ws[W_TH:W_TH + NTH]
    qq = ws[W_QQ:W_QQ + 6]
    seen = np.zeros((HELD_SEEN + 1, 6))  # (the dips searched, see held_fold_turn)
    for elbow in (1.0, -1.0):
        k = 0
        k0 = -1
        stayed = False
        while k < REDUCED_GRID and not stayed:
            k = _turn_arm(k, REDUCED_GRID - k, p, a, 3.0, elbow, K, th, True)
            if k < 0:
                break
            k0 = k if k0 < 0 else k0
            _held_start(th, R07, K, hint, ws, mats)
            count, stayed = held_fold_turn(qq, REDUCED_GRID, Td, K, out, count, mats, seen,
                                           HELD_ARM)
            k += 1
        if not stayed and k0 >= 0:
            _turn_arm(k0, 1, p, a, 3.0, elbow, K, th, True)
            _held_start(th, R07, K, hint, ws, mats)
            count, _ = held_fold_turn(qq, REDUCED_GRID, Td, K, out, count, mats, seen, math.inf)
    return count


@njit
def _held_start(th, R07, K, hint, ws, mats):
    """The start of a turn of :func:`_held_turns` into ``ws[W_QQ:W_QQ + 6]``: the arm of ``th``
    (made into ``ws`` and ``mats`` by :func:`arm_frame`) with its wrist, joint 5 at the fold."""
    arm_frame(th, R07, K, ws, mats)
    t5 = th[6]
    qq = ws[W_QQ:W_QQ + 6]
    set_wrist(ws[W_Q6:W_Q6 + 6], mats[MAT_Q, :3, :3], t5, math.cos(t5), math.sin(t5),
              K[L.SIGN + 3] * hint[3] + K[L.THETA_OFFSET4], K, mats, qq)
    qq[4] = user_angle(4, math.pi, K)


@njit
def _root_between(t0, g0, t1, g1, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count,
                  filt, ws, mats):
    """The gap's root between ``t0`` and ``t1`` (in either order; its values there ``g0`` and
    ``g1`` of opposite signs, :func:`gap_root`), completed by :func:`_gap_candidate`."""
    th = ws[W_TH:W_TH + NTH]
    lo, glo, hi, ghi = (t0, g0, t1, g1) if t0 < t1 else (t1, g1, t0, g0)
    tr = gap_root(lo, hi, glo, ghi, p, a, front, elbow, K, th)
    return _gap_candidate(tr, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count, filt,
                          ws, mats)


@njit
def _gap_candidate(t, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Complete the arm branch's root ``t`` of the bend gap with the wrist; accept what is exact."""
    if abs(front) == 2.0:
        return _fold_candidate(t, p, a, 0.5 * front, elbow, R07, Td, K, hint, has_hint, out, count,
                               filt, ws, mats)
    if front == 3.0:
        sw, ok = fold_axis_sw(t, p, a, K)
        if not ok:
            return count
        return _fold_candidate(sw, p, a, 1.0, elbow, R07, Td, K, hint, has_hint, out, count, filt,
                               ws, mats, t, True)
    th = ws[W_TH:W_TH + NTH]
    if front == 0.0:
        _, ok = shoulder_gap(t, p, a, elbow, K, th)  # the arm of the root, into th; theta5 th[6]
    elif abs(front) >= 5.0:
        # (the centre taken onto the lateral cylinder; the nearest arm beyond the stretch)
        _, ok = gap(t, p, a, front, elbow, K, th)
    else:
        # (theta1 from the seed where the virtual centre is on axis 1: the gap does not depend
        # on it when axis 7 is on axis 1 too, where the pose leaves q1 free)
        _, ok = bend_gap(t, p, a, front, elbow, K, th, K[L.SIGN] * hint[0] + K[L.THETA_OFFSET1])
    if ok:
        t5 = th[6]
        count = wrist_and_accept(th, t5, math.cos(t5), math.sin(t5), R07, Td, K, hint, has_hint,
                                  out, count, filt, ws, mats)
    return count
