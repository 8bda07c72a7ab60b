"""The exact model's reduced residual, for robots that deviate from the idealised family.

With one joint held (``j`` at ``v``) the five others are fitted by Gauss-Newton to the pose
(``_reduced_at``): ``det [J_other | e]`` is a signed scalar, continuous in ``v``, zero where
the fit is a solution. ``reduced_scan`` tracks it over a range on a grid and refines its sign
changes and dips; on it stand the straight-wrist family scan (``straight_family``), the other
wrist of a solution (``other_wrists``) and the partners of nearly singular solutions
(``partners``).
"""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .answers import accept, add_answer, apart, bend, straightened, theta5, walked
from .constants import (
    BENT_STUCK,
    CLOSED_TOL,
    CONTINUUM_WINDOW,
    DIP_NEAR,
    DIP_SHARP,
    DUP_TOL,
    FOLD_WINDOW,
    JUMP_CELLS,
    JUMP_NOTED,
    MAT_M,
    MAT_Q,
    MAT_R07,
    MAT_T,
    MAT_WR,
    NFAMILIES,
    NSTRETCHED,
    NTH,
    OTHER_WRIST_ARM,
    PARTNER_CELLS,
    PARTNER_REACH,
    PARTNER_SIGMA,
    PARTNER_STEP,
    REDUCED_GRID,
    REDUCED_ITERS,
    REDUCED_ROOT_TOL,
    REDUCED_SETTLE,
    REDUCED_STALL,
    ROOT_END_STEP,
    SCAN_HEAD,
    SCAN_MEMO,
    SCAN_MEMO_TOL,
    SCAN_SLOT,
    SPLIT_PARITY_STEP,
    STALL_PATIENCE,
    STRAIGHT_DEVIATING,
    STRAIGHTEN_REACH,
    STRETCH_CHUNK,
    STRETCH_ITERS,
    STRETCH_SPLITS,
    STRETCHED_TOL,
    TRACK_JUMP,
    TURN_JOIN_TOL,
    TURN_JUMP_VALLEY,
    TURN_JUMP_WIDTH,
    TURN_START_ROUNDS,
    TURN_TRACKED,
    TWO_PI,
    W_A,
    W_FAM,
    W_JUMP,
    W_NFAM,
    W_NRSCAN,
    W_NSTR,
    W_P,
    W_QQ,
    W_RSCAN,
    W_SEND,
    W_STR,
    W_TH,
    wrap,
)
from .fk import (
    STALL_RATIO,
    dh_angle,
    fk_jacobian,
    fk_user,
    polish_into,
    pose_error,
    residual,
    user_angle,
)
from .jit import njit
from .joints import arm_with_wrist, other_wrist
from .poly import brent_next, brent_start, brent_take, illinois_step, secant_point
from .singular import deviation_widening, turn_scanned


