"""``ik7r reproduce``: recompute the paper's tables and figures and write a report."""

from __future__ import annotations

from ..errors import CliError
from ._common import count


def add_parser(sub) -> None:
    p = sub.add_parser(
        "reproduce", help="reproduce the paper's Tables 2, 3, 5 and Figures 6-10, 12 into a directory",
        description="Recompute the paper's simulations on its robot and write table2.csv, table3.csv, "
                    "table5.csv, figure6..10.png, figure12.png and report.md (each table beside the "
                    "paper's numbers, and what differs and why).")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument("--quick", action="store_true",
                   help="reduced sizes (60 random targets, 1 deg grid...): a few seconds")
    p.add_argument("--seed", type=count, default=None, help="seed of the random draws (default 2016)")
    p.set_defaults(run=run)


#: Files ``ik7r reproduce`` writes (a new run removes those it does not write again);
#: ``report.md`` is the manifest, published last.
REPRODUCE_FILES = ("table2.csv", "table3.csv", "table5.csv", "figure6.png", "figure7.png",
                   "figure8.png", "figure9.png", "figure10.png", "figure12.png", "report.md")


def reproduce_into(out, plan, label: str):
    """Run the reproduction with ``plan`` into the directory ``out`` through the output stager
    (files published when all are complete, ``report.md`` last; nothing left on failure).
    Returns the :class:`~ik7r.reproduce.Reproduction` with the final paths."""
    from dataclasses import replace
    from pathlib import Path

    from ...outputs import OutputDir
    from ...progress import Progress
    from ...reproduce import plan_units, reproduce

    out = Path(out)
    if out.exists() and not out.is_dir():
        raise CliError(f"--out must be a directory; {out} is a file")
    with OutputDir(out, manifest="report.md", owned=REPRODUCE_FILES) as stage, \
            Progress(plan_units(plan), label) as bar:
        result = reproduce(stage.path, plan=plan, progress=bar)
    files = {k: out / Path(v).name for k, v in result.files.items()}
    return replace(result, out=out, files=files)


def run(args) -> int:
    from dataclasses import replace

    from ...reproduce import FULL, QUICK

    if args.robot not in (None, "paper"):
        raise CliError("reproduce uses the paper's robot (its Table 1); --robot is not supported here")
    plan = QUICK if args.quick else FULL
    if args.seed is not None:
        plan = replace(plan, seed=args.seed)
    out = args.out
    result = reproduce_into(out, plan, "reproducing the paper")
    print(f"Wrote {len(result.files)} files to {out}/ in {result.elapsed:.1f} s:")
    for path in result.files.values():
        print(f"  {path}")
    if result.painting_note and "figure12" not in result.files:
        print(f"note: {result.painting_note}")
    print(f"Read {result.out / 'report.md'} first.")
    return 0
