"""Compiled kernels of the exact model: joint mapping, forward kinematics, Jacobian, polishing.

All angles are radians; lengths are in the robot's unit. ``K`` is the parameter vector of
:mod:`ik7r._kernels.params`. Frames follow Craig's modified Denavit-Hartenberg convention (the
paper's eq. (1)): ``T_{i-1,i} = RotX(alpha_{i-1}) TransX(a_{i-1}) RotZ(theta_i) TransZ(d_i)``.
"""

from __future__ import annotations

import math

import numpy as np

from . import params as L
from .jit import njit

#: Largest joint step (rad) of one Newton iteration of the polish.
MAX_POLISH_STEP = 0.1
#: :func:`polish`'s mask of moving joints when every joint moves (bit ``i``: joint ``i + 1``).
ALL_JOINTS = 0b111111


@njit
def dh_angle(q, K, i):
    """DH angle of joint ``i`` (0-based) for user joints ``q`` (6,) (coupling folded in)."""
    if i < 5:
        return K[L.SIGN + i] * q[i] + K[L.DH + 4 * i + 3]
    if i == 5:
        return K[L.SIGN + 5] * (K[L.MIMIC] * q[4] + K[L.MIMIC + 1]) + K[L.THETA_OFFSET6]
    return K[L.SIGN + 6] * q[5] + K[L.THETA_OFFSET7]


@njit
def user_angle(i, theta_i, K):
    """DH angle of joint ``i`` (0-based, 0..6 except 5) -> user angle."""
    return (theta_i - K[L.DH + 4 * i + 3]) * K[L.SIGN + i]


@njit
def _copy_param44(K, off, out):
    for i in range(4):
        for j in range(4):
            out[i, j] = K[off + 4 * i + j]


@njit
def chain(theta, K, first, last, M, table=L.DH):
    """Post-multiply ``M`` (4, 4) in place by the DH transforms of joints first..last-1.

    ``table`` selects the exact (``L.DH``) or the nominal (``L.NDH``) DH table.
    """
    trig = L.TRIG if table == L.DH else L.TRIG + 14
    for i in range(first, last):
        _dh_step(M, K, table, trig, i, theta[i])


@njit
def _dh_step(M, K, table, trig, i, theta_i):
    """``M = M @ T(i-1, i)`` in place (eq. (1)) for DH angle ``theta_i``."""
    c, s = sincos(theta_i)
    dh_step_cs(M, K, table, trig, i, c, s)


# sincos: Cody-Waite reduction by pi / 2 and the minimax polynomials of fdlibm's __kernel_sin
# and __kernel_cos (Sun Microsystems, freely distributable), as in most C libraries' sin, cos
_PIO2_HI = 1.57079632673412561417e00  # first 33 bits of pi / 2 (k * _PIO2_HI is exact)
_PIO2_LO = 6.07710050650619224932e-11  # pi / 2 - _PIO2_HI
_INV_PIO2 = 6.36619772367581382433e-01
_S1, _S2, _S3 = -1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04
_S4, _S5, _S6 = 2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10
_C1, _C2, _C3 = 4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05
_C4, _C5, _C6 = -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11


@njit
def sincos(x):
    """``(cos x, sin x)`` within an ulp of the C library's, about twice as fast (one shared
    reduction, no call, no branch on the quadrant). |x| >= 1e5 rad, inf and nan go to the
    C library."""
    if not abs(x) < 1e5:
        return math.cos(x), math.sin(x)
    k = math.floor(x * _INV_PIO2 + 0.5)
    r = (x - k * _PIO2_HI) - k * _PIO2_LO  # in [-pi / 4, pi / 4]
    z = r * r
    s = r + r * z * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
    hz = 0.5 * z
    w = 1.0 - hz
    c = w + (((1.0 - w) - hz) + z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6))))))
    q = int(k) & 3  # quadrant: (c, s), (-s, c), (-c, -s), (s, -c)
    odd = q & 1
    return ((s if odd else c) * (1 - 2 * (((q + 1) >> 1) & 1)),
            (c if odd else s) * (1 - 2 * (q >> 1)))


@njit
def dh_step_cs(M, K, table, trig, i, ct, st):
    """:func:`_dh_step` given the cosine and sine of the DH angle."""
    a = K[table + 4 * i]
    d = K[table + 4 * i + 2]
    ca = K[trig + 2 * i]
    sa = K[trig + 2 * i + 1]
    for r in range(3):
        x = M[r, 0]
        y = M[r, 1] * ca + M[r, 2] * sa
        z = -M[r, 1] * sa + M[r, 2] * ca
        M[r, 3] += a * x + d * z
        M[r, 0] = ct * x + st * y
        M[r, 1] = -st * x + ct * y
        M[r, 2] = z


