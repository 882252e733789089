"""Differentiation and substitution that visit each distinct subtree once.

A model's closed equations (every intermediate substituted) are trees with few distinct
subtrees repeated many times: the expanded real-work equations of ``geodetic_vertical``
have about 7,500 nodes but 170 distinct ones. SymPy's ``diff`` and ``xreplace`` walk
every repetition, and each ``Derivative`` it builds walks its whole operand again
(``free_symbols``, ``is_zero``, a ``replace`` for nested derivatives), so the Jacobians
and second-order terms of ``make derive`` cost seconds per model.

:class:`SharedTrees` remembers, per distinct subtree, its free symbols, its derivative
by each symbol and its substitution under one rule. The results are the very
expressions SymPy returns (the same objects up to structural equality): the
derivative of a subtree is still computed by SymPy's own rule for that node
(``_eval_derivative_n_times``), only once, and the substitution rebuilds a node
exactly when ``Basic.xreplace`` would. Generated code printed from them is therefore
byte-identical.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping

import sympy as sp
from sympy.core.basic import _aresame
from sympy.core.expr import Expr
from sympy.matrices.expressions.matexpr import MatrixExpr

_UNION_NODES = (sp.Add, sp.Mul, sp.Pow, sp.Function)
"""Node types whose free symbols are the union of their arguments' (no bound symbols)."""


