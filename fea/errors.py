"""Errors raised by the FE package (derived from :mod:`railcheck.base.errors`)."""

from __future__ import annotations

from railcheck.base.errors import InputError, NumericalError

__all__ = ["ModelError", "NumericalError"]


class ModelError(InputError):
    """A model that cannot be solved as stated: a load on a group the mesh lacks, no
    support, a degenerate mesh (exit 2)."""
