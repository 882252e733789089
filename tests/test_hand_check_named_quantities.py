"""What a coefficient slip is, told in the terms the researcher wrote.

``tests/models/marine_ins.py`` (a marine probe's own file) writes its north channel with
a named quantity, ``dV_N/dt = a_N − ρ V_E`` with ρ = 2U sin φ + V_E tan φ/R, and damps
the loops through constant gains, ``α̇_N = ... + K2 δV_E/R + δV_E/R ...`` (1 + K2). Two
slips a hand derivation makes there:

* the coefficient of δV_E in δV̇_N written out as −(2U sin φ + V_E tan φ/R): the
  variation of ρ V_E gives −ρ − V_E tan φ/R = −2U sin φ − 2 V_E tan φ/R, so one
  V_E tan φ/R is missing. It was told as "model has −ρ where the hand has −2U sin φ"
  (ρ is the model's name, and the hand's 2U sin φ is right);
* K2/R written for (1 + K2)/R: the part 1/R is left out. With the gain a constant the
  two keep the ratio K2/(1 + K2) at every point, and it was told as a "wrong
  coefficient, hand/model = 0.75".
"""

from __future__ import annotations

from pathlib import Path

import pytest

from ins_errors.checker.compare import check_hand, resolve_model
from ins_errors.checker.notation import default_notation
from ins_errors.checker.parse import parse_hand_text

MODEL = str(Path(__file__).resolve().parent / "models" / "marine_ins.py")

LINES = """\
dot(delta_V_N) = g*alpha_E - a_E*alpha_U + accel_bias_north - (2*U*sin(phi) + V_E*tan(phi)/R)*delta_V_E - (2*U*V_E*cos(phi) + V_E**2/(R*cos(phi)**2))*delta_phi - K1*delta_V_N + K1*log_bias_north
dot(alpha_N) = -U*sin(phi)*delta_phi + K2*delta_V_E/R - K2*log_bias_east/R + gyro_drift_north - (U*sin(phi) + V_E*tan(phi)/R)*alpha_E - V_N/R*alpha_U
"""  # noqa: E501 (two lines of a hand file, as typed)


@pytest.fixture(scope="module")
def findings():
    definition = resolve_model(MODEL)
    hand = parse_hand_text(LINES, default_notation(definition))
    report = check_hand(hand, definition, effects=False)
    return {(r.equation.line, f.quantity): f for r in report.results for f in r.findings}


def test_a_term_left_out_beside_a_named_quantity_is_told_in_written_out_terms(findings):
    found = findings[(1, "delta_V_E")]
    assert "rho" not in found.detail
    assert found.detail == "model has -2*V_E*tan(phi)/R where the hand has -V_E*tan(phi)/R"
    assert found.severity.startswith("mistake")


def test_a_part_of_a_gain_coefficient_left_out_is_an_omitted_term(findings):
    found = findings[(2, "delta_V_E")]
    assert found.kind == "omitted term" and found.severity == "mistake"
    assert found.detail == "part of the coefficient is missing: 1/R"


def test_a_term_written_on_the_wrong_state_is_told_from_where_it_belongs():
    """north_pointing's azimuth row has V_N/(R+h)·α_N (the model's −ω_E α_N); a paper's
    line writes it on α_E beside the α_E term it has. The pairing picked the quantity with
    the larger model coefficient as the one that lost the term, and said backwards "the
    model's term (−U cos φ − ... + omega_N)*alpha_E is written on alpha_N". The
    quantity whose hand coefficient is 0 is the one that lost it."""
    line = ("dot(alpha_U) = tan(phi)*Delta_v_E/(R + h) + (Omega*cos(phi) + V_E/((R + h)*"
            "cos(phi)**2))*Delta_phi + (Omega*cos(phi) + V_E/(R + h))*alpha_E + "
            "V_N/(R + h)*alpha_E + epsilon_U")
    (finding,) = _north_pointing_findings(line)
    assert finding.quantity == "alpha_N -> alpha_E" and finding.kind == "wrong symbol or index"
    assert finding.detail.endswith("*alpha_N is written on alpha_E")


