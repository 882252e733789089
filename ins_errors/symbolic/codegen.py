"""Emit numeric code (numpy and CasADi) from SymPy matrices.

Each emitted function takes flat argument vectors (``x``, ``u``, ``p``, ...), unpacks
them into named locals, evaluates common subexpressions once (SymPy ``cse``) and returns
the matrix. The numpy functions broadcast: every argument may carry trailing batch axes
(shape ``(n, ...)``), and the result has shape ``(rows, cols, ...)`` for a matrix (also
when a dimension is 1) or ``(rows, ...)`` for a vector (:class:`FunctionSpec`), so a
whole trajectory is evaluated in one call. The CasADi module
builds the same expressions as ``casadi.Function`` objects over ``SX`` symbols.

Both backends are printed from the same CSE'd assignment list, so they cannot drift
apart; tests compare them with each other and with SymPy evaluated in memory.
"""

from __future__ import annotations

import functools
import keyword
import re
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.core.function import _coeff_isneg
from sympy.core.operations import LatticeOp
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.pycode import PythonCodePrinter
from sympy.simplify.radsimp import fraction

from ins_errors.symbolic.shared_trees import SharedTrees
from ins_errors.symbolic.term_order import FastTermOrder

_FUNCTIONS = ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sqrt", "exp", "log",
              "sinh", "cosh", "tanh", "Abs")
_ELEMENTWISE = ("where", "logical_and", "logical_or", "logical_not", "maximum", "minimum",
                "sign", "floor", "ceil")
"""Backend calls the printer writes itself (not SymPy function names): ``Piecewise`` as
nested ``where``, its ``And``/``Or``/``Not``, ``Max``/``Min`` as pairwise ``maximum``/
``minimum``, ``sign``, ``floor``, ``ceiling`` (and ``Heaviside`` through ``where``),
elementwise in both backends: Python's ``... if ... else ...``, ``max`` and
``math.copysign``, which SymPy's Python printer writes, fail on numpy arrays and CasADi
symbols."""
_NUMPY_NAMES = {"asin": "_m.arcsin", "acos": "_m.arccos", "atan": "_m.arctan",
                "atan2": "_m.arctan2", "Abs": "_m.abs"}
_CASADI_NAMES = {"Abs": "_m.fabs", "tan": "_tan", "where": "_m.if_else",
                 "logical_and": "_m.logic_and", "logical_or": "_m.logic_or",
                 "logical_not": "_m.logic_not", "maximum": "_m.fmax", "minimum": "_m.fmin"}
"""How each backend calls a function, where not ``_m.<name>`` (``_m`` the backend's
module). CasADi's ``tan`` is the module's own ``_tan``, sin x / cos x
(:data:`CASADI_TAN`): a compiled loop computes the sine and cosine of a latitude anyway
(in one ``sincos`` call) and then needs a division where ``tan`` was a call of its own,
about a sixth of a strapdown INS's RK4 step."""

CASADI_TAN = '''
def _tan(x):
    """tan x as sin x / cos x (the loop's sin x and cos x serve it; see codegen)."""
    return _m.sin(x) / _m.cos(x)
'''
"""The helper every generated CasADi module defines (after its imports)."""


def casadi_namespace() -> dict:
    """The names an emitted CasADi builder (:func:`emit_casadi_builder`) runs with when
    it is executed on its own, not in a generated module: ``_m`` and ``_tan``."""
    import casadi

    namespace = {"_m": casadi}
    exec(CASADI_TAN, namespace)  # our own constant text
    return namespace


