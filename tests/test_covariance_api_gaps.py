"""The covariance API's refusals of bad input, the memory of ``cross=True`` and the
warning of a growing mode (a Kalman-filter designer's findings)."""

from __future__ import annotations

import re
import tracemalloc
import warnings

import numpy as np
import pytest

import ins_errors
from ins_errors.analysis import covariance as cv
from ins_errors.analysis.discrete_model import process_noise
from ins_errors.conventions import error_matrices
from ins_errors.errors import InsErrorsError, InsErrorsWarning
from ins_errors.numeric import trajectories as tr

PHI = np.radians(45.0)
DEG_H = np.radians(1.0) / 3600.0


@pytest.fixture(scope="module")
def north_pointing():
    return ins_errors.load_model("north_pointing")


@pytest.fixture(scope="module")
def strapdown():
    return ins_errors.load_model("strapdown_ned")


@pytest.fixture(scope="module")
def ten_minutes(north_pointing):
    """north_pointing at rest, 10 steps of 60 s."""
    return cv.static_system(north_pointing, PHI, duration=600.0, step=60.0)


def _refused(call, *words: str) -> str:
    """The one-line message of the ins-errors error ``call`` raises, holding ``words``."""
    with pytest.raises(InsErrorsError) as caught:
        call()
    text = str(caught.value)
    assert "\n" not in text
    for word in words:
        assert word in text, text
    return text


# ------------------------------------------------------------------------------------
# Bad input: one line naming the problem, never a number or a numpy error
# ------------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["constant", "white"])
def test_a_correlation_time_is_refused_on_a_source_that_is_not_markov(kind):
    _refused(lambda: cv.SourceStatistics("gyro_drift_east", kind, 1e-7, -5.0),
             "tau applies only to kind 'markov'", repr(kind))


def test_functionals_of_the_wrong_widths_or_rows_are_refused(north_pointing, ten_minutes):
    n, nw = ten_minutes.E.shape
    white = [cv.SourceStatistics("gyro_drift_east", "white", 1e-7)]
    markov = [cv.SourceStatistics("gyro_drift_east", "markov", 1e-7, 100.0)]
    # C_b narrower than the model's sources: ran, weighing only the first three
    narrow = cv.Functionals(("a",), ("m",), np.ones((1, n)), np.zeros((1, 3)))
    _refused(lambda: cv.propagate(ten_minutes, markov, narrow), f"{nw} error sources",
             "3 columns")
    # names for two functionals, one row: numpy's broadcast error at .matrix
    _refused(lambda: cv.Functionals(("a", "b"), ("m",), np.ones((1, n)), np.zeros((1, nw))),
             "2 names and 1 units", "1 rows")
    # a time-varying C_x of 3 samples on an 11-time grid: IndexError
    varying = cv.Functionals(("a",), ("m",), np.ones((3, 1, n)), np.zeros((1, nw)))
    _refused(lambda: cv.propagate(ten_minutes, white, varying), "3 samples", "11 times")


@pytest.mark.parametrize("where", ["C_x", "C_b"])
@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_weights_that_are_not_finite_are_refused(ten_minutes, where, value):
    """They gave a NaN standard deviation."""
    n, nw = ten_minutes.E.shape
    C_x, C_b = np.ones((2, n)), np.zeros((2, nw))
    (C_x if where == "C_x" else C_b)[1, 0] = value
    _refused(lambda: cv.Functionals(("a", "b"), ("m", "m"), C_x, C_b), where,
             "NaN or infinite", "'b'")


@pytest.mark.parametrize("every", [0, -1, 2.5, True])
def test_an_output_stride_that_is_no_whole_number_of_steps_is_refused(ten_minutes,
                                                                       north_pointing,
                                                                       every):
    """0 divided by zero, -1 indexed out of range, 2.5 and True ran as 2 and 1."""
    fn = cv.state_and_output_functionals(north_pointing, ten_minutes)
    white = [cv.SourceStatistics("gyro_drift_east", "white", 1e-7)]
    for cross in (False, True):
        _refused(lambda cross=cross: cv.propagate(ten_minutes, white, fn, output_every=every,
                                                  cross=cross),
                 "output_every must be a whole number of grid steps >= 1", repr(every))


