"""The ``ins-errors`` command: thin argument parsing over the library.

Each subcommand lives in its own module under :mod:`ins_errors.commands` and exposes
``register(subparsers)``, which adds its parser and sets ``func`` (called with the parsed
arguments, returning an exit status). Errors a user can cause are printed as one line
(``ins-errors: error: ...``) with exit status 2, never as a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys
from functools import cache

COMMAND_MODULES = (
    "ins_errors.commands.models",
    "ins_errors.commands.derive",
    "ins_errors.commands.run",
    "ins_errors.commands.compare",
    "ins_errors.commands.validity",
    "ins_errors.commands.budget",
    "ins_errors.commands.sweep",
    "ins_errors.commands.check",
    "ins_errors.commands.study",
    "ins_errors.commands.propagation",
    "ins_errors.commands.cache",
)
"""Modules that each register one subcommand, in the order ``--help`` lists them."""


_NEGATIVE_QUANTITY = re.compile(r"^-\.?\d")
"""Arguments argparse must read as values, not options: ``-45deg``, ``-0.5 m/s``, ``-1e-3``."""


def version() -> str:
    """The installed version of ins-errors."""
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as installed

    try:
        return installed("ins-errors")
    except PackageNotFoundError:  # run from a source tree that is not installed
        from ins_errors import __version__

        return __version__


class _LazyVersion(argparse._VersionAction):
    """``--version``: reads the installed version only when asked (reading the package
    metadata costs a few milliseconds, which every other command would pay)."""

    def __call__(self, parser, namespace, values, option_string=None):
        self.version = f"%(prog)s {version()}"
        super().__call__(parser, namespace, values, option_string)


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line, like every other error."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def _accept_negative_quantities(parser: argparse.ArgumentParser) -> None:
    """Let ``--latitude -45deg`` through: argparse only knows bare negative numbers."""
    parser._negative_number_matcher = _NEGATIVE_QUANTITY
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                _accept_negative_quantities(sub)


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser with every registered subcommand."""
    parser = _Parser(
        prog="ins-errors",
        description="Error analysis of inertial navigation systems: derived error "
                    "equations, direct vs linear simulation, checks of hand derivations.",
    )
    parser.add_argument("--version", action=_LazyVersion)
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(subparsers)
    _accept_negative_quantities(parser)
    return parser


@cache
def _shared_parser() -> argparse.ArgumentParser:
    """The parser :func:`main` uses, built once per process.

    Building it imports and registers every command (~25 ms CPU), which scripts and
    tests calling :func:`main` many times paid at every call. Reusing it is safe:
    ``parse_args`` makes a fresh namespace each call and fills it from the parsers'
    defaults and ``set_defaults``, ``append`` options copy their default list before
    adding to it, and no command mutates the parsed values in place.
    """
    return build_parser()


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    from ins_errors.errors import InsErrorsError

    parser = _shared_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except InsErrorsError as error:
        print(f"ins-errors: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("ins-errors: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


if __name__ == "__main__":
    sys.exit(main())
