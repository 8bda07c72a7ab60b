"""The answers of one pose: what is exact, what is one solution, and how a candidate is accepted.

``accept`` verifies a candidate on the exact forward kinematics (polishing it: Newton on an
idealised family member, a homotopy from the idealised model on one that deviates) and
``add_answer`` appends it unless it is an answer already: within DUP_TOL, joined by an exact
segment (``_joined``) or walk (``walked``), the same exactly straight wrist (``_same_straight``,
the split of ``straight_split``), or a shadow of the continuum of axis 4 on axis 1 (turned to
the seed's joint 1). ``floor_shoulder`` and ``merge_folded`` are the passes over the whole
output at the end of a pose. See docs/guide/edges.md for the rules and their measurements.
"""

from __future__ import annotations

import math

from . import params as L
from .constants import (
    CIRCLE_WALK,
    CONTINUUM_WINDOW,
    CW_FOUND,
    CW_REF,
    CW_SHOULDER,
    DUP_TOL,
    FLOOR,
    FLOOR_ITERS,
    FOLD_WINDOW,
    HOMOTOPY_SETTLE,
    MAT_CW,
    MAT_MEMO,
    MAT_MEMO_N,
    MAT_T,
    MAT_WALK,
    MAT_WR,
    MEMO_SIZE,
    MEMO_TOL,
    MERGE_WINDOW,
    SHOULDER_NEAR,
    SINGULAR_ALONE,
    SNAP_ROUNDING,
    STALL_PATIENCE,
    START_REACH,
    STRAIGHT_EXACT,
    STRAIGHTEN_ITERS,
    STRAIGHTEN_REACH,
    STRETCH_EXACT,
    TURN_SLACK,
    VALLEY_WALK,
    WALK_MIN,
    WALK_SLACK,
    WALK_STEP,
    wrap,
)
from .fk import ALL_JOINTS, dh_angle, fk_user, newton_undefined, polish, residual, user_angle
from .jit import njit
from .singular import elbow_stretched, straight_circle


@njit
def straight_split(q, Q, K, hint, has_hint):
    """At the straight wrist (theta5 = 0) only theta4 + theta7 is defined: split it nearest to
    the hint, else with theta4 = 0."""
    total = math.atan2(Q[1, 0], Q[0, 0]) - K[L.THETA_OFFSET4] - K[L.THETA_OFFSET7]  # s4 q4 + s7 q7
    _split_sum(q, total, K, hint, has_hint)


@njit
def _split_sum(q, total, K, hint, has_hint):
    """Set q4 and q7 of a straight wrist to ``s4 q4 + s7 q7 = total``: the hint's split, each
    moved by half the difference (the nearest such pair to the hint), else q4 = 0."""
    s4 = K[L.SIGN + 3]
    s7 = K[L.SIGN + 6]
    if has_hint:
        lam = 0.5 * wrap(total - s4 * hint[3] - s7 * hint[5])
        q[3] = hint[3] + s4 * lam
        q[5] = hint[5] + s7 * lam
    else:
        q[3] = 0.0
        q[5] = s7 * total


@njit
def straight_damped(qq, Td, K, hint, has_hint, mats, free=True):
    """Polish the straight snap ``qq`` of an exact member that Newton could not polish by damped
    steps (:func:`ik7r._kernels.fk.polish`), in place; False when it does not reach an exactly
    straight point, else True, with q1 as the arm set it (the seed's; the continuum of axis 7 on axis 1 turns
    the wrist's sum with it) and the split of :func:`_split_sum`. Off the shoulder set as well
    (``free`` False: the held polish alone, given up after STALL_PATIENCE steps without
    progress): the straight wrist's root is a double one wherever the arm is, and an exact 45
    deg member's arm from it lay 2e-6 rad off (the snap 2e-3 mm off the pose; only the nearly
    straight shadows +-1e-6 came back). It lands only where the pose is straight to the
    tolerances: six conditions with the wrist held. (On the shoulder set the arm's root is only
    good to about sqrt(eps), a double root, and the FK is flat: Newton cannot polish the snap, and
    the two bends +-t5 beside it are shadows of the one straight solution. With the elbow
    stretched there as well, the arm's error is a few 1e-7 rad and the damped polish, free in
    q5, takes it up with a bend of the same size, one of those shadows: the snap is then polished
    again with the wrist held straight, q1..q4 alone, where that error is first order.)"""
    q1, q2, q3, q4_snap, q7 = qq[0], qq[1], qq[2], qq[3], qq[5]
    if not free or not polish(qq, Td, K, 8, True) or bend(qq, K) > STRAIGHT_EXACT:
        # (the polish left the straight wrist for a shadow beside it: hold the wrist instead)
        qq[0], qq[1], qq[2], qq[3], qq[5] = q1, q2, q3, q4_snap, q7
        qq[4] = user_angle(4, 0.0, K)
        # (q5 and q7 held; without the free polish first, given up once the error stalls)
        if not polish(qq, Td, K, 8, True, 0 if free else STALL_PATIENCE, 0.0, 0b001111):
            return False
    qq[4] = user_angle(4, 0.0, K)
    d1 = wrap(q1 - qq[0])
    q4 = qq[3]
    for sgn in (1.0, -1.0, 0.0):  # (0: q1 stays where the polish left it)
        qq[0] = q1 if sgn != 0.0 else q1 - d1
        qq[3] = q4 + sgn * d1
        if _exact(qq, Td, K, mats):
            break
    _split_sum(qq, K[L.SIGN + 3] * qq[3] + K[L.SIGN + 6] * qq[5], K, hint, has_hint)
    return True


