r"""Hand-written error equations in a researcher's convention (``@convention NAME``).

A hand file of ``strapdown_ned`` (or any model with conventions, see
:mod:`~ins_errors.checker.conventions`) may declare ``@convention phi`` (or ``psi``,
``phi_modified``, ... ``--list-conventions``). Its left-hand sides are then the time
derivatives of that convention's states (``dot(phi_N)``), and its right-hand sides are
linear in those states and the model's error sources, with coefficients written in named
quantities of the reference motion (:data:`QUANTITIES`: ``omega_ie_N``, ``f_E``, ``C12``,
...). ``φ̇ = −ω_in × φ + δω_in − C_b^n δω_ib`` is written as three component lines or as
one vector line ``dot(phi) = -cross(omega_in, phi) + vec(...) - C_bn*gyro_bias``
(:func:`split_vector_lines`; ``omega_in × phi`` is read as ``cross(omega_in, phi)``).

Lines ``NAME = expression`` before the rows define intermediate quantities (``rho_N =
v_E/(R_E + h)``, ``dlat = dr_N/(R_N + h)``), substituted into the rows in file order; a
finding names the definitions its entry comes through
(:mod:`~ins_errors.checker.convention_definitions`).

Each equation's coefficients are evaluated along the matrix checker's motions and placed
in that row of F and G; rows the file does not give are taken from the derived model. The
comparison is then exactly :func:`~ins_errors.checker.matrix.check_matrices` against the
derived model carried into the convention (``F_c = (T F + Ṫ) T⁺``, ``G_c = T G``), and each
finding is traced back to the line of its row.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
import sympy as sp

from ins_errors.checker import convention_definitions as cd
from ins_errors.checker import convention_height as ch
from ins_errors.checker import convention_names as cn
from ins_errors.checker.navigation import PARAMETERS
from ins_errors.errors import InsErrorsError, close_names

QUANTITIES: dict[str, str] = {
    "lat": "geodetic latitude φ, rad",
    "h": "height above the ellipsoid, m",
    "v_N": "north velocity, m/s", "v_E": "east velocity, m/s", "v_D": "down velocity, m/s",
    "R_N": "meridian radius of curvature (h not included), m",
    "R_E": "prime-vertical radius of curvature (h not included), m",
    "R_M": "meridian radius of curvature (h not included), m: the same as R_N",
    "a": "semi-major axis, m", "e2": "first eccentricity squared",
    "U": "Earth rotation rate, rad/s", "g": "magnitude of gravity, m/s²",
    **{f"omega_ie_{k}": f"Earth rate in NED, {k} component (U cos φ, 0, −U sin φ), rad/s"
       for k in "NED"},
    **{f"omega_en_{k}": f"transport rate in NED, {k} component, rad/s" for k in "NED"},
    **{f"omega_in_{k}": f"ω_ie + ω_en, {k} component, rad/s" for k in "NED"},
    **{f"f_{k}": f"specific force in NED (f^n = C_b^n f^b), {k} component, m/s²"
       for k in "NED"},
    **{f"f_{k}": f"specific force in the body frame (accelerometer output), {k}, m/s²"
       for k in "xyz"},
    **{f"omega_ib_{k}": f"body rate (gyro output), {k}, rad/s" for k in "xyz"},
    **{f"C{i + 1}{j + 1}": f"C_b^n (body → NED) row {i + 1}, column {j + 1}"
       for i in range(3) for j in range(3)},
}
"""Named quantities of the reference motion a right-hand side may use, with meanings.
A model's parameters are named quantities too (:func:`quantity_names`)."""

RADII = ("R_N", "R_E", "R_M")
"""The radii of curvature: a file's definition of one replaces it, and a file that uses
``R_M`` and ``R_N`` reads ``R_N`` as the prime-vertical radius (:func:`radius_reading`)."""

UP_QUANTITIES = ("v", "f", "omega_ie", "omega_en", "omega_in")
"""Named quantities whose down component ``X_D`` has an up component ``X_U = -X_D``."""


def quantity_names(model) -> list[str]:
    """The named quantities of ``model``'s ``@convention`` files, in the order of the
    coefficient functions' arguments: :data:`QUANTITIES`, then the model's parameters
    that are not among them (``k_h1``, ``gamma_e`` of ``strapdown_ned``)."""
    return [*QUANTITIES, *(p.name for p in model.parameters if p.name not in QUANTITIES)]


def up_components(states: list[str]) -> dict[str, tuple[str, str]]:
    """The up components an east-north-up file writes: name -> (down name, what it is).

    ``phi_U`` is ``-phi_D`` for every state triple of the convention (``phi``, ``psi``,
    ``dv``, ``dr``, ...), and ``v_U``, ``f_U``, ``omega_ie_U``, ... are ``-v_D``, ... of
    the named quantities; east and north components keep their names. ``dh`` of a
    ``_geodetic`` convention is already up.
    """
    out: dict[str, tuple[str, str]] = {}
    for name in states:
        prefix, _, axis = name.rpartition("_")
        if prefix and axis == "D" and f"{prefix}_N" in states and f"{prefix}_E" in states:
            out[f"{prefix}_U"] = (name, "state")
    for prefix in UP_QUANTITIES:
        out[f"{prefix}_U"] = (f"{prefix}_D", "quantity")
    return out


