"""Render a :class:`~ins_errors.checker.compare.CheckReport` as LaTeX, for a referee report.

``ins-errors check MODEL FILE --report findings.tex`` writes this. The output is a
*fragment*, not a document: a referee writes a report of their own and pulls the
findings into it with ``\\input{findings.tex}``. Its headings are unnumbered
(``\\subsection*`` and below), and it needs the packages :data:`PACKAGES` (the first
lines of the fragment say so, as comments).

The fragment carries what the Markdown report (:func:`ins_errors.checker.report.to_markdown`)
carries, in the same order. Each hand and model coefficient is typeset as mathematics,
between ``\\(`` and ``\\)`` (other mathematics, a quantity's name, between ``$``): the
coefficient's SymPy text is read with every name a plain symbol (:func:`coefficient_expr`),
and :func:`sympy.latex` writes it with the model's own LaTeX spelling of each symbol
(:class:`LatexNames`), so a report on ``orthodromic`` reads in the lab manual's notation
(``\\Delta u_{31}``, ``g'_\\xi``, ``\\varphi``). A coefficient the checker shortened
(it ends in ``...``) is typeset up to its last whole term, followed by ``+ \\dots``.
Every other text (labels, file names, explanations) is escaped for LaTeX's text mode
(:func:`escape`). Like the Markdown report, the output is deterministic: no dates, no
paths.
"""

from __future__ import annotations

import ast
import re
import unicodedata
from collections.abc import Iterable

import sympy as sp
from sympy.printing.latex import LatexPrinter

from ins_errors.checker.classify import Finding
from ins_errors.checker.compare import CheckReport, EquationResult
from ins_errors.checker.report import (
    FROM_MODEL_TEXT,
    SECTION_TITLES,
    _effect,
    _size,
    how_compared,
    omission_groups,
    omission_text,
    ordered,
    out_of_scope_text,
    scope_text,
    status_notes,
    summary_line,
)

PACKAGES = ("amsmath", "booktabs", "longtable")
"""LaTeX packages the fragment uses (``\\operatorname`` and ``\\text``; the rules of its
tables; tables that break across pages)."""

_TEXT_ESCAPES = {
    "\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "$": r"\$", "&": r"\&", "#": r"\#",
    "%": r"\%", "_": r"\_", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}",
    "<": r"\textless{}", ">": r"\textgreater{}", "|": r"\textbar{}",
    "[": "{[}", "]": "{]}",  # never an optional argument of a \item or a row's \\
}
_UNICODE = {
    "″": r"\ensuremath{''}", "′": r"\ensuremath{'}", "—": "---", "–": "--",
    "−": r"\ensuremath{-}", "×": r"\ensuremath{\times}", "·": r"\ensuremath{\cdot}",
    "°": r"\ensuremath{^\circ}", "±": r"\ensuremath{\pm}", "∓": r"\ensuremath{\mp}",
    "√": r"\ensuremath{\surd}", "…": r"\dots{}", "→": r"\ensuremath{\to}",
    "≤": r"\ensuremath{\le}", "≥": r"\ensuremath{\ge}", "≈": r"\ensuremath{\approx}",
    "≠": r"\ensuremath{\ne}", "∂": r"\ensuremath{\partial}", "µ": r"\ensuremath{\mu}",
    "‖": r"\ensuremath{\|}", "⊗": r"\ensuremath{\otimes}", "ᵀ": r"\ensuremath{^{\mathsf{T}}}",
    "²": r"\ensuremath{^{2}}", "³": r"\ensuremath{^{3}}", "¹": r"\ensuremath{^{1}}",
    "⁴": r"\ensuremath{^{4}}", "⁻": r"\ensuremath{^{-}}", "⁺": r"\ensuremath{^{+}}",
    "₀": r"\ensuremath{_{0}}", "₁": r"\ensuremath{_{1}}", "₂": r"\ensuremath{_{2}}",
    "\u00a0": "~",
}
_GREEK_VARIANTS = {"phi": "varphi", "epsilon": "varepsilon"}
_ACCENTS = {"\u0307": "dot", "\u0303": "tilde", "\u0302": "hat", "\u0304": "bar"}


