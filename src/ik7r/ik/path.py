"""Warm-started inverse kinematics along a path of poses (trajectories, painting strokes).

:func:`ik_path` solves poses in order, each from the previous solution: a few Newton steps on
the full forward kinematics when they verify and keep the configuration, the complete solver
otherwise. It is the fast way to follow a densely sampled path; every row it returns is exact.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..geometry.checks import check_config, check_joints, poses_status, reduce_seeds

if TYPE_CHECKING:
    from .._typing import ArrayLike, Config
    from ..robot.model import Robot

__all__ = ["PathIK", "ik_path"]


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
        True where the warm start from the previous row was enough (False where the complete
        solver was needed: the first pose, branch changes, jumps larger than ``max_step``).
    """

    q: np.ndarray
    ok: np.ndarray
    tracked: np.ndarray

    @property
    def full_solves(self) -> int:
        """Number of poses that needed the complete solver."""
        return int(np.count_nonzero(self.ok & ~self.tracked))


def ik_path(robot: Robot, T: ArrayLike, config: Config = 1, *, seed: ArrayLike | None = None,
            within_limits: bool = False,
            max_step: float = 0.2) -> PathIK:
    """Solve a path of poses in order, each from the previous solution.

    Parameters
    ----------
    robot : Robot
    T : array_like, shape (N, 4, 4)
        World <- tool poses along the path (robot length unit).
    config : int or (arm, elbow, wrist)
        The configuration to keep (1..8, the paper's Appendix 3).
    seed : array_like, shape (6,), optional
        Joints (rad) to start from; without it the first pose takes the solution nearest the
        zero posture. Periodic: joints beyond ``ik7r.robot.family.MAX_JOINT_ANGLE`` are reduced modulo
        2 pi first (the rows then continue from the reduced value).
    within_limits : bool
        Keep every row inside the joint limits (multi-turn joints included).
    max_step : float
        Largest joint change (rad) accepted from the warm start between consecutive poses; a
        larger one goes to the complete solver, which picks the solution nearest the previous.

    Returns
    -------
    PathIK
    """
    from .._kernels import bernstein_tables, track_path

    arm, elbow, wrist = check_config(config)
    Tc, good = poses_status(T)
    if Tc.ndim != 3:
        raise ValueError(f"T must have shape (N, 4, 4) (a path of poses); got {Tc.shape}")
    if not (np.isfinite(max_step) and max_step > 0):
        raise ValueError(f"max_step must be a positive angle in rad; got {max_step!r}")
    has_seed = seed is not None
    s = check_joints(seed, "seed").astype(float) if seed is not None else np.zeros(6)
    if s.shape != (6,):
        raise ValueError(f"seed must have shape (6,); got {s.shape}")
    s = reduce_seeds(s)  # periodic: joints beyond MAX_JOINT_ANGLE are reduced modulo 2 pi
    n = Tc.shape[0]
    q = np.empty((n, 6))
    ok = np.zeros(n, dtype=bool)
    tracked = np.zeros(n, dtype=bool)
    Bm, bnorm = bernstein_tables(robot.kernel_params)
    track_path(np.ascontiguousarray(Tc), robot.kernel_params, Bm, bnorm, arm, elbow, wrist,
               np.ascontiguousarray(s), has_seed, bool(within_limits), float(max_step),
               np.ascontiguousarray(good), q, ok, tracked)
    for arr in (q, ok, tracked):
        arr.setflags(write=False)
    return PathIK(q=q, ok=ok, tracked=tracked)
