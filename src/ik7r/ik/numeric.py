"""Jacobian-based baselines: Newton-Raphson (the paper's eq. (9)) and damped least squares.

They are here to compare against (the paper's Table 3 and the benchmarks), not to be used
for production: they find one solution near their start, or fail, and never tell whether
other solutions exist. Both report failure honestly; neither returns a non-converged result
as a solution.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .. import _kernels as _kin
from ..geometry.checks import check_joints, check_transforms
from ..geometry.rotations import wrap_angle

if TYPE_CHECKING:
    from .._typing import ArrayLike
    from ..robot.model import Robot

__all__ = ["NumericResult", "newton_raphson", "damped_least_squares", "manipulability"]


@dataclass(frozen=True)
class NumericResult:
    """Outcome of a Jacobian-based solve.

    ``q`` is the solution (rad, wrapped) when ``ok``, else None; ``q_last`` is the last
    iterate; ``reason`` says why it failed ('' when ok); ``elapsed`` is in seconds.
    """

    q: np.ndarray | None
    ok: bool
    iterations: int
    position_error: np.ndarray
    q_last: np.ndarray
    elapsed: float
    reason: str = ""


def _errors(robot, q, Td, T, e):
    _kin.fk_user(q, robot.kernel_params, T)
    _kin.pose_error(T, Td, e, np.empty((3, 3)))
    return _kin.residual(T, Td)


def _finish(robot, q, Td, T, e, it, hist, start, reason):
    q = wrap_angle(q)
    dp, dr = _errors(robot, q, Td, T, e)
    ok = reason == "" and dp <= robot.position_tolerance and dr <= robot.rotation_tolerance
    if reason == "" and not ok:
        reason = f"stopped {dp:.3g} {robot.unit} and {dr:.3g} rad from the pose"
    return NumericResult(q if ok else None, ok, it, np.array(hist), q, time.perf_counter() - start, reason)


def newton_raphson(robot: Robot, T: ArrayLike, q0: ArrayLike, *, tol: float = 1e-12, max_iter: int = 100,
                   singular_tol: float = 1e-10) -> NumericResult:
    """The paper's Newton-Raphson, ``theta += J^-1 e`` (eq. (9)), from ``q0`` (6,) rad.

    Stops when ``||d theta|| <= tol``. Fails (``ok = False``, reason given) when the Jacobian
    is singular (its smallest relative pivot below ``singular_tol``) or after ``max_iter``.
    """
    Td = check_transforms(T)
    q = check_joints(q0, "q0").astype(float).copy()
    K = robot.kernel_params
    J, T_, e, dq = np.empty((6, 6)), np.empty((4, 4)), np.empty(6), np.empty(6)
    hist = []
    start = time.perf_counter()
    for it in range(1, max_iter + 1):
        hist.append(_errors(robot, q, Td, T_, e)[0])
        _kin.jacobian(q, K, J)
        pivot = _kin.solve6(J, e.copy(), dq)
        if pivot < singular_tol:
            return _finish(robot, q, Td, T_, e, it, hist, start,
                           f"singular Jacobian at iteration {it} (relative pivot {pivot:.2e})")
        q += dq
        if not np.all(np.isfinite(q)):
            return _finish(robot, q, Td, T_, e, it, hist, start, "diverged")
        if np.linalg.norm(dq) <= tol:
            return _finish(robot, q, Td, T_, e, it, hist, start, "")
    return _finish(robot, q, Td, T_, e, max_iter, hist, start, f"no convergence in {max_iter} iterations")


def damped_least_squares(robot: Robot, T: ArrayLike, q0: ArrayLike, *, damping: float = 1e-3,
                         tol: float = 1e-12, max_iter: int = 500) -> NumericResult:
    """Levenberg-Marquardt (damped least squares) from ``q0``: the generic robust solver.

    Solves ``(J^T W J + lambda^2 I) dq = J^T W e`` with position rows scaled by the robot's
    size; ``lambda`` adapts (halved after a successful step, raised tenfold after a bad one).
    """
    Td = check_transforms(T)
    q = check_joints(q0, "q0").astype(float).copy()
    K = robot.kernel_params
    scale = robot.family.scale
    w = np.array([1 / scale] * 3 + [1.0] * 3)
    J, T_, e = np.empty((6, 6)), np.empty((4, 4)), np.empty(6)
    hist = []
    lam = damping
    start = time.perf_counter()
    dp, dr = _errors(robot, q, Td, T_, e)
    cost = float(np.sum((w * e) ** 2))
    for it in range(1, max_iter + 1):
        hist.append(dp)
        if dp <= robot.position_tolerance and dr <= robot.rotation_tolerance:
            return _finish(robot, q, Td, T_, e, it, hist, start, "")
        _kin.jacobian(q, K, J)
        Jw = J * w[:, None]
        dq = np.linalg.solve(Jw.T @ Jw + lam**2 * np.eye(6), Jw.T @ (w * e))
        trial = q + dq
        e2 = np.empty(6)
        dp2, dr2 = _errors(robot, trial, Td, T_, e2)
        cost2 = float(np.sum((w * e2) ** 2))
        if cost2 < cost:
            q, e, cost, dp, dr = trial, e2, cost2, dp2, dr2
            lam = max(lam * 0.5, 1e-12)
            if np.linalg.norm(dq) <= tol:
                return _finish(robot, q, Td, T_, e, it, hist, start, "")
        else:
            lam *= 10.0
            if lam > 1e8:
                return _finish(robot, q, Td, T_, e, it, hist, start, "stuck in a local minimum")
    return _finish(robot, q, Td, T_, e, max_iter, hist, start, f"no convergence in {max_iter} iterations")


def manipulability(robot: Robot, q: ArrayLike) -> np.ndarray:
    """``det(J J^T)`` (the paper's eq. (10)) for joints ``q`` (..., 6); zero at singularities."""
    J = robot.jacobian(q)
    return np.linalg.det(J @ np.swapaxes(J, -1, -2))