def _greek(char: str) -> str | None:
    """``\\ensuremath{\\alpha}`` for a Greek letter, else None."""
    name = unicodedata.name(char, "")
    match = re.fullmatch(r"GREEK (SMALL|CAPITAL) LETTER ([A-Z]+)", name)
    if not match:
        return None
    letter = match.group(2).lower()
    if letter == "lamda":
        letter = "lambda"
    if match.group(1) == "CAPITAL":
        if letter in ("gamma", "delta", "theta", "lambda", "xi", "pi", "sigma", "upsilon",
                      "phi", "psi", "omega"):
            return rf"\ensuremath{{\{letter.capitalize()}}}"
        return None  # a Latin-looking capital: kept as UTF-8
    if letter == "omicron":
        return "o"
    return rf"\ensuremath{{\{_GREEK_VARIANTS.get(letter, letter)}}}"


def _escape_char(char: str) -> str:
    if char in _TEXT_ESCAPES:
        return _TEXT_ESCAPES[char]
    if char.isascii():
        return char
    if char in _UNICODE:
        return _UNICODE[char]
    greek = _greek(char)
    if greek is not None:
        return greek
    parts = unicodedata.normalize("NFD", char)
    if len(parts) == 2 and parts[1] in _ACCENTS and parts[0].isascii():
        return rf"\ensuremath{{\{_ACCENTS[parts[1]]}{{{parts[0]}}}}}"
    return char  # kept as UTF-8, LaTeX's input encoding


def escape(text: str) -> str:
    """``text`` for LaTeX's text mode, on one line.

    The ten special characters (``\\ { } $ & # % _ ~ ^``) and ``< > |`` become the
    commands that print them, line breaks become spaces, and the non-ASCII characters
    the checker writes (``″``, ``×``, ``—``, Greek letters, superscript digits, dotted
    letters) their LaTeX spelling; any other character is kept (UTF-8).

    Examples
    --------
    >>> escape("50% of a_xi & {b}")
    '50\\\\% of a\\\\_xi \\\\& \\\\{b\\\\}'
    """
    text = re.sub(r"\s*[\r\n]+\s*", " ", str(text))
    return "".join(_escape_char(char) for char in text)


def _code(text: str) -> str:
    """``\\texttt{...}`` of ``text`` (escaped), or empty."""
    return rf"\texttt{{{escape(text)}}}" if text else ""


# -- coefficients ------------------------------------------------------------------------

_FUNCTIONS = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "cot": sp.cot, "sec": sp.sec, "csc": sp.csc,
    "asin": sp.asin, "acos": sp.acos, "atan": sp.atan, "atan2": sp.atan2, "acot": sp.acot,
    "sinh": sp.sinh, "cosh": sp.cosh, "tanh": sp.tanh, "exp": sp.exp, "log": sp.log,
    "sqrt": sp.sqrt, "Abs": sp.Abs, "sign": sp.sign,
}
"""Functions of SymPy's text a coefficient may hold; every other name is a plain symbol
(``E``, ``I``, ``N``, ``S``, ``Q``, ``O``, ``beta``, ``gamma``, ``zeta`` included)."""

WRAPPED = ("tilde", "dot")
"""``tilde(NAME)``, ``dot(NAME)`` in a coefficient are one symbol, named so."""

_BINARY = {ast.Add: sp.Add, ast.Sub: lambda a, b: a - b, ast.Mult: sp.Mul,
           ast.Div: lambda a, b: a / b}


class _UnreadableError(ValueError):
    """A coefficient text that is not SymPy arithmetic of names."""


