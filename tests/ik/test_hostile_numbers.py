"""Hostile numbers (issue 12, item 6): huge, infinite and NaN seeds, huge joint limits, huge
angles in fk. No answer is returned or marked ok that misses the robot's tolerances; compiled
and pure-Python kernels give the same answers and the same errors.

Every returned solution is checked against ``dh_product`` (tests/helpers.py: the paper's eq. (1) and
Table 1 written with numpy, no ik7r code), counts of the multi-turn expansion against a brute
force over turns.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from helpers import SIMULATION1_Q_DEG, angle_distance, dh_product, pose_errors, wrap
from hypothesis import given, settings
from hypothesis import strategies as st

import ik7r
from ik7r.ik.solve import MAX_WITHIN_LIMITS_ROWS
from ik7r.robot.family import MAX_JOINT_ANGLE

Q_SIM1 = np.radians(SIMULATION1_Q_DEG)


def _reference_ok(robot, sols, T):
    """Every row of ``sols`` (M, 6) reproduces ``T`` by the independent eq. (1) product, to the
    robot's tolerances (plus the rounding of two different products, 1e-11 mm)."""
    sols = np.atleast_2d(sols)
    F = np.array([dh_product(s) for s in sols])
    dp, dr = pose_errors(F, np.broadcast_to(T, F.shape))
    return bool(np.all(dp <= robot.position_tolerance + 1e-11) and np.all(dr <= 1e-11))


@pytest.fixture(scope="module")
def T1(robot):
    return dh_product(Q_SIM1)


# ---------------------------------------------------------------- seeds are periodic
def test_path_seed_1e100_is_reduced_and_every_row_exact(robot, T1):
    res = robot.ik_path(np.stack([T1, T1]), 1, seed=np.full(6, 1e100))
    assert res.ok.all()
    assert _reference_ok(robot, res.q, T1)
    assert angle_distance(res.q, Q_SIM1).max() < 1e-9


@pytest.mark.parametrize("k", [1e2, 1e4, 1e5, 1e6, 1e12])
def test_path_seed_many_turns_away_gives_exact_rows(robot, T1, k):
    seed = Q_SIM1 + 2 * np.pi * k
    res = robot.ik_path(np.stack([T1, T1, T1]), 1, seed=seed)
    assert res.ok.all()
    assert _reference_ok(robot, res.q, T1)  # (rows near 2 pi k rad would be 7e-7 mm off)
    assert angle_distance(res.q, Q_SIM1).max() < 1e-9


def test_path_seed_within_the_joint_range_keeps_its_turn(robot, T1):
    """A seed inside +-MAX_JOINT_ANGLE is not reduced: the rows continue its turn."""
    seed = Q_SIM1 + 2 * np.pi * np.array([0, 0, 0, 3, 0, -2])
    res = robot.ik_path(np.stack([T1, T1]), 1, seed=seed)
    assert res.ok.all() and _reference_ok(robot, res.q, T1)
    np.testing.assert_allclose(res.q[0], seed, atol=1e-9)


@pytest.mark.parametrize("value", [1e300, -1e300, 1e17, 2 * np.pi * 1e6, -1e5])
def test_ik_huge_seed_answers_its_configuration(robot, T1, value):
    for config in range(1, 9):
        q = robot.ik(T1, config, seed=np.full(6, value))
        assert int(robot.config_of(q)) == config
        assert _reference_ok(robot, q, T1)
    q1 = robot.ik(T1, 1, seed=np.full(6, value))
    assert angle_distance(q1, Q_SIM1) < 1e-9
    sols = robot.ik_all(T1, seed=np.full(6, value))
    assert len(sols) == 8 and _reference_ok(robot, sols, T1)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.lists(st.floats(-1e300, 1e300, allow_nan=False, allow_infinity=False), min_size=6, max_size=6),
       st.integers(1, 8))
def test_any_finite_seed_is_the_seed_reduced_modulo_2pi(robot, T1, seed, config):
    """The documented rule: a joint beyond MAX_JOINT_ANGLE counts as its value in (-pi, pi]
    (reduced here with math.remainder, not ik7r's code); the answer is exact."""
    seed = np.array(seed)
    reduced = np.array([x if abs(x) <= MAX_JOINT_ANGLE else math.remainder(x, 2 * math.pi) for x in seed])
    q = robot.ik(T1, config, seed=seed)
    assert _reference_ok(robot, q, T1) and int(robot.config_of(q)) == config
    np.testing.assert_allclose(q, robot.ik(T1, config, seed=reduced), atol=1e-12)


