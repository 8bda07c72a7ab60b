"""The complete solver's constants and the layout of its work array.

Every tolerance, window and grid of the solver (:mod:`.complete` and the modules below it),
each with the measurement that set it, and the one work array a pose uses (``ws``, sized
WORK_SIZE): its named blocks (``W_*``) and the stack of 4 x 4 matrices at its start (``mats``,
entries ``MAT_*``). Also the one angle wrap, to (-pi, pi] (:mod:`ik7r.geometry.rotations`).
"""

from __future__ import annotations

import math

from ..geometry import rotations
from .jit import shared
from .poly import ISOLATE_WORK, MAX_DEGREE, REFINE_GRID

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
#: magnitude and the parabola through it and its neighbours dips toward zero (:func:`dips_to_zero`):
#: a factor's minimum between grid points reads higher on the grid; one IRB 5400 pair beside the
#: stretched elbow read 6.6e-2 on the grid and 9e-5 at its minimum)
NEAR_RATIO_GRID = 0.25
#: ... and, at its refined minimum, for one factor of G at an end of the range (see
#: :func:`_near_misses`; inside the range a factor's grid minimum is held to NEAR_RATIO as G's) ...
NEAR_RATIO_END = 1e-4
#: ... but to this at the fold's end of a twist below 45 deg (where the range ends at the fully
#: bent wrist itself): a mirrored member with a lateral offset (deviating by 0.098 mm) had a
#: source with its wrist 0.041 rad from fully bent and no other solution near, from a factor's
#: minimum just beyond the fold at 2.8e-4 (missed). (At every end, on the 45 deg rounded robot's
#: singular-set poses, the fully bent wrist's answers moved by 2e-6 within its flat valley and
#: its rows took 3 to 9 % longer.)
NEAR_RATIO_FOLD_END = 1e-3
#: A grid value beside a root's cell, of one sign with its other neighbour and below it, that is
#: within this fraction of its terms: the cell on that side is searched for a minimum of its own
#: (:func:`_near_misses`). A cluster (a near miss in the cell before a simple root) hides its dip
#: there: a mirrored member with a lateral offset (deviating by 0.1 mm) read 1.5e-6 at the grid
#: point, its near miss 8.9e-8 a third of a cell away, the source's among it (missed). Below 1e-5
#: the test runs at 0.03 to 0.2 grid points a pose of the deviating benchmark robots.
NEAR_RATIO_ROOTSIDE = 1e-5
#: Most candidate roots of one pose: every bracket (24) may give REFINE_GRID + 2 candidates, and
#: on a deviating model the near misses (:func:`_near_misses`) three starts per grid point of
#: each of up to three residuals on NEAR_GRID + 1 points (a local minimum or a root's side each).
ROOT_CAP = 24 * (REFINE_GRID + 2) + 3 * 3 * (NEAR_GRID + 1)
#: solve_config skips candidates whose indicators differ beyond this margin (rad) from a
#: boundary (larger for deviating models, whose polish moves the joints further).
FILTER_MARGIN = 1e-3
FILTER_MARGIN_DEVIATING = 0.1
#: Window (rad) around theta5 = 0 and pi where solutions are tried at exactly 0 or pi first, and
#: where nearly folded solutions merge into the folded one.
FOLD_WINDOW = 1e-4
#: On the idealised model the wrist is snapped to theta5 = pi only this close (rad) to it: the two
#: wrist solutions +-(pi - eps) beside the fold are 2 eps apart (every other joint closer), so
#: below eps = DUP_TOL / 2 they are one solution (:func:`add_answer`), above it two, each exact, while
#: theta5 = pi between them only meets the pose within the tolerance (the paper robot at
#: eps = 2.4e-5: 2.5e-11 mm at best, its segment to either solution inexact by 7e-9 mm).
FOLD_SNAP = 0.5 * DUP_TOL
#: A solution with theta5 within this (rad) of 0 is exactly straight: only s4 q4 + s7 q7 counts.
STRAIGHT_EXACT = 1e-9
#: Two exact solutions closer than this (rad, every joint) are one when the segment between
#: them is exact too, or, both on the shoulder set, a walk of VALLEY_WALK points (see
#: :func:`add_answer`). Near the shoulder set and the straight wrist at once the pose may be met
#: along a curved valley longer than this (an exact 45 deg member 1.6e-3 rad from straight: 0.17
#: rad in q4 and q7, least error 2.5e-11 mm, three exact roots): its answers come at least this
#: far apart, each one solution with its part of the valley.
MERGE_WINDOW = 1e-2
#: A solution on the shoulder set (its virtual wrist centre on axis 1) lies in a valley where
#: the FK is flat in q1 (with the wrist nearly straight, also in q7): the polish stops at the
#: first point within the tolerances, at the edge of a band up to 1e-2 rad wide, and one
#: solution comes twice, once from each side, a straight segment apart that leaves the valley.
#: Such answers are polished on toward FLOOR times the tolerances (at most FLOOR_ITERS Newton
#: steps; see :func:`floor_shoulder`), which takes them to the solution's root within DUP_TOL.
FLOOR = 1e-3
FLOOR_ITERS = 4
#: A candidate snapped to the fully bent wrist (theta5 = pi) that misses the pose by no more than
#: this times the tolerances misses it by rounding alone (an exact member: 1.27 times, 1e-12 rad
#: from its source; an exact member with lateral offsets and a 17.8 deg twist: 11.4 times, 1e-7
#: rad from it): where Newton's step is not defined it is polished with joint 5 held (see
#: :func:`ik7r._kernels.answers._polish_exact`). Far farther off (1.5e6 times), on a 45 deg
#: twist, that polish travelled 0.12 rad along the fold's flat valley.
SNAP_ROUNDING = 1e3
#: Axis 4 on axis 1 (the arm stretched along it: the paper robot's q2 = 90, q3 = -90 deg) turns
#: joints 1 and 4 together without moving the tool: an exact solution there is a continuum, kept
#: once, at the seed's q1 (else 0; see :func:`add_answer`). An exact point within CONTINUUM_WINDOW (rad,
#: every joint) of the continuum's point at its own q1 is that solution when a walk from that
#: point to it stays exact (:func:`walked`, its points WALK_STEP apart): next to the continuum
#: the FK is flat, and the scans' exact points there (and the continuum's own isolated neighbours,
#: whose Jacobian's smallest singular value is about 1e-14 of its largest) are its shadows. In a
#: pose with such a continuum the same walk joins two exact points of the shoulder set this close
#: (elsewhere it would join distinct solutions of a near-shoulder pose, 1.3e-3 rad apart in q1,
#: that the straight segment of :func:`_joined` keeps apart).
CONTINUUM_WINDOW = 3e-2
WALK_STEP = 2e-3
WALK_MIN = 4  # (points at least: a walk shorter than WALK_STEP is checked at its quarters too)
#: ... and at least this many where two nearly straight solutions of a deviating model would be
#: one valley (see :func:`ik7r._kernels.answers._valley_pair`)
VALLEY_WALK = 40
#: ... and nearly straight solutions farther apart on one circle of the straight wrist are
#: walked only on a model whose deviation moves a pose by at most this many tolerances
#: (``ik7r.robot.family.Family.deviation_effect``; see :func:`ik7r._kernels.answers._valley_pair`)
CIRCLE_WALK = 1e4
WALK_SLACK = DUP_TOL  # (how much farther than twice its share a walk's step may move a joint)
#: ... and a point of the continuum turned to another joint 1 that misses the pose by no more
#: than this many times the tolerances is polished onto it (see :func:`_turn_onto`).
TURN_SLACK = 100.0
#: A candidate of the idealised model on the shoulder singular set (:func:`on_shoulder_set`)
#: whose Jacobian is singular is polished by damped steps (:func:`ik7r._kernels.fk.polish`) when
#: no solution found lies within this (rad, every joint): there a nearly straight wrist makes
#: clusters of exact solutions, and axis 7 on axis 1 continua, whose members Newton cannot
#: polish. Closer to a solution found, the candidate is taken for a shadow of it and polished by
#: plain Newton steps (damped steps there merged the candidates beside the fold into the solution
#: found). That is a measured rule, not a bound: the FK is flat along the cluster, not across it
#: (1e-3 rad off an exact solution in a random direction misses the pose by 0.2-0.9 mm on the paper
#: robot), so a second exact solution within 1e-3 rad relies on Newton (docs/guide/edges.md).
SINGULAR_ALONE = 1e-3

