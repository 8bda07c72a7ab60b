"""The kernels compiled ahead of time (ik7r._kernels.aot): built by the installation, used by the
public API without importing numba, never when stale, and bit for bit the JIT's answers."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys

import numpy as np
import pytest

import ik7r
from ik7r._kernels import aot
from ik7r._kernels import fk as jit_fk
from ik7r._kernels import select as jit_select
from ik7r._kernels import track as jit_track
from ik7r._kernels import validate as jit_validate
from ik7r._kernels.bernstein import bernstein_tables
from ik7r.geometry.checks import ORTHONORMAL_TOL

MAX_SOLUTIONS = ik7r.MAX_SOLUTIONS


def _compiled():
    module = aot.load()
    if module is None:
        if shutil.which("cc") is None and shutil.which("gcc") is None:
            pytest.skip("no C compiler: the compiled module cannot be built here (the JIT compiles)")
        pytest.fail("the compiled module is not built or stale: run `make` (python -m ik7r._kernels.aot)")
    return module


def _joints(rng, n):
    """Random joints plus the special postures: straight wrist (q5 = 0), fully bent (q5 = pi),
    q1 and q3 on their indicator boundaries (+-pi/2), the zero posture."""
    q = rng.uniform(-math.pi, math.pi, (n, 6))
    q[: n // 8, 4] = 0.0
    q[n // 8: n // 4, 4] = math.pi
    q[n // 4: n // 4 + n // 16, 0] = math.pi / 2
    q[n // 4 + n // 16: n // 4 + n // 8, 2] = -math.pi / 2
    q[-1] = 0.0
    return q


@pytest.fixture(scope="module", params=[None, "irb5400"], ids=["paper", "irb5400"])
def case(request):
    robot = ik7r.load_robot(request.param)
    Q = _joints(np.random.default_rng(20261201), 160)
    return robot, Q, robot.fk(Q)


def test_the_public_api_answers_without_importing_numba():
    _compiled()
    script = """
