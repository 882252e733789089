"""A term left out of an entry that holds several: found term by term.

An entry of the derived F is a sum of terms: the coefficient of δφ in δv̇_D holds the
change of gravity with latitude (∂γ/∂φ) and Coriolis and transport-rate terms. A hand
model that leaves one of them out has an entry whose ratio to the model's is no clean
coefficient, so the entry-by-entry classes would call it a ``wrong coefficient``. Here
the model's entry is taken apart into its additive terms (SymPy, from the model's
structured variation: :func:`~ins_errors.symbolic.variation.structured_variation`, each
term of an error-state line through the variations it names), each term is evaluated on
the matrix check's samples, and an entry is recognised as the model's minus one term (or
minus two) when the two agree at every sample to the check's agreement level
(:data:`~ins_errors.checker.matrix.AGREEMENT` of the row's largest term). It is then an
omitted term, classed by its size as the equation checker classes a part of a coefficient
that is missing (:func:`~ins_errors.checker.classify.diagnose`: ``omitted term``, a
``dropped small term`` below the threshold).

In a convention other than the model's own, ``F_c = (T F + Ṫ) T⁺``: a term τ of the
model's own entry F[a, b] enters F_c[i, j] as ``T[i, a] τ T⁺[b, j]``, evaluated with the
same T as the derived model in the convention. Imported only when an entry is a wrong
coefficient (the matrix check otherwise does not load SymPy).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np
import sympy as sp

MAX_LEFT_OUT = 2
"""Most terms of one entry the hand may leave out together and still be recognised."""

MAX_CANDIDATES = 60
"""Terms of one entry tried (the largest first); pairs of them as well."""

CLOSED = 1e-9
"""Relative agreement (to the entry's largest value) of the sum of an entry's terms with
the numeric derived entry required before its terms are used."""


@dataclass(frozen=True)
class Term:
    """One additive term of a derived entry, on the samples.

    Attributes
    ----------
    text : str
        The term as SymPy prints it, in the model's ideal quantities.
    origin : str
        The term of the model's error-state line it comes from (``Delta_gamma``), or ''
        when that is the term itself.
    line : str
        The model's own error state whose line holds it; ``column`` its error state.
    column : str
    weight_one : bool
        It enters the convention's entry with weight 1 (the model's own states, or a
        convention that keeps both states).
    values : numpy.ndarray, shape (S,)
        Its contribution to the convention's entry at every sample, SI.
    grouped : bool
        The whole contribution of a line's term whose parts are terms as well (the
        parts, not it, add up to the entry).
    """

    text: str
    origin: str
    line: str
    column: str
    weight_one: bool
    values: np.ndarray
    grouped: bool = False

    def describe(self) -> str:
        """``2*U*v_E*sin(lat) (from -2*Delta_Omega_N*v_E in the delta_v_D line)``."""
        where = [f"from {self.origin}" if self.origin else "",
                 f"in the {self.line} line" if self.origin else f"of the {self.line} line"]
        if not self.weight_one:
            where.append(f"through F[{self.line}, {self.column}] of the model's own states")
        return f"{self.text} ({' '.join(w for w in where if w)})"


def _short(text: str, limit: int = 100) -> str:
    return text if len(text) <= limit else text[:limit - 1] + "…"


class EntryTerms:
    """The terms of the derived F in a convention, entry by entry, on the samples.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    conv : Convention
    motion_list : list of Motion
        The samples, in the order the check stacks them.
    """

    def __init__(self, model, conv, motion_list) -> None:
        from ins_errors.symbolic.variation import ideal_intermediate_values, structured_variation

        self.motion_list = motion_list
        d = model.symbolic
        lines = structured_variation(d)
        known: dict[sp.Symbol, sp.Expr] = {}
        self._lines: dict[str, sp.Expr] = {}
        for line in lines:
            rhs = line.rhs.xreplace(known)
            if line.kind == "intermediate":
                known[line.lhs] = rhs
            elif line.kind == "state":
                self._lines[line.name] = line.rhs
        self._known = known
        self._values = ideal_intermediate_values(d)
        # ideal quantities the model defines as a sum of terms (one level)
        self._sums = {df.symbol: df.expression for df in d.ideal.definitions
                      if isinstance(df.expression, sp.Add)}
        self._args = [*d.x, *d.u, *d.p]
        self._own = [v.name for v in d.error_states]
        self._xe = list(d.xe)
        self._cache: dict[tuple[int, int], list[tuple[str, str, np.ndarray, bool]]] = {}
        T, T_plus = [], []
        for motion in motion_list:
            if conv.transform is None:
                t = np.broadcast_to(np.eye(len(self._own)),
                                    (motion.times.size, len(self._own), len(self._own)))
            else:
                t, _ = conv.matrices(model, motion.x, motion.p, motion.u)
            T.append(t)
            T_plus.append(np.linalg.inv(t) if t.shape[1] == t.shape[2] else np.linalg.pinv(t))
        self._T = np.concatenate(T)
        self._T_plus = np.concatenate(T_plus)

    def _evaluate(self, expr: sp.Expr) -> np.ndarray:
        """Values of an expression in the ideal quantities at every sample, (S,)."""
        closed = expr.xreplace(self._values)
        function = sp.lambdify(self._args, closed, "numpy")
        out = []
        for motion in self.motion_list:
            k = motion.times.size
            value = function(*motion.x, *motion.u, *np.asarray(motion.p, dtype=float))
            out.append(np.broadcast_to(np.asarray(value, dtype=float), (k,)))
        return np.concatenate(out)

    def own_terms(self, a: int, b: int) -> list[tuple[str, str, np.ndarray, bool]]:
        """(text, origin, values, grouped) of the terms of the model's own F[a, b].

        Each term of the error-state line ``a`` (as the structured variation writes it,
        ``Delta_gamma``, ``-2*Delta_Omega_N*v_E``, ``delta_v_E*(-2*Omega_N - rho_N)``)
        gives its coefficient of error state ``b`` (the variations it names substituted):
        that whole is one term, and when it is a sum, each of its parts is one too; a
        part that is a multiple of an ideal quantity the model defines as a sum is taken
        apart once more (:meth:`_split`). ``grouped``: a term whose parts are terms as
        well (the parts, not it, add up to the entry).
        """
        if (a, b) in self._cache:
            return self._cache[(a, b)]
        rhs = self._lines.get(self._own[a])
        found: list[tuple[sp.Expr, str, bool]] = []  # (term, origin, grouped)
        for top in sp.Add.make_args(rhs) if rhs is not None else ():
            part = sp.diff(top.xreplace(self._known), self._xe[b])
            if part == 0:
                continue
            direct = top.xreplace({self._xe[b]: sp.S.One}) == part
            origin = "" if direct else _short(sp.sstr(top), 60)
            parts = sp.Add.make_args(part)
            if len(parts) > 1 and not direct:
                found.append((part, origin, True))
            for p in parts:
                split = self._split(p)
                found.append((p, origin, bool(split)))
                found += [(q, f"{where} = {definition}", False) for q, where, definition in split]
        terms = [(_short(sp.sstr(t)), origin, self._evaluate(t), grouped)
                 for t, origin, grouped in found]
        self._cache[(a, b)] = terms
        return terms

    def _split(self, term: sp.Expr) -> list[tuple[sp.Expr, str, str]]:
        """A term ``c × S`` with S an ideal quantity the model defines as a sum
        (``turn_rate = 2*U*sin(phi) + V_E*tan(phi)/r_E``) taken apart: (c × each part of
        S, S, S's definition); empty for any other term."""
        for symbol in sorted(term.free_symbols & self._sums.keys(), key=sp.default_sort_key):
            c = sp.diff(term, symbol)
            if c.has(symbol) or sp.expand(term - c * symbol) != 0:
                continue
            definition = self._sums[symbol]
            return [(c * q, sp.sstr(symbol), _short(sp.sstr(definition), 60))
                    for q in sp.Add.make_args(definition)]
        return []

    def terms(self, i: int, j: int) -> list[Term]:
        """The terms of the convention's F[i, j] (row i, column j of the convention's
        states): each term of each own entry F[a, b] that reaches it, times its weight
        ``T[i, a] T⁺[b, j]`` (with ``Ṫ T⁺`` these make up the entry)."""
        weights = self._T[:, i, :, None] * self._T_plus[:, None, :, j]  # (S, ne, ne)
        reach = np.argwhere(np.abs(weights).max(axis=0) > 1e-12)
        out = []
        for a, b in reach:
            own = self.own_terms(int(a), int(b))
            w = weights[:, a, b]
            one = bool(np.all(w == 1.0))
            out += [Term(text, origin, self._own[a], self._own[b], one, w * values, grouped)
                    for text, origin, values, grouped in own]
        return out


def _candidates(terms: list[Term], model: np.ndarray, tolerance: np.ndarray
                ) -> list[Term] | None:
    """The terms a slip of the entry ``model`` may be made of: those above
    ``tolerance`` somewhere, largest first, at most :data:`MAX_CANDIDATES`; None when the
    terms do not make up the entry (in a convention whose Ṫ T⁺ reaches it, or whose
    weights mix terms that cancel: no term is named there)."""
    whole = [t for t in terms if not t.grouped]
    total = sum((t.values for t in whole), np.zeros_like(model))
    if not whole or not np.all(np.abs(total - model) <= CLOSED * np.abs(model).max()):
        return None
    usable = [t for t in terms if not np.all(np.abs(t.values) <= tolerance)]
    usable.sort(key=lambda t: -float(np.abs(t.values).max()))
    return usable[:MAX_CANDIDATES]


def left_out(terms: list[Term], hand: np.ndarray, model: np.ndarray, mag: float,
             scale: np.ndarray, agreement: float) -> list[list[Term]] | None:
    """The term (or up to :data:`MAX_LEFT_OUT` terms) whose omission from ``model``
    gives ``hand`` at every sample, or None; with every other choice of as many terms
    that does so too.

    Two terms of one entry can be equal in value at every sample (the transport rate
    ρ_D in ``Ω×δv`` and ``−v_E tan φ/(R_E + h)`` from ``Δρ_D v_E``): the hand leaves
    out one of them, and the samples cannot say which.

    Parameters
    ----------
    terms : list of Term
        The terms of the entry.
    hand, model : ndarray, shape (S,)
        The two entries at the samples, SI.
    mag : float
        Typical magnitude of the state the entry multiplies.
    scale : ndarray, shape (S,)
        The row's largest term at each sample.
    agreement : float
        Relative size at or below which two entries agree.

    Returns
    -------
    list of (list of Term) or None
        Each choice of terms (the fewest) whose omission gives ``hand``, the largest
        first; one choice when the terms are told apart.
    """
    tolerance = agreement * scale / mag
    usable = _candidates(terms, model, tolerance)
    if usable is None:
        return None
    missing = model - hand
    for count in range(1, MAX_LEFT_OUT + 1):
        # a term whose parts are terms too is left out alone (with another, it could
        # count one of its own parts twice)
        found: list[list[Term]] = []
        seen: set[tuple] = set()
        for subset in combinations(usable if count == 1 else
                                   [t for t in usable if not t.grouped], count):
            total = subset[0].values if count == 1 else sum(t.values for t in subset)
            key = tuple(sorted((t.text, t.origin, t.line, t.column) for t in subset))
            if key not in seen and np.all(np.abs(missing - total) <= tolerance):
                seen.add(key)
                found.append(list(subset))
        if found:
            return found
    return None


def scaled(terms: list[Term], hand: np.ndarray, model: np.ndarray, mag: float,
           scale: np.ndarray, agreement: float) -> list[tuple[Term, float]] | None:
    """The term whose multiple by a constant c (not 0, not 1) in ``model`` gives
    ``hand`` at every sample, with c, or None; with every other term that does so too
    (equal in value at every sample).

    A factor slip in one term of an entry that holds others (Coriolis' 2Ω sin φ written
    Ω sin φ beside the transport rate v_E tan φ/R) is no constant ratio of the whole
    entry on a moving base, and only at rest, where the term is the whole entry, is the
    ratio the factor: here ``hand − model = (c − 1) τ`` for one term τ at every sample
    (the parameters as :func:`left_out`; c fitted by least squares, the residual within
    the agreement level of the row's largest term).
    """
    tolerance = agreement * scale / mag
    usable = _candidates(terms, model, tolerance)
    if usable is None:
        return None
    difference = hand - model
    found: list[tuple[Term, float]] = []
    seen: set[tuple] = set()
    for t in usable:
        k = float(np.dot(difference, t.values) / np.dot(t.values, t.values))
        c = 1.0 + k
        key = (t.text, t.origin, t.line, t.column)
        if (key in seen or abs(c) <= 1e-6 or abs(k) <= 1e-6
                or not np.all(np.abs(difference - k * t.values) <= tolerance)):
            continue
        seen.add(key)
        found.append((t, c))
    return found or None


__all__ = ["EntryTerms", "Term", "left_out", "scaled"]
