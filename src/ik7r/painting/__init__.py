"""Off-line painting programs: a painting path in, a smooth, checked joint trajectory out.

>>> import ik7r
>>> from ik7r.painting import paint_raster
>>> robot = ik7r.load_robot()
>>> result = paint_raster(robot, duration=20.0, config=1)   # the paper's Simulation 3
>>> result.trajectory.q.shape[1], result.events
(6, [])

The steps, each usable on its own:

1. a :class:`Path` of tool poses in the base frame (:func:`raster_path`, :func:`load_path_csv`,
   :func:`path_from_poses`);
2. :func:`solve_path`: one joint solution per sample on one continuous branch, with
   :mod:`events <ik7r.painting.events>` for anything a programmer must know;
3. :func:`interpolate`: a spline in joint space over the duration, checked against the path
   (0.01 mm by default) and the joint speed and acceleration limits;
4. :func:`write_trajectory_csv`, :func:`plot_joint_trajectory` (the paper's Figure 12),
   :func:`plot_path_3d`, :func:`animate_painting`.

Real parts (:func:`paint_mesh`): :mod:`~ik7r.painting.parts` (meshes), :mod:`~ik7r.painting.surface`
(rasters on a surface), :mod:`~ik7r.painting.spray` (guns), :mod:`~ik7r.painting.film` (film
thickness), :mod:`~ik7r.painting.view` (heat map, 3-D view).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..geometry.checks import check_transforms
from .events import (
    JOINT_LABELS,
    AccelerationLimit,
    BranchChange,
    ConfigChange,
    DeviationExceeded,
    JointLimit,
    NearSingularity,
    PathEvent,
    PathNotFeasible,
    SpeedLimit,
    TimeScaled,
    Unreachable,
    WristCrossing,
    format_report,
)
from .export import CSV_COLUMNS, trajectory_table, write_trajectory_csv
from .interpolate import DEFAULT_RAMP, DEFAULT_RATE, Timing, Trajectory, default_tolerance, interpolate
from .mesh import MeshPaintResult, paint_mesh
from .parts import BUILTIN_PARTS, Part, load_part
from .paths import (
    DEFAULT_ORIGIN,
    DEFAULT_SIZE,
    DEFAULT_SPACING,
    DEFAULT_STEP,
    GUN_DOWN,
    Path,
    load_path_csv,
    path_from_poses,
    raster_path,
    workpiece_frame,
)
from .plots import animate_painting, plot_joint_trajectory, plot_path_3d
from .spray import BUILTIN_GUNS, Gun, load_gun
from .surface import surface_raster
from .trajectory import DEFAULT_MAX_STEP, DEFAULT_SINGULAR_MARGIN, PathSolution, solve_path, track

if TYPE_CHECKING:
    from .._typing import ArrayLike, Config
    from ..robot.model import Robot

__all__ = [
    "PaintResult", "paint_path", "paint_raster",
    "Path", "raster_path", "load_path_csv", "path_from_poses", "workpiece_frame", "GUN_DOWN",
    "DEFAULT_ORIGIN", "DEFAULT_SIZE", "DEFAULT_SPACING", "DEFAULT_STEP",
    "PathSolution", "solve_path", "track", "DEFAULT_MAX_STEP", "DEFAULT_SINGULAR_MARGIN",
    "Trajectory", "Timing", "interpolate", "default_tolerance", "DEFAULT_RAMP", "DEFAULT_RATE",
    "CSV_COLUMNS", "trajectory_table", "write_trajectory_csv",
    "plot_joint_trajectory", "plot_path_3d", "animate_painting",
    "PathEvent", "Unreachable", "BranchChange", "WristCrossing", "ConfigChange", "JointLimit",
    "NearSingularity", "SpeedLimit", "AccelerationLimit", "TimeScaled", "DeviationExceeded",
    "PathNotFeasible", "format_report", "JOINT_LABELS",
    "paint_mesh", "MeshPaintResult", "Part", "load_part", "BUILTIN_PARTS", "Gun", "load_gun", "BUILTIN_GUNS",
    "surface_raster",
]


@dataclass(frozen=True, eq=False)
class PaintResult:
    """A painting program: the path, its joint solutions, the timed trajectory, the events.

    Attributes
    ----------
    robot : Robot
        The robot with the tool (gun) used.
    path : Path
    solution : PathSolution
        One joint solution per path sample.
    trajectory : Trajectory
        ``t`` (M,) s; ``q``, ``dq``, ``ddq`` (M, 6) rad, rad/s, rad/s^2.
    events : list of PathEvent
        Everything to report (path and interpolation); empty when there is nothing.
    """

    robot: Robot
    path: Path
    solution: PathSolution
    trajectory: Trajectory
    events: list

    def report(self) -> str:
        """A readable summary: path, timing, peaks, deviation, then the events."""
        tr, u = self.trajectory, self.robot.unit
        configs = self.solution.configs
        lines = [
            f"path: {self.path.name}; {len(self.path)} samples, length {self.path.length:.3f} {u}",
            f"trajectory: {tr.kind} spline through {len(tr.knot_u)} IK samples, "
            f"duration {tr.duration:.4f} s, {len(tr.t)} rows, speed {tr.timing.speed:.3f} {u}/s",
            f"deviation from the path: max {tr.max_deviation:.3g} {u} (tolerance {tr.tolerance:g} {u}), "
            f"max angle {np.degrees(tr.max_angle_deviation):.3g} deg",
            "peak joint speed / limit:        " + _ratios(tr.speed_ratio),
            "peak joint acceleration / limit: " + _ratios(tr.acceleration_ratio),
            "configurations along the path:   " + ", ".join(str(c) for c in sorted(set(configs))),
            format_report(self.events),
        ]
        return "\n".join(lines)


def _ratios(r) -> str:
    if np.all(np.isnan(r)):
        return "no limits given"
    return "  ".join(f"{JOINT_LABELS[j]} {r[j]:.3f}" for j in range(6))


def paint_path(robot: Robot, path: Path, *, duration: float = 20.0, config: Config = 1,
               seed: ArrayLike | None = None, tool: ArrayLike | None = None,
               keep: str = "config", ramp: float = DEFAULT_RAMP, kind: str = "quintic",
               tolerance: float | None = None, rate: float = DEFAULT_RATE, rescale: bool = False,
               max_step: float = DEFAULT_MAX_STEP, singular_margin: float = DEFAULT_SINGULAR_MARGIN,
               progress: bool = False) -> PaintResult:
    """Turn a tool path into a checked joint trajectory.

    Parameters
    ----------
    robot : Robot
    path : Path
        Tool (gun tip) poses in the robot's base frame.
    duration : float
        Time for the whole path (s); see ``rescale``.
    config : int or (arm, elbow, wrist)
        Configuration (the paper's Appendix 3) of the program.
    seed : array_like, shape (6,), optional
        Joints (rad) the first sample's solution is nearest to.
    tool : array_like, shape (4, 4), optional
        Frame 7 <- gun tip; default the robot's own ``tool``.
    keep : {"config", "branch"}
        See :func:`solve_path`.
    ramp, kind, tolerance, rate, rescale
        See :func:`interpolate` (tolerance default 0.01 mm).
    max_step, singular_margin
        See :func:`solve_path`.
    progress : bool
        Progress bar on stderr (when it is a terminal).

    Returns
    -------
    PaintResult

    Raises
    ------
    PathNotFeasible
        Some samples are unreachable, or the joints would jump between samples; the exception
        carries the events and the path solution.
    """
    if tool is not None:
        robot = robot.with_tool(check_transforms(tool, "tool"))
    solution = solve_path(robot, path, config, seed, keep=keep, max_step=max_step,
                          singular_margin=singular_margin, progress=progress)
    if not solution.feasible:
        raise PathNotFeasible(solution.events, solution)
    trajectory, more = interpolate(robot, solution, duration, ramp=ramp, kind=kind, tolerance=tolerance,
                                   rate=rate, rescale=rescale, max_step=max_step)
    return PaintResult(robot, path, solution, trajectory, list(solution.events) + list(more))


def paint_raster(robot: Robot, *, duration: float = 20.0, config: Config = 1,
                 origin: ArrayLike = DEFAULT_ORIGIN, rpy: ArrayLike = (0.0, 0.0, 0.0),
                 size: tuple[float, float] = DEFAULT_SIZE, spacing: float = DEFAULT_SPACING,
                 margin: float = 0.0,
                 standoff: float = 0.0, step: float = DEFAULT_STEP,
                 gun_rotation: ArrayLike = GUN_DOWN, **options: Any) -> PaintResult:
    """Paint a raster over a rectangle (the paper's Simulation 3 with the defaults).

    The defaults: a 600 x 800 mm rectangle centred at (1100, 0, 200) mm in the base frame, in a
    plane parallel to the base's x-o-y, passes 100 mm apart along x, gun orientation
    :data:`GUN_DOWN` (x along the base's x, y and z opposite), no standoff, samples every
    5 mm, configuration 1, 20 s. Configuration 1 reaches it everywhere within the paper robot's
    Table 4 limits, far from singularities (the README, "Off-line painting programs").

    Parameters
    ----------
    robot : Robot
    duration, config
        See :func:`paint_path`.
    origin : (3,) float
        Centre of the rectangle in the base frame (length unit).
    rpy : (3,) float
        Orientation of the workpiece frame in the base frame (rad, URDF roll-pitch-yaw).
    size, spacing, margin, standoff, step, gun_rotation
        See :func:`raster_path` (``gun_rotation`` is ``R_workpiece_gun``).
    **options
        Passed to :func:`paint_path` (``seed``, ``tool``, ``keep``, ``ramp``, ``kind``,
        ``tolerance``, ``rate``, ``rescale``, ``max_step``, ``singular_margin``, ``progress``).
    """
    path = raster_path(workpiece_frame(origin, rpy), size=size, spacing=spacing, margin=margin,
                       standoff=standoff, step=step, R_workpiece_gun=gun_rotation)
    return paint_path(robot, path, duration=duration, config=config, **options)
