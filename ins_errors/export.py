"""Error curves for other tools: CSV (one row per case and time) and MATLAB ``.mat``.

``results.json`` holds the metrics; these files hold the curves themselves, every
quantity of every run (direct, linear, refined) of every case, in SI units, so a reader
can re-plot them in a spreadsheet, MATLAB/Octave, or pandas.

CSV columns: ``case`` (1-based), ``t [s]``, then ``<quantity>.<run> [<unit>]`` for each
quantity and run. The ``.mat`` file (via :func:`scipy.io.savemat`, with a fixed header
so the same curves give the same bytes: :func:`mat_bytes`) holds ``t_s`` (the common time
axis, s), ``labels`` (the case labels), ``units`` (a struct: SI unit of each quantity) and
one struct ``case_<k>`` per case with fields ``direct``, ``linear`` and ``refined``
(omitted when not run), each a struct of row vectors by quantity.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from pathlib import Path

import numpy as np

RUNS = ("direct", "linear", "refined")
"""The runs of a case, in column order."""


def _columns(comparison) -> list[tuple[str, str, str]]:
    """(quantity, run, unit) of every curve the case has."""
    return [(m.quantity, run, m.unit) for m in comparison.metrics for run in RUNS
            if m.quantity in getattr(comparison, run)]


def curves_csv(comparisons: Sequence) -> str:
    """Every curve of every case as CSV text (SI units; the header names them).

    Parameters
    ----------
    comparisons : sequence of Comparison
        The compared cases (:class:`ins_errors.numeric.compare.Comparison`).

    Returns
    -------
    str
        CSV with a header row; ``case`` and ``t [s]`` first.
    """
    buffer = io.StringIO()
    _write_csv(comparisons, buffer)
    return buffer.getvalue()


def save_curves_csv(comparisons: Sequence, path: str | Path) -> None:
    """Write :func:`curves_csv`'s text to ``path`` (UTF-8) row by row, never holding the
    whole text: a week's curves at a 1-s record are about 0.4 GB of it."""
    with open(path, "w", encoding="utf-8", newline="") as stream:
        _write_csv(comparisons, stream)


def _write_csv(comparisons: Sequence, stream) -> None:
    writer = csv.writer(stream, lineterminator="\n")
    columns = _columns(comparisons[0]) if comparisons else []
    writer.writerow(["case", "t [s]", *(f"{q}.{run} [{unit}]" for q, run, unit in columns)])
    for k, comparison in enumerate(comparisons, 1):
        data = np.column_stack([comparison.times] + [getattr(comparison, run)[q]
                                                     for q, run, _ in columns])
        start = f"{k},"
        for first in range(0, len(data), 65536):  # Python floats in C, then their reprs
            stream.writelines(start + ",".join(map(repr, row)) + "\n"
                              for row in data[first:first + 65536].tolist())


CSV_BYTES_PER_VALUE = 22
"""About the bytes one value takes in curves.csv (17 significant digits, sign, exponent,
comma)."""
LARGE_OUTPUT = 200e6
"""Bytes of curves from which writing them is announced with their size (a week at a 1-s
record is about 0.4 GB of CSV and takes several times the simulation to write)."""


def curves_size(comparisons: Sequence) -> float:
    """About the bytes of curves.csv for ``comparisons`` (curves.mat is compressed)."""
    if not comparisons:
        return 0.0
    return float(sum(len(c.times) for c in comparisons) * _width(comparisons[0])
                 * CSV_BYTES_PER_VALUE)


def _width(comparison) -> int:
    """Columns of curves.csv: ``case``, ``t`` and every curve of a case."""
    return 2 + len(_columns(comparison))