class _BackendPrinter(FastTermOrder, PythonCodePrinter):
    """Python printer whose elementary functions live in module alias ``_m`` (sums in
    SymPy's order, :mod:`~ins_errors.symbolic.term_order`)."""

    def __init__(self, names: dict[str, str]):
        functions = {f: names.get(f, f"_m.{f}") for f in _FUNCTIONS}
        super().__init__({"user_functions": functions, "fully_qualified_modules": False})
        self._sqrt = functions["sqrt"]
        self._calls = {f: names.get(f, f"_m.{f}") for f in _ELEMENTWISE}

    def _call(self, function: str, *args: sp.Basic | str) -> str:
        """``function(args)`` with the backend's name of one of :data:`_ELEMENTWISE`."""
        printed = (a if isinstance(a, str) else self._print(a) for a in args)
        return f"{self._calls[function]}({', '.join(printed)})"

    def _pairwise(self, function: str, args: Sequence[sp.Basic]) -> str:
        """``f(a, f(b, c))`` of a binary ``function`` over two or more ``args``."""
        text = self._print(args[-1])
        for a in reversed(args[:-1]):
            text = self._call(function, a, text)
        return text

    def _print_Piecewise(self, expr):
        pairs = list(expr.args)
        text = "float('nan')"  # no condition holds: SymPy's Piecewise is undefined
        if pairs[-1].cond == sp.true:
            text = self._print(pairs.pop().expr)
        for pair in reversed(pairs):
            text = self._call("where", pair.cond, pair.expr, text)
        return text

    def _print_And(self, expr):
        return self._pairwise("logical_and", expr.args)

    def _print_Or(self, expr):
        return self._pairwise("logical_or", expr.args)

    def _print_Not(self, expr):
        return self._call("logical_not", expr.args[0])

    def _print_Max(self, expr):
        return self._pairwise("maximum", expr.args)

    def _print_Min(self, expr):
        return self._pairwise("minimum", expr.args)

    def _print_sign(self, expr):
        return self._call("sign", expr.args[0])

    def _print_floor(self, expr):
        return self._call("floor", expr.args[0])

    def _print_ceiling(self, expr):
        return self._call("ceil", expr.args[0])

    def _print_Heaviside(self, expr):
        x = expr.args[0]
        at_zero = expr.args[1] if len(expr.args) > 1 else sp.S.Half
        return self._print(sp.Piecewise((1, x > 0), (0, x < 0), (at_zero, True)))

    def _print_Pow(self, expr, rational=False):
        exponent = expr.exp
        if (not rational and exponent.is_Rational and exponent.q == 2
                and abs(exponent.p) > 1 and expr.is_commutative):
            return self._half_power(expr.base, int(exponent.p))
        return self._hprint_Pow(expr, rational=rational, sqrt=self._sqrt)

    def _half_power(self, base: sp.Expr, p: int) -> str:
        """``base**(p/2)`` for odd ``|p| >= 3`` as ``base**n * sqrt(base)`` (n = (|p|−1)/2),
        inverted for ``p < 0``, in parentheses.

        A square root and a product or two instead of a call to ``pow``: several times
        cheaper in a compiled loop (CasADi prints ``x**2`` as ``x*x``), and within a few
        units in the last place of the exact power (two to four roundings of at most half
        a unit each instead of ``pow``'s one; tests/test_codegen_half_powers.py).
        """
        whole = (abs(p) - 1) // 2
        root = f"{self._sqrt}({self._print(base)})"
        factor = (self.parenthesize(base, PRECEDENCE["Mul"], strict=False) if whole == 1
                  else self._print(sp.Pow(base, whole, evaluate=False)))
        product = f"{factor}*{root}"
        return f"({product})" if p > 0 else f"(1/({product}))"

    def _module_format(self, fqn, register=True):  # keep "_m.sin" as written
        return fqn

    def _handle_UnevaluatedExpr(self, expr):
        # SymPy's version rebuilds the whole tree to rewrite re(...) of real arguments:
        # the same expression where there is none
        if isinstance(expr, sp.Basic) and not expr.has(sp.re):
            return expr
        return super()._handle_UnevaluatedExpr(expr)

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_Rational(self, expr):
        return f"({expr.p}/{expr.q})"

    def _print_Half(self, expr):
        return self._print_Rational(expr)

    def _print_Pi(self, expr):
        return "_m.pi"


NUMPY_PRINTER = _BackendPrinter(_NUMPY_NAMES)
CASADI_PRINTER = _BackendPrinter(_CASADI_NAMES)
"""Each backend's own printer (what the emitted text equals; see _in_backend)."""

