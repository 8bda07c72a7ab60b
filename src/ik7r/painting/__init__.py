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
3. :func:`time_path`: the joint path ``Q(u)`` (a spline through the IK samples, checked against
   the path to 0.01 mm by default) and its timing: the commanded gun speed where the spray is
   on and time-optimal elsewhere (``speed=``), or a duration (:func:`interpolate`); stops at
   sharp corners (or :func:`blend_corners` within a zone); the joint speed and acceleration
   limits checked densely;
4. :func:`write_trajectory_csv`, :func:`plot_joint_trajectory` (the paper's Figure 12),
   :func:`plot_gun_speed`, :func:`plot_joint_limits`, :func:`plot_path_3d`,
   :func:`animate_painting`; the robot program: :func:`make_program`, :func:`write_rapid`
   (ABB RAPID), :func:`write_program_json`.

Real parts (:func:`paint_mesh`): :mod:`~ik7r.painting.parts` (meshes), :mod:`~ik7r.painting.surface`
(rasters on a surface), :mod:`~ik7r.painting.spray` (guns), :mod:`~ik7r.painting.film` (film
thickness), :mod:`~ik7r.painting.view` (heat map, 3-D view).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..geometry.checks import check_transforms
from .corners import DEFAULT_CORNER_ANGLE, blend_corners, find_corners
from .events import (
    JOINT_LABELS,
    AccelerationLimit,
    BranchChange,
    CommandedSpeedTooHigh,
    ConfigChange,
    CornerStop,
    DeviationExceeded,
    JointLimit,
    NearSingularity,
    PathEvent,
    PathNotFeasible,
    RampOnPart,
    SlowDown,
    SpeedLimit,
    TimeScaled,
    Unreachable,
    WristCrossing,
    format_report,
)
from .export import CSV_COLUMNS, trajectory_table, write_trajectory_csv
from .interpolate import (
    DEFAULT_RAMP,
    DEFAULT_RATE,
    JointPath,
    ProfileTiming,
    Timing,
    Trajectory,
    default_tolerance,
    dense_peaks,
    interpolate,
)
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
from .plots import animate_painting, plot_gun_speed, plot_joint_limits, plot_joint_trajectory, plot_path_3d
from .program import Program, make_program, program_dict, rapid_text, write_program_json, write_rapid
from .spray import BUILTIN_GUNS, Gun, load_gun
from .surface import surface_raster
from .timing import time_path
from .trajectory import DEFAULT_MAX_STEP, DEFAULT_SINGULAR_MARGIN, PathSolution, solve_path, track

if TYPE_CHECKING:
    from .._typing import ArrayLike, Config
    from ..robot.model import Robot

__all__ = [
    "PaintResult", "paint_path", "paint_raster",
    "Path", "raster_path", "load_path_csv", "path_from_poses", "workpiece_frame", "GUN_DOWN",
    "DEFAULT_ORIGIN", "DEFAULT_SIZE", "DEFAULT_SPACING", "DEFAULT_STEP",
    "PathSolution", "solve_path", "track", "DEFAULT_MAX_STEP", "DEFAULT_SINGULAR_MARGIN",
    "Trajectory", "Timing", "ProfileTiming", "JointPath", "interpolate", "time_path", "dense_peaks",
    "default_tolerance", "DEFAULT_RAMP", "DEFAULT_RATE",
    "find_corners", "blend_corners", "DEFAULT_CORNER_ANGLE",
    "CSV_COLUMNS", "trajectory_table", "write_trajectory_csv",
    "Program", "make_program", "rapid_text", "write_rapid", "program_dict", "write_program_json",
    "plot_joint_trajectory", "plot_path_3d", "animate_painting", "plot_gun_speed", "plot_joint_limits",
    "PathEvent", "Unreachable", "BranchChange", "WristCrossing", "ConfigChange", "JointLimit",
    "NearSingularity", "SpeedLimit", "AccelerationLimit", "TimeScaled", "DeviationExceeded",
    "CornerStop", "CommandedSpeedTooHigh", "SlowDown", "RampOnPart",
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
        if tr.commanded_speed is None:
            timing = f"constant path speed {tr.timing.speed:.3f} {u}/s between ramps"
        else:
            timing = (f"gun speed {tr.commanded_speed:g} {u}/s where the spray is on, time-optimal "
                      f"elsewhere")
        lines = [
            f"path: {self.path.name}; {len(self.path)} samples, length {self.path.length:.3f} {u}",
            f"trajectory: {tr.kind} spline through {len(tr.knot_u)} IK samples, "
            f"duration {tr.duration:.4f} s, {len(tr.t)} rows; {timing}",
            f"deviation from the path: max {tr.max_deviation:.3g} {u} (tolerance {tr.tolerance:g} {u}), "
            f"max angle {np.degrees(tr.max_angle_deviation):.3g} deg",
            "peak joint speed / limit:        " + _ratios(tr.speed_ratio),
            "peak joint acceleration / limit: " + _ratios(tr.acceleration_ratio),
            "peaks (dense check) at t =       " + "  ".join(
                f"{JOINT_LABELS[j]} {tr.speed_peak_t[j]:.4f}/{tr.acceleration_peak_t[j]:.4f} s"
                for j in range(6)),
            "configurations along the path:   " + ", ".join(str(c) for c in sorted(set(configs))),
        ]
        if tr.commanded_speed is not None:
            on = tr.spray & ~_in_ranges(tr.u, tr.ramps)
            if np.any(on):
                dev = np.abs(tr.gun_speed[on] / tr.commanded_speed - 1.0).max()
                lines.append(f"gun speed on spray-on rows outside the ramps: within {100 * dev:.2f} % of "
                             f"{tr.commanded_speed:g} {u}/s")
            if len(tr.ramps):
                lines.append(f"ramps (spray on, below the commanded speed at a stretch's end): "
                             f"{len(tr.ramps)}, longest {np.max(np.diff(tr.ramps, axis=1)):.1f} {u}")
        lines.append(format_report(self.events))
        return "\n".join(lines)


def _in_ranges(u, ranges) -> np.ndarray:
    """Whether each ``u`` lies in one of the ``ranges`` (R, 2)."""
    u = np.asarray(u)
    out = np.zeros(u.shape, dtype=bool)
    for a, b in np.asarray(ranges).reshape(-1, 2):
        out |= (u >= a) & (u <= b)
    return out


def _ratios(r) -> str:
    if np.all(np.isnan(r)):
        return "no limits given"
    return "  ".join(f"{JOINT_LABELS[j]} {r[j]:.3f}" for j in range(6))


def paint_path(robot: Robot, path: Path, *, duration: float | None = None, speed: float | None = None,
               slow_down: bool = False, zone: float | None = None, config: Config = 1,
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
    duration : float, optional
        Time for the whole path (s; default 20 when no ``speed`` is given); see ``rescale``.
    speed : float, optional
        Commanded gun speed where the spray is on (length unit per s): the process mode of
        :func:`time_path` (time-optimal where the spray is off).
    slow_down : bool
        With ``speed``: slow the stroke where the commanded speed would break a joint limit
        (reported) instead of raising.
    zone : float, optional
        Blend the sharp corners of a sampled path within this radius (:func:`blend_corners`);
        without it the robot stops at them.
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
    if zone is not None:
        path = blend_corners(path, zone)
    solution = solve_path(robot, path, config, seed, keep=keep, max_step=max_step,
                          singular_margin=singular_margin, progress=progress)
    if not solution.feasible:
        raise PathNotFeasible(solution.events, solution)
    trajectory, more = time_path(robot, solution, speed=speed, duration=duration, slow_down=slow_down,
                                 ramp=ramp, kind=kind, tolerance=tolerance, rate=rate, rescale=rescale,
                                 max_step=max_step)
    return PaintResult(robot, path, solution, trajectory, list(solution.events) + list(more))


def paint_raster(robot: Robot, *, duration: float | None = None, config: Config = 1,
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
        Passed to :func:`paint_path` (``speed``, ``slow_down``, ``seed``, ``tool``, ``keep``, ``ramp``,
        ``kind``, ``tolerance``, ``rate``, ``rescale``, ``max_step``, ``singular_margin``, ``progress``).
    """
    T_bw = workpiece_frame(origin, rpy)
    path = raster_path(T_bw, size=size, spacing=spacing, margin=margin, standoff=standoff, step=step,
                       R_workpiece_gun=gun_rotation)
    result = paint_path(robot, path, duration=duration, config=config, **options)
    ramp = _ramp_on_part(result, T_bw, float(np.asarray(size, dtype=float)[0]), float(margin))
    if ramp is None:
        return result
    return PaintResult(result.robot, result.path, result.solution, result.trajectory, result.events + [ramp])


def _ramp_on_part(result: PaintResult, T_base_workpiece, width: float, margin: float):
    """A :class:`RampOnPart` when a speed ramp of a raster's pass reaches inside the rectangle."""
    tr = result.trajectory
    depth, count = 0.0, 0
    for a, b in tr.ramps:
        u = np.linspace(a, b, 64)
        p, _ = result.path.at(u)
        x_w = (p - T_base_workpiece[:3, 3]) @ T_base_workpiece[:3, 0]
        inside = result.path.sprayed(u) & (np.abs(x_w) < width / 2)
        if np.any(inside):
            count += 1
            depth = max(depth, float(np.max(width / 2 - np.abs(x_w[inside]))))
    return RampOnPart(count, depth, margin, result.robot.unit) if count else None
