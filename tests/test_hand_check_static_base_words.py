"""Words of the hand check for a static-base F (source 001's lab report, a student's
slips): a ratio said where it was measured, a missing factor of the latitude named, and
a forgotten ``@scope static base`` advised as such.

The expected ratios are computed here from the latitude of the static base (50°), not read
from the checker: ``dVx/R`` where the model has ``tan(L) dVx/R`` is hand/model =
1/tan 50° at that point; the terms of a moving base (velocity and height terms) are 0 at
rest, which the file re-checked with ``@scope static base`` shows independently.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import sympy as sp

from ins_errors.checker import classify as cl
from ins_errors.checker.compare import check_hand, check_hand_file
from ins_errors.checker.notation import default_notation
from ins_errors.checker.parse import parse_hand_text
from ins_errors.checker.ratio_names import factors
from ins_errors.checker.report import to_json, to_markdown, to_terminal

DATA = Path(__file__).parent / "data"
F_BAD = DATA / "north_pointing_F_bad_static.txt"
PHI = np.radians(50.0)  # the static base's latitude


def _text_without_scope() -> str:
    return "".join(line for line in F_BAD.read_text().splitlines(keepends=True)
                   if not line.startswith("@scope"))


def _check_text(text: str):
    hand = parse_hand_text(text, default_notation("north_pointing"))
    return check_hand(hand, model="north_pointing", effects=False)


def _finding(report, line: int, quantity: str):
    return next(f for r, f in report.findings
                if r.equation.line == line and f.quantity == quantity)


def test_a_missing_tan_phi_is_named_at_the_one_reference_point():
    report = check_hand_file(F_BAD, model="north_pointing", effects=False)
    assert len(report.points) == 1
    f = _finding(report, 37, "delta_v_E")  # dot(Qz) = dVx/R + ...
    assert f.kind == cl.COEFFICIENT
    assert f.detail == (f"hand/model = {1 / np.tan(PHI):.6g} = cot(phi) at the one "
                        "reference point: a factor tan(phi) missing?")
    # one point: no finding of the run says "every point"
    assert not [g.detail for _, g in report.findings if "every point" in g.detail]
    assert "at every point" not in to_terminal(report)


def test_a_mirror_pair_at_one_point_is_said_at_the_one_reference_point():
    text = (F_BAD.read_text().replace(" - wie*cos(L)*Qz", "")
            .replace("dot(Qz) = dVx/R + wie*sin(L)*dL + wie*cos(L)*Qx",
                     "dot(Qz) = tan(L)*dVx/R + wie*cos(L)*dL"))
    report = _check_text(text)
    pair = [f.detail for _, f in report.findings if "exactly minus" in f.detail]
    assert len(pair) == 1 and "here at the one reference point" in pair[0]
    assert "every point" not in pair[0]


def test_trig_factor_names_each_function_and_its_inverse_tightly():
    from ins_errors.checker.ratio_names import trig_factor

    s, c = np.sin(PHI), np.cos(PHI)
    assert trig_factor(c / s, s, c) == ("cot(phi)", "a factor tan(phi) missing?")
    assert trig_factor(s / c, s, c) == ("tan(phi)", "a factor tan(phi) too many?")
    assert trig_factor(s, s, c) == ("sin(phi)", "a factor sin(phi) too many?")
    assert trig_factor(1 / c, s, c) == ("sec(phi)", "a factor cos(phi) missing?")
    assert trig_factor(-1 / s, s, c) == ("−csc(phi)",
                                         "a factor sin(phi) missing and the wrong sign?")
    assert trig_factor(0.8391, s, c) is None  # 1/tan 50° typed to 4 digits: not a name
    assert trig_factor(0.8390996, s, c) is None  # 4e-8 relative: not within 1e-9
    q = np.radians(45.0)  # tan = cot = 1: no name says which
    assert trig_factor(1.0, np.sin(q), np.cos(q)) is None


def test_a_factor_one_half_stays_one_half_where_sin_phi_is_one_half():
    phi, x = sp.symbols("phi x", real=True)
    at = {phi: np.pi / 6, x: 3.0}  # sin 30° = 0.5 (to rounding)

    def evaluate(exprs):
        return np.array([[complex(sp.N(e.subs(at)))] for e in exprs])

    hand, model = sp.tan(phi) * x / 2, sp.tan(phi) * x
    hs, ms = evaluate([hand, model])[:, 0].real.reshape(2, 1)
    kind, detail = cl.diagnose(hand, model, hs, ms, 1e-30, evaluate, [],
                               factors=factors(None, None))
    assert kind == cl.COEFFICIENT
    assert "1/2" in detail and "sin" not in detail, detail
    assert "at the one reference point" in detail


def test_an_exact_trig_factor_is_named_before_a_unit_slip_it_is_near():
    """At 1°, cot φ = 57.290 is within 1e-4 of the degree's 57.2958 (matched to 1e-3 as
    a rounded unit factor): the tan φ left out is named, not a unit slip."""
    phi, x = sp.symbols("phi x", real=True)
    at = {phi: np.radians(1.0), x: 3.0}

    def evaluate(exprs):
        return np.array([[complex(sp.N(e.subs(at)))] for e in exprs])

    hand, model = x, sp.tan(phi) * x
    hs, ms = evaluate([hand, model])[:, 0].real.reshape(2, 1)
    kind, detail = cl.diagnose(hand, model, hs, ms, 1e-30, evaluate, [],
                               factors=factors(None, None))
    assert kind == cl.COEFFICIENT
    assert "cot(phi)" in detail and "tan(phi) missing" in detail, detail
    assert "unit slip" not in detail


def test_a_static_base_file_without_scope_is_advised_to_say_so():
    report = _check_text(_text_without_scope())
    scoped = check_hand_file(F_BAD, model="north_pointing", effects=False)
    at_scope = {(r.equation.line - 1, f.quantity) for r, f in scoped.findings}  # one
    # line less: the @scope line
    roots = [(r.equation.line, f) for r, f in report.root_mistakes]
    # independent of the flag: a root marked 0 at rest is no finding at all at the
    # static base alone; the others are there (a mistake or a declared drop)
    assert {(n, f.quantity) for n, f in roots if not f.at_rest} <= at_scope
    assert not {(n, f.quantity) for n, f in roots if f.at_rest} & at_scope
    rest = sum(f.at_rest for _, f in roots) + sum(o.at_rest for o in report.omissions)
    counted = len(roots) + sum(o.is_mistake for o in report.omissions)
    assert 0 < rest < counted
    # the omitted turn-rate variation (V_E tan φ / R: 0 at rest) is advised as a scope,
    # not as a @neglect of a name the file never writes
    (omission,) = report.omissions
    assert omission.at_rest and "turn_rate" in omission.neglect
    terminal = to_terminal(report)
    # the model's own name is said with what it is, as the model defines it
    from ins_errors.models import definition

    (turn,) = [df for df in definition("north_pointing").ideal.definitions
               if df.symbol.name == "turn_rate"]
    assert f"(the model's turn_rate = {sp.sstr(turn.expression)})" in terminal
    assert "declare it with: @scope static base" in terminal
    assert "@neglect Delta_turn_rate" not in terminal
    assert f"static base? {rest} of the {counted} root mistakes are 0 at rest" in terminal
    assert "say so with @scope static base" in terminal
    assert "**Static base?**" in to_markdown(report)
    data = to_json(report)
    assert data["scope_advice"].startswith(f"{rest} of the {counted} root mistakes")
    assert data["omissions"][0]["at_rest"] is True
    # with the scope: no advice
    assert scoped.scope_advice == "" and to_json(scoped)["scope_advice"] is None


def test_a_moving_base_file_keeps_the_neglect_advice():
    # the same file with a velocity term written (a moving-base derivation): its
    # velocity-dependent slips are mistakes of its own, the omission a @neglect
    text = _text_without_scope().replace(
        "dot(Qz) = dVx/R + wie*sin(L)*dL",
        "dot(Qz) = tan(L)*dVx/R + V_E*dL/(R*cos(L)**2) + wie*cos(L)*dL")
    report = _check_text(text)
    assert report.scope_advice == ""
    assert report.omissions and not any(o.at_rest for o in report.omissions)
    terminal = to_terminal(report)
    assert "static base?" not in terminal
    assert "declare it with: @neglect" in terminal
