"""File and folder paths as a user writes them: ``~`` means the home folder everywhere.

A shell expands ``~/m/eq.txt`` only where it stands alone, unquoted: ``"~/m/eq.txt"``,
``--matrix=~/m/psi.py:psi`` and ``file = "~/runs/motion.csv"`` in a scenario reach the
program with the ``~`` still in them. Every path a command takes from its user (the
arguments of the command line, the model and motion files a scenario names) goes through
:func:`expand_user` once, where it is read, so all of them mean the same by ``~``.
"""

from __future__ import annotations

import os
from pathlib import Path


def expand_user(text: str | os.PathLike[str]) -> str:
    """``text`` with a leading ``~`` (the home folder, ``$HOME``) or ``~name`` (that
    user's home folder) replaced, as a shell does; anything else unchanged.

    Parameters
    ----------
    text : str or path-like
        A path as given (``~/m/eq.txt``, ``~/m/psi.py:psi_model``, ``./out``). Only its
        start is looked at: a ``FILE.py:FUNCTION`` keeps its function, ``./x`` its dot.

    Returns
    -------
    str
        The path with its home folder written out; ``text`` itself (as text) when it does
        not start with ``~`` or the user is unknown.
    """
    return os.path.expanduser(os.fspath(text))


def user_path(text: str | os.PathLike[str]) -> Path:
    """:func:`expand_user` of ``text`` as a :class:`~pathlib.Path` (an ``argparse``
    ``type`` of the options whose value is used as a path).

    Parameters
    ----------
    text : str or path-like
        A path as given.

    Returns
    -------
    pathlib.Path
    """
    return Path(expand_user(text))
