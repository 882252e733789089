"""``--fail-on-warning`` of ``compare`` and ``run``: exit status 1 when the run warned.

Without the option a run that warns exits 0 like any other, its warnings printed (and in
the JSON's ``warnings``). With it, once every output is written as usual, the exit
status is 1 if the run gave a warning about its results, so that CI needs no JSON
parsing: every case's warnings (:attr:`ins_errors.numeric.compare.Comparison.warnings`)
and the warnings shown on stderr while it ran (:func:`watched_warnings`), except notes
(:data:`NOTE`: how an input was read) and notices about the machine
(:class:`~ins_errors.errors.InsErrorsNotice`), which leave the results as they are.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import warnings
from collections.abc import Iterator, Sequence

WARNINGS_COUNTED = (
    "validity, integration error, a refined run that diverges, an error moved only at "
    "second order or a source the linear model does not see, a growing mode, a noisy "
    "motion file, an interpolated true motion that may be off")
"""What ``--fail-on-warning`` counts, in words (its help and the docs say the same)."""

HELP = ("exit with status 1, after writing every output as usual, when the run warned "
        f"about its results ({WARNINGS_COUNTED}: every line of the JSON's warnings, and "
        "those on stderr); notes ('ins-errors: note: ...') and notices about the machine "
        "(no C compiler, a cache folder that cannot be written, a damaged cache entry, a "
        "stale generated package) do not count")

NOTE = "ins-errors: note:"
"""How a note on stderr begins (how an input was read): not counted."""

def counted(text: str, category: type[Warning]) -> bool:
    """Whether a warning shown on stderr counts for ``--fail-on-warning``: one of
    ins-errors's own (``ins-errors: ...``), neither a note nor a notice about the machine
    (:class:`~ins_errors.errors.InsErrorsNotice`)."""
    from ins_errors.errors import InsErrorsNotice

    return (text.startswith("ins-errors:") and not text.startswith(NOTE)
            and not issubclass(category, InsErrorsNotice))


def add_option(parser: argparse.ArgumentParser) -> None:
    """Add ``--fail-on-warning`` to a command's parser."""
    parser.add_argument("--fail-on-warning", action="store_true", help=HELP)


@contextlib.contextmanager
def watched_warnings() -> Iterator[list[str]]:
    """Note the counted warnings shown while the block runs (as the command shows them:
    the display is unchanged); yields the list they are added to, one text each."""
    shown: list[str] = []
    show = warnings.showwarning

    def noting(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())
        if counted(text, category):
            shown.append(text)
        return show(message, category, filename, lineno, file, line)

    warnings.showwarning = noting
    try:
        yield shown
    finally:
        if warnings.showwarning is noting:
            warnings.showwarning = show


def exit_status(args: argparse.Namespace, comparisons: Sequence | None,
                shown: Sequence[str]) -> int:
    """0, or 1 with ``--fail-on-warning`` when the cases of ``comparisons`` or the
    warnings ``shown`` hold a warning (said in one line on stderr).

    Parameters
    ----------
    args : argparse.Namespace
        The command's options (``fail_on_warning``).
    comparisons : sequence of Comparison, or None
        The cases run (None: nothing was run, e.g. ``run --schema``).
    shown : sequence of str
        The counted warnings shown on stderr (:func:`watched_warnings`).
    """
    count = sum(len(c.warnings) for c in comparisons or ()) + len(shown)
    if not getattr(args, "fail_on_warning", False) or count == 0:
        return 0
    print(f"ins-errors: exit status 1 (--fail-on-warning): the run gave {count} "
          f"warning{'s' if count > 1 else ''}", file=sys.stderr)
    return 1