def _build(node: ast.AST) -> sp.Expr:
    """SymPy expression of a parsed coefficient (no name evaluated, nothing imported)."""
    if isinstance(node, ast.Expression):
        return _build(node.body)
    if isinstance(node, ast.BinOp):
        left, right = _build(node.left), _build(node.right)
        if isinstance(node.op, ast.Pow):
            if left.is_Number and right.is_Number:  # sized by the checker; kept unevaluated
                return sp.Pow(left, right, evaluate=False)
            return left ** right
        if type(node.op) in _BINARY:
            return _BINARY[type(node.op)](left, right)
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        value = _build(node.operand)
        return -value if isinstance(node.op, ast.USub) else value
    elif isinstance(node, ast.Name):
        return sp.pi if node.id == "pi" else sp.Symbol(node.id)
    elif isinstance(node, ast.Constant) and type(node.value) in (int, float):
        return sp.Integer(node.value) if isinstance(node.value, int) else sp.Float(node.value)
    elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords:
        name = node.func.id
        if (name in WRAPPED and len(node.args) == 1 and isinstance(node.args[0], ast.Name)):
            return sp.Symbol(f"{name}({node.args[0].id})")
        args = [_build(arg) for arg in node.args]
        if name in _FUNCTIONS:
            return _FUNCTIONS[name](*args)
        return sp.Function(name)(*args)
    raise _UnreadableError(ast.dump(node))


def _read(text: str) -> sp.Expr:
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError) as error:
        raise _UnreadableError(text) from error
    return _build(tree)


def _whole_terms(text: str) -> list[str]:
    """Prefixes of ``text`` that end before a top-level ``+``/``-`` (longest first)."""
    depth, cuts = 0, []
    for k, char in enumerate(text):
        depth += {"(": 1, ")": -1}.get(char, 0)
        if depth == 0 and char in "+-" and k > 0 and text[k - 1] == " ":
            cuts.append(k)
    return [text[:k].rstrip() for k in reversed(cuts)]


def coefficient_expr(text: str) -> tuple[sp.Expr | None, bool]:
    """The SymPy expression of a finding's coefficient text, and whether it was shortened.

    Every name is a plain :class:`sympy.Symbol` (``E`` is not Euler's number, ``I`` not
    the imaginary unit; ``pi`` is π), ``tilde(X)`` and ``dot(X)`` are one symbol so
    named, and the functions of :data:`_FUNCTIONS` are SymPy's. A text the checker
    shortened (``... + c/(u11**2 +...``) gives the sum of its whole terms.

    Returns
    -------
    expr : sympy.Expr or None
        None when no part of the text reads as arithmetic of names.
    shortened : bool
    """
    text = text.strip()
    if not text.endswith("..."):
        try:
            return _read(text), False
        except (_UnreadableError, TypeError, ValueError, RecursionError):
            return None, False
    for prefix in _whole_terms(text[:-3]):
        try:
            return _read(prefix), True
        except (_UnreadableError, TypeError, ValueError, RecursionError):
            continue
    return None, True


class LatexNames:
    """LaTeX spelling of each name in a report: the model's own where it has one.

    The model's spellings are those of its error states, states, inputs, parameters,
    error sources and outputs (first wins), then of its intermediate quantities (ideal,
    true, real). A name the model does not spell (the file's own helpers, ``D``,
    ``e``) is written by SymPy; ``Delta_X`` is ``\\Delta`` before X's spelling,
    ``tilde(X)`` X's spelling with a tilde. Every spelling is wrapped in braces and no
    two names share one (a later name that would gets ``\\mathit{name}``).

    Attributes
    ----------
    used : dict of str to str
        Every name spelled so far -> its spelling (braces included), as typeset.
    """

    def __init__(self, definition=None):
        self._model: dict[str, str] = {}
        self.used: dict[str, str] = {}
        if definition is None:
            return
        groups = [definition.error_states, definition.states, definition.inputs,
                  definition.parameters, definition.sources, definition.outputs]
        for group in groups:
            for v in group:
                self._model.setdefault(v.name, v.latex)
        mechanisations = [definition.ideal]
        try:
            from ins_errors.symbolic.variation import output_mechanisations

            mechanisations.append(output_mechanisations(definition)[0])
        except Exception:  # a model without output mechanisations: its ideal ones only
            pass
        mechanisations.append(definition.real)
        for mech in mechanisations:
            for d in mech.definitions:
                self._model.setdefault(d.symbol.name, d.latex)
        for symbol, latex in definition.latex_names().items():
            self._model.setdefault(symbol.name, latex)

    def known(self, name: str) -> bool:
        """Whether the model spells ``name`` (or the X of ``Delta_X``, ``tilde(X)``)."""
        match = re.fullmatch(r"Delta_(\w+)|(?:tilde|dot)\((\w+)\)", name)
        return name in self._model or bool(
            match and (match.group(1) or match.group(2)) in self._model)

    def _bare(self, name: str) -> str:
        if name in self._model:
            return self._model[name]
        match = re.fullmatch(r"Delta_(\w+)", name)
        if match:
            return rf"\Delta {self._bare(match.group(1))}"
        match = re.fullmatch(r"(tilde|dot)\((\w+)\)", name)
        if match:
            from ins_errors.modeling import accent

            return accent(self._bare(match.group(2)), match.group(1))
        return sp.latex(sp.Symbol(name))

    def __call__(self, name: str) -> str:
        """The spelling of ``name``, in braces (recorded in :attr:`used`)."""
        if name in self.used:
            return self.used[name]
        spelled = "{" + self._bare(name) + "}"
        if spelled in self.used.values():
            spelled = r"{\mathit{" + escape(name) + "}}"
        self.used[name] = spelled
        return spelled


