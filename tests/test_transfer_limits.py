"""``ins-errors transfer`` near a pole, near the equator and with light damping, against
references built here independently of the code under test.

* A north-pointing platform's 7-state error equations written out by hand (Britting's
  form: x = δv_E, δv_N, δφ, δλ, α_E, α_N, α_U; α' = −Ω × α + δω_in + ε, the Coriolis
  terms 2Ω sin φ, the transport rate's tan φ / R), their response to a constant source
  by the matrix exponential of the augmented system [[F, g], [0, 0]].
* strapdown_ned's own F, G, H at the base with its vertical channel damped, its
  oscillations' amplitudes from F's eigen-decomposition (residues 2 |(h v)(w g)/λ| of a
  constant source).
* The textbook: near the pole a vertical gyro drift ε turns the platform about the
  vertical, and the longitude error grows as −ε sin φ t.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sl

from ins_errors.analysis.transfer import markov_zero, transfer_functions
from ins_errors.cli import main

R, GRAVITY, OMEGA = 6_371_000.0, 9.80665, 7.292115e-5
DEG_H = np.radians(1.0) / 3600.0
UG = 9.80665e-6
ARCMIN = np.radians(1.0 / 60.0)
SOURCES = {"gyro_drift_east": 4, "gyro_drift_north": 5, "gyro_drift_up": 6,
           "accel_bias_east": 0, "accel_bias_north": 1}
OUTPUTS = {"latitude": 2, "longitude": 3, "v_N": 1, "v_E": 0}


def platform(latitude: float) -> np.ndarray:
    """F of the north-pointing platform, written out from the equations."""
    s, c = np.sin(latitude), np.cos(latitude)
    F = np.zeros((7, 7))
    F[0, 1], F[0, 5] = 2 * OMEGA * s, -GRAVITY
    F[1, 0], F[1, 4] = -2 * OMEGA * s, GRAVITY
    F[2, 1] = 1 / R
    F[3, 0] = 1 / (R * c)
    w = np.array([0.0, OMEGA * c, OMEGA * s])
    F[4:, 4:] = -np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    F[4, 1] -= 1 / R
    F[5, 0] += 1 / R
    F[5, 2] -= OMEGA * s
    F[6, 0] += np.tan(latitude) / R
    F[6, 2] += OMEGA * c
    return F


def step_response(F: np.ndarray, g: np.ndarray, h: np.ndarray, t: np.ndarray,
                  size: float) -> np.ndarray:
    """h x(t) under a constant source of ``size`` from x(0) = 0 (matrix exponential)."""
    n = len(F)
    A = np.zeros((n + 1, n + 1))
    A[:n, :n], A[:n, n] = F, g
    return np.array([np.r_[h, 0.0] @ sl.expm(A * tk)[:, n] * size for tk in t])


def _unit(k: int) -> np.ndarray:
    return np.eye(7)[k]


# --------------------------------------------------------------------------------------
# near the pole: W = 0 only when proved
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("degrees", [89.99, 89.998, 89.9999])
def test_vertical_drift_turns_the_longitude_near_the_pole(degrees):
    latitude = np.radians(degrees)
    tf = transfer_functions("north_pointing", ["gyro_drift_up"], ["longitude", "v_N"],
                            latitude=latitude, magnitudes={"gyro_drift_up": DEG_H})
    longitude = tf.pair("gyro_drift_up", "longitude")
    assert not longitude.is_zero  # was 'W(s) = 0 … every mode cancelled'
    # the textbook: −ε sin φ t (−60′/h for 1 deg/h)
    assert longitude.long_run.kind == "power"
    assert longitude.long_run.coefficient * DEG_H == pytest.approx(
        -DEG_H * np.sin(latitude), rel=1e-6)
    F = platform(latitude)
    t = np.array([3600.0, 6 * 3600.0, 86400.0])
    for name in ("longitude", "v_N"):
        pair = tf.pair("gyro_drift_up", name)
        reference = step_response(F, _unit(SOURCES["gyro_drift_up"]),
                                  _unit(OUTPUTS[name]), t, DEG_H)
        assert np.allclose(pair.response(t), reference, rtol=1e-6,
                           atol=1e-9 * np.abs(reference).max())
    day = step_response(F, _unit(6), _unit(3), np.array([86400.0]), DEG_H)[0]
    assert np.degrees(day) == pytest.approx(-24.0, rel=0.02)  # the probe's −24° a day


def test_a_zero_needs_its_markov_parameters():
    F = platform(np.radians(89.998))
    # a vertical drift reaches the longitude only through Ω cos φ (tiny) times sec φ
    # (huge): not rounding
    assert not markov_zero(F, _unit(6), _unit(3))
    # an east accelerometer bias never reaches the latitude at the equator: exactly zero
    assert markov_zero(platform(0.0), _unit(0), _unit(2))


def test_the_command_answers_up_to_the_models_own_pole_limit(capsys):
    assert main(["transfer", "north_pointing", "--source", "gyro_drift_up", "--output",
                 "longitude", "--latitude", "89.9999deg"]) == 0
    out = capsys.readouterr().out
    assert "φ=89.9999°" in out  # not φ=90°
    assert "W(s) = 0" not in out and "−60 arcmin/h" in out.replace("-", "−")
    assert main(["transfer", "north_pointing", "--source", "gyro_drift_up", "--latitude",
                 "89.99999deg"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "pole" in err


# --------------------------------------------------------------------------------------
# near the equator: the Foucault-split pair stays two
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("degrees", [0.00001, 0.0001, 0.0003, 0.0005])
def test_foucault_pair_near_the_equator_stays_split(degrees):
    latitude = np.radians(degrees)
    sizes = {"accel_bias_north": 100 * UG, "gyro_drift_north": 0.01 * DEG_H}
    tf = transfer_functions("north_pointing", list(sizes), ["latitude", "longitude"],
                            latitude=latitude, magnitudes=sizes)
    F = platform(latitude)
    t = np.linspace(0.0, 30 * 86400.0, 61)
    bias = tf.pair("accel_bias_north", "latitude")
    assert [f.multiplicity for f in bias.poles] == [1, 1]
    assert bias.long_run.kind == "constant"  # bounded: not a resonance
    reference = step_response(F, _unit(1), _unit(2), t, 100 * UG)
    assert np.abs(bias.response(t) - reference).max() < 1e-6 * np.abs(reference).max()
    # the mean and the size of the oscillation: those of the equator, ∇/g and 2∇/g
    assert bias.long_run.coefficient * 100 * UG / ARCMIN == pytest.approx(
        100 * UG / GRAVITY / ARCMIN, rel=1e-6)
    peak = step_response(F, _unit(1), _unit(2), np.linspace(0, 86400.0, 2001), 100 * UG)
    assert peak.max() / ARCMIN == pytest.approx(0.6875, abs=2e-4)
    drift = tf.pair("gyro_drift_north", "longitude")
    assert drift.long_run.kind == "power" and drift.long_run.power == 1
    # over 30 days the linear growth (0.6′/h, 432′) outweighs the 4″ Schuler terms
    month = step_response(F, _unit(5), _unit(3), np.array([30 * 86400.0]), 0.01 * DEG_H)
    assert drift.long_run.coefficient * 0.01 * DEG_H == pytest.approx(
        month[0] / (30 * 86400.0), rel=1e-3)
    reference = step_response(F, _unit(5), _unit(3), t, 0.01 * DEG_H)
    assert np.abs(drift.response(t) - reference).max() < 1e-6 * np.abs(reference).max()


def test_close_roots_print_with_the_digits_that_tell_them_apart(capsys):
    assert main(["transfer", "north_pointing", "--source", "accel_bias_north", "--output",
                 "latitude", "--latitude", "0.0005deg"]) == 0
    out = capsys.readouterr().out
    rows = [line.split("|")[1].strip() for line in out.splitlines()
            if "| Schuler" in line]
    assert len(rows) == 2 and rows[0] != rows[1]
    assert "resonance" not in out and "repeated" not in out


# --------------------------------------------------------------------------------------
# light damping: the slow Schuler oscillations are listed
# --------------------------------------------------------------------------------------
def test_lightly_damped_schuler_pairs_are_in_the_long_run(capsys):
    from ins_errors import load_model
    from ins_errors.analysis.modes import static_modes

    parameters = {"k_h1": 0.0293, "k_h2": 4.42e-4}
    latitude = np.radians(45.0)
    model = load_model("strapdown_ned")
    tf = transfer_functions(model, ["gyro_bias_y", "accel_bias_x"], ["latitude", "height"],
                            latitude=latitude, parameters=parameters)
    base = static_modes(model, latitude, parameters=parameters)
    p = base.point
    F = base.state_matrix
    G = np.asarray(model.source_matrix(p.x, p.u, p.p), dtype=float)
    H = np.asarray(model.output_matrix(p.x, p.u, p.p), dtype=float)
    values, V = np.linalg.eig(F)
    W = np.linalg.inv(V)
    for source, output in [("gyro_bias_y", "latitude"), ("accel_bias_x", "height")]:
        pair = tf.pair(source, output)
        g = G[:, model.index("sources", source)]
        h = H[model.index("outputs", output)]
        expected = {}
        for k, value in enumerate(values):
            period = 2 * np.pi / value.imag if value.imag > 0 else None
            if period and 60 * 60 < period < 2 * 3600:  # the Schuler pairs
                expected[round(period)] = 2 * abs((h @ V[:, k]) * (W[k] @ g) / value)
        listed = {round(o.period_s): o for o in pair.long_run.oscillations
                  if o.decay_s is not None}
        assert sorted(listed) == sorted(expected)
        for period, amplitude in expected.items():
            assert listed[period].amplitude == pytest.approx(amplitude, rel=1e-6)
            assert listed[period].decay_s > 50 * 86400.0
    height = tf.pair("accel_bias_x", "height").long_run
    assert height.settles and height.settling_s > 100 * 86400.0


def test_amplitudes_are_sizes_for_a_negative_source(capsys):
    assert main(["transfer", "north_pointing", "--source", "accel_bias_north=-5ug",
                 "--output", "latitude", "--latitude", "45deg", "--json"]) == 0
    import json

    run = json.loads(capsys.readouterr().out)["pairs"][0]["long_run"]
    assert run["value"] < 0
    assert run["oscillations"] and all(o["amplitude"] > 0 for o in run["oscillations"])
    assert "amplitude -" not in run["text"]


# --------------------------------------------------------------------------------------
# the Bode plot: identical curves both show, the legend off the axes
# --------------------------------------------------------------------------------------
def test_bode_plot_marks_identical_curves_and_keeps_the_legend_off_the_axes(tmp_path,
                                                                           monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import ins_errors.output as output
    from ins_errors.analysis import transfer_plot

    figures = []
    monkeypatch.setattr(output, "save_figure", lambda fig, path, dpi: figures.append(fig)
                        or path)
    schuler = str(Path(__file__).resolve().parent.parent / "examples" / "own_model"
                  / "schuler_loop.py")
    # 1 deg/h of drift and 1 arcsec of initial tilt: the same W (1 deg/h = 1 arcsec/s)
    tf = transfer_functions(schuler, ["gyro_drift", "initial_tilt", "accel_bias"],
                            ["psi", "latitude", "v_N"])
    transfer_plot.plot_bode(tf, tmp_path / "bode.png")
    fig = figures[-1]
    top, bottom = fig.axes[:2]
    lines = top.get_lines()
    labels = [line.get_label() for line in lines if not line.get_label().startswith("_")]
    same = [label for label in labels if "the same curve as gyro_drift" in label]
    assert len(same) == 3
    styles = {(line.get_color(), str(line.get_linestyle())) for line in lines
              if not line.get_label().startswith("_")}
    assert len(styles) == len(labels)
    legend = bottom.get_legend()
    fig.canvas.draw()
    box = legend.get_window_extent()
    assert box.y1 < bottom.get_window_extent().y0  # below the axes, covering nothing
    plt.close(fig)


def test_bode_plot_labels_each_mode_beside_its_own_line(tmp_path, monkeypatch):
    """strapdown_ned's vertical channel (|λ| = √(2g/R), right of the Schuler pair) was
    labelled left of its own line, over the Schuler lines, reading as theirs. Each label
    now starts at its own line (its near edge closest to it of all the modes' lines),
    and one with a free side sits there: the vertical channel's box holds no other
    mode's line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import ins_errors.output as output
    from ins_errors.analysis import transfer_plot

    figures = []
    monkeypatch.setattr(output, "save_figure", lambda fig, path, dpi: figures.append(fig)
                        or path)
    tf = transfer_functions("strapdown_ned", ["accel_bias_y"], ["latitude", "height"])
    transfer_plot.plot_bode(tf, tmp_path / "bode.png")
    fig = figures[-1]
    top = fig.axes[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    rates: list[float] = []
    for rate in sorted(abs(m.eigenvalue) for m in tf.named_modes()):
        if not rates or rate > rates[-1] * (1 + 1e-9):  # ± the vertical channel: one
            rates.append(rate)
    assert len(rates) == 3  # Schuler ∓ Foucault, the vertical channel
    labels = [t for t in top.texts if t.get_color() == "dimgrey"]  # the modes' labels
    assert len(labels) == 3
    xs = [top.transData.transform((rate, 1.0))[0] for rate in rates]
    for own, text in zip(xs, labels, strict=True):
        box = text.get_window_extent(renderer)
        right = box.x0 >= own
        assert right or box.x1 <= own  # wholly on one side of its own line
        edge = box.x0 if right else box.x1
        assert min(xs, key=lambda x: abs(x - edge)) == own, text.get_text()
    vertical = labels[-1]
    assert vertical.get_text().startswith("vertical channel")
    box = vertical.get_window_extent(renderer)
    assert box.x0 >= xs[-1] and not any(box.x0 <= x <= box.x1 for x in xs[:-1])
    plt.close(fig)
