"""Typed errors raised by ik7r.

Every error is a subclass of :class:`ValueError` (or :class:`FileNotFoundError` for a
missing robot file), so callers that only know the standard library still catch them.
"""

from __future__ import annotations

__all__ = ["UnreachableError", "RobotFileError", "FamilyError"]


class UnreachableError(ValueError):
    """No exact solution exists for the requested pose (and configuration)."""


class RobotFileError(ValueError):
    """A robot file (TOML or URDF) is malformed; the message names the file and the problem."""


class FamilyError(ValueError):
    """A kinematic chain is not of the 7R coupled-wrist family ik7r solves."""
