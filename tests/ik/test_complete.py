"""Issue 3: every solution, certified; singular cases; limits; batch; numeric baselines."""

import numpy as np
import pytest
from helpers import angle_distance, dh_product, pose_errors, random_full_q, random_usable_q, wrap
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import count_solutions

import ik7r
from ik7r.ik.numeric import damped_least_squares, manipulability, newton_raphson


def _check_exact_and_distinct(sols, T):
    assert sols.ndim == 2 and sols.shape[1] == 6
    assert np.all((sols > -np.pi) & (sols <= np.pi))
    F = np.array([dh_product(s) for s in sols]).reshape(-1, 4, 4)
    dp, dr = pose_errors(F, T)
    assert np.all(dp < 1e-9), dp.max()
    assert np.all(dr < 1e-12), dr.max()
    for i in range(len(sols)):
        for j in range(i):
            assert angle_distance(sols[i], sols[j]) > 1e-6, "duplicate solutions"


@pytest.mark.parametrize("workspace", ["full", "usable"])
def test_every_solution_found_none_extra(robot, workspace):
    """Against the brute-force reference (dense theta5 sampling, written without ik7r)."""
    rng = np.random.default_rng(11 if workspace == "full" else 12)
    Q = random_full_q(rng, 400) if workspace == "full" else random_usable_q(rng, robot, 400)
    checked, counts = 0, {}
    for q in Q:
        T = dh_product(q)
        sols = robot.ik_all(T)
        _check_exact_and_distinct(sols, T)
        assert angle_distance(sols, q).min() < 1e-7, "the pose's own joints are missing"
        expected, ambiguous = count_solutions(T)
        if ambiguous:
            continue
        assert len(sols) == expected, np.degrees(q)
        checked += 1
        counts[len(sols)] = counts.get(len(sols), 0) + 1
    assert checked >= 340, f"only {checked} of 400 poses had an unambiguous reference"
    assert max(counts) <= ik7r.MAX_SOLUTIONS
    if workspace == "full":
        assert max(counts) > 8, "expected some poses with more than eight solutions"


def test_batch_equals_single(robot, rng):
    Q = random_full_q(rng, 60)
    T = robot.fk(Q)
    qa, valid = robot.ik_all_batch(T)
    assert qa.shape == (60, ik7r.MAX_SOLUTIONS, 6) and valid.shape == (60, ik7r.MAX_SOLUTIONS)
    for i in range(60):
        single = robot.ik_all(T[i])
        batch = qa[i][valid[i]]
        assert len(batch) == len(single)
        for s in single:
            assert angle_distance(batch, s).min() < 1e-9
        assert np.all(np.isnan(qa[i][~valid[i]]))


def test_batch_marks_bad_rows_and_solves_the_rest(robot, rng):
    Q = random_usable_q(rng, robot, 6)
    T = robot.fk(Q)
    T[1, 0, 0] = np.nan                      # NaN
    T[2, :3, :3] *= 1.01                      # not orthonormal
    T[3, :3, 3] = [9000.0, 0.0, 0.0]          # out of reach
    q, ok = robot.ik_batch(T, 1)
    assert q.shape == (6, 6) and ok.dtype == bool
    assert not ok[1] and not ok[2] and not ok[3]
    assert np.all(np.isnan(q[~ok]))
    for i in np.flatnonzero(ok):
        assert robot.config_of(q[i]) == 1 or abs(np.sin(q[i, 4])) < 1e-9
        dp, dr = pose_errors(dh_product(q[i]), T[i])
        assert dp < 1e-9 and dr < 1e-12
    qa, valid = robot.ik_all_batch(T)
    assert not valid[[1, 2, 3]].any()
    for i in (0, 4, 5):
        assert valid[i].sum() >= 1 and angle_distance(qa[i][valid[i]], Q[i]).min() < 1e-7


