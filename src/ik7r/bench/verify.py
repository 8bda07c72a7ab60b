"""The yardstick and the checks every timed answer goes through."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..geometry.rotations import dh_transform, wrap_angle

if TYPE_CHECKING:
    from .._typing import ArrayLike
    from ..robot.model import Robot

__all__ = ["numpy_fk", "fk_ok", "same_solution", "verify_all"]


def numpy_fk(robot: Robot, q: ArrayLike) -> np.ndarray:
    """The yardstick: plain vectorised numpy forward kinematics, the product of the seven
    eq. (1) matrices (with the robot's base and tool when they are not the identity).

    ``q`` (..., 6) rad -> (..., 4, 4).
    """
    q = np.asarray(q, dtype=float)
    dh = robot.dh
    sign = robot.joint_sign
    c0, c1 = robot.coupling
    q7 = np.concatenate([q[..., :5], c0 * q[..., 4:5] + c1, q[..., 5:6]], axis=-1)
    M = dh_transform(dh[:, 0], dh[:, 1], sign * q7 + dh[:, 3], dh[:, 2])
    T = M[..., 0, :, :]
    for i in range(1, 7):
        T = T @ M[..., i, :, :]
    if not np.array_equal(robot.base, np.eye(4)):
        T = robot.base @ T
    if not np.array_equal(robot.tool, np.eye(4)):
        T = T @ robot.tool
    return T


def fk_ok(robot, q: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Whether joints ``q`` (M, 6) reach poses ``T`` (M, 4, 4) within the robot's tolerances
    (the residual of the kernels: position distance, ``sqrt(|R - Rd|_F^2 / 2)``)."""
    if len(q) == 0:
        return np.zeros(0, dtype=bool)
    Tq = robot.fk(q)
    dp = np.linalg.norm(Tq[:, :3, 3] - T[:, :3, 3], axis=1)
    dr = np.sqrt(0.5 * ((Tq[:, :3, :3] - T[:, :3, :3]) ** 2).sum(axis=(1, 2)))
    return (dp <= robot.position_tolerance) & (dr <= robot.rotation_tolerance)


def _distance(x):
    """|x| modulo 2 pi, in [0, pi]."""
    return np.abs(wrap_angle(x))


def same_solution(sols: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Which rows of ``sols`` (..., 6) equal ``q`` (..., 6) modulo 2 pi (1e-6 rad); at a
    straight wrist (q5 = 0) only q4 + q7 is defined."""
    d = _distance(sols - q)
    same = d.max(axis=-1) < 1e-6
    straight = _distance(q[..., 4]) < 1e-6
    if np.any(straight):
        sum_ok = _distance((sols[..., 3] + sols[..., 5]) - (q[..., 3] + q[..., 5])) < 1e-6
        alt = (np.maximum(d[..., :3].max(axis=-1), d[..., 4]) < 1e-6) & sum_ok
        same = np.where(straight, same | alt, same)
    return same


def verify_all(robot, q: np.ndarray, valid: np.ndarray, T: np.ndarray, Q: np.ndarray) -> int:
    """Failures of ``ik_all_batch``'s answer: solutions off the pose, and poses whose
    generating joints ``Q`` are not among their solutions."""
    idx = np.nonzero(valid)
    wrong = int((~fk_ok(robot, q[idx], T[idx[0]])).sum())
    found = (same_solution(q, Q[:, None, :]) & valid).any(axis=1)
    return wrong + int((~found).sum())
