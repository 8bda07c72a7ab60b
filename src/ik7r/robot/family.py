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

import numpy as np

from ..errors import FamilyError

#: Twist angles must match the family within this (rad, about 0.06 deg).
ANGLE_TOL = 1e-3
#: Offsets that must vanish (a4, a5, a6) and the difference d5 - d6 must stay within this
#: fraction of the robot's size (about 1 mm on a 1 m arm).
LENGTH_TOL = 1e-3
#: Largest wrist twist (rad): 45 deg. There the fully bent wrist (theta5 = 180 deg) folds axis 7
#: back parallel to axis 4 and its virtual wrist centre is at infinity (the search runs in
#: u = 1 / d, which stays bounded).
MAX_BETA = math.radians(45.0)


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

    @property
    def scale(self) -> float:
        """A characteristic length of the robot (its reach)."""
        return abs(self.a1) + abs(self.a2) + abs(self.a3) + abs(self.d4) + 2 * abs(self.dw) + abs(self.d7)

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
    parameters. Raises :class:`~ik7r.errors.FamilyError` naming the joint that does not fit."""
    a, al, d, off = (dh[:, k] for k in range(4))
    size = abs(a[1]) + abs(a[2]) + abs(a[3]) + abs(d[3]) + abs(d[4]) + abs(d[5]) + abs(d[6])
    ltol = LENGTH_TOL * max(size, 1e-300)

    def fail(i: int, what: str) -> FamilyError:
        return FamilyError(f"joint {i + 1} ({joint_names[i]}): {what}")

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
    m, c = coupling
    if abs(sign[5] * m / sign[4] + 1.0) > 1e-9:
        raise fail(5, f"joint 6 must mirror joint 5 (theta6 = -theta5); got multiplier {m:g}")
    mirror_offset = sign[5] * c + off[5] + off[4]
    if not _near(mirror_offset, 0.0, ANGLE_TOL):
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
    deviation = float(max(np.abs(nominal[:, :3] - np.asarray(dh)[:, :3]).max(), abs(mirror_offset)))
    return Family(
        a1=float(a[1]), a2=float(a[2]), a3=float(a[3]), b=float(d[1] + d[2]), d1=float(d[0]),
        d4=float(d[3]), eps1=eps1, eps3=eps3, beta=float(beta), dw=float(dw), d7=float(d[6]),
        deviation=deviation, nominal_dh=nominal,
    )
