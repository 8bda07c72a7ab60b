"""Inverse kinematics: every solution of a pose, one configuration, and their batch forms.

These functions are what the :class:`~ik7r.model.Robot` methods call. They validate at the
boundary and hand the poses to the compiled kernels of :mod:`ik7r._complete` and
:mod:`ik7r._select`. See :mod:`ik7r._poly` for why no solution can be missed.
"""

from __future__ import annotations

import numpy as np

from . import _layout as L
from ._complete import solve_all, solve_all_batch
from ._poly import bernstein_matrices
from ._select import expand_within_limits, select, solve_config_batch
from .checks import check_config, check_joints, check_transforms, transforms_status
from .configs import config_number, describe_config
from .errors import UnreachableError

__all__ = ["ik_all", "ik", "ik_batch", "ik_all_batch", "MAX_SOLUTIONS"]

#: Most solutions one pose can have (see :mod:`ik7r._poly`): the width K of ``ik_all_batch``.
MAX_SOLUTIONS = L.MAX_SOLUTIONS


def _matrices(robot):
    n = int(robot.kernel_params[L.NCHEB])
    _, Bm = bernstein_matrices(n)
    return Bm, float(np.abs(Bm).sum(axis=1).max())


def _seed(seed, shape):
    if seed is None:
        return np.zeros(shape), False
    s = check_joints(seed, "seed")
    return np.ascontiguousarray(np.broadcast_to(s, shape), dtype=float), True


def _all(robot, T_world_tool: np.ndarray, hint: np.ndarray, has_hint: bool) -> np.ndarray:
    out = np.empty((MAX_SOLUTIONS, 6))
    Bm, bnorm = _matrices(robot)
    n = solve_all(np.ascontiguousarray(T_world_tool), robot.kernel_params, Bm, bnorm,
                  hint, has_hint, out)
    return out[:n].copy()


def ik_all(robot, T, *, within_limits: bool = False, seed=None) -> np.ndarray:
    """Every distinct solution of one pose.

    Parameters
    ----------
    robot : Robot
    T : array_like, shape (4, 4)
        World <- tool pose (robot length unit).
    within_limits : bool
        Keep only solutions inside the joint limits, with every multi-turn equivalent
        (joints whose range exceeds 2 pi, such as q4 and q7) inside the limits.
    seed : array_like, shape (6,), optional
        Chooses the free joints at singular poses (q4 / q7 split at a straight wrist, q1 when
        axis 7 lies on axis 1); default q4 = 0, q1 = 0.

    Returns
    -------
    q : ndarray, shape (M, 6)
        Joint solutions (rad), sorted by configuration number then joints; wrapped to
        (-pi, pi] unless ``within_limits``. Each satisfies the forward kinematics to the
        robot's tolerances. ``M = 0`` when the pose is out of reach.
    """
    T = check_transforms(T)
    if T.shape != (4, 4):
        raise ValueError(f"T must be one pose of shape (4, 4); got {T.shape} (use ik_all_batch)")
    hint, has = _seed(seed, (6,))
    sols = _all(robot, T, hint, has)
    if within_limits:
        out = np.empty((max(1, len(sols)) * 64, 6))
        n = expand_within_limits(np.ascontiguousarray(sols), len(sols), robot.kernel_params, out)
        sols = out[:n].copy()
    order = np.lexsort(tuple(sols[:, j] for j in range(5, -1, -1)) + (config_number(sols),))
    return sols[order]


