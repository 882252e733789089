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
import sys

COMMAND_MODULES = (
    "ins_errors.commands.models",
    "ins_errors.commands.run",
    "ins_errors.commands.compare",
    "ins_errors.commands.budget",
    "ins_errors.commands.check",
    "ins_errors.commands.study",
    "ins_errors.commands.propagation",
)
"""Modules that each register one subcommand, in the order ``--help`` lists them."""


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser with every registered subcommand."""
    parser = argparse.ArgumentParser(
        prog="ins-errors",
        description="Error analysis of inertial navigation systems: derived error "
                    "equations, direct vs linear simulation, checks of hand derivations.",
    )
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    from ins_errors.errors import InsErrorsError

    parser = build_parser()
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
