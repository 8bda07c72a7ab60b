"""Typed errors raised by ik7r.

Every error ik7r raises on purpose is an :class:`Ik7rError`; each is also a :class:`ValueError`
(bad input), so callers that only know the standard library still catch them. A missing file
raises the standard :class:`FileNotFoundError`.
"""

from __future__ import annotations

__all__ = ["Ik7rError", "UnreachableError", "RobotFileError", "FamilyError", "PartFileError", "GunFileError"]


class Ik7rError(Exception):
    """Base class of the errors ik7r raises on purpose."""


class UnreachableError(Ik7rError, ValueError):
    """No exact solution exists for the requested pose (and configuration)."""


class RobotFileError(Ik7rError, ValueError):
    """A robot file (TOML or URDF) is malformed; the message names the file and the problem."""


class FamilyError(Ik7rError, ValueError):
    """A kinematic chain is not of the 7R coupled-wrist family ik7r solves."""


class PartFileError(Ik7rError, ValueError):
    """A part (mesh) file is unreadable, empty, has no faces or non-finite vertices; the
    message names the file and the problem."""


class GunFileError(Ik7rError, ValueError):
    """A spray-gun file (TOML) is malformed; the message names the file and the problem."""