def test_an_output_stride_that_does_not_divide_the_grid_names_those_that_do(
        ten_minutes, north_pointing):
    """10 steps reported every 7 gave the times 0 and 420 s: the P at 600 s, the end of
    the grid, was silently left out."""
    fn = cv.state_and_output_functionals(north_pointing, ten_minutes)
    white = [cv.SourceStatistics("gyro_drift_east", "white", 1e-7)]
    for cross in (False, True):
        _refused(lambda cross=cross: cv.propagate(ten_minutes, white, fn, output_every=7,
                                                  cross=cross),
                 "output_every 7 does not divide the grid's 10 steps", "600 s",
                 "the nearest that divide it: 5 or 10")
    every_5 = cv.propagate(ten_minutes, white, fn, output_every=5)
    assert every_5.times.tolist() == [0.0, 300.0, 600.0]


def test_a_static_grid_that_is_not_a_whole_number_of_steps_is_refused(north_pointing):
    """600 s at 70 s ran 9 steps, to 630 s; trajectory() refuses the same duration."""
    text = _refused(lambda: cv.static_system(north_pointing, 0.7, duration=600.0,
                                             step=70.0),
                    "duration 600 s is not a whole number of steps of 70 s",
                    "560 s or 630 s")
    with pytest.raises(InsErrorsError) as flown:
        tr.trajectory(north_pointing, tr.static_profile(0.7), 600.0, 70.0)
    assert str(flown.value) in text     # the words trajectory() uses
    # a duration typed in decimal is a whole number of its steps
    assert cv.static_system(north_pointing, 0.7, duration=3600.0, step=0.1).times[-1] \
        == pytest.approx(3600.0, abs=1e-9)


def test_process_noise_refuses_an_initial_error_as_the_command_does(strapdown):
    """A white noise on initial_roll_error gave a zero column of Gw, as no noise drives
    an error that only sets the start; `matrices --noise` refused it."""
    system = cv.system_from_trajectory(strapdown, tr.trajectory(
        strapdown, tr.static_profile(0.7), 20.0, 1.0))
    em = error_matrices(strapdown, "phi", system.x, system.u, system.p,
                        bias_states=["gyro_bias_z"])
    _refused(lambda: process_noise(em.F, em.G, em.states, em.sources,
                                   white={"initial_roll_error": 1e-7}),
             "white['initial_roll_error']", "is an initial error")
    Gw, _, names = process_noise(em.F, em.G, em.states, em.sources,
                                 white={"gyro_bias_x": 1e-7})
    assert names == ("gyro_bias_x",) and np.any(Gw != 0)


# ------------------------------------------------------------------------------------
# Memory of cross=True
# ------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def two_hours(north_pointing):
    return cv.static_system(north_pointing, PHI, duration=7200.0, step=1.0)


def _sources(model, constants: int | None = None):
    """The model's first ``constants`` sources (default: all) as constants, two noises
    and a Markov part beside."""
    return [*(cv.SourceStatistics(s.name, "constant", 1e-5)
              for s in model.sources[:constants]),
            cv.SourceStatistics("gyro_drift_east", "white", 0.003 * DEG_H * 60.0),
            cv.SourceStatistics("gyro_drift_north", "white", 0.003 * DEG_H * 60.0),
            cv.SourceStatistics("gyro_drift_up", "markov", 0.01 * DEG_H, 3600.0)]


def _peak(call) -> tuple[object, int]:
    """What ``call`` returns and the peak of the memory numpy allocated meanwhile, B."""
    tracemalloc.start()
    try:
        result = call()
        return result, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_the_total_covariance_matrix_never_holds_one_matrix_per_source(north_pointing,
                                                                      two_hours):
    """by_source=False with cross=True built the (nt, q, q, ns) array of every source's
    matrix, then its product with the σ², and summed it: six sources more took twelve
    (nt, q, q) arrays more at the peak. Now the total is added up source by source, and
    six sources more take only their variances and sensitivities, (nt, q) each, q times
    smaller. The total is the by-source matrix to rounding."""
    fn = cv.state_and_output_functionals(north_pointing, two_hours)
    nt, q = len(two_hours.times), len(fn.names)
    peaks = []
    for constants in (6, 12):
        sources = _sources(north_pointing, constants)
        total, peak = _peak(lambda sources=sources: cv.propagate(
            two_hours, sources, fn, by_source=False, cross=True))
        peaks.append(peak)
    assert peaks[1] - peaks[0] < 6 * nt * q * q * 8 / 2, peaks
    each = cv.propagate(two_hours, sources, fn, cross=True)
    np.testing.assert_allclose(total.matrix, each.matrix, rtol=1e-13,
                               atol=1e-15 * np.abs(each.matrix).max())
    assert np.array_equal(total.variance, each.variance)


