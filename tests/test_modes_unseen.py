"""Modes no error reaches or no output sees: the constraint directions of a redundant state.

A wander-azimuth strapdown INS that stores C_b^w and C_w^e as 9 entries each has 22 error
states, but its errors move the state only along the rotations: its own modes are those of
a 9-state φ-model (tilt, velocity, position). The extra modes of F (integrators, and
oscillations at Ω and 2Ω where the matrices leave the orthonormal ones) must be listed
apart, not as the INS's modes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ins_errors.analysis.modes import static_modes
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
WANDER = str(ROOT / "tests/models/wander_azimuth.py")


def _phi_model(latitude: float) -> np.ndarray:
    """F of the textbook 9-state φ-model (NED; φ, δv_NED, δL, δλ, δh) at rest on the
    WGS-84 ellipsoid: φ̇ = −ω_ie × φ + δω_in, δv̇ = f × φ − 2ω_ie × δv + δg, with
    δω_in from δL (Earth rate) and δv (transport rate), f = (0, 0, −g), δg_D = −2g/R δh
    (Titterton & Weston, ch. 12)."""
    a, e2, omega = 6378137.0, 6.69437999014e-3, 7.292115e-5
    s, c = np.sin(latitude), np.cos(latitude)
    r_n = a / np.sqrt(1 - e2 * s * s)
    r_m = r_n * (1 - e2) / (1 - e2 * s * s)
    g = 9.7803253359 * (1 + 1.931852652e-3 * s * s) / np.sqrt(1 - e2 * s * s)
    w = np.array([omega * c, 0.0, -omega * s])

    def cross(v):
        return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

    F = np.zeros((9, 9))
    F[0:3, 0:3] = -cross(w)
    F[0, 4], F[1, 3], F[2, 4] = 1 / r_n, -1 / r_m, -np.tan(latitude) / r_n  # δω_en
    F[0, 6], F[2, 6] = -omega * s, -omega * c  # δω_ie from δL
    F[3:6, 0:3] = cross(np.array([0.0, 0.0, -g]))  # f × φ
    F[3:6, 3:6] = -2 * cross(w)
    F[5, 8] = -2 * g / np.sqrt(r_m * r_n)  # δg_D: gravity falls with height
    F[6, 3], F[7, 4], F[8, 5] = 1 / r_m, 1 / (r_n * c), -1.0
    return F


def _spectrum(modes) -> np.ndarray:
    """Every eigenvalue of ``modes`` (a pair both ways, each its multiplicity), sorted."""
    values = []
    for mode in modes:
        value = mode.eigenvalue
        values += [value] * mode.multiplicity
        if value.imag:
            values += [value.conjugate()] * mode.multiplicity
    return np.array(sorted(values, key=lambda v: (v.imag, v.real)))


@pytest.mark.parametrize("latitude_deg", [45.0, -30.0])
def test_wander_models_own_modes_are_those_of_the_9_state_phi_model(latitude_deg):
    latitude = np.radians(latitude_deg)
    result = static_modes(WANDER, latitude)
    own = _spectrum(result.modes)
    reference = np.array(sorted(np.linalg.eigvals(_phi_model(latitude)),
                                key=lambda v: (v.imag, v.real)))
    reference = np.where(abs(reference.real) < 1e-12, 1j * reference.imag, reference)
    assert len(own) == 9
    # the φ-model's gravity gradient is 2g/R, the model's the normal gravity's: 0.2 %
    np.testing.assert_allclose(own, reference, rtol=3e-3, atol=1e-12)
    assert [m.name for m in result.modes][:2] == ["integrator", "Earth"]
    assert all(m.seen for m in result.modes)
    hidden = result.unseen_modes
    assert hidden and not any(m.seen for m in hidden)
    assert len(_spectrum(hidden)) == 22 - 9
    # the 11.97-h oscillation (2Ω, the matrices turning against the Earth) is among them
    assert any(abs(m.eigenvalue.imag - 2 * 7.292115e-5) < 1e-9 for m in hidden)
    assert all(m.reference is None for m in hidden)


def test_wander_text_lists_the_constraint_modes_apart_without_the_jordan_note(capsys):
    assert main(["modes", WANDER, "--latitude", "45deg"]) == 0
    out = capsys.readouterr().out
    main_table, rest = out.split("Modes not reached by any error source", 1)
    assert "11.97 h" not in main_table and "11.97 h" in rest
    assert "(9 directions)" not in out and "Jordan chain" not in out
    assert "| integrator | 0 | 1 |" in main_table


def test_wander_json_flags_the_constraint_modes(capsys):
    import json

    assert main(["modes", WANDER, "--latitude", "45deg", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert all(m["reached_and_seen"] for m in data["modes"])
    assert data["unseen_modes"] and not any(m["reached_and_seen"]
                                            for m in data["unseen_modes"])


@pytest.mark.parametrize("model", ["north_pointing", "free_azimuth", "geodetic_vertical"])
def test_models_without_a_constrained_state_keep_every_mode(model):
    """Where every mode is reached and seen nothing moves: the modes equal those of F
    split by nothing (no H, no [G E])."""
    from ins_errors.analysis.modes import _modes, references
    from ins_errors.numeric.model import as_model

    result = static_modes(model, np.radians(45.0))
    assert result.unseen_modes == ()
    loaded = as_model(model, "test")
    names = [s.name for s in loaded.error_states]
    refs = references(loaded, result.point.u, result.point.p, result.references.latitude,
                      result.height or 0.0)
    plain, none = _modes(result.state_matrix, result.point.factors, names, refs,
                         loaded.mode_notes)
    assert none == () and plain == result.modes


def test_a_mode_no_output_reads_is_put_apart():
    """An oscillator read by the output and a decay no output reads (both reached)."""
    from ins_errors.analysis.mode_references import References
    from ins_errors.analysis.modes import _modes

    F = np.array([[0.0, 1.0, 0.0], [-1e-6, 0.0, 0.0], [0.0, 0.0, -1e-2]])
    refs = References(None, None, None, None)
    seen, unseen = _modes(F, np.ones(3), ["a", "b", "c"], refs,
                          H=np.array([[1.0, 0.0, 0.0]]), B=np.eye(3))
    assert [m.kind for m in seen] == ["oscillation"]
    assert [(m.kind, m.eigenvalue) for m in unseen] == [("damped", -1e-2 + 0j)]
    assert unseen[0].participation == {"a": 0.0, "b": 0.0, "c": 1.0}


def test_sphere_model_keeps_its_vertical_jordan_chain_and_puts_its_constraints_apart():
    """strapdown_sphere (T as 9 entries, constant g): 9 own eigenvalues, among them the
    neutral vertical channel's double zero (ḣ = −δv_D, δv̇_D = 0: a Jordan chain, kept)."""
    result = static_modes(str(ROOT / "examples/strapdown/strapdown_sphere.py"),
                          np.radians(45.0))
    assert len(_spectrum(result.modes)) == 9
    zero = result.mode("integrator")
    assert (zero.multiplicity, zero.independent_directions) == (3, 2)
    assert len(_spectrum(result.unseen_modes)) == 15 - 9