#: Grid of the theta5 scan of an undecided bracket (see :func:`scan_theta5`), and how close to
#: zero (rad) a local minimum of its bend gap must come to be a candidate (exact, deviating).
SCAN_GRID = 32
SCAN_PIECES = 12  # the grid and the pieces (next to branch ends, around dips) it may add
#: The fold scan's first grid (see :func:`ik7r._kernels.scans._fold_splits`) adds at most this
#: many pieces of its own: the two sides of each cell where the shoulder branches meet, the
#: sides of a hole in a branch (its elbow stretching and back between grid points)
FOLD_SPLIT_PIECES = 8
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
#: ... and this close on a (nearly) 45 deg twist where the line comes closest to axis 1 within
#: the fold scan's span (FOLD_SPAN in u): there the roots crowd in theta5 as theta1 swings, and
#: the fold scan's grid in sw, unlike the polynomial, has no cluster test (an exact member at
#: 2.3e-4 of the size: two roots 1.8e-3 apart in sw within one of its cells, beside a third in
#: the next, lost; in theta1 they are 1.4 rad apart)
SHOULDER_NEAR_FOLD = 2e-3
#: ... and a cell of its first grid where the gap's shoulder branch switches (the gap jumps) is
#: scanned as two pieces, one each side of the switch, where the gap at one of the cell's ends
#: is within this (rad) of zero (seen: -1.2e-5 beside a pair of solutions 3e-3 apart; a switch
#: lies in nearly every pose's turn, and splitting each cost the exact members' near-shoulder
#: rows twice their time)
SHOULDER_SWITCH_NEAR = 1e-3
#: ... and this for a model that deviates from the idealised one (near the set its solutions come
#: in clusters the idealised roots do not have: the nominal gap's dips are candidates there),
#: relative to the larger of the size and the line's d there (:func:`shoulder_offset`; this and
#: the two windows below)
SHOULDER_SCAN_DEVIATING = 2e-3
#: ... and for an arm with a lateral offset b, whose shoulder set is the cylinder of radius abs(b)
#: about axis 1 (the two shoulder branches meet there): a virtual centre this far inside it
#: (relative to the size, in distance) is on it, one merged branch: the rounding of a root there
#: (an exact member's centre came 1.7e-13 mm inside at its source's root, 6e-17 of its size, and
#: the squared test it had, r^2 - b^2 against -(1e-9 of the size)^2, which that makes -7.6e-11,
#: dropped the root: 77 sources of 16 members missed on the cylinder). Beyond it the branch is
#: not defined (the fold scan's meetings of the branches are checked 1e-9 in sw beyond) ...
LATERAL_ROUNDING = 1e-12
#: ... and on a deviating model this far, its exact solutions lying beside the cylinder where the
#: idealised centre falls inside it (0.07 and 0.13 mm inside on two hunted members); the polish
#: takes the merged branch's candidates onto the exact model (see
#: :func:`ik7r._kernels.candidates.solutions_at`, and the bend gap with the centre taken onto the
#: cylinder, scanned where the line of centres runs inside it: ``scans._lateral_inside``)
LATERAL_SHOULDER_DEVIATING = 2e-3
#: A root of the fold gap this close (in sw) to where its two shoulder branches meet on the
#: lateral offset's cylinder, but where neither is defined, is taken at the meeting (an exact
#: 45 deg member's root 1e-10 inside, its bracket's end: the source missed)
FOLD_MEET_SNAP = 1e-8
#: ... where the nominal shoulder gap has a dip below SHOULDER_DIP (rad), the exact model's
#: reduced residual in q1 is tracked SHOULDER_REACH (rad) each way from the dip's bottom, on
#: SHOULDER_CELLS cells each way (see :func:`_shoulder_exact`; the IRB 5400's exact solutions
#: were measured up to 0.11 rad from the bottom, beyond the dip's two cells of the turn's grid)
SHOULDER_DIP = 0.1
SHOULDER_REACH = 0.4
SHOULDER_CELLS = 8
#: ... and where such a scan ends with the error's norm still below DIP_NEAR, in the dip's
#: valley, its residual crossing zero over the last cell or falling to less than half toward it,
#: it goes on by as much again, up to SHOULDER_VALLEY_END (rad) from the bottom: a member
#: whose wrist offsets are 0.13 mm had a sheet's roots at 0.134 and -0.070 (the source), 0.37
#: and 0.57 rad from the bottom, the error 1.6e-5 at the reach and 2e-3 only 0.6 rad beyond it
SHOULDER_VALLEY_END = math.pi
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
#: ... these windows (and SHOULDER_SCAN_DEVIATING) were measured on models whose deviation moves
#: a pose by at most this much of their size (the family's ``deviation_effect`` in tolerances:
#: the IRB 5400 1.45e-4, the rounded robots 1.47e-4); on a model that deviates further they widen
#: in proportion (:func:`shoulder_offset`): a member whose deviation reaches 3.1e-4 had an exact
#: solution 1.9 rad in q1 from any other, at a nominal dip with the line 5.8e-4 from axis 1
SHOULDER_EFFECT_REF = 1.5e-4
#: ... and where no arm of the turn reaches the virtual centre (the elbow stretched or folded,
#: within the deviation of the exact model's reach), the whole turn is tracked from the nearest
#: arm of the first that misses it by less than this in the elbow's cosine (rounded_b45: a
#: source whose nominal arm is 0.026 mm, 7.2e-6 in the cosine, short of folded enough), times
#: :func:`ik7r._kernels.singular.deviation_widening` on a model that deviates further than the
#: published ones (a 45 deg member deviating 1.27 times as far: every arm short by 1.05e-3)
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
#: :func:`gap_near_misses`)
GAP_NEAR_GRID = 0.05
#: ... and one that comes below this (rad) without crossing zero is a candidate: beside the elbow
#: stretch, where the gap is steep, a near miss of 0.0148 gave a pair of exact solutions on a
#: rounded member (more than SCAN_NEAR_DEVIATING, the scans' threshold)
GAP_NEAR_DEPTH = 0.03
#: Near the fold of a (nearly) 45 deg twist the virtual centre's distance grows as 1 / sw^2 and a
#: deviating model's arm branch ends (the elbow stretched) where the nominal one does not: the
#: fold scan takes a branch's end itself as a candidate when the fold gap there is below this
#: (rad; 0.02 .. 0.025 seen on the rounded 45 deg robot of benchmarks/edges.py, and 0.152 at an
#: end 0.022 in sw before the exact solution: tests/ik/test_deviating.py). On the idealised model
#: too: an exact 45 deg member with a lateral offset had a pair of solutions, one per elbow,
#: within 1.4e-7 in theta5 at a branch's end whose gap the grid never saw change sign
FOLD_END_NEAR = 0.2
GAP_NEAR_CELLS = 12
#: (its gaps' grid and the islands' excess grid share the work block of SCAN_GRID + 1 values)
assert 2 * (GAP_NEAR_CELLS + 1) <= SCAN_GRID + 1
#: ... and a grid point beside an arm branch's end (the elbow stretched) whose |gap| falls toward
#: the end is refined up to the end when below this (rad): beside the stretch the gap is steep,
#: and on the rounded 45 deg robot a grid point 0.0512 there had a near miss of 3.6e-3 at the end
GAP_NEAR_END = 0.2
#: ... and beyond such an end the gap of the nominal arm allowed to miss the centre by this in the
#: elbow's cosine (times :func:`ik7r._kernels.singular.deviation_widening`) is searched for a
#: root as well: the exact model reaches further than the nominal one by about its deviation
#: (a member deviating like the published models: a source 0.02 rad in theta5 beyond the end,
#: its nominal arm short by 3e-5 there; see :func:`ik7r._kernels.scans._beyond_the_stretch`),
#: on REACH_SLACK_CELLS cells up to where that slack ends
REACH_SLACK_DEVIATING = 1e-3
REACH_SLACK_CELLS = 8
#: ... and so is each cell beside a grid maximum of the elbow's excess over its reach above
#: -REACH_PEAK (see :func:`ik7r._kernels.scans._near_the_stretch`)
REACH_PEAK = 1e-2
#: Robots whose fully bent wrist is nearly folded back (``u = cos(2 beta)`` below FOLD_NEAR, a
#: twist within about 0.6 deg of 45 deg): their virtual centre runs off to infinity near
#: theta5 = pi, where the residual polynomial cannot be evaluated. The FOLD_SPAN of u next to
#: the fold is searched with the fold gap instead (:func:`fold_gap`, finite there), the rest by
#: the polynomial.
FOLD_NEAR = 0.02
FOLD_SPAN = 0.05
#: ... and on a model that deviates from the idealised one, where a shoulder branch's elbow falls
#: short of the fold gap's centre by no more than this times the deviation (robot units) at a
#: point of the fold scan's grid, the exact model is followed from the stretched arm
#: (see :func:`ik7r._kernels.scans._fold_beyond_reach`; the rounded 45 deg robot's missed sources
#: had the nominal elbow 0.016 .. 0.07 mm short, its deviation 0.05; uniform poses 1.5 mm or more),
#: read on the fold scan's first grid (SCAN_GRID cells)
FOLD_REACH_SLACK = 10.0
#: ... and on the idealised model, where it falls short by no more than this of the robot's
#: size at a grid point (an island of reach narrower than a cell of the fold scan's grid, whose
#: solutions the grid never sees: an exact 45 deg member with a lateral offset, short by 2.8e-4
#: mm at a grid point, 1.1e-7 of its size). On either side the shortfall grew as about 575 mm
#: per unit of sw squared, so an island half a cell from the nearest grid point would need 3e-6
#: of the size; 1e-5 cost the 45 deg offsets member 60 % on its singular-set 99th percentile,
#: 1e-6 nothing measurable. Since the seventh session of 2026-12-04 the least between grid
#: points counts too (FOLD_REACH_DIP): an island anywhere in a cell is followed
FOLD_REACH_ISLAND = 1e-6
#: ... and between grid points (:func:`ik7r._kernels.scans._fold_splits`): every least shortfall
#: of the grid (both neighbours higher), and every greatest one where the branch reaches (both
#: neighbours lower), within this of the size of zero is minimised (maximised) over its two
#: cells by Brent. Below zero the least is an island of reach, above zero the greatest a hole
#: in the branch: pieces of the scan; the least is also the start of _fold_beyond_reach. An
#: island or hole anywhere in a cell is found so for any curvature of the shortfall up to 1e-2
#: of the size per half cell squared (575 mm per unit sw squared was measured: 7e-3 mm at half
#: a cell). The offsets 45 deg member's grid has such a dip in 9 % of its uniform and
#: singular-set poses (276 of 3,000: 89 least, 187 greatest), Brent about 30 shortfalls each
FOLD_REACH_DIP = 1e-2
#: ... and where that greatest shortfall comes within this of the size of zero (below it), the
#: elbow touches the stretch there: the point is a candidate (a tangency of the shortfall, found
#: to about 1e-16 of the size by Brent: a source made with the elbow stretched is often one)
FOLD_TOUCH = 1e-9
#: ... and on a model that deviates from the idealised one, u down to this (of the range) below
#: the fold too (the nominal roots there, theta5 clamped to pi, start exact solutions at the
#: fold; 2e-2 found nothing more over 40,000 poses of four rounded 45 deg robots), on a grid of
#: FOLD_BELOW_CELLS: finer in sw than the span above (see :func:`scan_fold`)
FOLD_BELOW = 2e-3
FOLD_BELOW_CELLS = 8
#: ... and where the scaled virtual centre at the fold is this close to axis 1 (relative to KW
#: and the robot's size; the approach nearly parallel to axis 1; widened with the deviation,
#: see :func:`fold_near_axis`) the fold gap is scanned in theta1 too.
FOLD_AXIS_NEAR = 0.01
#: ... where u up to this below the fold is taken at the fold (see :func:`fold_axis_sw`).
FOLD_AXIS_CLAMP = 1e-9
#: ... and on a model that deviates from the idealised one, the turn of q1 with joint 5 held at
#: the fold (:func:`ik7r._kernels.held.held_fold_turn`, REDUCED_GRID cells): a dip of its grid is
#: searched again over its two cells on this many cells (a member deviating as far as the
#: loader accepts had two dips of the least error 0.026 rad apart, one a pair of solutions, the
#: other a near miss of 2.8e-5) ...
HELD_CELLS = 32
#: ... a grid point being a dip only where its least error (position over the size, or rad)
#: is below this, and a point of the finer grid below HELD_SUB_DIP (the dips of the pairs
#: below: 5e-4 .. 4e-3 on the grid, 3e-5 .. 1.3e-4 on the finer one; a 45 deg robot's
#: near-shoulder poses whose solutions lie 0.05 rad from the fold: 1e-3 and more) ...
HELD_DIP = 1e-2
HELD_SUB_DIP = 1e-3
#: ... each dip taken to its bottom by Brent's minimiser, which stops where the error cannot come
#: below HELD_NEAR in its bracket at HELD_SLOPE times the steeper slope of the dip's two cells on
#: that grid (the error is at most V-shaped at a zero, its slope largest away from the bottom) ...
HELD_SLOPE = 2.0
#: ... and a bottom whose least error (position over the size, or rad) is below this polished
#: with joint 5 free, from the wrist this near and this far (rad) to either side of the fold
#: (pairs of solutions lay at -7e-4 and +7e-3 from it, at -2.5e-4 and -5.7e-3, their bottoms
#: 1e-9 .. 1e-7; a solution at a bend b from the fold leaves about b^2 / 2 there, 5e-5 at the
#: far side, 1e-3 for the 0.05 rad of solutions the fold scans find; near misses 1e-5 .. 3e-5) ...
HELD_NEAR = 1e-4
HELD_SIDE_NEAR = 1e-3
HELD_SIDE_FAR = 1e-2
#: ... each point's four other joints fitted by at most this many Gauss-Newton steps, stopping
#: at a step below HELD_SETTLE (rad: beside a solution 0.05 rad from the fold the fit converges
#: linearly, and a step of 1e-6 moves the error by about as much, far below the thresholds
#: above; at a solution it converges quadratically).
HELD_STEPS = 8
HELD_SETTLE = 1e-6
#: ... and a dip of the turn from the other elbow's arm whose fit is within this (rad, every
#: joint) of one the first turn searched is that one (up to HELD_SEEN dips kept).
HELD_SAME = 1e-4
HELD_SEEN = 16
#: ... and a turn starts at the first grid point where the fit of the fold gap's arm keeps q2
#: and q3 within this (rad) of the arm's: elsewhere it may leave for the other arm's curve.
HELD_ARM = 0.05

