"""Benchmarks: ik7r's solvers against a numpy forward-kinematics yardstick, the paper's
reported times and generic IK solvers, in one run, every timed answer verified.

>>> from ik7r.benchmark import run_benchmarks
>>> report = run_benchmarks(quick=True)          # doctest: +SKIP
>>> print(report.format_table())                 # doctest: +SKIP

The command line: ``ik7r bench [--quick] [--n N] [--json FILE]``; ``make bench`` runs
``benchmarks/run.py``, which is the same.

How to read the table
---------------------
Absolute times depend on the machine, so every time is also given as a *ratio* to a
yardstick timed in the same run: the plain vectorised numpy forward kinematics of the same
poses (the product of the seven eq. (1) matrices), per pose for batches ("batch"), and one
call for one pose for single calls ("single"). The issue's targets are ratios (except the
trajectory throughput and the start-up time, which are absolute). ``failures`` counts timed
answers that fail the forward-kinematics check, plus, for the complete solvers, poses whose
known solution (the joints the pose was made from) was not found; it must be 0. ``solved``
is the share of poses that got an answer (the numeric baselines can fail to converge).
"""

from __future__ import annotations

import json
import math
import os
import platform
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

__all__ = [
    "Row",
    "BenchReport",
    "Sizes",
    "run_benchmarks",
    "numpy_fk",
    "machine_info",
    "PAPER_MS_PER_POSE",
    "PAPER_MS_PER_POINT",
]

#: The paper's reported MATLAB times: one pose, one point of a trajectory (ms).
PAPER_MS_PER_POSE = 65.0
PAPER_MS_PER_POINT = 9.0

#: Targets of the issue (ratios to the yardstick, or absolute).
TARGET_IK_BATCH = 0.5
TARGET_IK_ALL_BATCH = 5.0
TARGET_IK_SINGLE = 0.25
TARGET_IK_ALL_SINGLE = 1.25
TARGET_POINTS_PER_SECOND = 500_000.0
TARGET_CLI_SECONDS = 0.5

SEED = 2024


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


# ---------------------------------------------------------------------- helpers
def numpy_fk(robot, q) -> np.ndarray:
    """The yardstick: plain vectorised numpy forward kinematics, the product of the seven
    eq. (1) matrices (with the robot's base and tool when they are not the identity).

    ``q`` (..., 6) rad -> (..., 4, 4).
    """
    from .geometry.rotations import dh_transform

    q = np.asarray(q, dtype=float)
    dh = robot.dh
    sign = robot.joint_sign
    c0, c1 = robot.coupling
    q7 = np.concatenate([q[..., :5], c0 * q[..., 4:5] + c1, q[..., 5:6]], axis=-1)
    M = dh_transform(dh[:, 0], dh[:, 1], sign * q7 + dh[:, 3], dh[:, 2])
    T = M[..., 0, :, :]
    for i in range(1, 7):
        T = T @ M[..., i, :, :]
    if not np.array_equal(robot.base, np.eye(4)):
        T = robot.base @ T
    if not np.array_equal(robot.tool, np.eye(4)):
        T = T @ robot.tool
    return T