def test_far_poses_have_no_solution_in_every_call(robot):
    irb = ik7r.load_robot("irb5400")
    for rob in (robot, irb):
        q_good = np.array([0.3, 0.2, -0.4, 0.5, 0.7, -0.7])
        good = rob.fk(q_good)
        for x in (1e300, 1e160, 1e20, 1e6):
            T = np.eye(4)
            T[:3, 3] = [x, -x / 3, x / 7]
            assert len(rob.ik_all(T)) == 0
            with pytest.raises(ik7r.UnreachableError, match="out of reach"):
                rob.ik(T, 1)
            q, ok = rob.ik_batch(np.stack([T, good]), int(rob.config_of(q_good)))
            assert ok.tolist() == [False, True] and np.isnan(q[0]).all()
            qa, valid = rob.ik_all_batch(np.stack([T, good]))
            assert not valid[0].any() and valid[1].any()
            assert rob.ik_path(np.stack([T, good]), 1).ok[0] == np.False_


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_single_seed_raises(robot, T1, bad):
    seed = np.zeros(6)
    seed[2] = bad
    for call in (lambda: robot.ik(T1, 1, seed=seed), lambda: robot.ik_all(T1, seed=seed),
                 lambda: robot.ik_path(np.stack([T1, T1]), 1, seed=seed),
                 lambda: robot.ik_batch(np.stack([T1, T1]), 1, seed=seed)):
        with pytest.raises(ValueError, match="seed must be finite"):
            call()


def test_paper_iteration_start_angle_periodic_or_refused(robot, T1):
    res = robot.ik_paper(T1, 1, theta5_start=1e300)
    assert res.ok and _reference_ok(robot, res.q, T1)
    for bad in (np.nan, np.inf):
        with pytest.raises(ValueError, match="theta5_start must be a finite"):
            robot.ik_paper(T1, 1, theta5_start=bad)


def test_batch_seeds_per_row_bad_rows_marked_rest_solved(robot, rng):
    Q = rng.uniform(robot.lower, robot.upper, (12, 6))
    T = np.array([dh_product(q) for q in Q])
    seeds = Q.copy()
    seeds[1, 0] = np.nan
    seeds[4, 3] = np.inf
    seeds[6, 5] = -np.inf
    seeds[7] = 1e300  # huge: reduced, the row is solved
    seeds[8] = Q[8] + 2 * np.pi * 1e7
    configs = robot.config_of(Q)
    for config in (1, 3):
        q, ok = robot.ik_batch(T, config, seed=seeds)
        bad = np.zeros(len(Q), dtype=bool)
        bad[[1, 4, 6]] = True
        assert not ok[bad].any() and np.isnan(q[bad]).all()
        for i in np.flatnonzero(~bad):
            try:
                single = robot.ik(T[i], config, seed=seeds[i])
            except ik7r.UnreachableError:
                assert not ok[i] and np.isnan(q[i]).all()
                continue
            assert ok[i] and _reference_ok(robot, q[i], T[i])
            np.testing.assert_allclose(q[i], single, atol=1e-12)
            if configs[i] == config and i != 7:  # the seed is the source (mod 2 pi)
                assert angle_distance(q[i], Q[i]) < 1e-7


def test_all_batch_bad_rows_marked_rest_solved(robot, rng):
    Q = rng.uniform(-np.pi, np.pi, (6, 6))
    T = np.array([dh_product(q) for q in Q])
    T[2, 0, 0] = np.nan
    T[4, 1, 3] = np.inf
    qa, valid = robot.ik_all_batch(T)
    assert not valid[[2, 4]].any() and np.isnan(qa[[2, 4]]).all()
    for i in (0, 1, 3, 5):
        sols = qa[i][valid[i]]
        assert _reference_ok(robot, sols, T[i])
        assert angle_distance(sols, Q[i]).min() < 1e-6


# ---------------------------------------------------------------- joint limits
def _brute_turn_count(sols, lower, upper):
    """Multi-turn equivalents inside the limits, by trying every turn in a wide range."""
    total = 0
    for s in sols:
        per_joint = [sum(1 for k in range(-40, 41) if lower[j] <= s[j] + 2 * np.pi * k <= upper[j])
                     for j in range(6)]
        total += int(np.prod(per_joint))
    return total


