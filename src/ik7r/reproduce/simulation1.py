"""Simulation 1 of the paper: Table 2 (eight solutions), Table 3 (times) and Figure 8 (convergence).

Pure computations: each function takes the robot and a seeded generator and returns frozen
dataclasses; plotting and writing live in :mod:`ik7r.reproduce.plots` and
:mod:`ik7r.reproduce.report`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..geometry.rotations import wrap_angle
from ..ik.numeric import damped_least_squares, newton_raphson
from .published import PAPER_TABLE2, PAPER_TABLE3, SIMULATION1_Q_DEG, TABLE3_STARTS_DEG

__all__ = [
    "Table2Row",
    "Table3Row",
    "ConvergenceRun",
    "simulation1_pose",
    "table2",
    "table3",
    "convergence_runs",
    "same_joints",
]

#: Two joint vectors closer than this (rad, every joint, modulo 2 pi) are the same solution.
SAME_SOLUTION_TOL = 1e-7


def simulation1_pose(robot) -> np.ndarray:
    """Simulation 1's ``T_end`` (4, 4): forward kinematics of [60, 60, 0, -30, 60, 30] deg."""
    return robot.fk(np.radians(SIMULATION1_Q_DEG))


def same_joints(a, b, tol: float = SAME_SOLUTION_TOL) -> np.ndarray:
    """Whether joint vectors ``a`` (..., 6) and ``b`` (..., 6) (rad) agree modulo 2 pi within ``tol``."""
    d = wrap_angle(np.asarray(a, dtype=float) - np.asarray(b, dtype=float))
    return np.abs(d).max(axis=-1) <= tol


def _fk_errors(robot, q, T):
    Tq = robot.fk(q)
    dp = np.linalg.norm(Tq[..., :3, 3] - T[:3, 3], axis=-1)
    dr = np.abs(Tq[..., :3, :3] - T[:3, :3]).max(axis=(-1, -2))
    return dp, dr


@dataclass(frozen=True)
class Table2Row:
    """One solution of Simulation 1's pose.

    Attributes
    ----------
    config : int
        Configuration number 1..8 (Appendix 3) of ``q``.
    q : ndarray (6,)
        Joints ``[q1, q2, q3, q4, q5, q7]`` (rad, wrapped to (-pi, pi]).
    source : str
        ``"paper's iteration"``, ``"complete solver (paper's iteration failed)"`` or
        ``"complete solver only (beyond the paper's eight)"``.
    paper_deg : ndarray (6,) or None
        The paper's Table 2 row of that configuration (deg), None for a further solution.
    deviation_deg : float
        Largest joint difference from ``paper_deg`` modulo 360 (deg); NaN without a paper row.
    position_error : float
        Forward-kinematics position error of ``q`` (robot length unit).
    rotation_error : float
        Largest rotation-matrix entry error of ``q``.
    in_complete_set : bool
        ``q`` is among the complete solver's solutions (``robot.ik_all``).
    iterations : int
        Iterations of the paper's method (0 when it did not produce the row).
    """

    config: int
    q: np.ndarray
    source: str
    paper_deg: np.ndarray | None
    deviation_deg: float
    position_error: float
    rotation_error: float
    in_complete_set: bool
    iterations: int


def table2(robot, rng: np.random.Generator) -> list[Table2Row]:
    """Simulation 1's solutions: the paper's iteration in each of the eight configurations
    (random start, as in the paper), then every further solution of the complete solver.

    Returns the eight configuration rows first (configurations 1..8), then the further
    solutions (if any) sorted by configuration.
    """
    T = simulation1_pose(robot)
    every = robot.ik_all(T)
    rows: list[Table2Row] = []
    for c in range(1, 9):
        res = robot.ik_paper(T, c, rng=rng)
        if res.ok:
            q, source, its = res.q, "paper's iteration", res.iterations
        else:  # never for the paper's pose; kept honest for other robots / poses
            q, source, its = robot.ik(T, c), f"complete solver (paper's iteration failed: {res.reason})", 0
        paper = PAPER_TABLE2[c - 1]
        dev = float(np.degrees(np.abs(wrap_angle(q - np.radians(paper)))).max())
        dp, dr = _fk_errors(robot, q, T)
        found = bool(len(every) and same_joints(every, q).any())
        rows.append(Table2Row(int(robot.config_of(q)), q, source, paper, dev, float(dp), float(dr),
                              found, its))
    for q in every:
        if any(same_joints(r.q, q) for r in rows):
            continue
        dp, dr = _fk_errors(robot, q, T)
        rows.append(Table2Row(int(robot.config_of(q)), q, "complete solver only (beyond the paper's eight)",
                              None, math.nan, float(dp), float(dr), True, 0))
    return rows


