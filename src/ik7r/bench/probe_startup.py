"""Time a fresh process's start.

Run by the benchmark's start-up rows in a new process, with the numba cache as it is (warm)
or pointed at an empty directory (``NUMBA_CACHE_DIR``: cold, every kernel compiles)::

    python -m ik7r.bench.probe_startup [--first-answer] [ROBOT]

Prints one JSON line of seconds. By default (the stages of numba's JIT route; the benchmark
runs it with ``IK7R_AOT=0``): ``numpy`` and ``numba`` (their imports), ``ik7r`` (``import ik7r``
and ``load_robot``), ``first_kernel`` (the first ``robot.fk``) and ``first_ik`` (the first
``robot.ik_all`` after it). With ``--first-answer``: what a user sees, ``import`` (``import
ik7r`` and ``load_robot``) and ``first_answer`` (``robot.ik_all`` as the process's first
compiled call; the pose is made with numpy), with ``compiled`` (1 when the answer came from
the kernels compiled ahead of time, :mod:`ik7r._kernels.aot`) and ``numba`` (1 when numba was
imported).
"""

from __future__ import annotations

import json
import sys
import time


def first_answer(robot_name: str | None) -> dict[str, float]:
    t0 = time.perf_counter()
    import numpy as np

    import ik7r
    from ik7r.bench.verify import numpy_fk

    robot = ik7r.load_robot(robot_name)
    T = numpy_fk(robot, np.full(6, 0.5))
    t1 = time.perf_counter()
    robot.ik_all(T)
    t2 = time.perf_counter()
    from ik7r._kernels import aot

    return {"import": t1 - t0, "first_answer": t2 - t1, "compiled": float(aot.load() is not None),
            "numba": float("numba" in sys.modules)}


def stages(robot_name: str | None) -> dict[str, float]:
    t0 = time.perf_counter()
    import numpy as np

    t1 = time.perf_counter()
    import numba  # noqa: F401

    t2 = time.perf_counter()
    import ik7r

    robot = ik7r.load_robot(robot_name)
    t3 = time.perf_counter()
    robot.fk(np.zeros(6))
    t4 = time.perf_counter()
    robot.ik_all(robot.fk(np.full(6, 0.5)))
    t5 = time.perf_counter()
    return {"numpy": t1 - t0, "numba": t2 - t1, "ik7r": t3 - t2, "first_kernel": t4 - t3,
            "first_ik": t5 - t4}


def main(argv: list[str]) -> None:
    answer = "--first-answer" in argv
    names = [a for a in argv if a != "--first-answer"]
    robot_name = names[0] if names else None
    print(json.dumps(first_answer(robot_name) if answer else stages(robot_name)))


if __name__ == "__main__":
    main(sys.argv[1:])
