"""The checker's shortcuts give exactly what the plain SymPy operations give.

Each shortcut exists only to save time; the reports must not change by one character, so
each is compared here with the plain computation it replaces, structurally (``srepr``),
on the model's own variations.
"""

from __future__ import annotations

import pytest
import sympy as sp

from ins_errors.checker.compare import _split_by_substitution
from ins_errors.checker.sides import model_side
from ins_errors.models import definition


def _plain_split(expr: sp.Expr, present: list[sp.Symbol]):
    zero = {b: sp.S.Zero for b in present}
    constant = expr.xreplace(zero)
    return {b: expr.xreplace({**zero, b: sp.S.One}) - constant for b in present}, constant


def test_split_by_substitution_is_plain_xreplace():
    side = model_side(definition("orthodromic"))
    basis = [*side.error_states.values(), *side.source_symbols.values()]
    expressions = [*side.state_rhs.values(), *side.delta_of.values()]
    assert len(expressions) > 20
    split = 0
    for expr in expressions:
        free = expr.free_symbols
        present = [b for b in basis if b in free]
        coefficients, constant = _split_by_substitution(expr, present)
        plain, plain_constant = _plain_split(expr, present)
        assert sp.srepr(constant) == sp.srepr(plain_constant)
        assert list(coefficients) == list(plain)
        for b in present:
            assert sp.srepr(coefficients[b]) == sp.srepr(plain[b]), (expr, b)
        split += len(present)
    assert split > 50


def test_kept_parses_follow_the_notation():
    """A parse kept for one notation is never handed to another."""
    from ins_errors.checker.notation import Notation
    from ins_errors.checker.parse import parse_latex_expression, parse_text_expression

    plain, spelled = Notation(), Notation(spellings={"w_xi": "omega_xi"})
    for _ in range(2):  # the second round reads the kept results
        assert parse_text_expression("2*w_xi", plain)[0] == 2 * sp.Symbol("w_xi")
        assert parse_text_expression("2*w_xi", spelled)[0] == 2 * sp.Symbol("omega_xi")
        assert parse_text_expression("2*w_xi", plain, column=5)[1] == {"w_xi": 7}
    primed = Notation(latex_primes={"omega": "omega_rel"})
    assert parse_latex_expression(r"\omega'_\xi", Notation())[0] == sp.Symbol("omegap_xi")
    assert parse_latex_expression(r"\omega'_\xi", primed)[0] == sp.Symbol("omega_rel_xi")
    # the caller may change the columns it gets without changing the kept ones
    parse_text_expression("2*w_xi", plain)[1].clear()
    assert parse_text_expression("2*w_xi", plain)[1] == {"w_xi": 3}


def _forget_kept_results() -> None:
    """Empty every per-process cache of the checker (as in a fresh interpreter)."""
    from ins_errors.checker import classify, compare, parse, realwork, sides

    for kept in (compare._shared_linear_parts, compare._identical, compare._display,
                 compare._shown, classify._candidates, compare._first_nonlinear,
                 sides._tautology, sides._identified_expr, sides._symbols_of,
                 sides._substituted, parse._parsed_text,
                 parse._parsed_latex, realwork._first_order_outputs, realwork._split,
                 realwork._varied_rate):
        kept.cache_clear()
    for side in sides._SHARED.values():
        side[1]._varied.clear()
    compare._SHARED.clear()  # reference points and their evaluated coefficients


def test_a_check_after_other_checks_equals_one_with_nothing_kept():
    """The kept splits, comparisons, tautologies, parses and real-work expansions change
    no report (the manual's file has real-work lines)."""
    from ins_errors.checker.compare import check_hand
    from ins_errors.checker.notation import default_notation
    from ins_errors.checker.parse import parse_hand_text
    from ins_errors.checker.report import to_json
    from tests.test_hand_check import CORRECT, MANUAL

    def report(text):
        hand = parse_hand_text(text, default_notation("orthodromic"))
        return to_json(check_hand(hand, threshold=1e-3, effects=False))

    wrong = CORRECT.replace("- a_zeta*alpha_y", "+ a_zeta*alpha_y")
    manual = (MANUAL / "equations.txt").read_text(encoding="utf-8")
    report(CORRECT)
    warm = report(wrong), report(manual)
    _forget_kept_results()
    cold = report(wrong), report(manual)
    assert warm == cold
    assert warm[0]["summary"]["findings"]["mistakes"] >= 1
    assert any(e["compared_with"].startswith("real work") for e in warm[1]["equations"])