_MARK = "\x00"
_NEUTRAL_PRINTER = _BackendPrinter({f: "_m." + _MARK + f
                                   for f in (*_FUNCTIONS, *_ELEMENTWISE)})
"""Prints ``_m.<mark><function>``: one printing serves both backends (see _in_backend)."""
_MARKED = re.compile(r"_m\." + _MARK + r"(\w+)")


def _in_backend(text: str, names: dict[str, str]) -> str:
    """Text of :data:`_NEUTRAL_PRINTER` as the backend with function ``names`` prints it.

    The printers differ only in the function-name strings they are given, which the
    printer inserts verbatim, so replacing the marked names gives the backend's text.
    """
    return _MARKED.sub(lambda m: names.get(m[1], f"_m.{m[1]}"), text)


@dataclass(frozen=True)
class Argument:
    """One flat vector argument of an emitted function."""

    name: str
    symbols: Sequence[sp.Symbol]
    description: str


@dataclass(frozen=True)
class FunctionSpec:
    """What to emit: ``name(arguments...) -> matrix``.

    ``matrix`` says what the result is, not its SymPy shape: True for a matrix (F, G,
    H, E, Jacobians: the numpy function returns shape ``(rows, cols, ...)`` even when
    ``cols`` is 1, a model with one error source or one error state), False for a column
    vector (right-hand sides, outputs, initial states: shape ``(rows, ...)``; the result
    must have one column).
    """

    name: str
    arguments: Sequence[Argument]
    result: sp.Matrix
    summary: str
    result_description: str
    matrix: bool = False

    def __post_init__(self) -> None:
        if not self.matrix and self.result.cols != 1:
            raise ValueError(f"{self.name}: a vector result must have one column, got shape "
                             f"{self.result.shape} (a matrix result needs matrix=True)")

    @property
    def numpy_shape(self) -> tuple[int, ...]:
        """Leading shape of the numpy result (before the batch axes)."""
        rows, cols = self.result.shape
        return (rows, cols) if self.matrix else (rows,)


@dataclass(frozen=True)
class _Prepared:
    spec: FunctionSpec
    unpack: list[tuple[str, str, int]]  # (local, argument, index)
    assignments: list[tuple[str, sp.Expr]]
    entries: list[tuple[int, int, sp.Expr]]  # nonzero entries after CSE

    @functools.cached_property
    def operations(self) -> int:
        """SymPy's operation count of the CSE'd function (counted when first read:
        ``make derive`` reports it for the model files only)."""
        return int(sum(_count_ops(e) for _, e in self.assignments)
                   + sum(_count_ops(e) for _, _, e in self.entries))

    @functools.cached_property
    def printed(self) -> tuple[list[tuple[str, str]], list[tuple[int, int, str]]]:
        """Assignments and entries as printed by :data:`_NEUTRAL_PRINTER`, once."""
        return ([(name, _NEUTRAL_PRINTER.doprint(e)) for name, e in self.assignments],
                [(i, j, _NEUTRAL_PRINTER.doprint(e)) for i, j, e in self.entries])


def _identifier(symbol: sp.Symbol, taken: set[str]) -> str:
    name = "".join(ch if ch.isalnum() or ch == "_" else "_" for ch in symbol.name)
    if not name or name[0].isdigit() or keyword.iskeyword(name):
        name = f"v_{name}"
    name = f"{name}_"  # never collides with the function's own names (x, u, p, _m, ...)
    while name in taken:
        name += "_"
    taken.add(name)
    return name


def _count_ops(expr: sp.Expr) -> int:
    """``sp.count_ops(expr)`` (the same number), each distinct subtree counted once.

    SymPy's count walks the tree once, appending a symbol per operation (``ADD``,
    ``NEG``, ``2*MUL``...) and adds them up symbolically at the end; the number is the
    sum of their coefficients. :func:`_walk` follows the same walk node by node, with
    the same tests and the same rewritten operands (``-a``, ``fraction``), and adds
    integers. Anything but a plain expression goes to SymPy.
    """
    if not isinstance(expr, sp.Expr) or expr.is_Relational:
        return sp.count_ops(expr)
    return _walk(expr)