class _Printer(LatexPrinter):
    r"""SymPy's LaTeX, each function application in braces: ``{\cos{\left(x \right)}} + 1``
    reads as one way only (to a reader, TeX shows no difference), where a parser may take
    ``\cos{\left(x \right)} + 1`` as the cosine of ``x + 1``."""

    def _print_Function(self, expr, exp=None):
        return "{" + super()._print_Function(expr, exp) + "}"


def coefficient_latex(text: str, names: LatexNames) -> str:
    """A coefficient as inline mathematics ``\\( ... \\)`` in the model's notation.

    Products are written with ``\\cdot``. A shortened coefficient ends in ``+ \\dots``;
    a text that does not read as arithmetic stays text (``\\texttt``).
    """
    expr, shortened = coefficient_expr(text)
    if expr is None:
        return _code(text)
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    spelled = {s: names(s.name) for s in symbols}
    body = _Printer({"symbol_names": spelled, "mul_symbol": "dot"}).doprint(expr)
    tail = r" + \dots" if shortened else ""
    return rf"\({body}{tail}\)"


def _quantity(text: str, names: LatexNames) -> str:
    """A finding's quantity: ``$\\Delta u_{31}$`` for a name the model spells (also
    ``a -> b``), else the text."""
    parts = text.split(" -> ")
    if all(re.fullmatch(r"\w+", p) and names.known(p) for p in parts):
        return "$" + r" \to ".join(names(p) for p in parts) + "$"
    return escape(text) if text.startswith("(") else _code(text)


# -- the document ------------------------------------------------------------------------

def _finding_item(result: EquationResult, f: Finding, names: LatexNames,
                  roots: bool = False) -> list[str]:
    detail = f.detail
    if roots and f.roots:
        detail = f"from {', '.join(f.roots)}" + (f"; {detail}" if detail else "")
    text = (rf"\item Line {result.equation.line}, {_code(result.label)}, on "
            f"{_quantity(f.quantity, names)}: {escape(f.kind)} ({escape(f.severity)}, "
            f"size {escape(_size(f.size))} at {escape(f.point)}). "
            f"Hand {coefficient_latex(f.hand, names)}; "
            f"model {coefficient_latex(f.model, names)}.")
    if detail:
        text += f" {escape(detail)}."
    if f.effect:
        text += rf" \emph{{Effect on the error (position, attitude):}} {escape(_effect(f))}."
    return [text]


def _items(pairs: list[tuple[EquationResult, Finding]], names: LatexNames,
           roots: bool = False) -> list[str]:
    lines = [r"\begin{itemize}"]
    for result, f in pairs:
        lines += _finding_item(result, f, names, roots)
    return [*lines, r"\end{itemize}"]


