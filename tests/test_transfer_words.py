"""What ``ins-errors transfer`` says beside its numbers, against references built here.

* strapdown_ned at 45° with its vertical channel undamped: the long run said only "pitch
  grows exponentially, ≈ -1.792e-06 arcsec e^(t/9.499 min)", leaving out the Schuler
  oscillations about ∇/g (20.6″) that the response follows for hours. The bounded terms
  are now listed beside the growth: the level against the textbook ∇/g, the amplitudes
  against F's eigen-decomposition (residues 2 |(h v)(w g)/λ| of a constant source), the
  time the growth overtakes them against that decomposition's growing term, and the
  whole against the matrix exponential of the augmented system [[F, g], [0, 0]].
* north_pointing at the equator, whose Schuler pair is double: one pair cancelled was
  printed "cancelled: integrator, Schuler" beside a Schuler pole; now with the count.
* docs/transfer.md quotes outputs of commands written inline (not in a ```sh block):
  each is run here and its quoted words found in what it prints.
"""

from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sl

from ins_errors.analysis.transfer import transfer_functions
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
UG = 9.80665e-6
ARCSEC = np.radians(1.0 / 3600.0)


@pytest.fixture(scope="module")
def undamped():
    """strapdown_ned at 45°, 100 µg of x accelerometer bias to pitch, with its F, g, h."""
    from ins_errors import load_model
    from ins_errors.analysis.modes import static_modes

    latitude = np.radians(45.0)
    model = load_model("strapdown_ned")
    base = static_modes(model, latitude)
    p = base.point
    G = np.asarray(model.source_matrix(p.x, p.u, p.p), dtype=float)
    H = np.asarray(model.output_matrix(p.x, p.u, p.p), dtype=float)
    pair = transfer_functions(model, ["accel_bias_x"], ["pitch"], latitude=latitude,
                              magnitudes={"accel_bias_x": 100 * UG}).pair(
        "accel_bias_x", "pitch")
    gravity = float(np.linalg.norm([p.u[model.index("inputs", f"f_{a}")] for a in "xyz"]))
    return (pair, base.state_matrix, G[:, model.index("sources", "accel_bias_x")],
            H[model.index("outputs", "pitch")], gravity)


def test_growth_lists_the_bounded_terms_beside_it(undamped):
    pair, F, g, h, gravity = undamped
    run = pair.long_run
    assert run.kind == "exponential" and run.growth.name == "vertical channel (growing)"
    rest = run.rest
    # the level: the textbook tilt under an accelerometer bias, ∇/g (the pitch's sign)
    assert rest.kind == "constant"
    assert abs(rest.coefficient) == pytest.approx(1 / gravity, rel=1e-3)
    # the amplitudes: F's eigen-decomposition, independent of the Krylov reduction
    values, V = np.linalg.eig(F)
    W = np.linalg.inv(V)
    expected = {}
    for k, value in enumerate(values):
        if value.imag > 0 and 3600 < 2 * np.pi / value.imag < 2 * 3600:  # Schuler pairs
            expected[round(2 * np.pi / value.imag)] = 2 * abs(
                (h @ V[:, k]) * (W[k] @ g) / value)
    listed = {round(o.period_s): o.amplitude for o in run.oscillations}
    assert sorted(listed) == sorted(expected) and len(listed) == 2
    for period, amplitude in expected.items():
        assert listed[period] == pytest.approx(amplitude, rel=1e-6)
    # they start at zero together with the level: y(0) = 0
    assert sum(listed.values()) == pytest.approx(abs(rest.coefficient), rel=1e-3)
    # when the growth reaches the bounded terms' largest size, from the decomposition
    [grow] = [k for k, value in enumerate(values) if value.real > 1e-4]
    size = abs((h @ V[:, grow]) * (W[grow] @ g) / values[grow]) * pair.magnitude
    bounded = (abs(rest.coefficient) + sum(expected.values())) * pair.magnitude
    assert run.overtakes_s == pytest.approx(np.log(bounded / size) / values[grow].real,
                                            rel=1e-6)
    assert 2 * 3600 < run.overtakes_s < 3 * 3600
    # the response those words describe: the matrix exponential, growth negligible at 1 h
    n = len(F)
    A = np.zeros((n + 1, n + 1))
    A[:n, :n], A[:n, n] = F, g
    times = np.linspace(0.0, 3600.0, 61)
    exact = np.array([np.r_[h, 0.0] @ sl.expm(A * t)[:, n] for t in times]) * pair.magnitude
    growing = ((h @ V[:, grow]) * (W[grow] @ g) / values[grow]).real * pair.magnitude
    assert run.coefficient * pair.magnitude == pytest.approx(growing, rel=1e-6)
    bounded_part = exact - growing * np.exp(values[grow].real * times)
    assert np.max(np.abs(bounded_part - rest.coefficient * pair.magnitude)) <= \
        sum(expected.values()) * pair.magnitude * (1 + 1e-4)
    assert np.max(np.abs(exact - pair.response(times))) <= 1e-8 * np.max(np.abs(exact))


