"""The ``ins-errors`` command: thin argument parsing over the library.

Each subcommand lives in its own module under :mod:`ins_errors.commands` and exposes
``register(subparsers)``, which adds its parser and sets ``func`` (called with the parsed
arguments, returning an exit status). Errors a user can cause are printed as one line
(``ins-errors: error: ...``) with exit status 2, never as a traceback.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import re
import sys
import warnings
from functools import cache

COMMAND_MODULES = (
    "ins_errors.commands.models",
    "ins_errors.commands.derive",
    "ins_errors.commands.run",
    "ins_errors.commands.compare",
    "ins_errors.commands.validity",
    "ins_errors.commands.modes",
    "ins_errors.commands.transfer",
    "ins_errors.commands.budget",
    "ins_errors.commands.sweep",
    "ins_errors.commands.check",
    "ins_errors.commands.matrices",
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
    """An argument parser whose usage errors are one line, like every other error, with
    the same prefix: ``ins-errors: error: compare: argument --motion: ...`` (the
    subcommand after it, as a file is named after it in the other errors), so that one
    pattern finds every error line."""

    def error(self, message: str):  # type: ignore[override]
        top, _, command = self.prog.partition(" ")
        where = f"{command}: " if command else ""
        self.exit(2, f"{top}: error: {where}{message} (see '{self.prog} --help')\n")

    def parse_args(self, args=None, namespace=None):  # type: ignore[override]
        """As argparse's, but arguments no option takes are reported by the subcommand
        they were given to (its --help lists its options, the top level's does not), with
        a hint where one is a unit split from its value (``--source x=0.01 deg/h``)."""
        parsed, extra = self.parse_known_args(args, namespace)
        if extra:
            command = getattr(parsed, "command", None)
            sub = _subparser(self, command) if command else None
            hint = ""
            if any(_is_unit(word) for word in extra):
                hint = ("; a value and its unit go together: write 0.01deg/h, or quote "
                        "'0.01 deg/h'")
            (sub or self).error(f"unrecognized arguments: {' '.join(extra)}{hint}")
        return parsed


def _subparser(parser: argparse.ArgumentParser, name: str) -> argparse.ArgumentParser | None:
    """The subcommand parser ``name`` of ``parser``, or None."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices.get(name)
    return None


def _is_unit(word: str) -> bool:
    """True for a word that is a unit alone (``deg/h``, ``ug``, ``m/s``), not an option nor
    a number (``1``: pint reads it as a dimensionless unit)."""
    if word.startswith("-") or "=" in word or not any(c.isalpha() or c == "°" for c in word):
        return False
    from ins_errors.units import registry

    try:
        registry().parse_units(word.replace("°", "deg"))
    except Exception:  # pint raises several types for text that is no unit
        return False
    return True


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


EXIT_BROKEN_PIPE = 128 + 13
"""Exit status when the reader of standard output went away (``| head``): 128 + SIGPIPE,
what a POSIX tool killed by SIGPIPE reports, so ``set -o pipefail`` never reads it as 1
(a mistake found)."""


class StdoutError(Exception):
    """Standard output could not be written (a full disk, a closed file, ...)."""


class _GuardedStdout:
    """``sys.stdout`` while a command runs: a failed write says so in one line.

    Writes and flushes that fail with anything but a broken pipe raise
    :class:`StdoutError`; everything else is the wrapped stream's.
    """

    def __init__(self, stream):
        self._stream = stream

    def __getattr__(self, name):
        return getattr(self._stream, name)

    def _guard(self, call, *args):
        try:
            return call(*args)
        except BrokenPipeError:
            raise
        except OSError as error:
            raise StdoutError(error.strerror or str(error)) from None

    def write(self, text):
        return self._guard(self._stream.write, text)

    def writelines(self, lines):
        return self._guard(self._stream.writelines, lines)

    def flush(self):
        return self._guard(self._stream.flush)


def _one_line_notices(show):
    """``warnings.showwarning`` for a command: ins-errors's own notices (messages that
    start with ``ins-errors:``) as their one line on stderr, without the source path and
    code line of Python's warning format; other warnings as ``show`` prints them."""

    def showwarning(message, category, filename, lineno, file=None, line=None):
        text = str(message)
        if not text.startswith("ins-errors:"):
            return show(message, category, filename, lineno, file, line)
        with contextlib.suppress(OSError, ValueError):  # no stderr to say it on
            print(" ".join(text.split()), file=sys.stderr if file is None else file)

    return showwarning


def _silence_stdout() -> None:
    """Point the stdout file descriptor at ``/dev/null`` so that the interpreter's final
    flush of what is still buffered neither fails nor prints."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)
    except (OSError, ValueError, AttributeError):  # no real file behind sys.stdout
        pass


@contextlib.contextmanager
def _writable_streams():
    """Standard output and error as a command can write them, whatever it was started
    with; put back as they were afterwards.

    A stream closed when Python started (``>&-``, ``2>&-``: ``sys.stdout`` is None) is
    a sink that writes nothing: the command runs, writes its files and gives its status
    (``print`` wrote to None and failed with an AttributeError traceback; an error line
    went to standard output when standard error was closed). On a standard output whose
    encoding lacks characters the command writes (``PYTHONIOENCODING=ascii``, a
    Windows console's code page), each such character is written as its Python escape
    (``φ`` as ``\u03c6``), as Python writes standard error, instead of a
    UnicodeEncodeError traceback.
    """
    import codecs

    sinks = {}
    for name in ("stdout", "stderr"):
        if getattr(sys, name) is None:
            sinks[name] = open(os.devnull, "w", encoding="utf-8")  # noqa: SIM115
            setattr(sys, name, sinks[name])
    stream, strict = sys.stdout, None
    try:
        utf = codecs.lookup(stream.encoding).name.startswith("utf")
    except (AttributeError, LookupError, TypeError):
        utf = True  # not a text file of the system (a notebook's, a test's): left alone
    if not utf and getattr(stream, "errors", None) == "strict" and hasattr(
            stream, "reconfigure"):
        with contextlib.suppress(Exception):
            stream.reconfigure(errors="backslashreplace")
            strict = "strict"
    try:
        yield
    finally:
        if strict is not None:
            with contextlib.suppress(Exception):
                stream.reconfigure(errors=strict)
        for name, sink in sinks.items():
            if getattr(sys, name) is sink:
                setattr(sys, name, None)
            sink.close()


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    Returns
    -------
    int
        0 done (a check found no mistake), 1 a finding (a check found at least one
        mistake, a budget's spec exceeded, a warning under ``--fail-on-warning``), 2 bad
        input or an output that cannot be written (one line on stderr), 3 a sweep or
        validity map that finished with points failed on their own input, 130 interrupted
        (143 when SIGTERM stopped it, after the clean-up Ctrl-C gets),
        141 (128 + SIGPIPE) the reader of standard output stopped reading, as a POSIX
        tool killed by SIGPIPE reports.
    """
    # first of all (the package's import is light): SIGTERM from the start of the
    # command gets Ctrl-C's clean-up and its one line, also while the parser is built
    from ins_errors.analysis.engine import terminate_interrupts

    with _writable_streams():
        before = None
        try:
            with terminate_interrupts(lasting=True):
                from ins_errors.output import unfinished

                before = unfinished()  # runs of the Python API before this command
                return _command(argv, before)
        except KeyboardInterrupt as error:  # Ctrl-C, or SIGTERM (engine.Terminated)
            status = _stopped(error)
            if before is not None:  # (a stop in _command's own clean-up)
                from ins_errors.output import take_back_unfinished

                take_back_unfinished(besides=before)
            return status


def _stopped(error: KeyboardInterrupt) -> int:
    """Say that the command was stopped (one line on stderr) and give its exit status,
    128 + the signal's number.

    The error's ``detail`` (what a sweep's store keeps) follows a colon; its ``when``
    (``"before any point was stored"``) follows the signal. Asyncio's notes on the
    tasks the stop abandoned (Zarr's writes on its own thread: ``Task was destroyed but
    it is pending!``) are silenced: the line says what happened."""
    import logging

    logging.getLogger("asyncio").setLevel(logging.CRITICAL + 1)
    signum = getattr(error, "signum", 2)
    detail = getattr(error, "detail", "")  # e.g. what a sweep's store keeps
    when = getattr(error, "when", "")
    print(("ins-errors: interrupted" if signum == 2 else
           f"ins-errors: terminated (signal {signum})")
          + (f" {when}" if when else "") + (f": {detail}" if detail else ""),
          file=sys.stderr)
    return 128 + signum


def _command(argv: list[str] | None, before: frozenset = frozenset()) -> int:
    """:func:`main` once SIGTERM is handled; a command that fails (an exception, Ctrl-C)
    takes back the folders it did not finish (not those in ``before``, unfinished runs
    of the Python API in this process before the command)."""
    from ins_errors.errors import InsErrorsError
    from ins_errors.output import os_error_line, take_back_unfinished

    parser = _shared_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        usage = " ".join(parser.format_usage().split()).removeprefix("usage: ")
        print(f"{parser.prog}: error: give a command, e.g. '{parser.prog} models' (usage: "
              f"{usage}; see '{parser.prog} --help')", file=sys.stderr)
        return 2
    from ins_errors.numeric.cache import check_settings

    real_stdout = sys.stdout
    sys.stdout = _GuardedStdout(real_stdout)
    shown_warning = warnings.showwarning
    warnings.showwarning = _one_line_notices(shown_warning)
    failed = True  # until the command has returned: its unfinished folders are taken back
    try:
        # before any work, whatever the cache holds: the cache's variables (a relative
        # $INS_ERRORS_CACHE is taken against the folder the command starts in)
        check_settings()
        if getattr(args, "no_progress", False):
            from ins_errors.progress import hide

            hide()   # also the stages of steps no command option reaches (compiling)
        from ins_errors.output import command_takes_back

        with command_takes_back():
            status = int(args.func(args) or 0)
        failed = False
        sys.stdout.flush()
        return status
    except InsErrorsError as error:
        print(f"ins-errors: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as error:  # Ctrl-C, or SIGTERM (engine.Terminated)
        return _stopped(error)
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        _silence_stdout()
        return EXIT_BROKEN_PIPE
    except StdoutError as error:
        _silence_stdout()
        print(f"ins-errors: error: cannot write to standard output: {error}",
              file=sys.stderr)
        return 2
    except OSError as error:  # a file or folder the system refused (named by the error)
        print(f"ins-errors: error: {os_error_line(error)}", file=sys.stderr)
        return 2
    except MemoryError as error:  # numpy's "Unable to allocate 43 GiB for an array ..."
        said = " ".join(str(error).split())
        print(f"ins-errors: error: out of memory{': ' + said if said else ''} (ask for "
              "less: a longer step, a shorter duration, fewer motions or points)",
              file=sys.stderr)
        return 2
    finally:
        if failed:  # after the line saying why: each folder it was writing, as it was
            take_back_unfinished(besides=before)
        if getattr(args, "no_progress", False):
            from ins_errors.progress import hide

            hide(False)   # main() called again in one process (a notebook, the tests)
        warnings.showwarning = shown_warning
        if sys.stdout is not real_stdout and isinstance(sys.stdout, _GuardedStdout):
            sys.stdout = real_stdout


if __name__ == "__main__":
    sys.exit(main())