def test_limits_two_pi_every_multi_turn_row_no_cap(robot, T1):
    r = robot.replace(lower=np.full(6, -2 * np.pi), upper=np.full(6, 2 * np.pi))
    sols = r.ik_all(T1, within_limits=True)
    wrapped = r.ik_all(T1)
    assert len(wrapped) == 8
    assert len(sols) == _brute_turn_count(wrapped, r.lower, r.upper) == 576  # 8 x 2^6 turns... and a few 3s
    assert set(r.config_of(sols).tolist()) == set(range(1, 9))
    assert np.all(sols >= r.lower) and np.all(sols <= r.upper)
    assert _reference_ok(r, sols, T1)
    assert len(np.unique(np.round(sols, 9), axis=0)) == len(sols)


@pytest.mark.parametrize("limit", [1e4, 1e15, 1e300, np.inf])
def test_huge_limits_refused_with_the_usable_range(robot, limit):
    with pytest.raises(ValueError, match=r"finite and within \+-MAX_JOINT_ANGLE = 100 rad"):
        robot.replace(lower=np.full(6, -limit), upper=np.full(6, limit))


def test_largest_limits_expansion_too_big_raises_but_ik_answers(robot, T1):
    r = robot.replace(lower=np.full(6, -MAX_JOINT_ANGLE), upper=np.full(6, MAX_JOINT_ANGLE))
    with pytest.raises(ValueError, match="MAX_WITHIN_LIMITS_ROWS"):
        r.ik_all(T1, within_limits=True)
    # one solution nearest a seed: each joint's nearest turn, checked by brute force
    seed = np.array([90.0, -50.0, 3.0, 97.0, -99.0, 0.5])
    q = r.ik(T1, 1, seed=seed, within_limits=True)
    assert _reference_ok(r, q, T1)
    assert np.all(np.abs(q) <= MAX_JOINT_ANGLE)
    base = r.ik(T1, 1)
    turns = np.arange(-20, 21)
    for j in range(6):
        cands = base[j] + 2 * np.pi * turns
        cands = cands[np.abs(cands) <= MAX_JOINT_ANGLE]
        assert abs(q[j] - cands[np.argmin(np.abs(cands - seed[j]))]) < 1e-9


def test_moderate_limits_rows_sized_exactly(robot, T1):
    lo = -np.array([1, 2, 3, 4, 5, 6.5]) * np.pi
    r = robot.replace(lower=lo, upper=-lo)
    sols = r.ik_all(T1, within_limits=True)
    n = _brute_turn_count(r.ik_all(T1), r.lower, r.upper)
    assert n <= MAX_WITHIN_LIMITS_ROWS and len(sols) == n
    assert _reference_ok(r, sols, T1)
    assert np.all(sols >= r.lower) and np.all(sols <= r.upper)
    assert len(np.unique(np.round(sols, 9), axis=0)) == len(sols)
    for rows in (sols, robot.replace(lower=np.full(6, -2 * np.pi), upper=np.full(6, 2 * np.pi))
                 .ik_all(T1, within_limits=True)):  # (beyond and within the one-call expansion)
        keys = tuple(rows[:, j] for j in range(5, -1, -1)) + (r.config_of(rows),)
        assert np.array_equal(np.lexsort(keys), np.arange(len(rows)))
    path = r.ik_path(np.stack([T1, T1]), 2, seed=np.full(6, 7.0), within_limits=True)
    assert path.ok.all() and _reference_ok(r, path.q, T1)


# ---------------------------------------------------------------- fk of huge angles
@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.lists(st.floats(-1e300, 1e300, allow_nan=False), min_size=6, max_size=6))
def test_fk_of_huge_angles_matches_the_reference(robot, q):
    """fk is periodic: it evaluates the angle as given (the C library reduces it exactly)."""
    q = np.array(q)
    dp, dr = pose_errors(robot.fk(q), dh_product(q))
    assert dp < 1e-9 and dr < 1e-12


def test_fk_of_non_finite_angles_raises(robot):
    for bad in (np.nan, np.inf):
        with pytest.raises(ValueError, match="finite"):
            robot.fk([0, 0, bad, 0, 0, 0])


