"""The paper's configuration indicators (section 3 and Appendix 3).

The rule and the numbering are written once here, over numpy operations, and serve numpy code
(on arrays) and the compiled kernels (on scalars) alike: the kernels compile these same
functions (:func:`ik7r._kernels.jit.shared`), so both give the same answers bit for bit.

- :func:`arm_elbow_wrist`, the one indicator rule: Arm = 1 when q1 is in [-pi/2, pi/2),
  Elbow = 1 when q3 is in [-pi/2, pi/2), Wrist = 1 when q5 is in [0, pi), each angle taken
  modulo 2 pi exactly (:func:`ik7r.geometry.rotations.remainder_2pi`, the reduction under the one
  wrap; the wrap itself rounds by an ulp, which would move q1 = pi/2 - 1 ulp onto pi/2).
- :func:`number_of`, the one numbering: configuration ``1 + 4 (1 - Arm) + 2 (1 - Elbow) +
  (1 - Wrist)``, so 1 is (1, 1, 1) and 8 is (0, 0, 0), as in the paper's Appendix 3.

The solver keeps one more rule on top of this one, for solutions *on* a boundary (they belong
to both sides): :func:`ik7r._kernels.select.matches`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._typing import ArrayLike
from .rotations import remainder_2pi

__all__ = ["indicators", "config_number", "config_of_indicators", "describe_config",
           "arm_elbow_wrist", "number_of"]

HALF_PI = 0.5 * np.pi


def arm_elbow_wrist(q1: np.ndarray | float, q3: np.ndarray | float,
                    q5: np.ndarray | float) -> tuple[Any, Any, Any]:
    """The one indicator rule: (Arm, Elbow, Wrist) of joints ``q1``, ``q3``, ``q5`` (rad, any
    value; floats or float64 arrays of one shape) as booleans (or boolean arrays).

    Half-open ranges of the angles modulo 2 pi (:func:`~ik7r.geometry.rotations.remainder_2pi`,
    exact, so a q1 one ulp below pi/2 has Arm = 1): Arm when q1 is in [-pi/2, pi/2), Elbow when
    q3 is in [-pi/2, pi/2), Wrist when q5 is in [0, pi). pi and -pi are the same angle, in none
    of the three ranges.
    """
    a, e, w = remainder_2pi(q1), remainder_2pi(q3), remainder_2pi(q5)
    return (a >= -HALF_PI) & (a < HALF_PI), (e >= -HALF_PI) & (e < HALF_PI), (w >= 0.0) & (w < np.pi)


def number_of(arm: Any, elbow: Any, wrist: Any) -> Any:
    """The one numbering: configuration 1..8 of indicators (0/1 or booleans, scalars or arrays),
    ``1 + 4 (1 - arm) + 2 (1 - elbow) + (1 - wrist)``."""
    return 8 - 4 * arm - 2 * elbow - wrist


def indicators(q: np.ndarray) -> np.ndarray:
    """(Arm, Elbow, Wrist) of joints ``q`` (..., 6) in rad -> (..., 3) int.

    Arm = 1 when q1 is in [-pi/2, pi/2); Elbow = 1 when q3 is in [-pi/2, pi/2);
    Wrist = 1 when q5 is in [0, pi). Angles are taken modulo 2 pi (:func:`arm_elbow_wrist`).
    """
    q = np.asarray(q, dtype=float)
    return np.stack(arm_elbow_wrist(q[..., 0], q[..., 2], q[..., 4]), axis=-1).astype(int)


def config_of_indicators(arm: ArrayLike, elbow: ArrayLike, wrist: ArrayLike) -> np.ndarray:
    """Configuration number 1..8 of the paper's Appendix 3 (:func:`number_of`)."""
    return number_of(np.asarray(arm), np.asarray(elbow), np.asarray(wrist))


def config_number(q: np.ndarray) -> np.ndarray:
    """Configuration number 1..8 of joints ``q`` (..., 6)."""
    q = np.asarray(q, dtype=float)
    return number_of(*arm_elbow_wrist(q[..., 0], q[..., 2], q[..., 4]))


def describe_config(arm: int, elbow: int, wrist: int) -> str:
    """``'configuration 3 (arm=1, elbow=0, wrist=1)'``."""
    number = int(config_of_indicators(arm, elbow, wrist))
    return f"configuration {number} (arm={arm}, elbow={elbow}, wrist={wrist})"
