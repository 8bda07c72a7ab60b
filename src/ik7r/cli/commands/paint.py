"""``ik7r paint raster | path FILE.csv``: off-line painting programs (the paper's Simulation 3).

Writes into ``--out DIR``: ``trajectory.csv`` (``t,x,y,z,q1..q7,dq1..dq7,ddq1..ddq7`` in s, the
robot's length unit, deg, deg/s, deg/s^2; rows every 1/rate s plus the peak instants),
``figure12.png`` (joint positions, velocities and accelerations), ``gun_speed.png`` (the gun's
speed, commanded and actual, spray-on shaded), ``joint_limits.png`` (joint speeds and
accelerations with the limits), ``path3d.png`` (the path with robot postures),
``animation.gif`` (or ``.html``) and ``report.txt``; ``--rapid FILE.mod`` and
``--program FILE.json`` write the robot program. Exit status 1 when no continuous joint
trajectory follows the path (the report says which samples and why), 2 on bad input.
"""

from __future__ import annotations

from pathlib import Path

from ...limits import MAX_FRAMES, MAX_PATH_SAMPLES, MAX_TRAJECTORY_ROWS
from ..errors import CliError, NoSolution
from ._common import count, finite_float, load_cli_robot

#: Files ``ik7r paint`` writes into ``--out`` (a new run removes those it does not write again);
#: ``report.txt`` is the manifest, published last.
PAINT_FILES = ("trajectory.csv", "report.txt", "figure12.png", "gun_speed.png", "joint_limits.png",
               "path3d.png", "animation.gif", "animation.html")


def _common(p) -> None:
    g = p.add_argument_group("program")
    g.add_argument("--speed", type=finite_float, default=None, metavar="V",
                   help="commanded gun speed where the spray is on (length unit per s); the rest of "
                        "the path is timed as fast as the joint limits allow")
    g.add_argument("--slow-down", action="store_true",
                   help="with --speed: where the commanded speed would break a joint limit, slow the "
                        "stroke there (reported) instead of failing")
    g.add_argument("--duration", type=finite_float, default=None, metavar="S",
                   help="without --speed: time for the whole path in seconds (default 20, the paper's)")
    g.add_argument("--zone", type=finite_float, default=None, metavar="D",
                   help="blend sharp corners of a loaded path within this radius (length unit; RAPID "
                        "zone data); default: stop at them")
    g.add_argument("--config", type=count, default=1, metavar="N",
                   help="configuration 1..8 (the paper's Appendix 3; default 1)")
    g.add_argument("--keep", choices=("config", "branch"), default="config",
                   help="when the continuous solution leaves the configuration (theta5 crossing 0): "
                        "'config' reports a branch change (default), 'branch' stays continuous and "
                        "reports the crossing")
    g.add_argument("--tool", nargs=6, type=finite_float, metavar=("X", "Y", "Z", "R", "P", "YAW"),
                   help="spray-gun TCP in frame 7: position (length unit) and roll-pitch-yaw (deg); "
                        "default the robot file's tool (none for the paper robot: frame 7)")
    g.add_argument("--seed", nargs=6, type=finite_float, metavar="Q",
                   help="joints (deg) the first sample's solution is nearest to")
    g.add_argument("--ramp", type=finite_float, default=1.0, metavar="S",
                   help="with --duration: duration of the speed ramps at start, end and corner stops "
                        "(s, default 1)")
    g.add_argument("--spline", choices=("quintic", "cubic"), default="quintic",
                   help="joint-space spline (default quintic)")
    g.add_argument("--tolerance", type=finite_float, default=None, metavar="D",
                   help="largest deviation of the tool from the path (length unit; default 0.01 mm, "
                        "at least 1e-4 mm)")
    g.add_argument("--rate", type=finite_float, default=100.0, metavar="HZ",
                   help="rows per second in trajectory.csv (default 100)")
    g.add_argument("--rescale", action="store_true",
                   help="stretch the time to respect the joint speed and acceleration limits "
                        "(default: report any excess)")
    o = p.add_argument_group("output")
    o.add_argument("--out", default="ik7r-paint", metavar="DIR", help="output directory (default ik7r-paint)")
    o.add_argument("--no-plots", action="store_true", help="write no figures (and no animation)")
    o.add_argument("--no-animation", action="store_true", help="write no animation")
    o.add_argument("--frames", type=count, default=60, metavar="N",
                   help="animation frames, spread evenly over the duration (default 60; fewer is faster)")
    o.add_argument("--animation-format", choices=("gif", "html"), default="gif",
                   help="animated GIF or a self-contained HTML page (default gif)")
    o.add_argument("--postures", type=count, default=5, metavar="N",
                   help="robot postures in path3d.png (default 5, at most 100)")
    o.add_argument("--rapid", default=None, metavar="FILE.mod",
                   help="also write the program as an ABB RAPID module (jointtargets, MoveAbsJ \\T)")
    o.add_argument("--program", default=None, metavar="FILE.json",
                   help="also write the program as JSON (targets in rad and deg, times, spray flags)")
    o.add_argument("--signal", default="doGunOn", metavar="NAME",
                   help="RAPID digital output that switches the gun (default doGunOn)")
    w = p.add_argument_group("work limits")
    w.add_argument("--max-samples", type=count, default=MAX_PATH_SAMPLES, metavar="N",
                   help=f"refuse paths of more samples (default {MAX_PATH_SAMPLES:,})")
    w.add_argument("--max-rows", type=count, default=MAX_TRAJECTORY_ROWS, metavar="N",
                   help="refuse trajectories of more rows, duration x rate "
                        f"(default {MAX_TRAJECTORY_ROWS:,})")


