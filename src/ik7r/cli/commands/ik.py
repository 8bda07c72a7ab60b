"""``ik7r ik``: inverse kinematics of one pose (one configuration, or every solution)."""

from __future__ import annotations

import numpy as np

from ..errors import CliError, NoSolution
from ._common import (
    add_pose_arguments,
    finite_float,
    fmt_deg,
    load_cli_robot,
    pose_from_args,
    print_json,
)


def add_parser(sub) -> None:
    p = sub.add_parser("ik", help="inverse kinematics: tool pose -> joints (deg)",
                       description="Inverse kinematics of one tool pose. Prints joints "
                                   "[q1 q2 q3 q4 q5 q7] in degrees.")
    add_pose_arguments(p)
    g = p.add_mutually_exclusive_group()
    g.add_argument("--config", type=int, default=None, metavar="N",
                   help="configuration 1..8 (the paper's Appendix 3; default 1)")
    g.add_argument("--all", action="store_true", help="every solution")
    p.add_argument("--seed", nargs=6, type=finite_float, metavar="Q",
                   help="joints (deg) choosing among solutions sharing a configuration")
    p.add_argument("--within-limits", action="store_true", help="only solutions inside the joint limits")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(run=run)


def run(args) -> int:
    from ...errors import UnreachableError

    robot = load_cli_robot(args)
    T = pose_from_args(args)
    seed = None if args.seed is None else np.radians(args.seed)
    try:
        if args.all:
            sols = robot.ik_all(T, within_limits=args.within_limits, seed=seed)
            if len(sols) == 0:
                limits = " within the joint limits" if args.within_limits else ""
                raise NoSolution(f"the pose has no solution{limits}")
        else:
            config = 1 if args.config is None else args.config
            if not 1 <= config <= 8:
                raise CliError(f"--config must be 1..8; got {config}")
            try:
                sols = robot.ik(T, config, seed=seed, within_limits=args.within_limits)[None]
            except UnreachableError as exc:
                raise NoSolution(str(exc)) from exc
    except NoSolution as exc:
        if args.json:  # valid JSON on stdout in any case: no solution is an empty list
            print_json({"robot": robot.name, "unit": robot.unit, "solutions": [], "reason": str(exc)})
            args._json_done = True
        raise
    configs = robot.config_of(sols)
    fk = robot.fk(sols)
    err = np.linalg.norm(fk[:, :3, 3] - T[:3, 3], axis=1)
    if args.json:
        print_json({"robot": robot.name, "unit": robot.unit, "solutions": [
            {"config": int(c), "q_deg": np.degrees(q).tolist(), "position_error": float(e)}
            for q, c, e in zip(sols, configs, err)]})
        return 0
    print(f"{'cfg':>3} {'q1':>10} {'q2':>10} {'q3':>10} {'q4':>10} {'q5':>10} {'q7':>10}  "
          f"FK error ({robot.unit})")
    for q, c, e in zip(sols, configs, err):
        print(f"{c:3d} {fmt_deg(q)}  {e:.1e}")
    return 0
