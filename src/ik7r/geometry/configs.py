"""The paper's configuration indicators (section 3 and Appendix 3)."""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike
from .rotations import wrap_angle

__all__ = ["indicators", "config_number", "config_of_indicators", "describe_config"]

HALF_PI = 0.5 * np.pi


def indicators(q: np.ndarray) -> np.ndarray:
    """(Arm, Elbow, Wrist) of joints ``q`` (..., 6) in rad -> (..., 3) int.

    Arm = 1 when q1 is in [-pi/2, pi/2); Elbow = 1 when q3 is in [-pi/2, pi/2);
    Wrist = 1 when q5 is in [0, pi). Angles are taken modulo 2 pi.
    """
    q1 = wrap_angle(q[..., 0])
    q3 = wrap_angle(q[..., 2])
    q5 = wrap_angle(q[..., 4])
    arm = (q1 >= -HALF_PI) & (q1 < HALF_PI)
    elbow = (q3 >= -HALF_PI) & (q3 < HALF_PI)
    wrist = (q5 >= 0.0) & (q5 < np.pi)
    return np.stack([arm, elbow, wrist], axis=-1).astype(int)


def config_of_indicators(arm: ArrayLike, elbow: ArrayLike, wrist: ArrayLike) -> np.ndarray:
    """Configuration number 1..8 of the paper's Appendix 3."""
    return 1 + 4 * (1 - np.asarray(arm)) + 2 * (1 - np.asarray(elbow)) + (1 - np.asarray(wrist))


def config_number(q: np.ndarray) -> np.ndarray:
    """Configuration number 1..8 of joints ``q`` (..., 6)."""
    ind = indicators(q)
    return config_of_indicators(ind[..., 0], ind[..., 1], ind[..., 2])


def describe_config(arm: int, elbow: int, wrist: int) -> str:
    """``'configuration 3 (arm=1, elbow=0, wrist=1)'``."""
    number = int(config_of_indicators(arm, elbow, wrist))
    return f"configuration {number} (arm={arm}, elbow={elbow}, wrist={wrist})"