def test_checks_run_with_one_blas_thread_and_restore_the_pools():
    from threadpoolctl import threadpool_info

    from ins_errors.numeric.blas_threads import one_blas_thread

    def blas_threads():
        return [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]

    before = blas_threads()
    inside = one_blas_thread(blas_threads)()
    assert inside and set(inside) == {1}
    assert blas_threads() == before


_EXPONENTIALS_IN_A_FRESH_PROCESS = """
import json
import sys

import numpy as np
from threadpoolctl import threadpool_info

from ins_errors.numeric.blas_threads import one_blas_thread

assert "scipy.linalg" not in sys.modules  # loaded only on first use, as in a check or budget
seen = []


def recording(function):  # the BLAS pools' threads just after a call inside the limit
    def recorded(*args):
        result = function(*args)
        seen.extend(p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas")
        return result
    return recorded


def schuler_system():  # 2 states (tilt rad, velocity error m/s), accelerometer bias
    from ins_errors.numeric.linear_system import LinearSystem

    times = np.arange(0.0, 3601.0, 600.0)
    F = np.array([[0.0, 1.0 / 6.371e6], [-9.81, 0.0]])
    G, E, H = np.array([[0.0], [1.0]]), np.zeros((2, 1)), np.eye(2)
    return LinearSystem(times, F, G, E, H, ("accel_bias",), ("constant",),
                        np.zeros((1, 7)), np.zeros((1, 7)), np.zeros(1))


def covariance():
    from ins_errors.analysis import covariance as cv

    cv._expm = recording(cv._expm)  # the first call imports SciPy
    system = schuler_system()
    functionals = cv.Functionals(("tilt", "dv"), ("rad", "m/s"), np.eye(2), np.zeros((2, 1)))
    cv.propagate(system, [cv.SourceStatistics("accel_bias", "constant", 1e-3)], functionals)


@one_blas_thread  # the check's own limit, set before SciPy (and its BLAS) is loaded
def effect():
    from ins_errors.checker import effect

    np.linalg.matrix_power = recording(np.linalg.matrix_power)  # called after SciPy's expm
    effect._propagate(np.eye(3) * 1e-4, np.ones(3), np.ones(3))


{"covariance": covariance, "effect": effect}[sys.argv[1]]()
assert "scipy.linalg" in sys.modules
after = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
print(json.dumps({"inside": sorted(set(seen)), "libraries": len(after),
                  "after": sorted(set(after))}))
"""


@pytest.mark.parametrize("where", ["effect", "covariance"])
def test_exponentials_run_with_one_blas_thread_of_every_library(where):
    """SciPy brings its own BLAS, loaded on first use of its exponential, after numpy's BLAS
    was limited to one thread (by a check, or by covariance propagation): the exponentials
    must run single-threaded in that one too (with two threads each 12 x 12 exponential
    cost ~7 ms of CPU instead of ~0.1 ms)."""
    import json
    import os
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", _EXPONENTIALS_IN_A_FRESH_PROCESS, where],
                          capture_output=True, text=True, check=True,
                          env={**os.environ, "OPENBLAS_NUM_THREADS": "2"})
    pools = json.loads(done.stdout)
    assert pools["inside"] == [1]
    assert pools["libraries"] >= 2  # numpy's and SciPy's: both were limited
    assert pools["after"] == [2]  # and both given back their threads when the call ended


def _forget_kept_values() -> None:
    """Empty the evaluated coefficients (and reference points) the checker keeps: the one
    kept result that could depend on what was checked before (a value compiled in a
    batch may differ in its last bit from the same value in another batch). The kept
    symbolic results are pure functions of their arguments
    (test_a_check_after_other_checks_equals_one_with_nothing_kept)."""
    from ins_errors.checker import compare

    compare._SHARED.clear()


