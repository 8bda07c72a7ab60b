"""Subcommands of the ``ik7r`` command line, one module each.

Each public module here (a name not starting with ``_``) defines ``add_parser(subparsers)``,
which registers the subcommand and sets ``run`` (a function of the parsed arguments returning
the exit status) as its default. Modules import their heavy dependencies inside ``run`` so
that ``ik7r`` starts fast.
"""

from __future__ import annotations

import pkgutil


def command_modules() -> list[str]:
    """Names of the subcommand modules, in alphabetical order."""
    return sorted(m.name for m in pkgutil.iter_modules(__path__) if not m.name.startswith("_"))
