"""Small, vectorised helpers for rotations and homogeneous transforms.

Conventions: transforms are ``(..., 4, 4)`` arrays mapping child to parent coordinates
(``T_A_C = T_A_B @ T_B_C``); roll-pitch-yaw is URDF's fixed-axis X-Y-Z convention,
``R = Rz(yaw) Ry(pitch) Rx(roll)``; quaternions are ``(w, x, y, z)``.
"""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike

__all__ = [
    "rot_x",
    "rot_z",
    "dh_transform",
    "rpy_to_matrix",
    "matrix_to_rpy",
    "quat_to_matrix",
    "matrix_to_quat",
    "transform",
    "invert",
    "remainder_2pi",
    "remainder_2pi_below_2_26",
    "wrap",
    "wrap_angle",
    "nearest_rotation",
]


def rot_x(angle: np.ndarray | float) -> np.ndarray:
    """Rotation about x by ``angle`` (rad), shape ``(..., 3, 3)``."""
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(c), np.zeros_like(c)
    return np.stack([o, z, z, z, c, -s, z, s, c], axis=-1).reshape(np.shape(c) + (3, 3))


def rot_z(angle: np.ndarray | float) -> np.ndarray:
    """Rotation about z by ``angle`` (rad), shape ``(..., 3, 3)``."""
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(c), np.zeros_like(c)
    return np.stack([c, -s, z, s, c, z, z, z, o], axis=-1).reshape(np.shape(c) + (3, 3))


def dh_transform(a: ArrayLike, alpha: ArrayLike, theta: ArrayLike, d: ArrayLike) -> np.ndarray:
    """Craig's modified DH transform (the paper's eq. (1)), broadcast over the inputs.

    ``T = RotX(alpha) TransX(a) RotZ(theta) TransZ(d)``; angles in rad, shape ``(..., 4, 4)``.
    """
    a, alpha, theta, d = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (a, alpha, theta, d)))
    ca, sa, ct, st = np.cos(alpha), np.sin(alpha), np.cos(theta), np.sin(theta)
    z, o = np.zeros_like(a), np.ones_like(a)
    rows = [ct, -st, z, a, st * ca, ct * ca, -sa, -d * sa, st * sa, ct * sa, ca, d * ca, z, z, z, o]
    return np.stack(rows, axis=-1).reshape(a.shape + (4, 4))


def rpy_to_matrix(rpy: ArrayLike) -> np.ndarray:
    """URDF roll-pitch-yaw (rad, ``(..., 3)``) to a rotation ``Rz(y) Ry(p) Rx(r)`` ``(..., 3, 3)``."""
    rpy = np.asarray(rpy, dtype=float)
    r, p, y = rpy[..., 0], rpy[..., 1], rpy[..., 2]
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rows = [
        cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,
        sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
        -sp, cp * sr, cp * cr,
    ]
    return np.stack(rows, axis=-1).reshape(r.shape + (3, 3))


def matrix_to_rpy(R: ArrayLike) -> np.ndarray:
    """Inverse of :func:`rpy_to_matrix`: ``(..., 3, 3)`` -> ``(..., 3)`` rad (pitch in [-pi/2, pi/2]).

    Yaw is read first; pitch and roll then come from ``RotZ(-yaw) R = RotY(pitch) RotX(roll)``,
    whose entries are of order one. Near gimbal lock (pitch about +-pi/2) yaw is ill-determined,
    but its error is then a turn about x that roll takes up, so the angles give back ``R`` to
    the rounding of its entries (reading roll from ``R``'s own entries, of order cos(pitch),
    left errors up to 2e-12 there: the URDF writer puts every joint origin through this)."""
    R = np.asarray(R, dtype=float)
    yaw = np.arctan2(R[..., 1, 0], R[..., 0, 0])
    cy, sy = np.cos(yaw), np.sin(yaw)
    c_pitch = cy * R[..., 0, 0] + sy * R[..., 1, 0]  # (RotZ(-yaw) R)[0, 0], >= 0
    c_roll = cy * R[..., 1, 1] - sy * R[..., 0, 1]  # (RotZ(-yaw) R)[1, 1]
    s_roll = sy * R[..., 0, 2] - cy * R[..., 1, 2]  # -(RotZ(-yaw) R)[1, 2]
    pitch = np.arctan2(-R[..., 2, 0], c_pitch)
    roll = np.arctan2(s_roll, c_roll)
    return np.stack([roll, pitch, yaw], axis=-1)


def quat_to_matrix(quat: ArrayLike) -> np.ndarray:
    """Unit quaternion ``(w, x, y, z)`` ``(..., 4)`` to rotation ``(..., 3, 3)`` (normalised first)."""
    q = np.asarray(quat, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    rows = [
        1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
        2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
        2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y),
    ]
    return np.stack(rows, axis=-1).reshape(w.shape + (3, 3))


