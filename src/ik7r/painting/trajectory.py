"""Trajectory inverse kinematics: one joint solution per path sample, continuous along the path.

:func:`solve_path` solves the first sample in the requested configuration (nearest ``seed``,
within the joint limits), then follows the solution branch: each next sample's solution is
the one, among *all* solutions within the limits (multi-turn equivalents of q4 / q7 included),
nearest the previous one. A step larger than ``max_step`` in any joint is bisected along the
path (:func:`track`) until every sub-step is small: a branch that cannot be followed that way
has ended (a joint limit, the edge of the workspace, a wrist flip near theta5 = 0).

Nothing is hidden: an unreachable sample, a jump to another branch, a crossing of
theta5 = 0 (the Wrist indicator flips by definition), a joint limit, and a stretch close to
a wrist singularity are reported as events (:mod:`ik7r.painting.events`).

Two policies say what to do when the continuous branch leaves the requested configuration
(in practice: theta5 crosses 0 on a path through the wrist singularity):

``keep="config"`` (default, the paper's)
    every sample stays in ``config``; leaving it is a :class:`BranchChange` (the joints jump;
    blocking), reported with the :class:`WristCrossing` that caused it.
``keep="branch"``
    the joints stay continuous and the configuration changes; the :class:`WristCrossing` is
    reported as a warning.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .._typing import ArrayLike, Config
    from ..robot.model import Robot

import math
from contextlib import nullcontext
from dataclasses import dataclass

import numpy as np

from ..errors import UnreachableError
from ..geometry.checks import check_config, check_joints
from ..geometry.configs import config_number, config_of_indicators
from ..geometry.rotations import wrap_angle
from .events import (
    JOINT_LABELS,
    BranchChange,
    ConfigChange,
    JointLimit,
    NearSingularity,
    PathEvent,
    Unreachable,
    WristCrossing,
    format_report,
)
from .paths import Path

__all__ = ["PathSolution", "solve_path", "track", "DEFAULT_MAX_STEP", "DEFAULT_SINGULAR_MARGIN"]

#: Largest joint step (rad) between consecutive (sub-)samples accepted as continuous motion.
DEFAULT_MAX_STEP = math.radians(3.0)
#: Bisection depth of :func:`track`: a path step is cut into at most 2**depth sub-steps.
DEFAULT_MAX_DEPTH = 12
#: Distance of theta5 from 0 or 180 deg (rad) reported as :class:`NearSingularity`.
DEFAULT_SINGULAR_MARGIN = math.radians(5.0)
#: Joint-limit slack (rad): values this close outside a limit count as on it.
_LIMIT_SLACK = 1e-9


@dataclass(frozen=True, eq=False)
class PathSolution:
    """Joint solutions along a path.

    Attributes
    ----------
    path : Path
    q : ndarray, shape (N, 6)
        ``[q1, q2, q3, q4, q5, q7]`` (rad) per sample, continuous and within the joint limits
        (multi-turn values kept, not wrapped); NaN rows at unreachable samples.
    ok : ndarray, shape (N,), bool
        Samples that have a solution.
    configs : ndarray, shape (N,), int
        Configuration number (1..8) per sample; 0 where unreachable.
    config : int
        The configuration asked for.
    keep : str
        The policy (``"config"`` or ``"branch"``).
    events : list of PathEvent
        What happened, in path order.
    """

    path: Path
    q: np.ndarray
    ok: np.ndarray
    configs: np.ndarray
    config: int
    keep: str
    events: list

    @property
    def feasible(self) -> bool:
        """True when a continuous joint trajectory follows the whole path (no blocking event)."""
        return bool(np.all(self.ok)) and not any(e.blocking for e in self.events)

    def report(self) -> str:
        """The events, one per line."""
        return format_report(self.events)


# ----------------------------------------------------------------------------- helpers
def _world(robot, T_base) -> np.ndarray:
    """World <- tool from base <- tool poses (the robot's ``base`` placement)."""
    return robot.base @ T_base


def _pose_at(robot, path: Path, u: float) -> np.ndarray:
    P, R = path.at(np.array([u]))
    T = np.eye(4)
    T[:3, :3] = R[0]
    T[:3, 3] = P[0]
    return _world(robot, T)


def _config_number(q) -> int:
    """Configuration number of one joint vector (the paper's Appendix 3)."""
    return int(config_number(q))


def _matches(q, cfg: int) -> bool:
    """``q`` is in configuration ``cfg``, by the solver's own rule (:func:`ik7r._kernels.matches`):
    a solution on a boundary between configurations belongs to both."""
    from .._kernels import matches  # here: importing a kernel imports numba

    return bool(matches(np.ascontiguousarray(q, dtype=float), *check_config(cfg)))


def _wrist_distance(q5) -> np.ndarray:
    """Distance of theta5 from the wrist singularities 0 and pi (rad)."""
    a = np.abs(wrap_angle(q5))
    return np.minimum(a, np.pi - a)


def _limit_violation(robot, q) -> tuple[int, float, float] | None:
    """(joint, value, limit) of the joint of ``q`` farthest outside its range, or None."""
    over = np.maximum(q - robot.upper, robot.lower - q)
    j = int(np.argmax(over))
    if over[j] <= _LIMIT_SLACK:
        return None
    limit = robot.upper[j] if q[j] > robot.upper[j] else robot.lower[j]
    return j, float(q[j]), float(limit)


def _in_range_by_turns(robot, q) -> np.ndarray:
    """Per joint: can a multiple of 2 pi bring ``q`` (6,) inside the limits?"""
    k = np.ceil((robot.lower - q) / (2 * np.pi) - 1e-12)
    return q + 2 * np.pi * k <= robot.upper + _LIMIT_SLACK


@dataclass(frozen=True)
class _Lost:
    """Why :func:`track` could not follow the branch: where and what."""

    u: float
    q_last: np.ndarray
    reason: str
    limit: tuple[int, float, float] | None = None


def _diagnose(robot, q_a: np.ndarray, u_b: float, T_b: np.ndarray, max_step: float) -> _Lost:
    sols = robot.ik_all(T_b, seed=q_a)
    if len(sols) == 0:
        return _Lost(u_b, q_a, "the path leaves the reachable workspace (no solution at all)")
    near = q_a + wrap_angle(sols - q_a)
    d = np.abs(near - q_a).max(axis=1)
    k = int(np.argmin(d))
    if d[k] <= max_step:
        lim = _limit_violation(robot, near[k])
        if lim is not None:
            j, v, L = lim
            side = "upper" if v > L else "lower"
            return _Lost(u_b, q_a, f"{JOINT_LABELS[j]} would pass its {side} limit "
                                   f"{math.degrees(L):.3f} deg (reaching {math.degrees(v):.3f} deg)", lim)
    w = float(_wrist_distance(q_a[4]))
    if w < 2 * DEFAULT_SINGULAR_MARGIN:
        why = (f"near the wrist singularity (theta5 = {math.degrees(q_a[4]):.3f} deg) q4 and q7 turn faster "
               f"than the path can be followed: the wrist flips")
    else:
        why = ("the solution branch ends (it merges with another solution: a singularity or the edge of "
               "the workspace)")
    return _Lost(u_b, q_a, why)


def track(robot: Robot, path: Path, q_from: ArrayLike, u_from: float, u_to: float, *,
          max_step: float = DEFAULT_MAX_STEP, max_depth: int = DEFAULT_MAX_DEPTH,
          T_to: ArrayLike | None = None) -> tuple[np.ndarray | None, _Lost | None]:
    """Follow the solution branch through ``q_from`` (at ``path.at(u_from)``) to ``u_to``.

    Parameters
    ----------
    robot : Robot
    path : Path
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
    lost : _Lost or None
        Where and why the branch could not be followed (None on success).
    """
    q_from = check_joints(q_from, "q_from")
    T_b = _pose_at(robot, path, u_to) if T_to is None else T_to

    def step(q_a, u_a, u_b, T_b, depth):
        sols = robot.ik_all(T_b, within_limits=True, seed=q_a)
        if len(sols):
            d = np.abs(sols - q_a).max(axis=1)
            k = int(np.argmin(d))
            if d[k] <= max_step:
                return sols[k], None
        if depth == 0:
            return None, _diagnose(robot, q_a, u_b, T_b, max_step)
        u_m = 0.5 * (u_a + u_b)
        T_m = _pose_at(robot, path, u_m)
        q_m, lost = step(q_a, u_a, u_m, T_m, depth - 1)
        if q_m is None:
            return None, lost
        return step(q_m, u_m, u_b, T_b, depth - 1)

    return step(q_from, float(u_from), float(u_to), T_b, max_depth)


def _why_unreachable(robot, T, config: int, seed) -> tuple[str, str, str]:
    """(category, headline, detail) saying why pose ``T`` has no solution in ``config`` within
    the joint limits."""
    sols = robot.ik_all(T, seed=seed)
    if len(sols) == 0:
        return "reach", "out of reach: no solution in any configuration", ""
    cfgs = robot.config_of(sols)
    mine = sols[cfgs == config]
    if len(mine) == 0:
        return "config", f"no solution in configuration {config}", (
            f"the pose's solutions are in configurations {sorted(set(int(c) for c in cfgs))}")
    inside = robot.ik_all(T, within_limits=True, seed=seed)
    others = sorted(set(int(c) for c in robot.config_of(inside))) if len(inside) else []
    # the configuration's solution with the fewest joints out of range, and by how much
    best, best_key = None, None
    for q in mine:
        bad = ~_in_range_by_turns(robot, q)
        excess = np.where(bad, np.minimum(np.abs(wrap_angle(q - robot.upper)),
                                          np.abs(wrap_angle(robot.lower - q))), 0.0)
        key = (int(bad.sum()), float(excess.sum()))
        if best_key is None or key < best_key:
            best, best_key = (q, bad), key
    q, bad = best
    parts = [f"{JOINT_LABELS[j]} = {math.degrees(q[j]):.3f} deg outside [{math.degrees(robot.lower[j]):.0f}, "
             f"{math.degrees(robot.upper[j]):.0f}] deg" for j in np.flatnonzero(bad)]
    tail = (f"; solutions within the limits exist in configurations {others}" if others
            else "; no solution within the limits in any configuration")
    return "limits", f"outside the joint limits in configuration {config}", ", ".join(parts) + tail


def _group_unreachable(unreach: dict, path: Path, unit: str) -> list[tuple[int, PathEvent]]:
    out = []
    idx = sorted(unreach)
    start = 0
    while start < len(idx):
        end = start
        cat = unreach[idx[start]][0]
        while end + 1 < len(idx) and idx[end + 1] == idx[end] + 1 and unreach[idx[end + 1]][0] == cat:
            end += 1
        first, last = idx[start], idx[end]
        _, head, detail = unreach[first]
        reason = head
        if detail:
            reason += f" (sample {first}: {detail}"
            if last != first and unreach[last][2] != detail:
                reason += f"; sample {last}: {unreach[last][2]}"
            reason += ")"
        pos = tuple(float(v) for v in path.positions[first])
        out.append((first, Unreachable(first, last, reason, pos, unit)))
        start = end + 1
    return out


def _near_singular(q: np.ndarray, ok: np.ndarray, margin: float) -> list[tuple[int, PathEvent]]:
    if margin <= 0:
        return []
    dist = np.full(len(q), np.inf)
    dist[ok] = _wrist_distance(q[ok, 4])
    near = dist < margin
    out = []
    i = 0
    while i < len(q):
        if near[i]:
            j = i
            while j + 1 < len(q) and near[j + 1]:
                j += 1
            turn = np.abs(q[j, [3, 5]] - q[i, [3, 5]])
            out.append((i, NearSingularity(i, j, float(dist[i:j + 1].min()), margin,
                                           float(turn[0]), float(turn[1]))))
            i = j + 1
        else:
            i += 1
    return out


# ----------------------------------------------------------------------------- solve_path
def solve_path(robot: Robot, path: Path, config: Config = 1, seed: ArrayLike | None = None, *,
               keep: str = "config",
               max_step: float = DEFAULT_MAX_STEP, singular_margin: float = DEFAULT_SINGULAR_MARGIN,
               progress: bool = False) -> PathSolution:
    """Solve every sample of ``path``, following one solution branch.

    Parameters
    ----------
    robot : Robot
        Its ``tool`` is the gun (the path is that of the tool); its ``base`` places the base frame
        in the world (the path is in the base frame).
    path : Path
        Tool poses in the base frame.
    config : int or (arm, elbow, wrist)
        Configuration (1..8, the paper's Appendix 3) of the first sample and, with
        ``keep="config"``, of every sample.
    seed : array_like, shape (6,), optional
        Joints (rad) the first sample's solution is nearest to (default: the zero posture).
    keep : {"config", "branch"}
        What to do when the continuous branch leaves ``config`` (see the module docstring).
    max_step : float
        Largest joint change (rad) between (sub-)samples accepted as continuous motion.
    singular_margin : float
        Report samples with theta5 closer than this (rad) to 0 or 180 deg (0: never).
    progress : bool
        Draw a progress bar on stderr (only when it is a terminal).

    Returns
    -------
    PathSolution
        Solutions and events; check ``feasible`` (or the events) before using ``q``.
    """
    if not isinstance(path, Path):
        raise ValueError(f"path must be an ik7r.painting.Path; got {type(path).__name__}")
    if keep not in ("config", "branch"):
        raise ValueError(f"keep must be 'config' or 'branch'; got {keep!r}")
    if not (math.isfinite(max_step) and max_step > 0):
        raise ValueError(f"max_step must be a positive number of rad; got {max_step!r}")
    arm, elbow, wrist = check_config(config)
    cfg = int(config_of_indicators(arm, elbow, wrist))
    seed0 = None if seed is None else check_joints(seed, "seed")

    from ..progress import Progress

    n = len(path)
    T_all = _world(robot, path.transforms)
    q = np.full((n, 6), np.nan)
    unit = robot.unit
    tagged: list[tuple[int, PathEvent]] = []
    unreach: dict[int, tuple[str, str, str]] = {}
    prev = None
    last_good = seed0

    def pos(i):
        return tuple(float(v) for v in path.positions[i])

    def by_config(i, seed_q):
        return robot.ik(T_all[i], cfg, seed=seed_q, within_limits=True)

    bar = Progress(n, "solving the path") if progress else nullcontext()
    with bar:
        for i in range(n):
            if progress:
                bar.advance(1)
            if prev is None:
                try:
                    q[i] = by_config(i, last_good)
                except UnreachableError:
                    unreach[i] = _why_unreachable(robot, T_all[i], cfg, last_good)
                    continue
                prev = q[i]
                last_good = prev
                continue
            cont, lost = track(robot, path, prev, path.u[i - 1], path.u[i], max_step=max_step,
                               T_to=T_all[i])
            chosen = None
            if cont is not None:
                c_prev, c_new = _config_number(prev), _config_number(cont)
                if c_new != c_prev:
                    ind_prev, ind_new = robot.indicators(prev), robot.indicators(cont)
                    if ind_prev[2] != ind_new[2] and np.array_equal(ind_prev[:2], ind_new[:2]):
                        angle = 0.0 if abs(wrap_angle(prev[4])) < np.pi / 2 else np.pi
                        tagged.append((i, WristCrossing(i, angle, float(prev[4]), float(cont[4]),
                                                        c_prev, c_new, pos(i), unit)))
                    else:
                        tagged.append((i, ConfigChange(i, c_prev, c_new, pos(i), unit)))
                if keep == "branch" or _matches(cont, cfg):
                    chosen = cont
                else:
                    reason = (f"the continuous solution leaves configuration {cfg} (to {c_new}); "
                              f"keeping configuration {cfg} turns the wrist over")
            else:
                reason = lost.reason
                if lost.limit is not None:
                    j, v, L = lost.limit
                    k = int(np.clip(np.searchsorted(path.u, lost.u), 0, n - 1))
                    tagged.append((i, JointLimit(j, v, L, index=k, position=pos(k), unit=unit)))
            if chosen is None:
                try:
                    chosen = by_config(i, prev)
                except UnreachableError:
                    unreach[i] = _why_unreachable(robot, T_all[i], cfg, prev)
                    prev = None
                    continue
                jump = np.abs(chosen - prev)
                j = int(np.argmax(jump))
                tagged.append((i, BranchChange(i, j, float(jump[j]), reason, pos(i), unit)))
            q[i] = chosen
            prev = chosen
            last_good = prev

    ok = np.all(np.isfinite(q), axis=1)
    tagged += _group_unreachable(unreach, path, unit)
    tagged += _near_singular(q, ok, singular_margin)
    order = sorted(range(len(tagged)), key=lambda k: (tagged[k][0], k))
    events = [tagged[k][1] for k in order]
    configs = np.zeros(n, dtype=int)
    if np.any(ok):
        configs[ok] = robot.config_of(q[ok])
    q.setflags(write=False)
    return PathSolution(path, q, ok, configs, cfg, keep, events)