# ---------------------------------------------------------------- compiled == pure Python
_CASES = r'''
import json, sys
import numpy as np
import ik7r
from ik7r.robot.files import robot_from_toml

robot = ik7r.load_robot()
q0 = np.radians([60, 60, 0, -30, 60, 30])
T = robot.fk(q0)
toml = open(ik7r.__path__[0] + "/robot/data/paper.toml").read()
out = {}

def case(name, fn):
    try:
        val = fn()
        if isinstance(val, tuple):
            val = [np.asarray(v, dtype=float).tolist() for v in val]
        else:
            val = np.asarray(val, dtype=float).tolist()
        out[name] = {"value": val}
    except Exception as exc:
        out[name] = {"error": type(exc).__name__, "message": str(exc)}

def path(seed, limits=False):
    r = robot.ik_path(np.stack([T, T]), 1, seed=seed, within_limits=limits)
    return r.q, r.ok

case("path_1e100", lambda: path(np.full(6, 1e100)))
for k in (1e4, 1e5, 1e6):
    case(f"path_k{k:g}", lambda k=k: path(q0 + 2 * np.pi * k))
case("ik_1e300", lambda: robot.ik(T, 1, seed=np.full(6, 1e300)))
case("ik_all_1e300", lambda: robot.ik_all(T, seed=np.full(6, -1e300)))
r2 = robot.replace(lower=np.full(6, -2 * np.pi), upper=np.full(6, 2 * np.pi))
case("limits_2pi", lambda: r2.ik_all(T, within_limits=True))
case("limits_2pi_ik", lambda: r2.ik(T, 6, seed=np.full(6, 5.0), within_limits=True))
case("limits_1e4", lambda: robot.replace(lower=np.full(6, -1e4), upper=np.full(6, 1e4)))
case("limits_1e15", lambda: robot.replace(lower=np.full(6, -1e15), upper=np.full(6, 1e15)))
r100 = robot.replace(lower=np.full(6, -100.0), upper=np.full(6, 100.0))
case("limits_100_all", lambda: r100.ik_all(T, within_limits=True))
case("limits_100_ik", lambda: r100.ik(T, 3, seed=np.full(6, 50.0), within_limits=True))
seeds = np.tile(q0, (4, 1)); seeds[1, 2] = np.nan; seeds[2] = 1e300; seeds[3, 0] = np.inf
case("batch_seeds", lambda: robot.ik_batch(np.stack([T] * 4), 1, seed=seeds))
case("batch_nan_seed", lambda: robot.ik_batch(np.stack([T] * 2), 1, seed=np.full(6, np.nan)))
case("fk_huge", lambda: robot.fk(np.array([[1e300, -1e200, 1e17, 6.3e6, 1e5, -2e5]])))
neg = toml.replace("a = [0, 0, 1000, 0, 0, 0, 0]", "a = [0, 0, -1000, 0, 0, 0, 0]")
case("negative_a2", lambda: robot_from_toml(neg).ik_all(robot_from_toml(neg).fk(q0)))
off = toml.replace("theta_offset = [0, 0, 0, 0, 0, 0, 0]", "theta_offset = [1e6, 0, 0, 1e300, 0, 0, 0]")
case("offset_1e6", lambda: robot_from_toml(off).ik_all(robot_from_toml(off).fk(q0)))
zero = toml.replace("a = [0, 0, 1000, 0, 0, 0, 0]", "a = [0, 0, 0, 0, 0, 0, 0]").replace(
    "d = [0, 0, 0, 900, 80, 80, 100]", "d = [0, 0, 0, 0, 0, 0, 0]")
case("zero_lengths", lambda: robot_from_toml(zero))
tiny = toml.replace("a = [0, 0, 1000, 0, 0, 0, 0]", "a = [0, 0, 1e-300, 0, 0, 0, 0]").replace(
    "d = [0, 0, 0, 900, 80, 80, 100]", "d = [0, 0, 0, 9e-301, 8e-302, 8e-302, 1e-301]")
case("tiny_lengths", lambda: robot_from_toml(tiny))
huge = toml.replace("a = [0, 0, 1000, 0, 0, 0, 0]", "a = [0, 0, 1e150, 0, 0, 0, 0]")
case("huge_lengths", lambda: robot_from_toml(huge))
# the singular-set examples of the issue's table (their completeness is item 1-5's; the two
# kernels must agree on them whatever they return)
irb = ik7r.load_robot("irb5400")
near_straight = [-0.659004369746492, 0.7831767594282759, 1.5705360987753219, -0.4800544631529009,
                 -1.1081977877580584e-06, 1.339136679393956]
case("paper_near_straight", lambda: robot.ik_all(robot.fk(near_straight)))
irb_q = [-2.7577578594390535, 1.742793594342996, 1.5876657076955594, 1.2817145857958927,
         -0.38076226367690147, 2.440234785047836]
case("irb_uniform", lambda: irb.ik_all(irb.fk(irb_q)))
case("irb_straight", lambda: irb.ik_all(irb.fk([0.3, 0.2, -0.4, 0.5, 0.0, -0.7])))
case("paper_elbow_stretched", lambda: robot.ik_all(robot.fk([0.4, 0.3, np.pi / 2, 0.2, 0.9, -0.3])))
case("paper_shoulder", lambda: robot.ik_all(robot.fk([0.0, 1.5707963267341256, 1.5707963267341256, 0, 0, 0])))
from ik7r.robot.model import Robot
flipped = Robot(name="flipped", dh=np.array([
    [0, 0, -300, 0.3], [-150, -np.pi / 2, 40, -1.0], [-1100, 0, -90, 2.5], [-120, -np.pi / 2, -1000, 0.7],
    [0, np.radians(30), -90, 0.4], [0, np.radians(-60), -90, -0.9], [0, np.radians(30), -110, 1.2]]),
    joint_sign=[-1, 1, -1, 1, -1, -1, 1], coupling=(-1.0, -0.5))
qf = [0.4, -0.3, 1.1, 2.0, -0.8, 0.6]
case("all_signs_flipped", lambda: flipped.ik_all(flipped.fk(qf)))
far = np.eye(4); far[:3, 3] = [1e300, -1e299, 1e298]
case("far_ik_all", lambda: robot.ik_all(far))
case("far_ik", lambda: robot.ik(far, 1))
json.dump(out, sys.stdout)
'''