def large_output_note(comparisons: Sequence) -> str | None:
    """``"writing about 405 MB of curves (604801 samples × 21 columns per case) ..."``
    when :func:`curves_size` reaches :data:`LARGE_OUTPUT`, else None."""
    size = curves_size(comparisons)
    if size < LARGE_OUTPUT:
        return None
    return (f"writing about {size / 1e6:.3g} MB of curves.csv ({len(comparisons[0].times)} "
            f"samples × {_width(comparisons[0])} columns per case, and curves.mat), which "
            f"takes longer than the runs; a coarser record interval writes less")


MAT_DESCRIPTION = 116
"""Bytes of a MAT-file's text header (level 5): the description, padded with spaces."""


def mat_bytes(content: dict[str, object], **options: object) -> bytes:
    """A MATLAB (level 5) ``.mat`` file's bytes, the same for the same content.

    :func:`scipy.io.savemat` writes ``Created on: <date and time>`` into the file's text
    header, so two writes of the same data differ. Here the header says ``MATLAB 5.0
    MAT-file, written by ins-errors <version>`` instead; the rest (version, byte-order
    mark, the variables, zlib-compressed when asked) is SciPy's, byte for byte.

    Parameters
    ----------
    content : dict
        Variable name -> value, as for :func:`scipy.io.savemat`.
    **options
        Passed on to :func:`scipy.io.savemat` (``do_compression``, ``oned_as``).

    Returns
    -------
    bytes
        The file, readable by :func:`scipy.io.loadmat` and MATLAB.
    """
    from scipy.io import savemat

    from ins_errors.cli import version

    buffer = io.BytesIO()
    savemat(buffer, content, **options)
    data = bytearray(buffer.getvalue())
    text = f"MATLAB 5.0 MAT-file, written by ins-errors {version()}".encode("ascii")
    data[:MAT_DESCRIPTION] = text[:MAT_DESCRIPTION].ljust(MAT_DESCRIPTION, b" ")
    return bytes(data)


def save_mat(path: str | Path, content: dict[str, object], **options: object) -> None:
    """Write :func:`mat_bytes` of ``content`` to ``path`` (as given: callers use
    :mod:`ins_errors.output` for atomicity); ``OSError`` propagates."""
    Path(path).write_bytes(mat_bytes(content, **options))


def save_curves_mat(comparisons: Sequence, path: str | Path) -> None:
    """Write every curve of every case as a MATLAB ``.mat`` file (see the module notes).

    Parameters
    ----------
    comparisons : sequence of Comparison
        The compared cases.
    path : str or Path
        Target file (written as given: callers use :mod:`ins_errors.output` for atomicity).
    """
    content: dict[str, object] = {
        "t_s": np.asarray(comparisons[0].times, float) if comparisons else np.zeros(0),
        "labels": np.array([c.label for c in comparisons], dtype=object),
        "units": {m.quantity: m.unit for m in comparisons[0].metrics} if comparisons else {},
    }
    for k, comparison in enumerate(comparisons, 1):
        content[f"case_{k}"] = {
            "t_s": np.asarray(comparison.times, float),
            **{run: {q: np.asarray(v, float) for q, v in getattr(comparison, run).items()}
               for run in RUNS if getattr(comparison, run)}}
    save_mat(path, content, do_compression=True, oned_as="row")


def write_curves(folder, comparisons: Sequence) -> list[Path]:
    """Write ``curves.csv`` and ``curves.mat`` into a report folder, atomically.

    Parameters
    ----------
    folder : ins_errors.output.OutputFolder
        The folder (its manifest records the two files; the caller calls ``finish``).
    comparisons : sequence of Comparison
        The compared cases.

    Returns
    -------
    list of Path
        The two files.

    Curves of :data:`LARGE_OUTPUT` bytes or more are announced first, with their size
    (a warning ``ins-errors: note: ...``, one line on the command line).
    """
    note = large_output_note(comparisons)
    if note:
        import warnings

        warnings.warn(f"ins-errors: note: {note}", stacklevel=2)
    return [folder.write_with("curves.csv", lambda p: save_curves_csv(comparisons, p)),
            folder.write_with("curves.mat", lambda p: save_curves_mat(comparisons, p))]