def test_ik_batch_per_config_matches_ik(robot, rng):
    Q = random_usable_q(rng, robot, 30)
    T = robot.fk(Q)
    for config in (1, 4, 6):
        q, ok = robot.ik_batch(T, config)
        for i in range(30):
            try:
                single = robot.ik(T[i], config)
            except ik7r.UnreachableError:
                assert not ok[i]
                continue
            assert ok[i] and angle_distance(q[i], single) < 1e-9


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.lists(st.floats(-np.pi, np.pi, allow_nan=False), min_size=6, max_size=6))
def test_round_trip_every_solution_exact(robot, q):
    q = np.array(q)
    T = robot.fk(q)
    sols = robot.ik_all(T)
    assert 1 <= len(sols) <= ik7r.MAX_SOLUTIONS
    _check_exact_and_distinct(sols, T)
    if abs(q[4]) < 1e-6:  # (nearly) straight wrist: only q4 + q7 is defined to FK precision
        d = np.abs(wrap(sols[:, [0, 1, 2]] - q[[0, 1, 2]])).max(axis=1)
        d = np.maximum(d, np.abs(wrap(sols[:, 3] + sols[:, 5] - q[3] - q[5])))
        assert d.min() < 1e-6
    else:
        assert angle_distance(sols, q).min() < 1e-6


def test_several_solutions_share_indicators_nearest_seed(robot):
    """Poses with 12 or 16 solutions: ik returns the one nearest the seed."""
    rng = np.random.default_rng(3)
    found = 0
    for q in random_full_q(rng, 400):
        T = robot.fk(q)
        sols = robot.ik_all(T)
        if len(sols) <= 8:
            continue
        cfg = robot.config_of(sols)
        values, n = np.unique(cfg, return_counts=True)
        shared = values[n > 1][0]
        group = sols[cfg == shared]
        for member in group:
            got = robot.ik(T, int(shared), seed=member + 0.01)
            assert angle_distance(got, member) < 1e-9
        # without a seed: the documented choice, nearest the zero posture
        d0 = np.linalg.norm(wrap(group), axis=1)
        assert angle_distance(robot.ik(T, int(shared)), group[np.argmin(d0)]) < 1e-9
        found += 1
        if found == 3:
            break
    assert found == 3


# ---------------------------------------------------------------- singular cases
def test_straight_wrist_theta5_zero(robot):
    q = np.radians([60, -30, 60, -30, 0, 30])  # the paper's singular configuration 1
    T = robot.fk(q)
    sols = robot.ik_all(T)
    _check_exact_and_distinct(sols, T)
    straight = sols[np.abs(sols[:, 4]) < 1e-12]
    assert len(straight) >= 1
    # the default split puts theta4 = 0; the sum theta4 + theta7 (mirror: theta4 + theta7) is kept
    assert np.any(np.abs(straight[:, 3]) < 1e-12)
    # with a seed the split follows it
    s = robot.ik(T, robot.config_of(q).item(), seed=q)
    assert angle_distance(s, q) < 1e-9
    assert not np.any(np.isnan(sols))


def test_folded_wrist_theta5_pi_returned_once(robot):
    q = np.radians([60, -30, 60, -30, 180, 30])  # the paper's singular configuration 2
    T = robot.fk(q)
    sols = robot.ik_all(T)
    _check_exact_and_distinct(sols, T)
    folded = sols[np.pi - np.abs(sols[:, 4]) < 1e-6]
    assert len(folded) >= 1
    assert angle_distance(folded, q).min() < 1e-9
    # both Wrist indicators name the folded solution
    arm, elbow, _ = robot.indicators(q)
    a = robot.ik(T, (int(arm), int(elbow), 1), seed=q)
    b = robot.ik(T, (int(arm), int(elbow), 0), seed=q)
    assert angle_distance(a, b) < 1e-12


