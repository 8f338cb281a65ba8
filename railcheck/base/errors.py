"""The one error hierarchy of railcheck, and the exit status each error maps to.

Every error the program reports names the field it is about (a scene key such as
``mechanism.ground``, a command-line option, or "" when there is none) and carries its
exit status, so the command line turns any of them into one line and a status with a
single ``except``. The domain packages (``railcheck.kinematics``, ``railcheck.fea``) derive
their errors from these classes; this module imports nothing, so any layer may use it.

Exit statuses: 0 pass, 1 check failed, 2 bad input or impossible mechanism, 3 numerical
failure.
"""

from __future__ import annotations

EXIT_PASS = 0
EXIT_FAIL = 1
EXIT_INPUT = 2
EXIT_NUMERICAL = 3


def _rebuild(cls: type[RailcheckError], args: tuple, state: dict) -> RailcheckError:
    """Unpickle an error without calling its ``__init__`` (whatever its signature)."""
    error = cls.__new__(cls)
    error.args = args
    error.__dict__.update(state)
    return error


def _one_line(text: str) -> str:
    """The error's text on one line: line breaks and tabs (from a key, a file name) escaped."""
    return text.replace("\r", "\\r").replace("\n", "\\n").replace("\t", "\\t")


class RailcheckError(Exception):
    """Base of every error railcheck reports: ``field`` (the scene key or option it is
    about, "" when none), ``message``, ``exit_status`` and the ``label`` the command line
    prints before it. Pickles with every attribute (raised in a worker process or on a
    Dask worker, re-raised in the caller)."""

    exit_status = EXIT_INPUT
    label = "error"

    def __init__(self, field: str, message: str):
        self.field = field
        self.message = message
        super().__init__(_one_line(f"{field}: {message}" if field else message))

    def __reduce__(self):
        return _rebuild, (type(self), self.args, dict(self.__dict__))


class InputError(RailcheckError, ValueError):
    """A bad scene, option or mechanism: one line naming the field; exit status 2."""


class InputErrors(InputError):
    """Several bad scene values found at once (``errors``, each an :class:`InputError`
    naming its field): ``field`` and ``message`` are the first's, ``str`` gives one line
    each, and the command line prints each on its own line."""

    def __init__(self, errors: list[InputError]):
        self.errors = tuple(errors)
        super().__init__(errors[0].field, errors[0].message)
        self.args = ("\n".join(str(e) for e in self.errors),)


class NumericalError(RailcheckError, RuntimeError):
    """A numerical failure: a solve that did not converge, a singular system, a result
    that is not finite; exit status 3."""

    exit_status = EXIT_NUMERICAL
    label = "numerical failure"

    def __init__(self, message: str, field: str = ""):
        super().__init__(field, message)