def test_reports_do_not_depend_on_the_order_of_the_checks():
    """Kept coefficient values depend on the batch they were evaluated in (last bit);
    exact ties such as the manual's "hand/model = 2 at every point" (lines 50-51) must
    still name the same point whichever check ran first. (With numpy's argmax in place
    of checker.extreme the manual's reports differ between the two orders.)"""
    from ins_errors.checker.compare import check_hand
    from ins_errors.checker.notation import default_notation
    from ins_errors.checker.parse import parse_hand_text
    from ins_errors.checker.report import to_json, to_markdown
    from tests.test_hand_check import CORRECT, MANUAL

    manual = (MANUAL / "equations.txt").read_text()
    wrong = CORRECT.replace("- a_zeta*alpha_y", "+ a_zeta*alpha_y")

    def report(text):
        result = check_hand(parse_hand_text(text, default_notation("orthodromic")),
                            threshold=1e-3, effects=False)
        return to_json(result), to_markdown(result)

    _forget_kept_values()
    manual_first, wrong_second = report(manual), report(wrong)
    _forget_kept_values()
    wrong_first, manual_second = report(wrong), report(manual)
    assert manual_first == manual_second
    assert wrong_first == wrong_second
    tied = [f for r in manual_first[0]["equations"] if r["line"] in (50, 51)
            for f in r["findings"] if "= 2 at every point" in f["detail"]]
    assert tied and {f["point"] for f in tied} == {"static base"}


def test_first_largest_ignores_last_bit_differences():
    import numpy as np

    from ins_errors.checker.extreme import at_least, first_largest, first_largest_item

    half = 0.5
    above = np.nextafter(half, 1.0)
    # the same tie with the last bit landing on either point: the first point both times
    assert first_largest(np.array([0.1, half, above, 0.2])) == 1
    assert first_largest(np.array([0.1, above, half, 0.2])) == 1
    assert first_largest(np.array([2.0 * (1 - 4e-16), 2.0, 1.0])) == 0
    # a real difference (1e-9 relative) still picks the larger one
    assert first_largest(np.array([half, half * (1 + 1e-9)])) == 1
    assert first_largest(np.array([-3.0, -1.0, np.nextafter(-1.0, 0.0)])) == 1
    # non-finite largest values: their first occurrence, as numpy.argmax
    assert first_largest(np.array([1.0, np.inf, np.inf])) == 1
    assert first_largest(np.array([1.0, np.nan, 2.0])) == 1
    assert at_least(half, above) and at_least(above, half)
    assert not at_least(half, half * (1 + 1e-9))
    assert at_least(np.inf, np.inf) and not at_least(1.0, np.inf)
    items = [("a", half), ("b", above), ("c", 0.3)]
    assert first_largest_item(items, lambda item: item[1])[0] == "a"
    assert first_largest_item(items[::-1], lambda item: item[1])[0] == "b"


def _first_nonlinear_by_diff(form: sp.Expr, errors: tuple[sp.Symbol, ...]):
    for b in errors:
        derivative = sp.diff(form, b)
        if any(q in derivative.free_symbols and sp.diff(derivative, q) != 0 for q in errors):
            return b
    return None


def test_linearity_read_off_the_tree_is_the_differentiated_answer():
    """The structural shortcut of the linearity check answers what differentiation
    answers, on every printed form of the orthodromic hand files (the manual's and the
    independent derivation) and on added linear and non-linear forms."""
    from pathlib import Path

    from ins_errors.checker.compare import _first_nonlinear
    from ins_errors.checker.notation import default_notation
    from ins_errors.checker.parse import parse_hand_text
    from ins_errors.checker.sides import HandSide, model_side, tilde_variations

    root = Path(__file__).resolve().parent.parent
    files = [(root / "tests" / "data" / "hand_correct_orthodromic.txt", "orthodromic"),
             (root / "examples" / "manual_000" / "equations.txt", "orthodromic")]
    extra = ["alpha_z**2 + omega_zeta*alpha_y", "sin(alpha_z)*omega_eta",
             "alpha_z*alpha_y", "omega_xi/alpha_z", "sqrt(alpha_z)*U", "U**alpha_z",
             "(alpha_z + alpha_y)**2 - alpha_z**2 - alpha_y**2",
             "(U + alpha_z)*(omega_xi - alpha_y)", "(omega_xi + U)**3*alpha_y",
             "cos(phi + alpha_z)", "alpha_z*omega_xi*(1 + U)**2 - 2*alpha_y/R_xi"]
    checked = nonlinear = 0
    for path, model in files:
        notation = default_notation(model)
        text = path.read_text(encoding="utf-8")
        if path.name.startswith("hand_correct"):
            text += "".join(f"\nDelta_X{k} = {rhs}" for k, rhs in enumerate(extra))
        hand = parse_hand_text(text, notation)
        resolver = HandSide(model_side(definition(model)), notation, hand)
        for eq in hand.equations:
            for form in eq.forms:
                form = form.xreplace(tilde_variations(form))
                errors = tuple(s for s in sorted(form.free_symbols, key=sp.default_sort_key)
                               if resolver.is_variational(s))
                expected = _first_nonlinear_by_diff(form, errors)
                assert _first_nonlinear.__wrapped__(form, errors) == expected, form
                checked += 1
                nonlinear += expected is not None
    assert checked > 90 and nonlinear >= 8, (checked, nonlinear)


