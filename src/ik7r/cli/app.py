"""The ``ik7r`` command line: degrees and millimetres (the robot file's unit) at the prompt.

Exit status: 0 success; 1 a pose with no solution; 2 bad input (one line on stderr, no
traceback). Each subcommand lives in :mod:`ik7r.cli.commands` (one module per command).
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from ..errors import UnreachableError
from .commands import command_modules
from .errors import CliError, NoSolution

#: One-shot commands that solve a single pose: they run the kernels without numba (see ik7r._kernels.jit).
FAST_START = ("fk", "ik")


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, exit status 2
        raise CliError(f"{self.prog}: {message}")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ik7r", description="Exact, complete and fast kinematics for 7R 6-DOF "
                     "painting robots with a coupled hollow wrist.")
    parser.add_argument("--robot", default=None, metavar="NAME|PATH",
                        help="built-in robot name (paper, irb5400) or a .toml / .urdf file "
                             "(default: the paper's robot)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in command_modules():
        module = importlib.import_module(f"ik7r.cli.commands.{name}")
        module.add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``ik7r`` console script."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 2
        if args.command in FAST_START and "ik7r._kernels.jit" not in sys.modules:
            os.environ.setdefault("IK7R_JIT", "0")  # one pose: plain Python beats numba's start-up
        return int(args.run(args) or 0)
    except CliError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except NoSolution as exc:
        print(f"no solution: {exc}", file=sys.stderr)
        return 1
    except UnreachableError as exc:
        print(f"no solution: {exc}", file=sys.stderr)
        return 1
    except (ValueError, FileNotFoundError) as exc:  # the library's own input checks
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader went away (``ik7r ... | head``): not an error
        try:
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - silence the flush at exit
        except OSError:
            pass
        return 0
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