#: Straight wrist of a model that deviates from the idealised one (see :func:`straight_family`):
#: a candidate with theta5 below this (rad) starts a scan of the split q4 over the whole turn,
#: on a grid of REDUCED_GRID cells with REDUCED_ITERS Gauss-Newton steps per point; at most
#: NFAMILIES arms per pose are remembered (further ones are scanned without that check).
STRAIGHT_DEVIATING = 2e-2
#: ... and below this where the arm is near the shoulder singular set (its virtual centre within
#: SHOULDER_DEVIATING of the robot's size from axis 1): there the deviation spreads the family's
#: solutions further (to |q5| = 0.07 on the IRB 5400; a rounded member with a1 = 32 mm had its
#: nominal candidates at theta5 = 0.105 and 0.18 and exact solutions at 0.054 and 0.127).
#: So does an arm whose elbow is within STRETCH_DEVIATING of stretched (the sine of the elbow's
#: angle from it): there the arm is singular too, and rounded members with the elbow stretched
#: had exact pairs at q5 = 0.029 and 0.037, 0.031, 0.053 that only the scan found (their nominal
#: candidates 2e-4 .. 1.6e-3 from the stretch).
STRAIGHT_SHOULDER = 0.2
SHOULDER_DEVIATING = 1e-2
STRETCH_DEVIATING = 3e-2
#: An exact member's candidate whose elbow is within this of stretched or folded (the sine of
#: its angle from there) is polished with damped steps where Newton's step is not defined (the
#: arm singular; with the wrist straight too: an exact 16 deg member with a lateral offset had
#: no answer at all for three poses made with the elbow stretched and the wrist within 3e-7 of
#: straight, see :func:`ik7r._kernels.answers._polish_exact`)
STRETCH_EXACT = 1e-4
REDUCED_GRID = 48
#: ... and a grid value of the reduced residual below this fraction of both its neighbours (one
#: sign) is a dip to minimise (see :func:`dips_to_zero`)
DIP_SHARP = 0.1
#: ... and a grid point whose least-squares error ``|e|`` (position over the size, and rad) is a
#: local minimum below this is a dip whatever the shape of its neighbours: a near miss of the
#: order of the deviation. Near the shoulder set the five other joints' least squares sharpen the
#: residual into a notch narrower than a cell, which no three grid values can tell from a
#: shallow minimum (generated(2): a pair of roots 0.015 rad apart under values -9.0e-8, -6.1e-8,
#: -3.1e-7 of ``r``, ``|e|`` 3.9e-5, 1.4e-5, 5.9e-5).
DIP_NEAR = 1e-4
#: ... and a cell beside a sign change over which ``|r|`` grows to less than this fraction of
#: what the root's slope (the sign change's secant) makes it is searched with the next cell for
#: the residual's turn toward the other sign: a second pair of roots there (a rounded 45 deg
#: member's straight wrist: roots 0.038 apart under a hump of 4.7e-11 in the cell after the
#: next root, whose ends were -2.6e-10 and -1.1e-9, the secant's slope making 8.9e-9). On the
#: straight wrist's split alone (``straight_family``): in q1 at the shoulder set stalls are
#: everywhere, and searching them cost the IRB 5400's near-shoulder poses half their time again
#: and found nothing over 27,000 poses
REDUCED_STALL = 0.1
REDUCED_ITERS = 4
#: ... stopping before a step below this (rad; see :func:`_reduced_at`)
REDUCED_SETTLE = 1e-5
#: ... and where the whole turns in q1 of both wrist signs end on one curve (their last points
#: within CLOSED_TOL: from a start far from the least-squares point, or where the wrist passes
#: straight, both took one branch and left the other to the dip-centred scans), the turn is
#: tracked again once per sign (``reduced_scan(..., one_sign=True)``, see
#: :func:`ik7r._kernels.scans._q1_scans`): its start first taken to its least-squares point (at
#: most TURN_START_ROUNDS rounds of Gauss-Newton), a point whose wrist passes straight to the
#: other sign taken onto the other wrist's branch (the two meet there, so the scans of the two
#: signs together cover both branches), and a point that jumps off the branch (``|e|`` above
#: DIP_NEAR and TRACK_JUMP times the point before's, Gauss-Newton not settled) solved again from
#: its prediction with the wrist solved for the arm's target. Over 40 near-shoulder poses of the
#: IRB 5400 that is 8 scans more to 144 whole turns.
TURN_START_ROUNDS = 12
TRACK_JUMP = 10.0
#: ... and a point of the straight wrist's split scan (j = 3) whose ``|e|`` is above TRACK_JUMP times both
#: neighbours' while these lie in a root's valley (below DIP_NEAR) jumped off the branch: the two
#: cells around it are scanned again on JUMP_CELLS cells from the point before (at most JUMP_NOTED
#: such points a scan; see :func:`ik7r._kernels.reduced.straight_family`). A point at q4 = 1.571
#: jumped between four roots within 0.33 rad (|e| 9.9e-4 against 9.3e-8 and 1.6e-6 beside it), and
#: the two cells showed one sign change for three roots: a member's source was missed.
JUMP_CELLS = 8
JUMP_NOTED = 4
#: ... and a scan over the whole turn in q1 (:func:`ik7r._kernels.scans._shoulder_turn`) notes
#: runs of up to TURN_JUMP_WIDTH such points whose neighbours lie below TURN_JUMP_VALLEY, and
#: scans each run's cells again the same way. Near the shoulder set the tracked curve sweeps
#: q4 by a radian a cell where the wrist is nearly straight: a member's scan jumped off the valley
#: for three points (|e| 3.3e-2, 6.2e-2, 2.4e-2 between 3.3e-4 and 1.1e-4) and missed the source
#: 0.03 rad in q1 beyond the first.
TURN_JUMP_WIDTH = 3
TURN_JUMP_VALLEY = 1e-3
#: ... and such a scan's point whose theta5 is within this (rad) of pi is at the fully bent wrist:
#: Gauss-Newton cannot move it off (the same wrist to first order either side), the scan leaves
#: it on one side, and the cell where it does is scanned again from the point beyond with
#: theta5 mirrored about pi (see :func:`ik7r._kernels.reduced._note_bent_exits`). A member's scan
#: sat at pi for 15 points and left it below pi; its source was 0.06 rad in q1 beyond, above pi.
BENT_STUCK = 1e-3
#: ... and after the whole turn from the first grid point whose nominal arm reaches the centre,
#: the turn again from the nominal arm half a turn on (near axis 1 the centre is reached in
#: front and over the back, each a curve of its own in q1 that a turn from the other need not
#: come onto), each wrist sign whose settled start lies within this (rad, every joint) of a
#: whole turn's grid point there skipped (see :func:`ik7r._kernels.reduced.turn_tracked`).
#: Members deviating 2 to 5 times as far as the published models had a source on such a curve
#: untracked (the wrist bent 0.64 rad, the arm 0.12 and 0.18 rad from the tracked ones'); on
#: 30 of the IRB 5400's near-shoulder poses 21 of 108 such starts were untracked, the same ones
#: for any bound from 1e-3 to 0.1.
TURN_TRACKED = 1e-2
#: ... and such a scan stops where two of its points in a row lie within this (rad, every joint)
#: of a whole turn of the pose scanned before: it has joined that turn's curve, whose rest is
#: scanned (see :func:`ik7r._kernels.reduced._turn_joins`). On 30 of the IRB 5400's
#: near-shoulder poses 17 of the 21 such scans joined one, after 2 to 46 cells (the points
#: within 1e-9 of the turn's two or three cells on); curves that only pass each other came
#: within 1e-2 and left again (their distances 1e-2, 4e-2, 9e-2 a cell apart).
TURN_JOIN_TOL = 1e-6
#: ... and a root of it refined until the residual the last step would leave is below this
#: (position over the size, and rad): the point is then within REDUCED_SETTLE of the solution
#: in the other joints anyway, which the polish on the exact model takes to the last bits
#: (see :func:`_reduced_root`)
REDUCED_ROOT_TOL = 1e-9
#: ... and where an end of a cell with a sign change is itself a root (its error ``|e|`` below
#: REDUCED_ROOT_TOL), Illinois stops at that end's root: the change may be that root's own with
#: a second root inside the cell. The cell is then refined again down to its bracket (a root
#: between the end and the read below: the IRB 5400, a straight wrist, roots of the split at
#: q4 = pi - 2.7e-4 and pi + 1.6e-4 astride a grid point), and its signs are read again
#: ROOT_END_STEP of the cell inside such an end, a change there refined too (rounded_gen2, a
#: straight wrist: roots of the split at q4 = -pi/2 - 2e-5, next to a grid point, and 0.073 rad
#: inside its cell; see :func:`ik7r._kernels.reduced.reduced_scan`)
ROOT_END_STEP = 1e-2
#: ... and a scan over the whole turn whose last point is within this (rad, every joint) of its
#: first has come back to its start: a closed curve (see :func:`reduced_scan`)
CLOSED_TOL = 1e-4
NFAMILIES = 8
#: Deviating models: a solution whose Jacobian's smallest singular value (position rows over the
#: robot's size, relative to the largest) is below this may have a partner the idealised model
#: does not have (see :func:`partners`), looked for up to PARTNER_REACH (rad) away (times
#: ``singular.deviation_widening`` on a model that deviates further than the published ones).
PARTNER_SIGMA = 2e-3
#: ... and a solution with no other one within this (rad, joints 1 to 3) whose theta5 has the
#: other sign starts a polish from its arm with the other wrist (see :func:`other_wrists`)
OTHER_WRIST_ARM = 1e-2
PARTNER_REACH = 0.3
#: ... and where the partner step finds nothing new, the reduced residual in the joint the
#: singular vector moves most is scanned this many cells each way (PARTNER_REACH times that
#: joint's share of the vector), from PARTNER_STEP of a cell beside the solution (where the
#: residual is zero, so that the first cell's sign test would read its rounding)
PARTNER_CELLS = 4
PARTNER_STEP = 0.1