@njit
def add_answer(q, out, count, Td, K, mats):
    """Append ``q`` (wrapped) to ``out[:count]`` unless it is already there: within DUP_TOL of
    a solution in every joint, or within MERGE_WINDOW and joined to it by a segment that is
    exact all along (:func:`_joined`), or, both on the shoulder set, by a walk of VALLEY_WALK
    points (:func:`walked`; there, with the wrist nearly straight too, the valley curves away
    from the segment and may be longer than MERGE_WINDOW): where the FK is flat (a
    nearly singular arm and wrist at once) exact solutions come as clusters of shadows wider
    than DUP_TOL, while two distinct solutions have an inexact pose between them. An exactly
    straight ``q`` takes the place of a nearly straight solution it is one with, and the other
    nearly straight shadows of its circle go (see :func:`_same_straight`). On the shoulder set
    a solution with axis 4 on axis 1 is first turned to its continuum's q1 (:func:`_axis4_turn`)
    and the continuum's shadows go (:func:`_drop_continuum_shadows`); a shadow of a continuum
    found is not added (:func:`_continuum_shadow`). A new solution when ``out`` is full raises
    RuntimeError (never a silent drop)."""
    for i in range(6):
        q[i] = wrap(q[i])
    sgn = 0.0
    shoulder = on_shoulder_set(q, K)
    if shoulder:
        mats[MAT_CW].reshape(16)[CW_SHOULDER] = 1.0
        sgn = _axis4_turn(q, Td, K, mats)
        if sgn == 0.0 and _continuum_shadow(q, out, count, Td, K, mats):
            return count
        if sgn != 0.0:
            mats[MAT_CW].reshape(16)[CW_FOUND] = 1.0
    count = _insert(q, out, count, Td, K, mats, shoulder)
    if sgn != 0.0:
        return _drop_continuum_shadows(out, count, q, sgn, Td, K, mats)
    return count


@njit
def _insert(q, out, count, Td, K, mats, shoulder):
    """:func:`add_answer`'s duplicate rules and the append (``shoulder``: ``q`` is on the shoulder set)."""
    for k in range(count):
        far = apart(out[k], q)
        if far <= DUP_TOL or _same_straight(out[k], q, Td, K, mats):
            if bend(q, K) <= STRAIGHT_EXACT < bend(out[k], K):
                for i in range(6):
                    out[k, i] = q[i]
                return _drop_straight_shadows(out, count, k, Td, K, mats)
            return count
        if far < MERGE_WINDOW:
            # (scratch: the next free row, or when full the wrist's work matrix, free here)
            mid = out[count] if count < out.shape[0] else mats[MAT_WR].reshape(16)[:6]
            if _joined(out[k], q, mid, Td, K, mats):
                return count
        if (shoulder and far < CONTINUUM_WINDOW and mats[MAT_CW].reshape(16)[CW_FOUND] != 0.0
                and on_shoulder_set(out[k], K) and walked(out[k], q, Td, K, mats)):
            return count  # (beside a continuum: see CONTINUUM_WINDOW)
        pair = _valley_pair(out[k], q, far, K)
        if pair or (far < MERGE_WINDOW and shoulder and on_shoulder_set(out[k], K)):
            # (one valley of a deviating model's nearly straight wrist, or of the shoulder set:
            # see MERGE_WINDOW; the one walk for both)
            if walked(out[k], q, Td, K, mats, VALLEY_WALK):
                if pair and bend(q, K) < bend(out[k], K):
                    for i in range(6):
                        out[k, i] = q[i]
                return count
    if count == out.shape[0]:
        raise RuntimeError("ik7r: more distinct solutions than the output holds (MAX_SOLUTIONS); "
                           "none is dropped silently: please report the pose")
    for i in range(6):
        out[count, i] = q[i]
    return count + 1


