"""Helpers shared by the subcommands: parsing numbers and poses, printing joints."""

from __future__ import annotations

import argparse
import json
import math
import sys

import numpy as np

from ..errors import CliError


def load_cli_robot(args):
    """The robot named by ``--robot`` (CliError on a missing or malformed file)."""
    from ...robot.files import load_robot

    try:
        return load_robot(args.robot)
    except (FileNotFoundError, ValueError) as exc:
        raise CliError(str(exc)) from exc
    except OSError as exc:
        raise CliError(f"cannot read robot file {args.robot}: {exc.strerror or exc}") from exc

#: Largest orthonormality error (max entry of ``|R^T R - I|``) of a rotation given at the
#: command line (``--matrix``): what numbers printed with 4 decimals give. Such rotations are
#: projected onto the nearest rotation, with a note on stderr when the error exceeds the API's
#: strict ``ik7r.geometry.checks.ORTHONORMAL_TOL``.
CLI_ORTHONORMAL_TOL = 1e-3


def finite_float(text: str) -> float:
    """argparse type: a finite number (``nan`` and ``inf`` are refused)."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return v


def count(text: str) -> int:
    """argparse type: a non-negative integer (``1e6`` and ``1_000_000`` are accepted)."""
    t = text.strip().replace("_", "")
    try:
        v = int(t)
    except ValueError:
        try:
            f = float(t)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if not math.isfinite(f) or f != int(f):
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        v = int(f)
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a non-negative whole number, got {text!r}")
    return v


def numbers(values, n: int, what: str) -> list[float]:
    """``values`` (strings from ``nargs="*"``) as ``n`` finite numbers; CliError saying what
    was expected otherwise ("6 joint values expected, got 5")."""
    values = list(values or [])
    if len(values) != n:
        raise CliError(f"{n} {what} expected, got {len(values)}")
    try:
        return [finite_float(v) for v in values]
    except argparse.ArgumentTypeError as exc:
        raise CliError(f"{what}: {exc}") from None


def pose_from_args(args) -> np.ndarray:
    """The world <- tool pose from ``--position/--rpy`` or ``--matrix`` (mm or the robot's
    unit, degrees) as a (4, 4) array; CliError on bad input.

    A ``--matrix`` rotation within :data:`CLI_ORTHONORMAL_TOL` of orthonormal is projected onto
    the nearest rotation (one line on stderr says by how much when the API would refuse it).
    """
    from ...geometry.checks import check_transforms, project_transforms
    from ...geometry.rotations import rpy_to_matrix, transform

    if args.matrix is not None:
        if args.position is not None or args.rpy is not None:
            raise CliError("give either --matrix or --position/--rpy, not both")
        vals = args.matrix
        if len(vals) not in (12, 16):
            raise CliError(f"--matrix: 12 or 16 numbers expected (row by row), got {len(vals)}")
        M = np.eye(4)
        M.reshape(-1)[: len(vals)] = vals
        try:
            M, err, moved = project_transforms(M, tol=CLI_ORTHONORMAL_TOL, name="--matrix")
        except ValueError as exc:
            raise CliError(str(exc)) from exc
        from ...geometry.checks import ORTHONORMAL_TOL

        if err > ORTHONORMAL_TOL:
            print(f"note: --matrix rotation projected onto the nearest rotation (max |R^T R - I| was "
                  f"{err:.2e}; entries moved by up to {moved:.2e})", file=sys.stderr)
    else:
        if args.position is None or args.rpy is None:
            raise CliError("give the pose with --position X Y Z and --rpy R P Y, or --matrix")
        M = transform(rpy_to_matrix(np.radians(args.rpy)), args.position)
    try:
        return check_transforms(M, "the pose")
    except ValueError as exc:
        raise CliError(str(exc)) from exc


def add_pose_arguments(p) -> None:
    p.add_argument("--position", nargs=3, type=finite_float, metavar=("X", "Y", "Z"),
                   help="tool position (the robot's length unit, mm for the paper robot)")
    p.add_argument("--rpy", nargs=3, type=finite_float, metavar=("R", "P", "Y"),
                   help="roll, pitch, yaw in degrees (URDF: fixed axes X-Y-Z)")
    p.add_argument("--matrix", nargs="+", type=finite_float, metavar="M",
                   help="12 or 16 numbers of the pose matrix, row by row (a rotation rounded to 4 "
                        "decimals is accepted and projected onto the nearest rotation)")


def print_json(obj) -> None:
    print(json.dumps(obj, indent=2))


def fmt_deg(q) -> str:
    return " ".join(f"{v:10.4f}" for v in np.degrees(q))
