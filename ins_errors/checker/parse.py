r"""Read a hand-written set of error equations (plain text or LaTeX) into SymPy.

Both formats hold one equation per line, ``lhs = rhs``; a printed chain ``lhs = A = B``
gives one equation with two forms (each is checked, the first is the definition), and
several equations may share a line (``;`` in text, ``\quad`` in LaTeX). Lines starting
with ``@`` are directives, in both formats:

``@section TITLE``
    start a new section; definitions of earlier sections stay visible, a section may
    redefine them (the manual's two listings define D and Δλ differently).
``@alt EQUATION``
    an alternative printed form of a quantity already defined in the section: checked,
    not used as the definition (plain repeated definitions are reported as duplicates).
``@alias NAME = EXPRESSION``
    the hand symbol NAME stands for EXPRESSION in the model's names.
``@source NAME = model_source[, model_source ...]``
    the hand error-source symbol NAME stands for those model error sources.
``@name NAME = model_name``
    the hand symbol NAME is another spelling of a model name (an error state such as
    ``delta_v_E``, a source, a parameter), from this line on.
``@neglect ITEM[, ITEM ...] [: REASON]``
    a declared simplification, in force from this line on: each ITEM is either a
    variation whose contributions the author drops (``Delta_R_xi``) or a term left out
    (``2*U*sin(phi)*delta_v_N``); findings it explains are classed "declared drop".
``@magnitude UNIT = QUANTITY``
    typical size of error quantities of that SI unit (``m/s = 0.5 m/s``), or
    ``attitude = 20 arcsec`` for the declared attitude error the others follow from.
``@scope MOTION``
    the derivation holds only on this motion class (``static base``): it is compared
    at those reference points only, so terms that vanish there are no findings.
``@realwork TITLE``
    start a section of *real-work* lines (instrument model and computer, not error
    equations): the accelerometer outputs ``a_x = ...`` and difference-scheme updates
    ``X_{k+1} = X_k + tau*(...)`` (text: ``X_k1``, ``X_k``). They are kept apart in
    :attr:`HandFile.real_work` and compared by :mod:`ins_errors.checker.realwork`; the
    next ``@section`` ends the real-work section.
``@convention NAME``
    the equations are written in a convention's states (``strapdown_ned``: ``phi``,
    ``psi``, ...): checked by :mod:`ins_errors.checker.convention_equations`.
``@markov SOURCE = QUANTITY``
    under ``@convention``: the bias state ``SOURCE`` (a model error source with its own
    line ``dot(SOURCE) = ...``, named as the model does or as the file spells it:
    ``b_gz``, in LaTeX ``b_{gz}``) is a first-order Gauss–Markov bias of correlation time
    QUANTITY (``1 h``); without it a bias state is a random constant.

Comments start with ``#`` (text) or ``%`` (LaTeX). Symbol spellings are documented in
``docs/hand_check.md``. The parser only reads and spells; what each symbol means in the
model is decided by :mod:`ins_errors.checker.compare`.

Plain text uses SymPy syntax (``**`` or ``^`` for powers, explicit ``*``) with ASCII names
such as ``Delta_V_xi``, ``dot(alpha_x)``, ``omega_rel_eta``. LaTeX is pre-processed into
plain placeholders (``\Delta\dot{V}_\xi``, ``\omega'_\eta``, ``u_{31}``,
``W_\xi^{nk}``, ``\operatorname{tg}``, ``\widetilde{W}``, implicit products). The
arithmetic left after that is parsed, by default, by this module's own small LALR grammar
(lark, backend ``"lalr"``, milliseconds per line); SymPy's ``parse_latex`` with its lark
backend (``"sympy"``, much slower) is kept as a cross-check, see :data:`LATEX_BACKENDS`.
"""

from __future__ import annotations

import ast
import math
import re
from dataclasses import dataclass, field
from functools import lru_cache, partial
from pathlib import Path
from typing import Literal

import sympy as sp
from sympy.parsing.sympy_parser import (
    convert_xor,
    parse_expr,
    standard_transformations,
)

from ins_errors.checker.notation import Notation
from ins_errors.errors import InsErrorsError

BOM = "\ufeff"
"""The byte-order mark some editors (Windows Notepad) put before a UTF-8 file's text:
dropped where a hand or mapping file's text is read."""
DOT = sp.Function("dot")
"""Time derivative of a hand quantity (only allowed on a left-hand side)."""
TILDE = sp.Function("tilde")
"""Computed ("tilde") value of a quantity: ``tilde(X) = X + Delta_X`` to first order."""


class HandParseError(InsErrorsError):
    """A hand file that cannot be read at all (missing, not UTF-8)."""


@dataclass(frozen=True)
class Problem:
    """One input problem, reported with its place in the file."""

    line: int
    column: int | None
    message: str

    def __str__(self) -> str:
        where = f"line {self.line}" + (f", column {self.column}" if self.column else "")
        return f"{where}: {self.message}"


@dataclass
class HandEquation:
    """One equation of a hand file.

    Attributes
    ----------
    line, column : int
        Where it starts (1-based).
    section : int
        Index into :attr:`HandFile.sections`.
    lhs : sympy.Expr
        A symbol (``Delta_omega_xi``, ``D``, ``v_E``) or ``dot(symbol)``.
    forms : list of sympy.Expr
        Right-hand sides of the printed chain ``lhs = forms[0] = forms[1] ...``.
    alternative : bool
        Marked ``@alt``: checked, never used as the definition.
    text : str
        The equation as written.
    note : str
        Trailing annotation (``\\text{...}`` in LaTeX).
    columns : dict
        Symbol name -> column of its first occurrence (for messages).
    declarations : tuple of int
        Indices into :attr:`HandFile.declarations` in force at this line.
    step : bool
        A real-work difference-scheme update (left-hand side at step k+1).
    """

    line: int
    column: int
    section: int
    lhs: sp.Expr
    forms: list[sp.Expr]
    alternative: bool = False
    text: str = ""
    note: str = ""
    columns: dict[str, int] = field(default_factory=dict)
    declarations: tuple[int, ...] = ()
    step: bool = False

    @property
    def label(self) -> str:
        """Readable left-hand side, e.g. ``dot(Delta_V_xi)``."""
        return str(self.lhs)


@dataclass(frozen=True)
class Declaration:
    """A declared simplification (``@neglect``) of a hand file.

    Attributes
    ----------
    line : int
    items : tuple of sympy.Expr
        Variations (``Delta_R_xi``) or terms the author leaves out.
    texts : tuple of str
        The items as written.
    reason : str
        The author's words after ``:`` (may be empty).
    """

    line: int
    items: tuple[sp.Expr, ...]
    texts: tuple[str, ...]
    reason: str = ""


@dataclass
class HandFile:
    """A parsed hand file: sections, equations, its own notation entries, problems.

    ``declarations``, ``magnitudes`` (SI unit or ``"attitude"`` -> quantity text),
    ``scope`` and ``markov`` (bias state -> correlation time text) come from the
    ``@neglect``, ``@magnitude``, ``@scope`` and ``@markov`` directives.
    """

    name: str
    format: Literal["text", "latex"]
    sections: list[str] = field(default_factory=lambda: ["main"])
    equations: list[HandEquation] = field(default_factory=list)
    notation: Notation = field(default_factory=Notation)
    problems: list[Problem] = field(default_factory=list)
    declarations: list[Declaration] = field(default_factory=list)
    magnitudes: dict[str, str] = field(default_factory=dict)
    scope: str | None = None
    real_work: list[HandEquation] = field(default_factory=list)
    convention: str | None = None
    markov: dict[str, str] = field(default_factory=dict)
    markov_lines: dict[str, int] = field(default_factory=dict)


class _LineError(Exception):
    """Internal: a problem on one line (converted to a :class:`Problem`)."""

    def __init__(self, column: int | None, message: str):
        message = " ".join(message.splitlines())  # reports are one line per problem
        super().__init__(message)
        self.column = column
        self.message = message


