"""``ik7r gun fit STRIPE.csv --model M``: calibrate a spray gun from a measured stripe.

The stripe is the film across one straight stroke sprayed at ``--speed`` and ``--standoff`` over
a flat plate perpendicular to the gun; the CSV has a header and the columns ``offset`` (distance
across the stroke, ``--unit``) and ``thickness_um``. Writes the gun file (TOML) and prints the
fitted parameters and the fit's residual. Exit status 2 on bad input.
"""

from __future__ import annotations

from ..errors import CliError
from ._common import finite_float


def add_parser(sub) -> None:
    p = sub.add_parser("gun", help="spray guns: fit a model to a measured stripe",
                       description="Spray-gun models (gaussian, beta, double-beta) and their calibration.")
    kinds = p.add_subparsers(dest="gun_kind", metavar="ACTION", parser_class=type(p))
    f = kinds.add_parser("fit", help="fit a gun model to a stripe profile and write the gun file",
                         description="Fit a model's parameters to a measured stripe (columns offset, "
                                     "thickness_um) sprayed at a known speed and standoff; write the gun "
                                     "file (TOML) and report the residual.")
    f.add_argument("stripe", metavar="STRIPE.csv", help="measured stripe: offset, thickness_um")
    f.add_argument("--model", required=True, choices=("gaussian", "beta", "double-beta"),
                   help="the gun model")
    f.add_argument("--speed", type=finite_float, required=True, metavar="V", help="stroke speed (unit/s)")
    f.add_argument("--standoff", type=finite_float, required=True, metavar="D",
                   help="standoff of the stroke (unit)")
    f.add_argument("--unit", default="mm", metavar="U",
                   help="length unit of offset, speed, standoff (default mm)")
    f.add_argument("--b", type=finite_float, default=None, metavar="D",
                   help="double-beta: the fan's half-length along the travel (a stripe cannot tell it)")
    f.add_argument("--beta2", type=finite_float, default=None, metavar="B",
                   help="double-beta: the exponent along the travel (a stripe cannot tell it)")
    f.add_argument("--name", default=None, help="gun name in the file (default the stripe file's stem)")
    f.add_argument("--out", default=None, metavar="FILE.toml", help="gun file to write (default STRIPE.toml)")
    f.set_defaults(run=run_fit)
    p.set_defaults(run=_no_kind)


def _no_kind(args) -> int:
    raise CliError("gun: give the action: 'ik7r gun fit STRIPE.csv --model M --speed V --standoff D'")


def run_fit(args) -> int:
    from pathlib import Path as FilePath

    from ...painting.spray import fit_stripe, gun_to_toml, load_stripe_csv

    src = FilePath(args.stripe)
    try:
        offset, thickness = load_stripe_csv(src)
        fit = fit_stripe(offset, thickness, model=args.model, speed=args.speed, standoff=args.standoff,
                         unit=args.unit, b=args.b, beta2=args.beta2, name=args.name or src.stem)
    except (FileNotFoundError, ValueError) as exc:
        raise CliError(str(exc)) from exc
    out = FilePath(args.out) if args.out else src.with_suffix(".toml")
    comment = (f"fitted by ik7r gun fit to {src.name} (speed {args.speed:g} {args.unit}/s, standoff "
               f"{args.standoff:g} {args.unit}): residual rms {fit.rms:.4g} um "
               f"({100 * fit.rms_relative:.3g} % of the peak), max {fit.max_abs:.4g} um")
    from ...outputs import write_text_atomic

    write_text_atomic(out, gun_to_toml(fit.gun, comment=comment))
    print(fit.report())
    print(f"wrote {out}")
    return 0
