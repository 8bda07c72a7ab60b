"""Shared test helpers: the paper's data and an independent reference of its kinematics.

``dh_product`` is written from the paper's eq. (1) and Table 1 alone (it does not import ik7r),
so tests that compare ik7r against it compare two independent implementations.
"""

from __future__ import annotations

import numpy as np

# the library's one wrap, for wrapped joint distances (tests/geometry/test_wrap_and_indicators.py
# holds it against an exact reference)
from ik7r.geometry import wrap_angle as wrap

#: Table 1 of the paper: (a_{i-1} mm, alpha_{i-1} deg, d_i mm) for joints 1..7.
TABLE1 = [(0, 0, 0), (0, 90, 0), (1000, 0, 0), (0, 90, 900), (0, -35, 80), (0, 70, 80), (0, -35, 100)]

#: Simulation 1: the joints and the pose T_end the paper prints (mm).
SIMULATION1_Q_DEG = [60, 60, 0, -30, 60, 30]
SIMULATION1_T = np.array([
    [-0.2536, 0.9073, 0.3353, 733.5055],
    [-0.5377, -0.4204, 0.7309, 1297.2539],
    [0.8041, 0.0051, 0.5944, 482.8780],
    [0, 0, 0, 1],
])

#: The paper's Table 2 (deg), OCR slips fixed as in docs/method.md; rows are configurations 1..8.
TABLE2_DEG = np.array([
    [60.0000, 60.0000, 0.0000, -30.0000, 60.0000, 30.0000],
    [60.0000, 60.0000, 0.0000, -159.3775, -60.0000, 159.3775],
    [60.0360, -27.5107, 178.4662, -178.6218, 21.6300, -177.6485],
    [60.0360, -27.5107, 178.4662, 19.1657, -21.6300, -15.4359],
    [-119.9640, -152.4893, 1.5338, 1.3782, 21.6300, -177.6485],
    [-119.9640, -152.4893, 1.5338, -160.8343, -21.6300, -15.4359],
    [-120.0000, 120.0000, 180.0000, 150.0000, 60.0000, 30.0000],
    [-120.0000, 120.0000, 180.0000, 20.6225, -60.0000, 159.3775],
])


def dh_link(a: float, alpha_deg: float, theta: float, d: float) -> np.ndarray:
    """Eq. (1): RotX(alpha) TransX(a) RotZ(theta) TransZ(d)."""
    al = np.radians(alpha_deg)
    ca, sa, ct, st = np.cos(al), np.sin(al), np.cos(theta), np.sin(theta)
    return np.array([
        [ct, -st, 0, a],
        [st * ca, ct * ca, -sa, -sa * d],
        [st * sa, ct * sa, ca, ca * d],
        [0, 0, 0, 1],
    ])


def dh_product(q6, first: int = 0, last: int = 7) -> np.ndarray:
    """Product of eq. (1) matrices of joints first+1..last for independent joints q6 (rad)."""
    t1, t2, t3, t4, t5, t7 = q6
    theta = [t1, t2, t3, t4, t5, -t5, t7]
    T = np.eye(4)
    for i in range(first, last):
        a, al, d = TABLE1[i]
        T = T @ dh_link(a, al, theta[i], d)
    return T


def angle_distance(a, b):
    """Largest wrapped joint difference (rad) along the last axis."""
    return np.abs(wrap(np.asarray(a) - np.asarray(b))).max(axis=-1)


def pose_errors(T_a, T_b):
    """(position error, largest rotation-entry error) between poses (..., 4, 4)."""
    dp = np.linalg.norm(T_a[..., :3, 3] - T_b[..., :3, 3], axis=-1)
    dr = np.abs(T_a[..., :3, :3] - T_b[..., :3, :3]).max(axis=(-1, -2))
    return dp, dr


def random_usable_q(rng, robot, n):
    """Joints uniform within the paper's Table 4 limits (the usable workspace)."""
    return rng.uniform(robot.lower, robot.upper, (n, 6))


def random_full_q(rng, n):
    """Joints uniform over (-pi, pi]."""
    return rng.uniform(-np.pi, np.pi, (n, 6))


def source_distance(robot, sols, q):
    """Largest joint difference (rad, wrapped, every joint) from ``q`` to its nearest answer.
    Where the pose leaves the answers a valley (the split q4/q7 of a nearly straight wrist, the
    shoulder set) a source farther than this may still be one solution with an answer:
    ``reference_ik.among`` decides that by the poses along the way."""
    if len(sols) == 0:
        return np.inf
    return np.abs(wrap(sols - q)).max(axis=1).min()