# --------------------------------------------------------------------------------------
# Names
# --------------------------------------------------------------------------------------
def canonical_name(name: str, notation: Notation) -> sp.Expr:
    """Canonical symbol for an ASCII spelling (``w_xi`` -> ``omega_xi``, ``X_dot``)."""
    if name.endswith("_dot") and len(name) > 4:
        return DOT(canonical_name(name[:-4], notation))
    if name in notation.spellings:
        return sp.Symbol(notation.spellings[name])
    if name in ("lambda", "varphi"):  # the LaTeX letters' ASCII names
        return canonical_name({"lambda": "lam", "varphi": "phi"}[name], notation)
    if name.startswith("Delta_") and len(name) > 6:
        inner = canonical_name(name[6:], notation)
        if isinstance(inner, sp.Symbol):
            full = "Delta_" + inner.name
            return sp.Symbol(notation.spellings.get(full, full))
        return inner
    return sp.Symbol(name)


# --------------------------------------------------------------------------------------
# Plain text
# --------------------------------------------------------------------------------------
_FUNCTIONS: dict[str, object] = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "tg": sp.tan, "cot": sp.cot, "ctg": sp.cot,
    "sqrt": sp.sqrt, "asin": sp.asin, "arcsin": sp.asin, "acos": sp.acos,
    "arccos": sp.acos, "atan": sp.atan, "arctan": sp.atan, "arctg": sp.atan,
    "atan2": sp.atan2, "exp": sp.exp, "log": sp.log, "ln": sp.log, "Abs": sp.Abs,
    "abs": sp.Abs, "sec": sp.sec, "Rational": sp.Rational, "dot": DOT, "tilde": TILDE,
}
_CONSTANTS = {"pi": sp.pi}
_TRANSFORMS = (*standard_transformations, convert_xor)

LARGEST_DECADE = 308
"""Numbers of a hand file are refused beyond 10**308 (the largest double is 1.8e308),
and powers of numbers beyond 10**±308, before SymPy computes them: ``10**(10**10)``
would keep it busy for hours computing an integer of ten billion digits."""

LARGEST_EXPONENT = 100
"""Largest exponent (in magnitude) of a power of a quantity: error equations have
squares, inverse square roots and the like; ``(psi + delta_V)**(10**10)`` would keep
SymPy busy."""


_LIMIT = f"numbers of a hand file are at most 1e{LARGEST_DECADE} in size"


class _TooLargeError(Exception):
    """Internal: a number or exponent beyond :data:`LARGEST_DECADE` or
    :data:`LARGEST_EXPONENT` (converted to a line problem)."""


def _power_decade(base: float | None, base_decade: float, exponent: float | None,
                  shown: object) -> float:
    """log10 |base ** exponent| of a power of two numbers, or :class:`_TooLargeError`.

    ``base`` and ``exponent`` are the values (None: beyond a double), ``base_decade`` is
    log10 |base|.
    """
    if exponent is None:
        raise _TooLargeError(f"the exponent of {shown} is too large to compute")
    if base is not None and abs(base) in (0.0, 1.0):
        return -math.inf if base == 0.0 and exponent > 0 else 0.0
    decade = exponent * base_decade
    if abs(decade) > LARGEST_DECADE:
        what = "large" if decade > 0 else "small"
        raise _TooLargeError(f"{shown} is about {_decade_text(decade)}, too {what} to "
                             f"compute ({_LIMIT})")
    return decade


class _Shown:
    """The source text of an AST node, made only when a message prints it."""

    def __init__(self, source: str, node: ast.AST):
        self.source, self.node = source, node

    def __str__(self) -> str:
        text = " ".join((ast.get_source_segment(self.source, self.node)
                         or ast.unparse(self.node)).split())
        return text if len(text) <= 40 else text[:37] + "..."

    def __format__(self, spec: str) -> str:
        return format(str(self), spec)


def _check_numbers(text: str, column: int) -> None:
    """Refuse, before SymPy evaluates them, numbers and powers of numbers too large to
    compute (:data:`LARGEST_DECADE`) and powers of quantities with huge exponents
    (:data:`LARGEST_EXPONENT`), naming the column of the offending part.

    The constant parts of the expression are sized bottom-up, by their decimal
    exponents, without computing them. ``^`` is read as ``**``, as SymPy reads it (with
    the precedence of a power, not Python's of ``^``).
    """
    source = text.replace("^", "**")
    try:
        tree = ast.parse(source, mode="eval")
    except (SyntaxError, RecursionError, MemoryError):  # told by the caller's parse
        return
    carets = [k for k, c in enumerate(text) if c == "^"]

    def place(node: ast.AST) -> int:
        """Column of ``node`` in ``text`` (each ``^`` is one character shorter)."""
        offset = node.col_offset
        return column + offset - sum(1 for k, c in enumerate(carets) if k + c < offset)

    # (value as a float or None when beyond a double, log10 of its magnitude)
    sizes: dict[int, tuple[float | None, float]] = {}

    def value(decade: float, number: float) -> float | None:
        return number if decade <= LARGEST_DECADE and math.isfinite(number) else None

    for node in reversed(list(ast.walk(tree))):  # breadth first, reversed: children first
        shown = _Shown(source, node)
        try:
            if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
                    and not isinstance(node.value, bool):
                number = node.value
                decade = math.log10(abs(number)) if number else -math.inf
                if decade > LARGEST_DECADE:
                    raise _TooLargeError(f"the number {shown} is too large ({_LIMIT})")
                sizes[id(node)] = (float(number), decade)
            elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)) \
                    and id(node.operand) in sizes:
                number, decade = sizes[id(node.operand)]
                sizes[id(node)] = (None if number is None else
                                   -number if isinstance(node.op, ast.USub) else number,
                                   decade)
            elif isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Pow, ast.BitXor)):
                if id(node.right) not in sizes:
                    continue
                exponent, _ = sizes[id(node.right)]
                if id(node.left) in sizes:
                    base, base_decade = sizes[id(node.left)]
                    decade = _power_decade(base, base_decade, exponent, shown)
                    number = (None if base is None or exponent is None
                              else _float_power(base, exponent))
                    sizes[id(node)] = (value(decade, number) if number is not None else None,
                                       decade)
                elif exponent is None or abs(exponent) > LARGEST_EXPONENT:
                    raise _TooLargeError(f"the exponent of {shown} is too large (at most "
                                         f"{LARGEST_EXPONENT} in an error equation)")
            elif isinstance(node, ast.BinOp) and id(node.left) in sizes \
                    and id(node.right) in sizes:
                (a, da), (b, db) = sizes[id(node.left)], sizes[id(node.right)]
                if isinstance(node.op, (ast.Add, ast.Sub)):
                    decade = max(da, db)
                    number = (None if a is None or b is None
                              else a + b if isinstance(node.op, ast.Add) else a - b)
                elif isinstance(node.op, ast.Mult):
                    decade = da + db if -math.inf not in (da, db) else -math.inf
                    number = None if a is None or b is None else a * b
                elif isinstance(node.op, ast.Div) and b != 0.0:
                    decade = da - db if da != -math.inf else -math.inf
                    number = None if a is None or b is None else a / b
                else:
                    continue
                if decade > LARGEST_DECADE:
                    raise _TooLargeError(f"{shown} is about {_decade_text(decade)}, too "
                                         f"large ({_LIMIT})")
                sizes[id(node)] = (None if number is None else value(decade, number), decade)
        except _TooLargeError as error:
            raise _LineError(place(node), str(error)) from None


def _number_decade(number: sp.Number) -> float:
    """log10 of the magnitude of a SymPy number, without making a float of it."""
    if number == 0:
        return -math.inf
    if isinstance(number, sp.Rational):
        return math.log10(abs(number.p)) - math.log10(number.q)
    return math.log10(abs(float(number))) if math.isfinite(float(number)) else math.inf


