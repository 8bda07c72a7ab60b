"""The ``ik7r`` command line: degrees and millimetres (the robot file's unit) at the prompt.

Exit status: 0 success; 1 a pose with no solution; 2 bad input (one line on stderr, no
traceback). Each subcommand lives in :mod:`ik7r.cli.commands` (one module per command).
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import sys

from ..errors import UnreachableError
from .commands import command_modules
from .errors import CliError, NoSolution

#: One-shot commands that solve a single pose: they run the kernels without numba (see ik7r._kernels.jit).
FAST_START = ("fk", "ik")


#: Exit status of an internal error (a bug: reported in one line, never a traceback).
EXIT_INTERNAL = 3


class _Parser(argparse.ArgumentParser):
    """One-line errors (exit status 2); every subcommand also takes ``--robot`` (after its name)."""

    def __init__(self, *a, robot_option: bool = True, **kw) -> None:
        super().__init__(*a, **kw)
        if robot_option:  # the global option, accepted after the subcommand too
            self.add_argument("--robot", default=argparse.SUPPRESS, metavar="NAME|PATH",
                              help="the robot (as the global option: a built-in name or a .toml / .urdf)")

    def error(self, message: str):  # one line, exit status 2
        raise CliError(f"{self.prog}: {message}")


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

    parser = _Parser(prog="ik7r", robot_option=False,
                     description="Exact, complete and fast kinematics for 7R 6-DOF "
                     "painting robots with a coupled hollow wrist.")
    parser.add_argument("--robot", default=None, metavar="NAME|PATH",
                        help="built-in robot name (paper, irb5400) or a .toml / .urdf file "
                             "(default: the paper's robot); also accepted after the subcommand")
    parser.add_argument("--version", action="version", version=f"ik7r {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in command_modules():
        module = importlib.import_module(f"ik7r.cli.commands.{name}")
        module.add_parser(sub)
    return parser


def _wants_json(args, argv) -> bool:
    """Whether ``--json`` (the flag, not bench's ``--json FILE``) was asked for."""
    if args is not None:
        return getattr(args, "json", None) is True
    return "--json" in argv and "bench" not in argv


def _one_line(text: str) -> str:
    line = " ".join(str(text).split())
    return line if len(line) <= 2000 else line[:1997] + "..."


def _compiled_kernels() -> bool:
    """Whether the kernels compiled at installation are there (:mod:`ik7r._kernels.aot`): they
    answer one pose without numba's start-up, faster than plain Python."""
    if os.environ.get("IK7R_JIT", "1") == "0":
        return False
    from .._kernels import aot

    return aot.load() is not None


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``ik7r`` console script: never a traceback, one line on stderr.

    Exit status: 0 success, 1 no solution, 2 bad input (or an output that cannot be written),
    130 interrupted (SIGINT), 128 + N on signal N (SIGTERM: 143), 3 an internal error.
    """
    import warnings

    import numpy as np

    from ..outputs import OutputError, Terminated, describe_os_error, signals_raise

    argv = list(sys.argv[1:] if argv is None else argv)
    args = None
    status, message, prefix = 0, "", "error"
    try:
        with signals_raise(), warnings.catch_warnings(), np.errstate(all="ignore"):
            # overflow and invalid-value warnings of hostile numbers: the results are verified
            # (or refused) anyway, the warnings would only be noise on stderr
            warnings.simplefilter("ignore", RuntimeWarning)
            parser = build_parser()
            if not argv:
                parser.print_usage(sys.stderr)
                print("error: give a command (ik7r --help lists them)", file=sys.stderr)
                return 2
            args = parser.parse_args(argv)
            if args.command is None:
                raise CliError("give a command (ik7r --help lists them)")
            if (args.command in FAST_START and "ik7r._kernels.jit" not in sys.modules
                    and not _compiled_kernels()):
                os.environ.setdefault("IK7R_JIT", "0")  # one pose: plain Python beats numba's start-up
            return int(args.run(args) or 0)
    except SystemExit as exc:  # --help, --version
        return exc.code if isinstance(exc.code, int) else 0
    except CliError as exc:
        status, message = 2, str(exc)
    except (NoSolution, UnreachableError) as exc:
        status, message, prefix = 1, str(exc), "no solution"
    except OutputError as exc:
        status, message = 2, exc.strerror or str(exc)
    except (ValueError, FileNotFoundError) as exc:  # the library's own input checks
        status, message = 2, str(exc)
    except BrokenPipeError:  # the reader went away (``ik7r ... | head``): not an error
        try:
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - silence the flush at exit
        except OSError:
            pass
        return 0
    except OSError as exc:
        status, message = 2, describe_os_error(exc, exc.filename or "output")
    except MemoryError:
        status, message = 2, "not enough memory for this input (see the work limits in --help)"
    except RecursionError:
        status, message = 2, "input nested too deeply"
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Terminated as exc:
        print(f"terminated ({exc})", file=sys.stderr)
        return 128 + exc.signum
    except Exception as exc:  # a bug: still one line, never a traceback
        status, message, prefix = EXIT_INTERNAL, f"{type(exc).__name__}: {exc}", "internal error"
    line = _one_line(message)
    if _wants_json(args, argv) and not (args is not None and getattr(args, "_json_done", False)):
        doc = {"error": line, "status": status}
        if (args.command if args is not None else "ik" if "ik" in argv else None) == "ik":
            doc["solutions"] = []
        print(json.dumps(doc))
    print(f"{prefix}: {line}", file=sys.stderr)
    return status