def _fk_ok(robot, q: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Whether joints ``q`` (M, 6) reach poses ``T`` (M, 4, 4) within the robot's tolerances
    (the residual of the kernels: position distance, ``sqrt(|R - Rd|_F^2 / 2)``)."""
    if len(q) == 0:
        return np.zeros(0, dtype=bool)
    Tq = robot.fk(q)
    dp = np.linalg.norm(Tq[:, :3, 3] - T[:, :3, 3], axis=1)
    dr = np.sqrt(0.5 * ((Tq[:, :3, :3] - T[:, :3, :3]) ** 2).sum(axis=(1, 2)))
    return (dp <= robot.position_tolerance) & (dr <= robot.rotation_tolerance)


def _wrapped(x):
    return np.abs(np.mod(x + np.pi, 2 * np.pi) - np.pi)


def _same_solution(sols: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Which rows of ``sols`` (..., 6) equal ``q`` (..., 6) modulo 2 pi (1e-6 rad); at a
    straight wrist (q5 = 0) only q4 + q7 is defined."""
    d = _wrapped(sols - q)
    same = d.max(axis=-1) < 1e-6
    straight = _wrapped(q[..., 4]) < 1e-6
    if np.any(straight):
        sum_ok = _wrapped((sols[..., 3] + sols[..., 5]) - (q[..., 3] + q[..., 5])) < 1e-6
        alt = (np.maximum(d[..., :3].max(axis=-1), d[..., 4]) < 1e-6) & sum_ok
        same = np.where(straight, same | alt, same)
    return same


def _best(fn: Callable[[], object], repeats: int) -> float:
    best = math.inf
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def _random_joints(rng, n: int) -> np.ndarray:
    return rng.uniform(-np.pi, np.pi, (n, 6))


def _path_joints(rng, n: int) -> np.ndarray:
    """A smooth joint path of ``n`` points, one configuration, about 1e-3 rad per step
    (about 1 mm at 1 m of reach: a finely sampled painting path)."""
    q0 = np.array([0.3, 0.5, 0.2, 0.4, 1.0, -0.3])
    amp = rng.uniform(0.2, 0.4, 6)
    freq = rng.uniform(0.5, 1.5, 6)
    phase = rng.uniform(0, 2 * np.pi, 6)
    speed = float(np.max(amp * freq))  # rad per unit of s
    s = np.arange(n)[:, None] * (1e-3 / speed)
    return q0 + amp * np.sin(freq * s + phase)


def machine_info() -> dict:
    """CPU model, cores, load, OS and the versions of Python and the libraries."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:  # pragma: no cover - not Linux
        pass
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover
        usable = os.cpu_count() or 1
    info = {"cpu": cpu, "cores": os.cpu_count(), "usable_cores": usable,
            "platform": platform.platform(), "python": platform.python_version()}
    try:
        info["load_average"] = [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover
        pass
    import numpy
    import scipy

    info["numpy"] = numpy.__version__
    info["scipy"] = scipy.__version__
    try:
        import numba

        info["numba"] = numba.__version__
    except ImportError:  # pragma: no cover
        info["numba"] = None
    from . import __version__
    from .ik.solve import num_threads

    info["ik7r"] = __version__
    info["threads"] = num_threads()
    return info


# ---------------------------------------------------------------------- the run
def run_benchmarks(robot=None, *, quick: bool = False, n: int | None = None, sizes: Sizes | None = None,
                   startup: bool = True, baselines: bool = True, pinocchio: bool = True,
                   big: int = 0, log: Callable[[str], None] | None = None) -> BenchReport:
    """Run every benchmark once and return the table.

    Parameters
    ----------
    robot : Robot, optional
        Default: the paper's robot.
    quick : bool
        Small sizes (a few seconds; for tests and CI).
    n : int, optional
        Poses of the batch rows and points of the trajectory (overrides the sizes).
    sizes : Sizes, optional
        Every size explicitly.
    startup : bool
        Time fresh processes (numba import and cache load, ``ik7r ik`` end to end).
    baselines : bool
        Time the paper's iteration, Newton-Raphson, DLS, scipy and pinocchio.
    pinocchio : bool
        Include pinocchio when ``import pinocchio`` works.
    big : int
        Also solve this many random poses with :func:`ik7r.ik.chunked.solve_all_chunked`.
    log : callable, optional
        Called with a line of text as each part starts (progress on stderr).
    """
    from . import load_robot

    robot = load_robot() if robot is None else robot
    sizes = sizes or (Sizes.quick() if quick else Sizes())
    if n is not None:
        if n < 1:
            raise ValueError(f"n must be a positive number of poses; got {n}")
        sizes = Sizes(**{**asdict(sizes), "batch": int(n), "trajectory": int(n)})
    say = log or (lambda _line: None)
    started = time.perf_counter()
    machine = machine_info()
    rng = np.random.default_rng(SEED)
    rows: list[Row] = []
    skipped: list[str] = []
    reps = sizes.repeats

    Q = _random_joints(rng, sizes.batch)
    T = robot.fk(Q)
    # warm every kernel up (cache load / compilation is not what is timed here)
    robot.ik_all_batch(T[:2])
    robot.ik_batch(T[:2], 1)
    robot.ik(T[0], int(robot.config_of(Q[0])))
    robot.ik_all(T[0])

    # ---- yardsticks
    say("numpy FK yardstick")
    T_np = numpy_fk(robot, Q)
    t_batch = _best(lambda: numpy_fk(robot, Q), reps) / sizes.batch
    bad = int((np.abs(T_np - T).max(axis=(1, 2)) > 1e-9 * robot.family.scale).sum())
    rows.append(Row("numpy FK, batch (yardstick)", "yardstick", sizes.batch, t_batch, "pose",
                    "batch", 1.0, failures=bad, note="product of the seven eq. (1) matrices"))
    Qs = Q[: sizes.single]
    Ts = T[: sizes.single]

    def np_single():
        for q in Qs:
            numpy_fk(robot, q)

    t_single = _best(np_single, reps) / len(Qs)
    rows.append(Row("numpy FK, one pose per call (yardstick)", "yardstick", len(Qs), t_single,
                    "call", "single", 1.0))

    def ratio_b(t):
        return t / t_batch

    def ratio_s(t):
        return t / t_single

    say("robot.fk")
    t = _best(lambda: robot.fk(Q), reps) / sizes.batch
    rows.append(Row("robot.fk, batch (compiled)", "ours", sizes.batch, t, "pose", "batch",
                    ratio_b(t), failures=bad))

    def fk_single():
        for q in Qs:
            robot.fk(q)

    t = _best(fk_single, reps) / len(Qs)
    rows.append(Row("robot.fk, one pose per call", "ours", len(Qs), t, "call", "single", ratio_s(t)))

    # ---- ik_batch, one configuration
    say("ik_batch")
    qb, ok = robot.ik_batch(T, 1)
    t = _best(lambda: robot.ik_batch(T, 1), reps) / sizes.batch
    wrong = int((~_fk_ok(robot, qb[ok], T[ok]) | (robot.config_of(qb[ok]) != 1)).sum())
    missed = int(((robot.config_of(Q) == 1) & ~ok).sum())
    rows.append(Row("ik_batch, one configuration", "ours", sizes.batch, t, "pose", "batch", ratio_b(t),
                    f"<= {TARGET_IK_BATCH:g}x", ratio_b(t) <= TARGET_IK_BATCH, int(ok.sum()),
                    wrong + missed, note=f"config 1; {_threads_note(sizes.batch)}"))

    # ---- ik_all_batch
    say("ik_all_batch")
    qa, valid = robot.ik_all_batch(T)
    t = _best(lambda: robot.ik_all_batch(T), reps) / sizes.batch
    fails = _verify_all(robot, qa, valid, T, Q)
    rows.append(Row("ik_all_batch, every solution", "ours", sizes.batch, t, "pose", "batch", ratio_b(t),
                    f"<= {TARGET_IK_ALL_BATCH:g}x", ratio_b(t) <= TARGET_IK_ALL_BATCH,
                    int(valid.any(axis=1).sum()), fails,
                    note=f"{valid.sum() / sizes.batch:.2f} solutions per pose; {_threads_note(sizes.batch)}"))
    if _threads_note(sizes.batch) != "1 thread":
        old = os.environ.get("IK7R_NUM_THREADS")
        os.environ["IK7R_NUM_THREADS"] = "1"
        try:
            t1 = _best(lambda: robot.ik_all_batch(T), reps) / sizes.batch
        finally:
            if old is None:
                del os.environ["IK7R_NUM_THREADS"]
            else:
                os.environ["IK7R_NUM_THREADS"] = old
        rows.append(Row("ik_all_batch, 1 thread", "ours", sizes.batch, t1, "pose", "batch", ratio_b(t1),
                        note="IK7R_NUM_THREADS=1"))

    # ---- single calls
    say("single ik / ik_all calls")
    cfg = robot.config_of(Qs)
    out = np.empty((len(Qs), 6))
    errors = [0]

    def ik_single():
        errors[0] = 0
        for i in range(len(Qs)):
            try:
                out[i] = robot.ik(Ts[i], int(cfg[i]))
            except ValueError:
                out[i] = np.nan
                errors[0] += 1

    t = _best(ik_single, reps) / len(Qs)
    good = ~np.isnan(out[:, 0])
    fails = int((~_fk_ok(robot, out[good], Ts[good])).sum()) + errors[0]
    fails += int((robot.config_of(out[good]) != cfg[good]).sum())
    rows.append(Row("robot.ik(T, config), one call", "ours", len(Qs), t, "call", "single", ratio_s(t),
                    f"<= {TARGET_IK_SINGLE:g}x", ratio_s(t) <= TARGET_IK_SINGLE, int(good.sum()),
                    fails, note="config of the joints the pose was made from"))
    sols: list[np.ndarray] = []

    def ik_all_single():
        sols.clear()
        for Ti in Ts:
            sols.append(robot.ik_all(Ti))

    t = _best(ik_all_single, reps) / len(Qs)
    fails = 0
    for i, s in enumerate(sols):
        fails += int((~_fk_ok(robot, s, np.broadcast_to(Ts[i], (len(s), 4, 4)))).sum())
        fails += int(not _same_solution(s, Qs[i][None]).any())
    rows.append(Row("robot.ik_all(T), one call", "ours", len(Qs), t, "call", "single", ratio_s(t),
                    f"<= {TARGET_IK_ALL_SINGLE:g}x", ratio_s(t) <= TARGET_IK_ALL_SINGLE,
                    sum(len(s) > 0 for s in sols), fails))

    # ---- trajectory
    say("trajectory")
    rows.extend(_trajectory_rows(robot, rng, sizes, ratio_b))

    # ---- baselines
    if baselines:
        rows.extend(_baseline_rows(robot, rng, sizes, ratio_s, pinocchio, skipped, say))

    # ---- the paper's reported times
    rows.append(Row("paper (MATLAB), one pose: reported", "reference", 0, PAPER_MS_PER_POSE * 1e-3,
                    "call", "single", ratio_s(PAPER_MS_PER_POSE * 1e-3), note="not measured here"))
    rows.append(Row("paper (MATLAB), trajectory point: reported", "reference", 0,
                    PAPER_MS_PER_POINT * 1e-3, "point", "batch", ratio_b(PAPER_MS_PER_POINT * 1e-3),
                    note="not measured here"))

    # ---- big chunked batch
    if big:
        say(f"chunked ik_all over {big} random poses")
        rows.append(_big_row(robot, big, ratio_b))

    # ---- fresh processes
    if startup:
        say("fresh processes")
        rows.extend(_startup_rows(reps))

    return BenchReport(tuple(rows), machine, robot.name, sizes, time.perf_counter() - started,
                       tuple(skipped))


def _threads_note(n: int) -> str:
    from .ik.solve import threads_for

    k = threads_for(n)
    return "1 thread" if k == 1 else f"{k} threads"


def _verify_all(robot, q: np.ndarray, valid: np.ndarray, T: np.ndarray, Q: np.ndarray) -> int:
    """Failures of ``ik_all_batch``'s answer: solutions off the pose, and poses whose
    generating joints ``Q`` are not among their solutions."""
    idx = np.nonzero(valid)
    wrong = int((~_fk_ok(robot, q[idx], T[idx[0]])).sum())
    found = (_same_solution(q, Q[:, None, :]) & valid).any(axis=1)
    return wrong + int((~found).sum())


def _trajectory_rows(robot, rng, sizes: Sizes, ratio_b) -> list[Row]:
    from .ik.path import ik_path

    Qp = _path_joints(rng, sizes.trajectory)
    Tp = robot.fk(Qp)
    cfg = int(robot.config_of(Qp[0]))
    ik_path(robot, Tp[:3], cfg, seed=Qp[0])  # warm the kernel
    res = ik_path(robot, Tp, cfg, seed=Qp[0])
    t = _best(lambda: ik_path(robot, Tp, cfg, seed=Qp[0]), sizes.repeats) / len(Qp)
    fails = int((~_fk_ok(robot, res.q[res.ok], Tp[res.ok])).sum()) + int((~res.ok).sum())
    rate = 1.0 / t
    rows = [Row("ik_path (warm-started trajectory)", "ours", len(Qp), t, "point", "batch", ratio_b(t),
                f">= {TARGET_POINTS_PER_SECOND / 1e3:,.0f} k points/s", rate >= TARGET_POINTS_PER_SECOND,
                int(res.ok.sum()), fails,
                note=f"{rate / 1e3:,.0f} k points/s; {res.tracked.mean():.1%} warm; ~1e-3 rad per step")]
    # ik_batch with every point seeded by the previous point's joints
    seeds = np.vstack([Qp[:1], Qp[:-1]])
    qb, ok = robot.ik_batch(Tp, cfg, seed=seeds)
    t = _best(lambda: robot.ik_batch(Tp, cfg, seed=seeds), sizes.repeats) / len(Qp)
    fails = int((~_fk_ok(robot, qb[ok], Tp[ok])).sum()) + int((~ok).sum())
    rows.append(Row("ik_batch seeded by the previous point", "ours", len(Qp), t, "point", "batch",
                    ratio_b(t), solved=int(ok.sum()), failures=fails,
                    note=f"{1 / t / 1e3:,.0f} k points/s; complete solve per point"))
    return rows


def _baseline_rows(robot, rng, sizes: Sizes, ratio_s, want_pinocchio: bool, skipped: list[str],
                   say) -> list[Row]:
    from .ik.numeric import damped_least_squares, newton_raphson

    rows = []
    # the paper's iteration, in each pose's own configuration, random theta5 start (the paper's)
    say("the paper's iteration")
    Qp = _random_joints(rng, sizes.paper)
    Tp = robot.fk(Qp)
    cfg = robot.config_of(Qp)
    robot.ik_paper(Tp[0], int(cfg[0]), rng=np.random.default_rng(0))
    results = []

    def paper():
        results.clear()
        prng = np.random.default_rng(SEED)
        for i in range(len(Qp)):
            results.append(robot.ik_paper(Tp[i], int(cfg[i]), rng=prng))

    t = _best(paper, min(sizes.repeats, 2)) / len(Qp)
    oks = [r for r in results if r.ok]
    fails = sum(int(not _fk_ok(robot, r.q[None], Tp[i][None])[0]) for i, r in enumerate(results) if r.ok)
    iters = np.mean([r.iterations for r in results])
    rows.append(Row("ik_paper (the paper's iteration, ours in Python)", "baseline", len(Qp), t, "call",
                    "single", ratio_s(t), solved=len(oks), failures=fails,
                    note=f"{iters:.0f} iterations per pose on average"))

    # Jacobian methods from a perturbed start (a typical warm start)
    Qn = _random_joints(rng, sizes.numeric)
    Tn = robot.fk(Qn)
    starts = Qn + rng.uniform(-0.2, 0.2, Qn.shape)
    for name, solver in (("numeric.newton_raphson", newton_raphson),
                         ("numeric.damped_least_squares", damped_least_squares)):
        say(name)
        solver(robot, Tn[0], starts[0])
        res = []

        def run(solver=solver, res=res):
            res.clear()
            for i in range(len(Qn)):
                res.append(solver(robot, Tn[i], starts[i]))

        t = _best(run, min(sizes.repeats, 2)) / len(Qn)
        fails = sum(int(not _fk_ok(robot, r.q[None], Tn[i][None])[0]) for i, r in enumerate(res) if r.ok)
        rows.append(Row(name, "baseline", len(Qn), t, "call", "single", ratio_s(t),
                        solved=sum(r.ok for r in res), failures=fails,
                        note="start: the solution + U(-0.2, 0.2) rad"))

    say("scipy least_squares")
    rows.append(_scipy_row(robot, Tn[: sizes.scipy], starts[: sizes.scipy], ratio_s, sizes))

    if want_pinocchio:
        say("pinocchio")
        row = _pinocchio_row(robot, Tn[: sizes.pinocchio], starts[: sizes.pinocchio], ratio_s, sizes)
        if isinstance(row, str):
            skipped.append(f"pinocchio ({row})")
        else:
            rows.append(row)
    return rows


def _scipy_row(robot, Tn, starts, ratio_s, sizes: Sizes) -> Row:
    from scipy.optimize import least_squares

    from .geometry.rotations import wrap_angle

    scale = robot.family.scale

    def residual(q, Td):
        Tq = robot.fk(q)
        e = np.empty(6)
        e[:3] = (Tq[:3, 3] - Td[:3, 3]) / scale
        R = Td[:3, :3].T @ Tq[:3, :3]
        e[3:] = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
        return e

    out = []

    def run():
        out.clear()
        for i in range(len(Tn)):
            r = least_squares(residual, starts[i], args=(Tn[i],), method="lm", xtol=1e-15,
                              ftol=1e-15, gtol=1e-15)
            out.append(wrap_angle(r.x))

    t = _best(run, min(sizes.repeats, 2)) / len(Tn)
    qs = np.array(out)
    ok = _fk_ok(robot, qs, Tn)
    return Row("scipy least_squares (LM, same FK)", "baseline", len(Tn), t, "call", "single", ratio_s(t),
               solved=int(ok.sum()), failures=0,
               note="answers checked to the robot's tolerance; misses count as not solved")


def _pinocchio_row(robot, Tn, starts, ratio_s, sizes: Sizes) -> Row | str:
    """The pinocchio row, or why there is none."""
    try:
        import pinocchio as pin
    except ImportError:
        return "import pinocchio failed: pip install pin"
    from .units import METRES_PER_UNIT

    m_per_unit = METRES_PER_UNIT[robot.unit]
    try:
        model = pin.buildModelFromXML(robot.to_urdf(), mimic=True)
    except (TypeError, ValueError, RuntimeError, AttributeError) as exc:  # an older pinocchio
        return f"pinocchio {pin.__version__} cannot load the mimic URDF: {exc}"
    data = model.createData()
    fid = model.getFrameId("tool0")
    eps_p = robot.position_tolerance * m_per_unit
    eps_r = robot.rotation_tolerance

    def solve(T_goal, q0):
        R = T_goal[:3, :3]
        goal = pin.SE3(R, T_goal[:3, 3] * m_per_unit)
        q = q0.copy()
        for _ in range(200):
            pin.framesForwardKinematics(model, data, q)
            err_se3 = data.oMf[fid].actInv(goal)
            err = pin.log6(err_se3).vector
            if np.linalg.norm(err[:3]) < eps_p and np.linalg.norm(err[3:]) < eps_r:
                return q, True
            J = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL)
            J = pin.Jlog6(err_se3.inverse()) @ J
            dq = J.T @ np.linalg.solve(J @ J.T + 1e-12 * np.eye(6), err)
            q = pin.integrate(model, q, dq)
        return q, False

    solve(Tn[0], starts[0])
    out = []

    def run():
        out.clear()
        for i in range(len(Tn)):
            out.append(solve(Tn[i], starts[i]))

    t = _best(run, min(sizes.repeats, 2)) / len(Tn)
    qs = np.array([q for q, _ in out])
    claimed = np.array([c for _, c in out])
    ok = _fk_ok(robot, qs, Tn)
    return Row(f"pinocchio {pin.__version__} DLS loop (mimic URDF)", "baseline", len(Tn), t, "call",
               "single", ratio_s(t), solved=int((ok & claimed).sum()), failures=int((claimed & ~ok).sum()),
               note="framesForwardKinematics + log6 + Jlog6 damped step, Python loop")


_BIG_SCRIPT = r"""
import json, resource, sys, time
import numpy as np
import ik7r
from ik7r.ik.chunked import RandomPoses, solve_all_chunked
from ik7r.benchmark import SEED, _verify_all
robot = ik7r.load_robot(sys.argv[2] if len(sys.argv) > 2 else None)
n = int(sys.argv[1])
robot.ik_all_batch(robot.fk(np.zeros((2, 6))))  # load the kernels before timing
rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
t0 = time.perf_counter()
fails = solutions = 0
for res in solve_all_chunked(robot, RandomPoses(robot, n, seed=SEED)):
    solutions += int(res.count.sum())
    k = slice(0, len(res.count), 97)  # verify 1 pose in 97 (all of them would double the time)
    fails += _verify_all(robot, res.q[k], res.valid[k], res.T[k], res.joints[k])
seconds = time.perf_counter() - t0
rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({"seconds": seconds, "failures": fails, "solutions": solutions,
                  "rss_mb": rss / 1024, "rss_before_mb": rss0 / 1024}))