def _table(columns: str, header: Iterable[str], rows: Iterable[Iterable[str]]) -> list[str]:
    """A longtable with booktabs rules; the header repeats on every page."""
    head = " & ".join(rf"\textbf{{{h}}}" for h in header) + r" \\"
    lines = [rf"\begin{{longtable}}{{{columns}}}", r"\toprule", head, r"\midrule",
             r"\endfirsthead", r"\toprule", head, r"\midrule", r"\endhead",
             r"\bottomrule", r"\endlastfoot"]
    lines += [" & ".join(row) + r" \\" for row in rows]
    return [*lines, r"\end{longtable}"]


def _status_notes(r: EquationResult) -> str:
    return escape(status_notes(r))


_MARKDOWN_INLINE = re.compile(r"\*\*(?P<bold>.+?)\*\*|\*(?P<em>.+?)\*|`(?P<code>.+?)`")
"""The inline Markdown of the reports' shared paragraphs: ``**bold**``, ``*emphasis*``,
```code```."""


def _from_markdown(text: str) -> str:
    """LaTeX of a paragraph in the reports' inline Markdown (:data:`_MARKDOWN_INLINE`),
    the text between the marks escaped."""
    out, at = [], 0
    for match in _MARKDOWN_INLINE.finditer(text):
        out.append(escape(text[at:match.start()]))
        if match["bold"] is not None:
            out.append(rf"\textbf{{{escape(match['bold'])}}}")
        elif match["em"] is not None:
            out.append(rf"\emph{{{escape(match['em'])}}}")
        else:
            out.append(rf"\texttt{{{escape(match['code'])}}}")
        at = match.end()
    return "".join(out) + escape(text[at:])