@functools.lru_cache(maxsize=65536)
def _walk(a: sp.Basic) -> int:
    """Operations ``sp.count_ops`` counts for node ``a`` and the operands it visits next."""
    if a.is_Rational:
        if a is not sp.S.One:
            return (a.p < 0) + (a.q != 1)  # -1/3 = NEG + DIV
    elif a.is_Mul:
        ops = 0
        if _coeff_isneg(a):
            ops += 1  # NEG
            a = a.as_two_terms()[1] if a.args[0] is sp.S.NegativeOne else -a
        if _whole_numerator(a):  # fraction(a) is (a, 1): no DIV
            return ops + _own_and_operands(a)
        n, d = fraction(a)
        if n.is_Integer:  # DIV (and NEG); d is no -Mul, but may be an Add
            return ops + 1 + (1 if n < 0 else 0) + _walk(d)
        if d is not sp.S.One:  # DIV; n may be a -Mul
            return ops + 1 + (0 if d.is_Integer else _walk(d)) + _walk(n)
        return ops + _own_and_operands(a)
    elif a.is_Add:
        ops, negative = 0, 0
        for i, term in enumerate(a.args):
            if _coeff_isneg(term):
                negative += 1
                ops += _walk(-term) + (i > 0)  # SUB
            else:
                ops += _walk(term) + (i > 0)  # ADD
        # all negative: -x - y = NEG + SUB; a negative first term: SUB - ADD, no change
        return ops + (negative == len(a.args))
    return _own_and_operands(a)


def _whole_numerator(a: sp.Basic) -> bool:
    """True if ``fraction(a)`` keeps every factor of ``a`` in the numerator as it is, so
    that it is ``(a, 1)``; False where it may move or rewrite one (then ask it).

    The same tests as ``fraction`` (not ``exact``), factor by factor, without building
    the two products: a power (or ``exp``) with a negative exponent, or with an
    exponent of unknown sign that is a product, and a non-integer rational go (or may
    go) to the denominator; every other factor stays in the numerator unchanged.
    """
    for term in sp.Mul.make_args(a):
        if term.is_commutative and (term.is_Pow or isinstance(term, sp.exp)):
            ex = term.as_base_exp()[1]
            if ex.is_negative or (not ex.is_positive and ex.is_Mul):
                return False
        elif term.is_Rational and not term.is_integer:
            return False
    return True


def _own_and_operands(a: sp.Basic) -> int:
    """The rest of ``sp.count_ops``'s walk for one node: exponentials, divisions by a
    power -1, the node's own operations, then its arguments (none for a symbol)."""
    if a.is_Pow and a.exp is sp.S.NegativeOne:
        return 1 + _walk(a.base)  # DIV
    if a == sp.S.Exp1:
        return 1  # EXP
    if a.is_Pow and a.base == sp.S.Exp1:
        return 1 + _walk(a.exp)  # EXP
    ops = 0
    if a.is_Mul or isinstance(a, LatticeOp):
        ops = len(a.args) - 1
    elif a.args and (a.is_Pow or a.is_Function
                     or isinstance(a, (sp.Derivative, sp.Integral, sp.Sum))):
        ops = 1
    if not a.is_Symbol:
        ops += sum(_walk(arg) for arg in a.args)
    return ops


