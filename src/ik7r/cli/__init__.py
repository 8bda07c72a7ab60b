"""The ``ik7r`` command line: :func:`main` (in :mod:`.app`), one module per subcommand in
:mod:`.commands`, and the errors it reports in one line (:mod:`.errors`).

The module holding ``main`` is ``app``, not ``main``: a submodule named like the function it
defines would be hidden by it (``ik7r.cli.main`` is the function).
"""

from __future__ import annotations

from .app import build_parser, main
from .errors import CliError, NoSolution

__all__ = ["main", "build_parser", "CliError", "NoSolution"]
