"""Warm-started path IK (robot.ik_path): exact rows, kept configuration, continuity, reports."""

import numpy as np
import pytest
from helpers import dh_product, pose_errors

import ik7r


def _path(robot, n=400):
    t = np.linspace(0.0, 1.0, n)[:, None]
    q0 = np.radians([10, 40, -20, 30, 50, -40])
    Q = q0 + t * np.array([0.5, 0.3, -0.4, 2.5, 0.6, 4.5]) + 0.05 * np.sin(7 * t * np.arange(1, 7))
    return Q, robot.fk(Q)


def test_path_rows_exact_continuous_and_in_configuration(robot):
    Q, T = _path(robot)
    res = robot.ik_path(T, config=int(robot.config_of(Q[0])), seed=Q[0])
    assert res.ok.all()
    F = np.array([dh_product(q) for q in res.q])
    dp, dr = pose_errors(F, T)
    assert dp.max() < 1e-9 and dr.max() < 1e-12
    # continuous, not wrapped: q7 turns past pi and keeps going
    assert np.abs(np.diff(res.q, axis=0)).max() < 0.1
    assert res.q[-1, 5] > np.pi
    np.testing.assert_allclose(res.q, Q, atol=1e-9)
    assert np.all(robot.config_of(res.q) == robot.config_of(Q[0]))
    assert res.tracked[1:].all() and res.full_solves == 0


def test_path_without_seed_starts_from_the_complete_solver(robot):
    Q, T = _path(robot, 50)
    cfg = int(robot.config_of(Q[0]))
    res = robot.ik_path(T, config=cfg)
    assert res.ok.all() and not res.tracked[0]
    np.testing.assert_allclose(res.q[0], robot.ik(T[0], cfg), atol=1e-12)


def test_path_reports_bad_and_unreachable_rows(robot):
    Q, T = _path(robot, 60)
    T = T.copy()
    T[10, 0, 0] = np.nan
    T[20:25, :3, 3] += [5000.0, 0.0, 0.0]
    res = robot.ik_path(T, config=int(robot.config_of(Q[0])), seed=Q[0])
    assert not res.ok[10] and not res.ok[20:25].any()
    assert np.isnan(res.q[~res.ok]).all()
    good = res.ok
    F = robot.fk(res.q[good])
    assert pose_errors(F, T[good])[0].max() < 1e-9
    assert res.ok[26:].all()


def test_path_within_limits(robot):
    Q, T = _path(robot, 100)
    res = robot.ik_path(T, config=int(robot.config_of(Q[0])), seed=Q[0], within_limits=True)
    ok = res.ok
    assert np.all(res.q[ok] >= robot.lower - 1e-12) and np.all(res.q[ok] <= robot.upper + 1e-12)


@pytest.mark.parametrize("kwargs,match", [
    ({"config": 0}, "config"),
    ({"config": 1, "max_step": -1.0}, "max_step"),
    ({"config": 1, "seed": np.zeros(5)}, "seed"),
])
def test_path_bad_input(robot, kwargs, match):
    _, T = _path(robot, 5)
    with pytest.raises(ValueError, match=match):
        robot.ik_path(T, **kwargs)
    with pytest.raises(ValueError, match=r"\(N, 4, 4\)"):
        robot.ik_path(T[0], config=1)


def test_unreachable_error_is_value_error():
    assert issubclass(ik7r.UnreachableError, ValueError)
