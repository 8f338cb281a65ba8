"""Errors raised by the FE package."""

from __future__ import annotations


class NumericalError(RuntimeError):
    """A numerical failure: a solve that did not converge, a singular system (exit 3)."""


class ModelError(ValueError):
    """A model that cannot be solved as stated: a load on a group the mesh lacks, no
    support, a degenerate mesh (exit 2)."""

    def __init__(self, field: str, message: str):
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}" if field else message)

    def __reduce__(self):      # raised in a worker process, re-raised in the caller
        return type(self), (self.field, self.message)