def prepare(spec: FunctionSpec, trees: SharedTrees | None = None) -> _Prepared:
    """Unpack arguments and CSE the result (the operation count is counted when read).

    ``trees`` (optional) renames each distinct subtree of the result once.
    """
    trees = trees or SharedTrees()
    taken: set[str] = set()
    rename: dict[sp.Symbol, sp.Symbol] = {}
    unpack: list[tuple[str, str, int]] = []
    used = set().union(*(trees.free_symbols(e) for e in spec.result))
    for argument in spec.arguments:
        for index, symbol in enumerate(argument.symbols):
            if symbol in used and symbol not in rename:
                local = _identifier(symbol, taken)
                rename[symbol] = sp.Symbol(local, real=True)
                unpack.append((local, argument.name, index))
    result = trees.rename_matrix(spec.result, rename)
    unknown = set().union(*(trees.free_symbols(e) for e in result)) - set(rename.values())
    if unknown:
        missing = sorted(map(str, unknown))
        raise ValueError(f"{spec.name}: symbols not among the arguments: {missing}")
    flat = [(i, j, result[i, j]) for i in range(result.rows) for j in range(result.cols)
            if result[i, j] != 0]
    temporaries = sp.numbered_symbols("_t")
    assignments, reduced = sp.cse([e for _, _, e in flat], symbols=temporaries,
                                  order="none")
    entries = [(i, j, e) for (i, j, _), e in zip(flat, reduced, strict=True)]
    return _Prepared(spec, unpack, [(str(s), e) for s, e in assignments], entries)


def _docstring(spec: FunctionSpec, indent: str) -> list[str]:
    lines = [f'{indent}"""{spec.summary}', "", f"{indent}Parameters", f"{indent}----------"]
    for argument in spec.arguments:
        lines.append(f"{indent}{argument.name} : array_like, shape ({len(argument.symbols)}, ...)")
        lines.append(f"{indent}    {argument.description}")
    shape = f"({', '.join(map(str, spec.numpy_shape))}, ...)"
    lines += ["", f"{indent}Returns", f"{indent}-------", f"{indent}numpy.ndarray, shape {shape}",
              f"{indent}    {spec.result_description}", f'{indent}"""']
    return [line.rstrip() for line in lines]


def emit_numpy_function(prepared: _Prepared) -> str:
    """Source of one broadcasting numpy function."""
    spec = prepared.spec
    args = ", ".join(a.name for a in spec.arguments)
    out = [f"def {spec.name}({args}):"]
    out += _docstring(spec, "    ")
    for argument in spec.arguments:
        out.append(f"    {argument.name} = _as_vector({argument.name}, {len(argument.symbols)},"
                   f" {argument.name!r}, {spec.name!r})")
    batch = ", ".join(f"{a.name}.shape[1:]" for a in spec.arguments)
    out.append(f"    _batch = _np.broadcast_shapes({batch})")
    for local, argument, index in prepared.unpack:
        out.append(f"    {local} = {argument}[{index}]")
    assignments, entries = prepared.printed
    for name, text in assignments:
        out.append(f"    {name} = {_in_backend(text, _NUMPY_NAMES)}")
    shape = spec.numpy_shape
    out.append(f"    _out = _np.zeros({shape!r} + _batch)")
    for i, j, text in entries:
        target = f"_out[{i}, {j}]" if spec.matrix else f"_out[{i}]"
        out.append(f"    {target} = {_in_backend(text, _NUMPY_NAMES)}")
    out.append("    return _out")
    return "\n".join(out)


def emit_casadi_builder(prepared: _Prepared) -> str:
    """Source of a function that builds the ``casadi.Function`` of one spec."""
    spec = prepared.spec
    out = [f"def _build_{spec.name}():"]
    for argument in spec.arguments:
        out.append(f"    {argument.name} = _m.SX.sym({argument.name!r}, {len(argument.symbols)})")
    for local, argument, index in prepared.unpack:
        out.append(f"    {local} = {argument}[{index}]")
    assignments, entries = prepared.printed
    for name, text in assignments:
        out.append(f"    {name} = {_in_backend(text, _CASADI_NAMES)}")
    rows, cols = spec.result.shape
    out.append(f"    _out = _m.SX({rows}, {cols})")
    for i, j, text in entries:
        out.append(f"    _out[{i}, {j}] = {_in_backend(text, _CASADI_NAMES)}")
    names = ", ".join(a.name for a in spec.arguments)
    labels = ", ".join(repr(a.name) for a in spec.arguments)
    out.append(f"    return _m.Function({spec.name!r}, [{names}], [_out], [{labels}], ['out'])")
    return "\n".join(out)