def _check_power(base: sp.Expr, exponent: sp.Expr) -> None:
    """Refuse a power of SymPy expressions that SymPy would take hours to compute (the
    LaTeX parser's; :func:`_check_numbers` sizes the plain text's)."""
    if not isinstance(exponent, sp.Number):
        return
    big = _number_decade(exponent) > LARGEST_DECADE
    shown = f"{sp.sstr(base):.20}^{sp.sstr(exponent):.20}"
    if isinstance(base, sp.Number):
        value = None if big else float(exponent)
        _power_decade(None if abs(base) not in (0, 1) else float(base), _number_decade(base),
                      value, shown)
    elif big or abs(float(exponent)) > LARGEST_EXPONENT:
        raise _TooLargeError(f"the exponent of {shown} is too large (at most "
                             f"{LARGEST_EXPONENT} in an error equation)")


def _decade_text(decade: float) -> str:
    """``1e+600``, or ``10^(1e+10)`` for a decade too long to write."""
    return f"1e{decade:+.0f}" if abs(decade) < 1e5 else f"10^({decade:.3g})"


def _float_power(base: float, exponent: float) -> float | None:
    """``base ** exponent`` as a float (None when not a real number)."""
    try:
        result = base ** exponent
    except (OverflowError, ZeroDivisionError):
        return None
    return result if isinstance(result, float | int) else None


_UNICODE_OPERATORS = str.maketrans({"\u2212": "-", "\u00d7": "*", "\u22c5": "*",
                                    "\u00b7": "*"})
"""Typeset operators a word processor or a PDF copy puts in a formula: the minus sign
U+2212, the multiplication signs × (U+00D7), ⋅ (U+22C5) and the middle dot · (U+00B7)."""


_TOO_LONG = ("this expression ({length} characters) is too long or too deeply nested "
             "to read (a few thousand terms or nested groups are too many)")


def parse_text_expression(text: str, notation: Notation, column: int = 1
                          ) -> tuple[sp.Expr, dict[str, int]]:
    """Parse one SymPy-syntax expression of a hand file.

    The result depends only on the text, the column and the notation's spellings, and
    is kept for the next parse of the same line (the same file checked again, or a copy
    of it with a few lines changed).

    Parameters
    ----------
    text : str
        The expression, e.g. ``-Delta_V_eta/R_eta + omega_dp``.
    notation : Notation
        Supplies the alternative spellings.
    column : int
        Column of ``text`` in its line (1-based), for messages.

    Returns
    -------
    expr : sympy.Expr
    columns : dict
        Canonical symbol name -> column of its first occurrence.
    """
    expr, columns = _parsed_text(text, column, tuple(notation.spellings.items()))
    return expr, dict(columns)


QUOTED = 60
"""Characters of a line an error message quotes at most: a window around the column (a
generated sum of thousands of terms is not echoed whole)."""