@njit
def _valley_pair(q0, q1, far, K):
    """Whether the exact ``q0`` and ``q1`` (``far`` apart, rad) of a model that deviates from the
    idealised one may be one solution of a nearly straight wrist: both within STRAIGHTEN_REACH of
    straight and closer than CONTINUUM_WINDOW; they are when a walk of VALLEY_WALK points at
    least joins them (:func:`walked`, in :func:`_insert`). There the FK is flat in the split,
    and polishes from a grid of starts (or from a scan's dip) stop at different points of one
    valley (a rounded member: four points over 2.6e-3 rad of q4, which the path of least pose
    error joins); its curve leaves the
    straight segment of :func:`_joined`. The walk is finer than WALK_MIN's (three inner points
    over such a pair) so that where two valleys nearly touch, the error's rise between them
    shows at one of its points. Farther apart, two such solutions with the arm, q5 and
    ``s4 q4 + s7 q7`` within MERGE_WINDOW (one circle of the idealised model's straight wrist)
    may be one too: a model that deviates by about the tolerance (a twist 1e-13 rad off, d6 1e-11
    mm) meets the pose along much of that circle, whose exact points then filled the output.
    Only on a model whose deviation moves a pose by CIRCLE_WALK tolerances at most: a valley
    longer than MERGE_WINDOW needs it within about 100 (the error along the circle grows about
    as the deviation's move times the turn)."""
    if not (K[L.DEVIATION] > 0.0 and bend(q0, K) <= STRAIGHTEN_REACH and bend(q1, K) <= STRAIGHTEN_REACH):
        return False
    if far < CONTINUUM_WINDOW:
        return True
    return K[L.DEVIATION_EFFECT] <= CIRCLE_WALK and _one_circle(q0, q1, K, MERGE_WINDOW)


@njit
def _floored(q, x, Td, K, mats):
    """``x``: the exact ``q`` polished by at most FLOOR_ITERS Newton steps toward FLOOR times the
    tolerances (its floor; the polish may stop short of that, at the FK's rounding); whether it
    is still exact and within MERGE_WINDOW of ``q``."""
    for i in range(6):
        x[i] = q[i]
    polish(x, Td, K, FLOOR_ITERS, True, 0, 0.0, ALL_JOINTS, FLOOR)
    return _exact(x, Td, K, mats) and apart(x, q) < MERGE_WINDOW


@njit
def _turned(q, q1, sgn, qq):
    """``qq``: ``q`` turned about axis 1 to joint 1 at ``q1``, joint 4 by ``sgn`` (+-1) times as
    much (the other way round when axis 4 points along axis 1 against it)."""
    d = wrap(q1 - q[0])
    for i in range(6):
        qq[i] = q[i]
    qq[0] = q1
    qq[3] = wrap(q[3] + sgn * d)


@njit
def _exact(q, Td, K, mats):
    """Whether ``q`` meets the pose ``Td`` to the robot's tolerances (a NaN does not)."""
    T = mats[MAT_T]
    fk_user(q, K, T)
    dp, dr = residual(T, Td)
    return dp <= K[L.POS_TOL] and dr <= K[L.ROT_TOL]


@njit
def _axis4_turn(q, Td, K, mats):
    """Where axis 4 of the exact solution ``q`` (wrapped) lies on axis 1, turn it in place to
    the continuum's joint 1 (the seed's q1, else 0; see :func:`add_answer`) and return the sign of the
    turn of joint 4 (+-1); else leave it and return 0. The turn is checked on the forward
    kinematics at its end and half way (:func:`_turn_onto`): a turn ``d`` about two axes ``e``
    apart moves the tool by about ``2 e sin(d / 2)``, which grows with ``abs(d)`` up to half a
    turn, so its end bounds the whole of it."""
    w = mats[MAT_CW].reshape(16)
    ref = w[CW_REF]
    to = ref if q[0] != ref else wrap(ref + 0.5 * math.pi)  # (on it already: a quarter turn tells)
    qq = w[:6]
    for sgn in (1.0, -1.0):
        if _turn_onto(q, q[0] + 0.5 * wrap(to - q[0]), sgn, qq, Td, K, mats) and _turn_onto(
                q, to, sgn, qq, Td, K, mats):
            if to == ref:
                for i in range(6):
                    q[i] = qq[i]
            return sgn
    return 0.0


