"""``ik7r reproduce``: recompute the paper's tables and figures and write a report."""

from __future__ import annotations

from ..errors import CliError


def add_parser(sub) -> None:
    p = sub.add_parser(
        "reproduce", help="reproduce the paper's Tables 2, 3, 5 and Figures 6-10, 12 into a directory",
        description="Recompute the paper's simulations on its robot and write table2.csv, table3.csv, "
                    "table5.csv, figure6..10.png, figure12.png and report.md (each table beside the "
                    "paper's numbers, and what differs and why).")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument("--quick", action="store_true",
                   help="reduced sizes (60 random targets, 1 deg grid...): a few seconds")
    p.add_argument("--seed", type=int, default=None, help="seed of the random draws (default 2016)")
    p.set_defaults(run=run)


def run(args) -> int:
    from dataclasses import replace
    from pathlib import Path

    from ...progress import Progress
    from ...reproduce import FULL, QUICK, plan_units, reproduce

    if args.robot not in (None, "paper"):
        raise CliError("reproduce uses the paper's robot (its Table 1); --robot is not supported here")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise CliError(f"--out must be a directory; {out} is a file")
    plan = QUICK if args.quick else FULL
    if args.seed is not None:
        plan = replace(plan, seed=args.seed)
    with Progress(plan_units(plan), "reproducing the paper") as bar:
        result = reproduce(out, plan=plan, progress=bar)
    print(f"Wrote {len(result.files)} files to {out}/ in {result.elapsed:.1f} s:")
    for path in result.files.values():
        print(f"  {path}")
    if result.painting_note and "figure12" not in result.files:
        print(f"note: {result.painting_note}")
    print(f"Read {out / 'report.md'} first.")
    return 0
