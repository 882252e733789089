"""The words of the matrix check for mistakes a Kalman-filter designer makes in F
written as code: a skew pair with a wrong sign (Coriolis), one of two equal terms left
out (ω_en × δv), a wrong gravity-gradient factor, a horizontal-only filter, and bad
returns of the hand's function.

Every hand model here is the derived F of ``strapdown_ned`` in the φ-geodetic
convention with one textbook term changed, the term written from the navigation
solution (Earth rate, transport rate, normal gravity) in the test, not by the package.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from ins_errors.checker import matrix as mc
from ins_errors.checker.conventions import convention
from ins_errors.checker.matrix_input import HandMatrices
from ins_errors.checker.matrix_report import to_terminal
from ins_errors.numeric.model import load_model

MODEL, CONV = "strapdown_ned", "phi_geodetic"


@pytest.fixture(scope="module")
def motions():
    return mc.motions(load_model(MODEL), hours=2.0, step=60.0)


@pytest.fixture(scope="module")
def derived(motions):
    """The derived F in the convention on every motion, and the state names."""
    model = load_model(MODEL)
    conv = convention(model, CONV)
    return {m.label: np.array(mc.derived_in_convention(model, conv, m)[0])
            for m in motions}, list(conv.names)


def _hand(derived, motions, edit, states=None) -> HandMatrices:
    """The derived F with ``edit(F, nav, index)`` applied on every motion, restricted
    to ``states`` (default all)."""
    F0, names = derived
    states = states or names
    keep = [names.index(s) for s in states]
    out = {}
    for m in motions:
        F = F0[m.label].copy()
        edit(F, m.navigation, names.index)
        out[m.label] = F[:, keep][:, :, keep]
    return HandMatrices("edited", list(states), [], out, {})


def _radius_e(nav):
    a, e2 = 6378137.0, 6.69437999014e-3
    return a / np.sqrt(1 - e2 * np.sin(nav["latitude"]) ** 2)


def _rho_d(nav):
    """Transport rate, down component: −v_E tan φ / (R_E + h), rad/s."""
    return -nav["v_ned"][1] * np.tan(nav["latitude"]) / (_radius_e(nav) + nav["height"])


def _check(hand, motions, effects=False):
    return mc.check_matrices(MODEL, hand, CONV, motion_list=motions, effects=effects)


# 2. one of two equal terms left out -------------------------------------------------
def test_one_of_two_equal_terms_left_out_names_both(derived, motions):
    """ω_en × δv left out of F[dv_N, dv_E]: the hand keeps −v_E tan φ/(R_E + h) of
    Δρ_D v_E and leaves out ρ_D of (2Ω + ρ) × δv, which is equal to it at every sample.
    Neither is named with confidence: both, as one of two equal terms."""
    def edit(F, nav, i):
        F[:, i("dv_N"), i("dv_E")] -= _rho_d(nav)  # the entry less ρ_D
    report = _check(_hand(derived, motions, edit), motions)
    [f] = report.findings
    assert (f.entry, f.kind) == ("F[dv_N, dv_E]", "omitted term")
    assert "one of 2 terms of the entry equal in value at every sample" in f.detail
    assert "rho_D" in f.detail and "v_E*tan(lat)/(R_E + h)" in f.detail
    assert " or " in f.detail


# 1. a skew pair with a wrong sign is one finding with the pair's effect -------------
@pytest.fixture(scope="module")
def day(derived):
    """The motions over a day (the effects after 24 h), coarse."""
    return mc.motions(load_model(MODEL), hours=24.0, step=600.0)


def _coriolis_sign(F, nav, i):
    """2Ω_D (Ω_D = −U sin φ) written with the wrong sign in both velocity rows: the
    derived −(2Ω_ie + Ω_en)× has +2Ω_D in F[dv_N, dv_E] and −2Ω_D in F[dv_E, dv_N]."""
    omega_d = -7.292115e-5 * np.sin(nav["latitude"])
    F[:, i("dv_N"), i("dv_E")] -= 2 * (2 * omega_d)
    F[:, i("dv_E"), i("dv_N")] += 2 * (2 * omega_d)


def test_a_coriolis_sign_slip_is_one_finding_of_both_entries(day):
    """Each entry of the pair alone breaks the antisymmetry (a 64 times larger error
    after a day than the slip): one finding, naming its mirror, whose effect is both
    entries together, which is then the whole hand's difference (nothing else differs)."""
    model = load_model(MODEL)
    conv = convention(model, CONV)
    derived_day = ({m.label: np.array(mc.derived_in_convention(model, conv, m)[0])
                    for m in day}, list(conv.names))
    report = _check(_hand(derived_day, day, _coriolis_sign), day, effects=True)
    [f] = report.findings
    assert {(f.row, f.column), f.pair} == {("dv_N", "dv_E"), ("dv_E", "dv_N")}
    assert f.severity == "mistake" and report.exit_status == 1
    assert report.compared == len(conv.names) ** 2 - 1  # the pair: one entry
    mirror = f"F[{f.pair[0]}, {f.pair[1]}]"
    text = to_terminal(report)
    assert f"one finding with its mirror {mirror}" in text and "1 mistake" in text
    assert "the pair together after 24 h: " in text and "alone after 24 h" not in text
    whole = max(e.position_difference for e in report.effects if e.hours == 24)
    pair = report.finding_effects[f.entry].position
    assert pair == pytest.approx(whole, rel=1e-9)
    # one entry of it alone: the antisymmetry broken, a much larger error
    from dataclasses import replace

    from ins_errors.checker import matrix_effects

    single = replace(f, pair=None)
    report.findings = [single]
    sampled = mc._Sampled(_hand(derived_day, day, _coriolis_sign).F, {},
                          derived_day[0], {m.label: np.array(mc.derived_in_convention(
                              model, conv, m)[1]) for m in day})
    alone = matrix_effects.finding_effects(report, sampled, conv, model, day)
    assert alone[f.entry].position > 20 * pair


