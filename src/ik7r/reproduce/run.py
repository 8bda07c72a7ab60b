"""The whole reproduction: compute every table and figure, write them and ``report.md``."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .._typing import PathLike
    from ..progress import Progress
    from ..robot.model import Robot

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import plots
from .published import PAPER_TABLE5, PAPER_TRAJECTORY_TIME_S
from .report import write_report, write_table2, write_table3, write_table5
from .simulation1 import convergence_runs, table2, table3
from .workspace import simulation2, table5_row
from .wrist import error_curves, wrist_solution_counts

__all__ = ["Plan", "FULL", "QUICK", "Reproduction", "reproduce", "plan_units"]


@dataclass(frozen=True)
class Plan:
    """Sizes of a reproduction run.

    Attributes
    ----------
    targets : int
        Random targets of Table 5 / Figure 10 (the paper: 500).
    singular_repeats : int
        Random-start solves of each singular configuration.
    table3_starts : int
        Random starts timed for the paper's method in Table 3.
    table3_repeats : int
        Repeats timed for each deterministic row of Table 3.
    convergence_starts : int
        Random starts drawn in Figure 8.
    figure6_step_deg : float
        theta5 grid step of Figure 6 (the paper: 0.1 deg).
    figure7_draws : int
        Random targets per theta5 value in Figure 7.
    painting_duration : float
        Duration of the painting trajectory of Figure 12 (s; the paper: 20).
    seed : int
        Seed of every random draw.
    quick : bool
        Marks a reduced run in the report.
    """

    targets: int = 500
    singular_repeats: int = 50
    table3_starts: int = 200
    table3_repeats: int = 50
    convergence_starts: int = 10
    figure6_step_deg: float = 0.1
    figure7_draws: int = 10
    painting_duration: float = 20.0
    seed: int = 2016
    quick: bool = False


#: The paper's sizes.
FULL = Plan()
#: A reduced run for tests and ``ik7r demo`` (a few seconds once the kernels are compiled).
QUICK = Plan(targets=60, singular_repeats=10, table3_starts=20, table3_repeats=10, convergence_starts=6,
             figure6_step_deg=1.0, figure7_draws=2, quick=True)


@dataclass(frozen=True)
class Reproduction:
    """What a reproduction wrote and computed.

    Attributes
    ----------
    out : Path
        The output directory.
    files : dict
        Output name (``"table2"``, ``"figure6"``, ``"report"``...) -> path written.
    table2, table3, table5 : lists of rows
    studies : list of WorkspaceStudy
    painting_note : str
        Figure 12's status ('' when written normally).
    elapsed : float
        Wall time (s).
    """

    out: Path
    files: dict
    table2: list
    table3: list
    table5: list
    studies: list = field(repr=False)
    painting_note: str = ""
    elapsed: float = 0.0


# rough share of the run's time of each stage (progress bar units)
_WEIGHTS = {"table2": 2, "table3": 3, "figure8": 1, "figure6": 20, "figure7": 2, "table5": 25,
            "plots": 12, "figure12": 10, "report": 1}


def plan_units(plan: Plan) -> int:
    """Total progress units of a run (for :class:`ik7r.progress.Progress`)."""
    return sum(_WEIGHTS.values()) * 10


class _Part:
    """Advance a parent progress by ``weight * 10`` units over ``n`` sub-steps."""

    def __init__(self, parent, key: str, n: int):
        self.parent, self.units, self.n, self.done, self.sent = parent, _WEIGHTS[key] * 10, max(n, 1), 0, 0

    def advance(self, k: int = 1) -> None:
        self.done = min(self.n, self.done + k)
        target = self.units * self.done // self.n
        if self.parent is not None and target > self.sent:
            self.parent.advance(target - self.sent)
        self.sent = max(self.sent, target)

    def finish(self) -> None:
        self.advance(self.n)


def reproduce(out_dir: PathLike, *, plan: Plan = FULL, robot: Robot | None = None,
              progress: Progress | None = None) -> Reproduction:
    """Recompute the paper's Tables 2, 3, 5 and Figures 6-10 and 12, write them to ``out_dir``.

    Parameters
    ----------
    out_dir : str or Path
        Created if missing; existing files of the same names are overwritten.
    plan : Plan
        :data:`FULL` (the paper's sizes) or :data:`QUICK`.
    robot : Robot, optional
        Default: the paper's robot (the comparisons with the paper only make sense for it).
    progress : object with ``advance(n)``, optional
        Advanced by :func:`plan_units` units in total (an :class:`ik7r.progress.Progress`).

    Returns
    -------
    Reproduction
    """
    start = time.perf_counter()
    if robot is None:
        from ..robot.files import load_robot

        robot = load_robot()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(plan.seed)
    unit = robot.unit
    files: dict = {}

    part = _Part(progress, "table2", 1)
    t2 = table2(robot, rng)
    files["table2"] = write_table2(t2, out / "table2.csv", unit)
    part.finish()

    part = _Part(progress, "table3", 1)
    t3 = table3(robot, rng, starts=plan.table3_starts, repeats=plan.table3_repeats)
    files["table3"] = write_table3(t3, out / "table3.csv")
    part.finish()

    part = _Part(progress, "figure8", 1)
    runs = convergence_runs(robot, rng, starts=plan.convergence_starts)
    part.finish()

    n6 = 4 * (int(round(360.0 / plan.figure6_step_deg)) + 1)
    part = _Part(progress, "figure6", n6)
    curves = error_curves(robot, plan.figure6_step_deg, progress=part)
    part.finish()

    part = _Part(progress, "figure7", 1)
    counts = wrist_solution_counts(robot, rng, draws=plan.figure7_draws)
    part.finish()

    part = _Part(progress, "table5", plan.targets + 2 * plan.singular_repeats)
    studies = simulation2(robot, rng, targets=plan.targets, singular_repeats=plan.singular_repeats,
                          progress=part)
    t5 = [table5_row(s) for s in studies]
    files["table5"] = write_table5(t5, out / "table5.csv", unit)
    part.finish()

    part = _Part(progress, "plots", 5)
    files["figure6"] = plots.figure6(curves, out / "figure6.png", unit)
    part.advance()
    files["figure7"] = plots.figure7(counts, out / "figure7.png")
    part.advance()
    files["figure8"] = plots.figure8(runs, out / "figure8.png", unit)
    part.advance()
    titles = [f"{'config' if r.paper_deg is not None else 'further, config'} {r.config}: "
              f"q5 = {np.degrees(r.q[4]):.2f}" for r in t2]
    files["figure9"] = plots.figure9(robot.frames(np.array([r.q for r in t2])), titles, out / "figure9.png")
    part.advance()
    files["figure10"] = plots.figure10(studies, out / "figure10.png", unit,
                                       published=PAPER_TABLE5["Randomly selected"][:2])
    part.finish()

    part = _Part(progress, "figure12", 1)
    path12, note = _figure12(robot, out / "figure12.png", plan.painting_duration)
    if path12 is not None:
        files["figure12"] = path12
    part.finish()

    part = _Part(progress, "report", 1)
    figures = {k: Path(v).name for k, v in files.items() if k.startswith("figure")}
    elapsed = time.perf_counter() - start
    files["report"] = write_report(
        out / "report.md", plan=plan, table2_rows=t2, table3_rows=t3, table5_rows=t5, studies=studies,
        curves=curves, counts=counts, runs=runs, figures=figures, painting_note=note, elapsed=elapsed,
        unit=unit)
    part.finish()
    return Reproduction(out, files, t2, t3, t5, studies, note, time.perf_counter() - start)


def _figure12(robot, path, duration):
    """Figure 12 from :mod:`ik7r.painting` (Simulation 3); (None, why) when it cannot be drawn."""
    try:
        from ..painting import paint_raster, plot_joint_trajectory
    except ImportError as exc:
        return None, f"Figure 12 needs `ik7r.painting`, which is not available ({exc})."
    t0 = time.perf_counter()
    result = paint_raster(robot, duration=duration, config=1)
    total_s = time.perf_counter() - t0
    plot_joint_trajectory(result.trajectory, path, robot=robot)
    note = (f"The {duration:g} s painting trajectory (the paper's raster, configuration 1) was planned, "
            f"solved and interpolated in {total_s:.2f} s on this machine.")
    try:  # beyond the contract: time the inverse kinematics per path sample (the paper: 9 ms)
        from ..painting import solve_path

        n = len(result.path)
        t0 = time.perf_counter()
        solve_path(robot, result.path, config=1)
        per_ms = 1e3 * (time.perf_counter() - t0) / n
        note += (f" Solving its {n} path samples alone takes {per_ms:.3f} ms per sample, against "
                 f"{PAPER_TRAJECTORY_TIME_S * 1e3:g} ms per point in the paper's Simulation 3 (MATLAB), "
                 f"{PAPER_TRAJECTORY_TIME_S * 1e3 / per_ms:,.0f}x.")
        events = list(result.events)
        note += (" The painting module reports no event (no unreachable sample, limit or singularity)."
                 if not events else f" The painting module reports {len(events)} event(s): see its report.")
    except (ImportError, AttributeError, TypeError, ValueError, ZeroDivisionError) as exc:
        note += f" (The time per path sample could not be measured: {exc}.)"
    return Path(path), note