@njit
def _turn_onto(q, q1, sgn, qq, Td, K, mats):
    """``qq``: ``q`` turned about axis 1 to joint 1 at ``q1`` (:func:`_turned`); whether it is
    exact. A turned point that misses the pose by no more than TURN_SLACK times the tolerances is
    polished with joint 1 held: the solver's own points on the continuum place axis 4 on axis 1
    only to about 1e-12 rad (the FK is flat there), which a half turn makes a miss of a few
    times the paper robot's 1e-9 mm."""
    _turned(q, q1, sgn, qq)
    T = mats[MAT_T]
    fk_user(qq, K, T)
    dp, dr = residual(T, Td)
    if dp <= K[L.POS_TOL] and dr <= K[L.ROT_TOL]:
        return True
    if not (dp <= TURN_SLACK * K[L.POS_TOL] and dr <= TURN_SLACK * K[L.ROT_TOL]):
        return False
    return polish(qq, Td, K, 8, True, 0, 0.0, ALL_JOINTS ^ 1)


@njit
def _continuum_shadow(q, out, count, Td, K, mats):
    """Whether the exact ``q`` (on the shoulder set, not itself turnable) is a shadow of an axis
    4 continuum in ``out[:count]`` (:func:`_beside`)."""
    ref = mats[MAT_CW].reshape(16)[CW_REF]
    for k in range(count):
        if out[k, 0] == ref and on_shoulder_set(out[k], K):
            for sgn in (1.0, -1.0):
                if _beside(out[k], sgn, q, Td, K, mats):
                    return True
    return False


@njit
def _drop_continuum_shadows(out, count, m, sgn, Td, K, mats):
    """Drop from ``out[:count]`` the shadows (:func:`_beside`) of the continuum of axis 4 on
    axis 1 through ``m`` (at the continuum's q1, joint 4 turning by ``sgn``); the continua's own
    rows (at that q1) stay. Returns the new count."""
    ref = mats[MAT_CW].reshape(16)[CW_REF]
    keep = 0
    for s in range(count):
        if out[s, 0] == ref or not (on_shoulder_set(out[s], K) and _beside(m, sgn, out[s], Td, K, mats)):
            keep = _kept(out, keep, s)
    return keep


@njit
def _beside(m, sgn, x, Td, K, mats):
    """Whether the exact ``x`` is a shadow of the continuum of axis 4 on axis 1 through ``m``
    (joint 4 turning by ``sgn``): within CONTINUUM_WINDOW of the continuum's point at its own q1
    and joined to it by an exact walk (:func:`walked`)."""
    c = mats[MAT_CW].reshape(16)[6:12]
    _turned(m, x[0], sgn, c)
    return (apart(c, x) < CONTINUUM_WINDOW and _turn_onto(m, x[0], sgn, c, Td, K, mats)
            and (apart(c, x) <= DUP_TOL or walked(c, x, Td, K, mats)))


@njit
def walked(a, b, Td, K, mats, least=WALK_MIN):
    """Whether a walk from the exact ``a`` to the exact ``b`` stays exact: its points WALK_STEP
    apart on the segment (``least`` of them at least, WALK_MIN: a shorter walk would check
    nothing), each that misses the pose polished onto it by damped steps with the joint of the
    largest difference held (the walk's parameter), no joint moved from the walk's point before
    it by more than twice its own share of the difference (plus WALK_SLACK): a walk that keeps
    to one solution and jumps to the other at its last step is no walk. Where the FK is flat an
    exact valley may curve away from the straight segment (:func:`_joined`) between two of its
    points; a walk that jumps is not one valley."""
    w = mats[MAT_WALK].reshape(16)
    x = w[:6]
    prev = w[6:12]
    far = 0.0
    j = 0
    for i in range(6):
        d = abs(wrap(b[i] - a[i]))
        if d > far:
            far = d
            j = i
    n = max(least, int(math.ceil(far / WALK_STEP)))
    for i in range(6):
        prev[i] = a[i]
    for k in range(1, n + 1):
        f = k / n
        for i in range(6):
            x[i] = a[i] + f * wrap(b[i] - a[i])
        if k < n and not _exact(x, Td, K, mats) and not polish(
                x, Td, K, 8, True, 0, 0.0, ALL_JOINTS ^ (1 << j)):
            return False
        for i in range(6):
            if abs(wrap(x[i] - prev[i])) > 2.0 * abs(wrap(b[i] - a[i])) / n + WALK_SLACK:
                return False
            prev[i] = x[i]
    return True


