"""Exceptions raised for bad input.

Every error a user can provoke with bad input is an :class:`InsErrorsError` (or a
subclass) whose message is one line naming the problem; the CLI prints that line and
exits with status 2 instead of showing a traceback.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Mapping, Sequence


class InsErrorsError(ValueError):
    """Base class of every user-facing error of ins-errors."""


class UnknownNameError(InsErrorsError, KeyError):
    """A model, state, source, output or study name that does not exist."""

    def __str__(self) -> str:  # KeyError would add quotes around the message
        return str(self.args[0]) if self.args else ""


class DomainError(InsErrorsError):
    """A value outside the domain where the model's formulas hold (pole, NaN, R <= 0...)."""


class ModelDefinitionError(InsErrorsError):
    """A model definition (built-in or a researcher's model file) that cannot be used:
    an undefined symbol, wrong shapes, a state without an equation, a failed variation."""


class ShapeError(InsErrorsError):
    """An array argument whose shape does not match what the function expects."""


class InsErrorsNotice(RuntimeWarning):
    """A notice about the machine or the checkout, not about the results, which are the
    same as without it: no C compiler or no disk space to compile (loops run in CasADi's
    virtual machine), a cache folder that cannot be written, a damaged cache entry made
    again, a stale or damaged generated package derived again, a file system without file
    locks. Each is given once per process and not again by the workers it starts; the
    command line prints it as one line on stderr and ``--fail-on-warning`` does not count
    it. Filter them all with ``warnings.simplefilter("ignore", InsErrorsNotice)``."""


class InsErrorsWarning(UserWarning):
    """A result that holds but needs a caveat (the integration error is large, the linear
    model leaves its validity, a quantity moves only at second order, ...), issued by the
    Python API; the command line prints the same words with its results instead."""


def name_mapping(values: Mapping | None, what: str, entries: str, example: str) -> dict:
    """The values of an argument that takes a mapping of names, as a dict (None: empty).

    Parameters
    ----------
    values : mapping or None
        What the caller gave.
    what : str
        How the message names the argument, e.g. ``"process_noise: white"``.
    entries, example : str
        What the mapping holds (``"source name -> density (SI)"``) and an example of it.

    Raises
    ------
    InsErrorsError
        One line for anything but a mapping (a name alone, whose letters would be read
        as names, a list, a number).
    """
    if values is None:
        return {}
    if not isinstance(values, Mapping):
        raise InsErrorsError(f"{what} takes a mapping {entries}, e.g. {example}, got "
                             f"{type(values).__name__} {values!r:.40}")
    return dict(values)


def name_list(names: str | Iterable[str], what: str) -> list[str]:
    """The names of an argument that takes a sequence of names, as a list.

    A single string is one name (``"accel_bias"`` as ``["accel_bias"]``, never the
    letters ``a``, ``c``, ...); anything else must be an iterable of strings.

    Parameters
    ----------
    names : str or iterable of str
        What the caller gave.
    what : str
        How messages name the argument, e.g. ``"transfer_functions: sources"``.

    Raises
    ------
    InsErrorsError
        One line for something that is neither a name nor names (a number, a mapping
        of names to values, a list holding a non-string).
    """
    if isinstance(names, str):
        return [names]
    if isinstance(names, bytes | Mapping) or not isinstance(names, Iterable):
        raise InsErrorsError(f"{what} takes a name or a list of names, got "
                             f"{type(names).__name__} {names!r:.60}")
    listed = list(names)
    for name in listed:
        if not isinstance(name, str):
            raise InsErrorsError(f"{what} takes names (str), got {name!r:.60} in "
                                 f"{listed!r:.80}")
    return listed


def unknown_name(kind: str, name: str, known: Iterable[str]) -> UnknownNameError:
    """Build an :class:`UnknownNameError` that suggests the closest known names.

    Parameters
    ----------
    kind : str
        What was looked up, e.g. ``"error source"``.
    name : str
        The name the user gave.
    known : iterable of str
        The valid names.
    """
    known = list(known)
    close = close_names(name, known)
    hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
    listing = "" if close else f"; known: {', '.join(known)}"
    return UnknownNameError(f"unknown {kind} {name!r}{hint}{listing}")


def close_names(name: str, known: Sequence[str], n: int = 3,
                cutoff: float = 0.5) -> list[str]:
    """The names of ``known`` closest to ``name``, for a "did you mean" list.

    A name equal to ``name`` but for case comes first; then the closest by
    ``difflib``'s similarity (at least ``cutoff``), equally close ones in the order of
    ``known`` (the model's order: ``gyro_drift_x``, ``_y``, ``_z``), not the reverse
    alphabetical order ``difflib.get_close_matches`` gives ties.

    Parameters
    ----------
    name : str
        The name the user gave.
    known : sequence of str
        The valid names, in the order they are listed.
    n : int
        At most this many.
    cutoff : float
        Least similarity (0 to 1) of a name listed.
    """
    matcher = difflib.SequenceMatcher()
    matcher.set_seq2(name)
    scored = []
    for index, candidate in enumerate(known):
        matcher.set_seq1(candidate)
        same_but_case = candidate.lower() == name.lower()
        if same_but_case or (matcher.real_quick_ratio() >= cutoff
                             and matcher.quick_ratio() >= cutoff
                             and matcher.ratio() >= cutoff):
            scored.append((not same_but_case, -matcher.ratio(), index, candidate))
    return [candidate for *_, candidate in sorted(scored)[:n]]