def ik(robot, T, config=1, *, seed=None, within_limits: bool = False) -> np.ndarray:
    """The solution of one pose in one configuration.

    Parameters
    ----------
    robot : Robot
    T : array_like, shape (4, 4)
        World <- tool pose.
    config : int or (arm, elbow, wrist)
        1..8 as in the paper's Appendix 3, or the three indicators (0 or 1 each).
    seed : array_like, shape (6,), optional
        When several solutions share the indicators (poses with 12 or 16 solutions) the one
        nearest ``seed`` is returned; without a seed, the one nearest the zero posture. The seed
        also splits q4 / q7 at a straight wrist.
    within_limits : bool
        Only solutions inside the joint limits (multi-turn equivalents included); the one
        nearest the seed (not wrapped) is returned.

    Returns
    -------
    q : ndarray, shape (6,)
        Joints ``[q1, q2, q3, q4, q5, q7]`` (rad), exact to the robot's tolerances.

    Raises
    ------
    UnreachableError
        No solution in that configuration (or none within the limits).
    """
    arm, elbow, wrist = check_config(config)
    T = check_transforms(T)
    if T.shape != (4, 4):
        raise ValueError(f"T must be one pose of shape (4, 4); got {T.shape} (use ik_batch)")
    hint, has = _seed(seed, (6,))
    sols = _all(robot, T, hint, has)
    q = np.empty(6)
    pool = np.ascontiguousarray(sols if len(sols) else np.empty((1, 6)))
    if select(pool, len(sols), arm, elbow, wrist, hint, within_limits, robot.kernel_params, q):
        return q
    what = describe_config(arm, elbow, wrist)
    if len(sols) == 0:
        raise UnreachableError(f"the pose is out of reach: no solution in any configuration ({what} asked)")
    have = sorted(set(int(c) for c in config_number(sols)))
    limits = " within the joint limits" if within_limits else ""
    raise UnreachableError(
        f"no solution in {what}{limits}; the pose has {len(sols)} solutions, in configurations {have}"
    )


def ik_batch(robot, T, config=1, *, seed=None, within_limits: bool = False):
    """:func:`ik` for many poses at once.

    Parameters
    ----------
    T : array_like, shape (N, 4, 4)
    config : int or (arm, elbow, wrist)
    seed : array_like, shape (6,) or (N, 6), optional

    Returns
    -------
    q : ndarray, shape (N, 6)
        Solutions (rad); rows that are not ok hold NaN.
    ok : ndarray, shape (N,), bool
        False for a bad pose (NaN, non-orthonormal rotation) or an unreachable one; every other
        row is still solved.
    """
    arm, elbow, wrist = check_config(config)
    Tc, good, _ = transforms_status(T)
    if Tc.ndim != 3:
        raise ValueError(f"T must have shape (N, 4, 4); got {Tc.shape}")
    n = Tc.shape[0]
    seeds, has = _seed(seed, (n, 6))
    q = np.full((n, 6), np.nan)
    ok = np.zeros(n, dtype=bool)
    Bm, bnorm = _matrices(robot)
    solve_config_batch(np.ascontiguousarray(Tc), robot.kernel_params, Bm, bnorm, arm, elbow,
                       wrist, seeds, has, within_limits, good, q, ok)
    q[~ok] = np.nan
    return q, ok


def ik_all_batch(robot, T):
    """:func:`ik_all` for many poses at once.

    Parameters
    ----------
    T : array_like, shape (N, 4, 4)

    Returns
    -------
    q : ndarray, shape (N, K, 6)
        ``K = MAX_SOLUTIONS``; invalid entries hold NaN. Valid entries come first in each row.
    valid : ndarray, shape (N, K), bool
    """
    Tc, good, _ = transforms_status(T)
    if Tc.ndim != 3:
        raise ValueError(f"T must have shape (N, 4, 4); got {Tc.shape}")
    n = Tc.shape[0]
    out = np.full((n, MAX_SOLUTIONS, 6), np.nan)
    counts = np.zeros(n, dtype=np.int64)
    Bm, bnorm = _matrices(robot)
    solve_all_batch(np.ascontiguousarray(Tc), robot.kernel_params, Bm, bnorm,
                    np.zeros((n, 6)), False, good, out, counts)
    valid = np.arange(MAX_SOLUTIONS)[None, :] < counts[:, None]
    out[~valid] = np.nan
    return out, valid