def _around(text: str, offset: int) -> str:
    """``text``, or the ``QUOTED`` characters around ``offset`` with ``…`` where cut."""
    if len(text) <= QUOTED:
        return text
    start = min(max(0, offset - QUOTED // 2), len(text) - QUOTED)
    end = start + QUOTED
    return f"{'…' * (start > 0)}{text[start:end]}{'…' * (end < len(text))}"


@lru_cache(maxsize=16384)
def _parsed_text(text: str, column: int, spellings: tuple[tuple[str, str], ...]
                 ) -> tuple[sp.Expr, dict[str, int]]:
    """:func:`parse_text_expression` for the given spellings (read-only result)."""
    notation = Notation(spellings=dict(spellings))
    source = re.sub(r"\blambda\b", "lam   ", text)  # same length: columns stay right
    source = source.translate(_UNICODE_OPERATORS)  # − × · ⋅ as - and *, one character each
    stripped = source.strip()
    shown = text.strip()
    lead = len(source) - len(source.lstrip())
    if not stripped:
        raise _LineError(column, "empty expression")
    try:
        tree = ast.parse(stripped, mode="eval")
    except SyntaxError as error:
        offset = (error.offset or 1) - 1
        raise _LineError(column + lead + offset,
                         f"cannot parse {_around(shown, offset)!r}: {error.msg}") from None
    except (RecursionError, MemoryError):  # a sum of thousands of terms, say
        raise _LineError(column + lead, _TOO_LONG.format(length=len(stripped))) from None
    _check_numbers(stripped, column + lead)
    local: dict[str, object] = {}
    columns: dict[str, int] = {}
    calls = {id(node.func) for node in ast.walk(tree) if isinstance(node, ast.Call)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute):
            raise _LineError(column + lead + node.col_offset,
                             f"attribute access {ast.unparse(node)!r} is not allowed")
        if not isinstance(node, ast.Name):
            continue
        where = column + lead + node.col_offset
        if id(node) in calls:
            if node.id not in _FUNCTIONS:
                raise _LineError(where, f"unknown function {node.id!r} (known: "
                                        f"{', '.join(sorted(_FUNCTIONS))})")
            local[node.id] = _FUNCTIONS[node.id]
            continue
        if node.id in _CONSTANTS:
            local[node.id] = _CONSTANTS[node.id]
            continue
        symbol = canonical_name(node.id, notation)
        local[node.id] = symbol
        for atom in symbol.atoms(sp.Symbol):
            columns.setdefault(atom.name, where)
    try:
        expr = parse_expr(stripped, local_dict=local, transformations=_TRANSFORMS)
    except (RecursionError, MemoryError):
        raise _LineError(column + lead, _TOO_LONG.format(length=len(stripped))) from None
    except Exception as error:  # SymPy raises many kinds here
        raise _LineError(column + lead,
                         f"cannot parse {_around(shown, 0)!r}: {error}") from None
    if not isinstance(expr, sp.Expr):
        raise _LineError(column + lead, f"{shown!r} is not an expression")
    return expr, columns


def _split_top(text: str, separator: str) -> list[tuple[str, int]]:
    """Split at ``separator`` outside brackets; returns (piece, offset) pairs."""
    pieces, depth, start = [], 0, 0
    i = 0
    while i < len(text):
        char = text[i]
        if char in "([{":
            depth += 1
        elif char in ")]}":
            depth -= 1
        elif depth == 0 and text.startswith(separator, i):
            before = text[i - 1] if i else ""
            if separator == "=" and (text[i + 1:i + 2] == "=" or (before and before in "<>!=")):
                i += 2
                continue
            pieces.append((text[start:i], start))
            start = i + len(separator)
            i = start
            continue
        i += 1
    pieces.append((text[start:], start))
    return pieces


# --------------------------------------------------------------------------------------
# LaTeX
# --------------------------------------------------------------------------------------
_GREEK = {
    "alpha": "alpha", "beta": "beta", "gamma": "gamma", "delta": "delta",
    "epsilon": "epsilon", "varepsilon": "epsilon", "zeta": "zeta", "eta": "eta",
    "theta": "theta", "vartheta": "theta", "iota": "iota", "kappa": "kappa",
    "lambda": "lam", "mu": "mu", "nu": "nu", "xi": "xi", "rho": "rho", "sigma": "sigma",
    "tau": "tau", "upsilon": "upsilon", "phi": "phi", "varphi": "phi", "chi": "chi",
    "psi": "psi", "omega": "omega", "Gamma": "Gamma", "Theta": "Theta",
    "Lambda": "Lambda", "Xi": "Xi", "Sigma": "Sigma", "Phi": "Phi", "Psi": "Psi",
    "Omega": "Omega", "nabla": "nabla",
}
_SYMPY_FUNCTIONS = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "tg": sp.tan, "cot": sp.cot, "ctg": sp.cot,
    "arcsin": sp.asin, "arccos": sp.acos, "arctan": sp.atan, "arctg": sp.atan,
    "exp": sp.exp, "ln": sp.log, "log": sp.log, "sec": sp.sec,
}
_ACCENTS = {"dot": "dot", "tilde": "tilde", "widetilde": "tilde"}
_FRACTIONS = ("frac", "dfrac", "tfrac", "cfrac")
"""Fraction commands: amsmath's display, text and continued forms read as ``\\frac``."""
_TOKEN = re.compile(r"\\[A-Za-z]+|\\.|[A-Za-z]|\d+(?:\.\d+)?|\s+|.")


def _placeholder(k: int) -> str:
    digits = str(k)
    return "Q_{" + "".join("abcdefghij"[int(c)] for c in digits) + "}"


@dataclass
class _Piece:
    text: str
    position: int
    starts: bool = False
    ends: bool = False


class _LatexConverter:
    """Turn one LaTeX side of an equation into parse_latex-ready text with placeholders."""

    def __init__(self, text: str, column: int, notation: Notation, backend: str = "lalr"):
        self.backend = backend
        self.column = column
        self.notation = notation
        text = text.translate(_UNICODE_OPERATORS)  # a typeset − or × as - and *
        self.tokens = [(m.group(), m.start()) for m in _TOKEN.finditer(text)
                       if not m.group().isspace()]
        self.i = 0
        self.symbols: dict[str, sp.Expr] = {}
        self.columns: dict[str, int] = {}

    # -- token helpers ---------------------------------------------------------------
    def peek(self, ahead: int = 0) -> str | None:
        j = self.i + ahead
        return self.tokens[j][0] if j < len(self.tokens) else None

    def position(self) -> int:
        if self.i < len(self.tokens):
            return self.column + self.tokens[self.i][1]
        return self.column + (self.tokens[-1][1] + 1 if self.tokens else 0)

    def take(self) -> str:
        token = self.tokens[self.i][0]
        self.i += 1
        return token

    def expect(self, token: str) -> None:
        if self.peek() != token:
            found = self.peek()
            raise _LineError(self.position(), f"expected {token!r}, found "
                                              f"{found if found else 'end of line'!r}")
        self.i += 1

    def skip_sizing(self) -> None:
        while self.peek() in (r"\left", r"\right", r"\big", r"\Big", r"\bigl", r"\bigr",
                              r"\Bigl", r"\Bigr", r"\bigg", r"\Bigg"):
            self.i += 1

    # -- symbols -----------------------------------------------------------------------
    def group_text(self) -> str:
        """ASCII text of a subscript: one token or a braced group of letters/digits."""
        token = self.peek()
        if token is None:
            raise _LineError(self.position(), "subscript missing")
        if token != "{":
            self.i += 1
            return _GREEK.get(token[1:]) if token.startswith("\\") else token
        self.i += 1
        parts = []
        while self.peek() not in ("}", None):
            token = self.take()
            if token.startswith("\\"):
                if token[1:] not in _GREEK:
                    raise _LineError(self.column + self.tokens[self.i - 1][1],
                                     f"unsupported command {token} in a subscript")
                parts.append(_GREEK[token[1:]])
            elif token in (",", "'"):
                continue
            else:
                parts.append(token)
        self.expect("}")
        return "".join(parts)

    def symbol(self, delta: bool, start: int | None = None) -> sp.Expr:
        """Read one symbol (with accent, primes, subscript, label) and return it.

        ``start`` is the column reported for it (that of a preceding ``\\Delta``).
        """
        start = self.position() if start is None else start
        accents = []
        token = self.peek()
        while token is not None and token.startswith("\\") and token[1:] in _ACCENTS:
            accents.append(_ACCENTS[token[1:]])
            self.i += 1
            argument = self.peek()
            if argument is not None and argument != "{" and (
                    (len(argument) == 1 and argument.isalpha())
                    or (argument.startswith("\\") and argument[1:] in _GREEK)):
                # TeX's one-token argument: \dot b_{gx} is \dot{b}_{gx}
                self.i += 1
                base = _GREEK[argument[1:]] if argument.startswith("\\") else argument
                return self.finish(sp.Symbol(base), accents, delta, start)
            self.expect("{")
            # \dot{\delta v}_N, as the generated equations print a variation's rate
            inner_delta = self.peek() in (r"\delta", r"\Delta") and self.peek(1) is not None \
                and (self.peek(1).isalpha() or self.peek(1)[1:] in _GREEK)
            if inner_delta:
                self.i += 1
            before = set(self.columns)
            inner = self.symbol(delta=inner_delta)
            self.expect("}")
            result = self.finish(inner, accents, delta, start)
            written = {atom.name for atom in result.atoms(sp.Symbol)}
            for name in set(self.columns) - before - written:  # \dot{\phi}_E: no phi
                del self.columns[name]
            return result
        if token is None:
            raise _LineError(start, "a symbol is missing")
        if token.startswith("\\"):
            name = token[1:]
            if name not in _GREEK:
                raise _LineError(start, f"expected a symbol, found {token}")
            base = _GREEK[name]
        elif token.isalpha():
            base = token
        else:
            raise _LineError(start, f"expected a symbol, found {token!r}")
        self.i += 1
        return self.finish(sp.Symbol(base), [], delta, start)

    def finish(self, inner: sp.Expr, accents: list[str], delta: bool, start: int) -> sp.Expr:
        """Primes, subscripts and labels after a (possibly accented) base."""
        base = inner.name if isinstance(inner, sp.Symbol) else None
        primes, sub = 0, ""
        while True:
            token = self.peek()
            if token == "'":
                primes += 1
                self.i += 1
            elif token == "_":
                self.i += 1
                text = self.group_text()
                if text is None:
                    raise _LineError(self.position(), "unsupported subscript")
                sub += text
            elif token == "^" and self.peek(1) == "{" and self.label_ahead():
                self.i += 2
                while self.take() != "}":
                    pass
            elif token == "^" and self.peek(1) == r"\prime":
                primes += 1
                self.i += 2
            elif token == "^" and self.peek(1) == "{" and self.peek(2) == r"\prime":
                primes += 1
                self.i += 3
                self.expect("}")
            else:
                break
        if base is None:  # accent applied to a full symbol: keep it
            name = inner.name if isinstance(inner, sp.Symbol) else str(inner)
        else:
            name = base
        if primes:
            name = self.notation.latex_primes.get(name, name + "p")
        if sub:
            joined = name + sub if len(name) == 1 and sub.isdigit() else f"{name}_{sub}"
            name = joined
        if delta:
            name = "Delta_" + name
            # Δ of a computed value (\Delta\tilde{f}, as the generated equations print a
            # real-work intermediate) is the variation of that quantity: Δf
            accents = [a for a in accents if a != "tilde"]
        result: sp.Expr = canonical_name(name, self.notation)
        for accent in accents:
            result = DOT(result) if accent == "dot" else TILDE(result)
        if isinstance(result, sp.Symbol):
            self.columns.setdefault(result.name, start)
        else:
            for atom in result.atoms(sp.Symbol):
                self.columns.setdefault(atom.name, start)
        return result

    def label_ahead(self) -> bool:
        """``^{nk}``-style label: two or more letters in braces (not a power)."""
        j = self.i + 2
        letters = []
        while j < len(self.tokens) and self.tokens[j][0] != "}":
            letters.append(self.tokens[j][0])
            j += 1
        return len(letters) >= 2 and all(t.isalpha() and len(t) == 1 for t in letters)

    # -- expressions -------------------------------------------------------------------
    def place(self, expr: sp.Expr, position: int) -> _Piece:
        key = _placeholder(len(self.symbols))
        self.symbols[key] = expr
        return _Piece(key, position, starts=True, ends=True)

    def convert(self, closing: str | None = None) -> list[_Piece]:
        """Convert tokens up to ``closing`` (not consumed) or the end."""
        out: list[_Piece] = []
        while self.peek() is not None and self.peek() != closing:
            position = self.position()
            token = self.peek()
            name = token[1:] if token.startswith("\\") else None
            if name in ("left", "right", "big", "Big", "bigl", "bigr", "Bigl", "Bigr",
                        "bigg", "Bigg"):
                self.i += 1
                if self.peek() == ".":
                    self.i += 1
                continue
            if token in (r"\,", r"\;", r"\!", r"\:", r"\ ", "~", "&") or name in (
                    "displaystyle", "limits"):
                self.i += 1
                continue
            if token in (r"\cdot", r"\times", "*"):
                self.i += 1
                out.append(_Piece(r" \cdot ", position))
                continue
            if token in ("(", "[", "{"):
                end = {"(": ")", "[": "]", "{": "}"}[token]
                self.i += 1
                inner = self.convert(end)
                self.skip_sizing()
                self.expect(end)
                out.append(self.place(self.parse_pieces(inner, position), position))
                continue
            if token in (")", "]", "}"):
                raise _LineError(position, f"unbalanced {token!r}")
            if token in ("+", "-", "/"):
                self.i += 1
                out.append(_Piece(f" {token} ", position))
                continue
            if token == "^":
                self.i += 1
                out.append(_Piece("^{", position))
                out.extend(self.argument())
                out.append(_Piece("}", position, ends=True))
                continue
            if token[0].isdigit():
                self.i += 1
                out.append(_Piece(token, position, starts=True, ends=True))
                continue
            if name in _FRACTIONS:
                self.i += 1
                numerator = self.fraction_argument(token, position)
                denominator = self.fraction_argument(token, position)
                out.append(self.place(numerator / denominator, position))
                continue
            if name == "sqrt":
                self.i += 1
                out.append(self.place(sp.sqrt(self.braced(position)), position))
                continue
            if name == "pi":
                self.i += 1
                out.append(self.place(sp.pi, position))
                continue
            if name == "operatorname":
                self.i += 1
                self.expect("{")
                word = ""
                while self.peek() not in ("}", None):
                    word += self.take()
                self.expect("}")
                if word not in _SYMPY_FUNCTIONS:
                    raise _LineError(position, f"unsupported function \\operatorname{{{word}}}")
                out.extend(self.function(word, position))
                continue
            if name in _SYMPY_FUNCTIONS:
                self.i += 1
                out.extend(self.function(name, position))
                continue
            if name in ("Delta", "delta") and self.peek(1) is not None and (
                    self.peek(1).isalpha() or self.peek(1)[1:] in _GREEK
                    or self.peek(1)[1:] in _ACCENTS):
                self.i += 1
                out.append(self.place(self.symbol(delta=True, start=position), position))
                continue
            if name in ("mathrm", "mathit") and self.peek(1) == "{" and self.peek(3) == "}" \
                    and len(self.peek(2) or "") == 1 and self.peek(2).isalpha():
                self.i += 2  # \mathrm{d}: an upright letter is the letter
                out.append(self.place(self.symbol(delta=False), position))
                self.expect("}")
                continue
            if name is not None and name not in _GREEK and name not in _ACCENTS:
                raise _LineError(position, f"unsupported LaTeX command {token}")
            if name is None and not token.isalpha():
                raise _LineError(position, f"unexpected character {token!r}")
            out.append(self.place(self.symbol(delta=False), position))
        return out

    def fraction_argument(self, command: str, position: int) -> sp.Expr:
        """One argument of ``\\frac`` (``\\dfrac``, ``\\tfrac``): a braced group or, as
        in TeX, a single token: one digit (``\\frac12`` is 1/2), one letter or one Greek
        letter (``\\frac1{R + h}``, ``\\frac\\pi2``)."""
        token = self.peek()
        if token == "{":
            return self.braced(position)
        spot = self.position()
        if token is None:
            raise _LineError(spot, f"{command} needs two arguments, e.g. "
                                   f"{command}{{a}}{{b}} or {command}12")
        if token[0].isdigit():
            text, offset = self.tokens[self.i]
            if len(text) > 1:  # \frac12: the digits 1 and 2 are two arguments
                self.tokens[self.i] = (text[1:], offset + 1)
            else:
                self.i += 1
            return sp.Integer(int(text[0]))
        if token == r"\pi":
            self.i += 1
            return sp.pi
        if (len(token) == 1 and token.isalpha()) or token[1:] in _GREEK:
            self.i += 1
            base = token if len(token) == 1 else _GREEK[token[1:]]
            symbol = canonical_name(base, self.notation)
            for atom in symbol.atoms(sp.Symbol):
                self.columns.setdefault(atom.name, spot)
            return symbol
        raise _LineError(spot, f"{command}: expected an argument in braces or a single "
                               f"digit or letter, found '{token}'")

    def braced(self, position: int) -> sp.Expr:
        """Parse a mandatory ``{...}`` argument (of \\frac, \\sqrt)."""
        self.expect("{")
        inner = self.convert("}")
        self.expect("}")
        return self.parse_pieces(inner, position)

    def parse_pieces(self, pieces: list[_Piece], position: int) -> sp.Expr:
        """Parse converted pieces (sums, products, powers of placeholders and numbers).

        Groups, fractions and function arguments are parsed on their own and enter the
        enclosing expression as placeholders, so each call sees a short string.
        """
        if not pieces:
            raise _LineError(position, "empty expression")
        if len(pieces) == 1 and pieces[0].text in self.symbols:
            return self.symbols[pieces[0].text]
        converted, where = _join(pieces)
        try:
            parsed = _parse_arithmetic(converted, self.backend)
        except ImportError as error:  # pragma: no cover - lark is a declared dependency
            raise HandParseError(f"LaTeX input needs the 'lark' package: {error}") from None
        except (RecursionError, MemoryError):
            raise _LineError(position, _TOO_LONG.format(length=len(converted))) from None
        except Exception as error:
            too_large = getattr(error, "orig_exc", error)  # lark wraps a callback's error
            if isinstance(too_large, _TooLargeError):
                raise _LineError(position, str(too_large)) from None
            offset = max(getattr(error, "column", 1) - 1, 0)
            original = pieces[0].position
            for start, spot in where:
                if start <= offset:
                    original = spot
            raise _LineError(original, "cannot parse this LaTeX") from None
        if not isinstance(parsed, sp.Expr):
            raise _LineError(position, "not an expression")
        mapping = {sp.Symbol(k): v for k, v in self.symbols.items()}
        stray = [s for s in parsed.free_symbols if s not in mapping]
        if stray:
            raise _LineError(position, f"could not read symbol {stray[0]}")
        try:  # a group put into a power, 10^{10^{10}}, is computed by the substitution
            for power in parsed.atoms(sp.Pow):
                _check_power(power.base.xreplace(mapping), power.exp.xreplace(mapping))
        except _TooLargeError as error:
            raise _LineError(position, str(error)) from None
        return parsed.xreplace(mapping)

    def argument(self) -> list[_Piece]:
        """A superscript or function argument: braced group or one token/symbol."""
        if self.peek() == "{":
            position = self.position()
            return [self.place(self.braced(position), position)]
        token = self.peek()
        position = self.position()
        if token is None:
            raise _LineError(position, "argument missing")
        if token[0].isdigit():
            self.i += 1
            return [_Piece(token, position, starts=True, ends=True)]
        if token == "-":
            self.i += 1
            return [_Piece("-", position), *self.argument()]
        return [self.place(self.symbol(delta=False), position)]

    def function(self, name: str, position: int) -> list[_Piece]:
        """``\\cos 2\\lambda``, ``\\sin^2 \\varphi``, ``\\cos(\\chi)`` -> explicit form."""
        power: list[_Piece] = []
        if self.peek() == "^":
            self.i += 1
            power = self.argument()
        self.skip_sizing()
        if self.peek() in ("(", "[", "{"):
            closing = {"(": ")", "[": "]", "{": "}"}[self.peek()]
            self.i += 1
            inner = self.convert(closing)
            self.skip_sizing()
            self.expect(closing)
        else:  # simple argument: optional number and one symbol, e.g. 2\chi
            inner = []
            if self.peek() is not None and self.peek()[0].isdigit():
                inner.append(_Piece(self.take(), self.position(), starts=True, ends=True))
            delta = self.peek() == r"\Delta"
            if delta:
                self.i += 1
            spot = self.position()
            inner.append(self.place(self.symbol(delta=delta), spot))
        value = _SYMPY_FUNCTIONS[name](self.parse_pieces(inner, position))
        pieces = [self.place(value, position)]
        if power:
            pieces += [_Piece("^{", position), *power, _Piece("}", position, ends=True)]
        return pieces


def _join(pieces: list[_Piece]) -> tuple[str, list[tuple[int, int]]]:
    """Concatenate pieces, inserting ``\\cdot`` for implicit products."""
    text, where = "", []
    previous: _Piece | None = None
    for piece in pieces:
        if previous is not None and previous.ends and piece.starts:
            text += r" \cdot "
        where.append((len(text), piece.position))
        text += piece.text
        previous = piece
    return text, where


_ARITHMETIC_GRAMMAR = r"""
?sum: product | sum "+" product -> add | sum "-" product -> sub
?product: unary | product "\\cdot" unary -> mul | product "/" unary -> div
?unary: power | "-" unary -> neg | "+" unary
?power: atom | atom "^{" sum "}" -> pow
?atom: NUMBER -> number | NAME -> name | "\\pi" -> pi | "(" sum ")"
NAME: /Q_\{[a-j]+\}/
NUMBER: /\d+(\.\d+)?/
%ignore /\s+/
"""


@lru_cache(maxsize=1)
def _arithmetic_parser():
    import lark

    class Build(lark.Transformer):
        def add(self, items):
            return items[0] + items[1]

        def sub(self, items):
            return items[0] - items[1]

        def mul(self, items):
            return items[0] * items[1]

        def div(self, items):
            return items[0] / items[1]

        def neg(self, items):
            return -items[0]

        def pow(self, items):
            _check_power(items[0], items[1])
            return items[0] ** items[1]

        def number(self, items):
            return sp.Rational(str(items[0]))

        def name(self, items):
            return sp.Symbol(str(items[0]))

        def pi(self, items):
            return sp.pi

    return lark.Lark(_ARITHMETIC_GRAMMAR, start="sum", parser="lalr", transformer=Build())


def _parse_arithmetic(text: str, backend: str) -> sp.Expr:
    """Parse placeholder arithmetic with lark (LALR), or SymPy's ``parse_latex``."""
    if backend == "sympy":
        from sympy.parsing.latex import parse_latex

        return parse_latex(text, backend="lark")
    return _arithmetic_parser().parse(text)


LATEX_BACKENDS = ("lalr", "sympy")
"""``"lalr"``: the pre-processed arithmetic is parsed by a small LALR grammar (lark),
milliseconds per line; ``"sympy"``: by SymPy's ``parse_latex(..., backend="lark")``
(Earley, about 0.1-0.5 s per call), kept as an independent cross-check."""


def parse_latex_expression(text: str, notation: Notation, column: int = 1,
                           backend: str = "lalr") -> tuple[sp.Expr, dict[str, int]]:
    """Parse one LaTeX expression of a hand file (see module docstring for notation).

    Parameters
    ----------
    text : str
        One side of an equation, e.g. ``a_\\eta \\alpha_z - \\frac{\\Delta V_\\eta}{R_\\eta}``.
    notation : Notation
        Spellings and the meaning of primes.
    column : int
        Column of ``text`` in its line (1-based), for messages.
    backend : {"lalr", "sympy"}
        Parser of the pre-processed arithmetic (see :data:`LATEX_BACKENDS`).
    """
    if backend not in LATEX_BACKENDS:
        raise InsErrorsError(f"unknown LaTeX backend {backend!r} (known: "
                             f"{', '.join(LATEX_BACKENDS)})")
    expr, columns = _parsed_latex(text, column, backend, tuple(notation.spellings.items()),
                                  tuple(notation.latex_primes.items()))
    return expr, dict(columns)


@lru_cache(maxsize=16384)
def _parsed_latex(text: str, column: int, backend: str,
                  spellings: tuple[tuple[str, str], ...],
                  primes: tuple[tuple[str, str], ...]) -> tuple[sp.Expr, dict[str, int]]:
    """:func:`parse_latex_expression` for the given spellings and primes, kept for the
    next parse of the same line (read-only result)."""
    notation = Notation(spellings=dict(spellings), latex_primes=dict(primes))
    converter = _LatexConverter(text, column, notation, backend)
    pieces = converter.convert()
    if converter.peek() is not None:
        raise _LineError(converter.position(), f"unbalanced {converter.peek()!r}")
    return converter.parse_pieces(pieces, column), converter.columns


# --------------------------------------------------------------------------------------
# Files
# --------------------------------------------------------------------------------------
def _strip_comment(line: str, marker: str) -> str:
    if marker == "%":
        match = re.search(r"(?<!\\)%", line)
        return line[: match.start()] if match else line
    return line.split("#", 1)[0]


_LATEX_WRAPPERS = re.compile(r"\$\$|\\\[|\\\]|\$|\\begin\{[a-z*]+\}|\\end\{[a-z*]+\}|\\\\")
_TEXT_NOTE = re.compile(r"\\(?:text|mbox|mathrm(?!\{\s*[A-Za-z]\s*\}))\{([^}]*)\}")
"""A note in words (``\\text{for orthodromic orientation}``); an upright letter
(``\\mathrm{d}`` of a derivative) is mathematics, not a note."""
_D = r"(?:\\mathrm\s*\{\s*d\s*\}|\\operatorname\s*\{\s*d\s*\}|d)"
_TIME_DERIVATIVE = re.compile(
    r"^(\s*\\[dt]?frac\s*\{\s*" + _D + r"(?:\s|\\[,;:!])*)((?:[^{}]|\{[^{}]*\})+?)(\s*\}\s*\{\s*"
    + _D + r"\s*t\s*\}\s*)$")
_TIME_DERIVATIVE_OF = re.compile(
    r"^(\s*\\[dt]?frac\s*\{\s*" + _D + r"\s*\}\s*\{\s*" + _D
    + r"\s*t\s*\}(?:\s|\\[,;:!])*)(\S.*?)(\s*)$")


_DOT_OPEN = r"\dot{"


def _time_derivative(text: str) -> str:
    r"""A left side written as a derivative, ``\frac{\mathrm{d}\,\delta\varphi}{\mathrm{d}t}``
    (or ``\frac{d\,X}{dt}``, ``\frac{d}{dt} X``), as ``\dot{X}`` with X at its own
    column; any other text unchanged."""
    for pattern in (_TIME_DERIVATIVE, _TIME_DERIVATIVE_OF):
        match = pattern.match(text)
        if match and len(match.group(1)) >= len(_DOT_OPEN):
            lead, inner, tail = match.groups()
            indent = len(lead) - len(lead.lstrip())  # \dot at \frac, X where it is
            return (" " * indent + _DOT_OPEN + " " * (len(lead) - indent - len(_DOT_OPEN))
                    + inner + "}" + " " * max(len(tail) - 1, 0))
    return text


def _blank(text: str, pattern: re.Pattern) -> str:
    """Replace matches by spaces (columns stay right)."""
    return pattern.sub(lambda m: " " * len(m.group()), text)


_EQUATION_LABELS = re.compile(r"\\tag\*?\s*\{[^{}]*\}|\\label\s*\{[^{}]*\}"
                              r"|\\(?:nonumber|notag)(?![A-Za-z])")
"""amsmath's equation numbering, ``\\tag{2}``, ``\\tag*{A}``, ``\\label{eq:dh}``,
``\\nonumber``, ``\\notag``: not part of the equation, ignored."""
_EQUATION_NUMBER = re.compile(r"\(\s*([A-Za-z]?\d+(?:[.\-]\d+)*[a-z]?)\s*\)[\s,;.]*$")
"""A parenthesised number ending a line: ``(2)``, ``(3.14)``, ``(2a)``, ``(A.1)``."""
_LATEX_SPACING = re.compile(r"(?:\s|\\[,;:! ]|\\q?quad(?![A-Za-z])|~|&)+$")
_TEXT_SPACING = re.compile(r"\s+$")
_LATEX_OPERAND_BEFORE = re.compile(
    r"(?:[-+*/^=(\[{]|\\cdot|\\times|\\left|\\(?:" + "|".join(_SYMPY_FUNCTIONS)
    + r")|\\operatorname\s*\{[^{}]*\})$")
"""What makes a parenthesised number after it arithmetic, not an equation number: an
operator, an opening bracket, or a function whose argument it is (``\\cos (2)``)."""
_TEXT_OPERAND_BEFORE = re.compile(r"(?:[-+*/^=(\[,]|\b(?:" + "|".join(_FUNCTIONS) + r"))$")


def _refuse_equation_number(body: str, latex: bool) -> None:
    """Refuse a parenthesised number that ends the line after spacing (``\\qquad (2)``,
    `` (2)``): an equation number, which read as arithmetic would multiply the last term
    (``\\nabla (2)`` is 2∇). After an operator or a function name (``\\cos (2)``), or
    without spacing (``x(2)``), it is arithmetic and left alone."""
    match = _EQUATION_NUMBER.search(body)
    if match is None:
        return
    before = body[:match.start()]
    spacing = (_LATEX_SPACING if latex else _TEXT_SPACING).search(before)
    if before.strip() and spacing is None:
        return
    previous = (before[:spacing.start()] if spacing else before).rstrip()
    if previous and (_LATEX_OPERAND_BEFORE if latex else _TEXT_OPERAND_BEFORE).search(
            previous):
        return
    number = match.group(1)
    written = f"({number})"
    if latex:
        how = (f"write it \\tag{{{number}}} (ignored) or leave it out; a factor is "
               f"written in front: {number} \\cdot ...")
    else:
        how = (f"put it in a comment (# {written}) or leave it out; a factor is written in "
               f"front: {number}*...")
    raise _LineError(match.start() + 1, f"{written} at the end of the line looks like an "
                     f"equation number, not a factor: {how}")


def _segments(body: str, latex: bool) -> list[tuple[str, int, str]]:
    """Equations of one line: (text, offset, note)."""
    if not latex:
        _refuse_equation_number(body, latex)
        return [(piece, offset, "") for piece, offset in _split_top(body, ";")
                if piece.strip()]
    notes = " ".join(m.group(1).strip() for m in _TEXT_NOTE.finditer(body))
    body = _blank(body, _TEXT_NOTE)
    body = _blank(body, _LATEX_WRAPPERS)
    body = _blank(body, _EQUATION_LABELS)
    _refuse_equation_number(body, latex)
    result = []
    for piece, offset in _split_quads(body):
        trimmed = piece.rstrip().rstrip(",;.").rstrip()
        if trimmed.strip():
            result.append((trimmed, offset, notes))
    return result


def _split_quads(body: str) -> list[tuple[str, int]]:
    pieces, depth, start, i = [], 0, 0, 0
    while i < len(body):
        if body[i] == "{":
            depth += 1
        elif body[i] == "}":
            depth -= 1
        elif depth == 0 and (m := re.match(r"\\q?quad(?![A-Za-z])", body[i:])):
            pieces.append((body[start:i], start))
            start = i + len(m.group())
            i = start
            continue
        i += 1
    pieces.append((body[start:], start))
    return pieces


def _split_chain(text: str, latex: bool) -> list[tuple[str, int]]:
    if latex:
        pieces, depth, start = [], 0, 0
        for i, char in enumerate(text):
            if char == "{":
                depth += 1
            elif char == "}":
                depth -= 1
            elif char == "=" and depth == 0:
                pieces.append((text[start:i], start))
                start = i + 1
        pieces.append((text[start:], start))
        return pieces
    return _split_top(text, "=")


def parse_hand_text(text: str, notation: Notation, name: str = "<hand>",
                    latex: bool = False, latex_backend: str = "lalr") -> HandFile:
    """Parse the content of a hand file.

    Parameters
    ----------
    text : str
        File content.
    notation : Notation
        Spellings and LaTeX primes to apply (the model's default notation).
    name : str
        File name used in messages and reports.
    latex : bool
        LaTeX equations instead of SymPy syntax.
    latex_backend : {"lalr", "sympy"}
        Parser of LaTeX arithmetic (see :data:`LATEX_BACKENDS`).

    Returns
    -------
    HandFile
        Every line that could be read; unreadable lines are listed in ``problems``.
    """
    hand = HandFile(name=name, format="latex" if latex else "text")
    notation = notation.merged(Notation())  # a copy: @name lines add spellings
    text = text.removeprefix(BOM)  # Windows Notepad's UTF-8 signature, not text
    parse = (partial(parse_latex_expression, backend=latex_backend) if latex
             else parse_text_expression)
    real = False
    for number, raw in enumerate(text.splitlines(), start=1):
        body = _strip_comment(raw, "%" if latex else "#")
        stripped = body.strip()
        if not stripped:
            continue
        alternative = False
        try:
            if stripped.startswith("@"):
                keyword = stripped.split(maxsplit=1)[0]
                if keyword in ("@section", "@realwork"):
                    title = stripped[len(keyword):].strip() or f"section {len(hand.sections)}"
                    hand.sections.append(title)
                    real = keyword == "@realwork"
                    continue
                if keyword in ("@alias", "@source", "@name", "@magnitude", "@markov"):
                    _directive(hand, keyword, stripped, body.index("@") + 1, notation,
                               number)
                    continue
                if keyword == "@neglect":
                    _declaration(hand, number, stripped, body.index("@") + 1, notation)
                    continue
                if keyword == "@scope":
                    scope = " ".join(stripped[len(keyword):].split())
                    if scope not in _SCOPES:
                        raise _LineError(body.index("@") + 1, f"@scope: unknown motion "
                                         f"class {scope!r} (known: {', '.join(_SCOPES)})")
                    hand.scope = scope
                    continue
                if keyword == "@convention":
                    name = stripped[len(keyword):].strip()
                    if not name.isidentifier():
                        raise _LineError(body.index("@") + 1, "@convention needs a "
                                         "convention name (e.g. '@convention phi')")
                    hand.convention = name
                    continue
                if keyword != "@alt":
                    raise _LineError(body.index("@") + 1, f"unknown directive {keyword!r} "
                                     "(known: @section, @realwork, @alt, @alias, @source, "
                                     "@name, @neglect, @magnitude, @scope, @convention, "
                                     "@markov)")
                alternative = True
                cut = body.index("@alt") + 4
                body = " " * cut + body[cut:]
            for segment, offset, note in _segments(body, latex):
                if real:
                    _real_work_equation(hand, number, segment, offset + 1, parse, notation,
                                        latex)
                    continue
                _equation(hand, number, segment, offset + 1, note, alternative, parse,
                          notation, latex)
        except _LineError as error:
            hand.problems.append(Problem(number, error.column, error.message))
        except (RecursionError, MemoryError):  # nested too deeply for the converter
            hand.problems.append(Problem(number, None, _TOO_LONG.format(
                length=len(stripped)).replace("this expression", "this line")))
    if len(hand.sections) > 1 and not any(e.section == 0 for e in hand.equations):
        hand.sections[0] = "(before the first section)"
    return hand


def _equation(hand: HandFile, number: int, segment: str, column: int, note: str,
              alternative: bool, parse, notation: Notation, latex: bool) -> None:
    parts = _split_chain(segment, latex)
    if len(parts) < 2:
        raise _LineError(column + len(segment) - len(segment.lstrip()),
                         f"no '=' in {segment.strip()!r}: expected 'lhs = rhs'")
    written = parts[0][0]
    if latex:  # d/dt on the left is the time derivative, as \dot
        parts[0] = (_time_derivative(written), parts[0][1])
    columns: dict[str, int] = {}
    exprs = []
    for piece, offset in parts:
        expr, where = parse(piece, notation, column + offset)
        exprs.append(expr)
        for key, value in where.items():
            columns.setdefault(key, value)
    lhs = exprs[0]
    ok = isinstance(lhs, sp.Symbol) or (
        isinstance(lhs, sp.Function) and lhs.func == DOT and isinstance(lhs.args[0], sp.Symbol))
    if not ok:
        raise _LineError(column + len(segment) - len(segment.lstrip()),
                         f"left-hand side '{' '.join(written.split())}' must be one "
                         "quantity "
                         "(a symbol, a variation or the time derivative of one)")
    if isinstance(lhs, sp.Function) and lhs.args[0].name in notation.true_states:
        raise _LineError(column + len(segment) - len(segment.lstrip()),
                         _true_rate_message(written, lhs.args[0].name,
                                            notation.true_states[lhs.args[0].name], latex))
    hand.equations.append(HandEquation(
        line=number, column=column + len(segment) - len(segment.lstrip()),
        section=len(hand.sections) - 1, lhs=lhs, forms=exprs[1:], alternative=alternative,
        text=" ".join(segment.split()), note=note, columns=columns,
        declarations=tuple(range(len(hand.declarations)))))


def _true_rate_message(written: str, name: str, state, latex: bool) -> str:
    r"""The refusal of ``dot(V)`` where ``V`` is a true state of the model: an error
    equation's left side is the rate of the error (``\Delta\dot{V}``, ``dot(Delta_V)``).

    ``state`` is the :class:`~ins_errors.checker.notation.TrueState` of ``name``."""
    if latex:
        base, underscore, index = state.latex.partition("_")
        forms = (f"\\Delta\\dot{{{base}}}{underscore}{index}",
                 f"\\dot{{{state.error_latex}}}")
    else:
        forms = (f"dot(Delta_{name})", f"dot({state.error})")
    return (f"left-hand side '{' '.join(written.split())}' is the rate of the true state "
            f"{name}, but an error equation's left side is the rate of its error: "
            f"{forms[0]} or {forms[1]} (the model's error state {state.error})")


_STEP_LATEX = re.compile(r"(_\{(?:\\[a-zA-Z]+|[a-zA-Z0-9]+?))\s*k\s*(\+\s*1\s*)?\}")
_STEP_TEXT = re.compile(r"(?<=[A-Za-z0-9])_k(1)?\b")


def _strip_steps(text: str, latex: bool) -> tuple[str, bool]:
    """Remove the time index ``k`` / ``k+1`` of a difference scheme (columns kept).

    Returns the text without the index and whether it held a ``k+1``.
    """
    found = False

    def cut(match: re.Match) -> str:
        nonlocal found
        found = found or match.group(match.re.groups) is not None
        kept = match.group(1) + "}" if latex else ""
        return kept + " " * (len(match.group()) - len(kept))

    return (_STEP_LATEX if latex else _STEP_TEXT).sub(cut, text), found


def _real_work_equation(hand: HandFile, number: int, segment: str, column: int, parse,
                        notation: Notation, latex: bool) -> None:
    """One real-work line: ``a_x = ...`` or ``X_{k+1} = X_k + tau*(...)``."""
    parts = _split_chain(segment, latex)
    start = column + len(segment) - len(segment.lstrip())
    if len(parts) != 2:
        raise _LineError(start, f"a real-work line needs exactly one '=': "
                                f"{segment.strip()!r}")
    (left, left_at), (right, right_at) = parts
    left, step = _strip_steps(left, latex)
    right, _ = _strip_steps(right, latex)
    columns: dict[str, int] = {}
    lhs, where = parse(left, notation, column + left_at)
    columns.update(where)
    rhs, where = parse(right, notation, column + right_at)
    for key, value in where.items():
        columns.setdefault(key, value)
    inner = lhs.args[0] if isinstance(lhs, sp.Function) and lhs.func == TILDE else lhs
    if not isinstance(inner, sp.Symbol):
        raise _LineError(start, f"left-hand side {left.strip()!r} of a real-work line must "
                                "be one quantity (a_x, or tilde(V_xi) at step k+1)")
    hand.real_work.append(HandEquation(
        line=number, column=start, section=len(hand.sections) - 1, lhs=lhs, forms=[rhs],
        text=" ".join(segment.split()), columns=columns, step=step,
        declarations=tuple(range(len(hand.declarations)))))


def _directive(hand: HandFile, keyword: str, text: str, column: int,
               notation: Notation, number: int = 0) -> None:
    body = text[len(keyword):]
    if "=" not in body:
        raise _LineError(column, f"{keyword} needs 'NAME = ...'")
    name, value = (part.strip() for part in body.split("=", 1))
    if keyword == "@magnitude":
        if not value:
            raise _LineError(column, "@magnitude needs 'UNIT = QUANTITY'")
        hand.magnitudes[name] = value
        return
    if keyword == "@markov":  # SOURCE as the file spells it (b_{gz} in LaTeX)
        if not name or not value or any(c.isspace() for c in name):
            raise _LineError(column, "@markov needs 'SOURCE = CORRELATION TIME' "
                             "(e.g. '@markov accel_bias_x = 1 h')")
        if name in hand.markov:
            raise _LineError(column, f"second @markov of {name} (first on line "
                             f"{hand.markov_lines[name]}): give one correlation time")
        hand.markov[name] = value
        hand.markov_lines[name] = number
        return
    if not name.isidentifier():
        raise _LineError(column, f"{keyword}: {name!r} is not a valid name")
    if keyword == "@name":
        if not value.isidentifier():
            raise _LineError(column, "@name needs 'NAME = model_name'")
        hand.notation.spellings[name] = value
        notation.spellings[name] = value
        return
    if keyword == "@alias":
        parse_text_expression(value, notation, column)  # syntax check now
        hand.notation.aliases[name] = value
    else:
        targets = tuple(t.strip() for t in value.split(",") if t.strip())
        if not targets or not all(t.isidentifier() for t in targets):
            raise _LineError(column, "@source needs 'NAME = model_source[, model_source ...]'")
        hand.notation.sources[name] = targets


_SCOPES = ("static base", "cruise", "climb")


def _declaration(hand: HandFile, number: int, text: str, column: int,
                 notation: Notation) -> None:
    """Read ``@neglect ITEM[, ITEM ...] [: REASON]``."""
    body = text[len("@neglect"):]
    listed, _, reason = body.partition(":")
    items, texts = [], []
    for piece, offset in _split_top(listed, ","):
        if not piece.strip():
            continue
        if "\\" in piece:  # a LaTeX file's habit: directives are written in text
            raise _LineError(column + len("@neglect") + offset,
                             "@neglect items are written as text, also in a LaTeX file: "
                             f"'{' '.join(piece.split())}' as e.g. 'Delta_R_N' (the names "
                             "of the equations' text form)")
        expr, _ = parse_text_expression(piece, notation, column + len("@neglect") + offset)
        items.append(expr)
        texts.append(" ".join(piece.split()))
    if not items:
        raise _LineError(column, "@neglect needs at least one variation or term "
                                 "('@neglect Delta_R_xi, Delta_R_eta : reason')")
    hand.declarations.append(Declaration(number, tuple(items), tuple(texts),
                                         " ".join(reason.split())))


def read_hand_file(path: str | Path, notation: Notation, latex: bool | None = None,
                   latex_backend: str = "lalr") -> HandFile:
    """Read and parse a hand file; LaTeX if ``latex`` or the suffix is ``.tex``.

    Raises
    ------
    HandParseError
        If the file cannot be read.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise HandParseError(f"hand file {str(path)!r} not found") from None
    except (OSError, UnicodeDecodeError) as error:
        raise HandParseError(f"cannot read hand file {str(path)!r}: {error}") from None
    if latex is None:
        latex = path.suffix.lower() in (".tex", ".latex")
    return parse_hand_text(text, notation, name=path.name, latex=latex,
                           latex_backend=latex_backend)


def read_mapping_file(path: str | Path) -> Notation:
    """Read a mapping file (``@alias`` / ``@source`` lines, ``#`` comments).

    Raises
    ------
    HandParseError
        If the file cannot be read or a line is not a mapping entry.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise HandParseError(f"cannot read mapping file {str(path)!r}: {error}") from None
    hand = parse_hand_text(text, Notation(), name=path.name)
    if hand.equations:
        first = hand.equations[0]
        hand.problems.append(Problem(first.line, first.column,
                                     "a mapping file holds only @alias and @source lines"))
    if hand.problems:
        raise HandParseError(f"{path.name}: {hand.problems[0]}")
    return hand.notation
