"""The public API as a user writes it, checked by mypy in ``make test`` (never run by pytest:
the file name does not start with test_). A changed signature or return type fails the check.
"""

from __future__ import annotations

import numpy as np

import ik7r
from ik7r.bench import BenchReport, Sizes, run_benchmarks
from ik7r.ik import Lost, NumericResult, PaperResult, PathIK, follow, newton_raphson
from ik7r.painting import PaintResult, Path, PathSolution, paint_raster, raster_path, solve_path

robot: ik7r.Robot = ik7r.load_robot()
irb: ik7r.Robot = ik7r.load_robot("irb5400")
T: np.ndarray = robot.fk([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
one: np.ndarray = robot.ik(T, config=1)
same: np.ndarray = robot.ik(T, config=(1, 1, 1), seed=one)
every: np.ndarray = robot.ik_all(T, within_limits=True)
q, ok = robot.ik_batch(np.stack([T, T]), 1)
qa, valid = robot.ik_all_batch(np.stack([T, T]))
path: PathIK = robot.ik_path(np.stack([T, T]), config=1, seed=one)
branch: PathIK = robot.ik_path(np.stack([T, T]), 1, seed=one, keep="branch", within_limits=True,
                               pose_at=lambda u: T, u=[0.0, 1.0], max_depth=4)
why: dict[int, Lost] = branch.lost
step, lost = follow(robot, lambda u: T, one, 0.0, 1.0, max_step=0.05)
stroke: Path = raster_path()
solved: PathSolution = solve_path(robot, stroke, 1, keep="branch")
painted: PaintResult = paint_raster(robot, duration=20.0)
paper: PaperResult = robot.ik_paper(T, 1)
numeric: NumericResult = newton_raphson(robot, T, one)
moved: ik7r.Robot = robot.with_tool(np.eye(4))
n: int = ik7r.MAX_SOLUTIONS
report: BenchReport = run_benchmarks(robot, sizes=Sizes(batch=10), startup=False, baselines=False)
try:
    robot.ik(T, config=2)
except ik7r.UnreachableError as err:
    message: str = str(err)
