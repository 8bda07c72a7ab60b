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
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import rotations
from . import params as L
from .arm import arm_cs, arm_params, arm_reach, shoulder_angle
from .fk import (
    ALL_JOINTS,
    dh_angle,
    dh_step_cs,
    fk_jacobian,
    fk_user,
    polish,
    pose_error,
    residual,
    user_angle,
)
from .jit import njit, shared
from .poly import (
    ISOLATE_WORK,
    MAX_DEGREE,
    REFINE_GRID,
    _least_abs,
    _newton_on_bracket,
    _off_zero,
    _power,
    bend_row_on_axis,
    brent_next,
    brent_start,
    brent_take,
    illinois_step,
    isolate,
    linear_system,
    refine,
    residual_of,
    secant_point,
)
from .wrist import (
    d_of_theta5,
    theta5_cs_of_d,
    theta5_cs_of_u,
    theta5_of_bend,
    wrist_ik_cs,
    wrist_rotation_cs,
    wrist_t7,
    wrist_target,
)

TWO_PI = 2.0 * math.pi
DUP_TOL = 1e-5  # two solutions closer than this (rad, every joint) are one (near a singular arm or
# wrist the FK is flat and its exact solutions come as clusters of numerically equal shadows)


#: Start (rad) off a singular wrist for polishing models that deviate from the idealised one.
NEAR_SINGULAR = 2e-3
#: Near-miss scan of deviating models: grid size, and how close to zero (relative to the
#: magnitude of the residual's terms) a local minimum of |residual| must come.
NEAR_GRID = 64
NEAR_RATIO = 1e-2
#: ... (or at its refined minimum, where the grid's least value is below NEAR_RATIO_GRID of that
#: magnitude and the parabola through it and its neighbours dips toward zero (:func:`_dips_to_zero`):
#: a factor's minimum between grid points reads higher on the grid; one IRB 5400 pair beside the
#: stretched elbow read 6.6e-2 on the grid and 9e-5 at its minimum)
NEAR_RATIO_GRID = 0.25
#: ... and, at its refined minimum, for one factor of G at an end of the range (see
#: :func:`_near_misses`; inside the range a factor's grid minimum is held to NEAR_RATIO as G's)
NEAR_RATIO_END = 1e-4
#: Most candidate roots of one pose: every bracket (24) may give REFINE_GRID + 2 candidates, and
#: on a deviating model the near misses (:func:`_near_misses`) three starts per local minimum of
#: each of up to three residuals on NEAR_GRID + 1 points (at most NEAR_GRID // 2 + 1 minima each).
ROOT_CAP = 24 * (REFINE_GRID + 2) + 3 * 3 * (NEAR_GRID // 2 + 1)
#: solve_config skips candidates whose indicators differ beyond this margin (rad) from a
#: boundary (larger for deviating models, whose polish moves the joints further).
FILTER_MARGIN = 1e-3
FILTER_MARGIN_DEVIATING = 0.1
#: Window (rad) around theta5 = 0 and pi where solutions are tried at exactly 0 or pi first, and
#: where nearly folded solutions merge into the folded one.
FOLD_WINDOW = 1e-4
#: On the idealised model the wrist is snapped to theta5 = pi only this close (rad) to it: the two
#: wrist solutions +-(pi - eps) beside the fold are 2 eps apart (every other joint closer), so
#: below eps = DUP_TOL / 2 they are one solution (:func:`_add`), above it two, each exact, while
#: theta5 = pi between them only meets the pose within the tolerance (the paper robot at
#: eps = 2.4e-5: 2.5e-11 mm at best, its segment to either solution inexact by 7e-9 mm).
FOLD_SNAP = 0.5 * DUP_TOL
#: A solution with theta5 within this (rad) of 0 is exactly straight: only s4 q4 + s7 q7 counts.
STRAIGHT_EXACT = 1e-9
#: Two exact solutions closer than this (rad, every joint) are one when the segment between
#: them is exact too (see :func:`_add`).
MERGE_WINDOW = 1e-2
#: A solution on the shoulder set (its virtual wrist centre on axis 1) lies in a valley where
#: the FK is flat in q1 (with the wrist nearly straight, also in q7): the polish stops at the
#: first point within the tolerances, at the edge of a band up to 1e-2 rad wide, and one
#: solution comes twice, once from each side, a straight segment apart that leaves the valley.
#: Such answers are polished on toward FLOOR times the tolerances (at most FLOOR_ITERS Newton
#: steps; see :func:`_floor_shoulder`), which takes them to the solution's root within DUP_TOL.
FLOOR = 1e-3
FLOOR_ITERS = 4
#: Axis 4 on axis 1 (the arm stretched along it: the paper robot's q2 = 90, q3 = -90 deg) turns
#: joints 1 and 4 together without moving the tool: an exact solution there is a continuum, kept
#: once, at the seed's q1 (else 0; see :func:`_add`). An exact point within CONTINUUM_WINDOW (rad,
#: every joint) of the continuum's point at its own q1 is that solution when a walk from that
#: point to it stays exact (:func:`_walked`, its points WALK_STEP apart): next to the continuum
#: the FK is flat, and the scans' exact points there (and the continuum's own isolated neighbours,
#: whose Jacobian's smallest singular value is about 1e-14 of its largest) are its shadows. In a
#: pose with such a continuum the same walk joins two exact points of the shoulder set this close
#: (elsewhere it would join distinct solutions of a near-shoulder pose, 1.3e-3 rad apart in q1,
#: that the straight segment of :func:`_joined` keeps apart).
CONTINUUM_WINDOW = 3e-2
WALK_STEP = 2e-3
WALK_MIN = 4  # (points at least: a walk shorter than WALK_STEP is checked at its quarters too)
WALK_SLACK = DUP_TOL  # (how much farther than twice its share a walk's step may move a joint)
#: ... and a point of the continuum turned to another joint 1 that misses the pose by no more
#: than this many times the tolerances is polished onto it (see :func:`_turn_onto`).
TURN_SLACK = 100.0
#: A candidate of the idealised model on the shoulder singular set (:func:`_on_shoulder_set`)
#: whose Jacobian is singular is polished by damped steps (:func:`ik7r._kernels.fk.polish`) when
#: no solution found lies within this (rad, every joint): there a nearly straight wrist makes
#: clusters of exact solutions, and axis 7 on axis 1 continua, whose members Newton cannot
#: polish. Closer to a solution found, the candidate is taken for a shadow of it and polished by
#: plain Newton steps (damped steps there merged the candidates beside the fold into the solution
#: found). That is a measured rule, not a bound: the FK is flat along the cluster, not across it
#: (1e-3 rad off an exact solution in a random direction misses the pose by 0.2-0.9 mm on the paper
#: robot), so a second exact solution within 1e-3 rad relies on Newton (docs/guide/edges.md).
SINGULAR_ALONE = 1e-3

#: Grid of the theta5 scan of an undecided bracket (see :func:`_scan_theta5`), and how close to
#: zero (rad) a local minimum of its bend gap must come to be a candidate (exact, deviating).
SCAN_GRID = 32
SCAN_PIECES = 12  # the grid and the pieces (next to branch ends, around dips) it may add
#: A dip that reaches (nearly) zero is scanned again on a grid of its own while its two cells
#: are at least SCAN_NEST of the scanned range wide, SCAN_NEST_FOLD_AXIS in the fold gap in
#: theta1 (:func:`_fold_axis_gap`): there a vertical approach next to the fold leaves two roots
#: 1.8e-3 rad apart in theta1 (b-45_mirrored, q5 1.2e-7 from pi), one grid cell of the nest
#: SCAN_NEST allows, and minimising |gap| over the cell finds only one of them.
SCAN_NEST = 1e-2
SCAN_NEST_FOLD_AXIS = 1e-4
#: Pieces narrower than this (relative to 1 + |start|, in their own variable) are not gridded:
#: one candidate from their sign change or their least |gap| (see :func:`_scan_piece`).
SCAN_TINY = 1e-10
#: A dip of a theta5 or fold gap (smooth on its branch) is minimised only until Brent's bracket
#: is below DIP_EARLY of the dip's two cells, if its least |gap| so far is then above DIP_FLOOR
#: (rad; twice SHOULDER_DIP, the largest threshold a dip's bottom is compared with): such a dip
#: gives no candidate (over 8,000 dips minimised to the end, none the rule stops came below 0.201).
#: Not for the gaps in theta1 (shoulder set, fold on axis 1): the shoulder gap's dips narrow to
#: zero within 1e-8 of their cells (docs/guide/edges.md, "The tail's time"), at every distance of
#: the deviating models' scan (1e-7 .. 2e-3 of the size) alike.
DIP_EARLY = 1e-1
DIP_FLOOR = 0.2
#: The theta1 scan runs where the line of virtual centres passes this close (relative to the
#: robot's size) to axis 1.
SHOULDER_NEAR = 1e-5
#: ... and this for a model that deviates from the idealised one (near the set its solutions come
#: in clusters the idealised roots do not have: the nominal gap's dips are candidates there),
#: relative to the larger of the size and the line's d there (:func:`_shoulder_offset`; this and
#: the two windows below)
SHOULDER_SCAN_DEVIATING = 2e-3
#: ... where the nominal shoulder gap has a dip below SHOULDER_DIP (rad), the exact model's
#: reduced residual in q1 is tracked SHOULDER_REACH (rad) each way from the dip's bottom, on
#: SHOULDER_CELLS cells each way (see :func:`_shoulder_exact`; the IRB 5400's exact solutions
#: were measured up to 0.11 rad from the bottom, beyond the dip's two cells of the turn's grid)
SHOULDER_DIP = 0.1
SHOULDER_REACH = 0.4
SHOULDER_CELLS = 8
#: ... where the line of virtual centres passes this close (relative to the robot's size, or to
#: its d there where that is larger) to axis 1 (1.0 mm on the IRB 5400, whose such clusters
#: were measured within 0.6 mm); out to SHOULDER_EXACT_FAR the reach shrinks as
#: SHOULDER_EXACT_NEAR / r (the deviation moves the virtual centre by about a fixed distance, so
#: the exact solutions move by about its angle seen from axis 1), on proportionally fewer cells
#: (at least 2): a rounded 35 deg robot's source 0.1 to 0.2 rad from the dip, the line 3.23e-4
#: of the size from axis 1. Within SHOULDER_EXACT_NEAR the exact model is also scanned over the
#: whole turn of q1, once per elbow branch and wrist sign (:func:`_shoulder_turn`): there the
#: deviation moves the virtual centre as far as its distance from axis 1, and exact solutions
#: lie far beyond any dip's reach.
SHOULDER_EXACT_NEAR = 3e-4
SHOULDER_EXACT_FAR = 5e-4
#: ... and where no arm of the turn reaches the virtual centre (the elbow stretched or folded,
#: within the deviation of the exact model's reach), the whole turn is tracked from the nearest
#: arm of the first that misses it by less than this in the elbow's cosine (rounded_b45: a
#: source whose nominal arm is 0.026 mm, 7.2e-6 in the cosine, short of folded enough)
SHOULDER_TURN_SLACK = 1e-3
#: ... and a scan in q1 starts its wrist bent by this (rad) at least: from a straight one the
#: five other joints' Gauss-Newton is singular (q4 and q7 on one axis) at every point of the turn,
#: and its two wrist signs are one start (rounded_b35: the nominal arm's d clamped to DMIN, the
#: source at q5 = 0.198 lost)
SHOULDER_TURN_BEND = 2e-2
#: ... and a dip within this (rad) of one already scanned on the same elbow branch in this pose is
#: that dip: the root and the dip tests of the shoulder gap's scan found the same one twice, 1e-10
#: apart, in 1 to 3 of a pose's 7 (IRB 5400), each time 40 reduced residuals more for the same
#: curves. SHOULDER_DIPS of them are remembered per pose.
SHOULDER_DIP_SAME = 1e-7
SHOULDER_DIPS = 16
#: Models that deviate from the idealised one: theta5 within this (rad) of 0 and pi is scanned
#: when a root lies there.
DEVIATING_ENDS = 2e-2
SCAN_NEAR = 1e-7
SCAN_NEAR_DEVIATING = 1e-2
#: ... and the minima of the arm branches' bend gaps on a grid of GAP_NEAR_CELLS over theta5 in
#: [0, pi] below this (rad) that dip toward zero are refined as near misses (see
#: :func:`_gap_near_misses`)
GAP_NEAR_GRID = 0.05
#: ... and one that comes below this (rad) without crossing zero is a candidate: beside the elbow
#: stretch, where the gap is steep, a near miss of 0.0148 gave a pair of exact solutions on a
#: rounded member (more than SCAN_NEAR_DEVIATING, the scans' threshold)
GAP_NEAR_DEPTH = 0.03
#: Near the fold of a (nearly) 45 deg twist the virtual centre's distance grows as 1 / sw^2 and a
#: deviating model's arm branch ends (the elbow stretched) where the nominal one does not: the
#: fold scan takes a branch's end itself as a candidate when the fold gap there is below this
#: (rad; 0.02 .. 0.025 seen on the rounded 45 deg robot of benchmarks/edges.py, and 0.152 at an
#: end 0.022 in sw before the exact solution: tests/ik/test_deviating.py)
FOLD_END_NEAR = 0.2
GAP_NEAR_CELLS = 12
#: ... and a grid point beside an arm branch's end (the elbow stretched) whose |gap| falls toward
#: the end is refined up to the end when below this (rad): beside the stretch the gap is steep,
#: and on the rounded 45 deg robot a grid point 0.0512 there had a near miss of 3.6e-3 at the end
GAP_NEAR_END = 0.2
#: Robots whose fully bent wrist is nearly folded back (``u = cos(2 beta)`` below FOLD_NEAR, a
#: twist within about 0.6 deg of 45 deg): their virtual centre runs off to infinity near
#: theta5 = pi, where the residual polynomial cannot be evaluated. The FOLD_SPAN of u next to
#: the fold is searched with the fold gap instead (:func:`_fold_gap`, finite there), the rest by
#: the polynomial.
FOLD_NEAR = 0.02
FOLD_SPAN = 0.05
#: ... and on a model that deviates from the idealised one, u down to this (of the range) below
#: the fold too (the nominal roots there, theta5 clamped to pi, start exact solutions at the
#: fold; 2e-2 found nothing more over 40,000 poses of four rounded 45 deg robots), on a grid of
#: FOLD_BELOW_CELLS: finer in sw than the span above (see :func:`_scan_fold`)
FOLD_BELOW = 2e-3
FOLD_BELOW_CELLS = 8
#: ... and where the scaled virtual centre at the fold is this close to axis 1 (relative to KW
#: and the robot's size; the approach nearly parallel to axis 1) the fold gap is scanned in
#: theta1 too.
FOLD_AXIS_NEAR = 0.01
#: ... where u up to this below the fold is taken at the fold (see :func:`_fold_axis_sw`).
FOLD_AXIS_CLAMP = 1e-9

#: Straight wrist of a model that deviates from the idealised one (see :func:`_straight_family`):
#: a candidate with theta5 below this (rad) starts a scan of the split q4 over the whole turn,
#: on a grid of REDUCED_GRID cells with REDUCED_ITERS Gauss-Newton steps per point; at most
#: _NFAMILIES arms per pose are remembered (further ones are scanned without that check).
STRAIGHT_DEVIATING = 2e-2
#: ... and below this where the arm is near the shoulder singular set (its virtual centre within
#: SHOULDER_DEVIATING of the robot's size from axis 1): there the deviation spreads the family's
#: solutions further (to |q5| = 0.07 on the IRB 5400; a rounded member with a1 = 32 mm had its
#: nominal candidates at theta5 = 0.105 and 0.18 and exact solutions at 0.054 and 0.127).
STRAIGHT_SHOULDER = 0.2
SHOULDER_DEVIATING = 1e-2
REDUCED_GRID = 48
#: ... and a grid value of the reduced residual below this fraction of both its neighbours (one
#: sign) is a dip to minimise (see :func:`_dips_to_zero`)
DIP_SHARP = 0.1
#: ... and a grid point whose least-squares error ``|e|`` (position over the size, and rad) is a
#: local minimum below this is a dip whatever the shape of its neighbours: a near miss of the
#: order of the deviation. Near the shoulder set the five other joints' least squares sharpen the
#: residual into a notch narrower than a cell, which no three grid values can tell from a
#: shallow minimum (generated(2): a pair of roots 0.015 rad apart under values -9.0e-8, -6.1e-8,
#: -3.1e-7 of ``r``, ``|e|`` 3.9e-5, 1.4e-5, 5.9e-5).
DIP_NEAR = 1e-4
REDUCED_ITERS = 4
#: ... stopping before a step below this (rad; see :func:`_reduced_at`)
REDUCED_SETTLE = 1e-5
#: ... and a root of it refined until the residual the last step would leave is below this
#: (position over the size, and rad): the point is then within REDUCED_SETTLE of the solution
#: in the other joints anyway, which the polish on the exact model takes to the last bits
#: (see :func:`_reduced_root`)
REDUCED_ROOT_TOL = 1e-9
#: ... and a scan over the whole turn whose last point is within this (rad, every joint) of its
#: first has come back to its start: a closed curve (see :func:`_reduced_scan`)
CLOSED_TOL = 1e-4
_NFAMILIES = 8
#: Deviating models: a solution whose Jacobian's smallest singular value (position rows over the
#: robot's size, relative to the largest) is below this may have a partner the idealised model
#: does not have (see :func:`_partners`), looked for up to PARTNER_REACH (rad) away.
PARTNER_SIGMA = 2e-3
#: ... and a solution with no other one within this (rad, joints 1 to 3) whose theta5 has the
#: other sign starts a polish from its arm with the other wrist (see :func:`_other_wrists`)
OTHER_WRIST_ARM = 1e-2
PARTNER_REACH = 0.3
#: ... and where the partner step finds nothing new, the reduced residual in the joint the
#: singular vector moves most is scanned this many cells each way (PARTNER_REACH times that
#: joint's share of the vector), from PARTNER_STEP of a cell beside the solution (where the
#: residual is zero, so that the first cell's sign test would read its rounding)
PARTNER_CELLS = 4
PARTNER_STEP = 0.1

#: Largest number of Bernstein coefficients, and of brackets.
_NB = MAX_DEGREE + 1
_NBRACKETS = 24


def _offsets(**sizes):
    """Consecutive offsets of named blocks in one work array, and its total size."""
    out, at = {}, 0
    for name, size in sizes.items():
        out[name] = at
        at += size
    return out, at


# One work array per pose (see solve_into) holds every scratch block.
# Its small matrices are one block viewed as a stack of 4 x 4 matrices (``mats``, made once per
# pose: a view of a stack entry costs nothing, a reshape does); these are their indices.
_T07, _R07, _M, _Q, _T, _WR, _PSI, _CW, _WALK = range(9)
#: The entry _CW of the stack: the joint 1 of the turn of axis 4 on axis 1 (see :func:`_add`),
#: at this index of its 16 values (the seed's q1, else 0), and at _CW_FOUND 1 once the pose has
#: such a continuum; the rest is the turn's scratch. The entry _WALK: a walk's point and the one
#: before it (:func:`_walked`).
_CW_REF = 12
_CW_FOUND = 13
_CW_SHOULDER = 14  # (1 once a solution on the shoulder set was added: see :func:`_floor_shoulder`)
#: Models that deviate from the idealised one: the starts already followed to the exact model in
#: this pose and what became of them (see :func:`_tried`), MEMO_SIZE of them (a ring, two per
#: 4 x 4 entry of the stack from index _MEMO on; their count in the entry _MEMO_N).
MEMO_SIZE = 64
MEMO_TOL = 1e-6  # (rad; 1e-9 and 1e-6 gave the same solutions over 36,000 poses of six robots)
#: ... and a start farther than this (relative to the robot's size) from meeting the pose is not
#: followed: a candidate of the idealised model misses the exact one by about the deviation, so
#: such a start is no candidate's (a wrong branch; its polish wanders 30 clamped steps, one
#: 0.1 rad at a time). Measured over 36,000 poses of six robots, 0.005 lost no solution either.
START_REACH = 0.05
#: ... and its polish gives up when the error stalls for this many Newton steps (see fk.polish;
#: 3 lost no solution either over those 36,000 poses).
STALL_PATIENCE = 6
#: A polish on an intermediate model of the homotopy stops once its Newton step is below this
#: (rad; the error left is of the order of its square): the forward kinematics that would verify
#: it is not needed there.
HOMOTOPY_SETTLE = 1e-4
#: The whole-turn reduced scans of this pose (:func:`_reduced_scan` over REDUCED_GRID cells) that
#: tracked a curve of their own, SCAN_MEMO of them (a ring). A later scan over the same grid
#: whose two last points coincide with an earlier one's within SCAN_MEMO_TOL (rad, every joint)
#: has joined its curve: the rest of its grid is that scan's (each point is Gauss-Newton from
#: the extrapolation of the two before it), and so is the refinement of every cell whose points
#: coincide. Near the shoulder set the candidates of one straight-wrist family, up to 0.3 rad
#: apart in q1, each track the same two sheets (a rounded 45 deg robot: 26 scans of 4 curves).
SCAN_MEMO = 16
SCAN_MEMO_TOL = 1e-9
_SCAN_HEAD = 5  # j, v0, v1, m, closed; then per grid point its six joints, r and |e|
_SCAN_SLOT = _SCAN_HEAD + 8 * (REDUCED_GRID + 1)
_MEMO = 9
_MEMO_N = _MEMO + MEMO_SIZE // 2
_NMATS = _MEMO_N + 1
_W, WORK_SIZE = _offsets(
    MATS=_NMATS * 16, P=3, A=3, TH=10, Q6=6, QQ=6,
    BLO=_NBRACKETS, BHI=_NBRACKETS, BSURE=_NBRACKETS, FOUND=REFINE_GRID + 2,
    BCOEF=_NBRACKETS * _NB, CAST=_NB, ISO=ISOLATE_WORK, ROOTS=ROOT_CAP, NB=1,
    SCAN=SCAN_GRID + 1, SUB=2 * SCAN_PIECES, FAM=4 * _NFAMILIES, NFAM=1, PAIR=2 * (SCAN_GRID + 1),
    RSCAN=SCAN_MEMO * _SCAN_SLOT, NRSCAN=1, SDIP=2 * SHOULDER_DIPS, NSDIP=1,
)
_MATS, _P, _A, _TH, _Q6, _QQ = _W["MATS"], _W["P"], _W["A"], _W["TH"], _W["Q6"], _W["QQ"]
_BLO, _BHI, _BSURE, _FOUND = _W["BLO"], _W["BHI"], _W["BSURE"], _W["FOUND"]
_BCOEF, _CAST, _ISO, _ROOTS = _W["BCOEF"], _W["CAST"], _W["ISO"], _W["ROOTS"]
_NBK, _SCAN, _SUB = _W["NB"], _W["SCAN"], _W["SUB"]
_NTH = 10  # the arm's cosines and sines, theta5, and O4 (see :func:`_fold_gap`)
_FAM, _NFAM, _PAIR = _W["FAM"], _W["NFAM"], _W["PAIR"]
_RSCAN, _NRSCAN = _W["RSCAN"], _W["NRSCAN"]
_SDIP, _NSDIP = _W["SDIP"], _W["NSDIP"]


# the one angle wrap, to (-pi, pi], and the exact reduction under it (ik7r.geometry.rotations)
shared(rotations.remainder_2pi_below_2_26)
remainder_2pi = shared(rotations.remainder_2pi)
wrap = shared(rotations.wrap)


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
def _psi_candidates(a11, a12, m, a21, a22, c, out, tol=1e-4):
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
def _straight_split(q, Q, K, hint, has_hint):
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
def _straight_damped(qq, Td, K, hint, has_hint, mats):
    """Polish the straight snap ``qq`` of the idealised model on the shoulder set by damped steps
    (:func:`ik7r._kernels.fk.polish`), in place; False when it does not reach an exactly
    straight point, else True, with q1 as the arm set it (the seed's; the continuum of axis 7 on axis 1 turns
    the wrist's sum with it) and the split of :func:`_split_sum`. (There the arm's root is only
    good to about sqrt(eps), a double root, and the FK is flat: Newton cannot polish the snap, and
    the two bends +-t5 beside it are shadows of the one straight solution. With the elbow
    stretched there as well, the arm's error is a few 1e-7 rad and the damped polish, free in
    q5, takes it up with a bend of the same size, one of those shadows: the snap is then polished
    again with the wrist held straight, q1..q4 alone, where that error is first order.)"""
    q1, q2, q3, q4_snap, q7 = qq[0], qq[1], qq[2], qq[3], qq[5]
    if not polish(qq, Td, K, 8, True) or _bend(qq, K) > STRAIGHT_EXACT:
        # (the polish left the straight wrist for a shadow beside it: hold the wrist instead)
        qq[0], qq[1], qq[2], qq[3], qq[5] = q1, q2, q3, q4_snap, q7
        qq[4] = user_angle(4, 0.0, K)
        if not polish(qq, Td, K, 8, True, 0, 0.0, 0b001111):  # (q5 and q7 held)
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
def _fold_snap(K):
    """How close (rad) to theta5 = pi a wrist is tried at pi exactly first: FOLD_SNAP on the
    idealised model, FOLD_WINDOW on a deviating one (whose polish starts off the fold)."""
    return FOLD_SNAP if K[L.DEVIATION] == 0.0 else FOLD_WINDOW


@njit
def _add(q, out, count, Td, K, mats):
    """Append ``q`` (wrapped) to ``out[:count]`` unless it is already there: within DUP_TOL of
    a solution in every joint, or within MERGE_WINDOW and joined to it by a segment that is
    exact all along (:func:`_joined`): where the FK is flat (a
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
    shoulder = _on_shoulder_set(q, K)
    if shoulder:
        mats[_CW].reshape(16)[_CW_SHOULDER] = 1.0
        sgn = _axis4_turn(q, Td, K, mats)
        if sgn == 0.0 and _continuum_shadow(q, out, count, Td, K, mats):
            return count
        if sgn != 0.0:
            mats[_CW].reshape(16)[_CW_FOUND] = 1.0
    count = _insert(q, out, count, Td, K, mats, shoulder)
    if sgn != 0.0:
        return _drop_continuum_shadows(out, count, q, sgn, Td, K, mats)
    return count


@njit
def _insert(q, out, count, Td, K, mats, shoulder):
    """:func:`_add`'s duplicate rules and the append (``shoulder``: ``q`` is on the shoulder set)."""
    for k in range(count):
        far = _far(out[k], q)
        if far <= DUP_TOL or _same_straight(out[k], q, K):
            if _bend(q, K) <= STRAIGHT_EXACT < _bend(out[k], K):
                for i in range(6):
                    out[k, i] = q[i]
                return _drop_straight_shadows(out, count, k, K)
            return count
        if far < MERGE_WINDOW:
            # (scratch: the next free row, or when full the wrist's work matrix, free here)
            mid = out[count] if count < out.shape[0] else mats[_WR].reshape(16)[:6]
            if _joined(out[k], q, mid, Td, K, mats):
                return count
        if (shoulder and far < CONTINUUM_WINDOW and mats[_CW].reshape(16)[_CW_FOUND] != 0.0
                and _on_shoulder_set(out[k], K) and _walked(out[k], q, Td, K, mats)):
            return count  # (beside a continuum: see CONTINUUM_WINDOW)
    if count == out.shape[0]:
        raise RuntimeError("ik7r: more distinct solutions than the output holds (MAX_SOLUTIONS); "
                           "none is dropped silently: please report the pose")
    for i in range(6):
        out[count, i] = q[i]
    return count + 1


@njit
def _floored(q, x, Td, K, mats):
    """``x``: the exact ``q`` polished by at most FLOOR_ITERS Newton steps toward FLOOR times the
    tolerances (its floor; the polish may stop short of that, at the FK's rounding); whether it
    is still exact and within MERGE_WINDOW of ``q``."""
    for i in range(6):
        x[i] = q[i]
    polish(x, Td, K, FLOOR_ITERS, True, 0, 0.0, ALL_JOINTS, FLOOR)
    return _exact(x, Td, K, mats) and _far(x, q) < MERGE_WINDOW


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
    T = mats[_T]
    fk_user(q, K, T)
    dp, dr = residual(T, Td)
    return dp <= K[L.POS_TOL] and dr <= K[L.ROT_TOL]


@njit
def _axis4_turn(q, Td, K, mats):
    """Where axis 4 of the exact solution ``q`` (wrapped) lies on axis 1, turn it in place to
    the continuum's joint 1 (the seed's q1, else 0; see :func:`_add`) and return the sign of the
    turn of joint 4 (+-1); else leave it and return 0. The turn is checked on the forward
    kinematics at its end and half way (:func:`_turn_onto`): a turn ``d`` about two axes ``e``
    apart moves the tool by about ``2 e sin(d / 2)``, which grows with ``abs(d)`` up to half a
    turn, so its end bounds the whole of it."""
    w = mats[_CW].reshape(16)
    ref = w[_CW_REF]
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
    T = mats[_T]
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
    ref = mats[_CW].reshape(16)[_CW_REF]
    for k in range(count):
        if out[k, 0] == ref and _on_shoulder_set(out[k], K):
            for sgn in (1.0, -1.0):
                if _beside(out[k], sgn, q, Td, K, mats):
                    return True
    return False


@njit
def _drop_continuum_shadows(out, count, m, sgn, Td, K, mats):
    """Drop from ``out[:count]`` the shadows (:func:`_beside`) of the continuum of axis 4 on
    axis 1 through ``m`` (at the continuum's q1, joint 4 turning by ``sgn``); the continua's own
    rows (at that q1) stay. Returns the new count."""
    ref = mats[_CW].reshape(16)[_CW_REF]
    keep = 0
    for s in range(count):
        if out[s, 0] == ref or not (_on_shoulder_set(out[s], K) and _beside(m, sgn, out[s], Td, K, mats)):
            keep = _kept(out, keep, s)
    return keep


@njit
def _beside(m, sgn, x, Td, K, mats):
    """Whether the exact ``x`` is a shadow of the continuum of axis 4 on axis 1 through ``m``
    (joint 4 turning by ``sgn``): within CONTINUUM_WINDOW of the continuum's point at its own q1
    and joined to it by an exact walk (:func:`_walked`)."""
    c = mats[_CW].reshape(16)[6:12]
    _turned(m, x[0], sgn, c)
    return (_far(c, x) < CONTINUUM_WINDOW and _turn_onto(m, x[0], sgn, c, Td, K, mats)
            and (_far(c, x) <= DUP_TOL or _walked(c, x, Td, K, mats)))


@njit
def _walked(a, b, Td, K, mats):
    """Whether a walk from the exact ``a`` to the exact ``b`` stays exact: its points WALK_STEP
    apart on the segment (WALK_MIN of them at least: a shorter walk would check nothing), each
    that misses the pose polished onto it by damped steps with the joint of the largest
    difference held (the walk's parameter), no joint moved from the walk's point before it by
    more than twice its own share of the difference (plus WALK_SLACK): a walk that keeps to one
    solution and jumps to the other at its last step is no walk. Where the FK is flat an exact valley may
    curve away from the straight segment (:func:`_joined`) between two of its points; a walk
    that jumps is not one valley."""
    w = mats[_WALK].reshape(16)
    x = w[:6]
    prev = w[6:12]
    far = 0.0
    j = 0
    for i in range(6):
        d = abs(wrap(b[i] - a[i]))
        if d > far:
            far = d
            j = i
    n = max(WALK_MIN, int(math.ceil(far / WALK_STEP)))
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
def _far(q0, q1):
    """The largest wrapped difference of joints 1..6 between ``q0`` and ``q1`` (rad): how two
    joint vectors are compared throughout (duplicates, the memo of starts, shadows)."""
    far = 0.0
    for i in range(6):
        far = max(far, abs(wrap(q0[i] - q1[i])))
    return far


@njit
def _theta5(q, K):
    """DH theta5 of ``q`` (user angles), wrapped to (-pi, pi]."""
    return wrap(dh_angle(q, K, 4))


@njit
def _bend(q, K):
    """abs(DH theta5) of ``q`` (user angles, wrapped)."""
    return abs(_theta5(q, K))


@njit
def _same_straight(q0, q1, K):
    """Whether ``q0`` and ``q1`` are one straight-wrist solution of the idealised model: one of
    them with theta5 within STRAIGHT_EXACT of 0, the other within DUP_TOL, the arm within
    DUP_TOL and the same ``s4 q4 + s7 q7`` (the only wrist angle defined there; the split is
    free). So a nearly straight solution within DUP_TOL (every joint) of a point of an exactly
    straight one's circle is that solution: where the FK is flat the circle has nearly straight
    shadows, e.g. the wrist's two bends +-3e-8 with q4 half a turn apart beside axis 7 on axis 1."""
    if K[L.DEVIATION] != 0.0:
        return False
    b0 = _bend(q0, K)
    if b0 > DUP_TOL:
        return False
    b1 = _bend(q1, K)
    if b1 > DUP_TOL or min(b0, b1) > STRAIGHT_EXACT:
        return False
    if abs(wrap(q0[4] - q1[4])) > DUP_TOL:
        return False
    for i in range(3):
        if abs(wrap(q0[i] - q1[i])) > DUP_TOL:
            return False
    s4 = K[L.SIGN + 3]
    s7 = K[L.SIGN + 6]
    return abs(wrap(s4 * (q0[3] - q1[3]) + s7 * (q0[5] - q1[5]))) <= DUP_TOL


@njit
def _kept(out, keep, s):
    """Keep row ``s`` of ``out`` as its row ``keep`` (the rows are compacted in order, ``keep``
    <= ``s``); returns the next row to keep."""
    if keep != s:
        for i in range(6):
            out[keep, i] = out[s, i]
    return keep + 1


@njit
def _drop_straight_shadows(out, count, k, K):
    """Drop from ``out[:count]`` the rows other than ``k`` that are one solution with the exactly
    straight ``out[k]`` (:func:`_same_straight`); returns the new count."""
    keep = 0
    for s in range(count):
        if s == k or not _same_straight(out[k], out[s], K):
            if s == k:
                k = keep
            keep = _kept(out, keep, s)
    return keep


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
def _accept(q, Td, K, out, count, mats, snap=False, follow=True):
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
    T = mats[_T]
    fk_user(q, K, T)
    dp, dr = residual(T, Td)
    if not (dp <= K[L.POS_TOL] and dr <= K[L.ROT_TOL]):  # (a NaN candidate is not exact)
        if not (dp < 1e300 and dr < 1e300):
            return count, False
        if K[L.DEVIATION] > 0.0:
            outcome = _MISSED if snap else _polish_deviating(q, dp, Td, K, follow, mats)
        else:
            outcome = _polish_exact(q, Td, K, out, count, snap)
        if outcome != _LANDED:
            return count, outcome == _KNOWN
    return _add(q, out, count, Td, K, mats), True


@njit
def _polish_deviating(q, dp, Td, K, follow, mats):
    """Polish the candidate ``q`` (position error ``dp``) onto the exact model of a robot that
    deviates from the idealised one, in place; returns _MISSED, _LANDED or _KNOWN (see
    :func:`_accept`). A start already followed in this pose gives the outcome it gave
    (:func:`_tried`: _KNOWN for a solution found then); one farther than START_REACH of the
    robot's size from meeting the pose is not followed; otherwise ``q`` is followed from the
    idealised model to the exact one (when ``follow``: a homotopy over HOMOTOPY_STEPS
    intermediate models) and polished by Newton, giving up after STALL_PATIENCE steps without
    progress."""
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
    exact = polish(q, Td, K, 30, False, STALL_PATIENCE)
    _remember(entry, exact, mats)
    return _LANDED if exact else _MISSED


@njit
def _polish_exact(q, Td, K, out, count, snap):
    """Polish the candidate ``q`` on an exact family member, in place; returns _MISSED, _LANDED
    or _KNOWN (see :func:`_accept`). Within DUP_TOL of a solution in ``out[:count]`` it is that
    solution (:func:`_known`), else Newton polishes it: by damped steps on the shoulder set when
    no solution found is within SINGULAR_ALONE (:func:`_on_shoulder_set`; not a snap)."""
    if _known(q, out, count, DUP_TOL):
        return _KNOWN  # the solution it would polish to is there (see _known)
    damped = not snap and _on_shoulder_set(q, K) and not _known(q, out, count, SINGULAR_ALONE)
    return _LANDED if polish(q, Td, K, 8, damped) else _MISSED


@njit
def _on_shoulder_set(q, K):
    """Whether the virtual wrist centre of ``q`` (user angles) lies within SHOULDER_NEAR of the
    robot's size from axis 1, for a robot without lateral offset: the shoulder singular set,
    where the arm leaves theta1 free (its distance in the arm plane, ``a1`` plus the reach of
    joints 2 and 3 to the centre at ``d4 + d(theta5)`` along axis 4)."""
    if K[L.B] != 0.0:
        return False
    x = K[L.SB] * math.sin(0.5 * _bend(q, K))
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
    :func:`_accept`) among those tried in this pose: a start within MEMO_TOL (rad, every joint)
    of one tried with the same ``follow`` lands where that one did (the polish is deterministic
    and continuous in its start). Returns (entry, outcome): the outcome of the start tried (1
    exact, 0 not), or -1 and a new entry holding ``q`` (the oldest one when the ring of
    MEMO_SIZE is full), whose outcome the caller records with :func:`_remember`."""
    n = int(mats[_MEMO_N, 0, 0])
    fl = 1.0 if follow else 0.0
    for k in range(min(n, MEMO_SIZE)):
        e = mats[_MEMO + k // 2].reshape(16)[8 * (k % 2):8 * (k % 2) + 8]
        if e[6] != fl or e[7] < 0.0:
            continue
        if _far(e, q) <= MEMO_TOL:
            return k, e[7]
    k = n % MEMO_SIZE
    e = mats[_MEMO + k // 2].reshape(16)[8 * (k % 2):8 * (k % 2) + 8]
    for i in range(6):
        e[i] = q[i]
    e[6] = fl
    e[7] = -1.0
    mats[_MEMO_N, 0, 0] = n + 1
    return k, -1.0


@njit
def _remember(k, exact, mats):
    """Record the outcome of the start in memo entry ``k`` (see :func:`_tried`)."""
    mats[_MEMO + k // 2].reshape(16)[8 * (k % 2) + 7] = 1.0 if exact else 0.0


@njit
def _known(q, out, count, radius):
    """Whether the candidate ``q`` is within ``radius`` (every joint) of a solution in
    ``out[:count]``. With DUP_TOL: it is that solution (two solutions that close are one), so
    polishing it, which on the flat forward kinematics of a singular arm or wrist takes all of
    Newton's steps, would only find it again. (Not for models that deviate from the idealised
    one, whose candidates are followed to the exact model one by one.) With SINGULAR_ALONE:
    see :func:`_accept`."""
    for k in range(count):
        if _far(out[k], q) <= radius:
            return True
    return False


@njit
def _arm_from_psi(d, rho, cp, sp, pz, c1, s1, K, th):
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
def _filter_margin(K):
    """FILTER_MARGIN, or FILTER_MARGIN_DEVIATING for a model that deviates from the idealised one."""
    return FILTER_MARGIN if K[L.DEVIATION] == 0.0 else FILTER_MARGIN_DEVIATING


@njit
def _may_match(i, c, s, indicator, margin, K):
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
    """DH theta_(i+1) from its cosine and sine in ``th`` (see :func:`_arm_from_psi`)."""
    return math.atan2(th[3 + i], th[i])


@njit
def _arm_may_match(th, filt, margin, K):
    """Whether the arm of ``th`` (DH cosines and sines of theta1..3, see :func:`_arm_from_psi`)
    may have the Arm and Elbow indicators of ``filt`` (see :func:`solve_config`) once polished."""
    return (_may_match(0, th[0], th[3], filt >> 2, margin, K)
            and _may_match(2, th[2], th[5], (filt >> 1) & 1, margin, K))


@njit
def _arm_frame(th, R07, K, ws, mats):
    """The arm of ``th`` (DH cosines and sines of theta1..3) made into frame 3 (``mats[_M]``),
    the wrist's target rotation for the flange ``R07`` (``mats[_Q]``, 3 x 3) and the arm's user
    angles (``q1..q3`` of ``ws[_Q6:_Q6 + 6]``)."""
    _arm_target(th, R07, K, mats[_M], mats[_Q, :3, :3])
    q = ws[_Q6:_Q6 + 6]
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
def _other_wrist(q, R07, K, th, M, Q, W, qq):
    """Make ``qq`` the arm of ``q`` (user joints 1 to 3) with the other wrist for the flange
    ``R07``: DH theta5 of the other sign, theta4 (the nearest to ``q``'s) and theta7 from the
    arm's wrist target. On the idealised model each arm comes with both; on a deviating one the
    exact solution lies about the deviation from it. ``th`` (6,), ``M`` (4, 4), ``Q`` and ``W``
    (3, 3) are work arrays."""
    for i in range(3):
        t = dh_angle(q, K, i)
        th[i] = math.cos(t)
        th[3 + i] = math.sin(t)
    _arm_target(th, R07, K, M, Q)
    t5 = -_theta5(q, K)
    t4, t7 = wrist_ik_cs(Q, math.cos(t5), math.sin(t5), K[L.SIGN + 3] * q[3] + K[L.THETA_OFFSET4], K, W)
    _completed(q, t4, t5, t7, K, qq)


@njit
def _wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Complete DH theta1..3 with the wrist bent by ``t5`` >= 0 (its cosine ``c5`` and sine
    ``s5``); accept every exact solution (with ``filt`` >= 0, only those that may have its
    indicators: see :func:`solve_config`)."""
    margin = _filter_margin(K)
    if filt >= 0 and not _arm_may_match(th, filt, margin, K):
        return count
    _arm_frame(th, R07, K, ws, mats)
    Q = mats[_Q, :3, :3]
    q = ws[_Q6:_Q6 + 6]
    qq = ws[_QQ:_QQ + 6]  # q completed with a wrist solution
    if K[L.DEVIATION] > 0.0 and t5 < STRAIGHT_SHOULDER:
        shoulder = _near_shoulder(th, K)
        window = STRAIGHT_SHOULDER if shoulder else STRAIGHT_DEVIATING
        # (the bend of the arm's own target: a root clamped to the end of the range is not enough)
        if t5 < window and theta5_of_bend(Q, K) < window:
            count = _straight_family(q, Q, Td, K, out, count, ws, mats, shoulder)
    t4_hint = K[L.SIGN + 3] * hint[3] + K[L.THETA_OFFSET4]
    if t5 < FOLD_WINDOW:
        # straight wrist: one member of the theta4 + theta7 family
        for i in range(6):
            qq[i] = q[i]
        qq[4] = user_angle(4, 0.0, K)
        _straight_split(qq, Q, K, hint, has_hint)
        count, exact = _accept(qq, Td, K, out, count, mats, True)
        if exact:
            return count
        if K[L.DEVIATION] == 0.0:
            for i in range(6):  # (the snap again: _accept's failed polish moved it)
                qq[i] = q[i]
            qq[4] = user_angle(4, 0.0, K)
            _straight_split(qq, Q, K, hint, has_hint)
            if _on_shoulder_set(qq, K) and _straight_damped(qq, Td, K, hint, has_hint, mats):
                count, exact = _accept(qq, Td, K, out, count, mats, True)
                if exact:
                    return count
        # nearly straight: theta5 from the bend itself (d is flat in theta5 at zero)
        t5 = theta5_of_bend(Q, K)
        if t5 == 0.0:
            return count
        c5, s5 = math.cos(t5), math.sin(t5)
    if math.pi - t5 < _fold_snap(K):
        # fully bent wrist: the two wrist solutions merge into one, at theta5 = pi exactly
        count, exact = _accept(_with_wrist(q, Q, math.pi, -1.0, 0.0, t4_hint, K, mats, qq), Td,
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
        count, _ = _accept(_with_wrist(q, Q, sgn * t5, c5, sgn * s5, t4_hint, K, mats, qq), Td,
                           K, out, count, mats)
        if t5_alt > 0.0:  # (both signs polish from one singular point: also start off it)
            alt = sgn * t5_alt
            count, _ = _accept(_with_wrist(q, Q, alt, math.cos(alt), math.sin(alt), t4_hint, K,
                                           mats, qq), Td, K, out, count, mats, False, False)
    return count


@njit
def _with_wrist(q, Q, t5, c5, s5, t4_hint, K, mats, qq):
    """``qq``: a copy of ``q`` (arm joints set) completed with the wrist for DH angle ``t5``
    (cosine ``c5``, sine ``s5``)."""
    t4, t7 = wrist_ik_cs(Q, c5, s5, t4_hint, K, mats[_WR, :3, :3])
    _completed(q, t4, t5, t7, K, qq)
    return qq


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
def _solutions_at(d, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Every exact solution whose virtual offset is the root ``d``."""
    t = K[L.D7] + d
    px = p[0] - t * a[0]
    py = p[1] - t * a[1]
    pz = p[2] - t * a[2]
    r2 = px * px + py * py
    b = K[L.B]
    scale = K[L.SCALE]
    psi = mats[_PSI]
    th = ws[_TH:_TH + 6]
    t5, c5, s5 = theta5_cs_of_d(d, K)
    if r2 <= (1e-9 * scale) ** 2 and b == 0.0:
        # P' on axis 1 (shoulder singularity): psi from the elbow condition alone, theta1 from
        # the bend condition u . a = eps3 (sin psi (c1 ax + s1 ay) - eps1 cos psi az)
        kw = K[L.KW]
        cphi = 2.0 * kw * kw / (d * d) - 1.0
        axy = math.hypot(a[0], a[1])
        t1h = K[L.SIGN] * hint[0] + K[L.THETA_OFFSET1]
        a11, a12, m, a21, a22, c = linear_system(d, 0.0, p, a, K)
        for k in range(_psi_candidates(a11, a12, m, 0.0, 0.0, 0.0, psi)):
            cp = psi[k, 0]
            sp = psi[k, 1]
            if abs(sp) * axy < 1e-12:
                _arm_from_psi(d, 0.0, cp, sp, pz, math.cos(t1h), math.sin(t1h), K, th)
                count = _wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                          mats)
                continue
            target = (cphi * K[L.EPS3] + K[L.EPS1] * cp * a[2]) / (sp * axy)
            if abs(target) > 1.0 + 1e-9:
                continue
            base = math.atan2(a[1], a[0])
            dev = math.acos(max(-1.0, min(1.0, target)))
            for sg in (1.0, -1.0):
                t1 = base + sg * dev
                _arm_from_psi(d, 0.0, cp, sp, pz, math.cos(t1), math.sin(t1), K, th)
                count = _wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                          mats)
        return count
    s2 = r2 - b * b
    if s2 < -(1e-9 * scale) ** 2:
        return count
    s = math.sqrt(max(s2, 0.0))
    bp = -K[L.EPS1] * b
    margin = _filter_margin(K)
    for sgn in (1.0, -1.0):
        rho = sgn * s
        x1 = rho * px + bp * py  # theta1 = atan2(y1, x1)
        y1 = rho * py - bp * px
        n1 = math.sqrt(x1 * x1 + y1 * y1)
        c1, s1 = (x1 / n1, y1 / n1) if n1 > 0.0 else (1.0, 0.0)
        if filt >= 0 and not _may_match(0, c1, s1, filt >> 2, margin, K):
            if s == 0.0:
                break
            continue  # this shoulder branch clearly has the other arm indicator
        a11, a12, m, a21, a22, c = linear_system(d, rho, p, a, K)
        n = _psi_candidates(a11, a12, m, a21, a22, c, psi, 1e-4 if K[L.DEVIATION] == 0.0 else 2e-2)
        for k in range(n):
            _arm_from_psi(d, rho, psi[k, 0], psi[k, 1], pz, c1, s1, K, th)
            count = _wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                      mats)
        if s == 0.0:
            break
    return count


@njit
def _bend_centre(t5, p, a, K, t1_hint=0.0, in_plane=False):
    """The virtual centre of the wrist bent by ``t5`` >= 0 (as :func:`_bend_gap` takes it, with
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
def _bend_gap(t5, p, a, front, elbow, K, th, t1_hint=0.0, in_plane=False, slack=1e-12):
    """The bend gap at wrist angle ``t5`` >= 0 on the arm branch (``front``, ``elbow``: +-1):
    the angle between axis 4 of the arm that places the virtual centre of that bend and the
    tool's approach ``a``, minus the wrist's bend ``phi(t5)``; zero exactly at solutions.
    Unlike the residual polynomial it is computed from t5 itself, with angles from atan2: it
    stays accurate (to rounding of the angles) where d is flat in t5 (straight or fully bent
    wrist) and where two roots of the polynomial merge within its rounding. Writes the arm's
    DH cosines and sines into ``th`` (as :func:`_arm_from_psi`). Returns (gap, ok); ok is False
    where the branch does not reach. ``t1_hint``: theta1 when the virtual centre is on axis 1;
    ``th[6]`` gets t5. ``in_plane``: theta1 is ``t1_hint`` (the virtual centre is taken in
    that arm plane: near axis 1 its direction from the axis is rounding noise). ``slack``:
    how far the arm may miss the centre (:func:`ik7r._kernels.arm.arm_ik`; the arm's cosines and
    sines come from :func:`ik7r._kernels.arm.arm_cs`, without a trigonometric call)."""
    x, d, px, py, pz, ok = _bend_centre(t5, p, a, K, t1_hint, in_plane)
    if not ok:
        return 0.0, False  # the fold of a 45 deg twist: the virtual centre is at infinity
    c1, s1, c2, s2, c3, s3, ok = arm_cs(px, py, pz, K[L.D4] + d, front, elbow, t1_hint, K, slack)
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
def _shoulder_gap(t1, p, a, elbow, K, th, slack=1e-12):
    """The bend gap as a function of theta1 (DH) on the elbow branch ``elbow`` (+-1), for a robot
    without lateral offset: the virtual centre is where the line ``p - t a`` meets the arm's
    plane at theta1, which fixes d and so theta5. Near the shoulder singular set (that line
    passes close to axis 1) theta1 swings fast with d, and the residual polynomial's roots
    there merge within its rounding; in theta1 they stay apart. Returns (gap, ok); ``slack`` as
    :func:`_bend_gap` takes it."""
    t5, front, ok = _shoulder_bend(t1, p, a, K)
    if not ok:
        return 0.0, False
    return _bend_gap(t5, p, a, front, elbow, K, th, t1, True, slack)


@njit
def _shoulder_bend(t1, p, a, K):
    """The wrist angle and shoulder branch :func:`_shoulder_gap` takes at theta1 = ``t1``:
    (t5, front, ok); ok is False where the arm's plane misses the line of virtual centres in
    the range of d."""
    c1 = math.cos(t1)
    s1 = math.sin(t1)
    an = -s1 * a[0] + c1 * a[1]
    if abs(an) < 1e-12:
        return 0.0, 0.0, False
    d = (-s1 * p[0] + c1 * p[1]) / an - K[L.D7]
    if not (K[L.DMIN] <= d <= K[L.DMAX]):
        if K[L.DEVIATION] == 0.0 or not _d_near_range(d, K):
            return 0.0, 0.0, False
        d = min(K[L.DMAX], max(K[L.DMIN], d))
    t5 = theta5_cs_of_d(d, K)[0]
    t = K[L.D7] + d
    rho = c1 * (p[0] - t * a[0]) + s1 * (p[1] - t * a[1])
    return t5, 1.0 if rho >= 0.0 else -1.0, True


@njit
def _gap_reaches(t, p, a, front, elbow, K, th):
    """Whether the arm branch of :func:`_gap` reaches at ``t`` (its ``ok``, the same to the last
    bit), at a fraction of its cost for the bend gaps (no angle of the arm, no gap): the
    bisections for the ends of arm branches in :func:`_scan_piece` ask only this."""
    if abs(front) == 2.0 or front == 3.0:
        return _gap(t, p, a, front, elbow, K, th)[1]
    t5, t1, in_plane = t, 0.0, front == 0.0
    if in_plane:
        t1 = t
        t5, front, ok = _shoulder_bend(t1, p, a, K)
        if not ok:
            return False
    x, d, px, py, pz, ok = _bend_centre(t5, p, a, K, t1, in_plane)
    return ok and arm_reach(px, py, pz, K[L.D4] + d, front, t1, K)[4]


@njit
def _gap(t, p, a, front, elbow, K, th):
    """The bend gap of :func:`_bend_gap` at theta5 = ``t`` on the branch (front, elbow), with
    ``front`` 0 that of :func:`_shoulder_gap` at theta1 = ``t`` on the elbow branch, with
    ``front`` +-2 the fold gap of :func:`_fold_gap` at ``sw = t`` on the branch (front / 2, elbow),
    with ``front`` 3 that of :func:`_fold_axis_gap` at theta1 = ``t``."""
    if abs(front) == 2.0:
        return _fold_gap(t, p, a, 0.5 * front, elbow, K, th)
    if front == 3.0:
        return _fold_axis_gap(t, p, a, elbow, K, th)
    if front != 0.0:
        return _bend_gap(t, p, a, front, elbow, K, th)
    return _shoulder_gap(t, p, a, elbow, K, th)


@njit
def _gap_root(t0, t1, g0, g1, p, a, front, elbow, K, th):
    """The root of the bend gap bracketed by [t0, t1] (``g0``, ``g1`` of opposite signs): the
    Illinois steps of :func:`ik7r._kernels.poly.illinois_step`, to the last bits."""
    side = 0
    for _ in range(200):
        t = secant_point(t0, t1, g0, g1)
        g, ok = _gap(t, p, a, front, elbow, K, th)
        if not ok or g == 0.0:
            return t
        t0, t1, g0, g1, side, done = illinois_step(t0, t1, g0, g1, side, t, g)
        if done:
            break
    return t0 if abs(g0) < abs(g1) else t1


@njit
def _gap_min(t0, t1, p, a, front, elbow, K, th, floor=0.0):
    """The least |bend gap| in [t0, t1] (Brent's minimiser); (t, |gap|, gap, ok) with the gap
    and its ``ok`` at t (|gap| is inf where not ok). ``floor`` > 0: stop once the bracket is
    below DIP_EARLY of [t0, t1] with the least |gap| so far at or above ``floor`` (the minimum
    is then only known to be about that high). (The value at the least point is kept from the
    search, not evaluated again; ``th`` holds the arm of the last point evaluated.)"""
    st, t = brent_start(t0, t1)
    early = DIP_EARLY * (t1 - t0)
    fx = 0.0
    okx = False
    for _ in range(200):
        f, ok = _gap(t, p, a, front, elbow, K, th)
        st = brent_take(st, t, abs(f) if ok else np.inf)
        if st[2] == t:
            fx, okx = f, ok
        if floor > 0.0 and st[1] - st[0] < early and st[5] >= floor:
            break
        st, t, done = brent_next(st)
        if done:
            break
    return st[2], abs(fx) if okx else np.inf, fx, okx


@njit
def _scan_theta5(ta, tb, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats, front1=1.0,
                 cells=SCAN_GRID):
    """Every solution with theta5 in [ta, tb] (an interval the residual polynomial left
    undecided: its values there are within their rounding of zero), from the bend gap of each
    of the four arm branches (:func:`_bend_gap`) on a grid: sign changes refined to the last
    bits, dips of |gap| (tangential roots, or two roots in one cell) refined by Brent's minimiser
    and split at the dip. Where a branch ends inside a cell (the elbow stretches) the end is
    found by bisection and the piece between it and the grid is scanned on a grid of its own.
    Each candidate is completed with the wrist and verified on the forward kinematics.
    ``front1`` 2: the same scan of the fold gap (:func:`_scan_fold`). ``cells``: the first grid's
    (the pieces it adds have SCAN_GRID)."""
    sub = ws[_SUB:_SUB + 2 * SCAN_PIECES]
    paired = abs(front1) == 2.0 and not _tiny_piece(ta, tb)
    for front in (front1, -front1):
        if paired:
            # the fold gap's two elbow branches share most of their arm: their first grids at once
            th = ws[_TH:_TH + _NTH]
            for i in range(cells + 1):
                gp, okp, gm, okm = _fold_gap_pair(ta + (tb - ta) * i / cells, p, a, 0.5 * front, K, th)
                ws[_PAIR + i] = gp if okp else np.nan
                ws[_PAIR + SCAN_GRID + 1 + i] = gm if okm else np.nan
        for elbow in (1.0, -1.0):
            sub[0] = ta
            sub[1] = tb
            npieces = 1
            j = 0
            while j < npieces:
                t0 = sub[2 * j]
                t1 = sub[2 * j + 1]
                given = (0 if elbow > 0.0 else 1) if paired and j == 0 else -1
                count, npieces = _scan_piece(t0, t1, sub, npieces, front, elbow, p, a, R07,
                                             Td, K, hint, has_hint, out, count, filt, ws, mats,
                                             cells if j == 0 else SCAN_GRID, given)
                j += 1
    return count


@njit
def _gap_near_misses(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Extra candidates for a model that deviates from the idealised one: the near misses of
    each of the four arm branches' bend gaps (:func:`_bend_gap`) over the whole theta5 range.
    A tangency of one branch's gap that the deviation turns into a pair of exact solutions is a
    near miss of one factor of the residual polynomial, but the factor of one shoulder branch
    is the product over its two elbow branches, and where the other elbow branch has a simple
    root less than a cell away the factor changes sign and shows no minimum (:func:`_near_misses`
    looks no deeper than the shoulder branches). Over theta5 in [0, pi] (up to the fold span
    where the fully bent wrist is nearly folded back), each grid minimum of ``|gap|`` below
    GAP_NEAR_GRID (rad) whose cells keep one sign is refined by Brent's minimiser (every one: beside
    the elbow stretch a dip is a V that no parabola through three grid values shows) and, when it
    comes below GAP_NEAR_DEPTH without crossing zero, completed with the wrist and polished
    on the exact model (its partner: :func:`_partners`). Next to an end of the branch (the elbow
    stretched), a grid point below GAP_NEAR_END whose ``|gap|`` falls toward the end has no
    defined neighbour there: the end is bisected for (:func:`_branch_end`) and the part between it
    and the point minimised the same way. Sign changes are the polynomial's."""
    m = GAP_NEAR_CELLS
    gs = ws[_SCAN:_SCAN + m + 1]
    th = ws[_TH:_TH + _NTH]
    top = math.pi
    if _u_fold(K) < FOLD_NEAR:  # (the fold span is the fold gap's: see :func:`_scan_fold`)
        top = theta5_cs_of_u(_u_fold(K) + FOLD_SPAN, K)[0]
    for front in (1.0, -1.0):
        for elbow in (1.0, -1.0):
            for i in range(m + 1):
                g, ok = _bend_gap(top * i / m, p, a, front, elbow, K, th)
                gs[i] = g if ok else np.nan
            for i in range(m + 1):
                # (at an end of the range, the straight or fully bent wrist, the one neighbour
                # is taken twice: a minimum there is refined over its one cell)
                g0, g1, g2 = gs[max(i - 1, 1 - i)], gs[i], gs[min(i + 1, 2 * m - 1 - i)]
                if (0 < i < m and abs(g1) < GAP_NEAR_END
                        and math.isfinite(g0) != math.isfinite(g2)):
                    # the branch ends in the cell beside: a near miss between the end and this
                    # point (the elbow nearly stretched) has no grid point of its own
                    out_i = i - 1 if math.isfinite(g2) else i + 1
                    g_in = g2 if math.isfinite(g2) else g0
                    if g1 * g_in > 0.0 and abs(g1) <= abs(g_in):
                        t_e = _branch_end(top * i / m, top * out_i / m, p, a, front, elbow, K, th)
                        tm, fm, gm, okm = _gap_min(min(t_e, top * i / m), max(t_e, top * i / m),
                                                   p, a, front, elbow, K, th)
                        if okm and fm < GAP_NEAR_DEPTH and gm * g1 > 0.0:
                            count = _gap_candidate(tm, p, a, front, elbow, R07, Td, K, hint,
                                                   has_hint, out, count, filt, ws, mats)
                    continue
                if not (abs(g1) < GAP_NEAR_GRID and g0 * g1 > 0.0 and g1 * g2 > 0.0
                        and abs(g1) <= abs(g0) and abs(g1) <= abs(g2)):
                    continue  # (NaN, a branch end, fails the comparisons)
                tm, fm, gm, okm = _gap_min(top * max(i - 1, 0) / m, top * min(i + 1, m) / m, p,
                                           a, front, elbow, K, th)
                if okm and fm < GAP_NEAR_DEPTH and gm * g1 > 0.0:
                    count = _gap_candidate(tm, p, a, front, elbow, R07, Td, K, hint, has_hint, out,
                                           count, filt, ws, mats)
    return count


@njit
def _branch_end(t_in, t_out, p, a, front, elbow, K, th):
    """The end of the arm branch (``front``, ``elbow``) between ``t_in``, where its gap is
    defined, and ``t_out``, where it is not: bisection to the last bit (:func:`_gap_reaches`);
    returns the last point found on the defined side."""
    for _ in range(60):
        tm = 0.5 * (t_in + t_out)
        if tm == t_in or tm == t_out:
            break
        if _gap_reaches(tm, p, a, front, elbow, K, th):
            t_in = tm
        else:
            t_out = tm
    return t_in


@njit
def _tiny_piece(ta, tb):
    """Whether [ta, tb] is narrower than SCAN_TINY (relative to 1 + |ta|): not gridded."""
    return tb - ta <= SCAN_TINY * (1.0 + abs(ta))


@njit
def _scan_piece(ta, tb, sub, npieces, front, elbow, p, a, R07, Td, K, hint, has_hint, out,
                count, filt, ws, mats, cells=SCAN_GRID, given=-1):
    """One grid of :func:`_scan_theta5` over [ta, tb] on one arm branch; the pieces next to
    branch ends and around dips it finds are appended to ``sub`` (while there is room: a piece
    is two cells of the one that found it, so they nest). In the fold scan of a deviating model
    a branch's end is itself a candidate (see FOLD_END_NEAR). ``cells``: the grid's (at most
    SCAN_GRID). ``given`` >= 0: the grid's values are row ``given`` of the work block _PAIR
    (:func:`_scan_theta5` evaluated them, both elbows at once). Returns (count, npieces)."""
    m = cells
    gs = ws[_SCAN:_SCAN + m + 1]
    th = ws[_TH:_TH + _NTH]
    near = SCAN_NEAR if K[L.DEVIATION] == 0.0 else SCAN_NEAR_DEVIATING
    if _tiny_piece(ta, tb):
        # a piece this narrow (an undecided bracket of the polynomial at its width limit) holds
        # roots within SCAN_TINY of each other, which its grid would not tell apart from rounding
        # (every grid point could look like a dip): its sign change, else its least |gap|
        g0, ok0 = _gap(ta, p, a, front, elbow, K, th)
        g1, ok1 = _gap(tb, p, a, front, elbow, K, th)
        if ok0 and ok1 and g0 * g1 < 0.0:
            t = _gap_root(ta, tb, g0, g1, p, a, front, elbow, K, th)
        else:
            t, fm, _, _ = _gap_min(ta, tb, p, a, front, elbow, K, th)
            if not fm < near:
                return count, npieces
        return _gap_candidate(t, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count, filt,
                              ws, mats), npieces
    for i in range(m + 1):
        if given >= 0:
            gs[i] = ws[_PAIR + given * (SCAN_GRID + 1) + i]
        else:
            g, ok = _gap(ta + (tb - ta) * i / m, p, a, front, elbow, K, th)
            gs[i] = g if ok else np.nan
    for i in range(m + 1):
        gi = gs[i]
        ti = ta + (tb - ta) * i / m
        if i < m and math.isfinite(gi) != math.isfinite(gs[i + 1]) and npieces < SCAN_PIECES:
            # the branch ends in this cell: bisect for the end, then scan the defined part
            t_in = _branch_end(ti if math.isfinite(gi) else ta + (tb - ta) * (i + 1) / m,
                               ta + (tb - ta) * (i + 1) / m if math.isfinite(gi) else ti,
                               p, a, front, elbow, K, th)
            edge = ti if math.isfinite(gi) else ta + (tb - ta) * (i + 1) / m
            if abs(front) == 2.0 and K[L.DEVIATION] > 0.0:
                g_end, ok_end = _gap(t_in, p, a, front, elbow, K, th)
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
            t = _gap_root(ti, ta + (tb - ta) * (i + 1) / m, gi, gs[i + 1], p, a, front, elbow, K, th)
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
            tm, fm, gm, okm = _gap_min(t_lo, t_hi, p, a, front, elbow, K, th,
                                       DIP_FLOOR if front != 0.0 and front != 3.0 else 0.0)
            if okm and gm * gi < 0.0:
                for t_end, g_end in ((t_lo, gs[lo_i]), (t_hi, gs[hi_i])):
                    if math.isfinite(g_end) and g_end * gm < 0.0:
                        tr = _gap_root(min(t_end, tm), max(t_end, tm), g_end if t_end < tm else gm,
                                       gm if t_end < tm else g_end, p, a, front, elbow, K, th)
                        count = _gap_candidate(tr, p, a, front, elbow, R07, Td, K, hint, has_hint,
                                               out, count, filt, ws, mats)
            if fm < near:  # (also when split: at a tangency the bottom itself is the root)
                t = tm
                have = True
            if (front == 0.0 and K[L.DEVIATION] > 0.0 and fm < SHOULDER_DIP and ta == sub[0]
                    and tb == sub[1]):
                count = _shoulder_exact(tm, elbow, p, a, R07, Td, K, hint, out, count, ws, mats)
            nest = SCAN_NEST_FOLD_AXIS if front == 3.0 else SCAN_NEST
            if fm < near and npieces < SCAN_PIECES and t_hi - t_lo >= nest * (sub[1] - sub[0]):
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
def _scan_shoulder(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Near the shoulder singular set (no lateral offset; the line of virtual centres
    ``p - t a`` passes within SHOULDER_NEAR of the robot's size from axis 1, at a d in range;
    on a deviating model within SHOULDER_SCAN_DEVIATING, see :func:`_shoulder_offset`):
    every solution from the bend gap in theta1 (:func:`_shoulder_gap`) on a grid over the whole
    turn, both elbow branches."""
    if K[L.B] != 0.0:
        return count
    if a[0] * a[0] + a[1] * a[1] < 1e-24:
        return count  # a along axis 1: P' is at one distance from it for every d
    t, r = _line_to_axis1(p, a)
    if K[L.DEVIATION] == 0.0:
        if r > SHOULDER_NEAR * K[L.SCALE]:
            return count
    elif _shoulder_offset(p, a, K) > SHOULDER_SCAN_DEVIATING:
        return count
    d = t - K[L.D7]
    if not _d_near_range(d, K):
        return count
    return _scan_turn(0.0, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)


@njit
def _scan_turn(front, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Every root of a gap in theta1 (``front`` 0: :func:`_shoulder_gap`, 3: :func:`_fold_axis_gap`)
    on a grid over the whole turn (:func:`_scan_piece`, nested pieces), both elbow branches.

    Where a deviating model's line of virtual centres passes within SHOULDER_EXACT_NEAR of axis
    1 (``turn``) the exact model is tracked over the whole turn (:func:`_shoulder_turn`) and only
    the nominal gap's first grid is scanned: its roots and dips start the dip-centred scans of
    :func:`_shoulder_exact`, while the nested pieces would refine nominal roots whose exact
    solutions those scans find anyway (the same solution sets over 12,000 near-shoulder poses
    of four deviating robots without them; they were 600 of such a pose's 830 gap values)."""
    sub = ws[_SUB:_SUB + 2 * SCAN_PIECES]
    turn = front == 0.0 and _turn_scanned(p, a, K)
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
def _turn_scanned(p, a, K):
    """Whether :func:`_scan_shoulder` tracks the exact model over the whole turn of q1 for the
    line of virtual centres ``p - t a`` (:func:`_shoulder_turn`)."""
    if K[L.B] != 0.0 or K[L.DEVIATION] == 0.0 or a[0] * a[0] + a[1] * a[1] < 1e-24:
        return False
    t, _ = _line_to_axis1(p, a)
    d = t - K[L.D7]
    return _d_near_range(d, K) and _shoulder_offset(p, a, K) <= SHOULDER_EXACT_NEAR


@njit
def _d_near_range(d, K):
    """Whether ``d`` is within 2 % of the robot's range of d (the shoulder scans' window: a
    deviating model's solutions there may come from a nominal d just beyond the range)."""
    return 0.98 * K[L.DMIN] <= d <= 1.02 * K[L.DMAX]


@njit
def _line_to_axis1(p, a):
    """The line of virtual centres ``p - t a`` (``a`` not along axis 1) at its closest to axis 1:
    (t there, the distance)."""
    axy2 = a[0] * a[0] + a[1] * a[1]
    t = (p[0] * a[0] + p[1] * a[1]) / axy2
    rx = p[0] - t * a[0]
    ry = p[1] - t * a[1]
    return t, math.sqrt(rx * rx + ry * ry)


@njit
def _shoulder_offset(p, a, K):
    """The line of virtual centres' distance from axis 1 (``a`` not along it) relative to the
    larger of the robot's size and the distance d of its closest point from the wrist: how far
    a deviating model's virtual centre moves is the deviation's lengths plus d times its angles,
    and near the fully bent wrist of a 45 deg twist d reaches 1,000 sizes and more."""
    t, r = _line_to_axis1(p, a)
    return r / max(K[L.SCALE], abs(t - K[L.D7]))


@njit
def _shoulder_turn(elbow, p, a, R07, Td, K, hint, out, count, ws, mats):
    """Where the line of virtual centres passes within SHOULDER_EXACT_NEAR of axis 1
    (:func:`_shoulder_offset`), on a model that deviates from the idealised one: every exact
    solution on the elbow branch ``elbow`` over the whole turn of q1. There the deviation moves the virtual
    centre by as much as its distance from axis 1 or more, so the exact solutions lie anywhere
    in theta1, not only near the nominal gap's dips (an IRB 5400 pose with the line 1.1e-5 of
    the size from axis 1 has one 1.2 rad from the nearest dip). The exact model's reduced
    residual in q1 (:func:`_reduced_at`) is tracked over the turn on REDUCED_GRID cells, one
    closed curve per wrist sign, from the nominal arm and wrist at the first grid point the
    branch reaches, or where none does, from the nearest arm of the first that misses by less
    than SHOULDER_TURN_SLACK; the dip-centred scans of :func:`_shoulder_exact` (finer,
    SHOULDER_REACH each way) still resolve the close pairs beside the dips."""
    th = ws[_TH:_TH + _NTH]
    ok = False
    for slack in (1e-12, SHOULDER_TURN_SLACK):
        for k in range(REDUCED_GRID):
            t1 = K[L.SIGN] * (-math.pi + TWO_PI * k / REDUCED_GRID) + K[L.THETA_OFFSET1]
            _, ok = _shoulder_gap(t1, p, a, elbow, K, th, slack)
            if ok:
                break
        if ok:
            break
    if not ok:
        return count
    _arm_frame(th, R07, K, ws, mats)
    return _q1_scans(th, TWO_PI, 0.0, REDUCED_GRID, Td, K, hint, out, count, ws, mats)


@njit
def _q1_scans(th, span_a, span_b, cells, Td, K, hint, out, count, ws, mats):
    """The exact model's reduced residual in q1 (:func:`_reduced_scan`) tracked from the
    nominal arm of ``th`` (made into ``ws`` and ``mats`` by :func:`_arm_frame`) with its wrist of
    either sign, from its q1 over ``span_a`` and then ``span_b`` (rad, user q1; 0: no scan), on
    ``cells`` cells each."""
    Q = mats[_Q, :3, :3]
    q = ws[_Q6:_Q6 + 6]
    qq = ws[_QQ:_QQ + 6]
    t5 = max(th[6], SHOULDER_TURN_BEND)
    t4_hint = K[L.SIGN + 3] * hint[3] + K[L.THETA_OFFSET4]
    v0 = q[0]
    for sgn in (1.0, -1.0):
        for span in (span_a, span_b):
            if span == 0.0:
                continue
            # (the start into qq: _reduced_scan reads it once, before it adds anything)
            _with_wrist(q, Q, sgn * t5, math.cos(t5), sgn * math.sin(t5), t4_hint, K, mats, qq)
            count = _reduced_scan(qq, 0, v0, v0 + span, cells, Td, K, out, count, ws, mats)
    return count


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
    SHOULDER_REACH either way (:func:`_reduced_scan`). Only where the line of virtual
    centres passes within SHOULDER_EXACT_FAR of axis 1 (:func:`_shoulder_offset`), beyond
    SHOULDER_EXACT_NEAR with the reach shrinking as its distance grows: further out the
    nominal candidates and their polish find these solutions (within SHOULDER_EXACT_NEAR the
    whole turn is scanned as well: :func:`_shoulder_turn`)."""
    r = _shoulder_offset(p, a, K)  # (a is not along axis 1: _scan_shoulder checked)
    if r > SHOULDER_EXACT_FAR:
        return count
    if _dip_scanned(t1, elbow, ws):
        return count
    reach = SHOULDER_REACH if r <= SHOULDER_EXACT_NEAR else SHOULDER_REACH * SHOULDER_EXACT_NEAR / r
    cells = max(2, int(math.ceil(SHOULDER_CELLS * reach / SHOULDER_REACH)))
    th = ws[_TH:_TH + _NTH]
    _, ok = _shoulder_gap(t1, p, a, elbow, K, th)
    if not ok:
        return count
    _arm_frame(th, R07, K, ws, mats)
    q1 = ws[_Q6]
    return _q1_scans(th, wrap(user_angle(0, t1 - reach, K) - q1), wrap(user_angle(0, t1 + reach, K) - q1),
                     cells, Td, K, hint, out, count, ws, mats)


@njit
def _dip_scanned(t1, elbow, ws):
    """Whether :func:`_shoulder_exact` has scanned the dip at theta1 = ``t1`` (DH) on the elbow
    branch ``elbow`` in this pose already (within SHOULDER_DIP_SAME); if not, it is remembered
    (while there is room for it: SHOULDER_DIPS)."""
    n = int(ws[_NSDIP])
    for k in range(n):
        if ws[_SDIP + 2 * k + 1] == elbow and abs(wrap(t1 - ws[_SDIP + 2 * k])) < SHOULDER_DIP_SAME:
            return True
    if n < SHOULDER_DIPS:
        ws[_SDIP + 2 * n] = t1
        ws[_SDIP + 2 * n + 1] = elbow
        ws[_NSDIP] = n + 1
    return False


@njit
def _fold_gap(sw, p, a, front, elbow, K, th, t1_in=0.0, in_plane=False):
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
    ``th[:6]`` (as :func:`_arm_from_psi`), theta5 (DH, in [0, pi]) into ``th[6]`` and O4 (frame 0)
    into ``th[7:10]``. Returns (gap, ok); ok is False where the branch does not reach.
    ``in_plane``: theta1 is ``t1_in`` and the scaled virtual centre is taken in that arm plane
    (``front`` unused; see :func:`_fold_axis_gap`)."""
    ok, half, psi0, gamma, t20, t1, ox, oy, oz = _fold_arm(sw, p, a, front, K, t1_in, in_plane)
    if not ok:
        return 0.0, False
    return _fold_branch(elbow, half, psi0, gamma, t20, math.cos(t1), math.sin(t1), ox, oy, oz,
                        sw, K, th)


@njit
def _fold_gap_pair(sw, p, a, front, K, th):
    """:func:`_fold_gap` at ``sw`` on both elbow branches of the shoulder branch ``front`` (+-1):
    (gap, ok) of elbow +1, then of elbow -1, from one evaluation of the part they share (the
    centre, theta1, the elbow's half angle: about a third of a gap's transcendental calls). ``th``
    holds the arm of elbow -1."""
    ok, half, psi0, gamma, t20, t1, ox, oy, oz = _fold_arm(sw, p, a, front, K, 0.0, False)
    if not ok:
        return 0.0, False, 0.0, False
    c1, s1 = math.cos(t1), math.sin(t1)
    gp, okp = _fold_branch(1.0, half, psi0, gamma, t20, c1, s1, ox, oy, oz, sw, K, th)
    gm, okm = _fold_branch(-1.0, half, psi0, gamma, t20, c1, s1, ox, oy, oz, sw, K, th)
    return gp, okp, gm, okm


@njit
def _fold_arm(sw, p, a, front, K, t1_in, in_plane):
    """The part of :func:`_fold_gap` its two elbow branches share: (ok, half, psi0, gamma, t20, t1,
    ox, oy, oz): half the elbow's angle, psi = theta2 + theta3 and theta2 before the elbow's sign
    (``psi0 + 2 elbow half``, ``t20 - elbow gamma``), theta1 (DH) and O, the centre of joint 6."""
    u = _u_fold(K) + sw * abs(sw)  # (sw < 0: u below the fold, scanned for deviating models)
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
            return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        disc = r2 - (u * b) ** 2
        if disc < -(1e-12 * scale * u) ** 2:
            return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        rho = front * math.sqrt(max(disc, 0.0))  # u rho
        t1 = shoulder_angle(rho, hx, hy, u * bp)
    xx = rho - u * a1  # u X: the centre in the arm plane, from the shoulder
    xy = e1 * (hz - u * d1)
    nx = math.hypot(xx, xy)
    nv = math.hypot(u * a3, lh)  # u |v|, v = (a3, -eps3 L)
    if nx == 0.0 or nv == 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # |X|^2 - |v|^2 = D / u with the terms of order 1 / u^2 cancelled exactly
    dd = (u * (ox * ox + oy * oy + oz * oz - b * b + a1 * a1 + d1 * d1 - a3 * a3 - d4 * d4)
          - 2.0 * kw * (ox * a[0] + oy * a[1] + oz * a[2] + d4) - 2.0 * (a1 * rho + d1 * hz))
    su = 1.0 if u >= 0.0 else -1.0  # (u < 0: the scaled vectors point the other way)
    dt = su * dd / (nx + nv)  # |X| - |v|
    s2 = a2 * a2 - dt * dt
    if s2 < -1e-12 * a2 * a2:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0  # the elbow does not reach
    root = math.sqrt(max(s2, 0.0) / (nx * nv))
    half = math.asin(min(1.0, 0.5 * abs(u) * root))  # half the angle between X and R(psi) v
    psi0 = math.atan2(xy, xx) - math.atan2(-e3 * lh, u * a3)
    # theta2: the angle at the shoulder between X and the upper arm (its sine from the law of
    # sines, both finite as u goes to 0)
    gamma = math.atan2(nv * root * math.cos(half) / a2, (su * dd + abs(u) * a2 * a2) / (2.0 * a2 * nx))
    t20 = math.atan2(su * xy, su * xx)  # (a2 > 0: ik7r.robot.family.frame_dh)
    return True, half, psi0, gamma, t20, t1, ox, oy, oz


@njit
def _fold_branch(elbow, half, psi0, gamma, t20, c1, s1, ox, oy, oz, sw, K, th):
    """The elbow branch ``elbow`` of :func:`_fold_gap` from its shared part (:func:`_fold_arm`;
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
    th[6] = math.pi - _fold_eps(sw, K)
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
def _fold_eps(sw, K):
    """``eps = pi - theta5`` (>= 0) of the wrist at ``u = cos(2 beta) + sw^2``: ``sw =
    sqrt(2) |sin(beta)| sin(eps / 2)`` (u is quadratic in eps, sw linear); 0 for ``sw < 0``
    (theta5 clamped to pi)."""
    return 2.0 * math.asin(min(1.0, max(sw, 0.0) / (math.sqrt(2.0) * abs(K[L.SB]))))


@njit
def _fold_candidate(sw, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count, filt, ws, mats,
                    t1=0.0, in_plane=False):
    """Complete the root ``sw`` of the fold gap on the branch (front, elbow) with the wrist and
    accept what is exact: theta5 = +-(pi - eps) (and pi itself when eps < FOLD_WINDOW); theta4
    from the position of O (the centre of joint 6) about axis 4, which stays defined where the
    orientation leaves only theta7 - theta4 (axis 7 folded back parallel to axis 4), then theta7
    from the orientation. ``t1``, ``in_plane``: the arm in that plane (:func:`_fold_axis_gap`)."""
    th = ws[_TH:_TH + _NTH]
    _, ok = _fold_gap(sw, p, a, front, elbow, K, th, t1, in_plane)
    if not ok:
        return count
    if filt >= 0 and not _arm_may_match(th, filt, _filter_margin(K), K):
        return count
    _arm_frame(th, R07, K, ws, mats)
    M = mats[_M]
    Q = mats[_Q, :3, :3]
    # O - O4 in frame 3 turned by alpha3 (frame 4 at theta4 = 0): its azimuth about axis 4
    d7 = K[L.D7]
    vx = p[0] - d7 * a[0] - th[7]
    vy = p[1] - d7 * a[1] - th[8]
    vz = p[2] - d7 * a[2] - th[9]
    x3 = M[0, 0] * vx + M[1, 0] * vy + M[2, 0] * vz
    y3 = M[0, 1] * vx + M[1, 1] * vy + M[2, 1] * vz
    z3 = M[0, 2] * vx + M[1, 2] * vy + M[2, 2] * vz
    az = math.atan2(K[L.NOMINAL_TRIG + 6] * y3 + K[L.NOMINAL_TRIG + 7] * z3, x3)
    q = ws[_Q6:_Q6 + 6]
    qq = ws[_QQ:_QQ + 6]
    eps = _fold_eps(sw, K)
    if eps < _fold_snap(K):
        count, exact = _accept(_with_fold_wrist(q, Q, math.pi, -1.0, 0.0, az, K, mats, qq), Td, K,
                               out, count, mats, True)
        # (done unless the polish left this arm: with the approach along axis 1 the fold has
        # solutions of its own, which a start beside them may slide to)
        if exact and max(abs(wrap(qq[0] - q[0])), abs(wrap(qq[1] - q[1])),
                         abs(wrap(qq[2] - q[2]))) < FOLD_WINDOW:
            return count
    for sgn in (1.0, -1.0):
        t5 = sgn * (math.pi - eps)
        count, _ = _accept(_with_fold_wrist(q, Q, t5, -math.cos(eps), sgn * math.sin(eps), az, K,
                                            mats, qq), Td, K, out, count, mats)
        if K[L.DEVIATION] > 0.0 and eps < NEAR_SINGULAR:  # (start off the singular fold too)
            alt = sgn * (math.pi - NEAR_SINGULAR)
            count, _ = _accept(_with_fold_wrist(q, Q, alt, math.cos(alt), math.sin(alt), az, K,
                                                mats, qq), Td, K, out, count, mats, False, False)
    return count


@njit
def _with_fold_wrist(q, Q, t5, c5, s5, az, K, mats, qq):
    """``qq``: a copy of ``q`` (arm joints set) completed with the wrist for DH angle ``t5``
    (cosine ``c5``, sine ``s5``), theta4 from the azimuth ``az`` of O - O4 about axis 4 (O - O4 =
    dw (z5 + z6) lies at azimuth theta4 + mu(theta5) in frame 4 at theta4 = 0)."""
    sb = K[L.SB]
    dwsb = K[L.DW] * sb
    mu = math.atan2(dwsb * math.sqrt(1.0 - sb * sb) * (1.0 - c5), dwsb * s5)
    t4 = az - mu
    c4, s4 = math.cos(t4), math.sin(t4)
    W = mats[_WR, :3, :3]
    wrist_rotation_cs(c5, s5, K, W)
    t7 = wrist_t7(Q, c4, s4, W)
    _completed(q, t4, t5, t7, K, qq)
    return qq


@njit
def _scan_fold(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Every solution within FOLD_SPAN (in u) of the fully bent wrist, for robots whose fold is
    (nearly) at infinity (``cos(2 beta)`` below FOLD_NEAR): the fold gap (:func:`_fold_gap`) of each
    of the four arm branches scanned as the bend gap is (:func:`_scan_piece`), in ``sw =
    sqrt(u - cos(2 beta))`` (proportional to sin((pi - theta5) / 2): solutions close to the fold
    stay apart on the grid) from the fold (0) to just past where the polynomial search begins."""
    if K[L.DEVIATION] > 0.0:
        # the exact model's solutions at the fold may come from nominal roots beyond it (u below
        # cos(2 beta), theta5 clamped to pi): near a fold at infinity a twist 1e-4 rad off moves
        # the virtual centre by d 1e-4, and it may come back from the other side (u < 0)
        count = _scan_theta5(-math.sqrt(FOLD_BELOW * (1.0 - _u_fold(K))), 0.0, p, a, R07, Td, K,
                             hint, has_hint, out, count, filt, ws, mats, 2.0, FOLD_BELOW_CELLS)
    count = _scan_theta5(0.0, math.sqrt(FOLD_SPAN) * (1.0 + 1e-3), p, a, R07, Td, K, hint,
                         has_hint, out, count, filt, ws, mats, 2.0)
    if _fold_near_axis(p, a, K):
        # the approach (nearly) along axis 1: the fold gap in theta1 as well, and on a finer grid
        # next to the fold (two roots there can be within 1e-4 in sw, one cell of the grid above)
        count = _scan_turn(3.0, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
        count = _scan_theta5(0.0, 1e-2 * math.sqrt(FOLD_SPAN), p, a, R07, Td, K, hint, has_hint,
                             out, count, filt, ws, mats, 2.0)
    return count


@njit
def _fold_span_u(K):
    """The span of ``u - cos(2 beta)`` the fold scan covers (see :func:`_scan_fold`)."""
    lo = -FOLD_BELOW * (1.0 - _u_fold(K)) if K[L.DEVIATION] > 0.0 else 0.0
    return lo, FOLD_SPAN * (1.0 + 1e-3) ** 2


@njit
def _fold_near_axis(p, a, K):
    """Whether the scaled virtual centre ``u P = u O - KW a`` (O the centre of joint 6) of the
    fully bent wrist (u = cos(2 beta)) lies within FOLD_AXIS_NEAR (relative to ``KW + |u|
    scale``) of axis 1: the approach (nearly) parallel to axis 1, where theta1 of the fold gap's
    arm swings next to the fold (and at the fold itself, with a vertical approach, is fixed not
    by the direction of P but by the position of O4)."""
    u = _u_fold(K)
    d7 = K[L.D7]
    hx = u * (p[0] - d7 * a[0]) - K[L.KW] * a[0]
    hy = u * (p[1] - d7 * a[1]) - K[L.KW] * a[1]
    return math.hypot(hx, hy) <= FOLD_AXIS_NEAR * (abs(K[L.KW]) + abs(u) * K[L.SCALE])


@njit
def _fold_axis_sw(t1, p, a, K):
    """``sw`` (:func:`_fold_gap`) of the u at which the scaled virtual centre ``u O - KW a`` lies in
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
    du = u - _u_fold(K)
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
    """The fold gap (:func:`_fold_gap`) as a function of theta1 (DH) on the elbow branch
    ``elbow``: u from the plane condition (:func:`_fold_axis_sw`), the arm in that plane. Where
    the approach is (nearly) parallel to axis 1 the scaled virtual centre is (nearly) on it near
    the fold, and theta1 of the fold gap's arm swings fast with u (at the fold itself a vertical
    approach leaves theta1 to the position of O4: the pose's solutions there form no branch of
    u at all); in theta1 they stay apart. Returns (gap, ok)."""
    sw, ok = _fold_axis_sw(t1, p, a, K)
    if not ok:
        return 0.0, False
    return _fold_gap(sw, p, a, 1.0, elbow, K, th, t1, True)


@njit
def _gap_candidate(t, p, a, front, elbow, R07, Td, K, hint, has_hint, out, count, filt, ws, mats):
    """Complete the arm branch's root ``t`` of the bend gap with the wrist; accept what is exact."""
    if abs(front) == 2.0:
        return _fold_candidate(t, p, a, 0.5 * front, elbow, R07, Td, K, hint, has_hint, out, count,
                               filt, ws, mats)
    if front == 3.0:
        sw, ok = _fold_axis_sw(t, p, a, K)
        if not ok:
            return count
        return _fold_candidate(sw, p, a, 1.0, elbow, R07, Td, K, hint, has_hint, out, count, filt,
                               ws, mats, t, True)
    th = ws[_TH:_TH + _NTH]
    if front == 0.0:
        _, ok = _shoulder_gap(t, p, a, elbow, K, th)  # the arm of the root, into th; theta5 th[6]
    else:
        # (theta1 from the seed where the virtual centre is on axis 1: the gap does not depend
        # on it when axis 7 is on axis 1 too, where the pose leaves q1 free)
        _, ok = _bend_gap(t, p, a, front, elbow, K, th, K[L.SIGN] * hint[0] + K[L.THETA_OFFSET1])
    if ok:
        t5 = th[6]
        count = _wrist_and_accept(th, t5, math.cos(t5), math.sin(t5), R07, Td, K, hint, has_hint,
                                  out, count, filt, ws, mats)
    return count


@njit
def _roots(kind, p, a, K, Bm, bnorm, roots, ws):
    """Every real root of the residual ``kind`` (:func:`ik7r._kernels.poly.residual_of`) over the
    search interval of d (into ``roots``), ascending; -1 when it vanishes identically (a
    continuum). ``ws``: the pose's work array."""
    lo, hi = _interval(K)
    nc = Bm.shape[0]
    blo = ws[_BLO:_BLO + _NBRACKETS]
    bhi = ws[_BHI:_BHI + _NBRACKETS]
    bsure = ws[_BSURE:_BSURE + _NBRACKETS]
    bcoef = ws[_BCOEF:_BCOEF + _NBRACKETS * nc].reshape((_NBRACKETS, nc))
    nb = isolate(kind, lo, hi, p, a, K, Bm, bnorm, blo, bhi, bsure, bcoef,
                 ws[_ISO:_ISO + ISOLATE_WORK])
    ws[_NBK] = max(nb, 0)
    if nb < 0:
        return -1
    count = 0
    found = ws[_FOUND:_FOUND + REFINE_GRID + 2]
    w = ws[_CAST:_CAST + nc]
    for k in range(nb):
        if bsure[k] == 1.0:  # exactly one root, and the interpolant on its bracket
            found[0] = _newton_on_bracket(kind, blo[k], bhi[k], bcoef[k], p, a, K, w)
            m = 1
        else:
            m = refine(kind, blo[k], bhi[k], p, a, K, found)
        for i in range(m):
            # u -> d; for a model that deviates from the idealised one a root just outside
            # the range stays where it is (its arm exists there; theta5 is clamped to 0 or pi)
            u = found[i]
            if K[L.DEVIATION] == 0.0:
                u = min(1.0, max(_u_fold(K), u))
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
    minimum: the grid reads a narrow dip between its points too high."""
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
            sc = _power(_off_zero(u), K)
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
                        fa < NEAR_RATIO_GRID * ms[k, i] and _dips_to_zero(fs[k, il], fs[k, i], fs[k, ir])))):
                u = _least_abs(kd, lo + (hi - lo) * il / m, lo + (hi - lo) * ir / m, p, a, K)
                fu, mu = residual_of(kd, u, p, a, K)
                if not (fa < NEAR_RATIO * ms[k, i] or abs(fu) < NEAR_RATIO * mu):
                    continue  # clear of zero on the grid and at its refined minimum
                if k > 0:
                    if fu * fs[k, i] <= 0.0 or not (0 < i < m or abs(fu) < NEAR_RATIO_END * mu):
                        continue  # two real roots (the certified search has them), or an end clear of zero
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
def _continuum(p, a, R07, Td, K, Bm, bnorm, hint, has_hint, out, count, filt, ws, mats):
    """Axis 7 on axis 1 (P' on axis 1 for every d): theta1 is free. Take it from the hint
    (else 0) and solve the remaining 1-D problem with the same certified root isolation."""
    roots = ws[_ROOTS:_ROOTS + ROOT_CAP]
    nr = _roots(1, p, a, K, Bm, bnorm, roots, ws)
    th1 = K[L.SIGN] * hint[0] + K[L.THETA_OFFSET1] if has_hint else K[L.THETA_OFFSET1]
    c1, s1 = math.cos(th1), math.sin(th1)
    psi = mats[_PSI]
    th = ws[_TH:_TH + 6]
    for k in range(max(nr, 0)):
        d = roots[k]
        t5, c5, s5 = theta5_cs_of_d(d, K)
        pz = p[2] - (K[L.D7] + d) * a[2]
        a11, a12, m, a21, a22, c = linear_system(d, 0.0, p, a, K)
        a21, a22, c = bend_row_on_axis(d, a, K)
        for k2 in range(_psi_candidates(a11, a12, m, a21, a22, c, psi)):
            _arm_from_psi(d, 0.0, psi[k2, 0], psi[k2, 1], pz, c1, s1, K, th)
            count = _wrist_and_accept(th, t5, c5, s5, R07, Td, K, hint, has_hint, out, count, filt, ws,
                                      mats)
    return count


@njit
def _u_fold(K):
    """``u = KW / d`` of the fully bent wrist (theta5 = pi): ``cos(2 beta)``."""
    return 1.0 - 2.0 * K[L.SB] * K[L.SB]


@njit
def _interval(K):
    """The search interval of ``u = KW / d = cos(phi / 2)``: the whole theta5 range (u = 1 at
    the straight wrist, cos(2 beta) fully bent), padded by rounding; for a fold (nearly) at
    infinity (cos(2 beta) < FOLD_NEAR) it starts FOLD_SPAN above the fold."""
    lo = _u_fold(K)
    pad = 1e-9 * (1.0 - lo)
    if K[L.DEVIATION] > 0.0:
        # the exact model's solutions near the ends of the range may come from nominal roots
        # just outside it (kept there, then polished on the exact model)
        pad = 0.02 * (1.0 - lo)
    if lo < FOLD_NEAR:
        return lo + FOLD_SPAN, 1.0 + pad  # the fold's neighbourhood is :func:`_scan_fold`'s
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
    mats = ws[_MATS:_MATS + _NMATS * 16].reshape((_NMATS, 4, 4))
    T07 = mats[_T07]
    frame07(Td, K, T07)
    p = ws[_P:_P + 3]
    a = ws[_A:_A + 3]
    R07 = mats[_R07, :3, :3]
    for i in range(3):
        p[i] = T07[i, 3]
        a[i] = T07[i, 2]
        for j in range(3):
            R07[i, j] = T07[i, j]
    na = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    for i in range(3):
        a[i] /= na
    roots = ws[_ROOTS:_ROOTS + ROOT_CAP]
    ws[_NFAM] = 0.0
    ws[_NRSCAN] = 0.0
    ws[_NSDIP] = 0.0
    mats[_MEMO_N, 0, 0] = 0.0
    mats[_CW].reshape(16)[_CW_REF] = wrap(hint[0]) if has_hint else 0.0
    mats[_CW].reshape(16)[_CW_FOUND] = 0.0
    mats[_CW].reshape(16)[_CW_SHOULDER] = 0.0
    nr = _roots(0, p, a, K, Bm, bnorm, roots, ws)
    count = 0
    if nr < 0:
        return _continuum(p, a, R07, Td, K, Bm, bnorm, hint, has_hint, out, count, filt, ws, mats)
    last = -1e300
    folded = False
    # theta5 grows with d: the roots within _fold_snap of theta5 = pi lie beyond this d
    d_fold = d_of_theta5(math.pi - _fold_snap(K), K) if _u_fold(K) > 1e-9 else math.inf
    for k in range(nr):
        d = roots[k]
        if d == last:
            continue  # the same root twice (clamped to an end of the range)
        last = d
        if not folded and d > d_fold:
            # near theta5 = pi the residual is flat: try the folded wrist's own d first
            folded = True
            count = _solutions_at(K[L.DMAX], p, a, R07, Td, K, hint, has_hint, out, count, filt,
                                  ws, mats)
        count = _solutions_at(d, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
    # brackets the polynomial left undecided (clusters of roots within its rounding): scan
    # them in theta5 with the bend gap, which resolves what the polynomial cannot
    sb2 = 2.0 * K[L.SB] * K[L.SB]
    for k in range(int(ws[_NBK])):
        if ws[_BSURE + k] == 0.0:
            ta = 2.0 * math.asin(math.sqrt(min(1.0, max(0.0, (1.0 - ws[_BHI + k]) / sb2))))
            tb = 2.0 * math.asin(math.sqrt(min(1.0, max(0.0, (1.0 - ws[_BLO + k]) / sb2))))
            count = _scan_theta5(ta, tb, p, a, R07, Td, K, hint, has_hint, out, count, filt, ws,
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
            count = _scan_theta5(0.0, DEVIATING_ENDS, p, a, R07, Td, K, hint, has_hint, out, count,
                                 filt, ws, mats)
        if nearpi and _u_fold(K) >= FOLD_NEAR:
            count = _scan_theta5(math.pi - DEVIATING_ENDS, math.pi, p, a, R07, Td, K, hint, has_hint,
                                 out, count, filt, ws, mats)
    if _u_fold(K) < FOLD_NEAR:
        # the fully bent wrist of a (nearly) 45 deg twist: the polynomial starts FOLD_SPAN above it
        count = _scan_fold(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
        folded = True
    count = _scan_shoulder(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
    if K[L.DEVIATION] > 0.0:
        count = _gap_near_misses(p, a, R07, Td, K, hint, has_hint, out, count, filt, ws, mats)
        count = _partners(Td, K, out, count, ws, mats)
        count = _other_wrists(R07, Td, K, out, count, ws, mats)
    if folded:
        count = _merge_folded(out, count)
    if mats[_CW].reshape(16)[_CW_SHOULDER] != 0.0:
        count = _floor_shoulder(out, count, Td, K, mats)
    return count


@njit
def _floor_shoulder(out, count, Td, K, mats):
    """Polish the answers on the shoulder set to their floor (:func:`_floored`; FLOOR), each
    in place when that stays exact, and drop those that come within DUP_TOL of one before them:
    two points of one solution's valley, from either side. A continuum's point (at its q1, see
    :func:`_axis4_turn`) and an exactly straight or fully bent wrist (set by their rules: the
    split of :func:`_split_sum`, theta5 = pi) stay where they are."""
    x = mats[_WALK].reshape(16)[:6]
    ref = mats[_CW].reshape(16)[_CW_REF]
    keep = 0
    for s in range(count):
        if (out[s, 0] != ref and STRAIGHT_EXACT < _bend(out[s], K) < math.pi - STRAIGHT_EXACT
                and _on_shoulder_set(out[s], K) and _floored(out[s], x, Td, K, mats)):
            for i in range(6):
                out[s, i] = wrap(x[i])
        if not _known(out[s], out, keep, DUP_TOL):
            keep = _kept(out, keep, s)
    return keep


@njit
def _merge_folded(out, count):
    """Drop solutions within FOLD_WINDOW (every joint) of an exact fully bent one (theta5 = pi):
    there the FK is flat in theta5, and what remains are shadows of the one merged solution."""
    keep = 0
    for s in range(count):
        shadow = False
        if out[s, 4] != math.pi and math.pi - abs(out[s, 4]) < FOLD_WINDOW:
            for e in range(count):
                if out[e, 4] == math.pi:
                    if _far(out[s], out[e]) < FOLD_WINDOW:
                        shadow = True
                        break
        if not shadow:
            keep = _kept(out, keep, s)
    return keep


@njit
def _near_shoulder(th, K):
    """Whether the arm of DH cosines and sines ``th`` (see :func:`_arm_from_psi`) places the
    straight wrist's virtual centre within SHOULDER_DEVIATING of the robot's size from axis 1
    (its distance in the arm plane, ``a1`` plus the reach of joints 2 and 3)."""
    c2, c3, s2, s3 = th[1], th[2], th[4], th[5]
    Ld = K[L.D4] + K[L.KW]
    e3 = K[L.EPS3]
    x2 = K[L.A2] + K[L.A3] * c3 + e3 * Ld * s3
    y2 = K[L.A3] * s3 - e3 * Ld * c3
    return abs(K[L.A1] + c2 * x2 - s2 * y2) < SHOULDER_DEVIATING * K[L.SCALE]


@njit(allocates=True)
def _straight_family(q, Q, Td, K, out, count, ws, mats, sheets=False):
    """Every exact solution near the straight-wrist family of the arm ``q[:3]`` (user angles) on a
    model that deviates from the idealised one. On the idealised model a straight wrist leaves
    only ``s4 q4 + s7 q7`` defined (a circle of solutions, the split free); the deviation breaks
    the circle into isolated solutions, spread over the whole turn of the split, with the arm
    and q5 moved by about the deviation. With q4 fixed the five other joints are regular there,
    so these solutions are the zeros of one function of q4 (:func:`_reduced_scan`), found by a
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
    0.09 rad apart in q4 on either side of the start)."""
    s4 = K[L.SIGN + 3]
    s7 = K[L.SIGN + 6]
    total = math.atan2(Q[1, 0], Q[0, 0]) - K[L.THETA_OFFSET4] - K[L.THETA_OFFSET7]
    nf = int(ws[_NFAM])
    for k in range(min(nf, _NFAMILIES)):
        f = ws[_FAM + 4 * k:_FAM + 4 * k + 4]
        far = abs(wrap(f[3] - total))
        for i in range(3):
            far = max(far, abs(wrap(f[i] - q[i])))
        if far < 1e-2:
            return count
    if nf < _NFAMILIES:
        f = ws[_FAM + 4 * nf:_FAM + 4 * nf + 4]
        for i in range(3):
            f[i] = q[i]
        f[3] = total
        ws[_NFAM] = nf + 1
    start = np.empty(6)
    for i in range(3):
        start[i] = q[i]
    start[3] = -math.pi
    start[4] = user_angle(4, 0.0, K)
    start[5] = s7 * (total + s4 * math.pi)
    back = start.copy()
    count = _reduced_scan(start, 3, -math.pi, math.pi, REDUCED_GRID, Td, K, out, count, ws,
                          mats)
    if not sheets:
        return count
    # near the shoulder set a sheet need not close over the turn (q1 drifts onto the other
    # sheet before the scan comes back): its last half turn is tracked back from the start too
    count = _reduced_scan(back, 3, math.pi, 0.0, REDUCED_GRID // 2, Td, K, out, count, ws, mats)
    # the other sheet, from the mirror of the scanned one's least bent point: theta4 and theta7
    # half a turn on, theta5 of the other sign (the same wrist to first order in theta5)
    start[3] = wrap(start[3] + s4 * math.pi)
    start[4] = user_angle(4, -dh_angle(start, K, 4), K)
    start[5] = wrap(start[5] + s7 * math.pi)
    for i in range(6):
        back[i] = start[i]
    count = _reduced_scan(start, 3, start[3], start[3] + TWO_PI, REDUCED_GRID, Td, K, out, count,
                          ws, mats)
    return _reduced_scan(back, 3, back[3], back[3] - math.pi, REDUCED_GRID // 2, Td, K, out, count,
                         ws, mats)


@njit
def _det6(A):
    """Determinant of ``A`` (6, 6; overwritten), by elimination with partial pivoting."""
    det = 1.0
    for k in range(6):
        p = k
        for i in range(k + 1, 6):
            if abs(A[i, k]) > abs(A[p, k]):
                p = i
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
def _dips_to_zero(r0, r1, r2):
    """Whether the parabola through three equally spaced values of one sign (``r1`` the least in
    magnitude) comes down to half of ``r1`` or beyond zero between them, or ``r1`` is below
    DIP_SHARP of both neighbours: a dip that may hide a tangency or two roots, not a shallow
    minimum. (The parabola underestimates a dip whose cell holds two close roots off its middle:
    one of the IRB 5400 at the shoulder set came down to 1.8e-8 between samples 9e-7, 2.5e-8 and
    6e-7, while the residual's two roots 0.01 rad apart lie 0.01 rad from the least sample.)"""
    if abs(r1) < DIP_SHARP * min(abs(r0), abs(r2)):
        return True
    c = 0.5 * (r0 + r2) - r1
    b = 0.5 * (r2 - r0)
    if c == 0.0 or (c > 0.0) != (r1 > 0.0):
        return False
    t = -b / (2.0 * c)
    if abs(t) > 1.0:
        return False
    bottom = r1 + b * t + c * t * t
    return (bottom < 0.5 * r1) if r1 > 0.0 else (bottom > 0.5 * r1)  # (or beyond zero)


@njit
def _reduced_root(qt, j, va, vb, ra, rb, Td, K, T, J, A, e, g, dq, ZO):
    """Refine the root of the reduced residual bracketed by [va, vb] (``ra``, ``rb`` of opposite
    signs) by Illinois (:func:`ik7r._kernels.poly.illinois_step`), each point Gauss-Newton from
    the one before (``qt``, left at the root), until the residual the last step would leave is
    below REDUCED_ROOT_TOL: closer in ``v`` is worth nothing, since ``qt`` stays up to
    REDUCED_SETTLE from the point that step reaches (bisecting the bracket down to 1e-11 took
    twice the reduced residuals near the shoulder set, about a sixth of a pose's)."""
    side = 0
    for _ in range(40):
        v = secant_point(va, vb, ra, rb)
        r, res, ok = _reduced_at(qt, j, v, Td, K, T, J, A, e, g, dq, ZO)
        if not ok or r == 0.0 or res <= REDUCED_ROOT_TOL:
            return
        va, vb, ra, rb, side, _ = illinois_step(va, vb, ra, rb, side, v, r)
        if abs(vb - va) <= 1e-11:
            return  # (the polish of _accept takes it to the last bits)


@njit
def _cell_kind(rs, es, k, kb, closed):
    """What the reduced scan refines in its cell ``k`` (grid values ``rs`` signed, ``es`` the
    error's norm; ``kb`` the point before ``k``, on a closed curve m - 1 for k = 0): 1 a sign
    change, 2 a dip of ``|e|`` toward zero without one (below DIP_NEAR, or by
    :func:`_dips_to_zero`), 0 nothing."""
    ra = rs[k]
    rb = rs[k + 1]
    if not (math.isfinite(ra) and math.isfinite(rb)):
        return 0
    if ra * rb < 0.0:
        return 1
    if ((0 < k or closed) and es[k] <= es[kb] and es[k] <= es[k + 1]
            and math.isfinite(rs[kb]) and rs[kb] * ra > 0.0
            and (es[k] < DIP_NEAR or _dips_to_zero(rs[kb], ra, rb))):
        return 2
    return 0


@njit
def _scan_seen(memo, n, j, v0, v1, m, qs, kind, k, kb):
    """Whether an earlier reduced scan of this pose (``memo``, ``n`` of them: see SCAN_MEMO)
    over the same grid (joint ``j``, [v0, v1], ``m`` cells) refined its cell ``k`` the same
    way (``kind``, see :func:`_cell_kind`) from the same points: ``k`` and ``k + 1`` (and
    ``kb`` for a dip) within SCAN_MEMO_TOL of ``qs``'. Its candidates are then this cell's."""
    for s in range(min(n, SCAN_MEMO)):
        slot = memo[s * _SCAN_SLOT:(s + 1) * _SCAN_SLOT]
        if slot[0] != j or slot[1] != v0 or slot[2] != v1 or slot[3] != m:
            continue
        pts = slot[_SCAN_HEAD:_SCAN_HEAD + 8 * (m + 1)].reshape((m + 1, 8))
        if _cell_kind(pts[:, 6], pts[:, 7], k, kb, slot[4] != 0.0) != kind:
            continue
        same = _far(pts[k], qs[k]) <= SCAN_MEMO_TOL and _far(pts[k + 1], qs[k + 1]) <= SCAN_MEMO_TOL
        if same and (kind == 1 or _far(pts[kb], qs[kb]) <= SCAN_MEMO_TOL):
            return True
    return False


@njit
def _scan_joined(memo, n, j, v0, v1, m, qs, k):
    """The earlier reduced scan of this pose (``memo``, ``n`` of them: see SCAN_MEMO) over the
    same grid whose points ``k - 2`` and ``k - 1`` are within SCAN_MEMO_TOL of ``qs``', or -1."""
    for s in range(min(n, SCAN_MEMO)):
        slot = memo[s * _SCAN_SLOT:(s + 1) * _SCAN_SLOT]
        if slot[0] != j or slot[1] != v0 or slot[2] != v1 or slot[3] != m:
            continue
        pts = slot[_SCAN_HEAD:_SCAN_HEAD + 8 * (m + 1)].reshape((m + 1, 8))
        if _far(pts[k - 2], qs[k - 2]) <= SCAN_MEMO_TOL and _far(pts[k - 1], qs[k - 1]) <= SCAN_MEMO_TOL:
            return s
    return -1


@njit
def _scan_keep(memo, n, j, v0, v1, m, qs, rs, es, closed):
    """Record a reduced scan's grid in the ring ``memo`` as its ``n``-th (see SCAN_MEMO)."""
    slot = memo[(n % SCAN_MEMO) * _SCAN_SLOT:(n % SCAN_MEMO + 1) * _SCAN_SLOT]
    slot[0] = j
    slot[1] = v0
    slot[2] = v1
    slot[3] = m
    slot[4] = 1.0 if closed else 0.0
    pts = slot[_SCAN_HEAD:_SCAN_HEAD + 8 * (m + 1)].reshape((m + 1, 8))
    for k in range(m + 1):
        for i in range(6):
            pts[k, i] = qs[k, i]
        pts[k, 6] = rs[k]
        pts[k, 7] = es[k]


@njit(allocates=True)
def _reduced_scan(start, j, v0, v1, m, Td, K, out, count, ws, mats):
    """Every exact solution on the branch of the reduced residual (:func:`_reduced_at`) with
    joint ``j`` over [v0, v1], tracked from ``start`` on a grid of ``m`` <= REDUCED_GRID cells
    (each point Gauss-Newton from the extrapolation of the two before it): sign changes refined
    by Illinois in ``v``, dips toward zero (tangencies, two roots in one cell) by Brent's
    minimiser on the signed residual and split at its bottom; each candidate is verified
    (polished) on the exact forward kinematics and added. A cell an earlier scan of the pose
    refined from the same points is not refined again (:func:`_scan_seen`). On return
    ``start`` holds the grid point whose wrist is the least bent (see
    :func:`_straight_family`)."""
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
    th6 = np.empty(6)  # (the other wrist at a dip: see _other_wrist)
    M3 = np.empty((4, 4))
    Q3 = np.empty((3, 3))
    W3 = np.empty((3, 3))
    memo = ws[_RSCAN:_RSCAN + SCAN_MEMO * _SCAN_SLOT]
    n = int(ws[_NRSCAN]) if m == REDUCED_GRID else 0
    joined = -1
    for k in range(m + 1):
        if joined < 0 and k >= 2:
            joined = _scan_joined(memo, n, j, v0, v1, m, qs, k)
        if joined >= 0:
            # (the earlier scan's point k: Gauss-Newton from the same start; added if exact then)
            pts = memo[joined * _SCAN_SLOT + _SCAN_HEAD:(joined + 1) * _SCAN_SLOT]
            for i in range(6):
                qs[k, i] = pts[8 * k + i]
            rs[k] = pts[8 * k + 6]
            es[k] = pts[8 * k + 7]
            continue
        for i in range(6):
            if k == 0:
                qt[i] = start[i]
            elif k == 1:
                qt[i] = qs[0, i]
            else:
                qt[i] = 2.0 * qs[k - 1, i] - qs[k - 2, i]
        r, res, ok = _reduced_at(qt, j, v0 + (v1 - v0) * k / m, Td, K, T, J, A, e, g, dq, ZO)
        for i in range(6):
            qs[k, i] = qt[i]
        rs[k] = r if ok else np.nan
        es[k] = res if ok else np.inf
        if ok:
            dp, dr = residual(T, Td)
            if dp <= K[L.POS_TOL] and dr <= K[L.ROT_TOL]:
                count = _add(qt.copy(), out, count, Td, K, mats)
    # over a whole turn the branch is a closed curve when it comes back to its start: the grid
    # point before the first is then the last but one (a dip at the start is a dip)
    closed = abs(v1 - v0 - TWO_PI) < 1e-12 and _far(qs[0], qs[m]) < CLOSED_TOL
    for k in range(m):
        va = v0 + (v1 - v0) * k / m
        vb = v0 + (v1 - v0) * (k + 1) / m
        ra = rs[k]
        rb = rs[k + 1]
        kb = k - 1 if k > 0 else m - 1  # (the point before; k = 0 only on a closed curve)
        kind = _cell_kind(rs, es, k, kb, closed)
        if kind == 0 or _scan_seen(memo, n, j, v0, v1, m, qs, kind, k, kb):
            continue
        if kind == 1:
            for i in range(6):
                qt[i] = qs[k, i]
            _reduced_root(qt, j, va, vb, ra, rb, Td, K, T, J, A, e, g, dq, ZO)
            count, _ = _accept(qt.copy(), Td, K, out, count, mats, False, False)
        else:
            # a dip of |e| without a sign change: a tangency, or two roots within one cell; where
            # the bottom has the other sign, both roots are refined
            for i in range(6):
                qt[i] = qs[k, i]
            sgn = 1.0 if ra > 0.0 else -1.0
            # the bottom of the signed residual (|e| would stop at a root), by Brent's minimiser
            st, x = brent_start(v0 + (v1 - v0) * (k - 1) / m, vb)
            for _ in range(200):
                f, _, okf = _reduced_at(qt, j, x, Td, K, T, J, A, e, g, dq, ZO)
                st = brent_take(st, x, sgn * f if okf else np.inf)
                st, x, done = brent_next(st)
                if done:
                    break
            vm = st[2]
            rm, _, okm = _reduced_at(qt, j, vm, Td, K, T, J, A, e, g, dq, ZO)
            qm = qt.copy()
            count, _ = _accept(qt.copy(), Td, K, out, count, mats, False, False)
            if okm and rm * ra < 0.0:
                v_lo = v0 + (v1 - v0) * (k - 1) / m
                for vx, rx in ((v_lo, rs[kb]), (vb, rb)):
                    for i in range(6):
                        qt[i] = qm[i]
                    _reduced_root(qt, j, min(vx, vm), max(vx, vm), rx if vx < vm else rm,
                                  rm if vx < vm else rx, Td, K, T, J, A, e, g, dq, ZO)
                    count, _ = _accept(qt.copy(), Td, K, out, count, mats, False, False)
            elif _bend(qm, K) > STRAIGHT_DEVIATING:
                # a bottom that is no root: the other wrist of its arm may be a solution on a
                # sheet this curve never reaches (it can cross the fully bent wrist, q5 = pi,
                # onto the sheet it started beside)
                _other_wrist(qm, mats[_R07, :3, :3], K, th6, M3, Q3, W3, qt)
                count, _ = _accept(qt.copy(), Td, K, out, count, mats, False, False)
    if m == REDUCED_GRID and joined < 0:
        _scan_keep(memo, n, j, v0, v1, m, qs, rs, es, closed)
        ws[_NRSCAN] = n + 1
    least = math.inf
    for k in range(m + 1):
        t5 = _bend(qs[k], K)
        if math.isfinite(rs[k]) and t5 < least:
            least = t5
            for i in range(6):
                start[i] = qs[k, i]
    return count


@njit
def _other_wrists(R07, Td, K, out, count, ws, mats):
    """The other wrist of each solution of a deviating model that has none: on the idealised
    model every arm comes with both wrists (theta5 of either sign, theta4 and theta7 from the
    arm's wrist target), and the deviation moves the two apart by about its own size. Where the
    idealised model has no solution near (both come from one near miss, beside the elbow stretch
    or the fully bent wrist), the polish of the near miss's candidates can reach one wrist and
    not the other: a solution with no other one within OTHER_WRIST_ARM (rad, joints 1 to 3) whose
    theta5 has the other sign starts a polish from its arm with the other wrist. Not at a straight
    wrist, whose neighbours the straight-wrist scan finds (:func:`_straight_family`)."""
    th = ws[_TH:_TH + _NTH]
    qq = ws[_QQ:_QQ + 6]
    n0 = count
    for s in range(n0):
        t5 = _theta5(out[s], K)
        if abs(t5) < STRAIGHT_DEVIATING:
            continue
        paired = False
        for e in range(count):
            if e == s or _theta5(out[e], K) * t5 >= 0.0:
                continue
            near = True
            for i in range(3):
                near = near and abs(wrap(out[e, i] - out[s, i])) < OTHER_WRIST_ARM
            if near:
                paired = True
                break
        if paired:
            continue
        _other_wrist(out[s], R07, K, th, mats[_M], mats[_Q, :3, :3], mats[_WR, :3, :3], qq)
        count, _ = _accept(qq, Td, K, out, count, mats, False, False)
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
        p = k
        for i in range(k + 1, 6):
            if abs(A[i, k]) > abs(A[p, k]):
                p = i
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
def _partners(Td, K, out, count, ws, mats):
    """Solutions of a deviating model next to a nearly singular one. Where the exact model has
    two solutions close together whose idealised counterparts are complex (or merged), the
    polish of every idealised candidate can land on one of them. At a solution ``x`` with the
    Jacobian's smallest singular value ``sigma`` (left and right vectors ``u``, ``v``) the pose
    error along ``x + t v`` is ``sigma t + c t^2 / 2`` on ``u`` (``c`` by central differences):
    its second zero ``t = -2 sigma / c`` is the partner's prediction, polished on the exact model
    (a check, not a certificate: see docs/guide/edges.md). Where that step finds nothing new,
    the reduced residual (:func:`_reduced_scan`) in the joint ``v`` moves most is scanned
    PARTNER_CELLS cells each way: the partner lies on the curve of nearly solutions through
    ``x``, which may bend away from the line (the error off ``u`` then grows along it). A
    partner found is itself searched for a partner (a cluster of three: a solution found only
    as a partner had its own missed). Not in q1 where :func:`_shoulder_turn` has tracked the
    exact model over its whole turn (:func:`_turn_scanned`): the same solution sets over 24,000
    poses of four deviating robots without those scans, a third of the partners' reduced
    residuals on a near-shoulder pose."""
    T = np.empty((4, 4))
    J = np.empty((6, 6))
    A = np.empty((6, 6))
    ZO = np.empty((7, 6))
    ep = np.empty(6)
    qt = np.empty(6)
    w = 1.0 / K[L.SCALE]
    turned = _turn_scanned(ws[_P:_P + 3], ws[_A:_A + 3], K)  # (once per pose, not per partner)
    s = -1
    while s + 1 < count:  # (each new row a distinct solution: bounded by the output's size)
        s += 1
        if _bend(out[s], K) < STRAIGHT_DEVIATING:
            continue  # a straight wrist's neighbours: the whole turn is scanned (_straight_family)
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
        if abs(t) <= PARTNER_REACH:
            for i in range(6):
                qt[i] = x[i] + t * Vt[5, i]
            count, _ = _accept(qt.copy(), Td, K, out, count, mats, False, False)
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
            reach = PARTNER_REACH * abs(Vt[5, j])
            for sg in (1.0, -1.0):
                # (from PARTNER_STEP of a cell beside x, not from x: the residual is zero at x, so
                # the first cell's sign test would read rounding, and a partner in it was lost)
                count = _reduced_scan(x.copy(), j, x[j] + sg * PARTNER_STEP * reach / PARTNER_CELLS,
                                      x[j] + sg * reach, PARTNER_CELLS, Td, K, out, count, ws, mats)
    return count