def to_latex(report: CheckReport, definition=None, source: str | None = None,
             names: LatexNames | None = None) -> str:
    """The LaTeX fragment of a check (see the module docstring).

    Parameters
    ----------
    report : CheckReport
    definition : ins_errors.modeling.ModelDefinition, optional
        The model checked against: its LaTeX spellings are used. Without it (and without
        ``names``) every name is written by SymPy.
    source : str, optional
        How the report was produced (plain text, e.g. ``"ins-errors check from eq.tex"``),
        for the first paragraph; omitted when None.
    names : LatexNames, optional
        The spellings to use (and record in ``names.used``); made from ``definition``
        when not given.

    Returns
    -------
    str
        The fragment, ending in a line break.
    """
    names = names if names is not None else LatexNames(definition)
    lines = [
        "% Findings of `ins-errors check`, a LaTeX fragment: \\input it into a document.",
        f"% Needs \\usepackage{{{','.join(PACKAGES)}}} and UTF-8 input (LaTeX's default).",
        "% Headings are unnumbered (\\subsection* and below).",
        "",
        rf"\subsection*{{Check of {_code(report.hand_name)} against the "
        rf"{_code(report.model)} model}}",
        "",
    ]
    if source:
        lines += [rf"\emph{{Generated by {escape(source)}. Do not edit: regenerate.}}", ""]
    lines += [
        rf"\textbf{{Result.}} {escape(summary_line(report))}.",
        "",
        rf"\textbf{{Typical magnitudes.}} {escape(report.magnitudes)}.",
        "",
        _from_markdown(how_compared(report.threshold)),
        "",
    ]
    if report.scope:
        lines += [_from_markdown(scope_text(report.scope)), ""]
    if report.scope_advice:
        lines += [_from_markdown(f"**Static base?** {report.scope_advice}"), ""]
    if report.declarations:
        lines += [r"\textbf{Declared simplifications.} "
                  + "; ".join(map(escape, report.declarations)) + ".", ""]
    lines += [r"\subsubsection*{Root mistakes and their knock-on effects}", ""]
    groups = ordered(report)
    roots = [pairs for kind, pairs in groups if kind == "root"]
    if not roots:
        lines += ["None.", ""]
    for pairs in roots:
        result, f = pairs[0]
        lines += [rf"\paragraph{{Line {result.equation.line}: {_code(result.label)} --- "
                  rf"{escape(f.kind)} on {_quantity(f.quantity, names)} "
                  rf"({escape(f.severity)})}}", ""]
        explanation = escape(f.detail or "the coefficients differ")
        text = (f"{explanation}. Hand {coefficient_latex(f.hand, names)}, model "
                f"{coefficient_latex(f.model, names)}; size {escape(_size(f.size))} at "
                f"{escape(f.point)}.")
        if f.effect:
            text += f" Effect: {escape(_effect(f))}."
        lines += [text, ""]
        merged = [(r, g) for r, g in pairs[1:] if g.merged]
        if merged:
            lines += ["The other half of this finding:", ""]
            lines += _items(merged, names)
            lines.append("")
        if len(pairs) > 1 + len(merged):
            lines += ["Knock-on findings:", ""]
            lines += _items(pairs[1 + len(merged):], names)
            lines.append("")
    if report.omissions:
        lines += [r"\subsubsection*{Undeclared dropped variations}", ""]
    for omission, pairs in omission_groups(report):
        title = omission.title[0].upper() + omission.title[1:]
        lines += [rf"\paragraph{{{escape(title)} ({escape(omission.severity)})}}", ""]
        lines += [_from_markdown(omission_text(omission)), "", "Its findings:", ""]
        lines += _items(pairs, names)
        lines.append("")
    for kind, pairs in groups:
        if kind == "root" or (kind == "knock-on" and not pairs):
            continue
        lines += [rf"\subsubsection*{{{SECTION_TITLES[kind]}}}", ""]
        lines += _items(pairs, names, roots=True) if pairs else ["None."]
        lines.append("")
    if report.idle_declarations:
        lines += ["Declared simplifications that explain no finding: "
                  + "; ".join(map(escape, report.idle_declarations)) + ".", ""]
    lines += [r"\subsubsection*{Equation by equation}", ""]
    for index, title in enumerate(report.sections):
        results = [r for r in report.results if r.equation.section == index]
        if not results:
            continue
        lines += [rf"\paragraph{{{escape(title)}}}", ""]
        lines += _table(r"r p{0.2\linewidth} p{0.14\linewidth} p{0.14\linewidth} "
                        r"p{0.34\linewidth}",
                        ("line", "equation", "compared with", "status", "notes"),
                        [(str(r.equation.line), _code(r.label), escape(r.target),
                          escape(r.status), _status_notes(r)) for r in results])
        lines.append("")
    lines += [r"\subsubsection*{How the comparison was made}", "", "Reference points:", ""]
    lines += _table(r"p{0.25\linewidth} p{0.68\linewidth}", ("point", "motion"),
                    [(escape(p.label), escape(p.description)) for p in report.points])
    if report.skipped_motions:
        lines += ["", "Motions not flown: " + "; ".join(map(escape, report.skipped_motions))
                  + "."]
    lines += ["", "Error quantities and their typical magnitudes:", ""]
    lines += _table(r"p{0.2\linewidth} p{0.1\linewidth} p{0.17\linewidth} "
                    r"p{0.43\linewidth}",
                    ("quantity", "unit", "typical magnitude", "stands for"),
                    [(_quantity(b.name, names), _code(b.unit), escape(b.magnitude_text),
                      ", ".join(_code(s) for s in b.stands_for)) for b in report.basis])
    if report.out_of_scope:
        lines += ["", _from_markdown(out_of_scope_text(report.out_of_scope))]
    if report.from_model:
        lines += ["", escape(FROM_MODEL_TEXT), "", r"\begin{itemize}"]
        lines += [rf"\item {_code(k)} (needed by lines {', '.join(map(str, v))})"
                  for k, v in report.from_model.items()]
        lines.append(r"\end{itemize}")
    if report.unused:
        lines += ["", "Hand-only definitions no line uses: "
                  + ", ".join(map(escape, report.unused)) + "."]
    lines += ["", r"\subsubsection*{Input problems}", ""]
    if report.problems:
        lines += [r"\begin{itemize}", *(rf"\item {escape(str(p))}" for p in report.problems),
                  r"\end{itemize}"]
    else:
        lines.append("None.")
    return "\n".join(lines) + "\n"
