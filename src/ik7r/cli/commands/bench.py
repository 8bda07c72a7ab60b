"""``ik7r bench``: the benchmark table (ours against the yardstick, the paper and other solvers)."""

from __future__ import annotations

import os
import sys

from ...limits import MAX_BENCH_POSES, MAX_POSES
from ..errors import CliError
from ._common import count, load_cli_robot


def add_parser(sub) -> None:
    p = sub.add_parser(
        "bench", help="benchmark the solvers (one table, every answer verified)",
        description="Time ik7r's solvers against a plain numpy forward kinematics of the same "
                    "poses (the yardstick), the paper's reported MATLAB times, our Newton-Raphson "
                    "and DLS, scipy least_squares and pinocchio (when installed), and print one "
                    "table with ratios and the machine it ran on. Every timed answer is checked "
                    "by forward kinematics.")
    p.add_argument("--quick", action="store_true", help="small sizes: a few seconds (CI)")
    p.add_argument("--n", type=count, default=None, metavar="N",
                   help="poses per batch and points of the trajectory (default 100000)")
    p.add_argument("--big", type=count, default=0, metavar="N",
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
    if args.n is not None and args.n > MAX_BENCH_POSES:
        raise CliError(f"--n {args.n} exceeds the limit of {MAX_BENCH_POSES:,} poses (memory); "
                       "use --big for more poses solved chunk by chunk")
    if args.big > MAX_POSES:
        raise CliError(f"--big {args.big} exceeds the limit of {MAX_POSES:,} poses")
    if args.json:  # fail before the benchmark, not after it
        from pathlib import Path

        from ...outputs import OutputError

        parent = Path(args.json).parent
        if Path(args.json).is_dir() or not parent.is_dir() or not os.access(parent, os.W_OK):
            raise OutputError(13, f"cannot write {args.json}: not a writable place for a file")
    robot = load_cli_robot(args)

    def log(line: str) -> None:
        print(f"bench: {line} ...", file=sys.stderr, flush=True)

    report = run_benchmarks(robot, quick=args.quick, n=args.n, big=args.big,
                            startup=not args.no_startup, baselines=not args.no_baselines, log=log)
    print(report.format_markdown() if args.markdown else report.format_table())
    if args.json:
        from ...outputs import write_text_atomic

        write_text_atomic(args.json, json.dumps(report.to_dict(), indent=2))
    return 0 if report.failures == 0 else 1
