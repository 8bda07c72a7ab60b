"""``ik7r paint mesh``: paint a part (mesh file or built-in name) and simulate the film.

Writes into ``--out``: ``trajectory.csv`` (the columns of ``paint raster`` plus ``spray``, 0 or
1), ``thickness.csv`` (``x,y,z,thickness_um`` per vertex, part frame and unit),
``thickness.png`` (heat map, colour bar in um), ``view.html`` (self-contained 3-D view),
``gun_speed.png`` and ``joint_limits.png`` (the timing: gun speed, joint speeds and
accelerations with their limits), ``report.txt`` and ``report.json`` (film statistics, the
chosen spacing and speed, the timing, events).
"""

from __future__ import annotations

from ..errors import CliError, NoSolution
from ._common import finite_float

#: Files ``ik7r paint mesh`` writes into ``--out`` (a new run removes those it does not write
#: again); the reports are the manifest, published last.
MESH_FILES = ("trajectory.csv", "thickness.csv", "thickness.png", "view.html", "gun_speed.png",
              "joint_limits.png", "report.txt", "report.json")


def add_mesh_parser(kinds, common) -> None:
    m = kinds.add_parser(
        "mesh", help="a raster on a part's surface, and the film it lays down",
        description="Cut the part's surface (seen from the gun side) with parallel planes, keep the gun "
                    "at a standoff along the smoothed normal, join the passes with spray-off turns, "
                    "solve the trajectory, integrate the gun's film over it and report it. PART is a "
                    "mesh file (STL, OBJ, PLY) or a built-in part (panel, hood). Lengths in the robot's "
                    "unit unless said; speeds in unit/s.")
    common(m)  # first: an option the common group already has (e.g. a --speed of the new timing) is kept

    def add(*flags, **kw):
        if not any(f in m._option_string_actions for f in flags):
            m.add_argument(*flags, **kw)

    add("part", metavar="PART",
        help="mesh file (.stl, .obj, .ply) or built-in part name (panel, hood)")
    add("--frame", nargs=6, type=finite_float, default=None, metavar=("X", "Y", "Z", "R", "P", "YAW"),
        help="part frame in the base frame: position (length unit), rpy (deg); default for the "
             "built-in parts a place the robot reaches (paper robot: 1100 0 0 mm; IRB 5400: "
             "1600 0 500 mm), for a file the base frame")
    add("--part-unit", default=None, metavar="U", help="length unit of the mesh file "
        "(m, cm, mm, in; default the robot's)")
    add("--direction", nargs=3, type=finite_float, default=(1.0, 0.0, 0.0), metavar=("X", "Y", "Z"),
        help="pass direction in the part frame (default 1 0 0)")
    add("--view", nargs=3, type=finite_float, default=(0.0, 0.0, 1.0), metavar=("X", "Y", "Z"),
        help="side of the part the gun sprays from, in the part frame (default 0 0 1)")
    add("--spacing", type=finite_float, default=None, metavar="D",
        help="distance between passes (default: the largest multiple of 5 mm with a "
             "ripple <= 1 %%)")
    add("--standoff", type=finite_float, default=None, metavar="D",
        help="gun tip to surface along the normal (default the gun's reference standoff)")
    add("--overspray", type=finite_float, default=None, metavar="D",
        help="pass extension past the part's edges, spray on (default 60 mm)")
    add("--approach", type=finite_float, default=None, metavar="D",
        help="length of the approach and retract, spray off (default 150 mm)")
    add("--spin", type=finite_float, default=0.0, metavar="DEG",
        help="tool x turned about the gun axis from the direction of travel (deg, default 0)")
    add("--speed", type=finite_float, default=None, metavar="V",
        help="commanded gun speed (unit/s; default 500 mm/s, or chosen for --target-thickness)")
    add("--target-thickness", type=finite_float, default=None, metavar="UM",
        help="mean film wanted (um): the speed is chosen for it")
    add("--tolerance-thickness", type=finite_float, default=None, metavar="UM",
        help="band around the target for the 'share within' statistic (um; default 10 %% of it)")
    add("--gun", default="bell", metavar="FILE|NAME",
        help="gun file (TOML) or built-in gun (bell, beta, fan; default bell)")
    add("--no-occlusion", action="store_true", help="ignore the part hiding itself from the gun")
    m.set_defaults(run=run_mesh, duration=None)  # (the animation options of raster/path do not apply)


