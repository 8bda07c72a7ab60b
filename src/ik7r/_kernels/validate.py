"""Compiled kernel of the pose check of :mod:`ik7r.geometry.checks`: finite, bottom row, proper
orthonormal rotation, and the projection onto the nearest rotation, for one pose or millions.

The projection is the polar factor of ``R`` computed by the Newton-Schulz iteration
``X <- X (3 I - X^T X) / 2``, which converges quadratically to the polar factor (the same
matrix as the SVD's ``U V^T``) whenever ``|X^T X - I| < 1``; an accepted pose is within
:data:`ik7r.geometry.checks.ORTHONORMAL_TOL` (1e-6) of it, so two or three steps reach rounding.
"""

from __future__ import annotations

import math

import numpy as np

from .jit import njit

OK = 0
NOT_FINITE = 1
BAD_BOTTOM = 2
BAD_ROTATION = 3


@njit
def _orth_error(X):
    """``max |X^T X - I|`` of a 3 x 3 matrix."""
    err = 0.0
    for i in range(3):
        for j in range(3):
            s = X[0, i] * X[0, j] + X[1, i] * X[1, j] + X[2, i] * X[2, j]
            if i == j:
                s -= 1.0
            err = max(err, abs(s))
    return err


@njit
def _det3(X):
    return (X[0, 0] * (X[1, 1] * X[2, 2] - X[1, 2] * X[2, 1])
            - X[0, 1] * (X[1, 0] * X[2, 2] - X[1, 2] * X[2, 0])
            + X[0, 2] * (X[1, 0] * X[2, 1] - X[1, 1] * X[2, 0]))


@njit
def _polar(X, tmp):
    """Replace the rotation block ``X`` (3, 3) (near a rotation) by its polar factor."""
    for _ in range(8):
        if _orth_error(X) <= 1e-15:
            return
        # tmp = (3 I - X^T X) / 2
        for i in range(3):
            for j in range(3):
                s = X[0, i] * X[0, j] + X[1, i] * X[1, j] + X[2, i] * X[2, j]
                tmp[i, j] = (3.0 if i == j else 0.0) * 0.5 - 0.5 * s
        for r in range(3):
            x0 = X[r, 0]
            x1 = X[r, 1]
            x2 = X[r, 2]
            for j in range(3):
                X[r, j] = x0 * tmp[0, j] + x1 * tmp[1, j] + x2 * tmp[2, j]


@njit
def validate_pose(T, tol, clean, tmp):
    """Check one pose ``T`` (4, 4) and write its cleaned form to ``clean`` (4, 4).

    Returns a code: :data:`OK`, :data:`NOT_FINITE`, :data:`BAD_BOTTOM` (bottom row off
    ``[0, 0, 0, 1]`` by more than ``tol``) or :data:`BAD_ROTATION` (``max |R^T R - I| > tol``
    or ``det R <= 0``). A good pose's rotation is replaced by the nearest rotation and its
    bottom row made exact; a bad pose is replaced by the identity.
    """
    finite = True
    for i in range(4):
        for j in range(4):
            if not math.isfinite(T[i, j]):
                finite = False
    code = OK
    if not finite:
        code = NOT_FINITE
    else:
        bottom = max(abs(T[3, 0]), abs(T[3, 1]), abs(T[3, 2]), abs(T[3, 3] - 1.0))
        if bottom > tol:
            code = BAD_BOTTOM
        else:
            for i in range(3):
                for j in range(3):
                    clean[i, j] = T[i, j]
            if _orth_error(clean) > tol or _det3(clean) <= 0.0:
                code = BAD_ROTATION
    if code != OK:
        for i in range(4):
            for j in range(4):
                clean[i, j] = 1.0 if i == j else 0.0
        return code
    _polar(clean, tmp)
    for i in range(3):
        clean[i, 3] = T[i, 3]
    clean[3, 0] = 0.0
    clean[3, 1] = 0.0
    clean[3, 2] = 0.0
    clean[3, 3] = 1.0
    return code


@njit(allocates=True)
def validate_poses(Ts, tol, clean, codes):
    """:func:`validate_pose` for every pose of ``Ts`` (N, 4, 4); returns the number of bad ones."""
    tmp = np.empty((3, 3))
    bad = 0
    for n in range(Ts.shape[0]):
        codes[n] = validate_pose(Ts[n], tol, clean[n], tmp)
        if codes[n] != OK:
            bad += 1
    return bad