@njit(allocates=True)
def straight_family(q, Q, Td, K, out, count, ws, mats, sheets=False, stretched=False):
    """Every exact solution near the straight-wrist family of the arm ``q[:3]`` (user angles) on a
    model that deviates from the idealised one. On the idealised model a straight wrist leaves
    only ``s4 q4 + s7 q7`` defined (a circle of solutions, the split free); the deviation breaks
    the circle into isolated solutions, spread over the whole turn of the split, with the arm
    and q5 moved by about the deviation. With q4 fixed the five other joints are regular there,
    so these solutions are the zeros of one function of q4 (:func:`reduced_scan`), found by a
    scan of the whole turn. ``Q``: the wrist target of the arm (its angle about z is the sum).
    The arms already scanned for this pose are skipped.

    Away from the shoulder set the least-squares point as q4 turns is one closed curve (q5
    about ``delta cos(q4 - phi)``, crossing zero twice), which the mirror of the wrist (theta4
    and theta7 half a turn on, theta5 of the other sign: the same wrist to first order in
    theta5) maps onto itself. Where the arm is near the shoulder set (``sheets``) q1 is nearly
    free as well and the curve splits into two sheets of one sign of q5 each, one the other's
    mirror, with q1 sweeping fast where q5 grows: a scan tracks one of them (and may jump to
    the other where q1 swings), so the other sheet is scanned too, from the mirror of the
    first one's least bent point (on the IRB 5400 the line of virtual centres 0.012 mm from
    axis 1 gave 12 solutions, four on each sheet; one was missed). There a sheet need not
    close over the turn either (it can drift onto the other before it comes back), so the last
    half turn of each is tracked back from its start too (generated(2) of the tests, a pair
    0.09 rad apart in q4 on either side of the start).

    With the elbow at its stretch (or folded) as well (``stretched``: see STRETCH_SPLITS)
    the five other joints are not regular there (the arm is singular), and the reduced
    residual may miss a solution at the straight wrist itself: the split is also tried on a
    grid of STRETCH_SPLITS over the whole turn, each start the arm with the wrist straight,
    polished by damped steps (:func:`_stretched_splits`), once per arm within STRETCHED_TOL of
    one tried before (:func:`_split_before`; the family's memo of arms does not hold for it: an
    arm scanned before need not have been as near the stretch).

    After each scan the two cells around each of its points that jumped off a root's valley are
    scanned again on a finer grid (:func:`_split_scan`, JUMP_CELLS)."""
    s4 = K[L.SIGN + 3]
    s7 = K[L.SIGN + 6]
    total = math.atan2(Q[1, 0], Q[0, 0]) - K[L.THETA_OFFSET4] - K[L.THETA_OFFSET7]
    if stretched and not _split_before(q, ws):
        x = np.empty(6)
        for i in range(3):
            x[i] = q[i]
        x[4] = user_angle(4, 0.0, K)
        count = _stretched_splits(x, total, Td, K, out, count, mats)
    nf = int(ws[W_NFAM])
    for k in range(min(nf, NFAMILIES)):
        f = ws[W_FAM + 4 * k:W_FAM + 4 * k + 4]
        far = abs(wrap(f[3] - total))
        for i in range(3):
            far = max(far, abs(wrap(f[i] - q[i])))
        if far < 1e-2:
            return count
    if nf < NFAMILIES:
        f = ws[W_FAM + 4 * nf:W_FAM + 4 * nf + 4]
        for i in range(3):
            f[i] = q[i]
        f[3] = total
        ws[W_NFAM] = nf + 1
    start = np.empty(6)
    for i in range(3):
        start[i] = q[i]
    start[3] = -math.pi
    start[4] = user_angle(4, 0.0, K)
    start[5] = s7 * (total + s4 * math.pi)
    back = start.copy()
    count = _split_scan(start, -math.pi, math.pi, REDUCED_GRID, Td, K, out, count, ws, mats)
    if not sheets:
        return count
    # near the shoulder set a sheet need not close over the turn (q1 drifts onto the other
    # sheet before the scan comes back): its last half turn is tracked back from the start too
    count = _split_scan(back, math.pi, 0.0, REDUCED_GRID // 2, Td, K, out, count, ws, mats)
    # the other sheet, from the mirror of the scanned one's least bent point: theta4 and theta7
    # half a turn on, theta5 of the other sign (the same wrist to first order in theta5)
    start[3] = wrap(start[3] + s4 * math.pi)
    start[4] = user_angle(4, -dh_angle(start, K, 4), K)
    start[5] = wrap(start[5] + s7 * math.pi)
    for i in range(6):
        back[i] = start[i]
    count = _split_scan(start, start[3], start[3] + TWO_PI, REDUCED_GRID, Td, K, out, count, ws,
                        mats)
    return _split_scan(back, back[3], back[3] - math.pi, REDUCED_GRID // 2, Td, K, out, count, ws,
                       mats)


@njit(allocates=True)
def _split_scan(start, v0, v1, m, Td, K, out, count, ws, mats):
    """:func:`reduced_scan` of the split (q4, j = 3) from ``start`` over [v0, v1] on ``m`` cells;
    then the two cells around each of its points that jumped off a root's valley (noted in
    ``ws[W_JUMP]`` by :func:`_note_jumps`) scanned again on JUMP_CELLS cells from the point
    before: roots closer than a cell that the jump hid (see JUMP_CELLS)."""
    count = reduced_scan(start, 3, v0, v1, m, Td, K, out, count, ws, mats)
    return rescan_jumps(3, Td, K, out, count, ws, mats)


@njit(allocates=True)
def rescan_jumps(j, Td, K, out, count, ws, mats):
    """The brackets the last :func:`reduced_scan` of joint ``j`` noted in ``ws[W_JUMP]`` (where it
    jumped off a root's valley, :func:`_note_jumps`, or left the fully bent wrist,
    :func:`_note_bent_exits`) scanned again on JUMP_CELLS cells each from its noted start. The
    notes are read first: these scans note their own (none: they are short)."""
    nj = int(ws[W_JUMP])
    todo = np.empty((JUMP_NOTED, 8))
    for k in range(nj):
        for i in range(8):
            todo[k, i] = ws[W_JUMP + 1 + 8 * k + i]
    for k in range(nj):
        count = reduced_scan(todo[k, 2:].copy(), j, todo[k, 0], todo[k, 1], JUMP_CELLS, Td, K, out,
                             count, ws, mats)
    return count


@njit
def _split_polish(x, Td, K, mats, J, e, dq, ZO):
    """Damped polish of a stretched split's start ``x`` (in place; see :func:`_stretched_splits`)
    for at most STRETCH_ITERS steps, STRETCH_CHUNK at a time: it gives up where a chunk has not
    brought the error (position over the robot's scale, or rotation) below STALL_RATIO of itself.
    There the steps are often clamped (the start far from its solution), which
    :func:`ik7r._kernels.fk.polish` does not count as a stall, and a start that circles would
    run all STRETCH_ITERS steps (63 of the 144 starts of an IRB 5400 pose, elbow stretched).
    ``J`` (6, 6), ``e``, ``dq`` (6,) and ``ZO`` (7, 6): the polish's work arrays
    (:func:`ik7r._kernels.fk.polish_into`), the caller's for all its starts."""
    T = mats[MAT_T]
    fk_user(x, K, T)
    dp, dr = residual(T, Td)
    mark = max(dp / K[L.SCALE], dr)
    for _ in range(STRETCH_ITERS // STRETCH_CHUNK):
        if polish_into(x, Td, K, STRETCH_CHUNK, T, J, e, dq, ZO, True, STALL_PATIENCE):
            return True
        fk_user(x, K, T)
        dp, dr = residual(T, Td)
        err = max(dp / K[L.SCALE], dr)
        if not err < STALL_RATIO * mark:
            return False
        mark = err
    return False


@njit
def _split_before(q, ws):
    """Whether the arm ``q[:3]`` is within STRETCHED_TOL (rad, each joint) of an arm whose
    stretched splits (:func:`_stretched_splits`) this pose has tried; if not, it is noted (NSTRETCHED
    of them at most, the later ones tried each time)."""
    n = int(ws[W_NSTR])
    for k in range(n):
        far = 0.0
        for i in range(3):
            far = max(far, abs(wrap(ws[W_STR + 3 * k + i] - q[i])))
        if far < STRETCHED_TOL:
            return True
    if n < NSTRETCHED:
        for i in range(3):
            ws[W_STR + 3 * n + i] = q[i]
        ws[W_NSTR] = n + 1
    return False


@njit(allocates=True)
def _stretched_splits(x, total, Td, K, out, count, mats):
    """The straight-wrist solutions of the arm ``x[:3]`` with its elbow (nearly) stretched or
    folded, on a deviating model: from the wrist straight (``x[4]``) with ``s4 q4 + s7 q7 =
    total`` and q4 on a grid of STRETCH_SPLITS over the whole turn, damped polishes
    (:func:`_split_polish`) on the exact forward kinematics; each that meets the pose is added
    (moved to the straight wrist where its valley reaches it:
    :func:`ik7r._kernels.answers.straightened`), once per
    valley: there the FK is flat in the split too,
    and starts a grid step apart stop at different points of one band of exact poses (a rounded
    member: 16 points over 0.02 rad of q4), so a point that a walk joins to one kept before
    (:func:`ik7r._kernels.answers.walked`, within CONTINUUM_WINDOW) is that one. (On the IRB
    5400 with the elbow stretched and the wrist straight, the reduced residual's scan of the
    split missed the source; 36 of 48 such starts polished onto it, to 1e-12 rad.) Between two
    roots found, the residual's signs tell of roots no start reached (:func:`_split_parity`)."""
    s4 = K[L.SIGN + 3]
    s7 = K[L.SIGN + 6]
    arm0, arm1, arm2, wrist = x[0], x[1], x[2], x[4]
    kept = np.empty((STRETCH_SPLITS, 6))
    J, e, dq, ZO = np.empty((6, 6)), np.empty(6), np.empty(6), np.empty((7, 6))
    nk = 0
    for k in range(STRETCH_SPLITS):
        x[0], x[1], x[2], x[4] = arm0, arm1, arm2, wrist
        x[3] = -math.pi + TWO_PI * k / STRETCH_SPLITS
        x[5] = s7 * (total - s4 * x[3])
        if not _split_polish(x, Td, K, mats, J, e, dq, ZO):
            continue
        one = False
        for i in range(nk):
            far = apart(kept[i], x)
            if far <= DUP_TOL or (far < CONTINUUM_WINDOW and walked(kept[i], x, Td, K, mats)):
                one = True
                break
        if not one:
            straightened(x, Td, K, mats)
            for i in range(6):
                kept[nk, i] = x[i]
            nk += 1
            count = add_answer(x.copy(), out, count, Td, K, mats)
    return _split_parity(kept, nk, Td, K, out, count, mats, J, e, dq, ZO)


@njit(allocates=True)
def _split_parity(kept, nk, Td, K, out, count, mats, J, e, dq, ZO):
    """The roots of the split that :func:`_stretched_splits`' starts left out between two they
    found (``kept[:nk]``): where the reduced residual in q4 (:func:`_reduced_at`) has opposite
    signs just past one root and just before the next (SPLIT_PARITY_STEP of the way between
    them, each by Gauss-Newton from its root), they hold an odd number of further roots
    between them, one of which is refined by Illinois to its bracket and added. (A rounded
    member with the elbow at its stretch and the wrist 2.4e-5 rad from straight: four roots
    within 0.32 rad of q4, two of them in one cell of the reduced scan beside a cell with a
    sign change, the starts on either side polished onto their neighbours.)"""
    if nk < 2:
        return count
    T = np.empty((4, 4))
    A = np.empty((6, 6))
    g = np.empty(6)
    qa = np.empty(6)
    qb = np.empty(6)
    v = np.empty(nk)
    for n in range(nk):
        v[n] = wrap(kept[n, 3])
    order = np.argsort(v)
    for n in range(nk - 1):
        a = kept[order[n]]
        b = kept[order[n + 1]]
        gap = v[order[n + 1]] - v[order[n]]
        if gap <= 2.0 * DUP_TOL:
            continue
        for i in range(6):
            qa[i] = a[i]
            qb[i] = b[i]
        va = v[order[n]] + SPLIT_PARITY_STEP * gap
        vb = v[order[n + 1]] - SPLIT_PARITY_STEP * gap
        ra, _, oka = _reduced_at(qa, 3, va, Td, K, T, J, A, e, g, dq, ZO)
        rb, _, okb = _reduced_at(qb, 3, vb, Td, K, T, J, A, e, g, dq, ZO)
        if oka and okb and ra * rb < 0.0:
            _reduced_root(qa, 3, va, vb, ra, rb, Td, K, T, J, A, e, g, dq, ZO, False)
            count, _ = accept(qa.copy(), Td, K, out, count, mats, False, False)
    return count


@njit
def _pivot(A, k):
    """The row of partial pivoting in column ``k`` of ``A`` (6, 6): the first of rows ``k`` .. 5
    with the largest ``abs(A[i, k])``."""
    p = k
    for i in range(k + 1, 6):
        if abs(A[i, k]) > abs(A[p, k]):
            p = i
    return p


@njit
def _det6(A):
    """Determinant of ``A`` (6, 6; overwritten), by elimination with partial pivoting."""
    det = 1.0
    for k in range(6):
        p = _pivot(A, k)
        if A[p, k] == 0.0:
            return 0.0
        if p != k:
            for c in range(6):
                A[k, c], A[p, c] = A[p, c], A[k, c]
            det = -det
        det *= A[k, k]
        for i in range(k + 1, 6):
            f = A[i, k] / A[k, k]
            for c in range(k, 6):
                A[i, c] -= f * A[k, c]
    return det


@njit
def _reduced_at(q, j, v, Td, K, T, J, A, e, g, dq, ZO):
    """The reduced residual at ``q[j] = v``: Gauss-Newton on the five other joints of ``q`` (from
    their values in ``q``, updated in place) for the least-squares pose error, then
    ``det [J_other | e]`` (position rows over the robot's size): a signed scalar, continuous in
    ``v``, zero exactly where the least-squares point is a solution (``e`` is orthogonal to the
    five columns there, so the determinant is ``e`` along their normal). Gauss-Newton stops
    before a step below REDUCED_SETTLE (rad): the determinant does not change when ``e`` takes
    the step's combination of the other columns (the residual the step leaves, to first order),
    so the point it would reach is worth no further forward kinematics; its residual
    ``e - J_other dq`` gives ``|e|``. Returns (r, |e|, ok); ``T`` is left at the forward
    kinematics of ``q``."""
    q[j] = v
    w = 1.0 / K[L.SCALE]
    ok = True
    for it in range(REDUCED_ITERS + 1):
        fk_jacobian(q, K, T, J, ZO)
        pose_error(T, Td, e, ZO[:3, :3])
        for r in range(3):
            e[r] *= w
            for c in range(6):
                J[r, c] *= w
        if it == REDUCED_ITERS:
            break
        if _least_squares_step(J, e, j, A, g, dq) < 1e-15:
            ok = False
            break
        big = 0.0
        for i in range(6):
            if i != j:
                big = max(big, abs(dq[i]))
        if big < REDUCED_SETTLE:
            for r in range(6):  # (the residual the step would leave; dq[j] is 0)
                s = 0.0
                for c in range(6):
                    if c != j:
                        s += J[r, c] * dq[c]
                e[r] -= s
            break
        f = 1.0 if big <= 0.1 else 0.1 / big
        for i in range(6):
            if i != j:
                q[i] += f * dq[i]
    norm = 0.0
    for r in range(6):
        norm += e[r] * e[r]
        for c in range(6):
            A[r, c] = e[r] if c == j else J[r, c]
    if not (norm < 1e300):
        return 0.0, math.inf, False
    return _det6(A), math.sqrt(norm), ok


@njit
def _wrist_again(qt, qp, j, v, r, res, Td, K, T, J, A, e, g, dq, ZO, R07, th, M, Q, W):
    """A point of the whole turn in q1 whose Gauss-Newton (from the grid's prediction ``qp``, to
    ``qt`` with ``r``, ``|e|`` = ``res``) did not settle and ended far above the point before:
    where the wrist passes close to straight, q4 and q7 turn by up to pi within a part of a
    cell, and four steps of at most 0.1 rad do not follow them. Gauss-Newton again from the
    prediction with its wrist solved for its arm's wrist target, theta5 kept
    (:func:`arm_with_wrist`; q4 and q7 on their turns nearest the prediction's), kept where it
    ends lower. ``qp`` is then work. Returns (r, |e|, ok) at the point in ``qt``."""
    qp[j] = v
    q4, q7 = qp[3], qp[5]
    arm_with_wrist(qp, theta5(qp, K), R07, K, th, M, Q, W, qp)
    qp[3] = q4 + wrap(qp[3] - q4)
    qp[5] = q7 + wrap(qp[5] - q7)
    r2, res2, ok2 = _reduced_at(qp, j, v, Td, K, T, J, A, e, g, dq, ZO)
    if ok2 and res2 < res:
        for i in range(6):
            qt[i] = qp[i]
        return r2, res2, ok2
    return r, res, True


@njit
def _settled(dq, j):
    """Whether the Gauss-Newton of the last :func:`_reduced_at` that succeeded stopped settled:
    it leaves its last step in ``dq``, below REDUCED_SETTLE (rad) where it stopped for that,
    the last step it took where it ran out of steps."""
    for i in range(6):
        if i != j and not abs(dq[i]) < REDUCED_SETTLE:
            return False
    return True


@njit
def _least_squares_step(J, e, j, A, g, dq):
    """The Gauss-Newton step ``dq`` (6,) in the five joints other than ``j`` for the error ``e``
    with the Jacobian ``J`` (6, 6): the least-squares solution of ``J_o dq_o = e``, by the
    normal equations, which are symmetric and positive definite, so by Cholesky (half the work
    of an elimination with pivoting, the reduced residual's largest cost); ``dq[j]`` = 0.
    Returns the least pivot of the factorisation relative to the largest diagonal entry (0
    where it is not positive definite: a singular Jacobian). ``A`` (6, 6) and ``g`` (6,) are
    work arrays."""
    big = 0.0
    for a_ in range(5):
        ca = a_ if a_ < j else a_ + 1
        s = 0.0
        for r in range(6):
            s += J[r, ca] * e[r]
        g[a_] = s
        for b_ in range(a_ + 1):
            cb = b_ if b_ < j else b_ + 1
            s = 0.0
            for r in range(6):
                s += J[r, ca] * J[r, cb]
            A[a_, b_] = s
        big = max(big, A[a_, a_])
    if not big > 0.0:
        return 0.0
    small = big
    for k in range(5):  # (A = L L^T, L in the lower triangle)
        d = A[k, k]
        for m in range(k):
            d -= A[k, m] * A[k, m]
        if not d > 0.0:
            return 0.0
        small = min(small, d)
        lk = math.sqrt(d)
        A[k, k] = lk
        for i in range(k + 1, 5):
            s = A[i, k]
            for m in range(k):
                s -= A[i, m] * A[k, m]
            A[i, k] = s / lk
    for i in range(5):  # L y = g
        s = g[i]
        for m in range(i):
            s -= A[i, m] * g[m]
        g[i] = s / A[i, i]
    for i in range(4, -1, -1):  # L^T x = y
        s = g[i]
        for m in range(i + 1, 5):
            s -= A[m, i] * g[m]
        g[i] = s / A[i, i]
    dq[j] = 0.0
    for a_ in range(5):
        dq[a_ if a_ < j else a_ + 1] = g[a_]
    return small / big


@njit
def _parabola_bottom(r0, r1, r2):
    """The parabola through three equally spaced values ``r0``, ``r1``, ``r2`` (at -1, 0, 1):
    (where it turns, its value there, whether it turns back away from zero: its curvature has
    the sign of ``r1``)."""
    c = 0.5 * (r0 + r2) - r1
    b = 0.5 * (r2 - r0)
    if c == 0.0 or (c > 0.0) != (r1 > 0.0):
        return 0.0, r1, False
    t = -b / (2.0 * c)
    return t, r1 + b * t + c * t * t, True


@njit
def dips_to_zero(r0, r1, r2):
    """Whether the parabola through three equally spaced values of one sign (``r1`` the least in
    magnitude) comes down to half of ``r1`` or beyond zero between them, or ``r1`` is below
    DIP_SHARP of both neighbours: a dip that may hide a tangency or two roots, not a shallow
    minimum. (The parabola underestimates a dip whose cell holds two close roots off its middle:
    one of the IRB 5400 at the shoulder set came down to 1.8e-8 between samples 9e-7, 2.5e-8 and
    6e-7, while the residual's two roots 0.01 rad apart lie 0.01 rad from the least sample.)"""
    if abs(r1) < DIP_SHARP * min(abs(r0), abs(r2)):
        return True
    t, bottom, turns = _parabola_bottom(r0, r1, r2)
    if not turns or abs(t) > 1.0:
        return False
    return (bottom < 0.5 * r1) if r1 > 0.0 else (bottom > 0.5 * r1)  # (or beyond zero)


@njit
def first_cell_dips(r0, r1, r2):
    """Whether a scan's first cell, between its first two values ``r0`` and ``r1`` (of one sign;
    ``r2`` the third), holds a dip: the parabola through the three turns inside that cell and
    comes down to half of the lesser of ``r0`` and ``r1`` or beyond zero. A first cell has no
    point before it, so the three-point test of the other cells (:func:`dips_to_zero`) cannot
    be made there; where the scan starts at a dip of its own (the shoulder set's exact scans, from
    the nominal gap's bottom), two roots may lie in that cell (seed 46's rounded member: the
    residual 3.8e-11, 1.1e-10, 4.4e-9 at the first three points, roots 3e-3 and 0.046 rad from
    the start in its cell of 0.05)."""
    t, bottom, turns = _parabola_bottom(r0, r1, r2)
    if not turns or not -1.0 < t < 0.0:
        return False
    half = 0.5 * min(abs(r0), abs(r1))
    return (bottom < half) if r1 > 0.0 else (bottom > -half)  # (or beyond zero)


@njit
def _reduced_root(qt, j, va, vb, ra, rb, Td, K, T, J, A, e, g, dq, ZO, settle=True):
    """Refine the root of the reduced residual bracketed by [va, vb] (``ra``, ``rb`` of opposite
    signs) by Illinois (:func:`ik7r._kernels.poly.illinois_step`), each point Gauss-Newton from
    the one before (``qt``, left at the root), until the residual the last step would leave is
    below REDUCED_ROOT_TOL: closer in ``v`` is worth nothing, since ``qt`` stays up to
    REDUCED_SETTLE from the point that step reaches (bisecting the bracket down to 1e-11 took
    twice the reduced residuals near the shoulder set, about a sixth of a pose's). Not with
    ``settle`` False: then only the bracket (1e-11) or an exact zero stops it, for a residual
    that stays below REDUCED_ROOT_TOL over much of the bracket (the split of a straight wrist;
    a bracket beside a root, see :func:`_inside_ends`), where the first such point can be
    another root's, or 0.01 rad from the bracket's."""
    side = 0
    for _ in range(40):
        v = secant_point(va, vb, ra, rb)
        r, res, ok = _reduced_at(qt, j, v, Td, K, T, J, A, e, g, dq, ZO)
        if not ok or r == 0.0 or (settle and res <= REDUCED_ROOT_TOL):
            return
        va, vb, ra, rb, side, _ = illinois_step(va, vb, ra, rb, side, v, r)
        if abs(vb - va) <= 1e-11:
            return  # (the polish of accept takes it to the last bits)


@njit
def _inside_ends(qa, qb, qt, xb, j, va, vb, ra, rb, root_a, root_b, Td, K, T, J, A, e, g, dq, ZO):
    """The bracket of a cell with a sign change whose end ``va`` (``root_a``) or ``vb``
    (``root_b``) is itself a root: that end moved ROOT_END_STEP of the cell inside, its residual
    there by Gauss-Newton from the end's point (``qa`` at ``va``, ``qb`` at ``vb``; ``qt`` and
    ``xb`` (6,) work arrays). Returns (whether the moved bracket still changes sign, va, vb, ra,
    rb), with ``qt`` left at the point of its new ``va``: a sign change that is only the end
    root's own is gone, one that holds another root inside the cell stays (see ROOT_END_STEP)."""
    step = ROOT_END_STEP * (vb - va)
    for i in range(6):
        qt[i] = qa[i]
    if root_b:
        for i in range(6):
            xb[i] = qb[i]
        r, _, ok = _reduced_at(xb, j, vb - step, Td, K, T, J, A, e, g, dq, ZO)
        if not ok:
            return False, va, vb, ra, rb
        vb = vb - step
        rb = r
    if root_a:
        r, _, ok = _reduced_at(qt, j, va + step, Td, K, T, J, A, e, g, dq, ZO)
        if not ok:
            return False, va, vb, ra, rb
        va = va + step
        ra = r
    return ra * rb < 0.0, va, vb, ra, rb


@njit
def _cell_kind(rs, es, k, kb, closed):
    """What the reduced scan refines in its cell ``k`` (grid values ``rs`` signed, ``es`` the
    error's norm; ``kb`` the point before ``k``, on a closed curve m - 1 for k = 0): 1 a sign
    change, 2 a dip of ``|e|`` toward zero without one (below DIP_NEAR, or by
    :func:`dips_to_zero`; in the first cell of a curve that is not closed, by
    :func:`first_cell_dips`), 3 a stall beside a sign change (:func:`_stall`: searched with the
    cell beyond it, see :func:`_stall_bracket`), 0 nothing."""
    ra = rs[k]
    rb = rs[k + 1]
    if not (math.isfinite(ra) and math.isfinite(rb)):
        return 0
    if ra * rb < 0.0:
        return 1
    if ((0 < k or closed) and es[k] <= es[kb] and es[k] <= es[k + 1]
            and math.isfinite(rs[kb]) and rs[kb] * ra > 0.0
            and (es[k] < DIP_NEAR or dips_to_zero(rs[kb], ra, rb))):
        return 2
    if k == 0 and not closed and len(rs) > 2 and math.isfinite(rs[2]) and first_cell_dips(ra, rb, rs[2]):
        return 2  # (a dip inside the first cell: see reduced_scan for its bracket)
    if _stall(rs, k) != 0:
        return 3
    return 0


@njit
def _stall(rs, k):
    """Whether ``|r|`` stalls over cell ``k`` (ends of one sign) beside a sign change: +1 when the
    cell before holds one and ``|r|`` at the cell's far end is below REDUCED_STALL of what the
    change's secant slope makes it there (the residual turns back toward zero, and may cross it
    twice in this cell or the next, unseen by the grid), -1 the same toward a change in the cell
    after; else 0."""
    m = len(rs) - 1
    ra = abs(rs[k])
    rb = abs(rs[k + 1])
    if k >= 1 and math.isfinite(rs[k - 1]) and rs[k - 1] * rs[k] < 0.0:
        if rb < REDUCED_STALL * (abs(rs[k - 1]) + 2.0 * ra):
            return 1
    if k + 2 <= m and math.isfinite(rs[k + 2]) and rs[k + 1] * rs[k + 2] < 0.0:
        if ra < REDUCED_STALL * (abs(rs[k + 2]) + 2.0 * rb):
            return -1
    return 0


@njit
def _stall_bracket(rs, k):
    """The grid points (lo, hi) bracketing the search of a stalled cell ``k`` (:func:`_stall`):
    the cell and the one beyond it, away from the sign change."""
    m = len(rs) - 1
    if _stall(rs, k) > 0:
        return k, min(k + 2, m)
    return max(k - 1, 0), k + 1


@njit
def _scan_seen(memo, n, j, v0, v1, m, qs, kind, k, kb):
    """Whether an earlier reduced scan of this pose (``memo``, ``n`` of them: see SCAN_MEMO)
    over the same grid (joint ``j``, [v0, v1], ``m`` cells) refined its cell ``k`` the same
    way (``kind``, see :func:`_cell_kind`) from the same points: ``k`` and ``k + 1`` (and
    ``kb`` for a dip) within SCAN_MEMO_TOL of ``qs``'. Its candidates are then this cell's."""
    for s in range(min(n, SCAN_MEMO)):
        slot = memo[s * SCAN_SLOT:(s + 1) * SCAN_SLOT]
        if slot[0] != j or slot[1] != v0 or slot[2] != v1 or slot[3] != m:
            continue
        pts = slot[SCAN_HEAD:SCAN_HEAD + 8 * (m + 1)].reshape((m + 1, 8))
        if _cell_kind(pts[:, 6], pts[:, 7], k, kb, slot[4] != 0.0) != kind:
            continue
        same = apart(pts[k], qs[k]) <= SCAN_MEMO_TOL and apart(pts[k + 1], qs[k + 1]) <= SCAN_MEMO_TOL
        if same and (kind == 1 or apart(pts[kb], qs[kb]) <= SCAN_MEMO_TOL):
            return True
    return False


@njit
def _scan_joined(memo, n, j, v0, v1, m, qs, k):
    """The earlier reduced scan of this pose (``memo``, ``n`` of them: see SCAN_MEMO) over the
    same grid whose points ``k - 2`` and ``k - 1`` are within SCAN_MEMO_TOL of ``qs``', or -1."""
    for s in range(min(n, SCAN_MEMO)):
        slot = memo[s * SCAN_SLOT:(s + 1) * SCAN_SLOT]
        if slot[0] != j or slot[1] != v0 or slot[2] != v1 or slot[3] != m:
            continue
        pts = slot[SCAN_HEAD:SCAN_HEAD + 8 * (m + 1)].reshape((m + 1, 8))
        if apart(pts[k - 2], qs[k - 2]) <= SCAN_MEMO_TOL and apart(pts[k - 1], qs[k - 1]) <= SCAN_MEMO_TOL:
            return s
    return -1


@njit
def _scan_keep(memo, n, j, v0, v1, m, qs, rs, es, closed):
    """Record a reduced scan's grid in the ring ``memo`` as its ``n``-th (see SCAN_MEMO)."""
    slot = memo[(n % SCAN_MEMO) * SCAN_SLOT:(n % SCAN_MEMO + 1) * SCAN_SLOT]
    slot[0] = j
    slot[1] = v0
    slot[2] = v1
    slot[3] = m
    slot[4] = 1.0 if closed else 0.0
    pts = slot[SCAN_HEAD:SCAN_HEAD + 8 * (m + 1)].reshape((m + 1, 8))
    for k in range(m + 1):
        for i in range(6):
            pts[k, i] = qs[k, i]
        pts[k, 6] = rs[k]
        pts[k, 7] = es[k]


@njit(allocates=True)
def reduced_scan(start, j, v0, v1, m, Td, K, out, count, ws, mats, one_sign=False, stop_joined=False):
    """Every exact solution on the branch of the reduced residual (:func:`_reduced_at`) with
    joint ``j`` over [v0, v1], tracked from ``start`` on a grid of ``m`` <= REDUCED_GRID cells
    (each point Gauss-Newton from the extrapolation of the two before it): sign changes refined
    by Illinois in ``v``, dips toward zero (tangencies, two roots in one cell) by Brent's
    minimiser on the signed residual and split at its bottom; each candidate is verified
    (polished) on the exact forward kinematics and added. A cell an earlier scan of the pose
    refined from the same points is not refined again (:func:`_scan_seen`). On return
    ``start`` holds the grid point whose wrist is the least bent (see
    :func:`straight_family`), and ``ws[W_SEND:W_SEND + 9]`` the last grid point, its ``|e|``
    (inf where Gauss-Newton failed there) and the residual at the last two points (nan there).
    ``one_sign`` (q1 only; see TURN_START_ROUNDS): the start is first taken to its
    least-squares point, the scan keeps its wrist's sign by going on along the other wrist's
    branch where the wrist passes straight, a point that jumps off the branch is solved again
    with its wrist solved for the arm's target (:func:`_wrist_again`), and the scan is not
    joined to an earlier one. A split scan (j = 3) notes its points that jumped off a root's
    valley in ``ws[W_JUMP]`` (:func:`_note_jumps`), a scan over the whole turn in q1 its runs of
    such points and the cells where it leaves the fully bent wrist (:func:`_note_bent_exits`);
    :func:`rescan_jumps` scans them again. ``stop_joined`` (a whole turn in q1): the scan stops
    where two of its points in a row lie within TURN_JOIN_TOL of a whole turn of the pose
    scanned before (:func:`_turn_joins`): the rest of its curve is that turn's."""
    T = np.empty((4, 4))
    J = np.empty((6, 6))
    A = np.empty((6, 6))
    ZO = np.empty((7, 6))
    e = np.empty(6)
    g = np.empty(6)
    dq = np.empty(6)
    qs = np.empty((m + 1, 6))
    rs = np.empty(m + 1)
    es = np.empty(m + 1)
    qt = np.empty(6)
    qp = np.empty(6)  # (a point's prediction, for _wrist_again; its other wrist)
    th6 = np.empty(6)  # (scratch: the other wrist at a dip, see other_wrist; a moved cell end)
    M3 = np.empty((4, 4))
    Q3 = np.empty((3, 3))
    W3 = np.empty((3, 3))
    memo = ws[W_RSCAN:W_RSCAN + SCAN_MEMO * SCAN_SLOT]
    n = int(ws[W_NRSCAN]) if m == REDUCED_GRID else 0
    joined = -1
    keep_sign = one_sign and j == 0  # (see :func:`ik7r._kernels.scans._q1_scans`)
    sign = 0.0
    mirrored = -1
    turn = j == 0 and abs(abs(v1 - v0) - TWO_PI) < 1e-12
    last = m
    for k in range(m + 1):
        if joined < 0 and k >= 2 and not keep_sign:
            joined = _scan_joined(memo, n, j, v0, v1, m, qs, k)
        if joined >= 0:
            # (the earlier scan's point k: Gauss-Newton from the same start; added if exact then)
            pts = memo[joined * SCAN_SLOT + SCAN_HEAD:(joined + 1) * SCAN_SLOT]
            for i in range(6):
                qs[k, i] = pts[8 * k + i]
            rs[k] = pts[8 * k + 6]
            es[k] = pts[8 * k + 7]
            continue
        for i in range(6):
            if k == 0:
                qt[i] = start[i]
            elif k == 1 or mirrored == k - 1:
                qt[i] = qs[k - 1, i]
            else:
                qt[i] = 2.0 * qs[k - 1, i] - qs[k - 2, i]
            qp[i] = qt[i]
        r, res, ok = _reduced_at(qt, j, v0 + (v1 - v0) * k / m, Td, K, T, J, A, e, g, dq, ZO)
        if (keep_sign and ok and k > 0 and res > max(TRACK_JUMP * es[k - 1], DIP_NEAR)
                and not _settled(dq, j)):
            # a jump off the branch: its wrist solved again for the arm's target at the prediction
            r, res, ok = _wrist_again(qt, qp, j, v0 + (v1 - v0) * k / m, r, res, Td, K, T, J, A,
                                      e, g, dq, ZO, mats[MAT_R07, :3, :3], th6, M3, Q3, W3)
        if keep_sign and ok:
            t5 = theta5(qt, K)
            if k == 0:
                for _ in range(TURN_START_ROUNDS):  # (the start to its least-squares point)
                    if not ok or _settled(dq, j):
                        break
                    r, res, ok = _reduced_at(qt, j, v0, Td, K, T, J, A, e, g, dq, ZO)
                sign = 1.0 if theta5(qt, K) >= 0.0 else -1.0
            elif sign * t5 < 0.0 and abs(t5) < 0.5 * math.pi:
                # the wrist passed straight, where this branch meets the other wrist's: go on
                # along the other, which keeps this scan's wrist sign (fully bent, Gauss-Newton
                # cannot move theta5 off pi: the scan goes on through it)
                other_wrist(qt, mats[MAT_R07, :3, :3], K, th6, M3, Q3, W3, qp)
                for i in range(6):
                    qt[i] = qp[i]
                r, res, ok = _reduced_at(qt, j, v0 + (v1 - v0) * k / m, Td, K, T, J, A, e, g, dq, ZO)
                mirrored = k
        for i in range(6):
            qs[k, i] = qt[i]
        rs[k] = r if ok else np.nan
        es[k] = res if ok else np.inf
        if ok:
            dp, dr = residual(T, Td)
            if dp <= K[L.POS_TOL] and dr <= K[L.ROT_TOL]:
                count = add_answer(qt.copy(), out, count, Td, K, mats)
        if stop_joined and k >= 1 and _turn_joins(memo, n, v0 + (v1 - v0) * k / m, (v1 - v0) / m,
                                                  qs[k - 1], qs[k]):
            last = k
            break
    # over a whole turn the branch is a closed curve when it comes back to its start: the grid
    # point before the first is then the last but one (a dip at the start is a dip)
    closed = last == m and abs(v1 - v0 - TWO_PI) < 1e-12 and apart(qs[0], qs[m]) < CLOSED_TOL
    rl = rs[:last + 1]  # (the points computed: all but where the scan joined a turn)
    el = es[:last + 1]
    for k in range(last):
        va = v0 + (v1 - v0) * k / m
        vb = v0 + (v1 - v0) * (k + 1) / m
        ra = rs[k]
        rb = rs[k + 1]
        kb = k - 1 if k > 0 else m - 1  # (the point before; k = 0 only on a closed curve)
        kind = _cell_kind(rl, el, k, kb, closed)
        if kind == 3 and j != 3:
            continue  # (a stall is searched on the straight wrist's split alone: see REDUCED_STALL)
        if kind == 0 or _scan_seen(memo, n, j, v0, v1, m, qs, kind, k, kb):
            continue
        if kind == 1:
            # (the split of a straight wrist, j = 3, to the bracket: its residual can stay below
            # REDUCED_ROOT_TOL over much of a cell, and the first point there be 0.01 rad from
            # the root, too far for the polish in a valley that flat)
            settle = j != 3
            for i in range(6):
                qt[i] = qs[k, i]
            _reduced_root(qt, j, va, vb, ra, rb, Td, K, T, J, A, e, g, dq, ZO, settle)
            count, _ = accept(qt.copy(), Td, K, out, count, mats, False, False)
            root_a = es[k] <= REDUCED_ROOT_TOL
            root_b = es[k + 1] <= REDUCED_ROOT_TOL
            if root_a or root_b:
                # an end that is itself a root: refined the other way too (the early stop finds
                # the end's root; to the bracket, a root between the end and ROOT_END_STEP
                # inside it) ...
                for i in range(6):
                    qt[i] = qs[k, i]
                _reduced_root(qt, j, va, vb, ra, rb, Td, K, T, J, A, e, g, dq, ZO, not settle)
                count, _ = accept(qt.copy(), Td, K, out, count, mats, False, False)
                # ... and a second root inside?
                inner, va, vb, ra, rb = _inside_ends(qs[k], qs[k + 1], qt, th6, j, va, vb, ra, rb,
                                                     root_a, root_b, Td, K, T, J, A, e, g, dq, ZO)
                if inner:
                    _reduced_root(qt, j, va, vb, ra, rb, Td, K, T, J, A, e, g, dq, ZO, False)
                    count, _ = accept(qt.copy(), Td, K, out, count, mats, False, False)
        else:
            # a dip of |e| without a sign change: a tangency, or two roots within one cell; where
            # the bottom has the other sign, both roots are refined
            for i in range(6):
                qt[i] = qs[k, i]
            sgn = 1.0 if ra > 0.0 else -1.0
            # the bottom of the signed residual (|e| would stop at a root), by Brent's minimiser,
            # from the point before (the first cell's dip, which has none, inside the cell; a
            # stall, over the cell and the one beyond it)
            lo, r_lo = (k, ra) if k == 0 and not closed else (k - 1, rs[kb])
            if kind == 3:
                lo, hi = _stall_bracket(rl, k)
                r_lo = rs[lo]
                for i in range(6):
                    qt[i] = qs[lo, i]
                vb = v0 + (v1 - v0) * hi / m
                rb = rs[hi]
            v_lo = v0 + (v1 - v0) * lo / m
            st, x = brent_start(v_lo, vb)
            for _ in range(200):
                f, _, okf = _reduced_at(qt, j, x, Td, K, T, J, A, e, g, dq, ZO)
                st = brent_take(st, x, sgn * f if okf else np.inf)
                st, x, done = brent_next(st)
                if done:
                    break
            vm = st[2]
            rm, _, okm = _reduced_at(qt, j, vm, Td, K, T, J, A, e, g, dq, ZO)
            qm = qt.copy()
            count, _ = accept(qt.copy(), Td, K, out, count, mats, False, False)
            if okm and rm * ra < 0.0:
                # each root refined to its bracket: the residual may stay below REDUCED_ROOT_TOL
                # across the bottom, where both would stop at one point; not at the fully bent
                # wrist, whose two wrist solutions that close are one
                settle = math.pi - bend(qm, K) < FOLD_WINDOW
                for vx, rx in ((v_lo, r_lo), (vb, rb)):
                    if not rx * rm < 0.0:
                        continue  # (a stall's far end may be past a root already: no bracket)
                    for i in range(6):
                        qt[i] = qm[i]
                    _reduced_root(qt, j, min(vx, vm), max(vx, vm), rx if vx < vm else rm,
                                  rm if vx < vm else rx, Td, K, T, J, A, e, g, dq, ZO, settle)
                    count, _ = accept(qt.copy(), Td, K, out, count, mats, False, False)
            elif bend(qm, K) > STRAIGHT_DEVIATING:
                # a bottom that is no root: the other wrist of its arm may be a solution on a
                # sheet this curve never reaches (it can cross the fully bent wrist, q5 = pi,
                # onto the sheet it started beside)
                other_wrist(qm, mats[MAT_R07, :3, :3], K, th6, M3, Q3, W3, qt)
                count, _ = accept(qt.copy(), Td, K, out, count, mats, False, False)
    if m == REDUCED_GRID and joined < 0 and last == m:
        _scan_keep(memo, n, j, v0, v1, m, qs, rs, es, closed)
        ws[W_NRSCAN] = n + 1
    ws[W_JUMP] = 0.0
    if j == 3:
        _note_jumps(qs, es, v0, v1, m, ws, 1, DIP_NEAR)
    elif turn:
        v_last = v0 + (v1 - v0) * last / m
        _note_jumps(qs[:last + 1], el, v0, v_last, last, ws, TURN_JUMP_WIDTH, TURN_JUMP_VALLEY)
        _note_bent_exits(qs[:last + 1], v0, v_last, last, K, ws)
    for i in range(6):
        ws[W_SEND + i] = qs[last, i]
    ws[W_SEND + 6] = es[last]
    ws[W_SEND + 7] = rs[last - 1]
    ws[W_SEND + 8] = rs[last]
    least = math.inf
    for k in range(last + 1):
        t5 = bend(qs[k], K)
        if math.isfinite(rs[k]) and t5 < least:
            least = t5
            for i in range(6):
                start[i] = qs[k, i]
    return count


@njit(allocates=True)
def settle_start(q, v, Td, K):
    """Take ``q`` (user angles; its q1 ``v``) to its least-squares point with q1 held, in place:
    at most TURN_START_ROUNDS rounds of Gauss-Newton (:func:`_reduced_at`). Returns False where
    Gauss-Newton failed."""
    T = np.empty((4, 4))
    J = np.empty((6, 6))
    A = np.empty((6, 6))
    ZO = np.empty((7, 6))
    e = np.empty(6)
    g = np.empty(6)
    dq = np.empty(6)
    for _ in range(TURN_START_ROUNDS):
        _, _, ok = _reduced_at(q, 0, v, Td, K, T, J, A, e, g, dq, ZO)
        if not ok:
            return False
        if _settled(dq, 0):
            break
    return True


@njit
def turn_tracked(q, v, Td, K, ws):
    """Whether a whole turn in q1 this pose has scanned (the memo of :func:`reduced_scan`, see
    SCAN_MEMO) passes through the branch of ``q`` (user angles; its q1 ``v``, a grid point of
    that turn): ``q``, taken to its least-squares point in place (:func:`settle_start`), within
    TURN_TRACKED of the turn's grid point at ``v``."""
    if not settle_start(q, v, Td, K):
        return False
    memo = ws[W_RSCAN:W_RSCAN + SCAN_MEMO * SCAN_SLOT]
    for s in range(min(int(ws[W_NRSCAN]), SCAN_MEMO)):
        if _on_turn(memo[s * SCAN_SLOT:(s + 1) * SCAN_SLOT], v, q, TURN_TRACKED):
            return True
    return False


@njit
def _turn_joins(memo, n, v, h, qa, qb):
    """Whether ``qa`` and ``qb`` (user angles; their q1 ``v - h`` and ``v``) lie within
    TURN_JOIN_TOL of two points in a row of a whole turn in q1 in the memo (``n`` scans, see
    SCAN_MEMO): the scan with them has joined that turn's curve. (The points a scan joins by
    come within 1e-9 of the turn's after two or three cells; curves that only pass each other
    stay 1e-3 and more apart.)"""
    for s in range(min(n, SCAN_MEMO)):
        slot = memo[s * SCAN_SLOT:(s + 1) * SCAN_SLOT]
        if _on_turn(slot, v - h, qa, TURN_JOIN_TOL) and _on_turn(slot, v, qb, TURN_JOIN_TOL):
            return True
    return False


@njit
def _on_turn(slot, v, q, tol):
    """Whether ``q`` (user angles; its q1 ``v``) lies within ``tol`` (rad, every joint) of the
    point at ``v`` of the whole turn in q1 kept in the memo ``slot`` (False where the slot is
    no such turn or ``v`` no point of its grid)."""
    if slot[0] != 0.0 or slot[3] != REDUCED_GRID or abs(abs(slot[2] - slot[1]) - TWO_PI) > 1e-12:
        return False
    h = (slot[2] - slot[1]) / REDUCED_GRID
    k = int(round(wrap(v - slot[1]) / h))
    if k < 0:
        k += REDUCED_GRID
    if abs(wrap(v - slot[1] - k * h)) > 1e-9:
        return False
    b = SCAN_HEAD + 8 * k
    if apart(slot[b:b + 6], q) < tol:
        return True
    if k == 0:  # (the turn's first point is at its last one's q1 too: the curve need not close)
        b = SCAN_HEAD + 8 * REDUCED_GRID
        return apart(slot[b:b + 6], q) < tol
    return False


@njit
def _note_jumps(qs, es, v0, v1, m, ws, width, valley):
    """Note in ``ws[W_JUMP]`` (count, then per run the ends of its bracket and the point before
    it) the runs of up to ``width`` points of a scan (grid ``qs`` over [v0, v1] on ``m`` cells,
    ``|e|`` ``es``) that jumped off a root's valley: ``|e|`` above TRACK_JUMP times the points
    either side of the run while these are below ``valley`` (see JUMP_CELLS and TURN_JUMP_WIDTH),
    at most JUMP_NOTED."""
    nj = int(ws[W_JUMP])
    k = 1
    while k < m and nj < JUMP_NOTED:
        run = 0
        for w in range(1, width + 1):
            if k + w > m:
                break
            side = max(es[k - 1], es[k + w])
            low = es[k]
            for i in range(k + 1, k + w):
                low = min(low, es[i])
            if side < valley and low > TRACK_JUMP * side:
                run = w
                break
        if run == 0:
            k += 1
            continue
        _note(ws, nj, v0 + (v1 - v0) * (k - 1) / m, v0 + (v1 - v0) * (k + run) / m, qs[k - 1])
        nj += 1
        k += run + 1
    ws[W_JUMP] = nj


@njit
def _note_bent_exits(qs, v0, v1, m, K, ws):
    """Note in ``ws[W_JUMP]`` (after :func:`_note_jumps`' runs, at most JUMP_NOTED in all) the
    cells where a scan over the whole turn in q1 (grid ``qs`` over [v0, v1] on ``m`` cells) leaves
    the fully bent wrist: theta5 within BENT_STUCK of pi at one end of the cell and not at the
    other. Gauss-Newton cannot move theta5 off pi (the fully bent wrist is the same wrist to first
    order on either side), so the scan leaves it on one side of pi, and the branch on the other
    side is not tracked: noted from the point off pi with theta5 mirrored about pi, back to the
    one at pi (see BENT_STUCK)."""
    nj = int(ws[W_JUMP])
    for k in range(1, m + 1):
        if nj >= JUMP_NOTED:
            break
        at_a = math.pi - bend(qs[k - 1], K) < BENT_STUCK
        at_b = math.pi - bend(qs[k], K) < BENT_STUCK
        if at_a == at_b:
            continue
        off, at = (k, k - 1) if at_a else (k - 1, k)
        b = _note(ws, nj, v0 + (v1 - v0) * off / m, v0 + (v1 - v0) * at / m, qs[off])
        ws[b + 2 + 4] = user_angle(4, TWO_PI - dh_angle(qs[off], K, 4), K)  # (the start's q5)
        nj += 1
    ws[W_JUMP] = nj


@njit
def _note(ws, nj, va, vb, q):
    """Write the ``nj``-th note of ``ws[W_JUMP]``: a bracket [va, vb] and its start ``q`` (six
    joints); returns where the note begins (the start's joints follow its two ends)."""
    b = W_JUMP + 1 + 8 * nj
    ws[b] = va
    ws[b + 1] = vb
    for i in range(6):
        ws[b + 2 + i] = q[i]
    return b


@njit
def other_wrists(R07, Td, K, out, count, ws, mats):
    """The other wrist of each solution of a deviating model that has none: on the idealised
    model every arm comes with both wrists (theta5 of either sign, theta4 and theta7 from the
    arm's wrist target), and the deviation moves the two apart by about its own size. Where the
    idealised model has no solution near (both come from one near miss, beside the elbow stretch
    or the fully bent wrist), the polish of the near miss's candidates can reach one wrist and
    not the other: a solution with no other one within OTHER_WRIST_ARM (rad, joints 1 to 3) whose
    theta5 has the other sign starts a polish from its arm with the other wrist. With the wrist
    within STRAIGHT_DEVIATING of straight the window is DUP_TOL: there the two wrists of an arm
    share it (to 1e-10 rad on a rounded member at theta5 = 9e-3, beside the elbow's stretch), while
    a second arm 1.5e-3 rad away, with a wrist of the other sign, had passed for the partner. Not
    within STRAIGHTEN_REACH of straight, whose neighbours the straight-wrist scan finds
    (:func:`straight_family`)."""
    th = ws[W_TH:W_TH + NTH]
    qq = ws[W_QQ:W_QQ + 6]
    n0 = count
    for s in range(n0):
        t5 = theta5(out[s], K)
        if abs(t5) < STRAIGHTEN_REACH:
            continue
        # (nearly straight, the two wrists of an arm share it: a window of DUP_TOL)
        window = OTHER_WRIST_ARM if abs(t5) >= STRAIGHT_DEVIATING else DUP_TOL
        paired = False
        for e in range(count):
            if e == s or theta5(out[e], K) * t5 >= 0.0:
                continue
            near = True
            for i in range(3):
                near = near and abs(wrap(out[e, i] - out[s, i])) < window
            if near:
                paired = True
                break
        if paired:
            continue
        other_wrist(out[s], R07, K, th, mats[MAT_M], mats[MAT_Q, :3, :3], mats[MAT_WR, :3, :3], qq)
        count, _ = accept(qq, Td, K, out, count, mats, False, False)
    return count


@njit
def _condition_frobenius(J, A, B):
    """``|J|_F |J^-1|_F`` of ``J`` (6, 6; inf when singular): at least ``sigma_max / sigma_min``
    and at most 6 times it, so that a solution whose value is below ``1 / PARTNER_SIGMA`` is
    regular beyond doubt, for the cost of a few Jacobians instead of a singular value
    decomposition. ``J^-1`` by one elimination with partial pivoting of ``J`` (into ``A``) beside
    the identity (into ``B``; both 6 x 6 work arrays), then a back substitution per column: the
    operations of :func:`ik7r._kernels.fk.solve6` on each column of the identity, done once for
    all six (the same numbers, bit for bit)."""
    for r in range(6):
        for c in range(6):
            A[r, c] = J[r, c]
            B[r, c] = 1.0 if r == c else 0.0
    for k in range(6):
        p = _pivot(A, k)
        if A[p, k] == 0.0:
            return math.inf
        if p != k:
            for c in range(6):
                A[k, c], A[p, c] = A[p, c], A[k, c]
                B[k, c], B[p, c] = B[p, c], B[k, c]
        for i in range(k + 1, 6):
            f = A[i, k] / A[k, k]
            for c in range(k, 6):
                A[i, c] -= f * A[k, c]
            for c in range(6):
                B[i, c] -= f * B[k, c]
    inv = 0.0
    for k in range(6):
        for i in range(5, -1, -1):  # (column k of J^-1, into column k of B)
            s = B[i, k]
            for c in range(i + 1, 6):
                s -= A[i, c] * B[c, k]
            B[i, k] = s / A[i, i]
        for r in range(6):
            inv += B[r, k] * B[r, k]
    nj = 0.0
    for r in range(6):
        for c in range(6):
            nj += J[r, c] * J[r, c]
    return math.sqrt(nj * inv)


@njit(allocates=True)
def partners(Td, K, out, count, ws, mats):
    """Solutions of a deviating model next to a nearly singular one. Where the exact model has
    two solutions close together whose idealised counterparts are complex (or merged), the
    polish of every idealised candidate can land on one of them. At a solution ``x`` with the
    Jacobian's smallest singular value ``sigma`` (left and right vectors ``u``, ``v``) the pose
    error along ``x + t v`` is ``sigma t + c t^2 / 2`` on ``u`` (``c`` by central differences):
    its second zero ``t = -2 sigma / c`` is the partner's prediction, polished on the exact model
    (a check, not a certificate: see docs/guide/edges.md). Where that step finds nothing new,
    the reduced residual (:func:`reduced_scan`) in the joint ``v`` moves most is scanned
    PARTNER_CELLS cells each way: the partner lies on the curve of nearly solutions through
    ``x``, which may bend away from the line (the error off ``u`` then grows along it). A
    partner found is itself searched for a partner (a cluster of three: a solution found only
    as a partner had its own missed). Not in q1 where :func:`_shoulder_turn` has tracked the
    exact model over its whole turn (:func:`turn_scanned`): the same solution sets over 24,000
    poses of four deviating robots without those scans, a third of the partners' reduced
    residuals on a near-shoulder pose. On a model that deviates further than the published ones
    the reach and the cells widen with it (:func:`deviation_widening`, as the shoulder windows
    do): a member deviating 4.7 times as far (wrist offsets of 0.44 mm) had a partner 0.45 to 0.6
    along ``v`` beside a stretched elbow, and it was missed."""
    T = np.empty((4, 4))
    J = np.empty((6, 6))
    A = np.empty((6, 6))
    ZO = np.empty((7, 6))
    ep = np.empty(6)
    qt = np.empty(6)
    w = 1.0 / K[L.SCALE]
    turned = turn_scanned(ws[W_P:W_P + 3], ws[W_A:W_A + 3], K)  # (once per pose, not per partner)
    widening = deviation_widening(K)
    cells = int(math.ceil(PARTNER_CELLS * widening))
    s = -1
    while s + 1 < count:  # (each new row a distinct solution: bounded by the output's size)
        s += 1
        if bend(out[s], K) < STRAIGHT_DEVIATING:
            continue  # a straight wrist's neighbours: the whole turn is scanned (straight_family)
        x = out[s].copy()
        fk_jacobian(x, K, T, J, ZO)
        for r in range(3):
            for c in range(6):
                J[r, c] *= w
        if PARTNER_SIGMA * _condition_frobenius(J, A, ZO[:6]) <= 1.0:
            continue  # clearly regular: sigma_min / sigma_max >= 1 / the Frobenius condition
        U, S, Vt = np.linalg.svd(J)
        if not S[5] < PARTNER_SIGMA * S[0]:
            continue
        h = 1e-3
        curv = 0.0
        for sg in (1.0, -1.0):
            for i in range(6):
                qt[i] = x[i] + sg * h * Vt[5, i]
            fk_user(qt, K, T)
            pose_error(T, Td, ep, ZO[:3, :3])
            for r in range(3):
                ep[r] *= w
            for r in range(6):
                curv -= U[r, 5] * ep[r]  # F = -pose_error
        curv /= h * h
        if curv == 0.0:
            continue
        t = -2.0 * S[5] / curv
        before = count
        if abs(t) <= PARTNER_REACH * widening:
            for i in range(6):
                qt[i] = x[i] + t * Vt[5, i]
            count, _ = accept(qt.copy(), Td, K, out, count, mats, False, False)
        if count == before:
            # no partner on the line: the curve of nearly solutions through x bends away from
            # x + t v (the error off u grows along the line), so follow it with the reduced
            # residual in the joint v moves most, PARTNER_CELLS cells each way
            j = 0
            for i in range(6):
                if abs(Vt[5, i]) > abs(Vt[5, j]):
                    j = i
            if j == 0 and turned:
                continue
            reach = PARTNER_REACH * widening * abs(Vt[5, j])
            for sg in (1.0, -1.0):
                # (from PARTNER_STEP of a cell beside x, not from x: the residual is zero at x, so
                # the first cell's sign test would read rounding, and a partner in it was lost)
                count = reduced_scan(x.copy(), j, x[j] + sg * PARTNER_STEP * reach / cells,
                                      x[j] + sg * reach, cells, Td, K, out, count, ws, mats)
    return count
