"""Progress lines on stderr for runs longer than a few seconds: '[elapsed s] stage message'."""

from __future__ import annotations

import sys
import textwrap
import time

#: the console's width (columns); a longer progress line wraps under its message
WIDTH = 100


class Progress:
    """Per-stage lines on stderr: ``[   1.2 s] stage      what``, elapsed since creation."""

    def __init__(self, quiet: bool = False, sink=None):
        """``sink``: a callable that receives each line instead of stderr (the API's
        ``progress=`` callback)."""
        self.quiet = quiet
        self.sink = sink
        self.t0 = time.perf_counter()

    def say(self, stage: str, message: str) -> None:
        if self.quiet:
            return
        line = f"[{time.perf_counter() - self.t0:7.1f} s] {stage:<10} {message}"
        if self.sink is not None:
            self.sink(line)
            return
        # one write per line: lines said from several threads never interleave
        print((wrapped(line) if _terminal() else line) + "\n", end="", file=sys.stderr, flush=True)


def wrapped(line: str) -> str:
    """A progress ``line`` within :data:`WIDTH` columns, its continuation indented under
    the message (a word longer than the width, a path, stays whole)."""
    if len(line) <= WIDTH:
        return line
    return "\n".join(textwrap.wrap(line, WIDTH, subsequent_indent=" " * 23, break_long_words=False, break_on_hyphens=False))


def _terminal() -> bool:
    """Whether stderr is a terminal: a person reads it at its width; a pipe or a log
    (scripts, CI, the tests that wait for a line) gets each progress line whole."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False
