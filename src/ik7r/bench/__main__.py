"""``python -m ik7r.bench``: the benchmark table, same options as ``ik7r bench``."""

import sys

from .runner import main

sys.exit(main())
