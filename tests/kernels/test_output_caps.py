"""Issue 12 item 6: no output cap of the complete solver drops a solution or a candidate root
silently. The caps (MAX_SOLUTIONS rows of ``_add``, ROOT_CAP roots of ``_roots``) are sized for
what a pose can have; reaching one raises. Shown with outputs smaller than a pose needs, on the
pure-Python kernels (``IK7R_JIT=0``: the same code, without compiling a new entry point)."""

import os
import subprocess
import sys

_CASE = r"""
import numpy as np
import ik7r
from ik7r._kernels import bernstein_tables, complete, constants

robot = ik7r.load_robot()
K = robot.kernel_params
Bm, bnorm = bernstein_tables(K)
T = robot.fk(np.radians([60.0, 60.0, 0.0, -30.0, 60.0, 30.0]))  # the paper's pose: 8 solutions
hint = np.zeros(6)
n = complete.solve_all(T, K, Bm, bnorm, hint, False, np.empty((32, 6)))
print("full", n)
try:
    complete.solve_all(T, K, Bm, bnorm, hint, False, np.empty((n - 1, 6)))
    print("rows: no error")
except RuntimeError as exc:
    print("rows:", exc)
T07 = np.empty((4, 4))
complete.frame07(T, K, T07)
ws = np.zeros(constants.WORK_SIZE)
a = T07[:3, 2] / np.linalg.norm(T07[:3, 2])
nr = complete._roots(0, T07[:3, 3].copy(), a, K, Bm, bnorm, np.empty(constants.ROOT_CAP), ws)
print("roots", nr)
try:
    complete._roots(0, T07[:3, 3].copy(), a, K, Bm, bnorm, np.empty(nr - 1), ws)
    print("roots: no error")
except RuntimeError as exc:
    print("roots:", exc)
"""


def test_reaching_a_cap_raises():
    env = dict(os.environ, IK7R_JIT="0")
    proc = subprocess.run([sys.executable, "-c", _CASE], capture_output=True, text=True, env=env,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr
    lines = dict(line.split(" ", 1) for line in proc.stdout.splitlines())
    assert lines["full"] == "8"
    assert int(lines["roots"]) >= 2
    assert "more distinct solutions than the output holds" in lines["rows:"]
    assert "more candidate roots than ROOT_CAP" in lines["roots:"]
