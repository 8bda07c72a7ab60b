"""``make bench``: the benchmark table of ``ik7r bench`` (same options, e.g. ``--quick``)."""

from __future__ import annotations

import sys

from ik7r.bench import main

if __name__ == "__main__":
    sys.exit(main())