def test_a_mirror_pair_not_opposite_stays_two_findings(derived, motions):
    """Two mirror entries wrong by amounts that are not opposite (2Ω_D added in one,
    plus 2Ω_D in the other: the same sign) are two findings."""
    def edit(F, nav, i):
        omega_d = -7.292115e-5 * np.sin(nav["latitude"])
        F[:, i("dv_N"), i("dv_E")] += 2 * omega_d
        F[:, i("dv_E"), i("dv_N")] += 2 * omega_d
    report = _check(_hand(derived, motions, edit), motions)
    assert len(report.findings) == 2 and all(f.pair is None for f in report.findings)


# 3. a wrong factor of one term of an entry: the ratio named ----------------------------
def test_gravity_gradient_g_over_r_for_2g_over_r_names_the_ratio(derived, motions):
    """F[dv_D, dh] holds the gravity gradient 2g/R and, moving, the transport rate's
    change with height. The hand's g/R (half the derived gradient, the gradient taken
    here as a finite difference of the WGS-84 normal gravity in height) is hand/model
    = 0.5 exactly on the static base and just under it moving: the ratio named."""
    def gamma(lat, h):
        s2 = np.sin(lat) ** 2
        g0 = 9.7803253359 * (1 + 0.00193185265241 * s2) / np.sqrt(1 - 6.69437999014e-3 * s2)
        return g0 * (1 - 2 * h / 6378137.0 * (1 + 0.00335281066 + 0.00344978600308
                                               - 2 * 0.00335281066 * s2)
                     + 3 * h * h / 6378137.0 ** 2)

    def edit(F, nav, i):
        lat, h = nav["latitude"], np.broadcast_to(nav["height"], nav["latitude"].shape)
        gradient = (gamma(lat, h + 1.0) - gamma(lat, h - 1.0)) / 2.0  # ∂γ/∂h ≈ −2g/R
        F[:, i("dv_D"), i("dh")] -= 0.5 * gradient
    report = _check(_hand(derived, motions, edit), motions)
    f = report.finding("dv_D", "dh")
    assert f.kind == "wrong coefficient"
    assert "hand/model = 0.5 at every sample on 'static'" in f.detail
    for label in ("cruise", "manoeuvre"):
        said = re.search(rf"([\d.]+)(?: to ([\d.]+)| at every sample) on '{label}'",
                         f.detail).groups()
        assert all(0.499 < float(x) < 0.5 for x in said if x)


