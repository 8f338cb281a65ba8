"""``python -m railcheck.cli``: the command line."""

import sys

from railcheck.cli import main

sys.exit(main())
