"""The ``railcheck`` command line.

One module per subcommand (``add_args(parser)`` and
``run(args) -> exit status``), registered in :data:`COMMANDS`.

Exit statuses: 0 pass, 1 a check failed, 2 bad input or impossible mechanism (one line on
stderr naming the field, no traceback), 3 numerical failure; 130 interrupted, 143
terminated.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
from importlib.metadata import PackageNotFoundError, version

from railcheck.base.errors import EXIT_INPUT, EXIT_PASS, InputError, RailcheckError
from railcheck.cli import bench, cache, check, convergence, init, kinematics, lookup, mechanism, sweep
from railcheck.environment import store_cap_bytes
from railcheck.files import writable_dir, writable_file

DESCRIPTION = (
    "Design check for reconfigurable planar linkages built from linear-guide rails: kinematics, "
    "joint reactions, bolt loads, FE stress, deflection and fatigue verdict."
)

#: subcommand name -> its module, in the order ``railcheck --help`` lists them
COMMANDS = {
    "init": init,
    "kinematics": kinematics,
    "check": check,
    "sweep": sweep,
    "lookup": lookup,
    "bench": bench,
    "convergence": convergence,
    "mechanism": mechanism,
    "cache": cache,
}

#: attribute -> (option, a directory?, the file name's required suffix or None)
OUTPUT_OPTIONS = {
    "plots": ("--plots", True, None),
    "csv": ("--csv", False, None),
    "html": ("--html", False, None),
    "gif": ("--gif", False, ".gif"),  # the writer picks GIF by the name
    "plot": ("--plot", False, None),  # written as PNG whatever its name
}


class _Parser(argparse.ArgumentParser):
    """argparse that exits 2 with one line (its default already uses 2)."""

    def error(self, message: str):  # noqa: D401
        self.exit(EXIT_INPUT, f"railcheck: error: {message}\n")


def _version() -> str:
    try:
        return version("railcheck")
    except PackageNotFoundError:
        return "unknown"


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="railcheck", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"railcheck {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, command in COMMANDS.items():
        options = {"description": command.HELP[0].upper() + command.HELP[1:] + ".", **getattr(command, "PARSER", {})}
        p = sub.add_parser(name, help=command.HELP, **options)
        command.add_args(p)
        p.set_defaults(func=command.run)
    return parser


def _check_output_options(args) -> None:
    """Every output path the command line names, and the store's size cap
    (``RAILCHECK_STORE_MB``), is checked before any work starts."""
    store_cap_bytes()
    for attr, (option, is_dir, suffix) in OUTPUT_OPTIONS.items():
        value = getattr(args, attr, None)
        if value is not None and not str(value).strip():
            raise InputError(option, "an empty name: give a file or folder, or leave the option out")
        if value:
            if is_dir:
                writable_dir(value, option)
            else:
                writable_file(value, option, suffix)


def _terminate(signum, frame):
    """SIGTERM unwinds like Ctrl-C, so staging directories are removed on the way out."""
    raise _Terminated()


class _Terminated(KeyboardInterrupt):
    pass


def main(argv: list[str] | None = None) -> int:
    """Run one command; every error becomes one line on stderr and an exit status."""
    for stream in (sys.stdout, sys.stderr):  # a console that cannot print a character gets an escape
        if hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="backslashreplace")
    parser = build_parser()
    if not (sys.argv[1:] if argv is None else argv):
        parser.print_help()
        return EXIT_INPUT
    args = parser.parse_args(argv)
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        _check_output_options(args)
        return int(args.func(args))
    except (RailcheckError, OSError, KeyboardInterrupt) as exc:
        return report_error(exc)
    finally:
        signal.signal(signal.SIGTERM, previous)


def report_error(exc: BaseException) -> int:
    """One line on stderr for an error that ends a run, and its exit status."""
    if isinstance(exc, BrokenPipeError):  # `railcheck ... | head`: end quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_PASS
    if isinstance(exc, RailcheckError):
        for one in getattr(exc, "errors", (exc,)):  # several scene errors: one line each
            print(f"railcheck: {exc.label}: {one}", file=sys.stderr)
        return exc.exit_status
    if isinstance(exc, OSError):  # a full disk, a vanished directory: nothing half-written
        print(f"railcheck: error: cannot write {exc.filename or 'the results'}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_INPUT
    terminated = isinstance(exc, _Terminated)
    print(f"railcheck: {'terminated' if terminated else 'interrupted'}", file=sys.stderr)
    return 143 if terminated else 130


if __name__ == "__main__":
    sys.exit(main())
