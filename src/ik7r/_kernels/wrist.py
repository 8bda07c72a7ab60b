"""Compiled kernels of the coupled hollow wrist (joints 4 to 7, theta6 = -theta5).

With the twists ``(-beta, 2 beta, -beta)`` and equal offsets ``dw`` the wrist is a mirror:
axes 4 and 7 meet at the virtual wrist centre P'c, at the distance ``d`` from O4 along axis 4
(and from O6 back along axis 7). With ``x = sin(beta) sin(theta5 / 2)`` the bend angle phi
between axes 4 and 7 and the distance ``d`` are (the quadratic of docs/method.md, factored)::

    phi = 4 asin(x),    cos(phi / 2) = 1 - 2 x^2,    d = dw cos(beta) / cos(phi / 2)   (eq. 5)

so ``d`` runs from ``KW = dw cos(beta)`` (straight wrist) to ``KW / cos(2 beta)``
(theta5 = +-pi), monotonically for ``|beta| < 45 deg``.
"""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .jit import njit


@njit
def d_of_theta5(t5, K):
    """Virtual offset d (robot length unit) of the wrist bent by joint angle ``t5`` (rad)."""
    x = K[L.SB] * math.sin(0.5 * t5)
    return K[L.KW] / (1.0 - 2.0 * x * x)


@njit
def theta5_of_d(d, K):
    """The non-negative theta5 (rad) whose virtual offset is ``d`` (clamped to the range)."""
    return theta5_cs_of_d(d, K)[0]


@njit
def theta5_cs_of_d(d, K):
    """:func:`theta5_of_d`, and its cosine and sine (from the half angle, no further
    trigonometric call)."""
    return theta5_cs_of_u(K[L.KW] / d, K)


@njit
def theta5_cs_of_u(h, K):
    """:func:`theta5_cs_of_d` of ``u = KW / d = cos(phi / 2)``, the polynomial's variable."""
    s2 = (1.0 - h) / (2.0 * K[L.SB] * K[L.SB])
    s2 = min(1.0, max(0.0, s2))  # sin^2(theta5 / 2)
    x = math.sqrt(s2)
    return 2.0 * math.asin(x), 1.0 - 2.0 * s2, 2.0 * x * math.sqrt(1.0 - s2)


@njit
def theta5_of_cos_bend(c, K):
    """The non-negative theta5 (rad) that bends axis 7 by ``acos(c)`` from axis 4."""
    h = math.sqrt(max(0.0, 0.5 * (1.0 + c)))  # cos(phi / 2)
    s2 = (1.0 - h) / (2.0 * K[L.SB] * K[L.SB])
    s2 = min(1.0, max(0.0, s2))
    return 2.0 * math.asin(math.sqrt(s2))


@njit
def theta5_of_bend(Q, K):
    """The non-negative theta5 (rad) of the bend of the wrist target ``Q`` (3, 3), accurate
    for small bends too (the bend from its sine and cosine, not from the cosine alone)."""
    phi = math.atan2(math.hypot(Q[0, 2], Q[1, 2]), Q[2, 2])
    x = math.sin(0.25 * phi) / K[L.SB]
    x = min(1.0, max(0.0, x))
    return 2.0 * math.asin(x)


@njit
def wrist_rotation(t5, K, W):
    """``W = RotX(-beta) RotZ(t5) RotX(2 beta) RotZ(-t5) RotX(-beta)`` (3, 3): frame 4 <- 7."""
    wrist_rotation_cs(math.cos(t5), math.sin(t5), K, W)


@njit
def wrist_rotation_cs(c5, s5, K, W):
    """:func:`wrist_rotation` given ``cos(t5)`` and ``sin(t5)``."""
    W[0, 0] = 1.0
    W[0, 1] = 0.0
    W[0, 2] = 0.0
    W[1, 0] = 0.0
    W[1, 1] = 1.0
    W[1, 2] = 0.0
    W[2, 0] = 0.0
    W[2, 1] = 0.0
    W[2, 2] = 1.0
    cb = math.sqrt(1.0 - K[L.SB] * K[L.SB])  # cos(beta) > 0: |beta| < 45 deg
    sb = K[L.SB]
    c2 = cb * cb - sb * sb
    s2 = 2.0 * sb * cb
    _rot_x(W, cb, -sb)
    _rot_z(W, c5, s5)
    _rot_x(W, c2, s2)
    _rot_z(W, c5, -s5)
    _rot_x(W, cb, -sb)


