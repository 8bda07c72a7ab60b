"""The benchmark's table: its rows, sizes and report, and how they are printed."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

__all__ = ["Row", "Sizes", "BenchReport", "format_table", "format_markdown"]


@dataclass(frozen=True)
class Row:
    """One line of the benchmark table.

    Attributes
    ----------
    name : str
        What was timed.
    kind : str
        ``"yardstick"``, ``"ours"``, ``"baseline"`` (other solvers), ``"reference"`` (times
        reported by the paper, not measured) or ``"startup"`` (fresh processes).
    n : int
        Poses, points or calls timed (0 for reference rows).
    seconds : float
        Time per pose, point or call (s): the best of the repeats.
    per : str
        What ``seconds`` is per: ``"pose"``, ``"point"``, ``"call"`` or ``"process"``.
    vs : str or None
        The yardstick of ``ratio``: ``"batch"`` (numpy FK per pose, vectorised) or
        ``"single"`` (numpy FK of one pose per call).
    ratio : float or None
        ``seconds`` over the yardstick's time.
    target : str
        The issue's target ('' when none).
    meets : bool or None
        Whether the target is met (None when there is no target).
    solved : int or None
        Poses (points) that got an answer.
    failures : int or None
        Answers failing the forward-kinematics check, plus known solutions a complete solver
        missed.
    note : str
    """

    name: str
    kind: str
    n: int
    seconds: float
    per: str
    vs: str | None = None
    ratio: float | None = None
    target: str = ""
    meets: bool | None = None
    solved: int | None = None
    failures: int | None = None
    note: str = ""


@dataclass(frozen=True)
class Sizes:
    """How many poses each part of the benchmark times."""

    batch: int = 100_000
    single: int = 2000
    trajectory: int = 200_000
    numeric: int = 200
    scipy: int = 100
    pinocchio: int = 200
    paper: int = 200
    repeats: int = 3

    @classmethod
    def quick(cls) -> Sizes:
        return cls(batch=2000, single=200, trajectory=5000, numeric=20, scipy=10, pinocchio=20,
                   paper=20, repeats=2)


@dataclass(frozen=True)
class BenchReport:
    """The result of :func:`run_benchmarks`: rows, the machine, the sizes."""

    rows: tuple[Row, ...]
    machine: dict
    robot: str
    sizes: Sizes
    seconds: float
    skipped: tuple[str, ...] = field(default_factory=tuple)

    def row(self, name: str) -> Row:
        """The row whose name starts with ``name``."""
        for r in self.rows:
            if r.name.startswith(name):
                return r
        raise KeyError(name)

    @property
    def failures(self) -> int:
        """Total verification failures over every row."""
        return sum(r.failures or 0 for r in self.rows)

    def to_dict(self) -> dict:
        return {"robot": self.robot, "machine": self.machine, "sizes": asdict(self.sizes),
                "seconds": self.seconds, "skipped": list(self.skipped),
                "failures": self.failures, "rows": [asdict(r) for r in self.rows]}

    def format_table(self) -> str:
        """The table as text (fixed-width, fit for a terminal or a Markdown code block)."""
        return format_table(self)

    def format_markdown(self) -> str:
        """The table as a Markdown table."""
        return format_markdown(self)


def _fmt_time(s: float) -> str:
    if s >= 1.0:
        return f"{s:.2f} s"
    if s >= 1e-3:
        return f"{s * 1e3:.3g} ms"
    return f"{s * 1e6:.3g} us"


def _cells(r: Row) -> list[str]:
    ratio = "" if r.ratio is None else f"{r.ratio:.3g}x {r.vs}"
    meets = "" if r.meets is None else ("yes" if r.meets else "NO")
    if r.solved is None or r.n == 0:
        solved = ""
    else:
        solved = f"{r.solved}/{r.n}" if r.kind != "startup" else ("ok" if r.solved else "failed")
    fails = "" if r.failures is None else str(r.failures)
    n = "" if r.n == 0 else f"{r.n:,}"
    return [r.name, n, f"{_fmt_time(r.seconds)}/{r.per}", ratio, r.target, meets, solved, fails]


_HEAD = ["method", "n", "time", "ratio", "target", "meets", "solved", "failures"]


def _machine_line(report: BenchReport) -> str:
    m = report.machine
    load = m.get("load_average")
    parts = [f"{m.get('cpu')}, {m.get('cores')} cores ({m.get('usable_cores')} usable)"]
    if load:
        parts.append(f"load average {load[0]} at start")
    parts.append(f"{m.get('platform')}")
    parts.append(f"Python {m.get('python')}, numpy {m.get('numpy')}, numba {m.get('numba')}, "
                 f"scipy {m.get('scipy')}, ik7r {m.get('ik7r')}, {m.get('threads')} solver threads")
    return "; ".join(parts)


def format_table(report: BenchReport) -> str:
    """Fixed-width text table of the report, with the machine it ran on."""
    body = [_cells(r) for r in report.rows]
    widths = [max(len(h), *(len(c[i]) for c in body)) for i, h in enumerate(_HEAD)]
    right = {1, 2, 3, 6, 7}

    def line(cells):
        return "  ".join(c.rjust(w) if i in right else c.ljust(w)
                         for i, (c, w) in enumerate(zip(cells, widths))).rstrip()

    out = [f"ik7r benchmark: robot {report.robot}, {report.sizes.batch:,} poses per batch, "
           f"best of {report.sizes.repeats}; {report.seconds:.0f} s in all",
           f"machine: {_machine_line(report)}", "", line(_HEAD), line(["-" * w for w in widths])]
    kind = None
    for r, cells in zip(report.rows, body):
        if kind is not None and r.kind != kind and r.kind in ("baseline", "reference", "startup"):
            out.append("")
        kind = r.kind
        out.append(line(cells))
    notes = [f"  {r.name}: {r.note}" for r in report.rows if r.note]
    out += ["", "ratio: time over the numpy FK yardstick measured in this run (batch: per pose, "
            "vectorised; single: one call for one pose).", "notes:", *notes]
    if report.skipped:
        out.append("skipped: " + "; ".join(report.skipped))
    out.append(f"verification failures in all: {report.failures}")
    return "\n".join(out)


def format_markdown(report: BenchReport) -> str:
    """Markdown table of the report, with the machine it ran on."""
    out = [f"Machine: {_machine_line(report)}.", "",
           "| " + " | ".join(_HEAD) + " |", "|" + "|".join("---" for _ in _HEAD) + "|"]
    for r in report.rows:
        out.append("| " + " | ".join(c.replace("|", "/") for c in _cells(r)) + " |")
    return "\n".join(out)
