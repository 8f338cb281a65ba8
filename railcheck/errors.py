"""Errors of the application layer and the exit status each one maps to.

Exit statuses: 0 pass, 1 check failed, 2 bad input or impossible
mechanism, 3 numerical failure.
"""

from __future__ import annotations

EXIT_PASS = 0
EXIT_FAIL = 1
EXIT_INPUT = 2
EXIT_NUMERICAL = 3


class InputError(ValueError):
    """A bad scene, option or mechanism: one line naming the field; exit status 2."""

    def __init__(self, field: str, message: str):
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}" if field else message)

    def __reduce__(self):      # raised in a worker process, re-raised in the caller
        return type(self), (self.field, self.message)
