"""The fast paths of single calls and batches (checks.py, solve.py, _select.py): same checks,
same messages, same answers as the general paths."""

from __future__ import annotations

import numpy as np
import pytest

import ik7r
from ik7r.geometry.checks import ORTHONORMAL_TOL, check_transforms, poses_status, transforms_status
from ik7r.geometry.configs import config_number
from ik7r.ik import solve


@pytest.fixture(scope="module")
def robot():
    return ik7r.load_robot()


@pytest.fixture(scope="module")
def poses(robot):
    Q = np.random.default_rng(21).uniform(-np.pi, np.pi, (150, 6))
    return Q, robot.fk(Q)


def _fk_ok(robot, q, T):
    Tq = robot.fk(q)
    dp = np.linalg.norm(Tq[..., :3, 3] - T[..., :3, 3], axis=-1)
    dr = np.sqrt(0.5 * ((Tq[..., :3, :3] - T[..., :3, :3]) ** 2).sum(axis=(-1, -2)))
    return (dp <= robot.position_tolerance) & (dr <= robot.rotation_tolerance)


def _bad_poses(T0):
    nan = T0.copy()
    nan[1, 2] = np.nan
    bottom = T0.copy()
    bottom[3, 0] = 1e-3
    skew = T0.copy()
    skew[:3, :3] *= 1.0 + 5e-6
    mirror = T0.copy()
    mirror[:3, 0] *= -1.0
    return {"NaN or infinity": nan, "bottom row": bottom, "not proper orthonormal": skew,
            "det = -1": mirror}


def test_one_pose_and_batch_checks_agree(poses):
    _, T = poses
    for what, bad in _bad_poses(T[0]).items():
        with pytest.raises(ValueError, match="T: ") as one:
            check_transforms(bad)
        assert what.split()[0] in str(one.value) or what in str(one.value)
        with pytest.raises(ValueError) as many:
            check_transforms(np.stack([T[0], bad]))
        assert str(many.value) == str(one.value).replace("T: ", "T (pose 1): ")
        # the same through a list and a non-contiguous view
        for form in (bad.tolist(), np.asfortranarray(bad)):
            with pytest.raises(ValueError) as other:
                check_transforms(form)
            assert str(other.value) == str(one.value)
    clean, ok, reasons = transforms_status(np.stack([T[0], *_bad_poses(T[0]).values()]))
    assert ok.tolist() == [True, False, False, False, False]
    assert reasons[0] == "" and all(reasons[1:])
    assert np.array_equal(clean[1:], np.broadcast_to(np.eye(4), (4, 4, 4)))


def test_projection_is_the_nearest_rotation(poses):
    _, T = poses
    rng = np.random.default_rng(5)
    noisy = T.copy()
    noisy[:, :3, :3] += rng.uniform(-1.5e-7, 1.5e-7, (len(T), 3, 3))
    clean, ok = poses_status(noisy)
    assert ok.all()
    R = clean[:, :3, :3]
    assert np.abs(np.swapaxes(R, 1, 2) @ R - np.eye(3)).max() < 1e-15
    assert (np.linalg.det(R) > 0).all()
    U, _, Vt = np.linalg.svd(noisy[:, :3, :3])  # the polar factor, independently
    assert np.abs(R - U @ Vt).max() < 1e-14
    assert np.array_equal(clean[:, :3, 3], noisy[:, :3, 3])
    assert np.array_equal(clean[:, 3], np.broadcast_to([0.0, 0.0, 0.0, 1.0], (len(T), 4)))
    one = check_transforms(noisy[7])
    assert np.array_equal(one, clean[7])


def test_tolerance_edge(poses):
    _, T = poses
    near = T[0].copy()
    near[:3, :3] *= 1.0 + 0.4 * ORTHONORMAL_TOL  # |R^T R - I| about 0.8e-6: accepted
    check_transforms(near)
    near[:3, :3] *= 1.0 + 0.2 * ORTHONORMAL_TOL  # about 1.2e-6: rejected
    with pytest.raises(ValueError, match="not proper orthonormal"):
        check_transforms(near)


def test_ik_all_order_and_answers(robot, poses):
    Q, T = poses
    for i in range(40):
        sols = robot.ik_all(T[i])
        keys = tuple(sols[:, j] for j in range(5, -1, -1)) + (config_number(sols),)
        assert np.array_equal(np.lexsort(keys), np.arange(len(sols)))
        assert _fk_ok(robot, sols, T[i]).all()
        d = np.abs(np.mod(sols - Q[i] + np.pi, 2 * np.pi) - np.pi).max(axis=1)
        assert d.min() < 1e-6
        inside = robot.ik_all(T[i], within_limits=True)
        assert ((inside >= robot.lower) & (inside <= robot.upper)).all()
        assert _fk_ok(robot, inside, T[i]).all()
        keys = tuple(inside[:, j] for j in range(5, -1, -1)) + (config_number(inside),)
        assert np.array_equal(np.lexsort(keys), np.arange(len(inside)))


def test_ik_answers_and_seed_checks(robot, poses):
    Q, T = poses
    for i in range(40):
        c = int(robot.config_of(Q[i]))
        q = robot.ik(T[i], c)
        assert _fk_ok(robot, q, T[i]) and robot.config_of(q) == c
        q2 = robot.ik(T[i], c, seed=Q[i])
        assert np.abs(np.mod(q2 - Q[i] + np.pi, 2 * np.pi) - np.pi).max() < 1e-6
    for seed in ([np.nan] * 6, np.array([0, 0, 0, np.inf, 0, 0.0])):
        with pytest.raises(ValueError, match="seed must be finite"):
            robot.ik(T[0], 1, seed=seed)
        with pytest.raises(ValueError, match="seed must be finite"):
            robot.ik_all(T[0], seed=seed)
    bad = T[0].copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match="^T: NaN"):  # the pose is reported first
        robot.ik(bad, 1, seed=[np.nan] * 6)
    with pytest.raises(ValueError, match="use ik_batch"):
        robot.ik(T[:2], 1)
    with pytest.raises(ValueError, match="use ik_all_batch"):
        robot.ik_all(T[:2])


def test_threads_give_the_same_batches(robot, poses, monkeypatch):
    Q, T = poses
    monkeypatch.setenv("IK7R_NUM_THREADS", "1")
    q1, v1 = robot.ik_all_batch(T)
    b1, ok1 = robot.ik_batch(T, 3, seed=Q)
    monkeypatch.setenv("IK7R_NUM_THREADS", "3")
    monkeypatch.setattr(solve, "MIN_POSES_PER_THREAD", 16)
    assert solve.threads_for(len(T)) == 3
    q3, v3 = robot.ik_all_batch(T)
    b3, ok3 = robot.ik_batch(T, 3, seed=Q)
    assert np.array_equal(v1, v3) and np.array_equal(q1[v1], q3[v3]) and np.isnan(q3[~v3]).all()
    assert np.array_equal(ok1, ok3) and np.array_equal(b1[ok1], b3[ok3]) and np.isnan(b3[~ok3]).all()
    idx = np.nonzero(v3)
    assert _fk_ok(robot, q3[idx], T[idx[0]]).all()
    assert _fk_ok(robot, b3[ok3], T[ok3]).all()
    monkeypatch.setenv("IK7R_NUM_THREADS", "many")
    with pytest.raises(ValueError, match="IK7R_NUM_THREADS"):
        solve.num_threads()