@njit
def _times_tool(M, K):
    """``M = M @ TOOL`` in place (row by row, no allocation)."""
    for r in range(3):
        m0 = M[r, 0]
        m1 = M[r, 1]
        m2 = M[r, 2]
        for j in range(4):
            M[r, j] = (m0 * K[L.TOOL + j] + m1 * K[L.TOOL + 4 + j] + m2 * K[L.TOOL + 8 + j]
                       + (M[r, 3] if j == 3 else 0.0))


@njit
def fk_user(q, K, out):
    """World <- tool transform for user joints ``q`` (6,) (no allocation)."""
    _copy_param44(K, L.BASE, out)
    for i in range(7):
        _dh_step(out, K, L.DH, L.TRIG, i, dh_angle(q, K, i))
    _times_tool(out, K)


@njit
def fk_batch(Q, K, out):
    """``Q`` (N, 6) -> ``out`` (N, 4, 4)."""
    for n in range(Q.shape[0]):
        fk_user(Q[n], K, out[n])


@njit(allocates=True)  # (row copies between frames)
def frames_batch(Q, K, out):
    """``Q`` (N, 6) -> world frames ``out`` (N, 9, 4, 4): base (frame 0), frames 1..7, tool."""
    for n in range(Q.shape[0]):
        _copy_param44(K, L.BASE, out[n, 0])
        for i in range(7):
            out[n, i + 1] = out[n, i]
            _dh_step(out[n, i + 1], K, L.DH, L.TRIG, i, dh_angle(Q[n], K, i))
        out[n, 8] = out[n, 7]
        _times_tool(out[n, 8], K)


@njit(allocates=True)
def jacobian(q, K, J):
    """Geometric Jacobian (6, 6) of the tool frame in world coordinates.

    Rows: linear velocity of the tool origin, then angular velocity. Columns: the six
    independent joints; joint 6 is folded into the column of joint 5 through the coupling.
    """
    fk_jacobian(q, K, np.empty((4, 4)), J, np.empty((7, 6)))


@njit
def fk_jacobian(q, K, T, J, ZO):
    """Forward kinematics ``T`` (4, 4) and the Jacobian ``J`` (6, 6) of :func:`jacobian` in one
    pass over the chain (``ZO`` (7, 6) work array: each joint's axis and origin)."""
    _copy_param44(K, L.BASE, T)
    for i in range(7):
        _dh_step(T, K, L.DH, L.TRIG, i, dh_angle(q, K, i))
        for r in range(3):
            ZO[i, r] = T[r, 2]
            ZO[i, 3 + r] = T[r, 3]
    _times_tool(T, K)
    for c in range(6):
        for r in range(6):
            J[r, c] = 0.0
    for i in range(7):
        if i == 5:
            c = 4
            w = K[L.SIGN + 5] * K[L.MIMIC]
        else:
            c = i if i < 5 else 5
            w = K[L.SIGN + i]
        dx = T[0, 3] - ZO[i, 3]
        dy = T[1, 3] - ZO[i, 4]
        dz = T[2, 3] - ZO[i, 5]
        J[0, c] += w * (ZO[i, 1] * dz - ZO[i, 2] * dy)
        J[1, c] += w * (ZO[i, 2] * dx - ZO[i, 0] * dz)
        J[2, c] += w * (ZO[i, 0] * dy - ZO[i, 1] * dx)
        J[3, c] += w * ZO[i, 0]
        J[4, c] += w * ZO[i, 1]
        J[5, c] += w * ZO[i, 2]


