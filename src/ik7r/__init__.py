"""ik7r: exact, complete and fast kinematics for 7R 6-DOF robots with a coupled hollow
non-spherical wrist (painting robots such as the ABB IRB 5400).

>>> import ik7r
>>> robot = ik7r.load_robot()          # the paper's robot (mm)
>>> T = robot.fk([1.0, 1.0, 0.0, -0.5, 1.0, 0.5])
>>> robot.ik_all(T).shape[1]
6

Nothing heavy happens at import time: the compiled kernels load on first use.
"""

from __future__ import annotations

from .errors import FamilyError, RobotFileError, UnreachableError

__version__ = "0.1.0"

__all__ = [
    "load_robot",
    "Robot",
    "UnreachableError",
    "RobotFileError",
    "FamilyError",
    "MAX_SOLUTIONS",
    "__version__",
]


def __getattr__(name: str):
    if name == "load_robot":
        from .robot.files import load_robot

        return load_robot
    if name == "Robot":
        from .robot.model import Robot

        return Robot
    if name == "MAX_SOLUTIONS":
        from ._kernels.params import MAX_SOLUTIONS  # no numba: params is plain numpy

        return MAX_SOLUTIONS
    raise AttributeError(f"module 'ik7r' has no attribute {name!r}")
