"""User text (case labels, titles, file names, motion descriptions) in Markdown documents.

A ``|`` in a table cell ends the cell: a case labelled ``gyro x | 0.01 deg/h`` would
split its row and shift every later value one column right. A line break ends the row
(in a heading, the heading). Every writer of a Markdown table puts user text through
:func:`table_cell`, and a heading's text through :func:`one_line`; the text reads the
same once rendered (``\\|`` shows as ``|``, by Python-Markdown as by GitHub's
renderer).

HTML in user text is not escaped here: ``report.md`` keeps the text as written, and
:func:`ins_errors.report.markdown_to_html` shows any HTML of the document as text.
"""

from __future__ import annotations

import re

_PIPE = re.compile(r"(\\*)\|")
_BREAK = re.compile(r"\s*[\r\n]+\s*")


def one_line(text: str) -> str:
    """``text`` on one line: each line break (with the blanks around it) becomes one
    space, so the text cannot end a heading or a table row early."""
    return _BREAK.sub(" ", str(text))


def table_cell(text: str) -> str:
    """``text`` for a cell of a Markdown table: on one line (:func:`one_line`), each
    ``|`` escaped as ``\\|`` (backslashes right before it doubled, so that they stay
    text and the pipe stays escaped).

    Examples
    --------
    >>> table_cell("gyro x | 0.01 deg/h")
    'gyro x \\\\| 0.01 deg/h'
    """
    return _PIPE.sub(lambda m: 2 * m.group(1) + "\\|", one_line(text))

