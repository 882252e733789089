"""Model-file mistakes that passed the checks of tests/test_model_file_checks_ecef.py.

* A function that is not smooth at zero error (``sp.Abs(bias)``, ``sp.Max``, ``sp.sign``,
  ``sp.Heaviside``, ``sp.floor``, ``sp.Mod``) of an error source or a computed state:
  its second derivative is a DiracDelta (or SymPy has no derivative of it), and
  ``compare`` ended in a traceback from the code printer. The error model is a Taylor
  expansion at zero error, where a kink has no derivative: refused in one line naming
  the equation and the function. The same functions of the true state, an input or a
  parameter are constants of that expansion and stay accepted.
* ``sp.Piecewise`` failed the dimension check whatever its branches ("the argument must
  be a pure number"): its dimension is now that of its branches, and its conditions
  compare quantities of one dimension.
* A real work written with the true state instead of the computed one (no computed state
  in any row) was accepted, and its F had no feedback: refused.
* An undefined symbol in the ideal work got the real work's hint.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from ins_errors.cli import main
from tests.helpers import fresh_model_cache

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
ECEF = ROOT / "tests" / "models" / "ecef_ins.py"
VELOCITY_SPHERE = ROOT / "tests" / "models" / "velocity_sphere.py"
G, R = 9.80665, 6_371_000.0
ACCEL_TERM = "g * sp.sin(psi) + bias,"
"""The end of the tutorial's accelerometer line (f = a_N cos ψ − g sin ψ + ∇)."""


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """Generated code of model files goes to a fresh cache per test."""
    return fresh_model_cache(tmp_path, monkeypatch)


def variant(tmp_path: Path, source: Path, *replacements: tuple[str, str],
            name: str = "my_model.py") -> Path:
    """A copy of a model file with text replacements."""
    text = source.read_text(encoding="utf-8")
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new)
    target = tmp_path / name
    target.write_text(text, encoding="utf-8")
    return target


def refusal(arguments: list[str], capsys) -> str:
    """The one line a command refuses a model file with (exit status 2)."""
    assert main(arguments) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ins-errors: error: "), captured.err
    assert "Traceback" not in captured.err
    return lines[0]


def compare(path: Path, capsys, source: str = "accel_bias=100ug") -> dict:
    """The one case of `compare` over 1 h at rest, as JSON."""
    assert main(["compare", str(path), "--source", source, "--hours", "1", "--step", "60s",
                 "--no-refined", "--json"]) == 0, capsys.readouterr().err
    [case] = json.loads(capsys.readouterr().out)["cases"]
    return case


def schuler_tilt_peak(bias: float) -> float:
    """Largest |ψ| over 1 h sampled each minute at rest for an accelerometer bias (m/s²):
    ψ = (∇/g)(1 − cos ω_s t), ω_s = √(g/R) (the loop's closed form, to first order)."""
    omega = math.sqrt(G / R)
    return max(bias / G * (1 - math.cos(omega * 60.0 * k)) for k in range(61))


NOT_SMOOTH = {
    # accelerometer term, the function the line must name, what it is a function of
    "abs_source": ("sp.Abs(bias)", "Abs(accel_bias)", "error source accel_bias"),
    "abs_difference": ("sp.Abs(V_c - V) * V / R", "Abs(V - V_c)", "computed state V_c"),
    "sqrt_square": ("sp.sqrt(bias**2)", "Abs(accel_bias)", "sqrt(x**2) is Abs(x)"),
    "sign": ("sp.sign(bias) * bias", "sign(accel_bias)", "error source accel_bias"),
    "heaviside": ("sp.Heaviside(bias) * bias", "Heaviside(accel_bias)",
                  "error source accel_bias"),
    "max": ("sp.Max(bias, 0)", "Max(0, accel_bias)", "where its arguments are equal"),
    "min": ("sp.Min(bias, 2 * bias)", "Min(", "where its arguments are equal"),
    "floor": ("g * sp.floor(psi)", "floor(psi)", "error state psi"),
    "mod": ("g * sp.Mod(psi, 1)", "Mod(psi, 1)", "error state psi"),
    # Max(b, 0) written as a Piecewise: accepted with G = 0 (the source unseen)
    "piecewise_at_zero": ("sp.Piecewise((bias, bias > 0), (0, True))",
                          "condition accel_bias > 0, of the error source accel_bias",
                          "changes at zero error"),
}