#: Largest number of Bernstein coefficients, and of brackets.
NCOEF = MAX_DEGREE + 1
NBRACKETS = 24


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
MAT_T07, MAT_R07, MAT_M, MAT_Q, MAT_T, MAT_WR, MAT_PSI, MAT_CW, MAT_WALK = range(9)
#: The entry MAT_CW of the stack: the joint 1 of the turn of axis 4 on axis 1 (see :func:`add_answer`),
#: at this index of its 16 values (the seed's q1, else 0), and at CW_FOUND 1 once the pose has
#: such a continuum; the rest is the turn's scratch. The entry MAT_WALK: a walk's point and the one
#: before it (:func:`walked`).
CW_REF = 12
CW_FOUND = 13
CW_SHOULDER = 14  # (1 once a solution on the shoulder set was added: see :func:`floor_shoulder`)
#: Models that deviate from the idealised one: the starts already followed to the exact model in
#: this pose and what became of them (see :func:`_tried`), MEMO_SIZE of them (a ring, two per
#: 4 x 4 entry of the stack from index MAT_MEMO on; their count in the entry MAT_MEMO_N).
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
#: The straight wrist of a deviating model with the elbow (nearly) stretched or folded: the
#: split is tried from STRETCH_SPLITS starts over the whole turn, each polished by damped steps
#: for at most STRETCH_ITERS, STRETCH_CHUNK at a time (a chunk that does not bring the error below
#: STALL_RATIO of itself ends the start: see :func:`ik7r._kernels.reduced._split_polish`; chunks
#: of 12 found three sources more of 18,000, at 10 % more on the IRB 5400's singular-set p99), where
#: a candidate arm's elbow is within STRETCH_DEVIATING of the stretch (the sine of its angle
#: from it) and the wrist within STRETCH_STRAIGHT of straight; once per
#: arm within STRETCHED_TOL (rad, each joint) of one tried before in the pose (NSTRETCHED of
#: them noted). The nominal arm misses the exact one by about the square root of the deviation
#: there (a rounded member: 2e-3 in the elbow's sine, 2.5e-2 rad in the arm, the wrist 2.4e-2
#: from straight): windows of 1e-3 and 2e-2 left 226 of 6,000 corner sources missed, these 18
#: (docs/guide/edges.md, 2026-12-05).
STRETCH_SPLITS = 48
#: ... and between two roots of the split they found, the reduced residual is read this fraction
#: of the way from each (see :func:`ik7r._kernels.reduced._split_parity`)
SPLIT_PARITY_STEP = 0.1
STRETCH_ITERS = 60
STRETCH_CHUNK = 6
STRETCH_STRAIGHT = 5e-2
NSTRETCHED = 8
STRETCHED_TOL = 1e-2
#: ... and a point kept there whose wrist is within STRAIGHTEN_REACH (rad) of straight is
#: polished with the wrist held straight (STRAIGHTEN_ITERS damped steps); where that meets the
#: pose and a walk joins it to the point, the straight one is kept: the valley reaches the Wrist
#: indicators' boundary, and its point there belongs to both (see
#: :func:`ik7r._kernels.answers.straightened`; also for any answer where Newton's step is not defined)
STRAIGHTEN_REACH = 1e-4
STRAIGHTEN_ITERS = 12
#: A polish on an intermediate model of the homotopy stops once its Newton step is below this
#: (rad; the error left is of the order of its square): the forward kinematics that would verify
#: it is not needed there.
HOMOTOPY_SETTLE = 1e-4
#: The whole-turn reduced scans of this pose (:func:`reduced_scan` over REDUCED_GRID cells) that
#: tracked a curve of their own, SCAN_MEMO of them (a ring). A later scan over the same grid
#: whose two last points coincide with an earlier one's within SCAN_MEMO_TOL (rad, every joint)
#: has joined its curve: the rest of its grid is that scan's (each point is Gauss-Newton from
#: the extrapolation of the two before it), and so is the refinement of every cell whose points
#: coincide. Near the shoulder set the candidates of one straight-wrist family, up to 0.3 rad
#: apart in q1, each track the same two sheets (a rounded 45 deg robot: 26 scans of 4 curves).
SCAN_MEMO = 16
SCAN_MEMO_TOL = 1e-9
SCAN_HEAD = 5  # j, v0, v1, m, closed; then per grid point its six joints, r and |e|
SCAN_SLOT = SCAN_HEAD + 8 * (REDUCED_GRID + 1)
MAT_MEMO = 9
MAT_MEMO_N = MAT_MEMO + MEMO_SIZE // 2
NMATS = MAT_MEMO_N + 1
_W, WORK_SIZE = _offsets(
    MATS=NMATS * 16, P=3, A=3, TH=10, Q6=6, QQ=6,
    BLO=NBRACKETS, BHI=NBRACKETS, BSURE=NBRACKETS, FOUND=REFINE_GRID + 2,
    BCOEF=NBRACKETS * NCOEF, CAST=NCOEF, ISO=ISOLATE_WORK, ROOTS=ROOT_CAP, NB=1,
    SCAN=SCAN_GRID + 1, SUB=2 * (SCAN_PIECES + FOLD_SPLIT_PIECES), FAM=4 * NFAMILIES, NFAM=1,
    PAIR=2 * (SCAN_GRID + 1), SHORT=2 * (SCAN_GRID + 1), SPLIT=2 * FOLD_SPLIT_PIECES, LEAST=4,
    RSCAN=SCAN_MEMO * SCAN_SLOT, NRSCAN=1, SDIP=2 * SHOULDER_DIPS, NSDIP=1,
    STR=3 * NSTRETCHED, NSTR=1, SEND=9, TEND=6, JUMP=1 + 8 * JUMP_NOTED,
)
W_MATS, W_P, W_A, W_TH, W_Q6, W_QQ = _W["MATS"], _W["P"], _W["A"], _W["TH"], _W["Q6"], _W["QQ"]
W_BLO, W_BHI, W_BSURE, W_FOUND = _W["BLO"], _W["BHI"], _W["BSURE"], _W["FOUND"]
W_BCOEF, W_CAST, W_ISO, W_ROOTS = _W["BCOEF"], _W["CAST"], _W["ISO"], _W["ROOTS"]
W_NB, W_SCAN, W_SUB = _W["NB"], _W["SCAN"], _W["SUB"]
NTH = 10  # the arm's cosines and sines, theta5, and O4 (see :func:`fold_gap`)
W_FAM, W_NFAM, W_PAIR, W_SHORT = _W["FAM"], _W["NFAM"], _W["PAIR"], _W["SHORT"]
W_SPLIT, W_LEAST = _W["SPLIT"], _W["LEAST"]
W_RSCAN, W_NRSCAN = _W["RSCAN"], _W["NRSCAN"]
W_SDIP, W_NSDIP = _W["SDIP"], _W["NSDIP"]
W_STR, W_NSTR = _W["STR"], _W["NSTR"]
W_SEND = _W["SEND"]  # (the last reduced scan's last grid point, its |e|, r there and before: reduced_scan)
W_TEND = _W["TEND"]  # (the first wrist sign's whole turn's last point: _q1_scans)
W_JUMP = _W["JUMP"]  # (the last split scan's jumped points: count; cell ends and point before each)


# the one angle wrap, to (-pi, pi], and the exact reduction under it (ik7r.geometry.rotations)
shared(rotations.remainder_2pi_below_2_26)
remainder_2pi = shared(rotations.remainder_2pi)
wrap = shared(rotations.wrap)