def add_parser(sub) -> None:
    p = sub.add_parser("paint", help="off-line painting program: path -> joint trajectory CSV and plots",
                       description="Turn a painting path into a smooth joint trajectory (the paper's "
                                   "Simulation 3): trajectory IK on one solution branch, joint-space "
                                   "spline, limit and deviation checks, CSV, figures, animation.")
    kinds = p.add_subparsers(dest="paint_kind", metavar="PATH", parser_class=type(p))
    r = kinds.add_parser("raster", help="a raster over a rectangle (defaults: the paper's scenario)",
                         description="A raster (boustrophedon) over a rectangle in the x-y plane of a "
                                     "workpiece frame, constant gun orientation (x along the "
                                     "workpiece's x, y and z opposite). Defaults: the paper's "
                                     "Simulation 3 on the paper robot.")
    r.add_argument("--origin", nargs=3, type=finite_float, default=None, metavar=("X", "Y", "Z"),
                   help="centre of the rectangle in the base frame (length unit; default 1100 0 200)")
    r.add_argument("--rpy", nargs=3, type=finite_float, default=(0.0, 0.0, 0.0), metavar=("R", "P", "Y"),
                   help="workpiece frame orientation in the base frame (deg; default 0 0 0)")
    r.add_argument("--size", nargs=2, type=finite_float, default=None, metavar=("W", "H"),
                   help="rectangle size along the workpiece x (passes) and y (default 600 800)")
    r.add_argument("--spacing", type=finite_float, default=None, metavar="D",
                   help="largest distance between passes (default 100)")
    r.add_argument("--margin", type=finite_float, default=0.0, metavar="D",
                   help="overrun of each pass beyond the rectangle (default 0)")
    r.add_argument("--standoff", type=finite_float, default=0.0, metavar="D",
                   help="gun tip distance above the surface (default 0)")
    r.add_argument("--step", type=finite_float, default=None, metavar="D",
                   help="largest distance between path samples (default 5)")
    _common(r)
    r.set_defaults(run=run)
    f = kinds.add_parser("path", help="a path loaded from CSV",
                         description="A path from a CSV file with a header: x,y,z (length unit) and "
                                     "optionally qw,qx,qy,qz or roll,pitch,yaw (deg) and spray (1/0), in a "
                                     "workpiece frame placed by --frame. Without orientation columns the gun "
                                     "points along -z of the workpiece (x along its x).")
    f.add_argument("file", metavar="FILE.csv", help="the path")
    f.add_argument("--frame", nargs=6, type=finite_float, default=None,
                   metavar=("X", "Y", "Z", "R", "P", "YAW"),
                   help="workpiece frame in the base frame: position (length unit), rpy (deg); "
                        "default the base frame")
    f.add_argument("--rotation-radius", type=finite_float, default=100.0, metavar="D",
                   help="length per radian of orientation change in the path timing (default 100)")
    _common(f)
    f.set_defaults(run=run)
    from ._paint_mesh import add_mesh_parser

    add_mesh_parser(kinds, _common)
    p.set_defaults(run=_no_kind)


def _no_kind(args) -> int:
    raise CliError("paint: give the path: 'ik7r paint raster [...]', 'ik7r paint path FILE.csv [...]' "
                   "or 'ik7r paint mesh PART [...]'")


def _pose(vals):
    import numpy as np

    from ...geometry.rotations import rpy_to_matrix, transform

    return transform(rpy_to_matrix(np.radians(vals[3:])), vals[:3])


