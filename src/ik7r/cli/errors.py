"""What the command line reports instead of a traceback."""

from __future__ import annotations

__all__ = ["CliError", "NoSolution"]


class CliError(Exception):
    """Bad input at the command line: reported in one line, exit status 2."""


class NoSolution(Exception):
    """The pose has no solution: reported in one line, exit status 1."""