class SharedTrees:
    """Memo of free symbols, derivatives and substitutions of expression subtrees.

    One instance serves one derivation (one model); it keeps every subtree it saw
    alive, so drop it when done.
    """

    def __init__(self) -> None:
        self._free: dict[sp.Basic, frozenset] = {}
        self._derivatives: dict[tuple[sp.Basic, sp.Symbol], sp.Expr] = {}
        self._substituted: dict[frozenset, dict] = {}
        self._unevaluated: dict[sp.Basic, bool] = {}
        self._renames: list[tuple[dict, dict]] = []  # (symbol renames so far, their memo)

    def free_symbols(self, expr: sp.Basic) -> frozenset:
        """``expr.free_symbols``, computed once per distinct subtree."""
        try:
            return self._free[expr]
        except KeyError:
            pass
        if isinstance(expr, _UNION_NODES) and expr.args:
            found = frozenset().union(*(self.free_symbols(a) for a in expr.args))
        else:
            found = frozenset(expr.free_symbols)
        self._free[expr] = found
        return found

    def xreplace(self, expr: sp.Basic, rule: Mapping) -> sp.Basic:
        """``expr.xreplace(rule)`` (same result), each distinct subtree replaced once.

        The memo is per rule (by its items), so calls with equal rules share it.
        """
        memo = self._substituted.setdefault(frozenset(rule.items()), {})
        return self._xreplace(expr, rule, memo)[0]

    def xreplace_matrix(self, matrix: sp.Matrix, rule: Mapping) -> sp.Matrix:
        """``matrix.xreplace(rule)`` with :meth:`xreplace` on each entry."""
        return matrix.applyfunc(lambda e: self.xreplace(e, rule))

    def rename_matrix(self, matrix: sp.Matrix, rule: Mapping[sp.Symbol, sp.Symbol]) -> sp.Matrix:
        """``matrix.xreplace(rule)`` (same result) for a rule that renames symbols.

        The substitution of a subtree depends only on what the rule does to the subtree's
        own free symbols. When ``rule`` maps every free symbol of ``matrix``, it shares
        its memo with earlier calls whose rules agree with it on every symbol both
        name (the functions of one model rename their common arguments alike), so a
        subtree common to several of them is rebuilt once. Otherwise as
        :meth:`xreplace_matrix`.
        """
        free = frozenset().union(*(self.free_symbols(e) for e in matrix))
        if not free <= rule.keys():
            return self.xreplace_matrix(matrix, rule)
        used = {symbol: rule[symbol] for symbol in free}
        agreeing = [(renames, memo) for renames, memo in self._renames
                    if all(renames.get(symbol, new) == new for symbol, new in used.items())]
        if agreeing:
            renames, memo = agreeing[0]
            renames.update(used)
        else:
            memo = {}
            self._renames.append((dict(used), memo))
        return matrix.applyfunc(lambda e: self._xreplace(e, used, memo)[0])

    def _xreplace(self, expr: sp.Basic, rule: Mapping, memo: dict) -> tuple[sp.Basic, bool]:
        # mirrors Basic._xreplace: rebuild when any argument was replaced
        if expr in rule:
            return rule[expr], True
        if not rule or not expr.args:
            return expr, False
        try:
            return memo[expr]
        except KeyError:
            pass
        args, changed = [], False
        for a in expr.args:
            if isinstance(a, sp.Basic):
                value, hit = self._xreplace(a, rule, memo)
                args.append(value)
                changed |= hit
            else:
                args.append(a)
        result = (expr.func(*args), True) if changed else (expr, False)
        memo[expr] = result
        return result

    def subs(self, expr: sp.Basic, old: sp.Basic, new: sp.Basic) -> sp.Basic:
        """``expr.subs(old, new)`` (same result) for one SymPy pair, each distinct
        subtree visited once.

        Mirrors ``Basic._subs``: a node equal to ``old`` becomes ``new``; else the node's
        own ``_eval_subs`` (SymPy's, e.g. an Add matching part of its terms) decides,
        and failing that the node is rebuilt exactly when one of its arguments changed.
        SymPy decides "changed" by comparing the new argument with the old one node by
        node, which makes a substitution into a large tree quadratic in its depth; an
        argument that comes back as the very same object is unchanged without that walk.
        """
        memo = self._substituted.setdefault(("subs", old, new), {})
        return self._subs(expr, old, new, memo)

    def _subs(self, expr: sp.Basic, old: sp.Basic, new: sp.Basic, memo: dict) -> sp.Basic:
        try:
            return memo[expr]
        except KeyError:
            pass
        if type(expr)._subs is not _SYMPY_SUBS:  # a class with its own rule: SymPy's way
            result = expr._subs(old, new)
        elif _aresame(expr, old):
            result = new
        else:
            result = expr._eval_subs(old, new)
            if result is None:
                args, hit = list(expr.args), False
                for i, arg in enumerate(args):
                    if not hasattr(arg, "_eval_subs"):
                        continue
                    value = self._subs(arg, old, new, memo)
                    if value is not arg and not _aresame(value, arg):
                        args[i], hit = value, True
                result = expr.func(*args) if hit else expr
        memo[expr] = result
        return result

    def _has_derivative(self, expr: sp.Basic) -> bool:
        """``expr.has(sp.Derivative)``, once per distinct subtree."""
        try:
            return self._unevaluated[expr]
        except KeyError:
            pass
        found = isinstance(expr, sp.Derivative) or any(
            self._has_derivative(a) for a in expr.args if isinstance(a, sp.Basic))
        self._unevaluated[expr] = found
        return found

    def derivative(self, expr: sp.Expr, symbol: sp.Symbol) -> sp.Expr:
        """``sp.diff(expr, symbol)`` (same result); use inside :meth:`differentiating`."""
        key = (expr, symbol)
        try:
            return self._derivatives[key]
        except KeyError:
            pass
        if symbol not in self.free_symbols(expr):
            result = sp.S.Zero
        else:
            result = expr._eval_derivative_n_times(symbol, 1)
            if result is None or self._has_derivative(result):  # left for SymPy to finish
                result = _SYMPY_DIFF(expr, symbol)
        self._derivatives[key] = result
        return result

    @contextlib.contextmanager
    def differentiating(self) -> Iterator[SharedTrees]:
        """Route ``Expr.diff`` by one plain symbol through :meth:`derivative` in the block.

        SymPy's rules for sums, products, powers and functions differentiate their
        arguments with ``arg.diff(s)`` (or ``arg.diff((s, k))``, k = 0 or 1); inside the
        block those calls hit the memo, so a repeated subtree is differentiated once.
        Any other form of call goes to SymPy unchanged. Not thread-safe: the block
        swaps a method of ``sympy.Expr`` and restores it on exit.
        """
        if Expr.diff is not _SYMPY_DIFF:  # nested block: the outer memo serves
            yield self
            return

        def diff(expr, *symbols, **options):
            if (len(symbols) == 1 and not options
                    and not isinstance(expr, (sp.Derivative, MatrixExpr))):
                symbol, count = symbols[0], 1
                if isinstance(symbol, tuple) and len(symbol) == 2:
                    symbol, count = symbol
                if isinstance(symbol, sp.Symbol) and count in (0, 1):
                    return expr if count == 0 else self.derivative(expr, symbol)
            return _SYMPY_DIFF(expr, *symbols, **options)

        Expr.diff = diff
        try:
            yield self
        finally:
            Expr.diff = _SYMPY_DIFF


_SYMPY_DIFF = Expr.diff
_SYMPY_SUBS = sp.Basic._subs