@njit
def apart(q0, q1):
    """The largest wrapped difference of joints 1..6 between ``q0`` and ``q1`` (rad): how two
    joint vectors are compared throughout (duplicates, the memo of starts, shadows)."""
    far = 0.0
    for i in range(6):
        far = max(far, abs(wrap(q0[i] - q1[i])))
    return far


@njit
def theta5(q, K):
    """DH theta5 of ``q`` (user angles), wrapped to (-pi, pi]."""
    return wrap(dh_angle(q, K, 4))


@njit
def bend(q, K):
    """abs(DH theta5) of ``q`` (user angles, wrapped)."""
    return abs(theta5(q, K))


@njit
def _same_straight(q0, q1, Td, K, mats):
    """Whether ``q0`` and ``q1`` are one straight-wrist solution of a model whose straight wrist
    is a circle (:func:`ik7r._kernels.singular.straight_circle`): one of
    them with theta5 within STRAIGHT_EXACT of 0, the other within DUP_TOL, the arm within
    DUP_TOL and the same ``s4 q4 + s7 q7`` (the only wrist angle defined there; the split is
    free), and the pose on the straight wrist's set (:func:`_circle_meets`). So a nearly
    straight solution within DUP_TOL (every joint) of a point of an exactly straight one's circle
    is that solution: where the FK is flat the circle has nearly straight shadows, e.g. the
    wrist's two bends +-3e-8 with q4 half a turn apart beside axis 7 on axis 1."""
    if not straight_circle(K):
        return False
    b0 = bend(q0, K)
    if b0 > DUP_TOL:
        return False
    b1 = bend(q1, K)
    if b1 > DUP_TOL or min(b0, b1) > STRAIGHT_EXACT or not _one_circle(q0, q1, K, DUP_TOL):
        return False
    return apart(q0, q1) <= DUP_TOL or _circle_meets(q0 if b0 <= b1 else q1, Td, K, mats)


@njit
def _circle_meets(q0, Td, K, mats):
    """Whether the pose lies on the straight wrist's set, so that the circle through ``q0`` (its
    arm and ``s4 q4 + s7 q7``) is one of solutions: ``q0`` made exactly straight meets it, at once
    or polished with the wrist held straight (a snap's rounding, a bend of 1e-12 rad, moves the
    tool by about the tolerance). Within STRAIGHT_EXACT of straight a bend still turns the tool by
    about its size times twice the twist's sine (a 45 deg member bent by 1e-9 rad: 1.4e-9 rad,
    beyond the tolerance), and there the two bends +-1e-9 with the split half a turn apart are
    two solutions, the wrist's mirror pair, not one circle's points."""
    x = mats[MAT_WALK].reshape(16)[:6]
    for i in range(6):
        x[i] = q0[i]
    x[4] = user_angle(4, 0.0, K)
    return _exact(x, Td, K, mats) or polish(x, Td, K, 8, True, 0, 0.0, ALL_JOINTS ^ 0b10000)


@njit
def _one_circle(q0, q1, K, tol):
    """Whether ``q0`` and ``q1`` have the arm, q5 and ``s4 q4 + s7 q7`` within ``tol`` (rad): one
    circle of the idealised model's straight wrist, whose split (q4 against q7) is free."""
    for i in (0, 1, 2, 4):
        if abs(wrap(q0[i] - q1[i])) > tol:
            return False
    s4 = K[L.SIGN + 3]
    s7 = K[L.SIGN + 6]
    return abs(wrap(s4 * (q0[3] - q1[3]) + s7 * (q0[5] - q1[5]))) <= tol


@njit
def _kept(out, keep, s):
    """Keep row ``s`` of ``out`` as its row ``keep`` (the rows are compacted in order, ``keep``
    <= ``s``); returns the next row to keep."""
    if keep != s:
        for i in range(6):
            out[keep, i] = out[s, i]
    return keep + 1


@njit
def _drop_straight_shadows(out, count, k, Td, K, mats):
    """Drop from ``out[:count]`` the rows other than ``k`` that are one solution with the exactly
    straight ``out[k]`` (:func:`_same_straight`); returns the new count."""
    keep = 0
    for s in range(count):
        if s == k or not _same_straight(out[k], out[s], Td, K, mats):
            if s == k:
                k = keep
            keep = _kept(out, keep, s)
    return keep


