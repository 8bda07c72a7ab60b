"""``python -m ik7r``: the command line (see :mod:`ik7r.cli.app`)."""

import sys

from ik7r.cli.app import main

sys.exit(main())
