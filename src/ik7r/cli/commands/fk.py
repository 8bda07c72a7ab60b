"""``ik7r fk Q1 Q2 Q3 Q4 Q5 Q7``: forward kinematics (degrees in, pose out)."""

from __future__ import annotations

import numpy as np

from ...geometry.rotations import matrix_to_rpy
from ._common import load_cli_robot, numbers, print_json


def add_parser(sub) -> None:
    p = sub.add_parser("fk", help="forward kinematics: joints (deg) -> tool pose",
                       description="Forward kinematics of the independent joints [q1 q2 q3 q4 q5 q7] "
                                   "in degrees (q6 = -q5).")
    p.add_argument("q", nargs="*", metavar="Q", help="the 6 joint angles q1 q2 q3 q4 q5 q7 in degrees")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(run=run)


def run(args) -> int:
    q = numbers(args.q, 6, "joint values (q1 q2 q3 q4 q5 q7, deg)")
    robot = load_cli_robot(args)
    T = robot.fk(np.radians(q))
    rpy = np.degrees(matrix_to_rpy(T[:3, :3]))
    if args.json:
        print_json({"robot": robot.name, "unit": robot.unit, "matrix": T.tolist(),
                    "position": T[:3, 3].tolist(), "rpy_deg": rpy.tolist()})
        return 0
    print(f"robot {robot.name}, pose of the tool ({robot.unit}):")
    for row in T:
        print("  " + " ".join(f"{v:14.7f}" for v in row))
    print(f"position {' '.join(f'{v:.6f}' for v in T[:3, 3])} {robot.unit}")
    print(f"rpy      {' '.join(f'{v:.6f}' for v in rpy)} deg")
    return 0
