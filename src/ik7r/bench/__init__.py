"""Benchmarks: ik7r's solvers against a numpy forward-kinematics yardstick, the paper's
reported times and generic IK solvers, in one run, every timed answer verified.

>>> from ik7r.bench import run_benchmarks
>>> report = run_benchmarks(quick=True)          # doctest: +SKIP
>>> print(report.format_table())                 # doctest: +SKIP

The command line: ``ik7r bench [--quick] [--n N] [--json FILE]``; ``make bench`` runs
``benchmarks/run.py``, which is the same.

The package: :mod:`~ik7r.bench.runner` (:func:`run_benchmarks`, the machine),
:mod:`~ik7r.bench.rows` (each group of rows, timed and verified), :mod:`~ik7r.bench.report`
(the table and its formatting), :mod:`~ik7r.bench.verify` (the yardstick and the checks) and
the scripts run in fresh processes with ``python -m``: :mod:`~ik7r.bench.probe_startup`
(start-up, warm and cold), :mod:`~ik7r.bench.probe_big` (millions of poses, peak memory),
:mod:`~ik7r.bench.cli_without_numba`.

How to read the table
---------------------
Absolute times depend on the machine, so every time is also given as a *ratio* to a
yardstick timed in the same run: the plain vectorised numpy forward kinematics of the same
poses (the product of the seven eq. (1) matrices), per pose for batches ("batch"), and one
call for one pose for single calls ("single"). The issue's targets are ratios (except the
trajectory throughput and the start-up times, which are absolute). ``failures`` counts timed
answers that fail the forward-kinematics check, plus, for the complete solvers, poses whose
known solution (the joints the pose was made from) was not found; it must be 0. ``solved``
is the share of poses that got an answer (the numeric baselines can fail to converge).
"""

from __future__ import annotations

from .report import BenchReport, Row, Sizes, format_markdown, format_table
from .rows import PAPER_MS_PER_POINT, PAPER_MS_PER_POSE, SEED
from .runner import machine_info, main, run_benchmarks
from .verify import numpy_fk

__all__ = [
    "Row",
    "BenchReport",
    "Sizes",
    "run_benchmarks",
    "numpy_fk",
    "machine_info",
    "format_table",
    "format_markdown",
    "main",
    "PAPER_MS_PER_POSE",
    "PAPER_MS_PER_POINT",
    "SEED",
]