def test_compare_of_abs_of_an_error_source_is_refused_in_one_line(tmp_path, capsys):
    """|∇| in the accelerometer: d²|∇|/d∇² = 2 δ(∇) reached the code printer, and
    compare ended in PrintMethodNotImplementedError ... DiracDelta. |a_N| is fine."""
    path = variant(tmp_path, SCHULER, (ACCEL_TERM, "g * sp.sin(psi) + sp.Abs(bias),"))
    line = refusal(["compare", str(path), "--source", "accel_bias=100ug", "--hours", "1",
                    "--step", "60s", "--no-refined"], capsys)
    assert "intermediate f_c of the real mechanisation" in line, line
    assert "Abs(accel_bias)" in line and "Taylor expansion" in line, line
    assert "DiracDelta" not in line, line
    # |a_N| scaling the bias is a constant of the expansion in the errors: accepted; at
    # rest a_N = 0, so the loop is the tutorial's and the tilt peaks at the closed form
    path = variant(tmp_path, SCHULER,
                   (ACCEL_TERM, "g * sp.sin(psi) + bias * (1 + sp.Abs(a_N) / g),"),
                   name="abs_input.py")
    case = compare(path, capsys)
    [psi] = [m for m in case["metrics"] if m["quantity"] == "psi"]
    assert psi["max_direct"] == pytest.approx(schuler_tilt_peak(1e-4 * G), rel=1e-6)


@pytest.mark.parametrize("case", NOT_SMOOTH, ids=list(NOT_SMOOTH))
def test_function_not_smooth_at_zero_error_is_refused(case, tmp_path, capsys):
    term, function, words = NOT_SMOOTH[case]
    path = variant(tmp_path, SCHULER, (ACCEL_TERM, f"g * sp.sin(psi) + bias + {term},"))
    line = refusal(["models", str(path)], capsys)
    for word in ("intermediate f_c of the real mechanisation", function, words,
                 "Taylor expansion"):
        assert word in line, (word, line)


def test_abs_of_an_initial_source_and_jumps_of_an_output_are_refused(tmp_path, capsys):
    """|ψ₀| as the initial tilt was accepted with E = sign(0) = 0 (the linear model saw
    no initial tilt at all); Mod or sign of a state in an output has no derivative for H
    (a traceback from the code printer)."""
    path = variant(tmp_path, SCHULER, ("sp.Matrix([v0, lat0, tilt0])",
                                       "sp.Matrix([v0, lat0, sp.Abs(tilt0)])"))
    line = refusal(["models", str(path)], capsys)
    assert "initial_real_state for 'psi'" in line and "Abs(initial_tilt)" in line, line
    path = variant(tmp_path, SCHULER, ("sp.Matrix([latitude, velocity])",
                                       "sp.Matrix([latitude, sp.Mod(velocity, 100)])"),
                   name="mod_output.py")
    line = refusal(["models", str(path)], capsys)
    assert "output 'v_N'" in line and "Mod(V, 100)" in line, line
    path = variant(tmp_path, SCHULER, ("sp.Matrix([latitude, velocity])",
                                       "sp.Matrix([latitude, sp.sign(velocity) * velocity])"),
                   name="sign_output.py")
    line = refusal(["models", str(path)], capsys)
    assert "output 'v_N'" in line and "sign(V)" in line and "output matrix H" in line, line


def test_piecewise_takes_the_dimension_of_its_branches(tmp_path, capsys):
    """A bias clipped at g/100: the branches are in m/s², the condition compares m/s²
    with m/s². Refused before ("the argument must be a pure number"); at 100 µg the
    clip is inactive and the tilt peaks at the closed form of the plain bias."""
    clipped = "sp.Piecewise((bias, bias < g / 100), (g / 100, True))"
    path = variant(tmp_path, SCHULER, (ACCEL_TERM, f"g * sp.sin(psi) + {clipped},"))
    case = compare(path, capsys)
    [psi] = [m for m in case["metrics"] if m["quantity"] == "psi"]
    assert psi["max_direct"] == pytest.approx(schuler_tilt_peak(1e-4 * G), rel=1e-6)
    assert case["worst_linear_ratio"] < 1e-6


@pytest.mark.parametrize(("term", "words"), [
    ("sp.Piecewise((bias, a_N > 0), (V_c / R, True))",
     "a Piecewise with branches in m/s**2 (accel_bias) and 1/s (V_c/R)"),
    ("sp.Piecewise((bias, V_c > a_N), (0, True))",
     "a condition V_c > a_N comparing m/s and m/s**2"),
], ids=["branches", "condition"])
def test_piecewise_of_mixed_dimensions_is_refused(term, words, tmp_path, capsys):
    path = variant(tmp_path, SCHULER, (ACCEL_TERM, f"g * sp.sin(psi) + {term},"))
    line = refusal(["models", str(path)], capsys)
    assert "intermediate f_c of the real mechanisation" in line and words in line, line