def test_transfer_counts_the_constraint_directions_among_the_cancelled():
    """Every pair's order plus what it cancels is F's order, the constraint directions
    named as such (they left the modes' main table, not F)."""
    from ins_errors.analysis.transfer import transfer_functions

    result = transfer_functions(WANDER, ["gyro_bias_x"], ["latitude", "longitude"],
                                latitude=np.radians(45.0))
    for pair in result.pairs:
        gone = sum(f.multiplicity * (2 if f.value.imag else 1) for f in pair.cancelled)
        assert pair.order + gone == pair.full_order == 22
        assert sum(f.multiplicity * (2 if f.value.imag else 1) for f in pair.cancelled
                   if f.name.endswith("(constraint direction)")) == 22 - 9


def test_a_mode_the_errors_reach_and_no_output_sees_is_not_a_constraint_direction(capsys):
    """north_pointing stores no rotation redundantly: it has no constraint direction.
    Without the Earth's rate (-p U=0rad/s) its azimuth error α_U feeds nothing (F's
    column of α_U is zero) while a vertical gyro drift drives it (G): its integrator is
    reached and seen by no output, and was listed and cancelled as a 'constraint
    direction'."""
    from ins_errors.analysis.transfer import transfer_functions
    from ins_errors.numeric.model import load_model

    model = load_model("north_pointing")
    result = static_modes(model, parameters={"U": 0.0})
    point, F = result.point, result.state_matrix
    k = model.index("error_states", "alpha_U")
    G = np.asarray(model.source_matrix(point.x, point.u, point.p), float)
    assert np.all(F[:, k] == 0)  # α_U reaches no state, so no output
    assert G[k, model.index("sources", "gyro_drift_up")] != 0  # and a drift drives it
    [azimuth] = [m for m in result.unseen_modes if m.participation["alpha_U"] == 1.0]
    assert azimuth.eigenvalue == 0 and azimuth.reached and not azimuth.seen
    assert all(m.reached for m in result.unseen_modes)  # no constraint direction at all
    assert main(["modes", "north_pointing", "-p", "U=0rad/s"]) == 0
    out = capsys.readouterr().out
    assert "constraint" not in out
    assert "Modes reached by the errors but not seen by any output" in out
    pair = transfer_functions(model, ["gyro_drift_east"], ["latitude"],
                              parameters={"U": 0.0}).pairs[0]
    names = [f.name for f in pair.cancelled]
    assert "integrator (seen by no output)" in names
    assert not any("constraint direction" in name for name in names)
    # a redundant state's constraint directions keep their name (strapdown_ned's q0)
    strapdown = static_modes("strapdown_ned")
    assert [m.reached for m in strapdown.unseen_modes] == [False]
