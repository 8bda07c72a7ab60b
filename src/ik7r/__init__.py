"""ik7r: exact, complete and fast kinematics for 7R 6-DOF robots with a coupled hollow
non-spherical wrist (painting robots such as the ABB IRB 5400).

>>> import ik7r
>>> robot = ik7r.load_robot()          # the paper's robot (mm)
>>> T = robot.fk([1.0, 1.0, 0.0, -0.5, 1.0, 0.5])
>>> robot.ik_all(T).shape[1]
6

Nothing heavy happens at import time: the subpackages and the compiled kernels load on first
use. The subpackages, one per concept:

=============== ==============================================================================
``robot``       the frozen :class:`Robot`, its family, TOML robot files and URDF
``geometry``    rotations and transforms, the Arm/Elbow/Wrist indicators, input checks
``ik``          the complete solver, warm-started paths, chunked batches, the paper's iteration
``painting``    painting paths, trajectory IK, timing, outputs and plots
``reproduce``   the paper's tables and figures
``cli``         the ``ik7r`` command line
=============== ==============================================================================
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ._lazy import lazy_exports
from .errors import FamilyError, Ik7rError, RobotFileError, UnreachableError

if TYPE_CHECKING:  # the lazy names below, as type checkers and IDEs should see them
    from ._kernels.params import MAX_SOLUTIONS
    from .robot.files import load_robot
    from .robot.model import Robot

__version__ = "0.1.0"

__all__ = [
    "load_robot",
    "Robot",
    "Ik7rError",
    "UnreachableError",
    "RobotFileError",
    "FamilyError",
    "MAX_SOLUTIONS",
    "__version__",
]


__getattr__, __dir__ = lazy_exports(
    __name__,
    {"load_robot": "robot.files", "Robot": "robot.model", "MAX_SOLUTIONS": "_kernels.params"},
    ("robot", "geometry", "ik", "painting", "reproduce", "units", "cli"),
)
