"""The benchmark runner: table structure and verification (never timings)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import ik7r
from ik7r.bench import BenchReport, Sizes, numpy_fk, run_benchmarks
from ik7r.bench.rows import _startup_rows
from ik7r.bench.verify import same_solution as _same_solution
from ik7r.bench.verify import verify_all as _verify_all
from ik7r.cli import main

TINY = Sizes(batch=300, single=30, trajectory=400, numeric=4, scipy=3, pinocchio=3, paper=4, repeats=1)

EXPECTED = [
    "numpy FK, batch (yardstick)",
    "numpy FK, one pose per call (yardstick)",
    "robot.fk, batch",
    "robot.fk, one pose per call",
    "ik_batch, one configuration",
    "ik_all_batch, every solution",
    "robot.ik(T, config), one call",
    "robot.ik_all(T), one call",
    "ik_path (warm-started trajectory)",
    "ik_batch seeded by the previous point",
    "ik_paper",
    "numeric.newton_raphson",
    "numeric.damped_least_squares",
    "scipy least_squares",
    "paper (MATLAB), one pose: reported",
    "paper (MATLAB), trajectory point: reported",
]


@pytest.fixture(scope="module")
def robot():
    return ik7r.load_robot()


@pytest.fixture(scope="module")
def report(robot) -> BenchReport:
    return run_benchmarks(robot, sizes=TINY, startup=False)


def test_every_row_is_there(report):
    names = [r.name for r in report.rows]
    for name in EXPECTED:
        assert any(n.startswith(name) for n in names), f"missing row {name!r}"
    try:
        import pinocchio  # noqa: F401
    except ImportError:
        assert any("pinocchio" in s for s in report.skipped)
    else:
        assert any(n.startswith("pinocchio") for n in names)


def test_verification_counted_no_failure(report):
    for r in report.rows:
        assert r.failures in (None, 0), f"{r.name}: {r.failures} failures"
    assert report.failures == 0


def test_complete_solvers_answer_every_pose(report):
    for name in ("ik_all_batch, every solution", "robot.ik(T, config)", "robot.ik_all(T)", "ik_path"):
        r = report.row(name)
        assert r.solved == r.n, f"{r.name}: {r.solved}/{r.n}"


def test_rows_are_consistent(report):
    for r in report.rows:
        assert math.isfinite(r.seconds) and r.seconds > 0, r.name
        assert r.kind in ("yardstick", "ours", "baseline", "reference", "startup")
        if r.kind != "startup":
            assert r.vs in ("batch", "single") and r.ratio is not None, r.name
        if r.target:
            assert isinstance(r.meets, bool), r.name
        else:
            assert r.meets is None, r.name
    batch = report.row("numpy FK, batch").seconds
    single = report.row("numpy FK, one pose per call").seconds
    for r in report.rows:
        base = batch if r.vs == "batch" else single
        if r.ratio is not None:
            assert r.ratio == pytest.approx(r.seconds / base, rel=1e-12), r.name
    assert report.row("paper (MATLAB), one pose").seconds == pytest.approx(0.065)
    assert report.row("paper (MATLAB), trajectory point").seconds == pytest.approx(0.009)


def test_table_and_json(report):
    text = report.format_table()
    for r in report.rows:
        assert r.name in text
    assert report.machine["cpu"] in text
    assert "verification failures in all: 0" in text
    md = report.format_markdown()
    assert md.count("\n|") >= len(report.rows) + 1
    data = json.loads(json.dumps(report.to_dict()))
    assert len(data["rows"]) == len(report.rows)
    assert {"cpu", "cores", "python", "numpy", "numba"} <= set(data["machine"])


def test_yardstick_is_the_forward_kinematics(robot):
    rng = np.random.default_rng(3)
    T_tool = robot.fk(np.array([0.1, -0.2, 0.3, 0.4, 0.5, 0.6]))
    other = robot.with_tool(T_tool).with_base(T_tool)
    for r in (robot, other):
        q = rng.uniform(-np.pi, np.pi, (50, 6))
        assert np.abs(numpy_fk(r, q) - r.fk(q)).max() < 1e-9
        assert np.abs(numpy_fk(r, q[0]) - r.fk(q[0])).max() < 1e-9


def test_verification_catches_wrong_and_missing_solutions(robot):
    rng = np.random.default_rng(4)
    Q = rng.uniform(-np.pi, np.pi, (20, 6))
    T = robot.fk(Q)
    q, valid = robot.ik_all_batch(T)
    assert _verify_all(robot, q, valid, T, Q) == 0
    bad = q.copy()
    bad[3, 0, 1] += 1e-6  # off the pose
    assert _verify_all(robot, bad, valid, T, Q) >= 1
    missing = valid.copy()
    hit = np.flatnonzero(_same_solution(q[5], Q[5][None]) & valid[5])[0]
    missing[5, hit] = False  # the known solution is dropped
    assert _verify_all(robot, q, missing, T, Q) == 1


def test_same_solution_at_a_straight_wrist():
    q = np.array([0.1, 0.2, 0.3, 0.5, 0.0, -0.2])
    split = q.copy()
    split[3], split[5] = 0.0, 0.3  # same q4 + q7
    assert _same_solution(split[None], q[None])[0]
    split[5] = 0.4
    assert not _same_solution(split[None], q[None])[0]


def test_startup_rows_run_the_cli():
    rows = _startup_rows(1)
    names = [r.name for r in rows]
    assert any(n.startswith("ik7r ik ... end to end") for n in names)
    assert any(n.startswith("JIT fallback: import numba") for n in names)
    assert any(n.startswith("warm: first ik_all after import ik7r") for n in names)
    assert any(n.startswith("warm, JIT fallback: first ik_all") for n in names)
    assert not any(n.startswith("cold, JIT fallback") for n in names)  # only when asked (it compiles)
    for r in rows:
        assert r.seconds > 0 and r.failures in (None, 0), r.name


def test_cli_bench_writes_json(tmp_path, capsys):
    out = tmp_path / "bench.json"
    code = main(["bench", "--quick", "--n", "200", "--no-startup", "--no-baselines", "--json", str(out)])
    assert code == 0
    data = json.loads(out.read_text())
    assert data["failures"] == 0
    assert any(r["name"].startswith("ik_all_batch") for r in data["rows"])
    assert "ik_all_batch" in capsys.readouterr().out


@pytest.mark.parametrize("args", [["--n", "0"], ["--big", "-1"], ["--nonsense"]])
def test_cli_bench_bad_input_exits_2(args, capsys):
    assert main(["bench", *args]) == 2
    assert "error" in capsys.readouterr().err


def test_big_chunked_row_runs_in_a_fresh_process(robot):
    from ik7r.bench.rows import _big_row

    row = _big_row(robot, 300, lambda t: t / 1e-6)
    assert row.failures == 0 and row.n == 300
    assert math.isfinite(row.seconds) and row.seconds > 0
    assert "peak RSS" in row.note
