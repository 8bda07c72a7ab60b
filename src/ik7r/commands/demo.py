"""``ik7r demo``: the paper's Simulation 1 solved on the built-in robot."""

from __future__ import annotations

import numpy as np

from ..cli import load_cli_robot
from ._common import fmt_deg

PAPER_TABLE2 = np.array([
    [60.0000, 60.0000, 0.0000, -30.0000, 60.0000, 30.0000],
    [60.0000, 60.0000, 0.0000, -159.3775, -60.0000, 159.3775],
    [60.0360, -27.5107, 178.4662, -178.6218, 21.6300, -177.6485],
    [60.0360, -27.5107, 178.4662, 19.1657, -21.6300, -15.4359],
    [-119.9640, 207.5107, 1.5338, 1.3782, 21.6300, -177.6485],
    [-119.9640, 207.5107, 1.5338, -160.8343, -21.6300, -15.4359],
    [-120.0000, 120.0000, 180.0000, 150.0000, 60.0000, 30.0000],
    [-120.0000, 120.0000, 180.0000, 20.6225, -60.0000, 159.3775],
])
"""The paper's Table 2 (OCR slips corrected, see NOTES.md), degrees."""

SIMULATION1_Q = np.radians([60.0, 60.0, 0.0, -30.0, 60.0, 30.0])


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="solve the paper's Simulation 1 (Table 2)")
    p.set_defaults(run=run)


def run(args) -> int:
    robot = load_cli_robot(args)
    T = robot.fk(SIMULATION1_Q)
    print(f"Simulation 1 on robot {robot.name}: the pose of q = [60, 60, 0, -30, 60, 30] deg")
    for row in T:
        print("  " + " ".join(f"{v:14.7f}" for v in row))
    print("\nik(T, config) for the eight configurations of the paper's Appendix 3:")
    print(f"{'cfg':>3} {'q1':>10} {'q2':>10} {'q3':>10} {'q4':>10} {'q5':>10} {'q7':>10}"
          f"  FK error ({robot.unit})  rot error")
    for c in range(1, 9):
        q = robot.ik(T, c)
        Tq = robot.fk(q)
        dp = np.linalg.norm(Tq[:3, 3] - T[:3, 3])
        dr = np.abs(Tq[:3, :3] - T[:3, :3]).max()
        print(f"{c:3d} {fmt_deg(q)}  {dp:.1e}            {dr:.1e}")
    sols = robot.ik_all(T)
    print(f"\nik_all: {len(sols)} distinct solutions (every one verified by forward kinematics).")
    return 0