def run(args) -> int:
    import numpy as np

    from ... import painting as P
    from ...limits import check_work, raised, rows_estimate
    from ...outputs import OutputDir

    robot = load_cli_robot(args)
    if not 1 <= args.config <= 8:
        raise CliError(f"--config must be 1..8; got {args.config}")
    if not 2 <= args.frames <= MAX_FRAMES:
        raise CliError(f"--frames must be 2..{MAX_FRAMES}; got {args.frames}")
    if args.postures > 100:
        raise CliError(f"--postures must be at most 100; got {args.postures}")
    if args.speed is not None and args.duration is not None:
        raise CliError("give --speed (the process speed) or --duration, not both")
    if args.slow_down and args.speed is None:
        raise CliError("--slow-down needs --speed")
    for name in ("speed", "duration", "zone", "rate"):
        v = getattr(args, name)
        if v is not None and not (np.isfinite(v) and v > 0):
            raise CliError(f"--{name} must be a positive number; got {v}")
    check_program_args(args)
    try:
        if args.duration is not None or args.speed is None:  # the rows, estimated before any work
            duration = 20.0 if args.duration is None else args.duration
            check_work(f"trajectory rows ({duration:g} s at {args.rate:g} Hz)",
                       rows_estimate(duration, args.rate), args.max_rows,
                       "--max-rows, or fewer rows with --rate")
        if args.paint_kind == "raster":
            path = P.raster_path(
                P.workpiece_frame(P.DEFAULT_ORIGIN if args.origin is None else args.origin,
                                  np.radians(args.rpy)),
                size=P.DEFAULT_SIZE if args.size is None else args.size,
                spacing=P.DEFAULT_SPACING if args.spacing is None else args.spacing,
                margin=args.margin, standoff=args.standoff,
                step=P.DEFAULT_STEP if args.step is None else args.step, max_samples=args.max_samples)
        else:
            frame = None if args.frame is None else _pose(args.frame)
            path = P.load_path_csv(args.file, frame, rotation_radius=args.rotation_radius,
                                   max_samples=args.max_samples)
        check_work("path samples", len(path), args.max_samples, "--max-samples")
    except (FileNotFoundError, ValueError) as exc:
        raise CliError(str(exc)) from exc
    tool = None if args.tool is None else _pose(args.tool)
    seed = None if args.seed is None else np.radians(args.seed)
    # every file goes through the stager: staged, published when complete, report.txt last
    with OutputDir(args.out, manifest="report.txt", owned=PAINT_FILES) as stage:
        out = stage.path
        try:
            with raised(MAX_TRAJECTORY_ROWS=args.max_rows):
                result = P.paint_path(robot, path, duration=args.duration, speed=args.speed,
                                      slow_down=args.slow_down, zone=args.zone, config=args.config,
                                      seed=seed, tool=tool, keep=args.keep, ramp=args.ramp,
                                      kind=args.spline, tolerance=args.tolerance, rate=args.rate,
                                      rescale=args.rescale, progress=True)
        except P.PathNotFeasible as exc:
            # the report of the failure only (older trajectories are removed): nothing that
            # looks like a program
            (out / "report.txt").write_text(f"path: {path.name}; {len(path)} samples\n{exc}\n",
                                            encoding="utf-8")
            stage.publish()
            raise NoSolution(f"(report in {stage.target / 'report.txt'}) {exc}") from exc
        except ValueError as exc:
            raise CliError(str(exc)) from exc
        written = [P.write_trajectory_csv(result.robot, result.trajectory, out / "trajectory.csv")]
        if not args.no_plots:
            written.append(P.plot_joint_trajectory(result.trajectory, out / "figure12.png",
                                                   robot=result.robot))
            written += timing_plots(result.robot, result.trajectory, out)
            written.append(P.plot_path_3d(result.robot, result.trajectory, out / "path3d.png",
                                          postures=max(1, args.postures)))
            if not args.no_animation:
                name = "animation.gif" if args.animation_format == "gif" else "animation.html"
                written.append(P.animate_painting(result.robot, result.trajectory, out / name,
                                                  frames=args.frames))
        report = result.report()
        (out / "report.txt").write_text(report + "\n", encoding="utf-8")
        written.append(out / "report.txt")
        written = [stage.target / Path(w).name for w in written]
        written += program_outputs(args, result.robot, result.path, result.trajectory)
    print(report)
    print("wrote " + ", ".join(str(w) for w in written))
    return 0


def check_program_args(args) -> None:
    """CliError for a ``--signal`` that is no RAPID identifier or a ``--rapid``/``--program``
    file in a directory that does not exist (checked before any work)."""
    from pathlib import Path as FilePath

    from ...painting.program import _IDENT

    if not _IDENT.match(args.signal):
        raise CliError(f"--signal must be a RAPID identifier (a letter, then letters, digits or _); "
                       f"got {args.signal!r}")
    for opt in ("rapid", "program"):
        f = getattr(args, opt)
        if f is not None and not FilePath(f).parent.is_dir():
            raise CliError(f"--{opt}: no such directory {FilePath(f).parent}")


def timing_plots(robot, trajectory, out) -> list:
    """The gun speed against time and the joint speeds and accelerations with their limits."""
    from ... import painting as P

    return [P.plot_gun_speed(trajectory, out / "gun_speed.png", robot=robot),
            P.plot_joint_limits(trajectory, out / "joint_limits.png", robot)]


def program_outputs(args, robot, path, trajectory) -> list:
    """The RAPID module and the JSON program asked for with ``--rapid`` and ``--program``."""
    from ... import painting as P

    if args.rapid is None and args.program is None:
        return []
    program = P.make_program(robot, path, trajectory, signal=args.signal, zone=args.zone)
    from ...outputs import atomic_path

    written = []
    for f, write in ((args.rapid, P.write_rapid), (args.program, P.write_program_json)):
        if f is not None:  # each complete or absent
            with atomic_path(f) as tmp:
                write(program, tmp)
            written.append(Path(f))
    return written