@njit(allocates=True)
def straightened(x, Td, K, mats, flat=False):
    """The exact ``x`` (modified in place) of a model that deviates from the idealised one moved
    to the straight wrist where its valley reaches it: within STRAIGHTEN_REACH of straight, a
    polish with the wrist held there that meets the pose and that a walk joins to ``x`` is the
    same solution, on the Wrist indicators' boundary, so that it belongs to both configurations
    (a rounded member's flat valley held q5 = -4.3e-9 and +5.2e-7; the point kept was the
    latter, and ``ik`` in the source's configuration raised). ``flat``: only where Newton's step
    at ``x`` is not defined (:func:`ik7r._kernels.fk.newton_undefined`: a valley; the IRB 5400's
    isolated nearly straight solutions have pivots of 4e-11 and more, which no held-straight
    polish would join, and trying cost a third of its singular row's median)."""
    wrist = user_angle(4, 0.0, K)
    if x[4] == wrist or abs(wrap(x[4] - wrist)) > STRAIGHTEN_REACH:
        return
    if flat and not newton_undefined(x, Td, K):
        return
    y = x.copy()
    y[4] = wrist
    if polish(y, Td, K, STRAIGHTEN_ITERS, True, STALL_PATIENCE, 0.0, ALL_JOINTS ^ 0b10000) and (
            apart(x, y) <= DUP_TOL or walked(x, y, Td, K, mats)):
        for i in range(6):
            x[i] = y[i]


@njit
def _joined(q0, q1, mid, Td, K, mats):
    """Whether the segment from ``q0`` to ``q1`` is exact all along (checked at a quarter, half
    and three quarters of the way; ``mid`` (6,): scratch)."""
    for f in (0.5, 0.25, 0.75):
        for i in range(6):
            mid[i] = q0[i] + f * wrap(q1[i] - q0[i])
        if not _exact(mid, Td, K, mats):
            return False
    return True


#: What the polish of an inexact candidate came to (:func:`_polish_deviating`,
#: :func:`_polish_exact`): nothing, an exact solution in ``q`` (to be appended), or one already
#: in the output.
_MISSED = 0
_LANDED = 1
_KNOWN = 2


@njit
def accept(q, Td, K, out, count, mats, snap=False, follow=True):
    """Verify ``q`` on the exact forward kinematics (polishing it if needed) and append it.

    Nothing reaches ``out`` that does not meet the pose to the robot's tolerances (a NaN
    candidate is refused). Returns the new count and whether ``q`` leads to a solution in
    ``out``: appended now, already there, or (on an exact model) within DUP_TOL of one there,
    which it would polish to (:func:`_known`). An inexact ``q`` is polished by
    :func:`_polish_deviating` on a model that deviates from the idealised one (``follow``: ``q``
    solves the idealised model), else by :func:`_polish_exact`. A ``snap`` (theta5 set to
    exactly 0 or pi) is not polished on a deviating model: the polish would leave the singular
    wrist for one of the two solutions beside it, and the caller would stop looking for the
    other. ``mats``: the pose's matrix stack (see :func:`solve_into`)."""
    T = mats[MAT_T]
    fk_user(q, K, T)
    dp, dr = residual(T, Td)
    if not (dp <= K[L.POS_TOL] and dr <= K[L.ROT_TOL]):  # (a NaN candidate is not exact)
        if not (dp < 1e300 and dr < 1e300):
            return count, False
        if K[L.DEVIATION] > 0.0:
            outcome = _MISSED if snap else _polish_deviating(q, dp, Td, K, follow, mats)
        else:
            outcome = _polish_exact(q, Td, K, out, count, snap,
                                    max(dp / K[L.POS_TOL], dr / K[L.ROT_TOL]) <= SNAP_ROUNDING)
        if outcome != _LANDED:
            return count, outcome == _KNOWN
    if K[L.DEVIATION] > 0.0:
        straightened(q, Td, K, mats, True)
    return add_answer(q, out, count, Td, K, mats), True


