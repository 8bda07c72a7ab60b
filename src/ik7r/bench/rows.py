"""The rows of the benchmark, one function per group (each verifies what it times)."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .report import Row, Sizes

if TYPE_CHECKING:
    from ..ik.numeric import NumericResult
    from ..ik.paper import PaperResult
from .verify import fk_ok

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
#: Targets of the first run: a fresh installation's first ``ik_all``, and a new process's first
#: compiled answer after ``import ik7r``.
TARGET_COLD_SECONDS = 15.0
TARGET_WARM_SECONDS = 0.3

SEED = 2024


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


def _threads_note(n: int) -> str:
    from ..ik.solve import threads_for

    k = threads_for(n)
    return "1 thread" if k == 1 else f"{k} threads"


def _trajectory_rows(robot, rng, sizes: Sizes, ratio_b) -> list[Row]:
    from ..ik.path import ik_path

    Qp = _path_joints(rng, sizes.trajectory)
    Tp = robot.fk(Qp)
    cfg = int(robot.config_of(Qp[0]))
    ik_path(robot, Tp[:3], cfg, seed=Qp[0])  # warm the kernel
    res = ik_path(robot, Tp, cfg, seed=Qp[0])
    t = _best(lambda: ik_path(robot, Tp, cfg, seed=Qp[0]), sizes.repeats) / len(Qp)
    fails = int((~fk_ok(robot, res.q[res.ok], Tp[res.ok])).sum()) + int((~res.ok).sum())
    rate = 1.0 / t
    rows = [Row("ik_path (warm-started trajectory)", "ours", len(Qp), t, "point", "batch", ratio_b(t),
                f">= {TARGET_POINTS_PER_SECOND / 1e3:,.0f} k points/s", rate >= TARGET_POINTS_PER_SECOND,
                int(res.ok.sum()), fails,
                note=f"{rate / 1e3:,.0f} k points/s; {res.tracked.mean():.1%} warm; ~1e-3 rad per step")]
    # ik_batch with every point seeded by the previous point's joints
    seeds = np.vstack([Qp[:1], Qp[:-1]])
    qb, ok = robot.ik_batch(Tp, cfg, seed=seeds)
    t = _best(lambda: robot.ik_batch(Tp, cfg, seed=seeds), sizes.repeats) / len(Qp)
    fails = int((~fk_ok(robot, qb[ok], Tp[ok])).sum()) + int((~ok).sum())
    rows.append(Row("ik_batch seeded by the previous point", "ours", len(Qp), t, "point", "batch",
                    ratio_b(t), solved=int(ok.sum()), failures=fails,
                    note=f"{1 / t / 1e3:,.0f} k points/s; complete solve per point"))
    return rows


def _baseline_rows(robot, rng, sizes: Sizes, ratio_s, want_pinocchio: bool, skipped: list[str],
                   say) -> list[Row]:
    from ..ik.numeric import damped_least_squares, newton_raphson

    rows = []
    # the paper's iteration, in each pose's own configuration, random theta5 start (the paper's)
    say("the paper's iteration")
    Qp = _random_joints(rng, sizes.paper)
    Tp = robot.fk(Qp)
    cfg = robot.config_of(Qp)
    robot.ik_paper(Tp[0], int(cfg[0]), rng=np.random.default_rng(0))
    results: list[PaperResult] = []

    def paper():
        results.clear()
        prng = np.random.default_rng(SEED)
        for i in range(len(Qp)):
            results.append(robot.ik_paper(Tp[i], int(cfg[i]), rng=prng))

    t = _best(paper, min(sizes.repeats, 2)) / len(Qp)
    oks = [r for r in results if r.ok]
    fails = sum(1 for i, r in enumerate(results)
                if r.ok and r.q is not None and not fk_ok(robot, r.q[None], Tp[i][None])[0])
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
        res: list[NumericResult] = []

        def run(solver=solver, res=res):
            res.clear()
            for i in range(len(Qn)):
                res.append(solver(robot, Tn[i], starts[i]))

        t = _best(run, min(sizes.repeats, 2)) / len(Qn)
        fails = sum(1 for i, r in enumerate(res)
                    if r.ok and r.q is not None and not fk_ok(robot, r.q[None], Tn[i][None])[0])
        rows.append(Row(name, "baseline", len(Qn), t, "call", "single", ratio_s(t),
                        solved=sum(int(r.ok) for r in res), failures=fails,
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

    from ..geometry.rotations import wrap_angle

    scale = robot.family.scale

    def residual(q, Td):
        Tq = robot.fk(q)
        e = np.empty(6)
        e[:3] = (Tq[:3, 3] - Td[:3, 3]) / scale
        R = Td[:3, :3].T @ Tq[:3, :3]
        e[3:] = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
        return e

    out: list[np.ndarray] = []

    def run():
        out.clear()
        for i in range(len(Tn)):
            r = least_squares(residual, starts[i], args=(Tn[i],), method="lm", xtol=1e-15,
                              ftol=1e-15, gtol=1e-15)
            out.append(wrap_angle(r.x))

    t = _best(run, min(sizes.repeats, 2)) / len(Tn)
    qs = np.array(out)
    ok = fk_ok(robot, qs, Tn)
    return Row("scipy least_squares (LM, same FK)", "baseline", len(Tn), t, "call", "single", ratio_s(t),
               solved=int(ok.sum()), failures=0,
               note="answers checked to the robot's tolerance; misses count as not solved")


def _pinocchio_row(robot, Tn, starts, ratio_s, sizes: Sizes) -> Row | str:
    """The pinocchio row, or why there is none."""
    try:
        import pinocchio as pin
    except ImportError:
        return "import pinocchio failed: pip install pin"
    from ..units import METRES_PER_UNIT

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
    out: list[tuple[np.ndarray, bool]] = []

    def run():
        out.clear()
        for i in range(len(Tn)):
            out.append(solve(Tn[i], starts[i]))

    t = _best(run, min(sizes.repeats, 2)) / len(Tn)
    qs = np.array([q for q, _ in out])
    claimed = np.array([c for _, c in out])
    ok = fk_ok(robot, qs, Tn)
    return Row(f"pinocchio {pin.__version__} DLS loop (mimic URDF)", "baseline", len(Tn), t, "call",
               "single", ratio_s(t), solved=int((ok & claimed).sum()), failures=int((claimed & ~ok).sum()),
               note="framesForwardKinematics + log6 + Jlog6 damped step, Python loop")


def _big_row(robot, n: int, ratio_b) -> Row:
    """Solve ``n`` random poses chunk by chunk in a fresh process (its peak memory is reported)."""
    with tempfile.TemporaryDirectory() as tmp:
        args = [sys.executable, "-m", "ik7r.bench.probe_big", str(n)]
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


def _probe(args: list[str], env: dict[str, str] | None = None) -> dict | None:
    """Run ``python -m ik7r.bench.probe_startup ARGS`` in a fresh process: its JSON, or None."""
    p = subprocess.run([sys.executable, "-m", "ik7r.bench.probe_startup", *args], capture_output=True,
                       text=True, timeout=1800, env=env)
    if p.returncode != 0:
        return None
    return json.loads(p.stdout.strip().splitlines()[-1])


def _best_of(runs: list[dict]) -> dict[str, float]:
    return {k: min(r[k] for r in runs) for k in runs[0]}


def _route(r: dict) -> str:
    if r.get("compiled"):
        return "kernels compiled at installation, numba not imported"
    return "numba JIT" + (", numba imported" if r.get("numba") else "")


def _cold_row(jit: bool) -> Row:
    """A fresh installation's first ``ik_all``: a new process whose numba cache directory is
    empty (``NUMBA_CACHE_DIR``), so every kernel the JIT needs compiles. With the compiled
    module (built by the installation) nothing compiles; ``jit``: without it (``IK7R_AOT=0``),
    numba's JIT compiles everything ``ik_all`` needs (it takes a while)."""
    name = ("cold, JIT fallback: first ik_all, empty numba cache (compiles)" if jit
            else "cold: first ik_all of a fresh install")
    with tempfile.TemporaryDirectory(prefix="ik7r-cold-cache-") as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "IK7R_QUIET": "1"}
        if jit:
            env["IK7R_AOT"] = "0"
        t0 = time.perf_counter()
        r = _probe(["--first-answer"], env)
        total = time.perf_counter() - t0
    if r is None:
        return Row(name, "startup", 1, math.nan, "process", target=f"<= {TARGET_COLD_SECONDS:g} s",
                   meets=False, solved=0, failures=1, note="the probe failed")
    t = r["first_answer"]
    note = (f"empty NUMBA_CACHE_DIR; {_route(r)}; after import ik7r ({r['import'] * 1e3:.0f} ms); "
            f"process {total:.1f} s")
    if not jit:
        from .._kernels import aot

        built = aot.info()
        if r.get("compiled") and built:
            note += (f"; the installation compiled the module once in {built.get('seconds')} s "
                     f"({built.get('cpu_seconds')} CPU s)")
    return Row(name, "startup", 1, t, "process", target="" if jit else f"<= {TARGET_COLD_SECONDS:g} s",
               meets=None if jit else t <= TARGET_COLD_SECONDS, solved=1, failures=0, note=note)


