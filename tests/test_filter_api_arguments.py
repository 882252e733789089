"""What a filter designer passes to the Python API of the error model in a convention
(``ins_errors.conventions.error_matrices``) and of its discrete model
(``ins_errors.analysis.discrete_model.process_noise``) is checked as the command line
checks it: a correlation time that is no positive number of seconds, a density given as
text, a mapping that is no mapping, each refused in one line of the library's error
class, naming the bias state or source and the value (a navigation engineer's probe).

References: the density a datasheet quotes, converted by hand (0.003 deg/√h =
0.003·π/180 rad / 60 √s), and the Gauss–Markov bias row −1/τ of F.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from ins_errors import InsErrorsError, load_model
from ins_errors.analysis.discrete_model import discrete_matrices, process_noise
from ins_errors.cli import main
from ins_errors.conventions import error_matrices


@pytest.fixture(scope="module")
def strapdown():
    """strapdown_ned at rest at 45° N: (model, x, u, p)."""
    model = load_model("strapdown_ned")
    p = model.parameter_vector()
    lat = math.radians(45.0)
    x = model.initial_state(model.initial_condition_vector(latitude=lat),
                            model.input_vector(), p)
    u = model.input_vector(omega_x=7.292115e-5 * math.cos(lat),
                           omega_z=-7.292115e-5 * math.sin(lat), f_z=-9.806)
    return model, x, u, p


def _refused(call) -> str:
    """The one line ``call`` is refused with (an InsErrorsError, nothing else)."""
    with pytest.raises(InsErrorsError) as error:
        call()
    text = str(error.value)
    assert "\n" not in text, text
    return text


@pytest.mark.parametrize("tau, said", [
    (0.0, "a correlation time of 0 s makes bias state 'gyro_bias_z' white noise"),
    (-5.0, "'gyro_bias_z' must be positive and finite, got -5 s: its row of F, -1/tau, "
           "would make the bias grow"),
    (float("nan"), "'gyro_bias_z' must be positive and finite, got nan s"),
    (float("inf"), "'gyro_bias_z' must be positive and finite, got inf s"),
    (1e-320, "-1/tau overflows"),
    (True, "must be a number of seconds, got True"),
    ("300 s", "convert text with ins_errors.units.parse_quantity('300 s', 's')"),
    (np.array([300.0, 600.0]), "must be one real number (s)"),
])
def test_a_correlation_time_that_is_no_positive_number_of_seconds_is_refused(
        strapdown, tau, said):
    """τ = 0 was a bare ZeroDivisionError, τ = −5 s a silently growing bias (+0.2/s on
    the bias row), NaN a message about the samples not being true states."""
    model, x, u, p = strapdown
    text = _refused(lambda: error_matrices(model, "phi", x, u, p, bias_states=["gyro_bias_z"],
                                           markov={"gyro_bias_z": tau}))
    assert text.startswith("markov['gyro_bias_z']"), text
    assert said in text, text


@pytest.mark.parametrize("markov", ["gyro_bias_z", 300.0, [("gyro_bias_z", 300.0)]])
def test_markov_that_is_no_mapping_is_refused(strapdown, markov):
    """A name alone was read letter by letter ("a correlation time is given for 'g'"),
    a number was a bare TypeError."""
    model, x, u, p = strapdown
    text = _refused(lambda: error_matrices(model, "phi", x, u, p, bias_states=["gyro_bias_z"],
                                           markov=markov))
    assert text.startswith("markov takes a mapping bias state -> correlation time (s)"), text


def test_a_good_correlation_time_still_makes_the_bias_row_minus_one_over_tau(strapdown):
    model, x, u, p = strapdown
    em = error_matrices(model, "phi", x, u, p, bias_states=["gyro_bias_z"],
                        markov={"gyro_bias_z": np.float32(300.0)})
    assert em.F[0, -1, -1] == -1.0 / 300.0
    assert not em.F[0, -1, :-1].any()


@pytest.mark.parametrize("value, api_value", [("0s", 0.0), ("-5s", -5.0)])
def test_the_command_line_and_the_api_say_the_same_of_a_correlation_time(
        strapdown, value, api_value, tmp_path, capsys):
    """One check serves both: after how each names the value, the same words."""
    model, x, u, p = strapdown
    api = _refused(lambda: error_matrices(model, "phi", x, u, p, bias_states=["gyro_bias_z"],
                                          markov={"gyro_bias_z": api_value}))
    status = main(["matrices", "strapdown_ned", "--bias-states", "gyro_bias_z", "--markov",
                   f"gyro_bias_z={value}", "--out", str(tmp_path / "fg.npz")])
    err = capsys.readouterr().err.splitlines()
    assert status == 2 and len(err) == 1, err
    prefix = f"ins-errors: error: --markov gyro_bias_z={value}: "
    assert err[0].startswith(prefix), err
    assert err[0][len(prefix):] == api.split(": ", 1)[1]
    assert not (tmp_path / "fg.npz").exists()


@pytest.fixture(scope="module")
def with_bias(strapdown):
    """F and G with gyro_bias_x a Gauss–Markov bias state (τ = 300 s)."""
    model, x, u, p = strapdown
    return error_matrices(model, "phi", x, u, p, bias_states=["gyro_bias_x"],
                          markov={"gyro_bias_x": 300.0})


def _hinted_call(text: str):
    """The ``ins_errors.units.parse_quantity(...)`` call a message hints at."""
    found = re.search(r"(ins_errors\.units\.parse_quantity\(.*\))", text)
    assert found, text
    return found.group(1)


@pytest.mark.parametrize("keyword, name, text, reference", [
    ("white", "gyro_bias_x", "0.003 deg/rt-hr", math.radians(0.003) / 60.0),  # rad/√s
    ("white", "accel_bias_y", "50 ug/rtHz", 50e-6 * 9.80665),  # m/s²·√s
    ("markov_sigma", "gyro_bias_x", "0.01 deg/h", math.radians(0.01) / 3600.0),  # rad/s
])
def test_text_for_a_density_or_sigma_is_refused_naming_parse_quantity(
        strapdown, with_bias, keyword, name, text, reference):
    """Was a bare ``TypeError: must be real number, not str``. The call the message
    hints at, run as written, gives the SI value a hand conversion gives, and that
    value is then taken."""
    import ins_errors

    model = strapdown[0]
    em = with_bias
    extra = {"markov": {"gyro_bias_x": 300.0}} if keyword == "markov_sigma" else {}
    said = _refused(lambda: process_noise(em.F, em.G, em.states, em.sources,
                                          **{keyword: {name: text}}, **extra))
    assert said.startswith(f"process_noise: {keyword}[{name!r}] takes a number"), said
    value = eval(_hinted_call(said), {"ins_errors": ins_errors, "model": model})
    assert value == pytest.approx(reference, rel=1e-12)
    _, densities, _ = process_noise(em.F, em.G, em.states, em.sources,
                                    **{keyword: {name: value}}, **extra)
    expected = value * math.sqrt(2.0 / 300.0) if keyword == "markov_sigma" else value
    assert densities.tolist() == [expected]


@pytest.mark.parametrize("arguments, said", [
    (dict(white={"gyro_bias_x": float("nan")}), "white['gyro_bias_x']: a white-noise density "
                                                 "must be a finite number >= 0, got nan"),
    (dict(white={"gyro_bias_x": -1e-6}), "must be a finite number >= 0, got -1e-06"),
    (dict(white={"gyro_bias_x": None}), "white['gyro_bias_x'] must be a number"),
    (dict(white={"gyro_bias_x": np.ones(2)}), "must be one real number"),
    (dict(white="gyro_bias_x"), "white takes a mapping source name -> a 1σ white-noise "
                                "density"),
    (dict(markov_sigma=[("gyro_bias_x", 1e-7)], markov={"gyro_bias_x": 300.0}),
     "markov_sigma takes a mapping"),
    (dict(markov_sigma={"gyro_bias_x": 1e-7}, markov={"gyro_bias_x": 0.0}),
     "markov['gyro_bias_x']: a correlation time of 0 s"),
    (dict(markov_sigma={"gyro_bias_x": 1e-7}, markov={"gyro_bias_x": -3.0}),
     "markov['gyro_bias_x']: the correlation time of bias state 'gyro_bias_x' must be "
     "positive"),
])
def test_process_noise_refuses_bad_values_in_one_line(with_bias, arguments, said):
    """τ = 0 was a ZeroDivisionError, τ < 0 'math domain error', None or an array a
    TypeError, a name alone a ValueError of dict()."""
    em = with_bias
    text = _refused(lambda: process_noise(em.F, em.G, em.states, em.sources, **arguments))
    assert text.startswith("process_noise: "), text
    assert said in text, text


def test_discrete_matrices_names_parse_quantity_for_a_density_as_text():
    F, G = np.zeros((2, 1, 1)), np.ones((2, 1, 1))
    text = _refused(lambda: discrete_matrices(F, G, [0.0, 1.0], ["0.003 deg/rt-hr"]))
    assert "densities takes numbers in SI units" in text
    assert "parse_quantity('0.003 deg/rt-hr', UNIT)" in text
    # one step of a random walk: Q = q² Δt
    dm = discrete_matrices(F, G, [0.0, 2.0], [0.5])
    assert dm.Qd[0, 0, 0] == pytest.approx(0.5**2 * 2.0, rel=1e-15)


@pytest.mark.parametrize("motions", [["static", "cruise"], ["static"]])
def test_the_sample_count_is_said_per_motion(motions, tmp_path, capsys):
    """'37 samples of static, cruise' read as 37 in all; each motion has them."""
    out = tmp_path / "fg.npz"
    options = [part for m in motions for part in ("--motion", m)]
    assert main(["matrices", "strapdown_ned", *options, "--hours", "1", "--step", "100s",
                 "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    data = np.load(out)
    counts = {data[f"t_{m}"].size for m in motions}
    assert len(counts) == 1
    k = counts.pop()
    assert k == 37  # 0, 100, ..., 3600 s
    said = (f"{k} samples each of static and cruise" if len(motions) == 2
            else f"{k} samples of static")
    assert f"in phi at {said}" in printed.splitlines()[0], printed
