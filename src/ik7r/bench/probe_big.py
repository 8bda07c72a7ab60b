"""Solve N random poses chunk by chunk and print the time, the failures and the peak memory.

Run by the benchmark in a fresh process (its peak resident memory is the number reported)::

    python -m ik7r.bench.probe_big N [ROBOT]
"""

from __future__ import annotations

import json
import resource
import sys
import time

import numpy as np


def main(argv: list[str]) -> None:
    import ik7r
    from ik7r.bench.rows import SEED
    from ik7r.bench.verify import verify_all
    from ik7r.ik.chunked import RandomPoses, solve_all_chunked

    n = int(argv[0])
    robot = ik7r.load_robot(argv[1] if len(argv) > 1 else None)
    robot.ik_all_batch(robot.fk(np.zeros((2, 6))))  # load the kernels before timing
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t0 = time.perf_counter()
    fails = solutions = 0
    for res in solve_all_chunked(robot, RandomPoses(robot, n, seed=SEED)):
        solutions += int(res.count.sum())
        k = slice(0, len(res.count), 97)  # verify 1 pose in 97 (all of them would double the time)
        assert res.joints is not None  # random poses are made from joints
        fails += verify_all(robot, res.q[k], res.valid[k], res.T[k], res.joints[k])
    seconds = time.perf_counter() - t0
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"seconds": seconds, "failures": fails, "solutions": solutions,
                      "rss_mb": rss / 1024, "rss_before_mb": rss0 / 1024}))


if __name__ == "__main__":
    main(sys.argv[1:])