def test_node_by_node_values_equal_the_compiled_functions():
    """The checker's node-by-node evaluation (checker.tree_values) gives the values
    SymPy's compiled functions give, to rounding, on the model's variations, their
    coefficients and the differences the checker builds from them; a node it does not
    evaluate (Piecewise) is left to the compiled function; non-finite results stay
    NaN/inf as in the compiled code."""
    import itertools

    import numpy as np

    from ins_errors.checker.compare import _points
    from ins_errors.checker.tree_values import TreeValues, UnsupportedError

    d = definition("orthodromic")
    side = model_side(d)
    points = _points(d, None)[0].points
    arguments = sorted(points[0].values, key=sp.default_sort_key)
    arrays = [np.array([p.values[s] for p in points]) for s in arguments]
    basis = [*side.error_states.values(), *side.source_symbols.values()]
    exprs = []
    for expr in [*side.state_rhs.values(), *side.delta_of.values()]:
        free = expr.free_symbols
        coefficients, _ = _split_by_substitution(expr, [b for b in basis if b in free])
        exprs += [c for c in coefficients.values() if c.free_symbols <= set(arguments)]
    exprs += [a - 2 * b for a, b in itertools.pairwise(exprs)]
    assert len(exprs) > 100
    tree = TreeValues(arguments, arrays)
    ours = np.array([np.broadcast_to(tree.value(e), (len(points),)) for e in exprs])
    compiled = sp.lambdify(arguments, exprs, "numpy", cse=True)(*arrays)
    compiled = np.array([np.broadcast_to(v, (len(points),)) for v in compiled])
    scale = np.max(np.abs(compiled), axis=1, keepdims=True)
    assert np.all(np.abs(ours - compiled) <= 1e-13 * np.maximum(scale, 1e-300))
    assert np.count_nonzero(scale) > 100

    x, y = sp.symbols("x y", real=True)
    small = TreeValues([x, y], [np.array([-4.0, 0.0, 9.0]), np.array([0.0, 2.0, 3.0])])
    with np.errstate(all="ignore"):
        root = small.value(sp.sqrt(x))
        quotient = small.value(x / y)
        assert np.isnan(root[0]) and root[2] == 3.0
        assert np.isinf(quotient[0]) and quotient[1] == 0.0 and quotient[2] == 3.0
    assert small.value(sp.I * x).dtype == complex
    for unsupported in (sp.Piecewise((x, y > 1), (y, True)), sp.Symbol("z")):
        try:
            small.value(unsupported + x)
        except UnsupportedError:
            continue
        raise AssertionError(f"{unsupported} was evaluated")


def test_reports_from_node_values_equal_reports_from_compiled_functions(monkeypatch):
    """The manual's report (every finding, size to 9 digits, point, effect) is the same
    whether the coefficients are evaluated node by node or by compiled functions (the
    way before checker.tree_values)."""
    from ins_errors.checker import tree_values
    from ins_errors.checker.compare import check_hand
    from ins_errors.checker.notation import default_notation
    from ins_errors.checker.parse import parse_hand_text
    from ins_errors.checker.report import to_json, to_markdown
    from tests.test_hand_check import MANUAL

    manual = (MANUAL / "equations.txt").read_text()

    def report():
        _forget_kept_values()
        result = check_hand(parse_hand_text(manual, default_notation("orthodromic")),
                            threshold=1e-3)
        return to_json(result), to_markdown(result)

    by_nodes = report()

    def refuse(self, expr):
        raise tree_values.UnsupportedError("compiled")

    monkeypatch.setattr(tree_values.TreeValues, "value", refuse)
    compiled = report()
    _forget_kept_values()
    assert by_nodes == compiled
    assert by_nodes[0]["summary"]["findings"]["mistakes"] >= 1