def test_the_matrix_and_correlation_are_formed_once(north_pointing, two_hours,
                                                    monkeypatch):
    """Each use summed the (nt, q, q, ns) array again (a new temporary of its size).
    Now the first use sums it a piece at a time, to the same bits as the sum in one go,
    and later uses give the same read-only array."""
    fn = cv.state_and_output_functionals(north_pointing, two_hours)
    sources = _sources(north_pointing)
    c = cv.propagate(two_hours, sources, fn, cross=True)
    nt, q, ns = c.unit_covariances.shape[0], len(fn.names), len(sources)
    monkeypatch.setattr(cv, "_SUM_CHUNK", 1000 * q * q * ns, raising=False)  # 1000 a piece
    matrix, peak = _peak(lambda: c.matrix)
    assert peak < 0.5 * nt * q * q * ns * 8
    sigma = np.array([s.sigma for s in sources])
    assert np.array_equal(matrix, (c.unit_covariances * sigma**2).sum(-1))
    correlation = c.correlation
    again, peak = _peak(lambda: (c.matrix, c.correlation, c.matrix, c.correlation))
    assert again[0] is matrix and again[2] is matrix and again[1] is correlation
    assert peak < 0.01 * nt * q * q * 8       # nothing of their size made again
    with pytest.raises(ValueError, match="read-only"):
        matrix[0, 0, 0] = 1.0
    # the correlation: the matrix over the product of the standard deviations
    k = len(c.times) - 1
    std = np.sqrt(np.diag(matrix[k]))
    live = np.outer(std, std) > 0
    np.testing.assert_allclose(c.correlation[k][live], (matrix[k] / np.outer(std, std))[live],
                               rtol=1e-12, atol=1e-15)


# ------------------------------------------------------------------------------------
# A growing mode
# ------------------------------------------------------------------------------------
def _growth_warnings(call) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call()
    return [str(w.message) for w in caught if issubclass(w.category, InsErrorsWarning)]


def _strapdown_4h(strapdown, **gains):
    p = strapdown.parameter_vector(**gains)
    return cv.system_from_trajectory(strapdown, tr.trajectory(
        strapdown, tr.static_profile(PHI), 4 * 3600.0, 10.0, p=p))


def test_an_undamped_vertical_channel_is_warned_of_a_damped_or_stable_one_not(
        strapdown, north_pointing):
    """strapdown_ned's default vertical channel (k_h1 = k_h2 = 0) over 4 h gave δh 1σ of
    1.7e9 m without a word. The warning's e-folding time is the one the propagated δh
    grows with over the last hour. With the gains set, and on north_pointing (Schuler
    and Foucault oscillations only), nothing is said."""
    system = _strapdown_4h(strapdown)
    fn = cv.state_and_output_functionals(strapdown, system)
    sources = [cv.SourceStatistics("accel_bias_z", "constant", 1e-3)]
    with pytest.warns(InsErrorsWarning) as caught:
        c = cv.propagate(system, sources, fn)
    (text,) = [str(w.message) for w in caught]
    assert text.startswith("propagate: the error equations grow exponentially")
    assert "the damping gains k_h1, k_h2 are 0 (undamped)" in text
    assert "`ins-errors modes strapdown_ned` names the mode" in text
    minutes = float(re.search(r"grows ×e every ([\d.]+) min", text)[1])
    h = c.std[:, c.index("delta_h")]
    hour = round(3600.0 / system.step)
    measured = 3600.0 / np.log(h[-1] / h[-1 - hour]) / 60.0
    assert minutes == pytest.approx(measured, rel=0.01)
    assert h[-1] > 1e6                          # the growth the warning is about
    assert _growth_warnings(lambda: cv.propagate(system, sources, fn, warn=False)) == []
    damped = _strapdown_4h(strapdown, k_h1=0.0293, k_h2=4.42e-4)
    fn = cv.state_and_output_functionals(strapdown, damped)
    sources = [cv.SourceStatistics("accel_bias_z", "constant", 1e-3)]
    assert _growth_warnings(lambda: cv.propagate(damped, sources, fn)) == []
    schuler = cv.static_system(north_pointing, PHI, duration=4 * 3600.0, step=10.0)
    fn = cv.state_and_output_functionals(north_pointing, schuler)
    sources = [cv.SourceStatistics("gyro_drift_east", "constant", 0.01 * DEG_H)]
    assert _growth_warnings(lambda: cv.propagate(schuler, sources, fn, cross=True)) == []
