"""Type aliases of the annotations of ik7r's public functions."""

from __future__ import annotations

import os
from typing import TypeAlias

import numpy as np
import numpy.typing as npt

__all__ = ["ArrayLike", "Array", "Config", "RobotSource", "PathLike"]

#: Anything numpy turns into an array of floats (lists, tuples, arrays).
ArrayLike: TypeAlias = npt.ArrayLike
#: A float64 array returned by ik7r.
Array: TypeAlias = npt.NDArray[np.float64]
#: A configuration: its number 1..8 (the paper's Appendix 3) or its (arm, elbow, wrist) indicators.
Config: TypeAlias = "int | tuple[int, int, int]"
#: A file system path.
PathLike: TypeAlias = "str | os.PathLike[str]"
#: What :func:`ik7r.load_robot` takes: None (the paper's robot), a built-in name or a file path.
RobotSource: TypeAlias = "str | os.PathLike[str] | None"
