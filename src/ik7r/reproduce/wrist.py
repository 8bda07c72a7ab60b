"""The multiple-solution study of the paper's section 3: Figure 6 (position error against theta5
for the four arm configurations) and Figure 7 (number of wrist solutions against theta5)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .published import EQ11_Q_DEG, FIGURE6_ARMS
from .simulation1 import same_joints

__all__ = [
    "ErrorCurve",
    "WristCount",
    "eq11_pose",
    "position_error_at_theta5",
    "error_curves",
    "wrist_solution_counts",
    "distinct",
    "DISTINCT_TOL",
]


def position_error_at_theta5(robot, T, arm: int, elbow: int, theta5) -> np.ndarray:
    """Position error of one step of the paper's method with theta5 held at each value.

    For each ``theta5``: place the virtual wrist centre (eqs. 4-5), solve the arm in the
    (Arm, Elbow) branch (Appendix 1), solve the wrist from the orientation (Appendix 2, the
    Wrist indicator being the sign of ``theta5``), and measure how far the resulting joints put
    the tool from ``T``. It is zero exactly at the solutions of that arm configuration.

    Parameters
    ----------
    robot : Robot
    T : array_like, shape (4, 4)
        World <- tool pose.
    arm, elbow : int
        Indicators, 0 or 1.
    theta5 : array_like, shape (n,)
        Values of theta5 (rad).

    Returns
    -------
    error : ndarray, shape (n,)
        Position error (robot length unit); NaN where the virtual wrist centre is out of reach.
    """
    t5 = np.atleast_1d(np.asarray(theta5, dtype=float))
    out = np.full(t5.shape, np.nan)
    for i, t in enumerate(t5):
        r = robot.ik_paper(T, (arm, elbow, 1 if t >= 0 else 0), theta5_start=float(t), max_iter=1)
        if r.iterations:
            out[i] = r.position_error[0]
    return out


@dataclass(frozen=True)
class ErrorCurve:
    """Figure 6, one panel.

    Attributes
    ----------
    label : str
        Panel name (A..D).
    arm, elbow : int
    theta5 : ndarray (n,)
        Grid (rad).
    error : ndarray (n,)
        :func:`position_error_at_theta5` on the grid (robot length unit).
    solutions_theta5 : ndarray (m,)
        theta5 (rad) of the complete solver's exact solutions in this arm configuration.
    """

    label: str
    arm: int
    elbow: int
    theta5: np.ndarray
    error: np.ndarray
    solutions_theta5: np.ndarray


def eq11_pose(robot) -> np.ndarray:
    """Eq. (11)'s pose (4, 4): forward kinematics of [30, 60, -60, -30, 60, 30] deg."""
    return robot.fk(np.radians(EQ11_Q_DEG))


def error_curves(robot, step_deg: float = 0.1, progress=None) -> list[ErrorCurve]:
    """Figure 6's four curves at eq. (11)'s pose, theta5 over [-180, 180] deg in ``step_deg`` steps.

    ``progress`` (optional) has ``advance(n)``; it is advanced once per grid point.
    """
    T = eq11_pose(robot)
    n = int(round(360.0 / step_deg)) + 1
    grid = np.radians(np.linspace(-180.0, 180.0, n))
    every = robot.ik_all(T)
    ind = robot.indicators(every) if len(every) else np.zeros((0, 3), dtype=int)
    curves = []
    for label, arm, elbow in FIGURE6_ARMS:
        err = np.empty(n)
        for lo in range(0, n, 200):
            err[lo:lo + 200] = position_error_at_theta5(robot, T, arm, elbow, grid[lo:lo + 200])
            if progress is not None:
                progress.advance(len(grid[lo:lo + 200]))
        mine = (ind[:, 0] == arm) & (ind[:, 1] == elbow)
        curves.append(ErrorCurve(label, arm, elbow, grid, err, np.sort(every[mine, 4])))
    return curves


@dataclass(frozen=True)
class WristCount:
    """Figure 7's data: for targets with a given theta5 and random other joints.

    Attributes
    ----------
    theta5 : ndarray (n,)
        theta5 of each target (rad).
    q : ndarray (n, 6)
        The target joints (rad).
    wrist_solutions : ndarray (n,) int
        Distinct exact solutions sharing the target's arm joints (q1, q2, q3): the solutions of
        the last four joints.
    all_solutions : ndarray (n,) int
        Every distinct exact solution of the pose (complete solver).
    raw_solutions : ndarray (n,) int
        What the complete solver returned before merging near-duplicates (solutions closer than
        ``DISTINCT_TOL`` in every joint); it differs from ``all_solutions`` only when the solver
        returned the same solution several times.
    """

    theta5: np.ndarray
    q: np.ndarray
    wrist_solutions: np.ndarray
    all_solutions: np.ndarray
    raw_solutions: np.ndarray


def wrist_solution_counts(robot, rng: np.random.Generator, *, step_deg: float = 10.0,
                          draws: int = 10) -> WristCount:
    """Figure 7: theta5 over [-180, 180] deg in ``step_deg`` steps, ``draws`` targets per value with
    the other joints uniform within the joint limits (the usable workspace, Table 4), solved by the
    complete solver; the wrist solutions are those sharing the target's arm."""
    n = int(round(360.0 / step_deg)) + 1
    t5 = np.repeat(np.radians(np.linspace(-180.0, 180.0, n)), draws)
    q = rng.uniform(robot.lower, robot.upper, (len(t5), 6))
    q[:, 4] = t5
    sols, valid = robot.ik_all_batch(robot.fk(q))
    arm = np.zeros(len(t5), dtype=int)
    every = np.zeros(len(t5), dtype=int)
    for i in range(len(t5)):
        s = distinct(sols[i][valid[i]])
        every[i] = len(s)
        arm[i] = int(same_joints(s[:, :3], q[i, :3], 1e-6).sum()) if len(s) else 0
    return WristCount(t5, q, arm, every, valid.sum(axis=1))


#: Solutions closer than this (rad, in every joint, modulo 2 pi) are counted once in Figure 7.
DISTINCT_TOL = 1e-4


def distinct(sols, tol: float = DISTINCT_TOL) -> np.ndarray:
    """The solutions ``sols`` (M, 6) rad with near-duplicates (closer than ``tol`` in every joint,
    modulo 2 pi) merged, keeping the first of each group: (M', 6)."""
    keep: list[np.ndarray] = []
    for s in np.asarray(sols, dtype=float).reshape(-1, 6):
        if not any(same_joints(k, s, tol) for k in keep):
            keep.append(s)
    return np.array(keep).reshape(-1, 6)