import sys
import numpy as np
import ik7r
r = ik7r.load_robot()
q = np.random.default_rng(1).uniform(-3, 3, (300, 6))
T = r.fk(q)
r.ik_all(T[0]); r.ik(T[1], r.config_of(q[1])); r.ik_all(T[2], within_limits=True)
r.ik_batch(T, 1); r.ik_all_batch(T); r.frames(q[:3])
r.ik_path(r.fk(np.linspace(q[0], q[0] + 0.01, 20)), int(r.config_of(q[0])), seed=q[0])
print("numba" in sys.modules)
"""
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "False"


def test_a_stale_or_disabled_module_is_not_used(tmp_path, monkeypatch):
    record = aot.info() or {"stamp": "x"}
    stale = tmp_path / "stamp.json"
    stale.write_text(json.dumps({**record, "stamp": "0" * 64}))
    monkeypatch.setattr(aot, "STAMP_FILE", stale)
    monkeypatch.setattr(aot, "_LOADED", [])
    assert aot.load() is None
    monkeypatch.setattr(aot, "STAMP_FILE", tmp_path / "missing.json")
    monkeypatch.setattr(aot, "_LOADED", [])
    assert aot.load() is None
    if record.get("stamp") == aot.source_stamp():  # the real stamp, but turned off
        monkeypatch.setattr(aot, "STAMP_FILE", aot.HERE / f"{aot.MODULE}.json")
        monkeypatch.setattr(aot, "_LOADED", [])
        monkeypatch.setenv("IK7R_AOT", "0")
        assert aot.load() is None


def test_the_stamp_follows_every_kernel_source():
    assert "complete.py" in aot.SOURCES and "select.py" in aot.SOURCES and "../robot/family.py" in aot.SOURCES
    for name in aot.SOURCES:
        assert (aot.HERE / name).is_file(), name


def test_the_solver_is_compiled_once_for_every_entry_point():
    # numba types a read-only array apart: entry points that hand the solver arrays typed
    # differently compile it (and every kernel below it) once each, 35-60 CPU s of the build each
    _compiled()
    assert aot.info().get("solver_compiles") == 1, aot.info()


def test_read_only_input_gives_the_same_answers(case):
    # the compiled entry points are typed for the writable arrays the API usually passes; a
    # read-only pose (an array the API passes on as it is) is read the same
    _compiled()
    robot, Q, T = case
    T = T[:24]
    frozen = T.copy()
    frozen.setflags(write=False)
    for a, b in zip(robot.ik_all_batch(T), robot.ik_all_batch(frozen)):
        assert np.array_equal(a, b, equal_nan=True)
    for a, b in zip(robot.ik_batch(T, 5), robot.ik_batch(frozen, 5)):
        assert np.array_equal(a, b, equal_nan=True)
    for i in range(0, 24, 4):
        assert np.array_equal(robot.ik_all(T[i]), robot.ik_all(frozen[i]))
    q = Q[:24].copy()
    q.setflags(write=False)
    assert np.array_equal(robot.fk(q), robot.fk(Q[:24]))


def test_fk_and_pose_checks_are_bit_identical(case):
    C = _compiled()
    robot, Q, T = case
    K = robot.kernel_params
    a, b = np.empty((len(Q), 4, 4)), np.empty((len(Q), 4, 4))
    jit_fk.fk_batch(Q, K, a)
    C.fk_batch(Q, K, b)
    assert np.array_equal(a, b)
    fa, fb = np.empty((3, 9, 4, 4)), np.empty((3, 9, 4, 4))
    jit_fk.frames_batch(Q[:3], K, fa)
    C.frames_batch(Q[:3], K, fb)
    assert np.array_equal(fa, fb)
    bad = T.copy()
    bad[::7, 0, 0] += 0.1  # not orthonormal
    bad[3, 2, 3] = np.nan
    ca, cb = np.empty_like(bad), np.empty_like(bad)
    codes_a, codes_b = np.empty(len(bad), np.int8), np.empty(len(bad), np.int8)
    assert jit_validate.validate_poses(bad, ORTHONORMAL_TOL, ca, codes_a) == C.validate_poses(
        bad, ORTHONORMAL_TOL, cb, codes_b) > 0
    assert np.array_equal(codes_a, codes_b) and np.array_equal(ca[codes_a == 0], cb[codes_b == 0])


def test_single_pose_solvers_are_bit_identical(case):
    C = _compiled()
    robot, Q, T = case
    K = robot.kernel_params
    Bm, bnorm = bernstein_tables(K)
    rows = 64 * MAX_SOLUTIONS
    compared = 0
    for i in range(len(T)):
        hint, has = (Q[(i + 1) % len(Q)], True) if i % 3 == 0 else (np.zeros(6), False)
        limits = i % 5 == 0
        got = []
        for f in (jit_select.ik_all_one, C.ik_all_one):
            sols, out = np.full((MAX_SOLUTIONS, 6), 7.0), np.full((rows, 6), 7.0)
            n, total = f(T[i], ORTHONORMAL_TOL, K, Bm, bnorm, hint, has, limits, sols, out)
            got.append((n, total, sols[:max(n, 0)], out[:total] if limits else None))
        (na, ta, sa, oa), (nb, tb, sb, ob) = got
        assert (na, ta) == (nb, tb) and na > 0
        assert np.array_equal(sa, sb) and (oa is None or np.array_equal(oa, ob))
        arm, elbow, wrist = 1 - (i % 2), 1 - (i // 2 % 2), 1 - (i // 4 % 2)
        got = []
        for f in (jit_select.ik_one, C.ik_one):
            sols, q = np.full((MAX_SOLUTIONS, 6), 7.0), np.full(6, 7.0)
            n, found = f(T[i], ORTHONORMAL_TOL, K, Bm, bnorm, arm, elbow, wrist, hint, has, limits, sols, q)
            got.append((n, found, q if found else None))
        assert got[0][:2] == got[1][:2]
        assert (got[0][2] is None) or np.array_equal(got[0][2], got[1][2])
        compared += na
    assert compared > 4 * len(T)


def test_batch_solvers_and_paths_are_bit_identical(case):
    C = _compiled()
    robot, Q, T = case
    K = robot.kernel_params
    Bm, bnorm = bernstein_tables(K)
    n = len(T)
    ok_in = np.ones(n, bool)
    ok_in[5] = False
    outs = []
    for f in (jit_select.all_rows, C.all_rows):
        out, counts = np.empty((n, MAX_SOLUTIONS, 6)), np.empty(n, np.int64)
        f(T, K, Bm, bnorm, ok_in, out, counts)
        outs.append((out, counts))
    assert np.array_equal(outs[0][1], outs[1][1]) and outs[0][1][5] == 0
    assert np.array_equal(outs[0][0], outs[1][0], equal_nan=True)
    seeds = np.ascontiguousarray(Q + 0.01)
    outs = []
    for f in (jit_select.config_rows, C.config_rows):
        q, ok = np.empty((n, 6)), np.empty(n, bool)
        f(T, K, Bm, bnorm, 1, 0, 1, seeds, True, False, ok_in, q, ok)
        outs.append((q, ok))
    assert np.array_equal(outs[0][1], outs[1][1]) and outs[0][1].sum() > 0
    assert np.array_equal(outs[0][0], outs[1][0], equal_nan=True)
    # a path: small steps from the first posture, then a jump the complete solver takes
    Qp = np.linspace(Q[1], Q[1] + 0.2, 40)
    Qp[30:] = Q[2]
    Tp = robot.fk(Qp)
    arm, elbow, wrist = (int(x) for x in robot.indicators(Qp[0]))
    outs = []
    for f in (jit_track.track_path, C.track_path):
        q, ok, tracked = np.empty((40, 6)), np.empty(40, bool), np.empty(40, bool)
        m = f(Tp, K, Bm, bnorm, arm, elbow, wrist, Qp[0], True, False, 0.5, np.ones(40, bool), q, ok, tracked)
        outs.append((m, q, ok, tracked))
    assert outs[0][0] == outs[1][0]
    for x, y in zip(outs[0][1:], outs[1][1:]):
        assert np.array_equal(x, y, equal_nan=True)
    assert outs[0][2][:30].all()
