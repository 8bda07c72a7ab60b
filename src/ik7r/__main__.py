"""``python -m ik7r``: the command line (see :mod:`ik7r.cli`)."""

import sys

from ik7r.cli import main

sys.exit(main())