def test_real_work_written_in_the_true_state_is_refused(tmp_path, capsys):
    """navigator(real, x, ...) for navigator(real, computed, ...): the real work then
    integrates the true state, F has no feedback and `modes` finds only integrators. Rows
    without a computed state are fine as long as some row has one (velocity_sphere's
    position rows), and so is a real work with no state at all (an integrator of its
    inputs, tests/test_degenerate_models.py's bare integrator)."""
    path = variant(tmp_path, ECEF, ("real_rhs=sp.Matrix(navigator(real, computed,",
                                    "real_rhs=sp.Matrix(navigator(real, x,"))
    line = refusal(["modes", str(path)], capsys)
    for word in ("real-work equations (real_rhs)", "use the true state (CXx, CXy, CXz, ...) "
                 "but none of the computed states",
                 "(CXx_c, CXy_c, CXz_c, ...)", "computed_symbols(STATES)",
                 "sensor inputs"):
        assert word in line, (word, line)
    path = variant(tmp_path, SCHULER, ('real.let("omega", V_c / R', 'real.let("omega", V / R'),
                   name="true_schuler.py")
    line = refusal(["models", str(path)], capsys)
    assert "use the true state (V) but none of the computed states (V_c, phi_c)" in line, line
    assert main(["models", str(VELOCITY_SPHERE)]) == 0, capsys.readouterr().err


@pytest.mark.parametrize(("symbol", "words"), [
    ("V_c", "V_c is a computed state: the ideal work is written in the true state"),
    ("bias", "accel_bias is an error source: the ideal work has no errors"),
    ("sp.Symbol('k')", "the ideal work may use the states, inputs and parameters and "
                       "its own intermediates"),
], ids=["computed_state", "source", "unknown"])
def test_undefined_symbol_in_the_ideal_work_gets_a_hint_for_the_ideal_work(
        symbol, words, tmp_path, capsys):
    path = variant(tmp_path, SCHULER, ("ideal_rhs = sp.Matrix([a_N, omega])",
                                       f"ideal_rhs = sp.Matrix([a_N + {symbol}, omega])"))
    line = refusal(["models", str(path)], capsys)
    assert "ideal-work equation (ideal_rhs) for 'V': uses undefined symbol" in line, line
    assert words in line, line
    assert "intermediate of the real mechanisation" not in line, line


def test_piecewise_max_sign_heaviside_floor_print_elementwise_for_both_backends():
    """SymPy's Python printer writes ``a if c else b``, ``max(a, b)`` and
    ``math.copysign``: a numpy array or a CasADi symbol has no truth value, so a model
    with a Piecewise (or Max of an input) failed in its generated code. Reference: SymPy
    evaluating each expression at each point itself (ties and zeros included)."""
    import casadi as ca
    import numpy as np
    import sympy as sp

    from ins_errors.symbolic.codegen import CASADI_PRINTER, NUMPY_PRINTER

    x, y = sp.symbols("x y", real=True)
    expressions = [
        sp.Piecewise((x, x > 0), (y / 2, x < y), (x * y, True)),
        sp.Piecewise((x + y, (x > 0) & (y < 1) | sp.Not(x < y)), (2 * x, y < 0)),  # else nan
        sp.Max(x, y, 1), sp.Min(x, -y), sp.sign(x - y), sp.Heaviside(x), sp.Heaviside(x, 0),
        sp.floor(3 * x), sp.ceiling(x - y), sp.Abs(x) * sp.sign(y),
    ]
    xs = np.array([-1.5, -0.25, 0.0, 0.0, 0.5, 0.5, 2.0, 1.0])
    ys = np.array([0.5, -2.0, 0.0, 3.0, 0.5, -1.0, 2.0, 1.5])
    sx, sy = ca.SX.sym("x"), ca.SX.sym("y")
    for expr in expressions:
        expected = np.array([float(expr.subs({x: sp.Rational(a), y: sp.Rational(b)}))
                             for a, b in zip(xs, ys, strict=True)])
        got_np = eval(NUMPY_PRINTER.doprint(expr), {"_m": np, "x": xs, "y": ys})
        function = ca.Function("f", [sx, sy], [eval(CASADI_PRINTER.doprint(expr),
                                                     {"_m": ca, "x": sx, "y": sy})])
        got_ca = np.array([float(function(a, b)) for a, b in zip(xs, ys, strict=True)])
        for got in (np.broadcast_to(got_np, xs.shape), got_ca):
            assert np.array_equal(got, expected, equal_nan=True), (expr, got, expected)
