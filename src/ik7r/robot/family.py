"""The robot family ik7r solves, and the nominal (idealised) parameters its solvers use.

A member is a serial chain of seven revolute joints in Craig's modified DH convention with

* an ``R perp R parallel R`` arm: ``alpha0 = 0, a0 = 0``, ``alpha1 = +-90 deg``, ``alpha2 = 0``,
  ``alpha3 = +-90 deg``; any shoulder offset ``a1``, upper arm ``a2``, elbow offset ``a3``,
  lateral offset ``d2 + d3``, base height ``d1`` and forearm ``d4``;
* a hollow wrist whose axes 4-5, 5-6 and 6-7 intersect (``a4 = a5 = a6 = 0``) with twists
  ``(-beta, 2 beta, -beta)``, ``0 < |beta| <= 45 deg`` (:data:`MAX_BETA`), equal offsets
  ``d5 = d6`` and a flange
  offset ``d7``;
* joint 6 mirror-coupled to joint 5 (``theta6 = -theta5`` in DH angles).

A model that deviates from this by less than the tolerances below (a published model with
rounded numbers, such as ROS-Industrial's ABB IRB 5400) is still of the family: the solvers
work on the idealised model and polish every solution on the exact one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..errors import FamilyError

#: Twist angles must match the family within this (rad, about 0.06 deg).
ANGLE_TOL = 1e-3
#: Offsets that must vanish (a4, a5, a6) and the difference d5 - d6 must stay within this
#: fraction of the robot's size (about 1 mm on a 1 m arm).
LENGTH_TOL = 1e-3
#: Largest rotation residual of a returned solution (rad; every element of the rotation matrix).
ROTATION_TOLERANCE = 1e-12
#: A table that differs from its idealised member so little that no pose moves by more than this
#: fraction of the tolerances (the lengths' differences, plus the twists' and the mirror offset's
#: times the robot's extent; the twists' alone against ROTATION_TOLERANCE) is solved as that
#: member (deviation 0), its answers still checked on the table as written. Such differences are
#: the rounding of a unit conversion (a URDF in metres: d6 = 80.00000000000001 mm) or of the
#: offsets' sum (theta5 + theta6 = 4e-16 rad): solved as a deviating model, an exactly straight
#: wrist then met the pose along most of the turn of q4 and filled the output (issue 12).
NEGLIGIBLE = 1e-2
#: Largest wrist twist (rad): 45 deg. There the fully bent wrist (theta5 = 180 deg) folds axis 7
#: back parallel to axis 4 and its virtual wrist centre is at infinity (the search runs in
#: u = 1 / d, which stays bounded).
MAX_BETA = math.radians(45.0)

# ------------------------------------------------------------------ numeric ranges (issue 12)
# A member is refused (FamilyError naming the parameter) when float arithmetic cannot meet the
# promised tolerances (docs/guide/ranges.md derives these numbers).

#: Smallest robot size (``Family.scale``, the robot's unit): below it the residual polynomial's
#: terms (up to the 24th power of a length) leave the float range.
MIN_SIZE = 1e-6
#: ``position_tolerance`` must be at least this fraction of the robot's extent (its size plus
#: ``|d1|``, ``|d2|``, ``|d3|`` and the base and tool translations): the float spacing of the
#: coordinates (1.1e-16 of them) leaves room for the solver's rounding. With the tolerance
#: ``min(1e-9, 1e-12 size)`` this admits robots up to 1e5 units (100 m in mm) and bases or
#: tools up to 100 times the robot's size away.
MIN_RELATIVE_TOLERANCE = 1e-14
#: The upper arm ``|a2|`` and the wrist offsets ``|d5| = |d6|`` must be at least this fraction
#: of the size: with ``a2 = 0`` joints 2 and 3 turn about one axis, with ``d5 = d6 = 0`` the four
#: wrist axes meet in one point (neither robot has six degrees of freedom).
MIN_LINK_RATIO = 1e-4
#: Largest |angle| (rad) of a DH twist, theta offset or coupling offset given in radians; smaller
#: ones are reduced modulo 2 pi exactly (TOML files give degrees, reduced modulo 360 exactly, so
#: any finite value in degrees is accepted).
MAX_ANGLE_PARAMETER = 1e6
#: Largest |joint limit| (rad, 15.9 turns): beyond it the float spacing of the angle and of its
#: 2 pi multiples (the multi-turn expansion) would move the tool by more than the tolerance.
#: Seeds are periodic: a seed joint beyond it is reduced modulo 2 pi to (-pi, pi].
MAX_JOINT_ANGLE = 100.0

# 2 pi to 40 digits, for reducing angles without the rounding of the float 2 pi
_TWO_PI_EXACT = Fraction("6.283185307179586476925286766559005768394")


def reduce_angle(x: float, name: str = "angle") -> float:
    """``x`` (rad) reduced modulo 2 pi to [-pi, pi] with the exact 2 pi (not the float one, whose
    multiples drift by 2.4e-16 per turn); a FamilyError naming ``name`` beyond
    :data:`MAX_ANGLE_PARAMETER`."""
    x = float(x)
    if not abs(x) <= MAX_ANGLE_PARAMETER:
        raise FamilyError(f"{name} must be within +-{MAX_ANGLE_PARAMETER:g} rad; got {x!r}")
    if abs(x) <= math.pi:
        return x
    k = round(x / (2 * math.pi))
    return float(Fraction(x) - k * _TWO_PI_EXACT)


def frame_dh(dh: np.ndarray) -> tuple[np.ndarray, bool]:
    """The DH table ``dh`` (7, 4) in the frames the solvers use, the same robot (the same forward
    kinematics for the same user joints): twists and theta offsets reduced modulo 2 pi, and a
    negative upper arm ``a2`` made positive by turning frame 2 by pi about its z axis (``a2`` and
    ``alpha2`` change sign, ``pi`` moves from theta3's offset to theta2's), and a mirror wrist of
    negative ``beta`` (twists ``(+b, -2 b, +b)``) made positive by turning frames 4 to 6 by pi
    about their z axes (the three twists and the three lengths ``a4 .. a6`` before them change
    sign, ``pi`` is added to theta4's offset and taken from theta7's: ``RotZ(pi) RotX(al)
    TransX(a) RotZ(-pi) = RotX(-al) TransX(-a)``; the kernels take ``beta`` > 0, as the half
    angles of :mod:`ik7r._kernels.wrist` do). Returns the table and whether the upper arm was
    flipped."""
    out = np.array(dh, dtype=float)
    for i in range(7):
        out[i, 1] = reduce_angle(out[i, 1], f"alpha{i} (joint {i + 1})")
        out[i, 3] = reduce_angle(out[i, 3], f"theta_offset{i + 1} (joint {i + 1})")
    flipped = bool(out[2, 0] < 0.0)
    if flipped:
        # T12 RotZ(pi) and RotZ(-pi) T23 = RotX(-alpha2) TransX(-a2) RotZ(theta3 - pi) TransZ(d3)
        out[2, 0] = -out[2, 0]
        out[2, 1] = -out[2, 1]
        out[1, 3] = math.remainder(out[1, 3] + math.pi, 2 * math.pi)
        out[2, 3] = math.remainder(out[2, 3] - math.pi, 2 * math.pi)
    if out[4, 1] > 0.0 and out[5, 1] < 0.0 and out[6, 1] > 0.0:
        # T34 RotZ(pi), RotZ(-pi) through T45 T56 T67 (twists and lengths a4 .. a6 negated: zero
        # on a member, not on a model that deviates from one), RotZ(-pi) into theta7
        out[4:7, 0] = -out[4:7, 0]
        out[4:7, 1] = -out[4:7, 1]
        out[3, 3] = math.remainder(out[3, 3] + math.pi, 2 * math.pi)
        out[6, 3] = math.remainder(out[6, 3] - math.pi, 2 * math.pi)
    out.setflags(write=False)
    return out, flipped


@dataclass(frozen=True)
class Family:
    """Nominal parameters of a family member (lengths in the robot's unit, angles in rad)."""

    a1: float
    a2: float
    a3: float
    b: float  # lateral offset d2 + d3
    d1: float
    d4: float
    eps1: float  # alpha1 = eps1 * 90 deg
    eps3: float  # alpha3 = eps3 * 90 deg
    beta: float  # wrist twists (-beta, 2 beta, -beta)
    dw: float  # d5 = d6
    d7: float
    deviation: float  # largest difference between the nominal and the exact DH table
    nominal_dh: np.ndarray  # (7, 4) the idealised DH table
    dh: np.ndarray | None = None  # (7, 4) the exact table in the solvers' frames (frame_dh)
    coupling_offset: float = 0.0  # the coupling offset reduced modulo 2 pi
    #: a bound on how far the deviation moves any pose, in tolerances (position over the
    #: position tolerance, rotation over ROTATION_TOLERANCE; 0 for a member solved as one)
    deviation_effect: float = 0.0
    #: the wrist's share of it (its twists, a4 .. a6, d5 and d6, the mirror offset): 0 when the
    #: model as written keeps axes 4 and 7 on one line at the straight wrist, so that its straight
    #: wrist leaves a circle of solutions (q4 against q7) like a member's, however its arm deviates
    wrist_effect: float = 0.0

    @property
    def scale(self) -> float:
        """A characteristic length of the robot (its reach)."""
        return abs(self.a1) + abs(self.a2) + abs(self.a3) + abs(self.d4) + 2 * abs(self.dw) + abs(self.d7)

    @property
    def position_tolerance(self) -> float:
        """Largest position residual of a returned solution (see :func:`position_tolerance`)."""
        return position_tolerance(self.scale)

    @property
    def zero_offsets(self) -> bool:
        """True when the arm has no shoulder, elbow or lateral offset (the paper's robot)."""
        return self.a1 == 0.0 and self.a3 == 0.0 and self.b == 0.0

    @property
    def kw(self) -> float:
        """The virtual offset d of the straight wrist, ``dw cos(beta)``."""
        return self.dw * math.cos(self.beta)

    @property
    def d_range(self) -> tuple[float, float]:
        """The range of the virtual offset d over theta5 in [-pi, pi]."""
        h = 1.0 - 2.0 * math.sin(self.beta) ** 2  # cos(2 beta): cos(phi / 2) at theta5 = pi
        far = self.kw / h if h > 1e-3 else math.copysign(1e3 * self.scale, self.kw)
        return (min(self.kw, far), max(self.kw, far))


def _near(x: float, target: float, tol: float) -> bool:
    return abs(math.remainder(x - target, 2 * math.pi)) <= tol


def family_of(dh: np.ndarray, sign: np.ndarray, coupling: tuple[float, float],
              joint_names: tuple[str, ...]) -> Family:
    """Check that the DH table ``dh`` (7, 4) describes a family member; return its nominal
    parameters. Raises :class:`~ik7r.errors.FamilyError` naming the joint that does not fit,
    or the parameter whose magnitude the solver cannot meet its tolerances with (see the
    numeric ranges above). The table is first put in the solvers' frames (:func:`frame_dh`)."""
    dh, _ = frame_dh(dh)
    a, al, d, off = (dh[:, k] for k in range(4))
    size = abs(a[1]) + abs(a[2]) + abs(a[3]) + abs(d[3]) + abs(d[4]) + abs(d[5]) + abs(d[6])

    def fail(i: int, what: str) -> FamilyError:
        return FamilyError(f"joint {i + 1} ({joint_names[i]}): {what}")

    _check_magnitudes(dh, size, fail)
    ltol = LENGTH_TOL * size

    if abs(a[0]) > 0 or abs(al[0]) > 0:
        raise fail(0, "frame 0 must sit on axis 1 (a0 = alpha0 = 0); move the rest into the base")
    checks = [(1, 0.5 * math.pi), (2, 0.0), (3, 0.5 * math.pi)]
    for i, ang in checks:
        if not (_near(al[i], ang, ANGLE_TOL) or _near(al[i], -ang, ANGLE_TOL)):
            kind = "parallel to" if ang == 0.0 else "perpendicular to"
            raise fail(i, f"axis {i + 1} must be {kind} axis {i} (alpha{i} = "
                       f"{'0' if ang == 0 else '+-90'} deg within {math.degrees(ANGLE_TOL):.3g} deg); "
                       f"got {math.degrees(al[i]):.6g} deg")
    if _near(al[2], math.pi, ANGLE_TOL) and not _near(al[2], 0.0, ANGLE_TOL):
        raise fail(2, "axes 2 and 3 are antiparallel; flip the sign of joint 3")
    for i in (4, 5, 6):
        if abs(a[i]) > ltol:
            raise fail(i, f"axes {i} and {i + 1} must intersect (a{i} = 0 within {ltol:.3g}); "
                       f"got {a[i]:.6g}")
    beta = -math.remainder(al[4], 2 * math.pi)
    if not (_near(al[6], -beta, ANGLE_TOL) and _near(al[5], 2 * beta, ANGLE_TOL)):
        raise fail(5, "the wrist must be a mirror: twists (-beta, 2 beta, -beta); got "
                   f"({math.degrees(al[4]):.6g}, {math.degrees(al[5]):.6g}, {math.degrees(al[6]):.6g}) deg")
    estimates = (-math.remainder(al[4], 2 * math.pi), 0.5 * math.remainder(al[5], 2 * math.pi),
                 -math.remainder(al[6], 2 * math.pi))
    if max(estimates) - min(estimates) > 1e-14:
        beta = sum(estimates) / 3.0
    if not 1e-6 < abs(beta) <= MAX_BETA + ANGLE_TOL:
        raise fail(4, f"the wrist twist beta must be within (0, {math.degrees(MAX_BETA):g}] deg; got "
                      f"{math.degrees(beta):.6g} deg (beyond 45 deg the fully bent wrist would fold axis 7 "
                      "back past axis 4)")
    beta = math.copysign(min(abs(beta), MAX_BETA), beta)
    if abs(d[4] - d[5]) > ltol:
        raise fail(5, f"the wrist must be a mirror: d5 = d6 within {ltol:.3g}; got {d[4]:.6g} and {d[5]:.6g}")
    _check_links(dh, size, fail)
    m, c = coupling
    c = reduce_angle(c, "the coupling offset")
    if abs(sign[5] * m / sign[4] + 1.0) > 1e-9:
        raise fail(5, f"joint 6 must mirror joint 5 (theta6 = -theta5); got multiplier {m:g}")
    # theta5 + theta6 in DH angles, reduced: the offsets may sum to a turn (2 pi is no deviation)
    mirror_offset = math.remainder(sign[5] * c + off[5] + off[4], 2 * math.pi)
    if not abs(mirror_offset) <= ANGLE_TOL:
        raise fail(5, "joint 6 must mirror joint 5 (theta6 = -theta5 in DH angles); the offsets "
                   f"leave theta5 + theta6 = {math.degrees(mirror_offset):.6g} deg")
    eps1 = 1.0 if math.remainder(al[1], 2 * math.pi) > 0 else -1.0
    eps3 = 1.0 if math.remainder(al[3], 2 * math.pi) > 0 else -1.0
    dw = 0.5 * (d[4] + d[5])
    nominal = np.array(dh, dtype=float)
    nominal[0, :2] = 0.0
    nominal[1, 1] = eps1 * 0.5 * math.pi
    nominal[2, 1] = 0.0
    nominal[3, 1] = eps3 * 0.5 * math.pi
    nominal[4:7, 0] = 0.0
    nominal[4:7, 1] = (-beta, 2 * beta, -beta)
    nominal[4:6, 2] = dw
    diff = np.abs(nominal[:, :3] - np.asarray(dh)[:, :3])
    deviation = float(max(diff.max(), abs(mirror_offset)))
    extent = size + abs(d[0]) + abs(d[1]) + abs(d[2])
    effect = _effect(diff, mirror_offset, size, extent)
    wrist_effect = _effect(diff[4:], mirror_offset, size, extent)  # (the wrist's rows alone)
    if wrist_effect <= NEGLIGIBLE:
        wrist_effect = 0.0  # (a rounded arm: the straight wrist is still a circle; see Family)
    if effect <= NEGLIGIBLE:
        deviation = effect = 0.0  # no pose moves by more than NEGLIGIBLE of the tolerances: the member
    return Family(
        a1=float(a[1]), a2=float(a[2]), a3=float(a[3]), b=float(d[1] + d[2]), d1=float(d[0]),
        d4=float(d[3]), eps1=eps1, eps3=eps3, beta=float(beta), dw=float(dw), d7=float(d[6]),
        deviation=deviation, nominal_dh=nominal, dh=dh, coupling_offset=float(c), deviation_effect=effect,
        wrist_effect=wrist_effect,
    )


def _effect(diff: np.ndarray, mirror_offset: float, size: float, extent: float) -> float:
    """How far differences ``diff`` (rows of abs(nominal - exact): length, twist, length) and the
    mirror offset move any pose at most, in tolerances: the twists' and the offset's sum (rad),
    and the lengths' sum plus that sum times the robot's ``extent`` (its unit), each over its
    tolerance (``ROTATION_TOLERANCE``, :func:`position_tolerance` of ``size``)."""
    turns = float(diff[:, 1].sum()) + abs(mirror_offset)
    moves = float(diff[:, [0, 2]].sum()) + turns * extent
    return max(moves / position_tolerance(size), turns / ROTATION_TOLERANCE)


#: Names of the DH lengths (row i: a_{i-1}, d_i) in messages.
_LENGTH_NAMES = [(f"a{i}", f"d{i + 1}") for i in range(7)]


def _check_magnitudes(dh: np.ndarray, size: float, fail) -> None:
    """Refuse lengths the solver cannot meet its tolerances with: a size outside
    [MIN_SIZE, ...], an extent whose float spacing is
    above MIN_RELATIVE_TOLERANCE of the position tolerance (see also :func:`_check_links`)."""
    lengths = [(abs(dh[i, k]), i, _LENGTH_NAMES[i][k // 2]) for i in range(7) for k in (0, 2)]
    big, i_big, name_big = max(lengths)
    if not size >= MIN_SIZE:
        raise fail(i_big, f"the robot's size (|a1| + |a2| + |a3| + |d4| + |d5| + |d6| + |d7| = {size:.6g}) "
                   f"must be at least MIN_SIZE = {MIN_SIZE:g} of its unit (rescale the unit); "
                   f"the largest length is {name_big} = {dh[i_big, 0 if name_big[0] == 'a' else 2]:.6g}")
    extent = size + abs(dh[0, 2]) + abs(dh[1, 2]) + abs(dh[2, 2])
    tol = position_tolerance(size)
    if extent * MIN_RELATIVE_TOLERANCE > tol:
        raise fail(i_big, f"lengths up to {tol / MIN_RELATIVE_TOLERANCE:.6g} (the position tolerance "
                   f"{tol:g} over MIN_RELATIVE_TOLERANCE = {MIN_RELATIVE_TOLERANCE:g}) can be solved to "
                   f"the tolerance; got {name_big} = {dh[i_big, 0 if name_big[0] == 'a' else 2]:.6g} "
                   f"(extent {extent:.6g}; use a larger length unit)")


def _check_links(dh: np.ndarray, size: float, fail) -> None:
    """Refuse a degenerate upper arm or wrist offset (checked after the chain's shape, so that a
    chain of the wrong shape is named for its shape)."""
    if abs(dh[2, 0]) < MIN_LINK_RATIO * size:
        raise fail(2, f"the upper arm a2 must not vanish (|a2| >= MIN_LINK_RATIO = {MIN_LINK_RATIO:g} "
                   f"times the size {size:.6g}: else joints 2 and 3 turn about one axis); got {dh[2, 0]:.6g}")
    dw = 0.5 * (abs(dh[4, 2]) + abs(dh[5, 2]))
    if dw < MIN_LINK_RATIO * size:
        raise fail(4, f"the wrist offsets d5 = d6 must not vanish (>= MIN_LINK_RATIO = {MIN_LINK_RATIO:g} "
                   f"times the size {size:.6g}: else the four wrist axes meet in one point); got "
                   f"d5 = {dh[4, 2]:.6g}, d6 = {dh[5, 2]:.6g}")


def position_tolerance(size: float) -> float:
    """The position tolerance of a robot of this size: 1e-9 of its unit, or 1e-12 of its size if
    smaller."""
    return min(1e-9, 1e-12 * size)


def check_placement(T: np.ndarray, size: float, name: str) -> None:
    """Refuse a base or tool transform whose translation puts the tool so far away that the
    float spacing of its coordinates exceeds MIN_RELATIVE_TOLERANCE of the tolerance."""
    far = float(np.abs(T[:3, 3]).sum())
    tol = position_tolerance(size)
    if (far + size) * MIN_RELATIVE_TOLERANCE > tol:
        raise FamilyError(f"{name}: translations up to {tol / MIN_RELATIVE_TOLERANCE - size:.6g} (the "
                          f"position tolerance {tol:g} over MIN_RELATIVE_TOLERANCE = "
                          f"{MIN_RELATIVE_TOLERANCE:g}, less the size) can be solved to the tolerance; "
                          f"got {T[:3, 3].tolist()}")
