"""Progress lines on stderr for runs longer than a few seconds: '[elapsed s] stage message'."""

from __future__ import annotations

import sys
import time


class Progress:
    """Per-stage lines on stderr: ``[   1.2 s] stage      what``, elapsed since creation."""

    def __init__(self, quiet: bool = False):
        self.quiet = quiet
        self.t0 = time.perf_counter()

    def say(self, stage: str, message: str) -> None:
        if not self.quiet:
            # one write per line: lines said from several threads never interleave
            print(f"[{time.perf_counter() - self.t0:7.1f} s] {stage:<10} {message}\n", end="", file=sys.stderr, flush=True)