def _startup_rows(reps: int, cold: bool = False) -> list[Row]:
    from ..geometry.rotations import matrix_to_rpy
    from ..robot.files import load_robot

    rows = []
    answers = [r for r in (_probe(["--first-answer"]) for _ in range(max(2, reps))) if r is not None]
    if answers:
        best = _best_of(answers)
        t = best["first_answer"]
        rows.append(Row("warm: first ik_all after import ik7r (new process)", "startup", len(answers), t,
                        "process", target=f"<= {TARGET_WARM_SECONDS:g} s", meets=t <= TARGET_WARM_SECONDS,
                        solved=1, failures=0,
                        note=f"{_route(answers[-1])}; import ik7r {best['import'] * 1e3:.0f} ms before it"))
    from .._kernels import aot

    if cold or aot.load() is not None:  # (cheap with the compiled module: nothing compiles)
        rows.append(_cold_row(jit=False))
    jit_env = {**os.environ, "IK7R_AOT": "0"}
    runs = [r for r in (_probe([], jit_env) for _ in range(max(2, reps))) if r is not None]
    if runs:
        best = _best_of(runs)
        rows.append(Row("JIT fallback: import numba (fresh process)", "startup", len(runs), best["numba"],
                        "process", note=f"IK7R_AOT=0; numpy import {best['numpy'] * 1e3:.0f} ms"))
        rows.append(Row("JIT fallback: first compiled call (numba init + cache load)", "startup", len(runs),
                        best["first_kernel"], "process", note="robot.fk, cached kernels"))
        rows.append(Row("JIT fallback: first ik_all (solver cache load)", "startup", len(runs),
                        best["first_ik"], "process"))
    answers = [r for r in (_probe(["--first-answer"], jit_env) for _ in range(max(2, reps))) if r is not None]
    if answers:
        best = _best_of(answers)
        rows.append(Row("warm, JIT fallback: first ik_all after import ik7r", "startup", len(answers),
                        best["first_answer"], "process",
                        note="IK7R_AOT=0: numba's import, start-up and cache load included"))
    if cold:
        rows.append(_cold_row(jit=True))
    q = np.radians([60.0, 60.0, 0.0, -30.0, 60.0, 30.0])  # the paper's Simulation 1
    T = load_robot().fk(q)
    args = ["ik", "--position", *(repr(float(x)) for x in T[:3, 3]),
            "--rpy", *(repr(float(x)) for x in np.degrees(matrix_to_rpy(T[:3, :3])))]
    script = Path(sys.executable).with_name("ik7r")
    base = [str(script)] if script.exists() else [sys.executable, "-m", "ik7r"]
    for name, cmd, note in (
        ("ik7r ik ... end to end", base + args, "process start to answer; the paper robot"),
        ("ik7r ik, kernels in pure Python (experiment)",
         [sys.executable, "-m", "ik7r.bench.cli_without_numba"] + args,
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
