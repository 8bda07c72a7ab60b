"""``ik7r`` with numba made unimportable: what a command line without the JIT would cost.

Run by the benchmark's start-up rows: ``python -m ik7r.bench.cli_without_numba ik ...``.
"""

from __future__ import annotations

import sys


def main() -> int:
    sys.modules["numba"] = None  # type: ignore[assignment]  # an import of numba now fails
    import ik7r.cli

    return ik7r.cli.main(sys.argv[1:])


if __name__ == "__main__":
    sys.exit(main())