@njit
def _polish_deviating(q, dp, Td, K, follow, mats):
    """Polish the candidate ``q`` (position error ``dp``) onto the exact model of a robot that
    deviates from the idealised one, in place; returns _MISSED, _LANDED or _KNOWN (see
    :func:`accept`). A start already followed in this pose gives the outcome it gave
    (:func:`_tried`: _KNOWN for a solution found then); one farther than START_REACH of the
    robot's size from meeting the pose is not followed; otherwise ``q`` is followed from the
    idealised model to the exact one (when ``follow``: a homotopy over HOMOTOPY_STEPS
    intermediate models) and polished by Newton, giving up after STALL_PATIENCE steps without
    progress; where that lands nowhere, Newton polishes from the start itself as well."""
    # the same start twice (candidates of nearby roots, brackets and scans often are): the
    # polish would only repeat itself
    entry, seen = _tried(q, follow, mats)
    if seen >= 0.0:
        return _KNOWN if seen == 1.0 else _MISSED
    if dp > START_REACH * K[L.SCALE]:
        _remember(entry, False, mats)
        return _MISSED
    # follow the solution from the idealised model to the exact one in small steps, so that
    # each candidate lands on its own exact solution even inside a close cluster
    for k in range(L.HOMOTOPY_STEPS if follow else 0):
        polish(q, Td, K[L.HOMOTOPY + k * L.BASE_SIZE:L.HOMOTOPY + (k + 1) * L.BASE_SIZE], 4,
               False, 0, HOMOTOPY_SETTLE)
    # (damped where Newton's step is not defined: a candidate at a nearly straight wrist, whose
    # split the FK hardly sees, stopped 1.6e-7 mm off at once, its solution 4e-6 rad away)
    exact = polish(q, Td, K, 30, True, STALL_PATIENCE)
    if not exact and follow:
        # the candidate may not solve the idealised model at all (where that has no solution
        # and the exact model has two): the homotopy then leads it toward the idealised model's
        # nearest point instead (a lateral crossing's candidate beside a far-deviating member's
        # fully bent wrist went from 0.17 to 0.3 mm off, beyond the fold, while Newton from the
        # start converges in two steps). Newton from the start as well
        m, o = _memo_slot(entry)
        start = mats[m].reshape(16)
        for i in range(6):
            q[i] = start[o + i]
        exact = polish(q, Td, K, 30, True, STALL_PATIENCE)
    _remember(entry, exact, mats)
    return _LANDED if exact else _MISSED


@njit
def _polish_exact(q, Td, K, out, count, snap, rounding=False):
    """Polish the candidate ``q`` on an exact family member, in place; returns _MISSED, _LANDED
    or _KNOWN (see :func:`accept`). Within DUP_TOL of a solution in ``out[:count]`` it is that
    solution (:func:`_known`), else Newton polishes it: by damped steps on the shoulder set when
    no solution found is within SINGULAR_ALONE (:func:`on_shoulder_set`; not a snap). A snap to
    the fully bent wrist that Newton cannot polish and that misses the pose only by rounding
    (``rounding``: within SNAP_ROUNDING times the tolerances) is polished with joint 5 held."""
    if _known(q, out, count, DUP_TOL):
        return _KNOWN  # the solution it would polish to is there (see _known)
    damped = (not snap and (on_shoulder_set(q, K) or _elbow_stretched(q, K))
              and not _known(q, out, count, SINGULAR_ALONE))
    if polish(q, Td, K, 8, damped):
        return _LANDED
    if snap and rounding and math.pi - bend(q, K) < STRAIGHT_EXACT:
        # the fully bent wrist, where Newton's step is not defined: the other joints by damped
        # steps, joint 5 held (an exact member: the arm's rounding left a snap 1.3e-9 mm off at
        # a tolerance of 1e-9, 1e-12 rad from its source; a snap farther off may be a point of
        # the fold's flat valley, whose held polish travels to another point of it)
        return _LANDED if polish(q, Td, K, 8, True, 0, 0.0, ALL_JOINTS & ~(1 << 4)) else _MISSED
    return _MISSED


@njit
def _elbow_stretched(q, K):
    """Whether the elbow of ``q`` (user angles) is within STRETCH_EXACT of stretched or folded
    (:func:`ik7r._kernels.singular.elbow_stretched`): the arm is singular, and with the wrist
    straight as well Newton's step is not defined."""
    t3 = K[L.SIGN + 2] * q[2] + K[L.DH + 11]
    return elbow_stretched(math.cos(t3), math.sin(t3), K, STRETCH_EXACT)


@njit
def on_shoulder_set(q, K):
    """Whether the virtual wrist centre of ``q`` (user angles) lies within SHOULDER_NEAR of the
    robot's size from axis 1, for a robot without lateral offset: the shoulder singular set,
    where the arm leaves theta1 free (its distance in the arm plane, ``a1`` plus the reach of
    joints 2 and 3 to the centre at ``d4 + d(theta5)`` along axis 4)."""
    if K[L.B] != 0.0:
        return False
    x = K[L.SB] * math.sin(0.5 * bend(q, K))
    h = 1.0 - 2.0 * x * x
    if h < 1e-9:
        return False  # the fold of a 45 deg twist: the virtual centre is at infinity
    Ld = K[L.D4] + K[L.KW] / h
    t2 = K[L.SIGN + 1] * q[1] + K[L.DH + 7]
    t3 = K[L.SIGN + 2] * q[2] + K[L.DH + 11]
    c3 = math.cos(t3)
    s3 = math.sin(t3)
    e3 = K[L.EPS3]
    x2 = K[L.A2] + K[L.A3] * c3 + e3 * Ld * s3
    y2 = K[L.A3] * s3 - e3 * Ld * c3
    return abs(K[L.A1] + math.cos(t2) * x2 - math.sin(t2) * y2) < SHOULDER_NEAR * K[L.SCALE]