@dataclass(frozen=True)
class Table3Row:
    """One line of Table 3: a method, its start, its time on this machine and the paper's.

    Attributes
    ----------
    method : str
    start_deg : tuple of 6 float or str
        Initial joints (deg), or a description (``"random theta5"``, ``"none"``).
    time_ms : float
        Mean wall time per solve (ms) on this machine.
    iterations : float
        Iterations (mean over the repeats); NaN for the complete solver (not iterative).
    converged : bool
        Every repeat gave an exact solution.
    successes, repeats : int
        How many repeats gave an exact solution, out of how many.
    reason : str
        Why it failed ('' when it converged).
    solution_config : int
        Configuration number of the solution found (0 when none).
    paper_time_ms : float or None
        The paper's time (ms); None when the paper has no such row or printed "Failure".
    in_paper : bool
        The row is one of the paper's (False for rows we add for comparison).
    """

    method: str
    start_deg: tuple | str
    time_ms: float
    iterations: float
    converged: bool
    successes: int
    repeats: int
    reason: str
    solution_config: int
    paper_time_ms: float | None
    in_paper: bool


def _timed(fn, repeats):
    fn()  # warm: the compiled kernels load on first use
    out, times = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = fn()
        times.append(time.perf_counter() - t0)
        out.append(r)
    return out, 1e3 * float(np.mean(times))


def table3(robot, rng: np.random.Generator, *, starts: int = 200, repeats: int = 50) -> list[Table3Row]:
    """Table 3 on this machine: the paper's method from ``starts`` random theta5 starts,
    Newton-Raphson (eq. 9) from the paper's three initial values (each timed over ``repeats``),
    then two rows the paper does not have: damped least squares from the singular start, and
    the complete solver."""
    T = simulation1_pose(robot)
    rows = []
    results, ms = _timed(lambda: robot.ik_paper(T, 1, rng=rng), starts)
    ok = [r for r in results if r.ok]
    configs = {int(robot.config_of(r.q)) for r in ok}
    rows.append(Table3Row(
        "the paper's method (config 1)", "random theta5", ms, float(np.mean([r.iterations for r in results])),
        len(ok) == len(results), len(ok), len(results),
        "" if len(ok) == len(results) else next(r.reason for r in results if not r.ok),
        configs.pop() if len(configs) == 1 else 0, PAPER_TABLE3["paper"], True))
    for start in TABLE3_STARTS_DEG:
        q0 = np.radians(start)
        results, ms = _timed(lambda q0=q0: newton_raphson(robot, T, q0), repeats)
        rows.append(_numeric_row("Newton-Raphson, eq. (9)", start, ms, results, robot,
                                 PAPER_TABLE3[start], True))
    start = TABLE3_STARTS_DEG[2]
    results, ms = _timed(lambda: damped_least_squares(robot, T, np.radians(start)), repeats)
    rows.append(_numeric_row("damped least squares (not in the paper)", start, ms, results, robot,
                             None, False))
    results, ms = _timed(lambda: robot.ik(T, 1), repeats)
    rows.append(Table3Row("complete solver robot.ik (not in the paper)", "none (no start value)", ms,
                          math.nan, True, repeats, repeats, "", int(robot.config_of(results[0])), None,
                          False))
    return rows


def _numeric_row(method, start, ms, results, robot, paper_ms, in_paper):
    r = results[0]  # deterministic: every repeat is the same
    return Table3Row(method, tuple(start), ms, float(r.iterations), bool(r.ok), sum(x.ok for x in results),
                     len(results), r.reason, int(robot.config_of(r.q)) if r.ok else 0, paper_ms, in_paper)


@dataclass(frozen=True)
class ConvergenceRun:
    """One run of the paper's iteration (Figure 8).

    Attributes
    ----------
    theta5_start : float
        Initial theta5 (rad).
    position_error : ndarray (k,)
        Position error after each iteration (robot length unit).
    elapsed : ndarray (k,)
        Seconds since the start after each iteration.
    ok : bool
    """

    theta5_start: float
    position_error: np.ndarray
    elapsed: np.ndarray
    ok: bool


def convergence_runs(robot, rng: np.random.Generator, *, starts: int = 10,
                     config: int = 1) -> list[ConvergenceRun]:
    """Figure 8's data: the paper's iteration on Simulation 1's pose from ``starts`` random theta5
    starts spread over the Wrist indicator's half (one per equal slice, jittered)."""
    T = simulation1_pose(robot)
    robot.ik_paper(T, config, theta5_start=0.5)  # warm
    sign = 1.0 if config % 2 == 1 else -1.0
    edges = np.linspace(0.0, math.pi, starts + 1)
    runs = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        t5 = sign * rng.uniform(lo, hi)
        r = robot.ik_paper(T, config, theta5_start=t5)
        runs.append(ConvergenceRun(float(t5), r.position_error, r.elapsed, r.ok))
    return runs