def matrix_to_quat(R: ArrayLike) -> np.ndarray:
    """Rotation ``(..., 3, 3)`` to unit quaternion ``(w, x, y, z)`` with ``w >= 0``."""
    R = np.asarray(R, dtype=float)
    tr = R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2]
    cand = np.stack(
        [
            np.stack([1 + tr, R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0],
                      R[..., 1, 0] - R[..., 0, 1]], -1),
            np.stack([R[..., 2, 1] - R[..., 1, 2], 1 + 2 * R[..., 0, 0] - tr,
                      R[..., 0, 1] + R[..., 1, 0], R[..., 0, 2] + R[..., 2, 0]], -1),
            np.stack([R[..., 0, 2] - R[..., 2, 0], R[..., 0, 1] + R[..., 1, 0],
                      1 + 2 * R[..., 1, 1] - tr, R[..., 1, 2] + R[..., 2, 1]], -1),
            np.stack([R[..., 1, 0] - R[..., 0, 1], R[..., 0, 2] + R[..., 2, 0],
                      R[..., 1, 2] + R[..., 2, 1], 1 + 2 * R[..., 2, 2] - tr], -1),
        ],
        axis=-2,
    )
    diag = np.stack([tr, R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]], -1)
    best = np.take_along_axis(cand, np.argmax(diag, -1)[..., None, None], -2)[..., 0, :]
    q = best / np.linalg.norm(best, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0, -q, q)


def transform(R: ArrayLike | None = None, p: ArrayLike | None = None) -> np.ndarray:
    """Homogeneous transform from rotation ``(..., 3, 3)`` and translation ``(..., 3)``."""
    R = np.eye(3) if R is None else np.asarray(R, dtype=float)
    p = np.zeros(3) if p is None else np.asarray(p, dtype=float)
    shape = np.broadcast_shapes(R.shape[:-2], p.shape[:-1])
    T = np.zeros(shape + (4, 4))
    T[..., :3, :3] = R
    T[..., :3, 3] = p
    T[..., 3, 3] = 1.0
    return T


def invert(T: ArrayLike) -> np.ndarray:
    """Inverse of rigid transforms ``(..., 4, 4)``."""
    T = np.asarray(T, dtype=float)
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    return transform(Rt, -np.einsum("...ij,...j->...i", Rt, T[..., :3, 3]))


#: The float 2 pi of :func:`wrap` (its multiples drift from the exact ones by 2.4e-16 rad a turn).
TWO_PI = 2.0 * np.pi
#: TWO_PI split into its leading 27 bits and the rest (``TWO_PI_HI + TWO_PI_LO == TWO_PI``
#: exactly): ``k * TWO_PI_HI`` and ``k * TWO_PI_LO`` are exact for every whole ``|k| <= 2**26``.
TWO_PI_HI = float.fromhex("0x1.921fb54p+2")
TWO_PI_LO = float.fromhex("0x1.10b46p-28")
#: 2**26 TWO_PI (4.2e8 rad, exact): angles beyond it are first reduced by ``fmod`` modulo this
#: multiple of TWO_PI (exact, and the same remainder modulo TWO_PI).
TWO_PI_2_26 = float.fromhex("0x1.921fb54442d18p+28")
#: 2**6 TWO_PI (402 rad, exact): :func:`wrap` first reduces larger angles by ``fmod`` modulo
#: this multiple of TWO_PI, so that ``x + pi`` rounds by at most 2.8e-14 rad.
TWO_PI_2_6 = float.fromhex("0x1.921fb54442d18p+8")


def remainder_2pi(x: np.ndarray | float) -> np.ndarray | float:
    """``x`` (rad, a float or a float64 array) minus the nearest whole multiple of the float
    2 pi, **exactly** (no rounding at all): a value in [-pi, pi] (pi itself may come as -pi), as
    ``math.remainder(x, TWO_PI)`` gives it (a zero may come without its sign); NaN and infinity
    give NaN.

    The one reduction of angles modulo 2 pi, for :func:`wrap` and the indicator rule
    (:func:`ik7r.geometry.configs.arm_elbow_wrist`). It is computed without ``fmod`` (a library
    call, ten times slower than the rest, in the solver's inner loops): with the quotient
    ``k = rint(x / TWO_PI)``, ``(x - k TWO_PI_HI) - k TWO_PI_LO`` is exact while ``|k| <= 2**26``
    (both products are exact; both differences are exact because their operands lie on the float
    grid of ``x`` or of the result, which is small). A quotient rounded to the wrong side of a
    half turn leaves a value just beyond +-pi, folded back by one TWO_PI (exact). Angles beyond
    2**26 turns are first reduced by ``fmod`` modulo 2**26 TWO_PI (exact, the same remainder), in
    a ``while`` that runs once at most: behind an ``if``, LLVM computes ``fmod`` on every call (it
    is free of side effects, so it is evaluated before the test), ten times the cost of the rest.

    Written once over numpy operations: numpy code calls it on arrays and the compiled kernels
    call this same function on scalars (:func:`ik7r._kernels.jit.shared`), so both give the same
    bits.
    """
    while np.any(np.abs(x) >= TWO_PI_2_26):  # once at most ("while": numba would call fmod always)
        x = np.fmod(x, TWO_PI_2_26)
    return remainder_2pi_below_2_26(x)