@njit
def _rot_x(W, c, s):
    """``W = W @ RotX(a)`` with ``c, s = cos(a), sin(a)``."""
    for r in range(3):
        y = W[r, 1]
        z = W[r, 2]
        W[r, 1] = c * y + s * z
        W[r, 2] = -s * y + c * z


@njit
def _rot_z(W, c, s):
    """``W = W @ RotZ(a)`` with ``c, s = cos(a), sin(a)``."""
    for r in range(3):
        x = W[r, 0]
        y = W[r, 1]
        W[r, 0] = c * x + s * y
        W[r, 1] = -s * x + c * y


@njit
def wrist_target(R03, R07, K, Q):
    """``Q = RotX(alpha3)^T R03^T R07`` (3, 3): the wrist's rotation with theta4 = theta7 = 0
    factored out, so that ``Q = RotZ(theta4) W(theta5) RotZ(theta7)``."""
    ca = K[L.NOMINAL_TRIG + 6]  # cos, sin of the nominal alpha3
    sa = K[L.NOMINAL_TRIG + 7]
    for j in range(3):
        x = R03[0, 0] * R07[0, j] + R03[1, 0] * R07[1, j] + R03[2, 0] * R07[2, j]
        y = R03[0, 1] * R07[0, j] + R03[1, 1] * R07[1, j] + R03[2, 1] * R07[2, j]
        z = R03[0, 2] * R07[0, j] + R03[1, 2] * R07[1, j] + R03[2, 2] * R07[2, j]
        Q[0, j] = x
        Q[1, j] = ca * y + sa * z
        Q[2, j] = -sa * y + ca * z


@njit(allocates=True)
def wrist_ik(Q, t5, t4_hint, K):
    """theta4 and theta7 (rad) with ``RotZ(theta4) W(t5) RotZ(theta7) = Q`` (Q's bend must
    match ``t5``). At the straight wrist (theta5 = 0) only theta4 + theta7 is defined:
    theta4 is then ``t4_hint``."""
    return wrist_ik_cs(Q, math.cos(t5), math.sin(t5), t4_hint, K, np.empty((3, 3)))


@njit
def wrist_ik_cs(Q, c5, s5, t4_hint, K, W):
    """:func:`wrist_ik` given ``cos(t5)`` and ``sin(t5)``, with a work array ``W`` (3, 3)."""
    wrist_rotation_cs(c5, s5, K, W)
    # theta4 turns W's third column onto Q's about z: the angle between their xy parts
    dot = W[0, 2] * Q[0, 2] + W[1, 2] * Q[1, 2]
    cross = W[0, 2] * Q[1, 2] - W[1, 2] * Q[0, 2]
    nw2 = W[0, 2] * W[0, 2] + W[1, 2] * W[1, 2]  # sin^2(bend)
    nn = math.sqrt(dot * dot + cross * cross)
    if nw2 > 1e-24 and nn > 0.0:
        t4 = math.atan2(cross, dot)
        c4 = dot / nn
        s4 = cross / nn
    else:
        t4 = t4_hint
        c4 = math.cos(t4)
        s4 = math.sin(t4)
    return t4, wrist_t7(Q, c4, s4, W)


@njit
def wrist_t7(Q, c4, s4, W):
    """theta7 (rad) with ``RotZ(theta4) W RotZ(theta7) = Q`` given ``cos(theta4)``, ``sin(theta4)``
    and the wrist rotation ``W`` (3, 3) of theta5 (:func:`wrist_rotation_cs`)."""
    # RotZ(t7) = W^T RotZ(-t4) Q: first column's x and y
    m0 = c4 * Q[0, 0] + s4 * Q[1, 0]
    m1 = -s4 * Q[0, 0] + c4 * Q[1, 0]
    m2 = Q[2, 0]
    x = W[0, 0] * m0 + W[1, 0] * m1 + W[2, 0] * m2
    y = W[0, 1] * m0 + W[1, 1] * m1 + W[2, 1] * m2
    return math.atan2(y, x)