def test_folded_wrist_no_near_duplicates(robot):
    """Near theta5 = pi the FK is flat in theta5: nearly folded shadows must merge into one."""
    rng = np.random.default_rng(21)
    for _ in range(150):
        q = random_full_q(rng, 1)[0]
        q[4] = np.pi * rng.choice([-1, 1])
        T = robot.fk(q)
        sols = robot.ik_all(T)
        _check_exact_and_distinct(sols, T)
        near = np.abs(wrap(sols[:, None, :] - sols[None, :, :])).max(axis=-1) + np.eye(len(sols))
        assert near.min() > 1e-4, "near-duplicate solutions at a folded wrist"
        assert angle_distance(sols, q).min() < 1e-9


def test_shoulder_singularity_theta1_from_seed(robot):
    # the virtual wrist centre on axis 1: choose q2, q3 to put it there
    q = np.radians([25.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    rng = np.random.default_rng(0)
    # find q2, q3 for which the wrist centre lies on the z axis: the arm folded over the top
    for t2 in np.radians(np.arange(-179, 180, 1.0)):
        q[1] = t2
        F = robot.frames(q)
        if np.hypot(*F[4][:2, 3]) < 1.0:
            break
    q[3:] = rng.uniform(-1, 1, 3)
    q[4] = 0.7
    T = robot.fk(q)
    sols = robot.ik_all(T, seed=q)
    _check_exact_and_distinct(sols, T)
    assert angle_distance(sols, q).min() < 1e-6


def test_elbow_stretched(robot):
    q = np.radians([10.0, 40.0, 90.0, 20.0, 50.0, -10.0])  # theta3 = 90 deg: arm fully stretched
    T = robot.fk(q)
    sols = robot.ik_all(T)
    _check_exact_and_distinct(sols, T)
    assert angle_distance(sols, q).min() < 1e-6


def test_unreachable_gives_empty_set(robot):
    T = np.eye(4)
    T[:3, 3] = [0.0, 0.0, 4000.0]
    assert robot.ik_all(T).shape == (0, 6)
    with pytest.raises(ik7r.UnreachableError):
        robot.ik(T, 3)


def test_missing_configuration_message_lists_available(robot):
    rng = np.random.default_rng(8)
    for q in random_full_q(rng, 200):
        T = robot.fk(q)
        have = set(robot.config_of(robot.ik_all(T)).tolist())
        missing = sorted(set(range(1, 9)) - have)
        if missing:
            with pytest.raises(ik7r.UnreachableError, match="in configurations"):
                robot.ik(T, missing[0])
            return
    pytest.fail("no pose with a missing configuration found")


# ---------------------------------------------------------------- limits and multi-turn joints
def test_within_limits_expands_multi_turn_joints(robot, rng):
    Q = random_usable_q(rng, robot, 40)
    for q in Q:
        T = robot.fk(q)
        sols = robot.ik_all(T, within_limits=True)
        assert np.all(sols >= robot.lower - 1e-12) and np.all(sols <= robot.upper + 1e-12)
        # the original joints (not wrapped) are among them
        assert np.abs(sols - q).max(axis=1).min() < 1e-7
        F = robot.fk(sols)
        dp, dr = pose_errors(F, T)
        assert np.all(dp < 1e-9) and np.all(dr < 1e-12)
        # every wrapped in-limit solution appears with all its 2 pi shifts of q4 and q7
        n_all = len(robot.ik_all(T))
        assert len(sols) >= 1 and len(sols) <= 4 * n_all


def test_ik_within_limits_nearest_seed(robot, rng):
    q = random_usable_q(rng, robot, 1)[0]
    q[3] = np.radians(300.0)  # beyond pi: only the multi-turn expansion reaches it
    T = robot.fk(q)
    cfg = int(robot.config_of(q))
    got = robot.ik(T, cfg, seed=q, within_limits=True)
    assert np.abs(got - q).max() < 1e-7
    assert np.all(got >= robot.lower) and np.all(got <= robot.upper)


def test_outside_limits_raises(robot):
    q = np.radians([100.0, 0.0, 0.0, 0.0, 30.0, 0.0])  # q1 beyond the 70 deg limit
    T = robot.fk(q)
    sols = robot.ik_all(T, within_limits=True)
    assert np.all(sols >= robot.lower - 1e-12) and np.all(sols <= robot.upper + 1e-12)
    cfg = int(robot.config_of(q))
    if not np.any(robot.config_of(sols) == cfg):
        with pytest.raises(ik7r.UnreachableError, match="within the joint limits"):
            robot.ik(T, cfg, within_limits=True)


# ---------------------------------------------------------------- baselines
def test_newton_raphson_converges_from_near(robot):
    q = np.radians([60, 60, 0, -30, 60, 30])
    T = robot.fk(q)
    res = newton_raphson(robot, T, np.radians([60, 60, 0, -30, 30, 30]))
    assert res.ok and res.q is not None
    dp, dr = pose_errors(dh_product(res.q), T)
    assert dp < 1e-9 and dr < 1e-12


def test_newton_raphson_fails_honestly_on_singular_jacobian(robot):
    T = robot.fk(np.radians([60, 60, 0, -30, 60, 30]))
    start = np.radians([0, 60, 0, -30, 0, 30])  # the paper's failing start: theta5 = 0
    regular = np.radians([0, 60, 0, -30, 30, 30])
    assert abs(manipulability(robot, start)) < 1e-6 * abs(manipulability(robot, regular))
    res = newton_raphson(robot, T, start)
    assert not res.ok and res.q is None
    assert "singular" in res.reason


def test_damped_least_squares_converges(robot, rng):
    for q in random_usable_q(rng, robot, 5):
        T = robot.fk(q)
        res = damped_least_squares(robot, T, q + rng.normal(0, 0.1, 6))
        if res.ok:
            dp, dr = pose_errors(dh_product(res.q), T)
            assert dp < 1e-9 and dr < 1e-12
        else:
            assert res.q is None and res.reason


def test_manipulability_vanishes_at_singular_wrist(robot):
    w_sing = manipulability(robot, np.radians([60, -30, 60, -30, 0, 30]))
    w_pi = manipulability(robot, np.radians([60, -30, 60, -30, 180, 30]))
    w_reg = manipulability(robot, np.radians([60, -30, 60, -30, 60, 30]))
    assert abs(w_sing) < 1e-9 * abs(w_reg) and abs(w_pi) < 1e-9 * abs(w_reg)


def test_wrist_twist_of_45_deg_complete():
    """At 45 deg the fully bent wrist's virtual centre is at infinity: still every solution."""
    dh = np.array(ik7r.load_robot().dh)
    b = np.radians(45.0)
    dh[4:7, 1] = [-b, 2 * b, -b]
    r45 = ik7r.load_robot().replace(dh=dh)
    rng = np.random.default_rng(45)
    for q in random_full_q(rng, 300):
        T = r45.fk(q)
        sols = r45.ik_all(T)
        F = r45.fk(sols)
        assert np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1).max() < 1e-9
        assert angle_distance(sols, q).min() < 1e-7, q.tolist()


@pytest.mark.parametrize("name", ["paper", "irb5400"])
def test_ik_per_configuration_agrees_with_ik_all(name):
    """ik / ik_batch search one configuration only: same answer as picking from ik_all."""
    r = ik7r.load_robot(name)
    rng = np.random.default_rng(31)
    Q = rng.uniform(r.lower, r.upper, (60, 6))
    T = r.fk(Q)
    for config in range(1, 9):
        qb, ok = r.ik_batch(T, config)
        for i in range(len(Q)):
            sols = r.ik_all(T[i])
            c = r.config_of(sols)
            folded = np.pi - np.abs(sols[:, 4]) < 1e-9
            arm_elbow = (c - 1) // 2 == (config - 1) // 2
            pool = sols[(c == config) | (folded & arm_elbow)]
            if len(pool) == 0:
                assert not ok[i]
                with pytest.raises(ik7r.UnreachableError):
                    r.ik(T[i], config)
                continue
            best = pool[np.argmin(np.linalg.norm(wrap(pool), axis=1))]
            assert ok[i]
            assert angle_distance(qb[i], best) < 1e-7
            assert angle_distance(r.ik(T[i], config), best) < 1e-7
