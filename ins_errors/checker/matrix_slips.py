"""Index slips in one row of a hand F (or G): a term written on the wrong column.

A hand linearisation that swaps two indices (``f_D*phi_N`` where the cross product
f^n × φ has ``f_D*phi_E``) differs from the derived model in two entries of the row: one
has a term too many, the other lacks it. Entry by entry these read as an extra term and
an omitted one (or two wrong coefficients); together they are one slip. Two patterns are
recognised, both exact to the agreement level of the row at every sample of every
motion, among the differing entries of one row, one matrix and one unit:

* **permuted entries**: the hand's entries of some columns are the derived entries of
  the same columns in another order (``hand[j] = model[π(j)]`` with π moving every one
  of them): a swap of two indices, or three indices rotated;
* **a moved term**: two entries whose differences cancel (``hand[j] − model[j] =
  model[k] − hand[k]``, the pair unique): a term of column k, perhaps part of a sum,
  written on column j.

Neither can arise from a dropped or approximated term, whose differences are not
exactly those of another entry of the row; a sign slip keeps its own kind.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations, permutations

import numpy as np

from ins_errors.checker.kinds import COEFFICIENT, EXTRA, OMITTED

ELIGIBLE = frozenset({OMITTED, EXTRA, COEFFICIENT, "approximated"})
"""Kinds of a differing entry that may be part of an index slip (``approximated`` is
:data:`~ins_errors.checker.matrix.APPROXIMATED`)."""
LARGEST = 6
"""At most this many differing entries of one unit are searched for a permutation."""


@dataclass(frozen=True, eq=False)
class Entry:
    """One differing entry of a row, sampled.

    Attributes
    ----------
    key : object
        The caller's handle of the finding.
    matrix : {"F", "G"}
    column : str
    unit : str
        Unit of the column's state or source (only entries of one unit are compared).
    kind : str
    hand, model : ndarray, shape (S,)
        The entry at the samples, SI.
    mag : float
        Typical size of the column's state or source.
    """

    key: object
    matrix: str
    column: str
    unit: str
    kind: str
    hand: np.ndarray
    model: np.ndarray
    mag: float


def index_slips(entries: list[Entry], scale: np.ndarray, agreement: float, row: str
                ) -> dict[object, str]:
    """The entries of one row that are index slips, with the detail of each.

    Parameters
    ----------
    entries : list of Entry
        The row's differing entries (findings).
    scale : ndarray, shape (S,)
        The row's largest term at each sample (what an agreement is measured against).
    agreement : float
        Relative size at or below which two values agree.
    row : str
        The row's name, for the details.

    Returns
    -------
    dict
        ``Entry.key`` -> detail, for every entry that is part of a slip (the caller
        gives it the kind :data:`~ins_errors.checker.kinds.SYMBOL`).
    """
    out: dict[object, str] = {}
    groups: dict[tuple[str, str], list[Entry]] = {}
    for e in entries:
        if e.kind in ELIGIBLE:
            groups.setdefault((e.matrix, e.unit), []).append(e)
    for group in groups.values():
        if len(group) < 2:
            continue

        def same(x: np.ndarray, y: np.ndarray, mag: float) -> bool:
            return bool(np.all(np.abs(x - y) * mag <= agreement * scale))

        def name(e: Entry) -> str:
            return f"{e.matrix}[{row}, {e.column}]"

        permuted = _permutation(group, same)
        members = ", ".join(e.column for e in group if e in permuted)
        for e, source in permuted.items():
            out[e.key] = (f"index slip: the hand's entry is the derived {name(source)}; "
                          f"the entries of {members} are the derived ones permuted")
        rest = [e for e in group if e not in permuted]
        pairs = [(a, b) for a, b in combinations(rest, 2)
                 if same(a.hand - a.model, b.model - b.hand, a.mag)]
        for a, b in pairs:
            if sum(a in p for p in pairs) != 1 or sum(b in p for p in pairs) != 1:
                continue  # not unique: no verdict
            for here, there in ((a, b), (b, a)):
                out[here.key] = (f"index slip with {name(there)}: hand − model here is "
                                 "model − hand there (a term written on the wrong one of "
                                 "the two columns)")
    return out


def _permutation(group: list[Entry], same) -> dict[Entry, Entry]:
    """The largest set of entries whose hand values are the derived values of the set in
    another order, every one moved: entry -> the entry whose derived value it holds."""
    if len(group) > LARGEST:
        return {}
    holds = {(a.key, b.key): a is not b and same(a.hand, b.model, a.mag)
             for a in group for b in group}
    for size in range(len(group), 1, -1):
        for subset in combinations(group, size):
            for order in permutations(subset):
                if all(holds[(a.key, b.key)] for a, b in zip(subset, order, strict=True)):
                    return dict(zip(subset, order, strict=True))
    return {}


TRIPLES = (("N", "E", "D"), ("x", "y", "z"), ("E", "N", "U"))
"""Suffixes of a vector's components, in order (``phi_N/E/D``, ``gyro_bias_x/y/z``)."""
TRANSPOSED = ("is the derived one transposed at every sample: C_n^b written where C_b^n "
              "belongs?")
"""The end of the detail of a transposed block (:func:`transposed_blocks`)."""


def triples(names: list[str]) -> list[tuple[str, str, str]]:
    """The vector triples among ``names``: three names with one stem and the suffixes of
    one of :data:`TRIPLES`, in that order (``("phi_N", "phi_E", "phi_D")``)."""
    out = []
    for suffixes in TRIPLES:
        stems = [n[:-len(suffixes[0])] for n in names
                 if n.endswith("_" + suffixes[0])]
        for stem in stems:
            triple = tuple(stem + s for s in suffixes)
            if all(t in names for t in triple) and triple not in out:
                out.append(triple)
    return out


def transposed_block(hand: np.ndarray, model: np.ndarray, mags: np.ndarray,
                     scales: np.ndarray, agreement: float) -> bool:
    """Whether a 3×3 block of the hand is the derived block transposed, and not the
    derived block itself.

    Parameters
    ----------
    hand, model : ndarray, shape (S, 3, 3)
        The block at the samples, SI (rows: one vector triple; columns: another).
    mags : ndarray, shape (3,)
        Typical size of the columns' states or sources.
    scales : ndarray, shape (S, 3)
        Each row's largest term at each sample (what an agreement is measured against).
    agreement : float
        Relative size at or below which two values agree.

    Returns
    -------
    bool
        True when hand = modelᵀ to the agreement level of each row at every sample while
        hand ≠ model somewhere (a block equal to its transpose, such as the identity at
        zero attitude, is no transposition), and from −model somewhere (a skew-symmetric
        block such as [f^n×] written with the wrong sign is its own transpose: a sign
        slip).
    """
    def close(x: np.ndarray) -> np.ndarray:
        return np.abs(x) * mags[None, None, :] <= agreement * scales[:, :, None]

    flipped = np.swapaxes(model, 1, 2)
    return bool(np.all(close(hand - flipped)) and not np.all(close(hand - model))
                and not np.all(close(hand + model)))
