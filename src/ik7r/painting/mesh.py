"""Painting a part end to end: surface raster -> joint trajectory -> film -> plan for a target.

:func:`paint_mesh` chains :func:`~ik7r.painting.surface.surface_raster`,
:func:`~ik7r.painting.solve_path`, a timing at a commanded gun speed
(:func:`~ik7r.painting.time_path`: the commanded speed where the spray is on, time-optimal
where it is off), :func:`~ik7r.painting.film.gun_poses` (forward kinematics of the
interpolated joints) and :func:`~ik7r.painting.film.part_film`; with a target thickness it
chooses the speed (thickness scales as 1 / speed for a fixed spacing), re-times and
integrates again; it checks the spacing against the spray width (ripple).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..units import unit_scale
from . import film as _film
from .parts import Part
from .paths import DEFAULT_STEP
from .spray import Gun, load_gun
from .surface import (
    DEFAULT_APPROACH,
    DEFAULT_OVERSPRAY,
    sprayed_length,
    surface_raster,
    target_faces,
)
from .timing import time_path

if TYPE_CHECKING:
    from . import PaintResult

__all__ = ["MeshPaintResult", "paint_mesh", "choose_spacing", "DEFAULT_SPEED",
           "RIPPLE_GOAL", "write_trajectory_spray_csv"]

#: Default commanded gun speed over the part (mm/s, converted to the robot's unit).
DEFAULT_SPEED = 500.0
#: The ripple the default spacing aims at (relative amplitude of the film of parallel strokes).
RIPPLE_GOAL = 0.01
#: Ripple above which the report warns that the spacing is too wide for the gun.
RIPPLE_WARN = 0.05


def choose_spacing(gun: Gun, goal: float = RIPPLE_GOAL, *, round_to: float | None = None) -> float:
    """The largest pass spacing (gun's unit) whose ripple (:func:`ripple`) is at most ``goal``,
    rounded down to a multiple of ``round_to`` (default 5 mm in the gun's unit)."""
    lo, hi = 1e-3 * gun.width, 4.0 * gun.reach
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _film.ripple(gun, mid) <= goal:
            lo = mid
        else:
            hi = mid
    step = unit_scale("mm", gun.unit) * 5.0 if round_to is None else round_to
    return max(step, math.floor(lo / step) * step) if lo >= step else lo


@dataclass(frozen=True, eq=False)
class MeshPaintResult:
    """A painted part: the program, the film and what was chosen.

    Attributes
    ----------
    program : PaintResult
        Robot, path (with spray flags), joint solution, timed trajectory, events.
    part : Part
    gun : Gun
        In the robot's unit.
    faces : ndarray (F,), bool
        The painted faces (facing the gun side).
    thickness : ndarray (V,)
        Film per vertex (um).
    stats : FilmStats
    poses : GunPoses
        The instants the film was integrated over.
    step : float
        The footprint move per instant (robot unit), from the step rule.
    speed : float
        Commanded gun speed (robot unit/s).
    plan : dict
        What was chosen and why (spacing, ripple, speed).
    """

    program: PaintResult
    part: Part
    gun: Gun
    faces: np.ndarray
    thickness: np.ndarray
    stats: _film.FilmStats
    poses: _film.GunPoses
    step: float
    speed: float
    plan: dict = field(default_factory=dict)

    @property
    def events(self) -> list:
        return self.program.events

    def report(self) -> str:
        u = self.part.unit
        p = self.plan
        lines = [
            f"part: {self.part.name}; {len(self.part.vertices)} vertices, {len(self.part.faces)} faces, "
            f"{int(self.faces.sum())} painted; unit {u}",
            f"gun: {self.gun.describe()}",
            f"spacing {p['spacing']:g} {u} ({p['spacing_why']}); ripple {100 * p['ripple']:.3g} % "
            f"(relative amplitude of the film of parallel strokes on a plane)",
        ]
        if p.get("ripple_warning"):
            lines.append("warning: " + p["ripple_warning"])
        lines += [
            f"speed {self.speed:.4g} {u}/s ({p['speed_why']}); timing: {p['timing']}",
            f"film step: the pattern moves at most {self.step:.4g} {u} between instants "
            f"({len(self.poses.t)} instants, {self.poses.spray_time:.3f} s sprayed): integration error "
            f"below 0.5 % of the peak; occlusion by a depth buffer seen from the gun tip",
            *self.stats.lines(u),
            self.program.report(),
        ]
        return "\n".join(lines)

    def to_json(self) -> dict:
        s = self.stats
        tr = self.program.trajectory
        return {
            "part": {"name": self.part.name, "vertices": int(len(self.part.vertices)),
                     "faces": int(len(self.part.faces)), "painted_faces": int(self.faces.sum()),
                     "unit": self.part.unit, "T_base_part": self.part.T_base_part.tolist()},
            "gun": {"name": self.gun.name, "model": self.gun.model, "unit": self.gun.unit,
                    "standoff": self.gun.standoff, "peak_rate_um_s": self.gun.peak_rate,
                    "params": self.gun.params},
            "film": {"mean_um": s.mean, "std_um": s.std, "std_over_mean": s.uniformity, "min_um": s.minimum,
                     "max_um": s.maximum, "painted_area": s.area, "film_volume_um_area": s.volume,
                     "target_um": s.target, "tolerance_um": s.tolerance, "share_within": s.within},
            "plan": {**self.plan, "speed": self.speed},
            "film_step": {"footprint_move": self.step, "instants": int(len(self.poses.t)),
                          "spray_time_s": self.poses.spray_time, "accuracy_of_peak": _film.STEP_ACCURACY},
            "trajectory": {"duration_s": tr.duration, "rows": int(len(tr.t)), "path": self.program.path.name,
                           "samples": int(len(self.program.path)), "max_deviation": tr.max_deviation},
            "events": [{"kind": type(e).__name__, "blocking": bool(e.blocking), "message": str(e)}
                       for e in self.events],
        }


def _speed_of(unit: str, speed) -> float:
    return DEFAULT_SPEED * unit_scale("mm", unit) if speed is None else float(speed)


def paint_mesh(robot, part: Part, *, gun="bell", spacing: float | None = None, standoff: float | None = None,
               overspray: float | None = None, approach: float | None = None, direction=(1.0, 0.0, 0.0),
               view=(0.0, 0.0, 1.0), spin: float = 0.0, speed: float | None = None,
               target_thickness: float | None = None, thickness_tolerance: float | None = None,
               config=1, seed=None, keep: str = "config", slow_down: bool = False, kind: str = "quintic",
               tolerance: float | None = None, rate: float = 100.0,
               occlusion: bool = True, resolution: int = _film.DEFAULT_RESOLUTION, step: float | None = None,
               progress: bool = False) -> MeshPaintResult:
    """Paint ``part`` with ``gun``: raster, trajectory, film; the speed for a target thickness.

    Lengths in the robot's unit (``part`` must be in it); ``spin`` in rad; speeds in unit/s.
    Defaults: ``standoff`` the gun's reference standoff, ``spacing`` the largest with a ripple
    of at most 1 % (:func:`choose_spacing`), ``overspray`` 60 mm, ``approach`` 150 mm,
    ``speed`` 500 mm/s (or chosen for ``target_thickness``, um). ``thickness_tolerance`` (um,
    default 10 % of the target) is the band of the "share within" statistic. ``tolerance`` is
    the path deviation tolerance. The timing is :func:`~ik7r.painting.time_path`'s process mode:
    ``speed`` on the passes, time-optimal within the joint limits on the turns, approach and
    retract; ``slow_down`` slows a pass where the speed would break a limit (the film shows it).
    A robot without acceleration limits (the IRB 5400 of the URDF) runs the whole path at the
    constant path speed ``speed`` instead (the plan's ``timing`` says so), and a joint speed
    limit that breaks is an error naming the speed to command.
    Raises ``PathNotFeasible`` when no continuous joint trajectory follows the raster within the
    limits (or the speed breaks one, without ``slow_down``).
    """
    from .events import PathNotFeasible
    from .trajectory import solve_path

    unit = robot.unit
    if part.unit != unit:
        raise ValueError(f"the part is in {part.unit} but the robot in {unit}: load it with unit={unit!r}")
    g = load_gun(gun).in_unit(unit)
    mm = unit_scale("mm", unit)
    standoff = g.standoff if standoff is None else float(standoff)
    overspray = DEFAULT_OVERSPRAY * mm if overspray is None else float(overspray)
    approach = DEFAULT_APPROACH * mm if approach is None else float(approach)
    plan: dict = {}
    if spacing is None:
        spacing = choose_spacing(g)
        plan["spacing_why"] = f"the largest multiple of 5 mm with a ripple of at most {100 * RIPPLE_GOAL:g} %"
    else:
        spacing = float(spacing)
        plan["spacing_why"] = "given"
    plan["spacing"] = spacing
    plan["ripple"] = _film.ripple(g, spacing)
    if g.model == "gaussian":
        plan["ripple_gaussian_formula"] = _film.gaussian_ripple(g.params["sigma"], spacing)
    if plan["ripple"] > RIPPLE_WARN:
        plan["ripple_warning"] = (f"spacing {spacing:g} {unit} is wide for this gun: ripple "
                                  f"{100 * plan['ripple']:.3g} %; {choose_spacing(g):g} {unit} gives at most "
                                  f"{100 * RIPPLE_GOAL:g} %")
    if target_thickness is not None and not (math.isfinite(target_thickness) and target_thickness > 0):
        raise ValueError(f"target thickness must be a positive number of um; got {target_thickness!r}")
    faces = target_faces(part, view)
    path = surface_raster(part, spacing=spacing, standoff=standoff, overspray=overspray, approach=approach,
                          direction=direction, view=view, spin=spin, step=DEFAULT_STEP * mm,
                          rotation_radius=100.0 * mm)
    solution = solve_path(robot, path, config, seed, keep=keep, progress=progress)
    if not solution.feasible:
        raise PathNotFeasible(solution.events, solution)
    h = _film.film_step(g) if step is None else float(step)
    opts = dict(kind=kind, tolerance=tolerance, rate=rate)

    if robot.acceleration is None:
        plan["timing"] = (f"robot {robot.name} has no joint acceleration limits: the whole path at the "
                          f"constant path speed of the commanded gun speed (the gun at that speed on the "
                          f"passes, slower in the turns where it rotates), ramps in the approach and "
                          f"retract; the joint speed limits checked, the accelerations unlimited")
    else:
        plan["timing"] = ("the commanded gun speed where the spray is on, time-optimal within the joint "
                          "speed and acceleration limits elsewhere")

    def timed(v):
        if robot.acceleration is not None:
            return time_path(robot, solution, speed=v, slow_down=slow_down, **opts)
        return _constant_path_speed(robot, solution, v, approach, opts)

    def run(v):
        traj, more = timed(v)
        poses = _film.gun_poses(robot, traj, path, part.T_base_part, g, step=h)
        thick = _film.part_film(part, poses, g, occlusion=occlusion, resolution=resolution)
        return traj, more, poses, thick

    v0 = _speed_of(unit, speed)
    traj, more, poses, thick = run(v0)
    mean0 = _film.film_stats(part, thick, faces).mean
    if target_thickness is None:
        plan["speed_why"] = "given" if speed is not None else f"default {DEFAULT_SPEED:g} mm/s"
        v = v0
    else:
        if not mean0 > 0:
            raise ValueError("the raster lays no film on the part: cannot plan a speed for the target")
        v = v0 * mean0 / float(target_thickness)
        plan["speed_why"] = (f"for a mean of {target_thickness:g} um: {mean0:.4g} um at {v0:.4g} {unit}/s, "
                             f"and "
                             f"for a fixed spacing the film scales as 1/speed")
        plan["trial_speed"] = v0
        plan["trial_mean_um"] = mean0
        traj, more, poses, thick = run(v)
    plan["sprayed_length"] = sprayed_length(path)
    stats = _film.film_stats(part, thick, faces, target=target_thickness, tolerance=thickness_tolerance)
    from . import PaintResult

    program = PaintResult(robot, path, solution, traj, list(solution.events) + list(more))
    return MeshPaintResult(program, part, g, faces, thick, stats, poses, h, v, plan)


def _constant_path_speed(robot, solution, speed: float, approach: float, opts: dict):
    """For a robot without acceleration limits: the path at the constant path speed ``speed``
    (with ``u`` the arc length on a pass, the gun's speed there), ramps of at most 1 s shortened
    to lie in the approach and retract; a joint speed limit exceeded is an error saying by how
    much (the speed to command instead), not a warning."""
    from .interpolate import DEFAULT_RAMP

    L = float(solution.path.u[-1])
    r = max(min(DEFAULT_RAMP, 2.0 * approach / speed), 1e-3) if approach > 0 else DEFAULT_RAMP
    traj, more = time_path(robot, solution, duration=L / speed + r, ramp=r, **opts)
    ratio = np.asarray(traj.speed_ratio, dtype=float)
    if robot.velocity is not None and np.max(ratio) > 1.0 + 1e-6:
        from .events import JOINT_LABELS

        j = int(np.nanargmax(ratio))
        raise ValueError(f"robot {robot.name} has no acceleration limits, so the path is timed at a constant "
                         f"path speed of {speed:g} {robot.unit}/s: {JOINT_LABELS[j]} then needs "
                         f"{ratio[j]:.2f} x its speed limit at t = {traj.speed_peak_t[j]:.3f} s; command at "
                         f"most {speed / ratio[j]:.4g} {robot.unit}/s or give the robot acceleration limits")
    return traj, more


def write_trajectory_spray_csv(robot, trajectory, path, file):
    """Today's trajectory CSV (:func:`write_trajectory_csv`'s columns) plus ``spray`` (0 or 1:
    the path's flag at the row's path parameter)."""
    from pathlib import Path as FilePath

    from .export import CSV_COLUMNS, trajectory_table

    fp = FilePath(file)
    on = path.sprayed(np.clip(trajectory.u, 0.0, path.u[-1])).astype(float)
    table = np.column_stack([trajectory_table(robot, trajectory), on])
    fmt = ["%.12g"] * (table.shape[1] - 1) + ["%d"]
    np.savetxt(fp, table, delimiter=",", fmt=fmt, header=",".join(list(CSV_COLUMNS) + ["spray"]), comments="")
    return fp