"""


def _big_row(robot, n: int, ratio_b) -> Row:
    """Solve ``n`` random poses chunk by chunk in a fresh process (its peak memory is reported)."""
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        args = [sys.executable, "-c", _BIG_SCRIPT, str(n)]
        if robot.name not in ("paper",):
            path = Path(tmp) / "robot.toml"
            path.write_text(robot.to_toml())
            args.append(str(path))
        p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        tail = (p.stderr.strip().splitlines() or ["?"])[-1]
        return Row(f"solve_all_chunked, {n:,} random poses", "ours", n, math.nan, "pose",
                   failures=1, note=f"the run failed: {tail}")
    r = json.loads(p.stdout.strip().splitlines()[-1])
    t = r["seconds"] / n
    return Row(f"solve_all_chunked, {n:,} random poses", "ours", n, t, "pose", "batch", ratio_b(t),
               failures=r["failures"],
               note=f"{1 / t:,.0f} poses/s, {r['solutions'] / n:.2f} solutions per pose; peak RSS "
                    f"{r['rss_mb']:.0f} MB ({r['rss_before_mb']:.0f} MB before); 1 pose in 97 verified")


_STARTUP_SCRIPT = r"""
import json, sys, time
t0 = time.perf_counter()
import numpy as np
t1 = time.perf_counter()
import numba
t2 = time.perf_counter()
import ik7r
robot = ik7r.load_robot(sys.argv[1] if len(sys.argv) > 1 else None)
robot.fk(np.zeros(6))
t3 = time.perf_counter()
robot.ik_all(robot.fk(np.full(6, 0.5)))
t4 = time.perf_counter()
print(json.dumps({"numpy": t1 - t0, "numba": t2 - t1, "first_kernel": t3 - t2, "first_ik": t4 - t3}))
"""

_NO_NUMBA = ("import sys; sys.modules['numba'] = None; from ik7r.cli.app import main; "
             "sys.exit(main(sys.argv[1:]))")


def _startup_rows(reps: int) -> list[Row]:
    from .geometry.rotations import matrix_to_rpy
    from .robot.files import load_robot

    rows = []
    runs = []
    for _ in range(max(2, reps)):
        p = subprocess.run([sys.executable, "-c", _STARTUP_SCRIPT], capture_output=True, text=True,
                           timeout=600)
        if p.returncode == 0:
            runs.append(json.loads(p.stdout.strip().splitlines()[-1]))
    if runs:
        best = {k: min(r[k] for r in runs) for k in runs[0]}
        rows.append(Row("import numba (fresh process)", "startup", len(runs), best["numba"], "process",
                        note=f"numpy import {best['numpy'] * 1e3:.0f} ms"))
        rows.append(Row("first compiled call (numba init + cache load)", "startup", len(runs),
                        best["first_kernel"], "process", note="robot.fk, cached kernels"))
        rows.append(Row("first ik_all (solver cache load)", "startup", len(runs), best["first_ik"],
                        "process"))
    q = np.radians([60.0, 60.0, 0.0, -30.0, 60.0, 30.0])  # the paper's Simulation 1
    T = load_robot().fk(q)
    args = ["ik", "--position", *(repr(float(x)) for x in T[:3, 3]),
            "--rpy", *(repr(float(x)) for x in np.degrees(matrix_to_rpy(T[:3, :3])))]
    script = Path(sys.executable).with_name("ik7r")
    base = [str(script)] if script.exists() else [sys.executable, "-m", "ik7r.cli.app"]
    for name, cmd, note in (
        ("ik7r ik ... end to end", base + args, "process start to answer; the paper robot"),
        ("ik7r ik, kernels in pure Python (experiment)", [sys.executable, "-c", _NO_NUMBA] + args,
         "numba not imported: what a no-JIT CLI would cost"),
    ):
        times = []
        for _ in range(max(2, reps)):
            t0 = time.perf_counter()
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
            times.append(time.perf_counter() - t0)
        ok = p.returncode == 0
        t = min(times)
        target = name.startswith("ik7r ik ...")
        rows.append(Row(name, "startup", len(times), t, "process",
                        target=f"< {TARGET_CLI_SECONDS:g} s" if target else "",
                        meets=(t < TARGET_CLI_SECONDS) if target else None,
                        solved=int(ok), failures=int(not ok), note=note))
    return rows


# ---------------------------------------------------------------------- formatting
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


def main(argv: list[str] | None = None) -> int:
    """``python benchmarks/run.py`` / ``python -m ik7r.benchmark``: same options as ``ik7r bench``."""
    from .cli.app import main as cli_main

    return cli_main(["bench", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
