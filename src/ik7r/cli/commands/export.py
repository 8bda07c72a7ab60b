"""``ik7r [--robot X] export --format toml|urdf [--out FILE]``: write the robot as a robot file."""

from __future__ import annotations

from ..errors import CliError
from ._common import load_cli_robot


def add_parser(sub) -> None:
    p = sub.add_parser("export", help="write the robot as a TOML robot file or a URDF",
                       description="Write the robot given by --robot (a built-in name, a .toml or a .urdf) "
                                   "as a TOML robot file (modified DH, degrees) or as a URDF (metres, "
                                   "joint 6 a <mimic> of joint 5). Both load back with the same forward "
                                   "kinematics.")
    p.add_argument("--format", choices=("toml", "urdf"), required=True, help="file format")
    p.add_argument("--out", metavar="FILE", default=None, help="output file (default: standard output)")
    p.add_argument("--unit", choices=("m", "cm", "mm"), default=None,
                   help="TOML only: length unit to write (default: the robot's own; URDF is always metres)")
    p.set_defaults(run=run)


def run(args) -> int:
    from ...robot.files import robot_in_unit

    robot = load_cli_robot(args)
    if args.unit is not None:
        if args.format == "urdf":
            raise CliError("--unit applies to --format toml only (a URDF is always in metres)")
        try:
            robot = robot_in_unit(robot, args.unit)
        except ValueError as exc:
            raise CliError(str(exc)) from exc
    try:
        text = robot.to_toml() if args.format == "toml" else robot.to_urdf()
    except ValueError as exc:
        raise CliError(str(exc)) from exc
    if args.out is None:
        print(text, end="")
        return 0
    from ...outputs import write_text_atomic

    write_text_atomic(args.out, text)  # complete or absent (OutputError: exit 2, one line)
    return 0