def test_the_text_and_json_say_the_bounded_terms(capsys):
    assert main(["transfer", "strapdown_ned", "--source", "accel_bias_x=100ug", "--output",
                 "pitch", "--latitude", "45deg", "--json"]) == 0
    run = json.loads(capsys.readouterr().out)["pairs"][0]["long_run"]
    assert run["kind"] == "exponential"
    # 100 µg / g = 1e-5 rad = 20.6″, the level; two Schuler oscillations, their amplitudes
    # adding up to it
    assert abs(run["rest"]["value"]) / ARCSEC == pytest.approx(20.63, rel=2e-3)
    assert [o["name"] for o in run["oscillations"]] == ["Schuler − Foucault",
                                                        "Schuler + Foucault"]
    assert run["rest"]["size"] == pytest.approx(
        abs(run["rest"]["value"]) + sum(o["amplitude"] for o in run["oscillations"]))
    assert run["overtakes_s"] / 3600 == pytest.approx(2.68, abs=0.01)
    text = run["text"]
    assert "grows exponentially" in text and "beside it pitch oscillates about" in text
    assert re.search(r"Schuler − Foucault \(period 87\.99 min, amplitude 0\.17\d\d arcmin\)",
                     text)
    assert "after about 2.684 h" in text
    # a long run without growth says what it said
    assert main(["transfer", "examples/own_model/schuler_loop.py", "--source", "accel_bias",
                 "--output", "psi"]) == 0
    assert "psi oscillates about 0.2063 arcsec" in capsys.readouterr().out


def test_a_partly_cancelled_repeated_mode_is_counted(capsys):
    tf = transfer_functions("north_pointing", ["gyro_drift_east"], ["latitude"],
                            latitude=0.0)
    pair = tf.pair("gyro_drift_east", "latitude")
    [schuler_mode] = [m for m in tf.modes.modes if m.name == "Schuler"]
    assert schuler_mode.multiplicity == 2  # at the equator the pair is double
    kept = [f for f in pair.poles if f.name == "Schuler"]
    [cancelled] = [f for f in pair.cancelled if f.name == "Schuler"]
    assert sum(f.multiplicity for f in kept) + cancelled.multiplicity == 2
    assert cancelled.mode_multiplicity == 2
    assert main(["transfer", "north_pointing", "--source", "gyro_drift_east", "--output",
                 "latitude", "--latitude", "0deg"]) == 0
    out = capsys.readouterr().out
    assert "cancelled: integrator, Schuler (1 of 2 pairs))" in out
    assert "| Schuler | period 84.41 min |" in out
    # a mode cancelled whole keeps its plain name
    assert main(["transfer", "north_pointing", "--source", "accel_bias_north", "--output",
                 "latitude", "--latitude", "45deg"]) == 0
    assert "(cancelled: integrator, Earth)" in capsys.readouterr().out