def test_a_dropped_coriolis_term_is_an_omitted_term_on_the_default_sphere():
    """north_pointing's radii are R/√(1 − e² sin²φ) + h with e² = 0 by default: a hand's
    R + h differed from them symbolically, so a line that dropped 2U sin φ beside a
    right V_E tan φ/(R + h) was a "wrong coefficient" whose detail printed the
    ellipsoid's radius. With the parameters that are 0 at every point set to 0 it is the
    omitted Coriolis term."""
    line = ("dot(Delta_v_E) = V_E*tan(phi)/(R + h)*Delta_v_N + V_N*(2*Omega*cos(phi) + "
            "V_E/((R + h)*cos(phi)**2))*Delta_phi + V_N*tan(phi)/(R + h)*Delta_v_E - "
            "f_U*alpha_N + a_N*alpha_U + nabla_E")
    (finding,) = _north_pointing_findings(line)
    assert finding.quantity == "delta_v_N" and finding.kind == "omitted term"
    assert finding.detail == "part of the coefficient is missing: 2*U*sin(phi)"


def _north_pointing_findings(text: str) -> list:
    """The findings of a hand file's text checked against north_pointing."""
    definition = resolve_model("north_pointing")
    report = check_hand(parse_hand_text(text, default_notation(definition)), definition,
                        effects=False)
    return [f for r in report.results for f in r.findings]


def test_north_pointing_reads_a_papers_radii_without_the_height():
    """north_pointing writes the radii with the height added (r_E = R_E + h); a paper's
    R_E + h was an unknown name R_E, and the suggested r_E read as R_E + h gave some
    twenty spurious mistakes. R_E and R_N now read as r_E − h and r_N − h: a right line
    written with them agrees."""
    line = ("dot(Delta_v_E) = (2*Omega*sin(phi) + V_E*tan(phi)/(R_E + h))*Delta_v_N + "
            "V_N*(2*Omega*cos(phi) + V_E/((R_E + h)*cos(phi)**2))*Delta_phi + "
            "V_N*tan(phi)/(R_E + h)*Delta_v_E - f_U*alpha_N + a_N*alpha_U + nabla_E")
    definition = resolve_model("north_pointing")
    hand = parse_hand_text(line, default_notation(definition))
    assert not hand.problems and len(hand.equations) == 1
    report = check_hand(hand, definition, effects=False)
    assert not report.problems  # was: unknown name 'R_E' (did you mean 'r_E'?)
    assert len(report.results) == 1 and not report.results[0].findings


def test_a_term_the_expansion_wrote_in_two_parts_is_no_difference():
    """A paper's azimuth-rate line writes d(V_E tan φ/R)/dφ as V_E tan φ/R (tan φ not
    differentiated). Beside it, its right U cos φ was told as a difference: expanding
    the model's U cos φ (R + h)/(R + h) gives R U cos φ/(R + h) + U h cos φ/(R + h), and
    the detail read "model has R*U*cos(phi)/(R + h) + U*h*cos(phi)/(R + h) + ... where
    the hand has U*cos(phi) + ...". Terms of one side that add up to a term of the other
    are no difference."""
    line = ("dot(alpha_U) = tan(phi)*Delta_v_E/(R + h) + (Omega*cos(phi) + V_E*tan(phi)/"
            "(R + h))*Delta_phi + (Omega*cos(phi) + V_E/(R + h))*alpha_E + "
            "V_N/(R + h)*alpha_N + epsilon_U")
    findings = {f.quantity: f for f in _north_pointing_findings(line)}
    found = findings["delta_latitude"]
    assert found.kind == "wrong coefficient"
    assert found.detail == ("model has V_E*tan(phi)**2/(R + h) + V_E/(R + h) where the hand "
                            "has V_E*tan(phi)/(R + h)")
