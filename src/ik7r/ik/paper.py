"""The paper's method: the 1-D fixed-point iteration on theta5 (its Figure 5).

Kept deliberately close to the paper: guess theta5; place the virtual wrist centre P'c
(eqs. 4-5); solve the arm for P'c with the Arm and Elbow indicators (Appendix 1); solve the
wrist from the orientation with the Wrist indicator (Appendix 2), which gives a new theta5;
stop when theta5 no longer changes. It converges to *a* fixed point of the chosen branch, or
not at all (about 1-2 % of poses of the usable workspace): :func:`ik7r.ik.solve.ik` (the complete
solver) is the one to use; this one reproduces the paper's Tables 2, 3 and 5 and Figure 8.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._kernels import (
    arm_ik,
    chain,
    d_of_theta5,
    fk_user,
    frame07,
    residual,
    theta5_of_cos_bend,
    user_angle,
    wrist_ik,
    wrist_target,
)
from .._kernels import params as L
from ..geometry.checks import check_config, check_transforms
from ..geometry.configs import arm_elbow_wrist
from ..geometry.rotations import wrap_angle

if TYPE_CHECKING:
    from .._typing import ArrayLike, Config
    from ..robot.model import Robot

__all__ = ["PaperResult", "ik_paper"]


@dataclass(frozen=True)
class PaperResult:
    """Outcome of the paper's iteration for one pose and configuration.

    Attributes
    ----------
    q : ndarray (6,) or None
        The solution (rad, wrapped to (-pi, pi]) when ``ok``; otherwise None.
    ok : bool
        Converged and exact (forward kinematics within the robot's tolerances).
    converged : bool
        The increment of theta5 fell below the tolerance.
    iterations : int
        Number of iterations performed.
    theta5 : ndarray (iterations,)
        theta5 (rad) after each iteration.
    position_error : ndarray (iterations,)
        Position error of the whole joint vector after each iteration (robot length unit).
    elapsed : ndarray (iterations,)
        Seconds since the start after each iteration.
    q_last : ndarray (6,)
        The last iterate, exact or not (for diagnostics only).
    reason : str
        Why the result is not ok ('' when ok).
    """

    q: np.ndarray | None
    ok: bool
    converged: bool
    iterations: int
    theta5: np.ndarray
    position_error: np.ndarray
    elapsed: np.ndarray
    q_last: np.ndarray
    reason: str = ""


def ik_paper(robot: Robot, T: ArrayLike, config: Config = 1, *, theta5_start: float | None = None,
             tol: float = 1e-14, max_iter: int = 1000,
             rng: np.random.Generator | None = None) -> PaperResult:
    """The paper's iteration for one pose in one configuration.

    Parameters
    ----------
    robot : Robot
    T : array_like, shape (4, 4)
        World <- tool pose.
    config : int or (arm, elbow, wrist)
    theta5_start : float, optional
        Initial theta5 (rad, periodic: reduced modulo 2 pi); default random in the Wrist
        indicator's half (the paper). NaN or infinity raise ValueError.
    tol : float
        Stop when ``|theta5_new - theta5| <= tol`` (rad).
    max_iter : int
    rng : numpy.random.Generator, optional
        For the random start.
    """
    arm, elbow, wrist = check_config(config)
    Td = check_transforms(T)
    K = robot.kernel_params
    T07 = np.empty((4, 4))
    frame07(Td, K, T07)
    p, a = T07[:3, 3], T07[:3, 2] / np.linalg.norm(T07[:3, 2])
    sign = 1.0 if wrist == 1 else -1.0
    if theta5_start is None:
        rng = np.random.default_rng() if rng is None else rng
        theta5_start = sign * rng.uniform(0.0, math.pi)
    t5 = float(theta5_start)
    if not math.isfinite(t5):
        raise ValueError(f"theta5_start must be a finite angle in rad; got {theta5_start!r}")
    t5 = math.remainder(t5, 2 * math.pi)  # periodic (a start angle): reduced to [-pi, pi]
    hist_t5, hist_err, hist_time = [], [], []
    q = np.zeros(6)
    T = np.empty((4, 4))
    converged, reason = False, ""
    start = time.perf_counter()
    for _ in range(max_iter):
        d = d_of_theta5(t5, K)                                 # eq. (5)
        P = p - (K[L.D7] + d) * a                              # eq. (4)
        th = _arm_by_indicators(P, K[L.D4] + d, arm, elbow, K)  # Appendix 1
        if th is None:
            reason = "the virtual wrist centre is out of the arm's reach with these indicators"
            break
        M = np.eye(4)
        chain(th, K, 0, 3, M, L.NDH)
        Q = np.empty((3, 3))
        wrist_target(M[:3, :3], T07[:3, :3], K, Q)
        t5_new = sign * theta5_of_cos_bend(Q[2, 2], K)        # Appendix 2
        t4, t7 = wrist_ik(Q, t5_new, K[L.THETA_OFFSET4], K)
        q = np.array([user_angle(0, th[0], K), user_angle(1, th[1], K), user_angle(2, th[2], K),
                      user_angle(3, t4, K), user_angle(4, t5_new, K), user_angle(6, t7, K)])
        fk_user(q, K, T)
        hist_t5.append(t5_new)
        hist_err.append(residual(T, Td)[0])
        hist_time.append(time.perf_counter() - start)
        step, t5 = abs(t5_new - t5), t5_new
        if step <= tol:
            converged = True
            break
    else:
        reason = f"no convergence in {max_iter} iterations"
    q = wrap_angle(q)
    fk_user(q, K, T)
    dp, dr = residual(T, Td)
    exact = converged and dp <= K[L.POS_TOL] and dr <= K[L.ROT_TOL]
    if converged and not exact:
        reason = f"converged to a point that misses the pose by {dp:.3g} {robot.unit}, {dr:.3g} rad"
    return PaperResult(
        q=q if exact else None, ok=exact, converged=converged, iterations=len(hist_t5),
        theta5=np.array(hist_t5), position_error=np.array(hist_err), elapsed=np.array(hist_time),
        q_last=q, reason=reason,
    )


def _arm_by_indicators(P, Ld, arm, elbow, K):
    """Appendix 1: of the two theta1 (and then two theta3) take the one in the indicator's range."""
    for front in (1.0, -1.0):
        for elb in (1.0, -1.0):
            t1, t2, t3, ok = arm_ik(P[0], P[1], P[2], Ld, front, elb, 0.0, K)
            if not ok:
                continue
            a, e, _ = arm_elbow_wrist(user_angle(0, t1, K), user_angle(2, t3, K), 0.0)
            if a == arm and e == elbow:
                return np.array([t1, t2, t3])
    return None