def _inline_quotes() -> list[tuple[str, list[str]]]:
    """(command, quoted outputs) of each bullet of docs/transfer.md that shows an
    ``ins-errors transfer`` command inline and quotes what it prints."""
    text = (ROOT / "docs" / "transfer.md").read_text(encoding="utf-8")
    out = []
    for bullet in re.split(r"\n(?=\* )|\n\n", text):
        spans = [re.sub(r"\s+", " ", s) for s in re.findall(r"`([^`]*)`", bullet, re.S)]
        commands = [s for s in spans if s.startswith("ins-errors transfer ")]
        if len(commands) == 1:
            quotes = [s for s in spans if s not in commands and not s.startswith("-p ")
                      and re.search(r"\d", s)]
            if quotes:
                out.append((commands[0], quotes))
    return out


def test_the_page_quotes_what_its_inline_commands_print(capsys):
    quoted = _inline_quotes()
    assert len(quoted) >= 3  # the growth, the damped height, the equator's count
    for command, quotes in quoted:
        assert main(shlex.split(command)[1:]) == 0, command
        printed = capsys.readouterr().out
        for quote in quotes:
            for piece in quote.split(" …"):
                assert piece.strip(", ") in printed, (command, piece)


def test_the_settling_time_is_each_decaying_term_alone_and_says_so(capsys):
    """'within 1 % after about 449.4 days' read as the response within 1 % of its final
    value, which the sum of the two Schuler terms is only some 30 days later. The time is
    each decaying term's own (the latest of τ ln(size/1 %)) and the text now says so.
    Reference: F's eigen-decomposition at 30 digits (mpmath) for strapdown_ned damped at
    45°, 1 µg of x bias to the height: y(t) = Σ c (e^(λt) − 1)/λ, c = (h v)(w g)/(w v),
    settling at −Σ c/λ, each term's size |c/λ| (twice for a pair)."""
    import mpmath as mp

    from ins_errors import load_model
    from ins_errors.analysis.modes import static_modes

    latitude, damping = np.radians(45.0), {"k_h1": 0.0293, "k_h2": 4.42e-4}
    model = load_model("strapdown_ned")
    base = static_modes(model, latitude, parameters=damping)
    p, F = base.point, base.state_matrix
    g = np.asarray(model.source_matrix(p.x, p.u, p.p), float)[
        :, model.index("sources", "accel_bias_x")] * UG
    h = np.asarray(model.output_matrix(p.x, p.u, p.p), float)[
        [o.name for o in model.outputs].index("height")]
    with mp.workdps(30):
        values, left, right = mp.eig(mp.matrix(F.tolist()), left=True, right=True)
        n = len(F)
        level, terms = mp.mpf(0), []
        for k, value in enumerate(values):
            c = (mp.fsum(h[i] * right[i, k] for i in range(n))
                 * mp.fsum(left[k, i] * g[i] for i in range(n))
                 / mp.fsum(left[k, i] * right[i, k] for i in range(n)))
            if abs(value) < 1e-12:  # the integrators: not reached in the height
                assert abs(c) < 1e-25
                continue
            level -= c / value
            if mp.re(value) < 0 and mp.im(value) >= 0:
                size = abs(c / value) * (2 if mp.im(value) > 0 else 1)
                terms.append((float(-1 / mp.re(value)), float(size)))
        level = float(mp.re(level))
    expected = max(tau * np.log(size / (0.01 * abs(level))) for tau, size in terms)
    pair = transfer_functions(model, ["accel_bias_x"], ["height"], latitude=latitude,
                              parameters=damping).pairs[0]
    assert pair.long_run.coefficient * UG == pytest.approx(level, rel=1e-9)
    assert pair.long_run.settling_s == pytest.approx(expected, rel=1e-9)
    together = max(tau for tau, _ in terms) * np.log(
        sum(size for _, size in terms) / (0.01 * abs(level)))
    assert together > expected + 20 * 86400  # the sum: a month later at least
    assert main(["transfer", "strapdown_ned", "--source", "accel_bias_x", "--output",
                 "height", "--latitude", "45deg", "-p", "k_h1=0.0293/s", "-p",
                 "k_h2=4.42e-4/s^2"]) == 0
    out = capsys.readouterr().out
    days = expected / 86400
    assert f"each of its decaying terms below 1 % of that after about {days:.1f} days" in out