@njit
def _tried(q, follow, mats):
    """Look up the start ``q`` of a polish on a model that deviates from the idealised one (see
    :func:`accept`) among those tried in this pose: a start within MEMO_TOL (rad, every joint)
    of one tried with the same ``follow`` lands where that one did (the polish is deterministic
    and continuous in its start). Returns (entry, outcome): the outcome of the start tried (1
    exact, 0 not), or -1 and a new entry holding ``q`` (the oldest one when the ring of
    MEMO_SIZE is full), whose outcome the caller records with :func:`_remember`."""
    n = int(mats[MAT_MEMO_N, 0, 0])
    fl = 1.0 if follow else 0.0
    for k in range(min(n, MEMO_SIZE)):
        m, o = _memo_slot(k)
        e = mats[m].reshape(16)[o:o + 8]
        if e[6] != fl or e[7] < 0.0:
            continue
        if apart(e, q) <= MEMO_TOL:
            return k, e[7]
    k = n % MEMO_SIZE
    m, o = _memo_slot(k)
    e = mats[m].reshape(16)[o:o + 8]
    for i in range(6):
        e[i] = q[i]
    e[6] = fl
    e[7] = -1.0
    mats[MAT_MEMO_N, 0, 0] = n + 1
    return k, -1.0


@njit
def _remember(k, exact, mats):
    """Record the outcome of the start in memo entry ``k`` (see :func:`_tried`)."""
    m, o = _memo_slot(k)
    mats[m].reshape(16)[o + 7] = 1.0 if exact else 0.0


@njit
def _memo_slot(k):
    """Where entry ``k`` of the memo of :func:`_tried` lies: the matrix of the pose's stack and
    the offset in it of its 8 numbers (the start's 6 joints, whether it was followed, its
    outcome)."""
    return MAT_MEMO + k // 2, 8 * (k % 2)


@njit
def _known(q, out, count, radius):
    """Whether the candidate ``q`` is within ``radius`` (every joint) of a solution in
    ``out[:count]``. With DUP_TOL: it is that solution (two solutions that close are one), so
    polishing it, which on the flat forward kinematics of a singular arm or wrist takes all of
    Newton's steps, would only find it again. (Not for models that deviate from the idealised
    one, whose candidates are followed to the exact model one by one.) With SINGULAR_ALONE:
    see :func:`accept`."""
    for k in range(count):
        if apart(out[k], q) <= radius:
            return True
    return False


@njit
def floor_shoulder(out, count, Td, K, mats):
    """Polish the answers on the shoulder set to their floor (:func:`_floored`; FLOOR), each
    in place when that stays exact, and drop those that come within DUP_TOL of one before them:
    two points of one solution's valley, from either side. A continuum's point (at its q1, see
    :func:`_axis4_turn`) and an exactly straight or fully bent wrist (set by their rules: the
    split of :func:`_split_sum`, theta5 = pi) stay where they are."""
    x = mats[MAT_WALK].reshape(16)[:6]
    ref = mats[MAT_CW].reshape(16)[CW_REF]
    keep = 0
    for s in range(count):
        if (out[s, 0] != ref and STRAIGHT_EXACT < bend(out[s], K) < math.pi - STRAIGHT_EXACT
                and on_shoulder_set(out[s], K) and _floored(out[s], x, Td, K, mats)):
            for i in range(6):
                out[s, i] = wrap(x[i])
        if not _known(out[s], out, keep, DUP_TOL):
            keep = _kept(out, keep, s)
    return keep


@njit
def merge_folded(out, count):
    """Drop solutions within FOLD_WINDOW (every joint) of an exact fully bent one (theta5 = pi):
    there the FK is flat in theta5, and what remains are shadows of the one merged solution."""
    keep = 0
    for s in range(count):
        shadow = False
        if out[s, 4] != math.pi and math.pi - abs(out[s, 4]) < FOLD_WINDOW:
            for e in range(count):
                if out[e, 4] == math.pi:
                    if apart(out[s], out[e]) < FOLD_WINDOW:
                        shadow = True
                        break
        if not shadow:
            keep = _kept(out, keep, s)
    return keep
