"""The one path follower's branch mode (robot.ik_path with keep= / pose_at= / u=): bisection along
the continuous path, following a branch across indicator boundaries, the diagnosis of a lost
branch. References: the joint-space lines the paths are made from, checked by the paper's own
eq. (1) product (tests/helpers.py), not by ik7r's forward kinematics."""

import numpy as np
import pytest
from helpers import dh_product, pose_errors

QA = np.radians([10.0, 60.0, -20.0, 30.0, 20.0, 40.0])
QB = np.radians([20.0, 70.0, -10.0, 50.0, -20.0, 60.0])  # theta5 crosses 0 half-way


def _line(robot, qa, qb, n):
    """A continuous path (pose_at) made from the joint-space line qa -> qb, and n poses on it."""
    u = np.linspace(0.0, 1.0, n)

    def pose_at(s):
        return robot.fk(qa + s * (qb - qa))

    Q = qa + u[:, None] * (qb - qa)
    return u, pose_at, np.stack([pose_at(s) for s in u]), Q


def _exact(res, T):
    F = np.array([dh_product(q) for q in res.q[res.ok]])
    dp, dr = pose_errors(F, T[res.ok])
    return dp.max() < 1e-8 and dr.max() < 1e-10


def test_keep_branch_follows_the_line_through_the_straight_wrist(robot):
    u, pose_at, T, Q = _line(robot, QA, QB, 40)
    res = robot.ik_path(T, 1, seed=QA, keep="branch", pose_at=pose_at, u=u, within_limits=True)
    assert res.ok.all() and res.tracked[1:].all() and res.lost == {}
    np.testing.assert_allclose(res.q, Q, atol=1e-8)
    assert _exact(res, T)
    # the Wrist indicator flips where theta5 changes sign: configuration 1, then 2
    assert list(robot.config_of(res.q)) == [1] * 20 + [2] * 20


def test_keep_config_refuses_the_continuation_that_leaves_the_configuration(robot):
    u, pose_at, T, Q = _line(robot, QA, QB, 40)
    res = robot.ik_path(T, 1, seed=QA, pose_at=pose_at, u=u, within_limits=True)
    assert res.ok.all() and _exact(res, T)
    assert np.all(robot.config_of(res.q) == 1)
    assert list(res.lost) == [20] and not res.tracked[20] and res.tracked[21:].all()
    lost = res.lost[20]
    assert "leaves configuration 1 (to 2)" in lost.reason and lost.limit is None
    # the refused continuation is the line's next row; the row taken turns the wrist over
    np.testing.assert_allclose(lost.continued, Q[20], atol=1e-8)
    np.testing.assert_allclose(res.q[:20], Q[:20], atol=1e-8)
    assert abs(res.q[20, 3] - Q[20, 3]) > np.radians(150)


def test_bisection_tells_a_fast_continuous_step_from_a_jump(robot):
    # 6 poses 0.4 rad apart in q4 / q7: each step is far above max_step = 0.05 rad
    qb = QA + np.array([0.1, 0.05, -0.05, 2.0, 0.3, 2.0])
    u, pose_at, T, Q = _line(robot, QA, qb, 6)
    along = robot.ik_path(T, 1, seed=QA, pose_at=pose_at, u=u, within_limits=True, max_step=0.05)
    assert along.tracked[1:].all() and along.lost == {}
    np.testing.assert_allclose(along.q, Q, atol=1e-8)
    # without the path between the poses nothing can be bisected: every step is lost (and the
    # configuration's solution nearest the previous, the same line, is taken instead)
    alone = robot.ik_path(T, 1, seed=QA, keep="branch", within_limits=True, max_step=0.05)
    assert not alone.tracked[1:].any() and sorted(alone.lost) == [1, 2, 3, 4, 5]
    np.testing.assert_allclose(alone.q, Q, atol=1e-8)
    assert alone.full_solves == 6 and along.full_solves == 1  # the first row is a solve too


def test_a_lost_branch_names_the_joint_limit(robot):
    qa = QA.copy()
    qa[0] = robot.upper[0] - 0.05
    qb = qa + np.array([0.2, 0.0, 0.0, 0.0, 0.0, 0.0])  # q1 runs through its upper limit
    u, pose_at, T, Q = _line(robot, qa, qb, 9)
    res = robot.ik_path(T, 1, seed=qa, pose_at=pose_at, u=u, within_limits=True)
    inside = Q[:, 0] <= robot.upper[0]
    first_out = int(np.flatnonzero(~inside)[0])
    assert res.ok[:first_out].all() and res.tracked[1:first_out].all()
    lost = res.lost[first_out]
    assert lost.limit is not None and lost.limit[0] == 0 and lost.limit[2] == robot.upper[0]
    assert "q1 would pass its upper limit" in lost.reason
    assert np.all(res.q[res.ok, 0] <= robot.upper[0] + 1e-12)


@pytest.mark.parametrize("kwargs,match", [
    ({"keep": "branch"}, "within_limits=True"),
    ({"keep": "both", "within_limits": True}, "keep"),
    ({"pose_at": lambda s: np.eye(4), "within_limits": True}, "go together"),
    ({"u": np.zeros(5), "within_limits": True}, "go together"),
    ({"pose_at": lambda s: np.eye(4), "u": np.zeros(4), "within_limits": True}, r"shape \(5,\)"),
    ({"keep": "branch", "within_limits": True, "max_depth": -1}, "max_depth"),
])
def test_branch_follower_bad_input(robot, kwargs, match):
    _, _, T, _ = _line(robot, QA, QB, 5)
    with pytest.raises(ValueError, match=match):
        robot.ik_path(T, 1, **kwargs)