def _run_cases(jit: str) -> dict:
    env = dict(os.environ, IK7R_JIT=jit)
    proc = subprocess.run([sys.executable, "-c", _CASES], capture_output=True, text=True, env=env,
                          timeout=900)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def test_compiled_and_pure_python_agree_on_every_case(robot):
    compiled = _run_cases("1")
    plain = _run_cases("0")
    assert compiled.keys() == plain.keys()
    for name in compiled:
        a, b = compiled[name], plain[name]
        assert a.keys() == b.keys(), (name, a, b)
        if "error" in a:
            assert (a["error"], a["message"]) == (b["error"], b["message"]), name
            continue
        va, vb = a["value"], b["value"]
        if isinstance(va, list) and va and isinstance(va[0], list) and name in ("path_1e100", "batch_seeds") \
                or name.startswith("path_k"):
            pairs = list(zip(va, vb))
        else:
            pairs = [(va, vb)]
        for x, y in pairs:
            x, y = np.array(x, dtype=float), np.array(y, dtype=float)
            assert x.shape == y.shape, name
            np.testing.assert_allclose(x, y, atol=1e-9, rtol=0, err_msg=name)
    # and the answers themselves are right
    expect_errors = {"limits_1e4": "ValueError", "limits_1e15": "ValueError", "limits_100_all": "ValueError",
                     "batch_nan_seed": "ValueError", "zero_lengths": "FamilyError",
                     "tiny_lengths": "FamilyError", "huge_lengths": "FamilyError"}
    for name, err in expect_errors.items():
        assert compiled[name].get("error") == err, (name, compiled[name])
    T1 = dh_product(Q_SIM1)
    for name in ("path_1e100", "path_k10000", "path_k100000", "path_k1e+06"):
        q, ok = (np.array(v) for v in compiled[name]["value"])
        assert ok.all() and _reference_ok(robot, q, T1), name
    assert len(compiled["limits_2pi"]["value"]) == 576
    q, ok = (np.array(v) for v in compiled["batch_seeds"]["value"])
    assert ok.tolist() == [True, False, True, False]
    assert _reference_ok(robot, q[[0, 2]], T1)
    for name in ("negative_a2", "offset_1e6"):  # the source is among the solutions of its own pose
        assert angle_distance(np.array(compiled[name]["value"]), Q_SIM1).min() < 1e-9, name
    assert angle_distance(np.array(compiled["all_signs_flipped"]["value"]),
                          np.array([0.4, -0.3, 1.1, 2.0, -0.8, 0.6])).min() < 1e-9
    assert wrap(np.array(compiled["ik_1e300"]["value"]) - Q_SIM1).max() < 1e-9
