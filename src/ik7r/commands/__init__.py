"""Subcommands of the ``ik7r`` command line, one module each.

Each module defines ``add_parser(subparsers)``, which registers the subcommand and sets
``run`` (a function of the parsed arguments returning the exit status) as its default.
"""

COMMANDS = ["fk", "ik", "demo"]
