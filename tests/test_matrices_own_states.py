"""``ins-errors matrices`` of a model with no convention but its own error states.

A filter designer with a platform INS (the built-in ``orthodromic``, a velocity-damped
model file of their own) got "has no convention but its own error states ('model'), so
not 'phi'", and with ``--convention model`` "cannot be checked with --matrix": no F(t),
G(t) at all. Now such a model's own error states are the default, along the check's
motions. References, independent of the generated matrices: central differences of the
model's real-work equations at the file's true states and inputs (F and G), scipy's
matrix exponential of that F (Φ on a static base) and a quadrature of the noise integral
(Q).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad_vec
from scipy.linalg import expm

from ins_errors.cli import main
from ins_errors.numeric.model import load_model
from ins_errors.units import parse_quantity

ROOT = Path(__file__).resolve().parents[1]
DAMPED = ROOT / "tests" / "models" / "damped_ins.py"
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
STEP = {"1": 1e-8, "rad": 1e-8, "m/s": 1e-4, "m": 1e-2, "rad/s": 1e-9, "m/s**2": 1e-6}
"""Central-difference step of a state or source, by its SI unit (about its typical size
over 1e4: the rounding of the real-work rates stays far below the entries)."""


def _central_differences(model, x, u, p, sources):
    """F (ne, ne) and the columns of G for ``sources`` (ne, m): derivatives of the
    real-work rates by the error state (computed − true, then the platform angles) and
    by the sources, at zero error."""
    n, ne = len(model.states), len(model.error_states)
    xr0 = np.concatenate([x, np.zeros(ne - n)])
    w0 = model.source_vector()

    def rates(xr, w):
        return np.asarray(model.real_rhs(xr, x, u, w, p), dtype=float)

    F = np.column_stack([(rates(xr0 + STEP[s.unit] * e, w0) - rates(xr0 - STEP[s.unit] * e, w0))
                         / (2 * STEP[s.unit])
                         for s, e in zip(model.error_states, np.eye(ne), strict=True)])
    columns = []
    for name in sources:
        j = model.index("sources", name)
        h = STEP[model.sources[j].unit]
        e = h * np.eye(len(w0))[j]
        columns.append((rates(xr0, e) - rates(xr0, -e)) / (2 * h))
    return F, np.column_stack(columns)


def _agree(written, reference, steps, tol):
    """Each row agrees to ``tol`` of its largest entry, the entries taken in the typical
    sizes ``steps`` of the columns (an entry of 1/R beside one of g is judged on its
    own scale, the rounding of a zero entry on the row's)."""
    scale = np.abs(reference) * steps
    error = np.abs(written - reference) * steps
    bound = tol * scale.max(axis=1, keepdims=True) + 1e-300
    assert np.all(error <= bound), float((error / bound).max())


@pytest.mark.parametrize("model_name, options", [
    ("orthodromic", []),
    (str(DAMPED), ["-p", "k_v=1.24e-3/s", "-p", "k_p=0.5"]),
])
def test_f_and_g_in_the_models_own_states_are_its_real_work_linearised(model_name, options,
                                                                        tmp_path, capsys):
    out = tmp_path / "fg.npz"
    assert main(["matrices", model_name, "--hours", "1", *options, "--out", str(out)]) == 0
    captured = capsys.readouterr()
    model = load_model(model_name)
    assert f"note: {model.name} has no φ/ψ convention" in captured.err, captured.err
    assert "--convention model" in captured.err
    assert "in model at 61 samples each of static, cruise and manoeuvre" in captured.out
    data = np.load(out)
    assert [str(s) for s in data["states"]] == [s.name for s in model.error_states]
    sources = [str(s) for s in data["sources"]]
    assert sources == [s.name for s in model.sources if s.kind != "initial"]
    assert not any(key.startswith(("latitude_", "C_bn_", "f_b_")) for key in data)
    p = data["parameters"]
    if options:
        assert p[[q.name for q in model.parameters].index("k_v")] == 1.24e-3
    state_steps = np.array([STEP[s.unit] for s in model.error_states])
    source_steps = np.array([STEP[model.source(s).unit] for s in sources])
    for motion in ("static", "cruise", "manoeuvre"):
        x, u = data[f"x_{motion}"], data[f"u_{motion}"]
        assert data[f"F_{motion}"].shape == (61, len(state_steps), len(state_steps))
        for k in (0, 30, 60):
            F, G = _central_differences(model, x[k], u[k], p, sources)
            _agree(data[f"F_{motion}"][k], F, state_steps, 1e-6)
            _agree(data[f"G_{motion}"][k], G, source_steps, 1e-6)


def test_phi_and_q_of_the_model_file_on_a_static_base(tmp_path, capsys):
    """--discrete in the model's own states: Φ = e^{FΔt} (scipy's expm of the central-
    difference F) and Q = ∫ e^{Fs} L diag(q²) Lᵀ e^{Fᵀs} ds (a quadrature), over 60 s."""
    out = tmp_path / "d.npz"
    noise = {"gyro_drift_east": "0.003deg/rt-hr", "accel_bias_north": "50ug/rtHz"}
    assert main(["matrices", str(DAMPED), "--motion", "static", "--hours", "1", "--step",
                 "60s", "-p", "k_v=1.24e-3/s", "--discrete", "--noise",
                 ",".join(f"{k}={v}" for k, v in noise.items()), "--out", str(out)]) == 0
    capsys.readouterr()
    model = load_model(str(DAMPED))
    data = np.load(out)
    assert data["Phi_static"].shape == (60, 7, 7) and "F_cruise" not in data
    x, u, p = data["x_static"][0], data["u_static"][0], data["parameters"]
    F, L = _central_differences(model, x, u, p, list(noise))
    q = np.array([parse_quantity(noise[name], f"({model.source(name).unit})*s**0.5", name)
                  for name in noise])
    steps = np.array([STEP[s.unit] for s in model.error_states])
    Phi = expm(F * 60.0)
    Q, _ = quad_vec(lambda s: expm(F * s) @ L @ np.diag(q**2) @ L.T @ expm(F * s).T,
                    0.0, 60.0, epsabs=0.0, epsrel=1e-12)
    for k in (0, 59):  # (a static base: every step alike)
        _agree(data["Phi_static"][k], Phi, steps, 1e-7)
        scale = np.sqrt(np.outer(np.diag(Q), np.diag(Q)))
        assert np.all(np.abs(data["Qd_static"][k] - Q) <= 1e-7 * scale + 1e-300)
    assert Q[1, 1] > 0 and Q[4, 4] > 0  # (both noises reach Q: δv_N and α_E)


def test_a_model_that_flies_the_static_base_only_is_written_there(tmp_path, capsys):
    """A north-channel model without an east velocity follows the static base only: the
    file holds it and the command lists the others as not flown (no refusal); asking for
    the cruise is one line."""
    out = tmp_path / "s.npz"
    assert main(["matrices", str(SCHULER), "--hours", "1", "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "of static\n" in said and "not flown: cruise: " in said
    assert "no east velocity" in said
    data = np.load(out)
    assert "F_static" in data and "F_cruise" not in data
    assert main(["matrices", str(SCHULER), "--motion", "cruise", "--hours", "1",
                 "--out", str(tmp_path / "c.npz")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("ins-errors: error: model 'schuler_loop' cannot fly the "
                              "cruise motion: model 'schuler_loop' has no east velocity")


def test_without_convention_a_model_without_phi_but_with_others_is_one_line(tmp_path,
                                                                           capsys):
    """north_pointing has psi and its own states, no phi: the default is no guess."""
    status = main(["matrices", "north_pointing", "--hours", "1", "--out",
                   str(tmp_path / "x.npz")])
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert status == 2 and len(err) == 1 and not captured.out, err
    assert "has no phi convention: give --convention model or psi" in err[0]
    assert not (tmp_path / "x.npz").exists()