def run_mesh(args) -> int:
    import json
    from pathlib import Path as FilePath

    import numpy as np

    from ... import painting as P
    from ...outputs import OutputDir
    from ...painting import mesh as M
    from ...painting import view as W
    from ...painting.parts import BUILTIN_PARTS, load_part
    from ...painting.spray import load_gun
    from ...units import unit_scale
    from ._common import load_cli_robot
    from .paint import _pose, check_program_args, program_outputs, timing_plots

    robot = load_cli_robot(args)
    if args.tool is not None:
        robot = robot.with_tool(_pose(args.tool))
    if args.duration is not None:
        raise CliError("paint mesh: the timing comes from --speed or --target-thickness, not --duration")
    if args.zone is not None:
        raise CliError("paint mesh: --zone blends the corners of sampled paths; a surface raster has none")
    check_program_args(args)
    if not 1 <= args.config <= 8:
        raise CliError(f"--config must be 1..8; got {args.config}")
    try:
        if args.frame is not None:
            frame = _pose(args.frame)
        elif args.part in BUILTIN_PARTS:
            origin = (1600.0, 0.0, 500.0) if robot.name == "irb5400" else (1100.0, 0.0, 0.0)
            frame = P.workpiece_frame(np.asarray(origin) * unit_scale("mm", robot.unit))
        else:
            frame = None
        part = load_part(args.part, unit=robot.unit, part_unit=args.part_unit, T_base_part=frame)
        result = M.paint_mesh(
            robot, part, gun=load_gun(args.gun), spacing=args.spacing, standoff=args.standoff,
            overspray=args.overspray, approach=args.approach, direction=args.direction, view=args.view,
            spin=np.radians(args.spin), speed=args.speed, target_thickness=args.target_thickness,
            thickness_tolerance=args.tolerance_thickness, config=args.config,
            seed=None if args.seed is None else np.radians(args.seed), keep=args.keep,
            slow_down=args.slow_down, kind=args.spline, tolerance=args.tolerance, rate=args.rate,
            occlusion=not args.no_occlusion, progress=True)
    except P.PathNotFeasible as exc:
        # the report of the failure only (an older run's outputs are removed): nothing that
        # looks like a program
        with OutputDir(args.out, manifest=("report.json", "report.txt"), owned=MESH_FILES) as stage:
            (stage.path / "report.txt").write_text(f"part: {args.part}\n{exc}\n", encoding="utf-8")
        raise NoSolution(f"(report in {stage.target / 'report.txt'}) {exc}") from exc
    except (FileNotFoundError, ValueError) as exc:
        raise CliError(str(exc)) from exc
    # every file through the stager: published when all are complete, the reports last
    with OutputDir(args.out, manifest=("report.json", "report.txt"), owned=MESH_FILES) as stage:
        out = stage.path
        tr, path = result.program.trajectory, result.program.path
        written = [M.write_trajectory_spray_csv(result.program.robot, tr, path, out / "trajectory.csv"),
                   W.write_thickness_csv(part, result.thickness, out / "thickness.csv")]
        if not args.no_plots:
            written.append(W.plot_thickness(part, result.thickness, out / "thickness.png",
                                            faces=result.faces, direction=args.direction, view=args.view,
                                            target=args.target_thickness, tolerance=result.stats.tolerance,
                                            title=_title(part.name, result)))
            written.append(W.write_view_html(out / "view.html", result.program.robot, part, result.thickness,
                                             tr, path, faces=result.faces, postures=max(1, args.postures)))
            written += timing_plots(result.program.robot, tr, out)
        report = result.report()
        (out / "report.txt").write_text(report + "\n", encoding="utf-8")
        (out / "report.json").write_text(json.dumps(result.to_json(), indent=2) + "\n", encoding="utf-8")
        written += [out / "report.txt", out / "report.json"]
        written = [stage.target / FilePath(w).name for w in written]
        written += program_outputs(args, result.program.robot, path, tr)
    print(report)
    print("wrote " + ", ".join(str(w) for w in written))
    return 0


def _title(name, result) -> str:
    s = result.stats
    within = "" if s.within is None else f", {100 * s.within:.0f} % within {s.target:g} +- {s.tolerance:g} um"
    return (f"Film on {name}: mean {s.mean:.2f} um, std/mean {100 * s.uniformity:.1f} %{within}\n"
            f"{result.gun.name} gun, {result.speed:.0f} {result.part.unit}/s, passes "
            f"{result.plan['spacing']:g} {result.part.unit} apart")
