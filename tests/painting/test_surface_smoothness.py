"""A surface raster is as smooth as the surface: on a flat plate every pass (with its overspray)
is a straight line at a fixed tool orientation between the samples too, and the joints need
next to no acceleration on it at a constant gun speed (references: the straight line itself,
and the IK of poses built on it here, differentiated by finite differences)."""

from __future__ import annotations

import numpy as np
import pytest

import ik7r
from ik7r.painting import solve_path, time_path, workpiece_frame
from ik7r.painting.parts import builtin_part
from ik7r.painting.surface import surface_raster

SPEED = 500.0  # mm/s, the default of paint mesh
STANDOFF, OVER, SPACING = 200.0, 60.0, 100.0
ORIGIN = np.array([1100.0, 0.0, 0.0])


def _stretches(mask):
    m = np.concatenate([[0], mask.astype(int), [0]])
    d = np.diff(m)
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1))


@pytest.fixture(scope="module")
def panel_path():
    part = builtin_part("panel", T_base_part=workpiece_frame(ORIGIN))
    return surface_raster(part, spacing=SPACING, standoff=STANDOFF, overspray=OVER, approach=150.0)


def test_passes_on_a_plate_are_straight_at_a_fixed_orientation_between_samples(panel_path):
    path = panel_path
    runs = _stretches(path.spray)
    assert len(runs) == 6  # ceil(600 / 100) passes
    for k, (a, b) in enumerate(runs):
        u = np.linspace(path.u[a], path.u[b], 4001)  # every pass from one end of its overspray to the other
        P, R = path.at(u)
        sign = 1.0 if k % 2 == 0 else -1.0
        y = -250.0 + SPACING * k
        # the reference: the line y = const at the standoff above the plate, run at unit speed in u
        x_ref = ORIGIN[0] + sign * (-250.0 - OVER) + sign * (u - u[0])
        np.testing.assert_allclose(P[:, 0], x_ref, atol=1e-9)
        np.testing.assert_allclose(P[:, 1], y, atol=1e-9)
        np.testing.assert_allclose(P[:, 2], STANDOFF, atol=1e-9)
        assert P[-1, 0] == pytest.approx(ORIGIN[0] + sign * (250.0 + OVER), abs=1e-9)
        # gun axis down, tool x along the travel, everywhere along the pass
        R_ref = np.diag([sign, -sign, -1.0])
        np.testing.assert_allclose(R, np.broadcast_to(R_ref, R.shape), atol=1e-12)


def test_turns_join_the_passes_with_continuous_curvature_and_turn_rate(panel_path):
    """Second derivatives of the position and first of the orientation, just before and just
    after every end of a pass: all zero on both sides (the U turns start straight, at rest)."""
    path = panel_path
    h = 1e-3
    for a, b in _stretches(path.spray):
        for u0, side in ((path.u[a], -1.0), (path.u[b], 1.0)):  # the turn is on this side
            u = u0 + side * np.array([h, 2 * h, 3 * h])
            P, R = path.at(u)
            p2 = (P[2] - 2 * P[1] + P[0]) / h ** 2
            assert np.abs(p2).max() < 1e-3  # curvature of about 1e-3 / mm or less so close to the end
            dR = (R[1] - R[0]) / h
            assert np.abs(dR).max() < 1e-4


def test_joint_accelerations_on_a_straight_pass_are_those_of_the_straight_line(panel_path):
    """At a constant gun speed on a pass, q'' = Q''(u) v^2; away from the turns (30 mm inside the
    overspray and beyond) it matches the IK of the exact line, differentiated here, and the
    wrist joints (q4, q7) need next to nothing: at most 2 % of their acceleration limits."""
    robot = ik7r.load_robot()
    path = panel_path
    sol = solve_path(robot, path, 1)
    assert sol.feasible, sol.report()
    traj, events = time_path(robot, sol, speed=SPEED)  # raises if the speed broke a limit on a pass
    jp = traj.joint_path
    for k, (a, b) in enumerate(_stretches(path.spray)):
        u = np.linspace(path.u[a] + 30.0, path.u[b] - 30.0, 300)
        sign = 1.0 if k % 2 == 0 else -1.0
        h = 0.5
        x0 = ORIGIN[0] + sign * (-250.0 - OVER)
        T = np.zeros((3, len(u), 4, 4))
        for i, du in enumerate((-h, 0.0, h)):
            T[i, :, :3, :3] = np.diag([sign, -sign, -1.0])
            T[i, :, 0, 3] = x0 + sign * (u - path.u[a] + du)
            T[i, :, 1, 3] = -250.0 + SPACING * k
            T[i, :, 2, 3] = STANDOFF
            T[i, :, 3, 3] = 1.0
        q, ok = robot.ik_batch((robot.base @ T).reshape(-1, 4, 4), 1)
        assert ok.all()
        q = np.unwrap(q.reshape(3, len(u), 6), axis=0)
        qdd_ref = (q[2] - 2 * q[1] + q[0]) / h ** 2
        demand = jp.evaluate(u, 2) * SPEED ** 2
        ref = qdd_ref * SPEED ** 2
        np.testing.assert_allclose(demand / robot.acceleration, ref / robot.acceleration, atol=0.01)
        assert np.abs(demand[:, [3, 5]] / robot.acceleration[[3, 5]]).max() <= 0.02
