"""Inverse kinematics: every solution of a pose, one configuration, and their batch forms.

These functions are what the :class:`~ik7r.robot.model.Robot` methods call. They validate at the
boundary and hand the poses to the compiled kernels of :mod:`ik7r._kernels.complete` and
:mod:`ik7r._kernels.select`. See :mod:`ik7r._kernels.poly` for why no solution can be missed.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING

import numpy as np

from .._kernels import (
    all_rows,
    bernstein_tables,
    config_rows,
    count_within_limits,
    expand_within_limits,
    ik_all_one,
    ik_one,
)
from .._kernels import params as L
from ..errors import UnreachableError
from ..geometry.checks import (
    ORTHONORMAL_TOL,
    check_config,
    check_finite,
    check_joints,
    check_transforms,
    pose_batch,
    poses_status_into,
    reduce_seeds,
)
from ..geometry.configs import config_number, describe_config

if TYPE_CHECKING:
    from .._typing import ArrayLike, Config
    from ..robot.model import Robot

__all__ = ["ik_all", "ik", "ik_batch", "ik_all_batch", "MAX_SOLUTIONS", "MAX_WITHIN_LIMITS_ROWS",
           "num_threads", "threads_for"]

#: Most solutions one pose can have (see :mod:`ik7r._kernels.poly`): the width K of ``ik_all_batch``.
MAX_SOLUTIONS = L.MAX_SOLUTIONS

#: Fewest poses a thread of the batch functions is given (smaller batches run in one thread).
MIN_POSES_PER_THREAD = 2048

def num_threads() -> int:
    """Threads the batch functions use: ``IK7R_NUM_THREADS`` if set, else the usable cores."""
    env = os.environ.get("IK7R_NUM_THREADS", "").strip()
    if env:
        try:
            return max(1, int(env))
        except ValueError:
            raise ValueError(f"IK7R_NUM_THREADS must be a positive integer; got {env!r}") from None
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


_POOL: ThreadPoolExecutor | None = None

# The hint of single-pose calls without a seed. The kernels never write into a hint (a
# caller's seed array is handed to them as it is, too).
_ZERO_HINT = np.zeros(6)


def threads_for(n: int) -> int:
    """Threads a batch of ``n`` poses is solved with (at least
    :data:`MIN_POSES_PER_THREAD` poses per thread, at most :func:`num_threads`)."""
    return max(1, min(num_threads(), n // MIN_POSES_PER_THREAD))


def _in_threads(n: int, work) -> None:
    """Run ``work(start, stop)`` over ``range(n)`` split into contiguous slices, one per
    thread (the compiled kernels release the GIL)."""
    threads = threads_for(n)
    if threads <= 1:
        work(0, n)
        return
    global _POOL
    if _POOL is None or _POOL._max_workers < threads:  # noqa: SLF001
        _POOL = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="ik7r")
    bounds = np.linspace(0, n, threads + 1).astype(int)
    futures = [_POOL.submit(work, int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]
    for f in futures:
        f.result()


def _seed(seed, shape, T=None):
    """The seed broadcast to ``shape`` and whether one was given; a bad pose ``T`` is
    reported before a bad seed (the order of the checks). A float (6,) seed of a single-pose
    call is passed as it is: the kernel checks that it is finite (see :func:`_bad_input`)."""
    if seed is None:
        return (_ZERO_HINT if shape == (6,) else np.zeros(6)), False
    if (shape == (6,) and type(seed) is np.ndarray and seed.shape == (6,)
            and seed.dtype == np.float64 and seed.flags.c_contiguous):
        return seed, True
    try:
        s = check_joints(seed, "seed")
    except ValueError:
        if T is not None:
            check_transforms(T)
        raise
    return np.ascontiguousarray(np.broadcast_to(s, shape), dtype=float), True


def _batch_seeds(seed, n: int):
    """The seeds of ``ik_batch``: ``(seeds (N, 6) or (1, 6), given, ok (N,) or None)``. Seeds are
    periodic: joints beyond MAX_JOINT_ANGLE are reduced modulo 2 pi (:func:`reduce_seeds`).
    One (6,) seed must be finite (it is the argument that is bad); of (N, 6) seeds, a row with
    NaN or infinity makes only its own pose not ok."""
    if seed is None:
        return np.zeros((1, 6)), False, None
    try:
        arr = np.asarray(seed, dtype=float)
    except (TypeError, ValueError):
        arr = None
    if arr is not None and arr.shape == (1, 6):
        arr = arr[0]
    if arr is None or arr.ndim not in (1, 2) or arr.shape[-1] != 6 or (arr.ndim == 2 and arr.shape[0] != n):
        raise ValueError(f"seed must have shape (6,) or ({n}, 6) (joints [q1, q2, q3, q4, q5, q7] in rad); "
                         f"got {getattr(arr, 'shape', seed)!r}")
    if arr.ndim == 1:
        check_finite(arr, "seed")
        return np.ascontiguousarray(np.broadcast_to(reduce_seeds(arr), (n, 6))), True, None
    ok = np.isfinite(arr).all(axis=1)
    clean = np.where(ok[:, None], arr, 0.0)
    return np.ascontiguousarray(reduce_seeds(clean)), True, (None if ok.all() else ok)


def _bad_input(T, seed) -> None:
    """Raise the ValueError of the checks for a pose or seed a kernel rejected."""
    check_transforms(T)
    check_joints(seed, "seed")
    raise AssertionError("a kernel rejected an input the checks accept")  # pragma: no cover


def _one_pose(T, batch_name: str) -> np.ndarray:
    """``T`` as a C-contiguous float (4, 4) array, or the ValueError of the checks."""
    if type(T) is np.ndarray and T.dtype == np.float64 and T.shape == (4, 4) and T.flags.c_contiguous:
        return T
    arr = check_transforms(T)
    if arr.shape != (4, 4):
        raise ValueError(f"T must be one pose of shape (4, 4); got {arr.shape} (use {batch_name})")
    return arr


def ik_all(robot: Robot, T: ArrayLike, *, within_limits: bool = False,
           seed: ArrayLike | None = None) -> np.ndarray:
    """Every distinct solution of one pose.

    Parameters
    ----------
    robot : Robot
    T : array_like, shape (4, 4)
        World <- tool pose (robot length unit).
    within_limits : bool
        Keep only solutions inside the joint limits, with every multi-turn equivalent
        (joints whose range exceeds 2 pi, such as q4 and q7) inside the limits. The output is
        sized to hold them all; more than :data:`MAX_WITHIN_LIMITS_ROWS` raise ValueError.
    seed : array_like, shape (6,), optional
        Chooses the free joints at singular poses (q4 / q7 split at a straight wrist, q1 when
        axis 7 or axis 4 lies on axis 1); default q4 = 0, q1 = 0. Periodic: joints beyond
        ``ik7r.robot.family.MAX_JOINT_ANGLE`` are reduced modulo 2 pi first.

    Returns
    -------
    q : ndarray, shape (M, 6)
        Joint solutions (rad), sorted by configuration number then joints; wrapped to
        (-pi, pi] unless ``within_limits``. Each satisfies the forward kinematics to the
        robot's tolerances. ``M = 0`` when the pose is out of reach.
    """
    T = _one_pose(T, "ik_all_batch")
    hint, has = _seed(seed, (6,), T)
    Bm, bnorm = bernstein_tables(robot.kernel_params)
    sols = np.empty((MAX_SOLUTIONS, 6))
    out = _NO_ROWS if not within_limits else np.empty((WITHIN_LIMITS_ROWS, 6))
    K = robot.kernel_params
    n, total = ik_all_one(T, ORTHONORMAL_TOL, K, Bm, bnorm, hint, has, bool(within_limits), sols, out)
    if n < 0:
        _bad_input(T, seed)
    if not within_limits:
        return sols[:n]
    if total <= len(out):
        return out[:total].copy()
    return _expanded(sols, n, K)


#: Rows ``ik_all(T, within_limits=True)`` expands into in its one compiled call; more are
#: expanded by :func:`_expanded` into an output of their exact size.
WITHIN_LIMITS_ROWS = 64 * MAX_SOLUTIONS
_NO_ROWS = np.empty((0, 6))


#: Most rows ``ik_all(T, within_limits=True)`` returns (every multi-turn equivalent inside the
#: limits); limits whose expansion exceeds it raise ValueError rather than drop rows.
MAX_WITHIN_LIMITS_ROWS = 100_000


def _expanded(sols: np.ndarray, n: int, K: np.ndarray) -> np.ndarray:
    """Every multi-turn equivalent of ``sols[:n]`` inside the joint limits, sorted by
    configuration number then joints; the output is sized to hold them all."""
    total = count_within_limits(sols, n, K)
    if total > MAX_WITHIN_LIMITS_ROWS:
        raise ValueError(
            f"ik_all(within_limits=True) would return {total} rows (every multi-turn equivalent of "
            f"{n} solutions inside the joint limits), more than MAX_WITHIN_LIMITS_ROWS = "
            f"{MAX_WITHIN_LIMITS_ROWS}; narrow the limits, or use ik(T, config, seed=..., "
            "within_limits=True) for the one nearest a seed")
    out = np.empty((total, 6))
    if expand_within_limits(sols, n, K, out) != total:  # pragma: no cover - sized above
        raise AssertionError("the multi-turn expansion did not fill its output")
    order = np.lexsort(tuple(out[:, j] for j in range(5, -1, -1)) + (config_number(out),))
    return out[order]


def ik(robot: Robot, T: ArrayLike, config: Config = 1, *, seed: ArrayLike | None = None,
       within_limits: bool = False) -> np.ndarray:
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
        also splits q4 / q7 at a straight wrist, and gives q1 where axis 7 or axis 4 lies on
        axis 1 (the pose leaves it free). Periodic: joints beyond
        ``ik7r.robot.family.MAX_JOINT_ANGLE`` are reduced modulo 2 pi first.
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
    T = _one_pose(T, "ik_batch")
    hint, has = _seed(seed, (6,), T)
    Bm, bnorm = bernstein_tables(robot.kernel_params)
    sols = np.empty((MAX_SOLUTIONS, 6))
    q = np.empty(6)
    n, found = ik_one(T, ORTHONORMAL_TOL, robot.kernel_params, Bm, bnorm, arm, elbow, wrist,
                      hint, has, bool(within_limits), sols, q)
    if found:
        return q
    if n < 0:
        _bad_input(T, seed)
    sols = sols[:n]
    what = describe_config(arm, elbow, wrist)
    if len(sols) == 0:
        raise UnreachableError(f"the pose is out of reach: no solution in any configuration ({what} asked)")
    have = sorted(set(int(c) for c in config_number(sols)))
    limits = " within the joint limits" if within_limits else ""
    raise UnreachableError(
        f"no solution in {what}{limits}; the pose has {len(sols)} solutions, in configurations {have}"
    )


def ik_batch(robot: Robot, T: ArrayLike, config: Config = 1, *, seed: ArrayLike | None = None,
             within_limits: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """:func:`ik` for many poses at once.

    Parameters
    ----------
    T : array_like, shape (N, 4, 4)
    config : int or (arm, elbow, wrist)
    seed : array_like, shape (6,) or (N, 6), optional
        Periodic, as in :func:`ik`. One (6,) seed must be finite; of (N, 6) seeds, a row with
        NaN or infinity makes only its pose not ok.

    Returns
    -------
    q : ndarray, shape (N, 6)
        Solutions (rad); rows that are not ok hold NaN.
    ok : ndarray, shape (N,), bool
        False for a bad pose (NaN, non-orthonormal rotation), a bad seed row or an unreachable
        pose; every other row is still solved.
    """
    arm, elbow, wrist = check_config(config)
    T = pose_batch(T)
    n = T.shape[0]
    seeds, has, seed_ok = _batch_seeds(seed, n)
    q = np.empty((n, 6))
    ok = np.empty(n, dtype=bool)
    Tc = np.empty_like(T)
    good = np.empty(n, dtype=bool)
    Bm, bnorm = bernstein_tables(robot.kernel_params)
    K = robot.kernel_params

    def work(a, b):
        poses_status_into(T[a:b], Tc[a:b], good[a:b])
        if seed_ok is not None:
            good[a:b] &= seed_ok[a:b]
        config_rows(Tc[a:b], K, Bm, bnorm, arm, elbow, wrist, seeds[a:b] if has else seeds, has,
                    bool(within_limits), good[a:b], q[a:b], ok[a:b])

    _in_threads(n, work)
    return q, ok


def ik_all_batch(robot: Robot, T: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
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
    T = pose_batch(T)
    n = T.shape[0]
    out = np.empty((n, MAX_SOLUTIONS, 6))
    counts = np.empty(n, dtype=np.int64)
    Tc = np.empty_like(T)
    good = np.empty(n, dtype=bool)
    Bm, bnorm = bernstein_tables(robot.kernel_params)
    K = robot.kernel_params

    def work(a, b):
        poses_status_into(T[a:b], Tc[a:b], good[a:b])
        all_rows(Tc[a:b], K, Bm, bnorm, good[a:b], out[a:b], counts[a:b])

    _in_threads(n, work)
    valid = np.arange(MAX_SOLUTIONS)[None, :] < counts[:, None]
    return out, valid