def quantity_values(nav: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Values of :data:`QUANTITIES` along a motion's navigation arrays (trailing axis K)."""
    k = np.asarray(nav["latitude"]).shape[-1]

    def full(value) -> np.ndarray:
        return np.broadcast_to(np.asarray(value, dtype=float), (k,)).copy()

    out = {"lat": full(nav["latitude"]), "h": full(nav["height"]),
           "R_N": full(nav["R_N"]), "R_E": full(nav["R_E"]), "R_M": full(nav["R_N"]),
           "a": full(nav["a"]), "e2": full(nav["e2"]), "U": full(nav["earth_rate"]),
           "g": full(nav["gravity"])}
    f_n = np.einsum("ijk,jk->ik", nav["C_bn"], nav["f_b"])
    for n, axis in enumerate("NED"):
        out[f"v_{axis}"] = full(nav["v_ned"][n])
        out[f"omega_ie_{axis}"] = full(nav["omega_ie_n"][n])
        out[f"omega_en_{axis}"] = full(nav["omega_en_n"][n])
        out[f"omega_in_{axis}"] = out[f"omega_ie_{axis}"] + out[f"omega_en_{axis}"]
        out[f"f_{axis}"] = full(f_n[n])
    for n, axis in enumerate("xyz"):
        out[f"f_{axis}"] = full(nav["f_b"][n])
        out[f"omega_ib_{axis}"] = full(nav["omega_ib_b"][n])
    for i in range(3):
        for j in range(3):
            out[f"C{i + 1}{j + 1}"] = full(nav["C_bn"][i, j])
    for name, value in nav.get(PARAMETERS, {}).items():  # the model's parameters
        out.setdefault(name, full(value))
    return out


@dataclass
class ConventionCheck:
    """Result of checking a ``@convention`` hand file.

    Attributes
    ----------
    report : MatrixReport
        The entry-by-entry comparison (:mod:`~ins_errors.checker.matrix`).
    lines : dict
        Row (state name) -> (line number, equation text) of the hand file.
    from_model : list of str
        Rows the file does not give (taken from the derived model, not compared).
    definitions : dict
        Name -> :class:`~ins_errors.checker.convention_definitions.Definition` of the
        file's ``NAME = expression`` lines, in file order.
    via : dict
        Row -> {column: names of the definitions the entry's coefficient comes through}
        (entries through none left out).
    notes : list of str
        One-line notes on how a name was read (which radius ``R_N`` is).
    """

    report: object
    lines: dict[str, tuple[int, str]] = field(default_factory=dict)
    from_model: list[str] = field(default_factory=list)
    definitions: dict = field(default_factory=dict)
    via: dict[str, dict[str, tuple[str, ...]]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    @property
    def exit_status(self) -> int:
        """0 no mistake, 1 at least one mistake."""
        return self.report.exit_status

    def line_of(self, finding) -> int:
        """Line number of a finding's row."""
        return self.lines[finding.row][0]

    def via_of(self, finding) -> list:
        """The definitions (:class:`~ins_errors.checker.convention_definitions.
        Definition`) a finding's entry comes through, in file order."""
        return [self.definitions[d]
                for d in self.via.get(finding.row, {}).get(finding.column, ())]


VECTORS: dict[str, tuple[str, ...]] = {
    **{f"omega_{k}": tuple(f"omega_{k}_{a}" for a in "NED") for k in ("ie", "en", "in")},
    "f_n": ("f_N", "f_E", "f_D"), "v_n": ("v_N", "v_E", "v_D"),
    "f_b": ("f_x", "f_y", "f_z"), "omega_ib": ("omega_ib_x", "omega_ib_y", "omega_ib_z"),
}
"""Vector names of a vector line (NED or body components of :data:`QUANTITIES`); also
``C_bn`` (the 3 × 3 matrix ``C11`` … ``C33``), every triple of convention states by its
prefix (``phi``, ``dv``, ``dr``) and of error sources (``gyro_bias``, ``accel_bias``)."""

_VECTOR_LINE = re.compile(r"^\s*dot\(\s*([A-Za-z_][A-Za-z0-9_]*)\s*\)\s*=(.*)$")


def _triples(names: list[str], suffixes: tuple[str, str, str]) -> dict[str, tuple[str, ...]]:
    """Prefix -> three names ``PREFIX_a`` for every complete triple of suffixes."""
    out = {}
    for n in names:
        prefix, _, axis = n.rpartition("_")
        if prefix and axis == suffixes[0] and all(f"{prefix}_{a}" in names
                                                  for a in suffixes):
            out[prefix] = tuple(f"{prefix}_{a}" for a in suffixes)
    return out


class _Vector(sp.MutableDenseMatrix):
    """A SymPy matrix of a vector line in which ``a @ b`` (written ``a × b``) is the cross
    product of two 3-vectors and ``+a`` is ``a``; sums and products with it stay of this
    class (its class priority is above SymPy's matrices)."""

    _class_priority = 20

    def __pos__(self):
        return self

    def __matmul__(self, other):
        if self.shape == (3, 1) and getattr(other, "shape", None) == (3, 1):
            return _Vector(self.cross(other))
        raise ValueError("a × b needs two 3-vectors")

    def __rmatmul__(self, other):
        raise ValueError("a × b needs two 3-vectors")


def _vector_namespace(states: list[str], sources: list[str],
                      defined: dict[str, str] | None = None,
                      extra: dict[str, sp.Expr] | None = None) -> dict[str, object]:
    """Names a vector line may use: vectors (3 × 1), ``C_bn``, scalars, functions, and
    the file's definitions (name as written -> the name the rows use); ``extra``: more
    scalars (the model's parameters, the up components ``phi_U`` = ``-phi_D``, ...)."""
    space: dict[str, object] = {q: sp.Symbol(q) for q in QUANTITIES}
    space.update(extra or {})
    space.update({k: sp.Symbol(v) for k, v in (defined or {}).items()})
    space.update({n: sp.Symbol(n) for n in (*states, *sources)})
    vectors = {**VECTORS, **_triples(states, ("N", "E", "D")),
               **_triples(sources, ("x", "y", "z"))}
    space.update({k: _Vector([sp.Symbol(c) for c in v]) for k, v in vectors.items()})
    space["C_bn"] = _Vector(3, 3, lambda i, j: sp.Symbol(f"C{i + 1}{j + 1}"))
    space.update({"cross": lambda a, b: _Vector(sp.Matrix(a).cross(sp.Matrix(b))),
                  "skew": lambda a: _Vector([[0, -a[2], a[1]], [a[2], 0, -a[0]],
                                             [-a[1], a[0], 0]]),
                  "vec": lambda *c: _Vector(c), "sin": sp.sin, "cos": sp.cos,
                  "tan": sp.tan, "sqrt": sp.sqrt, "pi": sp.pi})
    return space


def _reserved_names(states: list[str], sources: list[str]) -> dict[str, str]:
    """Names a definition may not take, with what they are (for messages).

    The radii of curvature (:data:`RADII`) are not reserved: a file's definition of one
    says which radius its symbol is. Nor are the up components (:func:`up_components`):
    a file that defines ``phi_U = -phi_D`` itself keeps its definition; nor are the
    model's parameters (``k_1 = 0.05`` of a LaTeX file is the file's own ``k1``).
    """
    out = {n: "a vector or function of vector lines"
           for n in _vector_namespace(states, sources) if n not in QUANTITIES}
    out.update({q: f"a named quantity ({meaning})" for q, meaning in QUANTITIES.items()
                if q not in RADII})
    out.update({s: "an error source of the model" for s in sources})
    out.update({s: "a state of the convention" for s in states})
    return out


class _RefusedError(Exception):
    """A right-hand side that uses something a vector line may not (message for people)."""


_OPERATORS = frozenset({"+", "-", "*", "/", "**", "@", "(", ")", ","})
"""The operators a vector line may use (``@`` is ``×``, the cross product)."""


def _only_known_names(tokens: list, local_dict: dict, global_dict: dict) -> list:
    """SymPy parser transformation run first: let through only the namespace's names,
    numbers and arithmetic; refuse the rest (attributes, strings, brackets, keywords)."""
    from tokenize import ENDMARKER, NAME, NEWLINE, NUMBER, OP, STRING

    for kind, text in tokens:
        if kind == STRING:
            raise _RefusedError(f"strings are not allowed in a right-hand side ({text})")
        if kind == NAME and text not in local_dict:
            raise _RefusedError(f"unknown name {text!r} (vectors, states, sources and named "
                           "quantities: docs/hand_check.md)")
        if kind == OP and text == ".":
            raise _RefusedError("attribute access is not allowed")
        if kind == OP and text not in _OPERATORS:
            raise _RefusedError(f"operator {text!r} is not allowed (+ - * / ** × and calls)")
        if kind not in (NAME, NUMBER, OP, NEWLINE, ENDMARKER):
            raise _RefusedError(f"{text!r} is not allowed in a right-hand side")
    return tokens


def _parse_vector_rhs(text: str, space: dict[str, object]):
    """Read a right-hand side with SymPy's parser over ``space`` only (no builtins).

    Names are checked token by token before anything is evaluated; numbers become SymPy
    numbers (``1/2`` is exact).

    Raises
    ------
    _RefusedError
        Unbalanced parentheses, an unknown name, a disallowed operator, attribute or
        string.
    SyntaxError, tokenize.TokenError, TypeError, ValueError, ...
        Text that does not parse or does not evaluate (shapes, arguments).
    """
    from sympy.parsing.sympy_parser import auto_number, parse_expr

    depth = 0
    for character in text:
        depth += {"(": 1, ")": -1}.get(character, 0)
        if depth < 0:
            raise _RefusedError("cannot parse the right-hand side: unmatched ')'")
    if depth:
        raise _RefusedError("cannot parse the right-hand side: unclosed parenthesis")
    numbers = {"Integer": sp.Integer, "Float": sp.Float, "Rational": sp.Rational}
    return parse_expr(text, local_dict=dict(space),
                      global_dict={"__builtins__": {}, **numbers},
                      transformations=(_only_known_names, auto_number))


def split_vector_lines(text: str, states: list[str], sources: list[str], name: str,
                       bias_sources: list[str] | tuple[str, ...] = (),
                       defined: dict[str, str] | None = None,
                       extra: dict[str, sp.Expr] | None = None
                       ) -> tuple[str, dict[str, tuple[int, str, sp.Expr]]]:
    """Take the vector lines ``dot(phi) = ...`` out of a hand file's text.

    Returns the text with those lines blanked (line numbers kept) and their rows
    {state: (line, text, expression)}; a vector line gives the three rows of its prefix
    (``dot(gyro_bias) = ...``: the three bias states of ``bias_sources``, error sources
    that may be states).
    The right-hand side is read by SymPy's parser (:func:`_parse_vector_rhs`) over the
    names of :func:`_vector_namespace` alone: no Python is run. ``defined``: the file's
    definitions (:mod:`~ins_errors.checker.convention_definitions`), name as written ->
    name of the rows; they are scalars, substituted later like those of component rows.
    ``extra``: more scalars by name (:func:`_vector_namespace`).

    Raises
    ------
    InsErrorsError
        A right-hand side that cannot be read or is not a 3-vector, or a definition in
        vector notation (one line, naming it).
    """
    from tokenize import TokenError

    prefixes = {**_triples(states, ("N", "E", "D")),
                **_triples(list(bias_sources), ("x", "y", "z"))}
    space = _vector_namespace(states, sources, defined, extra)
    vectors = {k for k, v in space.items() if isinstance(v, sp.MatrixBase)}
    kept, rows = [], {}
    for number, raw in enumerate(text.splitlines(), start=1):
        body = raw.split("#", 1)[0].replace("×", "@")  # same width: a × b is cross(a, b)
        _not_a_vector_definition(body, vectors, f"{name}, line {number}")
        match = _VECTOR_LINE.match(body)
        if match and match.group(1) not in prefixes:
            _not_a_vector_line(match.group(1), match.group(2), states, prefixes, vectors,
                               f"{name}, line {number}")
        if not match or match.group(1) not in prefixes:
            kept.append(raw)
            continue
        kept.append("")
        shown = " ".join(raw.split("#", 1)[0].split())
        where = f"{name}, line {number}"
        try:
            value = _parse_vector_rhs(match.group(2).strip(), space)
        except _RefusedError as error:
            raise InsErrorsError(f"{where}: {error}") from None
        except TokenError as error:
            raise InsErrorsError(f"{where}: cannot parse the right-hand side: "
                                 f"{' '.join(str(error.args[0]).split())}") from None
        except SyntaxError as error:
            raise InsErrorsError(f"{where}: cannot parse the right-hand side: "
                                 f"{' '.join(str(error.msg).split())}") from None
        except Exception as error:  # shapes, wrong arguments: one line
            raise InsErrorsError(f"{where}: cannot evaluate the right-hand side: "
                                 f"{' '.join(str(error).split())}") from None
        if not isinstance(value, sp.MatrixBase) or value.shape != (3, 1):
            raise InsErrorsError(f"{where}: dot({match.group(1)}) needs a 3-vector on the "
                                 "right-hand side")
        for row, expr in zip(prefixes[match.group(1)], value, strict=True):
            if row in rows:
                raise InsErrorsError(f"{where}: second equation for dot({row})")
            rows[row] = (number, shown, sp.expand(expr))
    return "\n".join(kept) + "\n", rows


_VECTOR_WORDS = re.compile(r"\b(cross|skew|vec)\s*\(|@")
_DEFINITION_LINE = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*=(?!=)(.*)$")


def _not_a_vector_definition(body: str, vectors: set, where: str) -> None:
    """Refuse a definition ``NAME = ...`` in vector notation: definitions are scalars."""
    match = _DEFINITION_LINE.match(body)
    if not match:
        return
    rhs = match.group(2)
    found = _VECTOR_WORDS.search(rhs)
    named = sorted(set(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", rhs)) & vectors)
    if found or named:
        what = (f"{found.group(1)}()" if found and found.group(1) else "×" if found
                else f"the vector {named[0]!r}")
        raise InsErrorsError(
            f"{where}: the definition of {match.group(1)} uses {what}, but a definition is "
            f"one scalar: define its components ({match.group(1)}_N = ..., ...) and use "
            "them in vec(...)")


def _not_a_vector_line(lhs: str, rhs: str, states: list[str], prefixes: dict, vectors: set,
                       where: str) -> None:
    """Refuse, in one line naming the real problem, a line ``dot(X) = ...`` that is not a
    vector line but uses vector notation on its right: a row of one component
    (``dot(phi_N) = cross(...)``) or a left side that is no state or state triple
    (``dot(dw) = -cross(...)``). Other lines are left to the equation reader."""
    found = _VECTOR_WORDS.search(rhs)
    named = sorted(set(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", rhs)) & vectors)
    if not found and not named:
        return
    what = (f"{found.group(1)}()" if found and found.group(1) else "×" if found
            else f"the vector {named[0]!r}")
    if lhs in states:
        prefix = lhs.rpartition("_")[0]
        raise InsErrorsError(
            f"{where}: dot({lhs}) is one component, but its right-hand side uses {what}, "
            f"a vector: write the component's terms, or the vector line "
            f"'dot({prefix}) = ...' for all three rows")
    close = close_names(lhs, [*prefixes, *states], cutoff=0.5)
    hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
    raise InsErrorsError(
        f"{where}: dot({lhs}): {lhs!r} is neither a state of the convention nor a "
        f"vector of its states (vectors: {', '.join(prefixes)}){hint}")


EARTH_RATE_SPELLINGS = ("Omega", "Omega_ie")
r"""Spellings of the Earth rate ``U`` in a ``@convention`` file (``\Omega``,
``\Omega_{ie}``; in LaTeX also ``\omega_{ie}``, which in text is the vector of vector
lines), unless the model's LaTeX gives one to another of its names."""


def convention_notation(model_name: str, states: list[str], sources: list[str],
                        parameters: list[str] | tuple[str, ...] = (), latex: bool = False):
    r"""Spellings of a ``@convention`` file: the convention's states as they are printed
    and read from LaTeX, the model's own spellings of its error sources, and the named
    quantities' LaTeX forms (:data:`QUANTITIES`).

    * ``\delta v_N`` (read as ``Delta_v_N``) is ``dv_N``; likewise ``\delta r_N`` ->
      ``dr_N``, ``\delta u_N`` -> ``du_N``, and in a ``_geodetic`` convention
      ``\deltaarphi`` -> ``dlat``, ``\delta\lambda`` -> ``dlon``, ``\delta h`` -> ``dh``
      (the text spellings ``Delta_v_N`` ... too); ``\delta\dot{v}_N`` is ``dot(dv_N)``;
      the up components likewise (``\delta v_U`` -> ``dv_U``, read as ``-dv_D``:
      :func:`up_components`); ``\delta L`` (``Delta_lat``) -> ``dlat`` where ``dlat``
      is a state;
    * the model's LaTeX of its sources and ``parameters``: ``b_{gx}`` ->
      ``gyro_bias_x``, ``b_{ax}``, ..., ``k_1`` -> ``k_h1``;
    * the Earth rate: ``\Omega``, ``\Omega_{ie}`` (and with ``latex``, ``\omega_{ie}``)
      -> ``U`` (:data:`EARTH_RATE_SPELLINGS`), whatever the model's LaTeX of it;
    * ``\omega_{in,D}`` (read as ``omega_inD``) -> ``omega_in_D``, and so for ``ie``,
      ``en``, ``ib``; ``L`` (latitude, as Titterton and Weston write it) -> ``lat``.

    A spelling never hides a name a file may use as it is (states, sources, quantities).
    """
    from ins_errors.checker.notation import Notation, default_notation

    known = set(states) | set(sources) | set(QUANTITIES) | set(parameters)
    spellings: dict[str, str] = {}
    for name in [*states, *(up for up, (_, kind) in up_components(states).items()
                            if kind == "state")]:
        base, _, axis = name.rpartition("_")
        if base in ("dv", "dr", "du"):
            spellings[f"Delta_{base[1:]}_{axis}"] = name
    spellings.update({k: v for k, v in (("Delta_phi", "dlat"), ("Delta_lam", "dlon"),
                                        ("Delta_h", "dh"), ("Delta_lat", "dlat"),
                                        ("Delta_lon", "dlon")) if v in states})
    model_spellings = default_notation(model_name).spellings
    spellings.update({k: v for k, v in model_spellings.items()
                      if v in sources or v in parameters or (v == "U" and k == "Omega")})
    for spelling in (*EARTH_RATE_SPELLINGS, *(("omega_ie",) if latex else ())):
        spellings.setdefault(spelling, "U")
    for q in QUANTITIES:
        if q.startswith("omega_") and q.count("_") == 2:
            _, frame, axis = q.split("_")
            spellings[f"omega_{frame}{axis}"] = q
    spellings["L"] = "lat"
    return Notation(spellings={k: v for k, v in spellings.items() if k not in known})


def _giving_way(notation, raw, states: list[str]):
    """``notation`` without the spellings of states that a file's definition takes.

    ``\\delta L`` (``Delta_lat``) is ``dlat`` and ``\\delta v_U`` is ``dv_U``
    (``-dv_D``) only since east-north-up names are read; a file that defines one of
    them itself (``\\delta L = \\delta\\varphi``, ``\\delta v_U = -\\delta v_D``)
    keeps its definition, as before.
    """
    from ins_errors.checker.notation import Notation
    from ins_errors.checker.parse import canonical_name

    soft = {k for k, v in notation.spellings.items()
            if k in ("Delta_lat", "Delta_lon") or v in up_components(states)}
    written = [eq.lhs.name for eq in raw.equations if isinstance(eq.lhs, sp.Symbol)]
    drop = set()
    for key in soft:
        without = Notation(spellings={k: v for k, v in notation.spellings.items()
                                      if k != key})
        if any(canonical_name(text, without) == sp.Symbol(key) for text in written):
            drop.add(key)
    if not drop:
        return notation
    return Notation(aliases=dict(notation.aliases), sources=dict(notation.sources),
                    spellings={k: v for k, v in notation.spellings.items()
                               if k not in drop},
                    latex_primes=dict(notation.latex_primes))


def _names_used(hand, vector_rows: dict) -> set[str]:
    """Every name the equations, definitions and ``@neglect`` items of a file use."""
    exprs = [*(f for eq in hand.equations for f in eq.forms),
             *(item for d in hand.declarations for item in d.items),
             *(rhs for _, _, rhs in vector_rows.values())]
    return {s.name for e in exprs for s in e.free_symbols}


def radius_reading(used: set[str], own: set[str], name: str
                   ) -> tuple[dict[str, str], list[str]]:
    """Which radius of curvature a file's ``R_N`` is, and the note that says so.

    ``R_N`` is the meridian radius (Titterton and Weston's, with ``R_E`` the prime
    vertical); many east-north-up texts write ``R_M`` for the meridian and ``R_N`` for
    the prime vertical. A file that uses ``R_M`` (or defines it) and ``R_N`` has the
    second meaning: its ``R_N`` is read as the prime-vertical radius, with a note. A file
    that also uses ``R_E`` has no reading: it is refused. A file using ``R_N`` alone gets
    a note that it is read as the meridian radius. ``@name R_N = ...`` or a definition
    of ``R_N`` says which it is: no note.

    Parameters
    ----------
    used : set of str
        The names the file's equations use (after its spellings).
    own : set of str
        The names the file defines.
    name : str
        File name, for the note.

    Returns
    -------
    reading : dict
        File's radius -> the named quantity whose value it takes (``{"R_N": "R_E"}``).
    notes : list of str
        One line each.

    Raises
    ------
    InsErrorsError
        ``R_M``, ``R_N`` and ``R_E`` all used, ``R_N`` undeclared.
    """
    if "R_N" not in used or "R_N" in own:
        return {}, []
    paired = "R_M" in used or "R_M" in own
    with_east = "R_E" in used or "R_E" in own
    if paired and with_east:
        raise InsErrorsError(
            f"{name}: R_M, R_N and R_E are all used, so R_N could be either radius of "
            "curvature: say which with '@name R_N = R_E' (prime vertical) or '@name R_N = "
            "R_M' (meridian), or define R_N")
    if paired:
        return {"R_N": "R_E"}, [
            f"{name}: R_N is read as the prime-vertical radius of curvature (R_E of "
            "docs/hand_check.md), as the file writes R_M for the meridian radius; "
            "'@name R_N = R_E' says so without this note, '@name R_N = R_M' reads R_N as "
            "the meridian radius"]
    if with_east:
        return {}, []
    return {}, [f"{name}: R_N is read as the meridian radius of curvature (Titterton and "
                "Weston's R_N, with R_E the prime vertical); for the prime-vertical "
                "radius, as east-north-up texts often write R_N, add '@name R_N = R_E'"]


def _eccentricity_named(hand, vector_rows: dict, model, own: set[str]) -> list[str]:
    """The note that ``e`` (of ``e^2``) or ``e2`` is 0 in a file of a model without an
    eccentricity parameter (a spherical Earth), naming the first line; empty otherwise.

    Not refused: an ellipsoid's equations hold on a sphere with e² = 0
    (``examples/strapdown/phi_attitude.txt`` against ``strapdown_sphere.py``).
    """
    from ins_errors.earth_constants import earth_parameter_names

    if earth_parameter_names(model.parameters).eccentricity is not None:
        return []
    names = {"e", "e2"} - own
    lines = [(eq.line, f) for eq in hand.equations for f in eq.forms]
    lines += [(d.line, item) for d in hand.declarations for item in d.items]
    lines += [(line, rhs) for line, _, rhs in vector_rows.values()]
    for line, expr in sorted(lines, key=lambda pair: pair[0]):
        found = sorted(s.name for s in expr.free_symbols if s.name in names)
        if found:
            return [f"{hand.name}, line {line}: {'e^2' if found[0] == 'e' else 'e2'} "
                    f"(eccentricity squared) is read as 0: model {model.name!r} has no "
                    "eccentricity, its Earth is a sphere (parameters "
                    f"{', '.join(p.name for p in model.parameters)})"]
    return []


def _in_convention_names(hand, substitution: dict, ups: dict[str, tuple[str, str]]):
    """``hand`` with the up components and ``e`` in the convention's names: every
    right-hand side and ``@neglect`` item through ``substitution`` (``phi_U`` ->
    ``-phi_D``, ``e`` -> ``sqrt(e2)``), and a row ``dot(phi_U) = X`` made ``dot(phi_D)
    = -X`` (exactly the same row)."""
    from dataclasses import replace

    from ins_errors.checker.parse import DOT

    equations = []
    for eq in hand.equations:
        forms = [f.xreplace(substitution) for f in eq.forms]
        lhs = eq.lhs
        if (isinstance(lhs, sp.Function) and lhs.func == DOT
                and isinstance(lhs.args[0], sp.Symbol)
                and ups.get(lhs.args[0].name, ("", ""))[1] == "state"
                and sp.Symbol(lhs.args[0].name) in substitution):
            lhs = DOT(sp.Symbol(ups[lhs.args[0].name][0]))
            forms = [-f for f in forms]
        equations.append(replace(eq, lhs=lhs, forms=forms))
    declarations = [replace(d, items=tuple(i.xreplace(substitution) for i in d.items))
                    for d in hand.declarations]
    return replace(hand, equations=equations, declarations=declarations)


def _up_states_written(hand, ups: dict[str, tuple[str, str]], own: set[str]
                       ) -> dict[str, str]:
    """``{X_D: X_U}`` of each state the file writes as its up component only (``phi_U``
    on a left side or in a right-hand side, ``phi_D`` nowhere): its findings name the
    entry as the file wrote it too (:func:`~ins_errors.checker.up_states.as_written`)."""
    from ins_errors.checker.parse import DOT

    names: set[str] = set()
    for eq in hand.equations:
        names |= set(eq.columns)
        lhs = eq.lhs
        if (isinstance(lhs, sp.Function) and lhs.func == DOT
                and isinstance(lhs.args[0], sp.Symbol)):
            names.add(lhs.args[0].name)
    return {down: up for up, (down, kind) in ups.items()
            if kind == "state" and up in names and up not in own and down not in names}


def _rows(hand, states: list[str], sources: list[str],
          vector_rows: dict[str, tuple[int, str, sp.Expr]],
          bias_sources: list[str] | tuple[str, ...] = (),
          defined: set[str] | frozenset[str] = frozenset(),
          bias_example: str = "dot(gyro_bias_x)", quantities=QUANTITIES):
    """{row: (line, text, expression)} of the hand file's equations; one-line errors.

    A row is a state of the convention or a bias state: one of ``bias_sources`` (the
    model's error sources that enter its equations) with its own line. Equations with a
    name on the left are definitions (``defined``, read by
    :func:`~ins_errors.checker.convention_definitions.read_definitions`); a row's
    expression still holds them by name."""
    from ins_errors.checker.parse import DOT

    known = set(states) | set(sources) | set(quantities) | set(defined)
    rows: dict[str, tuple[int, str, sp.Expr]] = dict(vector_rows)
    for eq in hand.equations:
        lhs = eq.lhs
        if isinstance(lhs, sp.Symbol) and lhs.name in defined:
            continue
        if not (isinstance(lhs, sp.Function) and lhs.func == DOT
                and isinstance(lhs.args[0], sp.Symbol)
                and (lhs.args[0].name in states or lhs.args[0].name in bias_sources)):
            raise InsErrorsError(f"{hand.name}, line {eq.line}: left-hand side {str(lhs)!r} "
                                 f"must be dot(STATE) of a state of the convention "
                                 f"({', '.join(states)}) or of an error source carried as a "
                                 f"bias state ({bias_example})" + cn.true_rate_hint(lhs, states))
        row = lhs.args[0].name
        if row in rows:
            raise InsErrorsError(f"{hand.name}, line {eq.line}: second equation for "
                                 f"dot({row}) (first on line {rows[row][0]})")
        if len(eq.forms) != 1:
            raise InsErrorsError(f"{hand.name}, line {eq.line}: one right-hand side per "
                                 "equation under @convention")
        rhs = eq.forms[0]
        for s in sorted(rhs.free_symbols, key=str):
            if s.name not in known:
                raise InsErrorsError(
                    f"{hand.name}, line {eq.line}: unknown name {s.name!r} (states: "
                    f"{', '.join(states)}; error sources of the model; named quantities "
                    "and definitions NAME = expression: docs/hand_check.md)")
        rows[row] = (eq.line, eq.text, rhs)
    if not rows:
        raise InsErrorsError(f"{hand.name}: no equation under @convention")
    for s in sorted(set().union(*(r[2].free_symbols for r in rows.values())), key=str):
        if s.name not in known:
            raise InsErrorsError(f"{hand.name}: unknown name {s.name!r}")
    return rows


def _latex_rate(latex: str) -> str:
    r"""How a LaTeX file writes a source's rate: ``b_{gx}`` -> ``\dot{b}_{gx}``."""
    base, underscore, rest = latex.partition("_")
    return f"\\dot{{{base}}}{underscore}{rest}"


def _source_named(written: str, notation, form: str, sources: list[str]) -> str:
    r"""The error source an ``@markov`` line names, in the file's spelling: the model's
    name, or its LaTeX (``b_{gz}``, ``\varepsilon_z``) or text (``b_gz``) spelling; what
    names no source is returned as written (refused with the other bias-state checks)."""
    from ins_errors.checker.parse import (
        _LineError,
        parse_latex_expression,
        parse_text_expression,
    )

    if written in sources:
        return written
    read = parse_latex_expression if form == "latex" else parse_text_expression
    try:
        expr, _ = read(written, notation)
    except (_LineError, InsErrorsError):
        return written
    return expr.name if isinstance(expr, sp.Symbol) and expr.name in sources else written


def _markov_sources(hand, notation, sources: list[str], rows, states: list[str]
                    ) -> tuple[dict[str, str], dict[str, int]]:
    """The ``@markov`` lines by the model's source names: (source -> time text,
    source -> line), for :func:`~ins_errors.checker.matrix_input.
    correlation_times`.

    Raises
    ------
    InsErrorsError
        Two lines for one source in different spellings (``gyro_bias_z`` and ``b_gz``),
        or one for a source that is no bias state (no line ``dot(SOURCE)``), naming the
        line.
    """
    out: dict[str, str] = {}
    lines: dict[str, int] = {}
    for written, value in hand.markov.items():
        line = hand.markov_lines.get(written, 0)
        name = _source_named(written, notation, hand.format, sources)
        if name in out:
            raise InsErrorsError(f"{hand.name}, line {line}: second @markov of {name} "
                                 f"(first on line {lines[name]}): give one correlation "
                                 "time")
        if name not in rows or name in states:
            raise InsErrorsError(f"{hand.name}, line {line}: @markov gives a correlation "
                                 f"time for {written!r}, which is not a bias state (a model "
                                 "error source with a line dot(SOURCE))")
        out[name], lines[name] = value, line
    return out, lines


def _coefficients(row: str, line: int, name: str, rhs: sp.Expr, variables: list[str]
                  ) -> list[sp.Expr]:
    """Coefficient of each variable in ``rhs``; error if not linear in them."""
    symbols = [sp.Symbol(v) for v in variables]
    out = [sp.diff(rhs, s) for s in symbols]
    for s, c in zip(symbols, out, strict=True):
        if c.free_symbols & set(symbols):
            raise InsErrorsError(f"{name}, line {line}: dot({row}) is not linear in the error "
                                 f"quantities (coefficient of {s} is {c})")
    rest = sp.simplify(rhs.subs({s: 0 for s in symbols}))
    if rest != 0:
        raise InsErrorsError(f"{name}, line {line}: dot({row}) has a term without an error "
                             f"quantity: {rest}")
    return out


_NO_VARIATIONS = ("under @convention an item of @neglect is a term left out of a right-hand "
                  "side, a coefficient times a state or error source (e.g. "
                  "'(2*omega_ie_D + omega_en_D)*dv_E'); the derived side is the model's "
                  "matrix in the convention's states, which has no intermediate quantity "
                  "whose variation could be dropped")


def _declared_items(hand, states: list[str], sources: list[str],
                    definitions: dict | None = None, quantities=QUANTITIES
                    ) -> list[tuple[int, int, str, dict[str, sp.Expr]]]:
    """The ``@neglect`` items of a ``@convention`` file as terms: (declaration index,
    line, item text, {column: coefficient}) with a column for each state or source the
    item multiplies (the equation checker's declared terms,
    :class:`~ins_errors.checker.classify.Declarations`).

    Raises
    ------
    InsErrorsError
        An item with an unknown name, without a state or source (a dropped variation has
        no meaning here: :data:`_NO_VARIATIONS`), not linear in them, or with a part
        free of them; one line naming the ``@neglect`` line and the item. Definitions of
        earlier lines are substituted (a later one is refused).
    """
    definitions = definitions or {}
    known = set(states) | set(sources) | set(quantities)
    variables = [sp.Symbol(v) for v in (*states, *sources)]
    out = []
    for k, declaration in enumerate(hand.declarations):
        for item, text in zip(declaration.items, declaration.texts, strict=True):
            if item == sp.Symbol("h") and "h" not in definitions:
                continue  # the height held at 0: convention_height.held_heights
            where = f"{hand.name}, line {declaration.line}: @neglect {text}"
            item = cd.expand(item, declaration.line, f"@neglect {text}", definitions,
                             hand.name)
            unknown = sorted(s.name for s in item.free_symbols if s.name not in known)
            if unknown:
                raise InsErrorsError(f"{where}: {unknown[0]!r} is not a state, error source "
                                     f"or named quantity; {_NO_VARIATIONS}")
            if not item.free_symbols & set(variables):
                held = ("; of the named quantities only the height can be neglected, held "
                        "at 0 ('@neglect h : h << R')" if item.is_Symbol else "")
                raise InsErrorsError(f"{where}: no state or error source in it; "
                                     f"{_NO_VARIATIONS}{held}")
            expanded = sp.expand(item)
            columns = {}
            for v in variables:
                c = sp.diff(expanded, v)
                if c == 0:
                    continue
                if c.free_symbols & set(variables):
                    raise InsErrorsError(f"{where}: not linear in the states and error "
                                         f"sources (coefficient of {v} is {c})")
                columns[v.name] = c
            rest = sp.simplify(expanded.subs({v: 0 for v in variables}))
            if rest != 0:
                raise InsErrorsError(f"{where}: a part without a state or error source "
                                     f"({rest}); {_NO_VARIATIONS}")
            out.append((k, declaration.line, text, columns))
    return out


@lru_cache(maxsize=1024)
def _row_function(coefficients: tuple[sp.Expr, ...],
                  names: tuple[str, ...] = tuple(QUANTITIES)):
    """The coefficients of one row as a numpy function of the named quantities ``names``
    (:func:`quantity_names`), kept per
    process: a file checked again (or a copy with other rows changed) prints and
    compiles each row once (the same expressions give the same code)."""
    return sp.lambdify([sp.Symbol(q) for q in names], list(coefficients),
                       modules="numpy", docstring_limit=0)


def check_convention_file(path: str | Path, model_name: str = "strapdown_ned",
                          threshold: float | None = None,
                          magnitudes: dict[str, str] | None = None,
                          latex: bool | None = None, hours: float | None = None,
                          step: float | None = None, effects: bool = True,
                          parameters: Mapping[str, float] | None = None
                          ) -> ConventionCheck:
    """Check a hand file with ``@convention NAME`` against the derived model.

    Parameters
    ----------
    path : str or Path
        Hand file (SymPy text; LaTeX by suffix or ``latex``).
    model_name : str
        Model with conventions (``strapdown_ned``).
    threshold : float, optional
        Relative size separating dropped small terms from mistakes (default 1e-3).
    magnitudes : dict, optional
        Typical sizes by SI unit (added to the file's ``@magnitude`` lines, overriding them).
    hours, step : float, optional
        Length (h) and sample step (s) of the motions (default: the matrix checker's).
    effects : bool
        Also propagate both linear models (1 h and 24 h).
    parameters : mapping of str to float, optional
        Parameter values (SI) the motions are flown and the derived model is evaluated
        with (e.g. damping gains); default: the model's.

    Raises
    ------
    InsErrorsError
        Unreadable file, unknown names, non-linear equations, no ``@convention``.
    """
    from ins_errors.checker import matrix as mx
    from ins_errors.checker import matrix_input as mx_input
    from ins_errors.checker.conventions import convention
    from ins_errors.checker.matrix_input import HandMatrices
    from ins_errors.checker.notation import Notation
    from ins_errors.checker.parse import parse_hand_text, read_hand_file
    from ins_errors.numeric.model import load_model

    hand = read_hand_file(path, Notation(), latex=latex)
    if hand.convention is None:
        raise InsErrorsError(f"{hand.name}: no '@convention NAME' line")
    if hand.notation.aliases:  # read by the model-equation check only: never ignored
        alias, value = next(iter(hand.notation.aliases.items()))
        raise InsErrorsError(
            f"{hand.name}: '@alias {alias} = {value}' is not read in a @convention file; "
            f"write it as a definition line, '{alias} = {value}'")
    model = load_model(model_name)
    conv = convention(model, hand.convention)
    states = conv.names
    src_names = [s.name for s in model.sources]
    rate_sources = [s.name for s in model.sources if s.kind == "constant"]
    names = quantity_names(model)
    parameters_named = names[len(QUANTITIES):]
    ups = up_components(states)
    vector_rows: dict[str, tuple[int, str, sp.Expr]] = {}
    # the file's own definitions (NAME = ...) keep their names (Omega is not U there)
    reserved = _reserved_names(states, src_names)
    notation, defined = cd.defined_names(
        hand, _giving_way(convention_notation(model_name, states, src_names,
                                              parameters_named, hand.format == "latex"),
                          hand, states),
        reserved, {k: v for k, v in reserved.items() if k in states or k in src_names},
        hand.name)
    own = set(defined.values())
    # an east-north-up file's up components, and e of e^2, in the convention's names
    substitution = {sp.Symbol(up): -sp.Symbol(down) for up, (down, _) in ups.items()
                    if up not in own}
    if "e" not in own:
        substitution[sp.Symbol("e")] = sp.sqrt(sp.Symbol("e2"))
    if hand.format == "text":
        extra = {**{p: sp.Symbol(p) for p in parameters_named},
                 **{k.name: v for k, v in substitution.items()}}
        text, vector_rows = split_vector_lines(Path(path).read_text(encoding="utf-8-sig"),
                                               states, src_names, hand.name, rate_sources,
                                               defined, extra)
        hand = parse_hand_text(text, notation, name=hand.name)
    else:  # read again with the convention's spellings (\delta v_N is dv_N)
        hand = read_hand_file(path, notation, latex=True)
    if hand.problems:
        raise InsErrorsError(f"{hand.name}: {hand.problems[0]}")
    cn.check_names_written(hand, set(states) | set(src_names) | set(names) | own | set(ups)
                        | {"e"}, states, model, notation)
    sphere = _eccentricity_named(hand, vector_rows, model, own)
    up_written = _up_states_written(hand, ups, own)
    hand = _in_convention_names(hand, substitution, ups)
    reading, notes = radius_reading(_names_used(hand, vector_rows), own, hand.name)
    notes += sphere
    known = set(states) | set(src_names) | set(names)
    definitions = cd.read_definitions(hand, known, [*states, *src_names])
    example = "dot(gyro_bias_x)"
    if hand.format == "latex" and rate_sources:
        first = next(s for s in model.sources if s.name == rate_sources[0])
        example = f"dot({first.name}), in LaTeX {_latex_rate(first.latex)}"
    written = _rows(hand, states, src_names, vector_rows, rate_sources, set(definitions),
                    example, names)
    rows = {row: (line, text, cd.expand(rhs, line, f"dot({row})", definitions, hand.name))
            for row, (line, text, rhs) in written.items()}
    # error sources with a line of their own are bias states (after the convention's)
    times, lines = _markov_sources(hand, notation, src_names, rows, conv.names)
    markov = mx_input.correlation_times(times, hand.name, "@markov", lines)
    conv = conv.with_biases(mx.bias_states([*states, *(s for s in src_names if s in rows)],
                                           [], markov, conv, model, hand.name, "@markov"))
    states = conv.names
    held = set().union(*(r[2].free_symbols for r in rows.values()))  # (one walk a row)
    used = [s for s in src_names if sp.Symbol(s) in held and s not in states]
    variables = states + used
    functions, coefficient_of = {}, {}
    for row, (line, _, rhs) in rows.items():
        coefficient_of[row] = _coefficients(row, line, hand.name, rhs, variables)
        functions[row] = _row_function(tuple(coefficient_of[row]), tuple(names))
    via = {row: cd.provenance(rhs, definitions, variables)
           for row, (_, _, rhs) in written.items()}
    items = _declared_items(hand, states, src_names, definitions, names)
    held = ch.held_heights(hand, definitions)
    since = min((at for _, at, _ in held), default=None)  # h is 0 in the rows after it
    at_zero = {row for row, (line, _, _) in rows.items() if since is not None and since < line}
    item_functions = [(list(cols), _row_function(tuple(cols.values()), tuple(names)))
                      for _, _, _, cols in items]
    item_values: list[dict[str, dict[str, np.ndarray]]] = [{} for _ in items]
    motion_list, skipped = mx.flown_motions(model, mx.HOURS if hours is None else hours,
                                            mx.STEP if step is None else step,
                                            parameters=parameters)
    if hand.scope is not None:
        label = {"static base": "static", "cruise": "cruise", "climb": "manoeuvre"}[hand.scope]
        motion_list = [m for m in motion_list if m.label == label]
        skipped = [s for s in skipped if s.split(":", 1)[0] == label]
        if not motion_list:  # the model cannot fly the one motion the file is about
            raise InsErrorsError(f"{hand.name}: '@scope {hand.scope}' is the {label} "
                                 f"motion: {skipped[0].split(': ', 1)[1]}")
    F, G = {}, {}
    src_cols = [src_names.index(s) for s in used]
    samples = []  # (quantities, derived F, derived G) of each motion, for symbol slips
    height_terms: dict[tuple[str, str, str], dict[str, np.ndarray]] = {}
    for motion in motion_list:
        Fz, Gz = mx.derived_in_convention(model, conv, motion)
        Fh, Gh = Fz.copy(), Gz[:, :, src_cols].copy()
        values = quantity_values(motion.navigation)
        args = [values[reading.get(q, q)] for q in names]
        samples.append((args, Fz, Gz[:, :, src_cols]))
        k = Fz.shape[0]
        for row, fn in functions.items():
            i = states.index(row)
            coefficients = [np.broadcast_to(np.asarray(c, dtype=float), (k,))
                            for c in fn(*args)]
            Fh[:, i, :] = np.stack(coefficients[:len(states)], axis=-1)
            if used:
                Gh[:, i, :] = np.stack(coefficients[len(states):], axis=-1)
        F[motion.label], G[motion.label] = Fh, (Gh if used else {})
        if at_zero:  # @neglect h: the part of each difference that vanishes at h = 0
            level = ch.at_zero_height(model, motion, f"{hand.name}, line {since}: @neglect h")
            Fz0, Gz0 = mx.derived_in_convention(model, conv, level)
            values0 = quantity_values(level.navigation)
            args0 = [values0[reading.get(q, q)] for q in names]
            for row in at_zero:
                i = states.index(row)
                c0 = np.stack([np.broadcast_to(np.asarray(c, dtype=float), (k,))
                               for c in functions[row](*args0)], axis=-1)
                ch.height_terms(height_terms, motion.label, row, states, used,
                              (Fh[:, i, :] - Fz[:, i, :]) - (c0[:, :len(states)]
                                                             - Fz0[:, i, :]),
                              (Gh[:, i, :] - Gz[:, i, src_cols])
                              - (c0[:, len(states):] - Gz0[:, i, src_cols]))
        for values_of, (columns, fn) in zip(item_values, item_functions, strict=True):
            for column, c in zip(columns, fn(*args), strict=True):
                values_of.setdefault(column, {})[motion.label] = np.broadcast_to(
                    np.asarray(c, dtype=float), (k,))
    if not used:
        G = {}
    sampled = HandMatrices(Path(path).name, list(states), used, F, G, markov)
    overrides = {**hand.magnitudes, **(magnitudes or {})}
    declared: dict[tuple[str, str, str], list[mx.DeclaredTerm]] = {}
    for row, (line, _, _) in rows.items():  # a declaration holds from its line on
        for (k, at, text, _), values_of in zip(items, item_values, strict=True):
            for column, values in values_of.items():
                matrix = "F" if column in states else "G"
                if at < line and (matrix == "F" or column in used):
                    declared.setdefault((matrix, row, column), []).append(
                        mx.DeclaredTerm(k, at, text, values))
    for entry, values in height_terms.items():  # what h brings to the derived entry
        if any(np.any(v) for v in values.values()):
            for k, at, text in held:
                declared.setdefault(entry, []).append(
                    mx.DeclaredTerm(k, at, f"{text}, held at 0", values))
    found: set[int] = set()
    report = mx.check_matrices(model_name, sampled, conv.name,
                               threshold=1e-3 if threshold is None else threshold,
                               effects=effects, motion_list=motion_list,
                               magnitudes=overrides, declared=declared, declared_used=found,
                               parameters=parameters, skipped_motions=skipped)
    report.written = up_written
    report.declarations = [f"line {d.line}: {', '.join(d.texts)}"
                           + (f" ({d.reason})" if d.reason else "")
                           for d in hand.declarations]
    report.idle_declarations = [f"line {d.line}: {', '.join(d.texts)}"
                                for k, d in enumerate(hand.declarations) if k not in found]
    # rows taken from the derived model agree by construction: count the file's rows only
    report.findings = [f for f in report.findings if f.row in rows]
    report.findings = _symbol_slips(report.findings, coefficient_of, states, used, samples,
                                    report.threshold, names, set(reading.values()))
    report.compared = len(rows) * (len(states) + len(used))
    return ConventionCheck(report, {r: (v[0], v[1]) for r, v in rows.items()},
                           [s for s in states if s not in rows], definitions,
                           {r: v for r, v in via.items() if v}, notes)


def _symbol_slips(findings: list, coefficient_of: dict[str, list[sp.Expr]],
                  states: list[str], used: list[str], samples: list,
                  threshold: float, names: list[str] | None = None,
                  untried: set[str] | frozenset[str] = frozenset()) -> list:
    """The findings with each ``wrong coefficient`` or ``approximated`` entry that one
    index of a named quantity explains made a ``wrong symbol or index`` (a mistake
    whatever its size: ``R_E`` for ``R_N`` is within 0.7 % of the derived entry, which
    alone would read as an approximation): the hand's coefficient with one quantity
    replaced by a sibling (``f_E`` by ``f_D``, ``C12`` by ``C13``, ``R_N`` by ``R_E``:
    :func:`~ins_errors.checker.classify.candidates`) equals the derived entry at every
    sample of every motion, to 1e-6 of its largest value (the equation checker's rule
    for a symbol slip; slips of a whole term to another column are found by the matrix
    check, :mod:`~ins_errors.checker.matrix_slips`).

    ``samples``: (the values of the named quantities ``names``, default
    :data:`QUANTITIES`, in their order, derived F, derived G of the file's sources) of
    each motion; ``untried``: quantities not tried as another index (the radius a file's
    ``R_N`` stands for: :func:`radius_reading`); ``threshold``: the check's, for the
    severity. A
    finding the matrix check already found a radius slip
    (:data:`~ins_errors.checker.matrix.RADII_SWAP`) gets the symbol named.
    """
    from dataclasses import replace

    from ins_errors.checker.classify import candidates
    from ins_errors.checker.kinds import COEFFICIENT, SYMBOL
    from ins_errors.checker.kinds import severity as classify_severity
    from ins_errors.checker.matrix import APPROXIMATED, RADII_SWAP

    arguments = tuple(QUANTITIES) if names is None else tuple(names)
    known = [sp.Symbol(q) for q in arguments if q not in untried]
    out = []
    for f in findings:
        if not (f.kind in (COEFFICIENT, APPROXIMATED)
                or (f.kind == SYMBOL and f.detail.startswith(RADII_SWAP))):
            out.append(f)
            continue
        i = states.index(f.row)
        if f.matrix == "F":
            j = states.index(f.column)
            derived = np.concatenate([Fz[:, i, j] for _, Fz, _ in samples])
        else:
            c = used.index(f.column)
            j = len(states) + c
            derived = np.concatenate([Gz[:, i, c] for _, _, Gz in samples])
        top = float(np.max(np.abs(derived)))
        for kind, text, changed in candidates(coefficient_of[f.row][j], known):
            if kind != SYMBOL:
                continue
            fn = _row_function((changed,), arguments)
            with np.errstate(all="ignore"):  # a trial change may divide by 0: not a fit
                values = np.concatenate([np.broadcast_to(np.asarray(fn(*args)[0],
                                                                    dtype=float),
                                                         (Fz.shape[0],))
                                         for args, Fz, _ in samples])
            if np.all(np.isfinite(values)) and np.all(np.abs(values - derived)
                                                      <= 1e-6 * top):
                f = replace(f, kind=SYMBOL, detail=f"{text} (with it the entry is the "
                            "derived one at every sample)",
                            severity=classify_severity(SYMBOL, f.size, threshold))
                break
        out.append(f)
    return out


def to_terminal(check: ConventionCheck) -> str:
    """The matrix report, then every finding with the hand file's line (and the lines of
    the definitions its entry comes through: ``via rho_N, line 7``)."""
    from ins_errors.checker.definition_causes import causes
    from ins_errors.checker.matrix_report import to_terminal as matrix_terminal
    from ins_errors.checker.up_states import as_written

    out = [matrix_terminal(check.report), "", "Findings by line of the hand file:"]
    out += [f"  {cause.text}" for cause in causes(check)]  # a definition they share first
    if not check.report.findings:
        out.append("  (none: every term agrees)")
    for f in sorted(check.report.findings, key=check.line_of):  # (stable: worst first)
        line, text = check.lines[f.row]
        through = "; ".join(d.label for d in check.via_of(f))
        yours = as_written(f.matrix, f.row, f.column, check.report.written)
        out.append(f"  line {line}: {f.severity}: {f.kind} {f.entry}{yours} "
                   f"(size {f.size:.2g}"
                   f"{', ' + f.detail if f.detail else ''})"
                   f"{' via ' + through if through else ''}  [{text}]")
    if check.from_model:
        out.append(f"Rows not in the file (taken from the derived model, not compared): "
                   f"{', '.join(check.from_model)}")
    return "\n".join(out)


def row_status(check: ConventionCheck, row: str) -> str:
    """Status of one row's equation, in the equation checker's words
    (:func:`~ins_errors.checker.classify.set_status`): ``mistake``, ``agrees up to
    dropped small terms``, ``agrees up to declared drops`` or ``agrees``."""
    from ins_errors.checker.kinds import DROPPED, MISTAKE, SMALL_MISTAKE

    severities = {f.severity for f in check.report.findings if f.row == row}
    if severities & {MISTAKE, SMALL_MISTAKE}:
        return "mistake"
    if DROPPED in severities:
        return "agrees up to dropped small terms"
    return "agrees up to declared drops" if severities else "agrees"


def summary_counts(check: ConventionCheck) -> dict:
    """The ``summary`` of ``check --json`` for a ``@convention`` file: the keys of the
    equation checker's (:func:`~ins_errors.checker.report.summary_counts`).

    Each row is one equation (a vector line gives three); ``hand_only_definition``,
    ``tautology`` and ``input_error`` are 0 (definitions are substituted into the rows,
    not counted as equations, and a line that cannot be read stops the check before any
    report), as are ``knock_on_mistakes`` (a mistake in a definition is found in the
    entries of the rows, each a root mistake naming the definition by ``via``) and
    ``input_problems``.
    """
    from ins_errors.checker.kinds import DECLARED, DROPPED
    from ins_errors.checker.report import STATUSES, status_key

    by_status = dict.fromkeys(map(status_key, STATUSES), 0)
    for row in check.lines:
        by_status[status_key(row_status(check, row))] += 1
    findings = check.report.findings
    mistakes = len(check.report.mistakes)
    return {
        "equations_by_status": by_status,
        "findings": {
            "mistakes": mistakes, "root_mistakes": mistakes, "knock_on_mistakes": 0,
            "declared_drops": sum(1 for f in findings if f.severity == DECLARED),
            "dropped_small_terms": sum(1 for f in findings if f.severity == DROPPED),
            "undeclared_drops": 0,  # the rows have no named intermediates to vary
        },
        "input_problems": 0,
    }


def to_json(check: ConventionCheck) -> dict:
    """The matrix report's JSON (:func:`~ins_errors.checker.matrix_report.to_json`) with
    the ``summary`` of ``check --json`` (:func:`summary_counts`), ``lines`` (row -> line
    of the hand file), ``definitions`` (name -> line) and, in each finding, ``via``: the
    definitions its entry comes through, ``[{"name": ..., "line": ...}]`` (empty when
    none)."""
    from ins_errors.checker.matrix_report import to_json as matrix_json

    out = {"summary": summary_counts(check), **matrix_json(check.report)}
    for shown, f in zip(out["findings"], check.report.findings, strict=True):
        shown["via"] = [{"name": d.name, "line": d.line} for d in check.via_of(f)]
    from ins_errors.checker.definition_causes import causes

    out["causes"] = [{"definition": c.name, "line": c.line, "entries": list(c.entries),
                      "reached": c.reached, "slip": c.slip or None, "text": c.text}
                     for c in causes(check)]
    out["lines"] = {row: line for row, (line, _) in check.lines.items()}
    out["definitions"] = {d.name: d.line for d in check.definitions.values()}
    if check.notes:
        out["notes"] = list(check.notes)
    return out


_PLACE = re.compile(r"^(?:, line (\d+)(?:, column (\d+))?|: line (\d+)(?:, column (\d+))?)"
                    r": ")


def problem_place(message: str, names: tuple[str, ...]) -> tuple[int | None, int | None, str]:
    """(line, column, what is wrong) of a refusal of a ``@convention`` file, read from its
    one-line message (``FILE, line 4, column 56: unknown name ...``, ``FILE: line 2,
    column 37: ...``); ``None`` where the message names no line (a problem of the whole
    file) or no column. ``names``: how the message may name the file (as given, bare)."""
    for name in names:
        if message.startswith(name):
            rest = message[len(name):]
            match = _PLACE.match(rest)
            if match:
                line = match.group(1) or match.group(3)
                column = match.group(2) or match.group(4)
                return (int(line), int(column) if column else None, rest[match.end():])
            if rest.startswith(": "):
                return None, None, rest[2:]
    return None, None, message


def refused_json(model_name: str, convention_name: str | None, hand_name: str,
                 threshold: float, states: list[str], problem: tuple[int | None,
                                                                     int | None, str]
                 ) -> dict:
    """The ``check --json`` object of a ``@convention`` file that could not be checked:
    the keys of a checked one (:func:`to_json`) with nothing compared, ``exit_status`` 2,
    ``summary.input_problems`` 1 and the problem under ``problems`` (``line``,
    ``column``, ``message``: :func:`problem_place`).

    Parameters
    ----------
    model_name, convention_name, hand_name : str
        The model, the convention the file declares (None: none readable), the file.
    threshold : float
        The check's threshold.
    states : list of str
        The convention's states (empty when the convention is not known).
    problem : tuple
        (line or None, column or None, message).
    """
    from ins_errors.checker.matrix import MatrixReport

    report = MatrixReport(model_name, convention_name or "", hand_name, list(states), [],
                          threshold, [], {}, [], 0, [], [])
    out = to_json(ConventionCheck(report))
    out["exit_status"] = 2
    out["summary"]["input_problems"] = 1
    line, column, message = problem
    out["problems"] = [{"line": line, "column": column, "message": message}]
    return out
