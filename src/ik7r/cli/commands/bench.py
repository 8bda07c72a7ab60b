"""``ik7r bench``: the benchmark table (ours against the yardstick, the paper and other solvers)."""

from __future__ import annotations

import sys

from ..errors import CliError
from ._common import load_cli_robot


def add_parser(sub) -> None:
    p = sub.add_parser(
        "bench", help="benchmark the solvers (one table, every answer verified)",
        description="Time ik7r's solvers against a plain numpy forward kinematics of the same "
                    "poses (the yardstick), the paper's reported MATLAB times, our Newton-Raphson "
                    "and DLS, scipy least_squares and pinocchio (when installed), and print one "
                    "table with ratios and the machine it ran on. Every timed answer is checked "
                    "by forward kinematics.")
    p.add_argument("--quick", action="store_true", help="small sizes: a few seconds (CI)")
    p.add_argument("--n", type=int, default=None, metavar="N",
                   help="poses per batch and points of the trajectory (default 100000)")
    p.add_argument("--big", type=int, default=0, metavar="N",
                   help="also solve N random poses chunk by chunk (e.g. 10000000)")
    p.add_argument("--no-startup", action="store_true",
                   help="skip the fresh-process timings (numba import, ik7r ik end to end)")
    p.add_argument("--no-baselines", action="store_true",
                   help="skip the paper's iteration, Newton-Raphson, DLS, scipy and pinocchio")
    p.add_argument("--markdown", action="store_true", help="print a Markdown table")
    p.add_argument("--json", metavar="FILE", default=None, help="also write the results as JSON")
    p.set_defaults(run=run)


def run(args) -> int:
    import json

    from ...bench import run_benchmarks

    if args.n is not None and args.n < 1:
        raise CliError(f"--n must be a positive number of poses; got {args.n}")
    if args.big < 0:
        raise CliError(f"--big must be a non-negative number of poses; got {args.big}")
    robot = load_cli_robot(args)

    def log(line: str) -> None:
        print(f"bench: {line} ...", file=sys.stderr, flush=True)

    report = run_benchmarks(robot, quick=args.quick, n=args.n, big=args.big,
                            startup=not args.no_startup, baselines=not args.no_baselines, log=log)
    print(report.format_markdown() if args.markdown else report.format_table())
    if args.json:
        try:
            with open(args.json, "w") as f:
                json.dump(report.to_dict(), f, indent=2)
        except OSError as exc:
            raise CliError(f"cannot write {args.json}: {exc}") from exc
    return 0 if report.failures == 0 else 1