# 4. a horizontal-only filter ---------------------------------------------------------
def test_a_horizontal_only_hand_is_told_so_and_is_no_mistake(derived, motions):
    """A filter without dv_D and dh (the derived F less their rows and columns): its
    couplings to the vertical channel, which the effect comparison holds anyway, are one
    finding of the report, no mistakes: exit status 0. Without dh alone (dv_D kept) the
    vertical channel is broken, not left out: mistakes, exit 1."""
    states = [s for s in derived[1] if s not in ("dv_D", "dh")]
    report = _check(_hand(derived, motions, lambda F, nav, i: None, states), motions,
                    effects=True)
    assert report.findings and report.exit_status == 0 and report.mistakes == []
    assert {f.column for f in report.without_vertical} == {"dv_D", "dh"}
    assert report.without_vertical == report.findings
    text = to_terminal(report)
    assert "the hand has no vertical channel (no dv_D, dh)" in text
    assert f"{len(report.findings)} couplings to the vertical channel" in text
    assert "Mistakes:" not in text and "state left out" not in text
    # the effects: none (what the hand leaves out is held in the derived model too)
    assert all(not e.position_above_rounding for e in report.effects)
    part = _check(_hand(derived, motions, lambda F, nav, i: None,
                        [s for s in derived[1] if s != "dh"]), motions)
    assert part.exit_status == 1 and part.without_vertical == []


# 5. rough edges of a function's input ------------------------------------------------
STATES = ["phi_N", "phi_E", "phi_D", "dv_N", "dv_E", "dv_D", "dlat", "dlon", "dh"]


def _function(body):
    def fn(nav, imu):
        return body(nav)
    fn.states = list(STATES)
    return fn


def test_states_of_another_convention_suggest_it(motions):
    """φ-geodetic states checked in the model's own convention (--convention forgotten):
    the convention whose states they are is named, not a list of 34 names."""
    fn = _function(lambda nav: np.zeros((9, 9)))
    with pytest.raises(mc.InsErrorsError) as error:
        mc.check_matrices(MODEL, fn, "model", motion_list=motions, effects=False)
    text = str(error.value)
    assert "'phi_N' is no state of convention 'model'" in text
    assert "(--convention phi_geodetic)" in text and "known:" not in text
    # a name of no convention still lists the known ones
    fn.states = [*STATES[:-1], "dheight"]
    with pytest.raises(mc.InsErrorsError, match="unknown state of convention"):
        mc.check_matrices(MODEL, fn, CONV, motion_list=motions, effects=False)


def test_nan_is_named_by_its_states_and_none_is_said(motions):
    def with_nan(nav):
        F = np.zeros((9, 9))
        F[3, 4] = np.nan
        return F
    with pytest.raises(mc.InsErrorsError, match=r"F\[dv_N, dv_E\] \(F\[3, 4\]\) is NaN$"):
        mc.check_matrices(MODEL, _function(with_nan), CONV, motion_list=motions,
                          effects=False)

    def with_inf(nav):
        F = np.zeros((9, 9))
        F[8, 0] = np.inf
        return F
    with pytest.raises(mc.InsErrorsError, match=r"F\[dh, phi_N\] \(F\[8, 0\]\) is infinite"):
        mc.check_matrices(MODEL, _function(with_inf), CONV, motion_list=motions,
                          effects=False)
    with pytest.raises(mc.InsErrorsError, match="the function returned None"):
        mc.check_matrices(MODEL, _function(lambda nav: None), CONV, motion_list=motions,
                          effects=False)
