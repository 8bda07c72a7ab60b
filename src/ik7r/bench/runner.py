"""``run_benchmarks``: every row once, on the same poses, and the machine it ran on."""

from __future__ import annotations

import os
import platform
import sys
import time
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .report import BenchReport, Row, Sizes
from .rows import (
    PAPER_MS_PER_POINT,
    PAPER_MS_PER_POSE,
    SEED,
    TARGET_IK_ALL_BATCH,
    TARGET_IK_ALL_SINGLE,
    TARGET_IK_BATCH,
    TARGET_IK_SINGLE,
    _baseline_rows,
    _best,
    _big_row,
    _random_joints,
    _startup_rows,
    _threads_note,
    _trajectory_rows,
)
from .verify import fk_ok, numpy_fk, same_solution, verify_all

if TYPE_CHECKING:
    from ..robot.model import Robot

__all__ = ["run_benchmarks", "machine_info", "main"]


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
    info: dict[str, object] = {"cpu": cpu, "cores": os.cpu_count(), "usable_cores": usable,
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
    from .. import __version__
    from ..ik.solve import num_threads

    info["ik7r"] = __version__
    info["threads"] = num_threads()
    return info


def run_benchmarks(robot: Robot | None = None, *, quick: bool = False, n: int | None = None,
                   sizes: Sizes | None = None, startup: bool = True, baselines: bool = True,
                   pinocchio: bool = True, big: int = 0, cold: bool | None = None,
                   log: Callable[[str], None] | None = None) -> BenchReport:
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
        Time fresh processes: the first ``ik_all`` after ``import ik7r`` (with the kernels
        compiled at installation, :mod:`ik7r._kernels.aot`, and on the JIT fallback route:
        numba import and cache load), ``ik7r ik`` end to end.
    cold : bool, optional
        With ``startup``, also time a fresh installation's first ``ik_all`` on the JIT
        fallback route (``IK7R_AOT=0`` and an empty numba cache directory: every kernel it
        needs compiles, about a minute). Default: not with ``quick``. The cold row of the
        compiled route (an empty numba cache, nothing compiles) runs whenever the compiled
        module is there.
    baselines : bool
        Time the paper's iteration, Newton-Raphson, DLS, scipy and pinocchio.
    pinocchio : bool
        Include pinocchio when ``import pinocchio`` works.
    big : int
        Also solve this many random poses with :func:`ik7r.ik.chunked.solve_all_chunked`.
    log : callable, optional
        Called with a line of text as each part starts (progress on stderr).
    """
    from .. import load_robot

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
    wrong = int((~fk_ok(robot, qb[ok], T[ok]) | (robot.config_of(qb[ok]) != 1)).sum())
    missed = int(((robot.config_of(Q) == 1) & ~ok).sum())
    rows.append(Row("ik_batch, one configuration", "ours", sizes.batch, t, "pose", "batch", ratio_b(t),
                    f"<= {TARGET_IK_BATCH:g}x", ratio_b(t) <= TARGET_IK_BATCH, int(ok.sum()),
                    wrong + missed, note=f"config 1; {_threads_note(sizes.batch)}"))

    # ---- ik_all_batch
    say("ik_all_batch")
    qa, valid = robot.ik_all_batch(T)
    t = _best(lambda: robot.ik_all_batch(T), reps) / sizes.batch
    fails = verify_all(robot, qa, valid, T, Q)
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
    fails = int((~fk_ok(robot, out[good], Ts[good])).sum()) + errors[0]
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
        fails += int((~fk_ok(robot, s, np.broadcast_to(Ts[i], (len(s), 4, 4)))).sum())
        fails += int(not same_solution(s, Qs[i][None]).any())
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
        rows.extend(_startup_rows(reps, cold=not quick if cold is None else cold))

    return BenchReport(tuple(rows), machine, robot.name, sizes, time.perf_counter() - started,
                       tuple(skipped))


def main(argv: list[str] | None = None) -> int:
    """``python benchmarks/run.py`` / ``python -m ik7r.bench``: same options as ``ik7r bench``."""
    import ik7r.cli

    cli_main = ik7r.cli.main

    return cli_main(["bench", *(sys.argv[1:] if argv is None else argv)])
