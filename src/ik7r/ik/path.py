"""Inverse kinematics along a path of poses: the one path follower.

:func:`ik_path` solves poses in order, each from the previous solution, and keeps one solution
branch as long as it can; where it cannot, it takes the configuration's solution nearest the
previous one (a jump, reported by ``tracked``). Two ways to continue a branch from one pose to
the next, chosen by the arguments:

the compiled follower (``keep="config"``, no ``pose_at``; the default)
    a few Newton steps on the full forward kinematics from the previous solution (linearly
    extrapolated), taken when they verify, keep the configuration's indicators and move no
    joint more than ``max_step``; the complete solver otherwise. About 1 us a pose: the way to
    follow a densely sampled path (:mod:`ik7r._kernels.track`).
the branch follower (``pose_at=`` and ``u=``, or ``keep="branch"``)
    the next solution is the one, among *all* the pose's solutions within the joint limits
    (multi-turn equivalents of q4 / q7 included, every configuration), nearest the previous
    one; a joint step larger than ``max_step`` is bisected along the continuous path
    ``pose_at(u)`` between the two poses (:func:`follow`) until every sub-step is small, so
    fast but continuous motion is told apart from a jump to another branch. With
    ``keep="branch"`` the branch is followed across indicator boundaries (theta5 crossing 0
    flips the Wrist indicator); with ``keep="config"`` a continuation that leaves the
    configuration is refused. Every row where the branch was lost says why
    (:attr:`PathIK.lost`). It runs in Python over the complete solver (tens of us a pose); the
    painting trajectories use it (:func:`ik7r.painting.solve_path`, which turns its answers
    into events).

Why one function and two continuations, not one compiled loop: the bisection evaluates the path
between poses (a painting path's spline and rotation interpolation, any callable), which a
compiled kernel cannot call back into, and painting needs the diagnosis of a lost branch; the
dense discrete case needs neither and is 10 to 50 times faster compiled. The policy (continue
the branch, else the configuration's solution nearest the previous), the inputs and the result
are shared. Every row either follower returns is exact (forward kinematics within the robot's
tolerances).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from contextlib import nullcontext
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..errors import UnreachableError
from ..geometry.checks import check_config, check_joints, poses_status, reduce_seeds
from ..geometry.configs import config_number, config_of_indicators
from ..geometry.rotations import wrap_angle
from ..robot.model import JOINT_LABELS

if TYPE_CHECKING:
    from .._typing import ArrayLike, Config
    from ..progress import Progress
    from ..robot.model import Robot

__all__ = ["PathIK", "Lost", "PoseAt", "ik_path", "follow", "in_configuration", "wrist_singularity_distance",
           "DEFAULT_MAX_DEPTH", "LIMIT_SLACK"]

#: Bisection depth of the branch follower: a path step is cut into at most 2**depth sub-steps.
DEFAULT_MAX_DEPTH = 12
#: Joint-limit slack (rad): values this close outside a limit count as on it.
LIMIT_SLACK = 1e-9
#: theta5 this close (rad) to 0 or 180 deg when the branch is lost: the wrist flips.
_FLIP_ZONE = math.radians(10.0)

#: A pose along the path: ``pose_at(u)`` -> world <- tool pose (4, 4) at path parameter ``u``.
PoseAt = Callable[[float], np.ndarray]


@dataclass(frozen=True)
class Lost:
    """Why the branch follower could not continue the branch into a row: where and what.

    Attributes
    ----------
    u : float
        Path parameter where the branch was lost (between the row's and the previous row's).
    q_last : ndarray, shape (6,)
        The last solution on the branch (rad): where the follower stood when it lost it (the
        previous row, or a sub-step of the bisection).
    reason : str
        A sentence: a joint limit, the edge of the workspace, a wrist flip, leaving the
        configuration.
    limit : (joint, value, limit) or None
        The joint (0..5) that would pass its limit, the value it would reach and the limit (rad).
    continued : ndarray, shape (6,), or None
        The continuation that was found but refused because it leaves the configuration
        (``keep="config"``); None when no continuation was found.
    """

    u: float
    q_last: np.ndarray
    reason: str
    limit: tuple[int, float, float] | None = None
    continued: np.ndarray | None = None


@dataclass(frozen=True)
class PathIK:
    """Joint solutions along a path.

    Attributes
    ----------
    q : ndarray, shape (N, 6)
        Joints (rad), continuous along the path (not wrapped); NaN where not ``ok``.
    ok : ndarray, shape (N,), bool
        False for a bad pose or one without a solution in the configuration (within the
        limits when asked).
    tracked : ndarray, shape (N,), bool
        True where the row continues the previous row's branch: the warm start was enough
        (compiled follower) or the continuation along the path was kept (branch follower).
        False where the configuration's solution nearest the previous (or the seed) was taken:
        the first pose, rows after a gap, branch changes, jumps larger than ``max_step``.
    lost : dict of int to Lost
        The branch follower's diagnosis of every row where the branch was lost and the
        configuration's solution was taken instead (row index -> :class:`Lost`); empty from the
        compiled follower, which does not diagnose.
    """

    q: np.ndarray
    ok: np.ndarray
    tracked: np.ndarray
    lost: dict[int, Lost] = field(default_factory=dict)

    @property
    def full_solves(self) -> int:
        """Number of rows that are not a continuation of the previous one (they needed the
        complete solver's choice in the configuration)."""
        return int(np.count_nonzero(self.ok & ~self.tracked))


def in_configuration(q: ArrayLike, config: Config) -> bool:
    """``q`` (6,) is in configuration ``config``, by the solver's own rule
    (:func:`ik7r._kernels.matches`): a solution on a boundary between configurations belongs
    to both."""
    from .._kernels import matches  # here: importing a kernel imports numba

    return bool(matches(np.ascontiguousarray(q, dtype=float), *check_config(config)))


def wrist_singularity_distance(q5: ArrayLike) -> np.ndarray:
    """Distance of theta5 (rad) from the wrist singularities 0 and pi (rad)."""
    a = np.abs(wrap_angle(q5))
    return np.minimum(a, np.pi - a)


def _limit_violation(robot: Robot, q: np.ndarray) -> tuple[int, float, float] | None:
    """(joint, value, limit) of the joint of ``q`` farthest outside its range, or None."""
    over = np.maximum(q - robot.upper, robot.lower - q)
    j = int(np.argmax(over))
    if over[j] <= LIMIT_SLACK:
        return None
    limit = robot.upper[j] if q[j] > robot.upper[j] else robot.lower[j]
    return j, float(q[j]), float(limit)


def _diagnose(robot: Robot, q_a: np.ndarray, u_b: float, T_b: np.ndarray, max_step: float) -> Lost:
    sols = robot.ik_all(T_b, seed=q_a)
    if len(sols) == 0:
        return Lost(u_b, q_a, "the path leaves the reachable workspace (no solution at all)")
    near = q_a + wrap_angle(sols - q_a)
    d = np.abs(near - q_a).max(axis=1)
    k = int(np.argmin(d))
    if d[k] <= max_step:
        lim = _limit_violation(robot, near[k])
        if lim is not None:
            j, v, L = lim
            side = "upper" if v > L else "lower"
            return Lost(u_b, q_a, f"{JOINT_LABELS[j]} would pass its {side} limit "
                                  f"{math.degrees(L):.3f} deg (reaching {math.degrees(v):.3f} deg)", lim)
    w = float(wrist_singularity_distance(q_a[4]))
    if w < _FLIP_ZONE:
        why = (f"near the wrist singularity (theta5 = {math.degrees(q_a[4]):.3f} deg) q4 and q7 turn faster "
               f"than the path can be followed: the wrist flips")
    else:
        why = ("the solution branch ends (it merges with another solution: a singularity or the edge of "
               "the workspace)")
    return Lost(u_b, q_a, why)


def follow(robot: Robot, pose_at: PoseAt | None, q_from: ArrayLike, u_from: float, u_to: float, *,
           max_step: float, max_depth: int = DEFAULT_MAX_DEPTH,
           T_to: ArrayLike | None = None) -> tuple[np.ndarray | None, Lost | None]:
    """Follow the solution branch through ``q_from`` (at ``pose_at(u_from)``) to ``u_to``: the
    branch follower's step.

    Parameters
    ----------
    robot : Robot
    pose_at : callable or None
        ``pose_at(u)`` -> world <- tool pose (4, 4) along the continuous path; None: no
        bisection (``T_to`` is then required).
    q_from : array_like, shape (6,)
        A solution (rad) of the pose at ``u_from``.
    u_from, u_to : float
        Path parameters.
    max_step : float
        Largest joint change (rad) accepted between sub-samples; larger steps are bisected.
    max_depth : int
        Most bisections.
    T_to : array_like, shape (4, 4), optional
        The world pose at ``u_to`` if already known.

    Returns
    -------
    q : ndarray, shape (6,) or None
        The solution at ``u_to`` on the same branch (within the joint limits), or None.
    lost : Lost or None
        Where and why the branch could not be followed (None on success).
    """
    q_from = check_joints(q_from, "q_from")
    if T_to is not None:
        T_b = np.asarray(T_to)
    elif pose_at is not None:
        T_b = pose_at(u_to)
    else:
        raise ValueError("follow needs pose_at or T_to (the pose at u_to)")

    def step(q_a: np.ndarray, u_a: float, u_b: float, T_b: np.ndarray,
             depth: int) -> tuple[np.ndarray | None, Lost | None]:
        sols = robot.ik_all(T_b, within_limits=True, seed=q_a)
        if len(sols):
            d = np.abs(sols - q_a).max(axis=1)
            k = int(np.argmin(d))
            if d[k] <= max_step:
                return sols[k], None
        if depth == 0 or pose_at is None:
            return None, _diagnose(robot, q_a, u_b, T_b, max_step)
        u_m = 0.5 * (u_a + u_b)
        T_m = pose_at(u_m)
        q_m, lost = step(q_a, u_a, u_m, T_m, depth - 1)
        if q_m is None:
            return None, lost
        return step(q_m, u_m, u_b, T_b, depth - 1)

    return step(q_from, float(u_from), float(u_to), T_b, max_depth)


def ik_path(robot: Robot, T: ArrayLike, config: Config = 1, *, seed: ArrayLike | None = None,
            within_limits: bool = False, max_step: float = 0.2, keep: str = "config",
            pose_at: PoseAt | None = None, u: ArrayLike | None = None,
            max_depth: int = DEFAULT_MAX_DEPTH, progress: bool = False) -> PathIK:
    """Solve a path of poses in order, each from the previous solution.

    Parameters
    ----------
    robot : Robot
    T : array_like, shape (N, 4, 4)
        World <- tool poses along the path (robot length unit).
    config : int or (arm, elbow, wrist)
        The configuration (1..8, the paper's Appendix 3) of the first pose, of every pose with
        ``keep="config"``, and of the solution taken where the branch is lost.
    seed : array_like, shape (6,), optional
        Joints (rad) to start from; without it the first pose takes the solution nearest the
        zero posture. Periodic: joints beyond ``ik7r.robot.family.MAX_JOINT_ANGLE`` are reduced
        modulo 2 pi first (the rows then continue from the reduced value).
    within_limits : bool
        Keep every row inside the joint limits (multi-turn joints included). The branch
        follower always works within them (it needs ``within_limits=True``).
    max_step : float
        Largest joint change (rad) accepted as continuing the branch: from the warm start
        between consecutive poses (compiled follower; a larger one goes to the complete solver,
        which picks the solution nearest the previous), or between sub-samples of the bisection
        (branch follower).
    keep : {"config", "branch"}
        ``"config"``: every row is in ``config``; a continuation that leaves it is refused and
        the configuration's solution nearest the previous taken (a jump). ``"branch"`` (branch
        follower): the joints stay continuous across indicator boundaries (theta5 crossing 0
        flips the Wrist indicator) and the configuration may change.
    pose_at : callable, optional
        ``pose_at(u)`` -> the world <- tool pose (4, 4) at path parameter ``u``, the continuous
        path the poses ``T`` sample (``T[i] = pose_at(u[i])``): the branch follower bisects a
        large joint step along it. Needs ``u``.
    u : array_like, shape (N,), optional
        The path parameter of each pose, in path order; with ``pose_at``.
    max_depth : int
        Most bisections of one step (branch follower with ``pose_at``): at most
        ``2**max_depth`` sub-steps.
    progress : bool
        Draw a progress bar on stderr (only when it is a terminal).

    Returns
    -------
    PathIK
        ``q``, ``ok``, ``tracked``; from the branch follower also ``lost`` (why the branch was
        lost at each jump).

    Examples
    --------
    >>> import numpy as np, ik7r
    >>> robot = ik7r.load_robot()
    >>> q = np.radians([10, 40, -20, 30, 50, -40]) + np.linspace(0, 0.3, 20)[:, None]
    >>> fast = robot.ik_path(robot.fk(q), config=1, seed=q[0])
    >>> branch = robot.ik_path(robot.fk(q), config=1, seed=q[0], keep="branch", within_limits=True)
    >>> bool(fast.ok.all()), bool(np.allclose(fast.q, q)), bool(np.allclose(branch.q, q))
    (True, True, True)
    """
    arm, elbow, wrist = check_config(config)
    Tc, good = poses_status(T)
    if Tc.ndim != 3:
        raise ValueError(f"T must have shape (N, 4, 4) (a path of poses); got {Tc.shape}")
    if not (np.isfinite(max_step) and max_step > 0):
        raise ValueError(f"max_step must be a positive angle in rad; got {max_step!r}")
    if keep not in ("config", "branch"):
        raise ValueError(f"keep must be 'config' or 'branch'; got {keep!r}")
    n = Tc.shape[0]
    uu = None
    if pose_at is not None or u is not None:
        if pose_at is None or u is None or not callable(pose_at):
            raise ValueError("pose_at (a callable u -> pose (4, 4)) and u (the path parameter of each "
                             "pose) go together")
        uu = np.asarray(u, dtype=float)
        if uu.shape != (n,) or not np.all(np.isfinite(uu)):
            raise ValueError(f"u must hold one finite path parameter per pose, shape ({n},); got "
                             f"shape {uu.shape}")
    branch = uu is not None or keep == "branch"
    if branch and not within_limits:
        raise ValueError("the branch follower (keep='branch' or pose_at=) works within the joint limits: "
                         "pass within_limits=True")
    if branch and not (isinstance(max_depth, (int, np.integer)) and 0 <= max_depth <= 60):
        raise ValueError(f"max_depth must be an integer from 0 to 60; got {max_depth!r}")
    has_seed = seed is not None
    s = check_joints(seed, "seed").astype(float) if seed is not None else np.zeros(6)
    if s.shape != (6,):
        raise ValueError(f"seed must have shape (6,); got {s.shape}")
    s = reduce_seeds(s)  # periodic: joints beyond MAX_JOINT_ANGLE are reduced modulo 2 pi
    from ..progress import Progress

    bar = Progress(n, "solving the path") if progress else None
    with bar if bar is not None else nullcontext():
        if branch:
            res = _branch_path(robot, np.asarray(T, dtype=float), good,
                               int(config_of_indicators(arm, elbow, wrist)), s if has_seed else None,
                               keep, max_step, pose_at, uu, int(max_depth), bar)
        else:
            res = _compiled_path(robot, Tc, good, (arm, elbow, wrist), s, has_seed, within_limits, max_step)
            if bar is not None:
                bar.advance(n)
    for arr in (res.q, res.ok, res.tracked):
        arr.setflags(write=False)
    return res


def _compiled_path(robot: Robot, Tc: np.ndarray, good: np.ndarray, indicators: tuple[int, int, int],
                   s: np.ndarray, has_seed: bool, within_limits: bool, max_step: float) -> PathIK:
    from .._kernels import bernstein_tables, track_path

    n = Tc.shape[0]
    q = np.empty((n, 6))
    ok = np.zeros(n, dtype=bool)
    tracked = np.zeros(n, dtype=bool)
    Bm, bnorm = bernstein_tables(robot.kernel_params)
    track_path(np.ascontiguousarray(Tc), robot.kernel_params, Bm, bnorm, *indicators,
               np.ascontiguousarray(s), has_seed, bool(within_limits), float(max_step),
               np.ascontiguousarray(good), q, ok, tracked)
    return PathIK(q=q, ok=ok, tracked=tracked)


def _branch_path(robot: Robot, T: np.ndarray, good: np.ndarray, cfg: int, seed: np.ndarray | None,
                 keep: str, max_step: float, pose_at: PoseAt | None, u: np.ndarray | None,
                 max_depth: int, bar: Progress | None) -> PathIK:
    """The branch follower over the poses ``T`` (N, 4, 4) (see :func:`ik_path`)."""
    n = T.shape[0]
    u = np.arange(n, dtype=float) if u is None else u
    q = np.full((n, 6), np.nan)
    tracked = np.zeros(n, dtype=bool)
    lost: dict[int, Lost] = {}
    prev = None  # the previous row's solution, None at the start and after a gap
    last_good = seed  # the seed of a (re)start: the last solution found
    for i in range(n):
        if bar is not None:
            bar.advance(1)
        if not good[i]:
            prev = None
            continue
        if prev is None:
            try:
                q[i] = robot.ik(T[i], cfg, seed=last_good, within_limits=True)
            except UnreachableError:
                continue
            prev = last_good = q[i]
            continue
        cont, why = follow(robot, pose_at, prev, u[i - 1], u[i], max_step=max_step, max_depth=max_depth,
                           T_to=T[i])
        if cont is not None:
            if keep == "branch" or in_configuration(cont, cfg):
                q[i] = cont
                tracked[i] = True
                prev = last_good = cont
                continue
            why = Lost(float(u[i]), prev, f"the continuous solution leaves configuration {cfg} (to "
                                          f"{int(config_number(cont))}); keeping configuration {cfg} "
                                          f"turns the wrist over", continued=cont)
        assert why is not None
        lost[i] = why
        try:
            chosen = robot.ik(T[i], cfg, seed=prev, within_limits=True)
        except UnreachableError:
            prev = None
            continue
        q[i] = chosen
        prev = last_good = chosen
    ok = np.all(np.isfinite(q), axis=1)
    return PathIK(q=q, ok=ok, tracked=tracked, lost=lost)
