"""Simulation 2 of the paper: accuracy and time over the usable workspace and at the two
singular configurations (Table 5, Figure 10), for the paper's iteration and the complete solver."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .published import PAPER_TABLE5, SINGULAR_Q_DEG
from .simulation1 import same_joints

__all__ = ["WorkspaceStudy", "Table5Row", "random_targets", "study", "table5_row", "simulation2"]


@dataclass(frozen=True)
class WorkspaceStudy:
    """Both solvers on a set of targets, one row per attempt.

    Attributes
    ----------
    label : str
        ``"Randomly selected"``, ``"Singular configuration 1"`` or ``"Singular configuration 2"``.
    q_target : ndarray (n, 6)
        Target joints (rad); the pose of each is their forward kinematics.
    config : ndarray (n,) int
        Configuration (1..8) of the target, the one both solvers are asked for.
    paper_ok : ndarray (n,) bool
        The paper's iteration returned an exact solution.
    paper_error : ndarray (n,)
        Position error (robot length unit) of the paper's solution, or of its last iterate when
        it failed.
    paper_time : ndarray (n,)
        Wall time of the paper's iteration (s), random theta5 start.
    paper_iterations : ndarray (n,) int
    paper_reason : tuple of str
        Why each failed attempt failed ('' when ok).
    paper_other : ndarray (n,) bool
        The paper's iteration converged to an exact solution that is not the target's joints
        (another fixed point with the same indicators).
    complete_ok : ndarray (n,) bool
        ``robot.ik(T, config)`` returned a solution.
    complete_error : ndarray (n,)
        Its position error (robot length unit); NaN when it raised.
    complete_time : ndarray (n,)
        Its wall time (s).
    found_target : ndarray (n,) bool
        The target's joints are among ``robot.ik_all(T)``'s solutions.
    n_solutions : ndarray (n,) int
        Number of distinct solutions of the pose.
    """

    label: str
    q_target: np.ndarray
    config: np.ndarray
    paper_ok: np.ndarray
    paper_error: np.ndarray
    paper_time: np.ndarray
    paper_iterations: np.ndarray
    paper_reason: tuple
    paper_other: np.ndarray
    complete_ok: np.ndarray
    complete_error: np.ndarray
    complete_time: np.ndarray
    found_target: np.ndarray
    n_solutions: np.ndarray


def random_targets(robot, rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` target joint vectors (n, 6) uniform within the joint limits (the paper's Table 4)."""
    return rng.uniform(robot.lower, robot.upper, (n, 6))


def study(robot, label: str, q_target, rng: np.random.Generator, progress=None) -> WorkspaceStudy:
    """Solve the pose of every target with the paper's iteration (random start, the target's
    configuration) and with the complete solver; ``progress.advance(1)`` after each target."""
    q_target = np.asarray(q_target, dtype=float)
    n = len(q_target)
    T_all = robot.fk(q_target)
    config = robot.config_of(q_target).astype(int)
    p_ok, p_err, p_time = np.zeros(n, bool), np.full(n, np.nan), np.zeros(n)
    p_it, p_other, reasons = np.zeros(n, int), np.zeros(n, bool), []
    c_ok, c_err, c_time = np.zeros(n, bool), np.full(n, np.nan), np.zeros(n)
    found, count = np.zeros(n, bool), np.zeros(n, int)
    from ..errors import UnreachableError

    robot.ik_paper(T_all[0], int(config[0]), theta5_start=0.5)  # load the kernels before timing
    robot.ik(T_all[0], int(config[0]))
    for i in range(n):
        T, c = T_all[i], int(config[i])
        t0 = time.perf_counter()
        r = robot.ik_paper(T, c, rng=rng)
        p_time[i] = time.perf_counter() - t0
        q = r.q if r.ok else r.q_last
        p_ok[i], p_it[i] = r.ok, r.iterations
        p_err[i] = np.linalg.norm(robot.fk(q)[:3, 3] - T[:3, 3])
        reasons.append(r.reason)
        t0 = time.perf_counter()
        try:
            qc = robot.ik(T, c)
        except UnreachableError:
            qc = None
        c_time[i] = time.perf_counter() - t0
        if qc is not None:
            c_ok[i] = True
            c_err[i] = np.linalg.norm(robot.fk(qc)[:3, 3] - T[:3, 3])
        every = robot.ik_all(T, seed=q_target[i])
        count[i] = len(every)
        found[i] = bool(len(every) and (same_joints(every, q_target[i], 1e-6).any()
                                        or _same_at_straight_wrist(every, q_target[i])))
        if r.ok:
            p_other[i] = not (same_joints(r.q, q_target[i], 1e-6)
                              or _same_at_straight_wrist(r.q[None], q_target[i]))
        if progress is not None:
            progress.advance(1)
    return WorkspaceStudy(label, q_target, config, p_ok, p_err, p_time, p_it, tuple(reasons), p_other,
                          c_ok, c_err, c_time, found, count)


def _same_at_straight_wrist(sols, q, tol=1e-6) -> bool:
    """At theta5 = 0 only q4 + q7 is defined: compare q1..q3, q5 and q4 + q7."""
    if abs(math.remainder(q[4], 2 * math.pi)) > tol:
        return False
    a = np.column_stack([sols[:, :3], sols[:, 4], sols[:, 3] + sols[:, 5]])
    b = np.array([q[0], q[1], q[2], q[4], q[3] + q[5]])
    return bool(same_joints(a, b, tol).any())


@dataclass(frozen=True)
class Table5Row:
    """One row of Table 5 (errors in the robot's length unit, times in s).

    The averages and maxima of the errors are over the attempts that returned a solution; the
    failures are counted apart. Times are averaged over every attempt.
    """

    label: str
    attempts: int
    paper_solved: int
    paper_other_solution: int
    paper_average_error: float
    paper_maximum_error: float
    paper_average_time: float
    paper_maximum_time: float
    complete_solved: int
    complete_average_error: float
    complete_maximum_error: float
    complete_average_time: float
    complete_maximum_time: float
    found_target: int
    published: tuple


def _stats(x):
    return (float(np.mean(x)), float(np.max(x))) if len(x) else (math.nan, math.nan)


def table5_row(s: WorkspaceStudy) -> Table5Row:
    """Summarise a study as a row of Table 5 (beside the paper's published numbers)."""
    pa, pm = _stats(s.paper_error[s.paper_ok])
    ca, cm = _stats(s.complete_error[s.complete_ok])
    return Table5Row(
        s.label, len(s.config), int(s.paper_ok.sum()), int(s.paper_other.sum()), pa, pm,
        float(s.paper_time.mean()), float(s.paper_time.max()), int(s.complete_ok.sum()), ca, cm,
        float(s.complete_time.mean()), float(s.complete_time.max()), int(s.found_target.sum()),
        PAPER_TABLE5.get(s.label, (math.nan, math.nan, math.nan)),
    )


def simulation2(robot, rng: np.random.Generator, *, targets: int = 500, singular_repeats: int = 50,
                progress=None) -> list[WorkspaceStudy]:
    """The three studies of Table 5: ``targets`` random targets in the usable workspace, then
    each singular configuration solved ``singular_repeats`` times (random theta5 starts)."""
    out = [study(robot, "Randomly selected", random_targets(robot, rng, targets), rng, progress)]
    for k, q in enumerate(SINGULAR_Q_DEG, start=1):
        reps = np.repeat(np.radians(q)[None], singular_repeats, axis=0)
        out.append(study(robot, f"Singular configuration {k}", reps, rng, progress))
    return out