@njit
def rotation_log(R, w):
    """Rotation vector ``w`` (3,) of a rotation matrix ``R`` (axis * angle), robust near 0
    and pi."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    c = min(1.0, max(-1.0, 0.5 * (tr - 1.0)))
    vx = R[2, 1] - R[1, 2]
    vy = R[0, 2] - R[2, 0]
    vz = R[1, 0] - R[0, 1]
    s = 0.5 * math.sqrt(vx * vx + vy * vy + vz * vz)
    ang = math.atan2(s, c)
    if s > 1e-6 or c > 0.0:
        f = 0.5 if s < 1e-12 else 0.5 * ang / s
        w[0] = f * vx
        w[1] = f * vy
        w[2] = f * vz
        return
    # angle close to pi: axis from the diagonal of R + I
    k = 0
    if R[1, 1] > R[k, k]:
        k = 1
    if R[2, 2] > R[k, k]:
        k = 2
    for r in range(3):  # the axis, into w
        w[r] = R[k, k] + 1.0 if r == k else 0.5 * (R[r, k] + R[k, r])
    n = math.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2)
    sgn = 1.0
    if w[0] * vx + w[1] * vy + w[2] * vz < 0.0:
        sgn = -1.0
    for r in range(3):
        w[r] *= sgn * ang / n


@njit
def pose_error(T, Td, e, Rerr):
    """Error ``e`` (6,) taking ``T`` to ``Td``: position difference, then world rotation vector
    (``Rerr`` (3, 3): work array)."""
    for r in range(3):
        e[r] = Td[r, 3] - T[r, 3]
    for i in range(3):
        for j in range(3):
            s = 0.0
            for k in range(3):
                s += Td[i, k] * T[j, k]
            Rerr[i, j] = s
    rotation_log(Rerr, e[3:])


@njit
def residual(T, Td):
    """(position error, rotation error) between two transforms: norms, robot unit and rad."""
    dp = 0.0
    for r in range(3):
        dp += (T[r, 3] - Td[r, 3]) ** 2
    # |R - Rd|_F^2 = 8 sin^2(angle / 2), so sqrt(dr / 2) = 2 sin(angle / 2) ~ angle
    dr = 0.0
    for i in range(3):
        for j in range(3):
            dr += (T[i, j] - Td[i, j]) ** 2
    return math.sqrt(dp), math.sqrt(0.5 * dr)


@njit
def solve6(A, b, x):
    """Solve ``A x = b`` (6 x 6) by Gaussian elimination with partial pivoting.

    Returns the smallest pivot magnitude relative to the largest entry of ``A`` (0 when
    singular); ``A`` and ``b`` are overwritten.
    """
    n = 6
    big = 0.0
    for i in range(n):
        for j in range(n):
            big = max(big, abs(A[i, j]))
    if big == 0.0:
        return 0.0
    small = big
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(A[i, k]) > abs(A[p, k]):
                p = i
        if A[p, k] == 0.0:
            return 0.0
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            b[k], b[p] = b[p], b[k]
        small = min(small, abs(A[k, k]))
        for i in range(k + 1, n):
            f = A[i, k] / A[k, k]
            for j in range(k, n):
                A[i, j] -= f * A[k, j]
            b[i] -= f * b[k]
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= A[i, j] * x[j]
        x[i] = s / A[i, i]
    return small / big


@njit(allocates=True)
def polish(q, Td, K, max_iter, damped=False, patience=0, settle=0.0, moving=ALL_JOINTS, floor=1.0):
    """Newton-Raphson on the full forward kinematics from ``q`` (modified in place).

    Returns True when the residual is within the robot's tolerances (``POS_TOL`` in the
    length unit, ``ROT_TOL`` in rad). Never claims success it did not verify. ``damped``:
    where the Jacobian is singular take a damped least-squares step (:func:`_damped_step`)
    instead of giving up. ``patience`` > 0: give up when the error (position over the robot's
    size, or rotation, the larger) has not come down by STALL_RATIO within that many full Newton
    steps (from the first step on): Newton then circles a local minimum of the error, which is
    no solution. Steps clamped to MAX_POLISH_STEP do not count: a start far off may travel
    without progress before it converges (one such start, on a rounded 45 deg robot, lost its
    solution when they counted). ``settle`` > 0: stop once a full Newton step is below it (rad),
    returning False (not verified): for the intermediate models of a homotopy, where Newton's
    quadratic convergence leaves an error of the order of that step squared and the forward
    kinematics that would verify it is not needed. ``moving``: a bit mask of the joints that
    move (bit ``i`` for joint ``i + 1``); with any joint held the others move by damped
    least-squares steps (:func:`_damped_step`). ``floor`` < 1: polish on to that fraction of
    the tolerances (where the FK is flat the first point within them is at the edge of a wide
    band; see :func:`ik7r._kernels.answers._floored`).
    """
    return polish_into(q, Td, K, max_iter, np.empty((4, 4)), np.empty((6, 6)), np.empty(6), np.empty(6),
                       np.empty((7, 6)), damped, patience, settle, moving, floor)


#: See :func:`polish`: the error must fall below this fraction of itself every ``patience`` steps.
STALL_RATIO = 0.9
#: ... and Newton's step is not defined where the Jacobian's least pivot (relative to its largest
#: entry, :func:`solve6`) is below this.
NEWTON_PIVOT = 1e-14


@njit(allocates=True)
def newton_undefined(q, Td, K):
    """Whether Newton's step of :func:`polish` at ``q`` (user angles) is not defined for the
    pose ``Td``: the Jacobian singular to its pivot test (NEWTON_PIVOT). Where ``q`` is exact,
    the FK is flat there: ``q`` is a point of a valley of exact poses."""
    T = np.empty((4, 4))
    J = np.empty((6, 6))
    ZO = np.empty((7, 6))
    e = np.empty(6)
    fk_jacobian(q, K, T, J, ZO)
    pose_error(T, Td, e, ZO[:3, :3])
    return solve6(J, e, np.empty(6)) < NEWTON_PIVOT


#: Damping of :func:`_damped_step`, relative to the mean squared singular value of the
#: weighted Jacobian: directions whose singular value is below about 1e-8 of the others' stay put.
POLISH_DAMPING = 1e-16


@njit
def _damped_step(q, Td, K, T, J, e, dq, ZO, moving=ALL_JOINTS):
    """The step ``dq`` of :func:`polish_into` where the Jacobian at ``q`` is singular (a singular
    arm and wrist at once: the shoulder singular set with a nearly straight wrist, or axis 7 on
    axis 1, where the pose leaves joints free): damped least squares ``(Jw^T Jw + lam I) dq =
    Jw^T ew`` with the position rows over the robot's size. It moves least along the free or
    nearly free directions (a joint the pose leaves free keeps its value, which came from the
    seed). Recomputes ``J`` and ``e`` (:func:`solve6` destroyed them); ``ZO`` holds the normal
    equations. ``moving``: the bit mask of the joints that take a step (``dq`` is 0 for the
    rest). Returns False when even they are singular."""
    fk_jacobian(q, K, T, J, ZO)
    pose_error(T, Td, e, ZO[:3, :3])
    w = 1.0 / K[L.SCALE] if K[L.SCALE] > 0.0 else 1.0
    for r in range(3):
        e[r] *= w
        for c in range(6):
            J[r, c] *= w
    tr = 0.0
    n = 0
    for i in range(6):
        mi = (moving >> i) & 1 == 1
        g = 0.0
        for r in range(6):
            g += J[r, i] * e[r]
        ZO[6, i] = g if mi else 0.0
        for j in range(6):
            s = 0.0
            for r in range(6):
                s += J[r, i] * J[r, j]
            ZO[i, j] = s if mi and (moving >> j) & 1 == 1 else (1.0 if i == j else 0.0)
        if mi:
            tr += ZO[i, i]
            n += 1
    lam = POLISH_DAMPING * tr / max(n, 1)
    for i in range(6):
        if (moving >> i) & 1 == 1:
            ZO[i, i] += lam
    return solve6(ZO[:6], ZO[6], dq) > 0.0


@njit
def polish_into(q, Td, K, max_iter, T, J, e, dq, ZO, damped=False, patience=0, settle=0.0,
                moving=ALL_JOINTS, floor=1.0):
    """:func:`polish` with caller-provided work arrays ``T`` (4, 4), ``J`` (6, 6), ``e``, ``dq``
    (6,) and ``ZO`` (7, 6)."""
    tol_p = floor * K[L.POS_TOL]
    tol_r = floor * K[L.ROT_TOL]
    mark = math.inf
    travelled = False  # a step since the last mark was clamped to MAX_POLISH_STEP
    for it in range(max_iter + 1):
        fk_jacobian(q, K, T, J, ZO)
        dp, dr = residual(T, Td)
        if dp <= tol_p and dr <= tol_r:
            return True
        if not (dp < 1e300 and dr < 1e300):
            return False
        if patience > 0 and it % patience == 1 % patience:
            err = max(dp / K[L.SCALE], dr)
            if err > STALL_RATIO * mark and not travelled:
                return False
            mark = err
            travelled = False
        pose_error(T, Td, e, ZO[:3, :3])  # (ZO is free until the next fk_jacobian)
        if moving != ALL_JOINTS:
            if not _damped_step(q, Td, K, T, J, e, dq, ZO, moving):
                return False
        elif solve6(J, e, dq) < NEWTON_PIVOT and not (damped and _damped_step(q, Td, K, T, J, e, dq,
                                                                              ZO)):
            return False
        # a limited step keeps the polish on the solution it started near
        big = 0.0
        for i in range(6):
            big = max(big, abs(dq[i]))
        f = 1.0 if big <= MAX_POLISH_STEP else MAX_POLISH_STEP / big
        travelled = travelled or f < 1.0
        for i in range(6):
            q[i] += f * dq[i]
        if big < settle:
            return False
    return False
