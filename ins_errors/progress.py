"""Progress for steps that can take more than about two seconds (tqdm, stderr only).

Counted work (integration steps, tasks) uses tqdm bars with a known total; a step whose
length is unknown (compiling a loop, the first parse of a hand file, a covariance
propagation) shows :func:`stage`: a one-line tqdm status with its label and the elapsed
time. Nothing is drawn when stderr is not a terminal (a pipe, a CI log, a test), so
output that is captured stays clean.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager

SHOW_AFTER = 0.5
"""Seconds before a stage's status line appears (quick stages draw nothing)."""


_HIDDEN = False
"""Set by :func:`hide` (the command line's ``--no-progress``): nothing is drawn at all."""


def hide(hidden: bool = True) -> None:
    """Draw no progress from now on (``--no-progress``): no bar and no stage, including
    those of steps that take no ``progress`` argument (compiling a loop)."""
    global _HIDDEN
    _HIDDEN = hidden


def on_terminal() -> bool:
    """Whether progress may be drawn: stderr is an interactive terminal and progress is
    not hidden (:func:`hide`)."""
    if _HIDDEN:
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # replaced or closed stream
        return False


@contextmanager
def stage(label: str, enabled: bool = True) -> Iterator[None]:
    """Show ``label`` and the elapsed time on stderr while the block runs.

    Parameters
    ----------
    label : str
        What is being done, e.g. ``"compiling the simulation loop"``.
    enabled : bool
        ``False`` draws nothing (e.g. ``--no-progress``).

    Notes
    -----
    The status appears only after :data:`SHOW_AFTER` seconds and only on a terminal; it
    is removed when the block ends. Stages do not nest: an inner stage (or a counted bar)
    inside a shown stage draws on its own line.
    """
    if not (enabled and on_terminal()):
        yield
        return
    from tqdm import tqdm

    done = threading.Event()

    def show() -> None:
        if done.wait(SHOW_AFTER):
            return
        bar = tqdm(total=None, desc=label, bar_format="{desc} … {elapsed}", leave=False,
                   file=sys.stderr)
        try:
            while not done.wait(0.5):
                bar.refresh()
        finally:
            bar.close()

    thread = threading.Thread(target=show, daemon=True)
    thread.start()
    try:
        yield
    finally:
        done.set()
        thread.join()
