"""Trajectory inverse kinematics: one joint solution per path sample, continuous along the path.

:func:`solve_path` solves the first sample in the requested configuration (nearest ``seed``,
within the joint limits), then follows the solution branch: each next sample's solution is
the one, among *all* solutions within the limits (multi-turn equivalents of q4 / q7 included),
nearest the previous one. A step larger than ``max_step`` in any joint is bisected along the
path (:func:`track`) until every sub-step is small: a branch that cannot be followed that way
has ended (a joint limit, the edge of the workspace, a wrist flip near theta5 = 0).

The following itself is the one path follower, :func:`ik7r.ik.path.ik_path` (its branch
follower: ``pose_at=`` the path, ``within_limits=True``); this module turns its answers (which
rows continue the branch, and why the branch was lost where it was) into events.

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
from dataclasses import dataclass
from functools import partial

import numpy as np

from ..geometry.checks import check_config, check_joints
from ..geometry.configs import config_number, config_of_indicators
from ..geometry.rotations import wrap_angle
from ..ik.path import DEFAULT_MAX_DEPTH, LIMIT_SLACK, Lost, follow, ik_path, wrist_singularity_distance
from ..ik.path import in_configuration as _matches  # noqa: F401  (the painting name of the rule)
from ..robot.model import JOINT_LABELS
from .events import (
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
#: Distance of theta5 from 0 or 180 deg (rad) reported as :class:`NearSingularity`.
DEFAULT_SINGULAR_MARGIN = math.radians(5.0)


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
def _world(robot: Robot, T_base: np.ndarray) -> np.ndarray:
    """World <- tool from base <- tool poses (the robot's ``base`` placement)."""
    return robot.base @ T_base


def _pose_at(robot: Robot, path: Path, u: float) -> np.ndarray:
    P, R = path.at(np.array([u]))
    T = np.eye(4)
    T[:3, :3] = R[0]
    T[:3, 3] = P[0]
    return _world(robot, T)


def _in_range_by_turns(robot: Robot, q: np.ndarray) -> np.ndarray:
    """Per joint: can a multiple of 2 pi bring ``q`` (6,) inside the limits?"""
    k = np.ceil((robot.lower - q) / (2 * np.pi) - 1e-12)
    return q + 2 * np.pi * k <= robot.upper + LIMIT_SLACK


def track(robot: Robot, path: Path, q_from: ArrayLike, u_from: float, u_to: float, *,
          max_step: float = DEFAULT_MAX_STEP, max_depth: int = DEFAULT_MAX_DEPTH,
          T_to: ArrayLike | None = None) -> tuple[np.ndarray | None, Lost | None]:
    """Follow the solution branch through ``q_from`` (at ``path.at(u_from)``) to ``u_to``.

    The path follower's step, :func:`ik7r.ik.path.follow` (its parameters and returns), along
    the painting :class:`Path` ``path`` (its poses placed in the world by the robot's ``base``),
    with painting's defaults (``max_step`` 3 deg).
    """
    return follow(robot, partial(_pose_at, robot, path), q_from, u_from, u_to, max_step=max_step,
                  max_depth=max_depth, T_to=T_to)


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
    best: tuple[np.ndarray, np.ndarray] | None = None
    best_key: tuple[int, float] | None = None
    for q in mine:
        bad = ~_in_range_by_turns(robot, q)
        excess = np.where(bad, np.minimum(np.abs(wrap_angle(q - robot.upper)),
                                          np.abs(wrap_angle(robot.lower - q))), 0.0)
        key = (int(bad.sum()), float(excess.sum()))
        if best is None or best_key is None or key < best_key:
            best, best_key = (q, bad), key
    assert best is not None  # mine is not empty
    q, bad = best
    parts = [f"{JOINT_LABELS[j]} = {math.degrees(q[j]):.3f} deg outside [{math.degrees(robot.lower[j]):.0f}, "
             f"{math.degrees(robot.upper[j]):.0f}] deg" for j in np.flatnonzero(bad)]
    tail = (f"; solutions within the limits exist in configurations {others}" if others
            else "; no solution within the limits in any configuration")
    return "limits", f"outside the joint limits in configuration {config}", ", ".join(parts) + tail


def _sample_position(path: Path, i: int) -> tuple[float, float, float]:
    """The position of sample ``i`` (length unit), for an event."""
    x, y, z = (float(v) for v in path.positions[i])
    return x, y, z


def _group_unreachable(unreach: dict, path: Path, unit: str) -> list[tuple[int, PathEvent]]:
    out: list[tuple[int, PathEvent]] = []
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
        out.append((first, Unreachable(first, last, reason, _sample_position(path, first), unit)))
        start = end + 1
    return out


def _near_singular(q: np.ndarray, ok: np.ndarray, margin: float) -> list[tuple[int, PathEvent]]:
    if margin <= 0:
        return []
    dist = np.full(len(q), np.inf)
    dist[ok] = wrist_singularity_distance(q[ok, 4])
    near = dist < margin
    out: list[tuple[int, PathEvent]] = []
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

    n = len(path)
    T_all = _world(robot, path.transforms)
    res = ik_path(robot, T_all, cfg, seed=seed0, within_limits=True, max_step=max_step, keep=keep,
                  pose_at=partial(_pose_at, robot, path), u=path.u, progress=progress)
    q = np.array(res.q)
    unit = robot.unit
    tagged: list[tuple[int, PathEvent]] = []
    unreach: dict[int, tuple[str, str, str]] = {}

    def pos(i: int) -> tuple[float, float, float]:
        return _sample_position(path, i)

    def crossing(i: int, prev: np.ndarray, cont: np.ndarray) -> None:
        """The events of the continuous branch from ``prev`` (row i - 1) to ``cont`` (row i)."""
        c_prev, c_new = int(config_number(prev)), int(config_number(cont))
        if c_new == c_prev:
            return
        ind_prev, ind_new = robot.indicators(prev), robot.indicators(cont)
        if ind_prev[2] != ind_new[2] and np.array_equal(ind_prev[:2], ind_new[:2]):
            angle = 0.0 if abs(wrap_angle(prev[4])) < np.pi / 2 else np.pi
            tagged.append((i, WristCrossing(i, angle, float(prev[4]), float(cont[4]), c_prev, c_new,
                                            pos(i), unit)))
        else:
            tagged.append((i, ConfigChange(i, c_prev, c_new, pos(i), unit)))

    last_good = seed0  # the solution the follower (re)started from: the last one found
    for i in range(n):
        lost = res.lost.get(i)
        if res.tracked[i]:
            crossing(i, q[i - 1], q[i])
        elif lost is not None:
            if lost.continued is not None:
                crossing(i, q[i - 1], lost.continued)
            if lost.limit is not None:
                j, v, L = lost.limit
                k = int(np.clip(np.searchsorted(path.u, lost.u), 0, n - 1))
                tagged.append((i, JointLimit(j, v, L, index=k, position=pos(k), unit=unit)))
            if res.ok[i]:
                jump = np.abs(q[i] - q[i - 1])  # a row is lost only after a solved one
                j = int(np.argmax(jump))
                tagged.append((i, BranchChange(i, j, float(jump[j]), lost.reason, pos(i), unit)))
        if res.ok[i]:
            last_good = q[i]
        else:
            unreach[i] = _why_unreachable(robot, T_all[i], cfg, last_good)

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
