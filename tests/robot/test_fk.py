"""Forward kinematics against an independent product of the paper's eq. (1) matrices."""

import numpy as np
import pytest
from helpers import SIMULATION1_Q_DEG, SIMULATION1_T, dh_product, random_full_q


def test_fk_equals_independent_dh_product(robot, rng):
    Q = random_full_q(rng, 200)
    T = robot.fk(Q)
    ref = np.array([dh_product(q) for q in Q])
    assert T.shape == (200, 4, 4)
    np.testing.assert_allclose(T, ref, rtol=0, atol=1e-9)


def test_simulation1_pose_as_printed(robot):
    T = robot.fk(np.radians(SIMULATION1_Q_DEG))
    np.testing.assert_allclose(T[:3, :3], SIMULATION1_T[:3, :3], atol=5e-5)
    np.testing.assert_allclose(T[:3, 3], SIMULATION1_T[:3, 3], atol=5e-5)


def test_fk_broadcasts_leading_axes(robot, rng):
    Q = random_full_q(rng, 12).reshape(3, 4, 6)
    T = robot.fk(Q)
    assert T.shape == (3, 4, 4, 4)
    np.testing.assert_allclose(T[2, 1], robot.fk(Q[2, 1]), atol=1e-12)


def test_frames_end_with_fk_and_follow_the_chain(robot, rng):
    q = random_full_q(rng, 1)[0]
    F = robot.frames(q)
    assert F.shape == (9, 4, 4)
    np.testing.assert_allclose(F[-1], robot.fk(q), atol=1e-9)
    for i in range(1, 8):
        np.testing.assert_allclose(F[i], dh_product(q, 0, i), atol=1e-9)


def test_coupling_mirrors_joint5(robot, rng):
    # the wrist bend depends on |q5| only: the angle between axes 4 and 7
    q = random_full_q(rng, 1)[0]
    qm = q.copy()
    qm[4] = -q[4]
    F, Fm = robot.frames(q), robot.frames(qm)
    assert np.dot(F[4][:3, 2], F[7][:3, 2]) == pytest.approx(np.dot(Fm[4][:3, 2], Fm[7][:3, 2]), abs=1e-12)


def test_jacobian_matches_finite_differences(robot, rng):
    q = random_full_q(rng, 1)[0]
    J = robot.jacobian(q)
    h = 1e-6
    T0 = robot.fk(q)
    for j in range(6):
        dq = np.zeros(6)
        dq[j] = h
        Tp, Tm = robot.fk(q + dq), robot.fk(q - dq)
        v = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T0[:3, :3].T
        w = np.array([dR[2, 1], dR[0, 2], dR[1, 0]])
        np.testing.assert_allclose(J[:3, j], v, atol=1e-4)
        np.testing.assert_allclose(J[3:, j], w, atol=1e-8)


def test_tool_and_base_compose(robot, rng):
    from ik7r.geometry.rotations import rpy_to_matrix, transform

    q = random_full_q(rng, 1)[0]
    T_base = transform(rpy_to_matrix([0.1, -0.2, 0.3]), [100.0, -50.0, 20.0])
    T_tool = transform(rpy_to_matrix([0.0, 0.5, 0.0]), [0.0, 10.0, 250.0])
    r2 = robot.with_base(T_base).with_tool(T_tool)
    np.testing.assert_allclose(r2.fk(q), T_base @ dh_product(q) @ T_tool, atol=1e-9)
