"""Length units: the one table of the units ik7r knows, and conversions between them.

Robot files, parts, guns and paths name their length unit; everything else is in the robot's
unit. Angles are radians in the API and degrees at the command line and in files.
"""

from __future__ import annotations

__all__ = ["METRES_PER_UNIT", "check_unit", "unit_scale"]

#: Metres in one unit, for every length unit ik7r accepts.
METRES_PER_UNIT = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "in": 0.0254}


def check_unit(unit: object, what: str = "length unit") -> str:
    """``unit`` if it is a known length unit, else ValueError naming the known ones."""
    if not isinstance(unit, str) or unit not in METRES_PER_UNIT:
        raise ValueError(f"unknown {what} {unit!r}; expected one of {', '.join(METRES_PER_UNIT)}")
    return unit


def unit_scale(from_unit: str, to_unit: str) -> float:
    """The factor that converts a length in ``from_unit`` into ``to_unit``."""
    return METRES_PER_UNIT[check_unit(from_unit)] / METRES_PER_UNIT[check_unit(to_unit)]
