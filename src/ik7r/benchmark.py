"""The benchmark's former name: everything is in :mod:`ik7r.bench` now.

``from ik7r.benchmark import run_benchmarks`` keeps working; new code imports
:mod:`ik7r.bench`.
"""

from __future__ import annotations

import sys

from .bench import *  # noqa: F403
from .bench import __all__, main  # noqa: F401

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
