"""Helpers shared by the subcommands: parsing poses, printing joints."""

from __future__ import annotations

import json

import numpy as np

from ..errors import CliError


def load_cli_robot(args):
    """The robot named by ``--robot`` (CliError on a missing or malformed file)."""
    from ...robot.files import load_robot

    try:
        return load_robot(args.robot)
    except (FileNotFoundError, ValueError) as exc:
        raise CliError(str(exc)) from exc


def pose_from_args(args) -> np.ndarray:
    """The world <- tool pose from ``--position/--rpy`` or ``--matrix`` (mm or the robot's
    unit, degrees) as a (4, 4) array; CliError on bad input."""
    from ...geometry.checks import check_transforms
    from ...geometry.rotations import rpy_to_matrix, transform

    if args.matrix is not None:
        if args.position is not None or args.rpy is not None:
            raise CliError("give either --matrix or --position/--rpy, not both")
        vals = args.matrix
        if len(vals) not in (12, 16):
            raise CliError(f"--matrix takes 12 or 16 numbers (row-major); got {len(vals)}")
        M = np.eye(4)
        M.reshape(-1)[: len(vals)] = vals
    else:
        if args.position is None or args.rpy is None:
            raise CliError("give the pose with --position X Y Z and --rpy R P Y, or --matrix")
        M = transform(rpy_to_matrix(np.radians(args.rpy)), args.position)
    try:
        return check_transforms(M, "the pose")
    except ValueError as exc:
        raise CliError(str(exc)) from exc


def add_pose_arguments(p) -> None:
    p.add_argument("--position", nargs=3, type=float, metavar=("X", "Y", "Z"),
                   help="tool position (the robot's length unit, mm for the paper robot)")
    p.add_argument("--rpy", nargs=3, type=float, metavar=("R", "P", "Y"),
                   help="roll, pitch, yaw in degrees (URDF: fixed axes X-Y-Z)")
    p.add_argument("--matrix", nargs="+", type=float, metavar="M",
                   help="12 or 16 numbers of the pose matrix, row by row")


def print_json(obj) -> None:
    print(json.dumps(obj, indent=2))


def fmt_deg(q) -> str:
    return " ".join(f"{v:10.4f}" for v in np.degrees(q))
