"""Writing a painting trajectory as CSV.

Columns ``t, x, y, z, q1..q7, dq1..dq7, ddq1..ddq7``: time (s); the path point of the row
(tool position in the robot's base frame, robot length unit); the seven joints (deg) with the
coupled joint 6 from ``robot.coupling`` (``q6 = multiplier * q5 + offset``), their velocities
(deg/s) and accelerations (deg/s^2). Numbers are printed with 12 significant digits, so the
joints are exact to about 1e-10 deg (about 1e-8 mm of tool position on a 2 m robot).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .._typing import PathLike
    from ..robot.model import Robot
    from .interpolate import Trajectory

from pathlib import Path as FilePath

import numpy as np

__all__ = ["CSV_COLUMNS", "trajectory_table", "write_trajectory_csv"]

#: Column names of :func:`write_trajectory_csv`.
CSV_COLUMNS = (["t", "x", "y", "z"] + [f"q{i}" for i in range(1, 8)] + [f"dq{i}" for i in range(1, 8)]
               + [f"ddq{i}" for i in range(1, 8)])
_FMT = "%.12g"


def _seven(robot, x: np.ndarray, derivative: bool) -> np.ndarray:
    """(M, 6) independent joints (or their derivatives) -> (M, 7) with joint 6 inserted."""
    mult, offset = robot.coupling
    q6 = mult * x[:, 4] + (0.0 if derivative else offset)
    return np.column_stack([x[:, :5], q6, x[:, 5]])


def trajectory_table(robot: Robot, trajectory: Trajectory) -> np.ndarray:
    """The CSV's numbers ``(M, 25)`` in its units (s, length unit, deg, deg/s, deg/s^2)."""
    return np.column_stack([
        trajectory.t,
        trajectory.positions,
        np.degrees(_seven(robot, trajectory.q, False)),
        np.degrees(_seven(robot, trajectory.dq, True)),
        np.degrees(_seven(robot, trajectory.ddq, True)),
    ])


def write_trajectory_csv(robot: Robot, trajectory: Trajectory, file: PathLike) -> FilePath:
    """Write ``trajectory`` to ``file`` (see the module docstring); returns the path."""
    fp = FilePath(file)
    np.savetxt(fp, trajectory_table(robot, trajectory), delimiter=",", fmt=_FMT,
               header=",".join(CSV_COLUMNS), comments="")
    return fp