def remainder_2pi_below_2_26(x: np.ndarray | float) -> np.ndarray | float:
    """:func:`remainder_2pi` of angles within 2**26 turns (``abs(x) < TWO_PI_2_26``), without the
    test for larger ones (what :func:`wrap` calls, having reduced them already)."""
    k = np.rint(x / TWO_PI)
    r = (x - k * TWO_PI_HI) - k * TWO_PI_LO
    return (r + TWO_PI * (r < -np.pi)) - TWO_PI * (r > np.pi)


def wrap(x: np.ndarray | float) -> np.ndarray | float:
    """The one angle wrap: ``x`` (rad, a float or a float64 array) modulo 2 pi into (-pi, pi].

    The value is ``(x + pi) mod TWO_PI`` (exact, :func:`remainder_2pi`) moved into (0, TWO_PI],
    minus pi: what ``numpy.mod`` gives, and what the solver has always returned. The only
    roundings are those of ``x + pi`` and of the final ``- pi``, so a value already in
    (-pi, pi] may move by an ulp (the indicator rule therefore reads :func:`remainder_2pi`, which
    does not round). Beyond 2**6 turns (402 rad) ``x`` is first reduced exactly by whole
    multiples of 2**6 TWO_PI: ``x + pi`` would otherwise round by up to half of ``x``'s float
    spacing, and beyond 1e16 rad lose pi altogether (``numpy.mod(x + pi, 2 pi) - pi`` is then
    ``x``'s angle plus pi). So every finite ``x``, 1e300 included, gives a value in (-pi, pi]
    within 3e-14 rad of ``x``'s remainder; NaN and infinity give NaN.

    Written once over numpy operations: numpy code calls it on arrays (through
    :func:`wrap_angle`) and the compiled kernels call this same function on scalars
    (:func:`ik7r._kernels.jit.shared` registers it with numba; in pure-Python mode they call it as
    it is), so both give the same bits.
    """
    while np.any(np.abs(x) >= TWO_PI_2_6):  # once at most, as in remainder_2pi
        x = np.fmod(x, TWO_PI_2_6)  # exact, the same angle; a smaller x loses less to x + pi
    r = remainder_2pi_below_2_26(x + np.pi)
    return (r + TWO_PI * (r <= 0.0)) - np.pi


def wrap_angle(x: ArrayLike) -> np.ndarray:
    """Angles wrapped to (-pi, pi] (:func:`wrap` of ``x`` as float64).

    >>> float(wrap_angle(-np.pi)), float(wrap_angle(3 * np.pi)), float(wrap_angle(1e300))
    (3.141592653589793, 3.141592653589793, -0.7234267005270318)
    """
    return wrap(np.asarray(x, dtype=float))  # type: ignore[return-value]


def nearest_rotation(R: ArrayLike) -> np.ndarray:
    """The proper rotation nearest ``R`` (..., 3, 3) in the Frobenius norm (polar factor)."""
    U, _, Vt = np.linalg.svd(np.asarray(R, dtype=float))
    D = np.ones(U.shape[:-1])
    D[..., -1] = np.sign(np.linalg.det(U @ Vt))
    return (U * D[..., None, :]) @ Vt


def relative_rotvec(R_a: ArrayLike, R_b: ArrayLike) -> np.ndarray:
    """Rotation vectors (..., 3) of ``R_a^T R_b``: the turn from each frame ``R_a`` (..., 3, 3)
    to ``R_b`` in ``R_a``'s own axes, its norm the angle between them (rad).

    Examples
    --------
    >>> import numpy as np
    >>> from ik7r.geometry import relative_rotvec, rot_z
    >>> relative_rotvec(rot_z(0.25), rot_z(1.0)).round(12)
    array([0.  , 0.  , 0.75])
    """
    from scipy.spatial.transform import Rotation

    rel = np.einsum("...ji,...jk->...ik", np.asarray(R_a, dtype=float), np.asarray(R_b, dtype=float))
    return Rotation.from_matrix(rel.reshape(-1, 3, 3)).as_rotvec().reshape(rel.shape[:-2] + (3,))
