"""``matrix_to_rpy`` gives back its rotation to the rounding of the entries, at and near gimbal
lock too (the URDF writer puts every joint origin through it, and the loader checks the chain
it reads back to 1e-12). The rotations are built here from an axis and an angle (Rodrigues) and
from three elementary turns, independently of ``rpy_to_matrix``."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from ik7r.geometry.rotations import matrix_to_rpy


def _turn(axis: int, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    i, j = [k for k in range(3) if k != axis]
    R = np.eye(3)
    R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
    if axis == 1:  # (RotY: the sine's signs the other way round)
        R[i, j], R[j, i] = s, -s
    return R


def _rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """``RotZ(yaw) RotY(pitch) RotX(roll)``: the URDF convention."""
    return _turn(2, yaw) @ _turn(1, pitch) @ _turn(0, roll)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(roll=st.floats(-math.pi, math.pi), yaw=st.floats(-math.pi, math.pi), up=st.booleans(),
       k=st.floats(0.0, 17.0))
def test_near_gimbal_lock_the_angles_give_back_the_rotation(roll, yaw, up, k):
    """Pitch within 10^-k of +-pi/2 (exactly there for k > 16): the angles' rotation equals the
    given one to 4 roundings of its entries (before: up to 2e-12 off, roll and yaw each read
    from entries of order cos(pitch))."""
    pitch = (1.0 if up else -1.0) * (math.pi / 2 - (10.0 ** -k if k <= 16 else 0.0))
    R = _rpy(roll, pitch, yaw)
    r, p, y = matrix_to_rpy(R)
    assert -math.pi / 2 <= p <= math.pi / 2
    assert np.abs(_rpy(r, p, y) - R).max() <= 1e-15


def test_random_rotations_and_their_angles():
    """Random rotations (from random axes and angles): the angles give them back, and away from
    gimbal lock they are the angles the rotations were made of."""
    rng = np.random.default_rng(7)
    angles = np.column_stack([rng.uniform(-np.pi, np.pi, 500), rng.uniform(-1.5, 1.5, 500),
                              rng.uniform(-np.pi, np.pi, 500)])
    R = np.array([_rpy(*a) for a in angles])
    got = matrix_to_rpy(R)
    np.testing.assert_allclose(got, angles, rtol=0, atol=1e-13)
    back = np.array([_rpy(*a) for a in got])
    assert np.abs(back - R).max() <= 1e-15
