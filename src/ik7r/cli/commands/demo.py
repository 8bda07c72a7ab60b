"""``ik7r demo``: the paper's Simulation 1 solved on the built-in robot, then a quick reproduction."""

from __future__ import annotations

import numpy as np

from ...reproduce.published import PAPER_TABLE2, SIMULATION1_Q_DEG
from ..errors import CliError
from ._common import fmt_deg, load_cli_robot

__all__ = ["PAPER_TABLE2", "SIMULATION1_Q", "add_parser", "run"]

#: Simulation 1's target joints (rad).
SIMULATION1_Q = np.radians(SIMULATION1_Q_DEG)


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="solve the paper's Simulation 1 (Table 2), then a quick reproduction")
    p.add_argument("--out", default="out/demo", metavar="DIR",
                   help="where the quick reproduction goes (default out/demo)")
    p.add_argument("--no-reproduce", action="store_true", help="only print Simulation 1")
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
        print(f"{c:3d} {fmt_deg(np.round(q, 12) + 0.0)}  {dp:.1e}            {dr:.1e}")
    sols = robot.ik_all(T)
    print(f"\nik_all: {len(sols)} distinct solutions (every one verified by forward kinematics).")
    if args.no_reproduce:
        return 0
    if robot.name != "paper":
        print("\n(the quick reproduction of the paper needs the paper's robot: skipped)")
        return 0
    return _quick_reproduction(args.out)


def _quick_reproduction(out) -> int:
    from pathlib import Path

    from ...reproduce import QUICK
    from .reproduce import reproduce_into

    out = Path(out)
    if out.exists() and not out.is_dir():
        raise CliError(f"--out must be a directory; {out} is a file")
    print(f"\nQuick reproduction of the paper's tables and figures into {out}/ ...")
    result = reproduce_into(out, QUICK, "reproducing the paper (quick)")
    t5 = result.table5[0]
    t3 = result.table3
    print(f"Table 5 (random targets): the paper's method {t5.paper_solved}/{t5.attempts} solved, max error "
          f"{t5.paper_maximum_error:.1e} mm; complete solver {t5.complete_solved}/{t5.attempts}, max error "
          f"{t5.complete_maximum_error:.1e} mm (the paper: 0.01 mm)")
    print(f"Table 3: the paper's method {t3[0].time_ms:.2f} ms here (the paper: 65 ms in MATLAB); "
          f"Newton-Raphson from [0, 60, 0, -30, 0, 30]: {'converged' if t3[3].converged else t3[3].reason}")
    print(f"Wrote {len(result.files)} files to {out}/ in {result.elapsed:.1f} s "
          f"({', '.join(Path(p).name for p in result.files.values())}).")
    if "figure12" not in result.files:
        print(f"note: {result.painting_note}")
    print(f"Open {out / 'report.md'} for each table beside the paper's and what differs.")
    return 0
