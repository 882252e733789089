"""The streamed strapdown truth against the full-rate one it replaces.

References: the full-rate truth (DOP853 position, exact kinematics at every step and
midpoint), computed here the way the stored trajectory computed it before it was
streamed (all samples in one evaluation) for the bit-for-bit checks; and the direct
error runs users read, whose differences between the two truths must lie far below the
linear-vs-direct differences the toolchain reports.
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest

from ins_errors.errors import DomainError, InsErrorsError
from ins_errors.numeric import strapdown_stream as ss
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate
from tests.helpers import joined_chunks

DEG = np.pi / 180.0
SOURCES = {"gyro_bias_x": 0.01 * DEG / 3600, "accel_bias_y": 5e-5,
           "initial_heading_error": 1e-4, "gyro_scale_error_z": 1e-5}


@pytest.fixture(scope="module")
def model():
    from ins_errors import load_model

    return load_model("strapdown_ned")


PROFILE_LEGS = [tr.Leg(300.0, 280.0, 75 * DEG, 2500.0), tr.Leg(123.456, 230.0, -40 * DEG, 1500.0),
                tr.Leg(12.0, 230.0, 90 * DEG, 1500.0), tr.Leg(300.0, 200.0, -90 * DEG, 500.0)]
PROFILE = tr.manoeuvre_profile(48 * DEG, 20 * DEG, 30 * DEG, 220.0, PROFILE_LEGS, h=1000.0)
"""A CLI-style profile whose leg joins fall between steps (423.456 s) with a hard turn
(90° in 12 s, about 2 g of bank)."""


def _profile_flight_at(t: float) -> tuple[float, float, float]:
    """Ground speed V (m/s), turn rate r (rad/s, to the right) and down velocity v_D (m/s)
    of PROFILE at time t, from its legs' definition: within a leg the speed, the course
    (to the left) and the height move from their start to their end values along
    s(θ) = 10θ³ − 15θ⁴ + 6θ⁵, θ = (t − start)/duration; constant after the last leg."""
    start, speed, height = 0.0, 220.0, 1000.0
    for leg in PROFILE_LEGS:
        if t < start + leg.duration:
            theta = max(t - start, 0.0) / leg.duration
            ramp = theta**3 * (10 - 15 * theta + 6 * theta**2)
            slope = 30 * theta**2 * (1 - theta) ** 2 / leg.duration  # ds/dt
            return (speed + (leg.speed - speed) * ramp, -leg.turn * slope,
                    -(leg.height - height) * slope)
        start, speed, height = start + leg.duration, leg.speed, leg.height
    return speed, 0.0, 0.0


def _flights():
    """A cruise, the standard manoeuvre, and the CLI-style profile."""
    return {"cruise": st.great_circle(50 * DEG, 30 * DEG, 60 * DEG, 250.0, 10_000.0),
            "manoeuvre": st.standard_manoeuvre(),
            "profile": st.flight_from_profile(PROFILE)}


FLIGHTS = _flights()


@pytest.fixture(scope="module")
def pairs(model):
    """(fine, interpolated) trajectories of 600 s at 100 Hz for every flight: the fine
    one stored (read twice; streamed, its signals would be computed again each time),
    the interpolated one streamed."""
    return {name: tuple(st.trajectory(model, flight, 600.0, 0.01, truth=truth,
                                      stream=truth == "interpolated")
                        for truth in ("fine", "interpolated"))
            for name, flight in FLIGHTS.items()}


def _unit_sizes(values, units):
    """Largest magnitude over the run of the quantities sharing each row's unit."""
    size = np.abs(values).max(axis=1)
    return np.array([size[[k for k, v in enumerate(units) if v == unit]].max()
                     for unit in units])


def test_fine_truth_streamed_is_the_stored_truth_bit_for_bit(model):
    """The full-rate truth in chunks of any size (and stored from chunks) has the bits of
    one evaluation of every step and midpoint, as the trajectory was built before."""
    flight = FLIGHTS["profile"]
    duration, tau = 500.0, 0.05
    n = round(duration / tau)
    p = model.parameter_vector()
    earth = st._earth(model, p)
    solution = st._position_solution(flight, earth, duration, tau)
    t = np.arange(0, n + 1) * tau
    truth, inputs, _ = st.rigid_body_signals(flight, earth, t, solution.sol(t))
    tm = (np.arange(0, n) + 0.5) * tau
    _, midpoints, _ = st.rigid_body_signals(flight, earth, tm, solution.sol(tm))
    stored = st.trajectory(model, flight, duration, tau, truth="fine", stream=False)
    assert isinstance(stored.source, ss.FullRateTruth)
    for got, want in ((stored.truth, truth), (stored.inputs, inputs),
                      (stored.midpoints, midpoints)):
        assert np.array_equal(got, want)
    streamed = st.trajectory(model, flight, duration, tau, truth="fine", stream=True)
    assert streamed.is_streamed
    for got, want in zip(joined_chunks(streamed, 777), (truth, inputs, midpoints), strict=True):
        assert np.array_equal(got, want)


# largest difference interpolated vs fine over 600 s at 100 Hz, relative to the size of
# the quantities of the same unit over the run: (states, inputs and midpoints). Measured:
# cruise 1.5e-15 / 1.4e-15; manoeuvre 5.6e-11 / 1.2e-11; profile 8.8e-8 / 3.8e-9. The
# profile's are the fine truth's own error: its position integrator reads the commands
# through cubic Hermite pieces 1/16 s long, one of which straddles the off-grid join
# before the 6-g turn (2e-4 m after it, see the test against an exact reference below).
TOLERANCES = {"cruise": (1e-13, 1e-13), "manoeuvre": (1e-9, 1e-10),
              "profile": (5e-7, 3e-8)}


@pytest.mark.parametrize("name", list(FLIGHTS))
def test_interpolated_states_and_inputs_match_the_fine_truth(model, pairs, name):
    """At every 100 Hz step and midpoint, across leg joins on and off the step grid."""
    fine, fast = pairs[name]
    assert isinstance(fast.source, ss.InterpolatedFlight)
    x_f, u_f, m_f = joined_chunks(fine)
    x_i, u_i, m_i = joined_chunks(fast)
    state_units = [s.unit for s in model.states]
    input_units = [i.unit for i in model.inputs]
    states, inputs = TOLERANCES[name]
    for fine_values, fast_values, units, tolerance in (
            (x_f, x_i, state_units, states), (u_f, u_i, input_units, inputs),
            (m_f, m_i, input_units, inputs)):
        error = np.abs(fast_values - fine_values).max(axis=1) / _unit_sizes(fine_values, units)
        assert error.max() < tolerance
    assert fast.source.worst < 1e-7  # the interpolation's own estimate (measured 3e-8)
    if name != "cruise":  # the flight really manoeuvres: body rates of turns and climbs
        assert np.abs(u_f[:3]).max() > 0.02


@pytest.mark.parametrize("name", list(FLIGHTS))
def test_direct_errors_match_far_below_linear_differences(model, pairs, name):
    fine, fast = pairs[name]
    runs = [simulate(model, t, SOURCES, method="rk4", record_interval=1.0,
                     parts=("real", "linear")) for t in (fine, fast)]
    direct_fine, direct_fast = (r.direct_errors() for r in runs)
    linear = runs[0].linear_errors()
    size = np.abs(direct_fine.values).max(axis=(1, 2))
    excited = size > 1e-12 * size.max()
    apart = np.abs(direct_fast.values - direct_fine.values).max(axis=(1, 2))[excited]
    linear_apart = np.abs(linear.values - direct_fine.values).max(axis=(1, 2))[excited]
    # measured (largest over the quantities, of each curve's size): 5e-11 (cruise), 2.5e-9
    # (manoeuvre), 3.8e-9 (profile); linear vs direct 5e-7 and more, at most 4e-4 of which
    # the two truths differ
    assert (apart / size[excited]).max() < 1e-7
    assert (apart / linear_apart).max() < 1e-2


def test_interpolated_position_follows_an_exact_integration(model, pairs):
    """Latitude, longitude and height of the interpolated truth against DOP853 at the
    tightest tolerance, restarted at every leg join and reading the speed, turn rate and
    down velocity from the legs' definition (not through the profile's commands or
    samples): 1e-8 m measured, where the fine truth is 2e-4 m off."""
    from scipy.integrate import solve_ivp

    from ins_errors.models.earth import radii_of_curvature

    flight = FLIGHTS["profile"]
    earth = st._earth(model, model.parameter_vector())

    def rhs(t, y):
        lat, _, h, psi = y
        V, r, vD = _profile_flight_at(t)  # the legs' own definition, not the commands
        R_N, R_E = radii_of_curvature(lat, earth.a, earth.e2)
        vN, vE = V * np.cos(psi), V * np.sin(psi)
        return [vN / (R_N + h), vE / ((R_E + h) * np.cos(lat)), -vD,
                vE * np.tan(lat) / (R_E + h) + r]

    checks = [150.0, 430.0, 450.0, 600.0]
    knots = sorted({0.0, *checks, *(b for b in flight.breaks if b < 600.0)})
    y = np.array([flight.latitude, flight.longitude, flight.height, flight.course])
    exact = {}
    for a, b in itertools.pairwise(knots):
        y = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=3e-14,
                      atol=1e-16 * np.array([1, 1, 1e7, 1]), max_step=1.0).y[:, -1]
        exact[b] = y
    truth = pairs["profile"][1]
    x = joined_chunks(truth)[0]
    for t in checks:
        lat, lon, h = x[7:, round(t / 0.01)]
        metres = np.array([(lat - exact[t][0]) * 6.4e6,
                           (lon - exact[t][1]) * 6.4e6 * np.cos(lat), h - exact[t][2]])
        assert np.abs(metres).max() < 1e-6, t


def test_interpolated_chunks_do_not_change_the_numbers(model):
    """Stored, streamed in any chunk size, and the first chunks of a week-long flight
    (streamed, nothing computed until run): identical to the bit."""
    flight = FLIGHTS["profile"]
    stored = st.trajectory(model, flight, 1000.0, 0.01, stream=False)
    assert isinstance(stored.source, ss.InterpolatedFlight)  # "auto" chose it
    streamed = st.trajectory(model, flight, 1000.0, 0.01, stream=True)
    for got, want in zip(joined_chunks(streamed, 3333), (stored.truth, stored.inputs,
                                                   stored.midpoints), strict=True):
        assert np.array_equal(got, want)
    week = st.trajectory(model, flight, 7 * 86400.0, 0.01)
    assert week.is_streamed and week.n_steps == 60_480_000
    first = next(week.chunks(20_000))
    assert np.array_equal(first.inputs, stored.inputs[:, :20_001])
    assert np.array_equal(first.midpoints, stored.midpoints[:, :20_000])
    assert np.array_equal(week.start_state, stored.truth[:, 0])


def test_sampled_commands_have_the_bits_of_scipys_hermite_splines():
    """The fine truth's position integrator reads the commands through cubic Hermite
    pieces evaluated on Python floats: the same bits as SciPy's CubicHermiteSpline of
    each block, at random times, on the breakpoints, just before them and at block ends,
    in the order the integrator asks (forwards) and out of order."""
    from scipy.interpolate import CubicHermiteSpline

    flight = FLIGHTS["profile"]
    commands = st._SampledCommands(flight)
    span = commands.SPACING * commands.BLOCK
    rng = np.random.default_rng(5)
    grid = np.arange(0.0, 3.5 * span, commands.SPACING)
    times = np.concatenate([np.sort(rng.uniform(0.0, 3.5 * span, 1000)), grid,
                            np.nextafter(grid[1:], 0.0), rng.uniform(0.0, 3.5 * span, 100),
                            [span, 2 * span, np.nextafter(span, 0.0)]])
    splines = {}
    for k in range(int(times.max() // span) + 1):
        knots = k * span + commands.SPACING * np.arange(commands.BLOCK + 1)
        V, dV, r, dr, vD, dvD = flight.commands(knots)
        splines[k] = CubicHermiteSpline(knots, np.array([V, r, vD]),
                                        np.array([dV, dr, dvD]), axis=1)

    def expected(times):
        """SciPy's values at every time, (T, 3): each block's spline evaluated at its
        times in one call (a spline's value at a point does not depend on the others)."""
        out = np.empty((times.size, 3))
        block = (times // span).astype(int)
        for k in np.unique(block):
            out[block == k] = splines[k](times[block == k]).T
        return out

    for t, want in zip(times, expected(times), strict=True):
        assert commands(t) == tuple(want.tolist()), t
    # a flight's commands sampled only up to its end (the last block cut short there)
    t_end = 1.5 * span + 0.03
    ending = st._SampledCommands(flight, t_end)
    times = np.concatenate([np.sort(rng.uniform(0.0, t_end, 300)), [t_end]])
    for t, want in zip(times, expected(times), strict=True):
        assert ending(t) == tuple(want.tolist()), t


def test_position_rates_are_the_exact_ones_to_rounding(model):
    """The position integrator's right-hand side (on Python floats) against the same
    equations evaluated with 40 significant digits (mpmath), at random positions, courses
    and times of the CLI-style profile: within 4 units in the last place of each rate."""
    import mpmath

    flight = FLIGHTS["profile"]
    earth = st._earth(model, model.parameter_vector())
    rhs = st._position_rhs(flight, earth)
    commands = st._SampledCommands(flight)
    rng = np.random.default_rng(11)
    a, e2 = mpmath.mpf(earth.a), mpmath.mpf(earth.e2)
    with mpmath.workdps(40):
        for _ in range(60):
            t = float(rng.uniform(0.0, 900.0))
            y = np.array([rng.uniform(-1.4, 1.4), 0.3, rng.uniform(-400.0, 12_000.0),
                          rng.uniform(-np.pi, np.pi)])
            got = rhs(t, y)
            V, r, vD = (mpmath.mpf(c) for c in commands(t))
            lat, h, psi = (mpmath.mpf(float(v)) for v in y[[0, 2, 3]])
            w = mpmath.sqrt(1 - e2 * mpmath.sin(lat) ** 2)
            R_N, R_E = a * (1 - e2) / w**3, a / w
            vN, vE = V * mpmath.cos(psi), V * mpmath.sin(psi)
            exact = [vN / (R_N + h), vE / ((R_E + h) * mpmath.cos(lat)), -vD,
                     vE * mpmath.tan(lat) / (R_E + h) + r]
            for g, e in zip(got, exact, strict=True):
                assert abs(g - float(e)) <= 4 * np.spacing(abs(float(e))), (t, y)


def test_fine_position_follows_an_exact_integration(model):
    """The fine truth's position and course (DOP853 at rtol 1e-13, steps up to 60 s,
    commands read through their Hermite samples) over 3 h, against DOP853 at the
    tightest tolerance SciPy allows with 10-s steps reading the commands directly: a
    great circle within 1e-7 m (measured 6e-9 m), and keeping Clairaut's constant
    (R_E + h) cos φ sin ψ of a geodesic of the surface at height h to 1e-14 (measured
    8e-16); a weaving flight (turns, speed and height changes) within 1e-5 m (measured
    8e-7 m)."""
    import math

    from scipy.integrate import solve_ivp

    earth = st._earth(model, model.parameter_vector())
    duration = 3 * 3600.0
    t = np.linspace(0.0, duration, 181)

    def weave(t):
        w, v = 2 * np.pi / 1200.0, 2 * np.pi / 3600.0
        return (220.0 + 30.0 * np.sin(v * t), 30.0 * v * np.cos(v * t),
                0.01 * np.cos(w * t), -0.01 * w * np.sin(w * t),
                -5.0 * np.cos(v * t), 5.0 * v * np.sin(v * t))

    # each flight with its speed, turn rate and down velocity at one time (floats): the
    # cruise's definition (250 m/s, level, no turn) and the weave's own functions
    flights = {"cruise": (FLIGHTS["cruise"], lambda t: (250.0, 0.0, 0.0), 1e-7),
               "weave": (st.Flight(50 * DEG, 30 * DEG, 5000.0, 60 * DEG, weave, "weave"),
                         lambda t: weave(t)[::2], 1e-5)}
    for name, (flight, flown, tolerance) in flights.items():
        def rhs(t, y, flown=flown):
            lat, _, h, psi = y
            V, r, vD = flown(t)
            w = math.sqrt(1 - earth.e2 * math.sin(lat) ** 2)
            R_N, R_E = earth.a * (1 - earth.e2) / w**3, earth.a / w
            vN, vE = V * math.cos(psi), V * math.sin(psi)
            return [vN / (R_N + h), vE / ((R_E + h) * math.cos(lat)), -vD,
                    vE * math.tan(lat) / (R_E + h) + r]

        y0 = [flight.latitude, flight.longitude, flight.height, flight.course]
        exact = solve_ivp(rhs, (0.0, duration), y0, method="DOP853", rtol=2.5e-14,
                          atol=1e-16 * np.array([1, 1, 1e7, 1]), max_step=10.0,
                          dense_output=True).sol(t)
        fine = st._position_solution(flight, earth, duration, 60.0).sol(t)
        lat = exact[0]
        metres = np.abs([(fine[0] - lat) * 6.4e6, (fine[1] - exact[1]) * 6.4e6 * np.cos(lat),
                         fine[2] - exact[2], (fine[3] - exact[3]) * 6.4e6])
        assert metres.max() < tolerance, (name, metres.max(axis=1))
        if name == "cruise":
            _, R_E = st.radii_of_curvature(fine[0], earth.a, earth.e2)
            clairaut = (R_E + fine[2]) * np.cos(fine[0]) * np.sin(fine[3])
            assert np.abs(clairaut / clairaut[0] - 1).max() < 1e-14


def test_manoeuvre_commands_of_any_time_span_have_the_bits_of_the_whole_flights():
    """A manoeuvre's commands evaluated over a span that leaves out some legs (they are
    skipped) equal, bit for bit, the same times evaluated with the whole flight (every
    leg evaluated)."""
    flight = FLIGHTS["manoeuvre"]
    t = np.concatenate([np.arange(0.0, 1200.0, 0.0625), [np.nextafter(b, 0) for b in
                                                         flight.breaks], flight.breaks])
    t.sort()
    whole = np.array(flight.commands(t))
    rng = np.random.default_rng(3)
    for a, b in [(0.0, 10.0), (100.0, 130.0), (119.9, 120.1), (900.0, 1200.0),
                 *np.sort(rng.uniform(0.0, 1200.0, (20, 2)), axis=1)]:
        part = (t >= a) & (t <= b)
        assert np.array_equal(np.array(flight.commands(t[part])), whole[:, part]), (a, b)


def test_coarse_steps_keep_the_full_rate_truth(model):
    """At steps of 0.5 s (fewer than 50 per interval) "auto" keeps the full-rate truth, as
    does a flight whose breaks are unknown."""
    flight = FLIGHTS["manoeuvre"]
    coarse = st.trajectory(model, flight, 600.0, 0.5)
    assert isinstance(coarse.source, ss.FullRateTruth)
    own = st.Flight(flight.latitude, flight.longitude, flight.height, flight.course,
                    flight.commands, "own")
    assert isinstance(st.trajectory(model, own, 60.0, 0.01).source, ss.FullRateTruth)


def test_bad_truth_choices_and_polar_flights_are_one_line_errors(model):
    flight = FLIGHTS["cruise"]
    with pytest.raises(InsErrorsError, match="truth"):
        st.trajectory(model, flight, 10.0, 0.01, truth="coarse")
    own = st.Flight(flight.latitude, flight.longitude, flight.height, flight.course,
                    flight.commands, "own")
    with pytest.raises(InsErrorsError, match="breaks"):
        st.trajectory(model, own, 10.0, 0.01, truth="interpolated")
    # over the pole after about 37 s: named with its time when it is run (by the truth,
    # or by the run's domain check when no step falls within 1e-6 rad of the pole)
    polar = st.great_circle(89.9 * DEG, 0.0, 0.0, 300.0)
    for truth in ("fine", "interpolated"):
        streamed = st.trajectory(model, polar, 600.0, 0.01, truth=truth, stream=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with pytest.raises(DomainError, match=r"(pole|domain).* at t = 3\d"):
                simulate(model, streamed, {"gyro_bias_x": 1e-7}, method="euler")


def test_own_flight_with_commands_that_are_not_finite_is_a_one_line_error(model):
    """The fine truth names the time span where a flight's own commands are NaN."""
    cruise = FLIGHTS["cruise"]

    def commands(t):
        V, *rest = cruise.commands(t)
        return (np.where(t > 100.0, np.nan, V), *rest)

    own = st.Flight(cruise.latitude, cruise.longitude, cruise.height, cruise.course,
                    commands, "own")
    with pytest.raises(DomainError, match=r"commands are not finite between t = \d+ and \d+ s"):
        st.trajectory(model, own, 200.0, 0.5, truth="fine")


@pytest.mark.parametrize("method", ["rk4", "euler"])
def test_streamed_run_keeps_its_bits_with_rows_read_in_place(model, monkeypatch, method):
    """A streamed run (real + linear, several pieces and a tail of single records) gives
    the same bits whether the compiled driver reads each piece's input rows where they
    lie (InputRows), reads the stream built by stacking them and copying its transpose
    (the construction it replaced), or runs in the CasADi virtual machine."""
    from ins_errors.numeric import integrators as integ
    from ins_errors.numeric import simulate as sim_module

    traj = st.trajectory(model, st.great_circle(50 * DEG, 30 * DEG, 60 * DEG, 250.0,
                                                10_000.0), 100.0, 0.01)
    monkeypatch.setattr(sim_module, "STREAM_STEPS", 3200)   # pieces of 32 records

    def run(jit=True):
        return simulate(model, traj, SOURCES, method=method, record_interval=1.0,
                        parts=("real", "linear"), jit=jit)

    new = run()
    virtual = run(jit=False)
    monkeypatch.setattr(sim_module, "_piece_rows", lambda part, method: np.ascontiguousarray(
        integ.input_stream(part.inputs, part.midpoints, method).T))
    old = run()
    for part in ("ideal", "real", "linear"):
        assert np.array_equal(getattr(new, part), getattr(old, part)), part
        assert np.array_equal(getattr(new, part), getattr(virtual, part)), part
    assert np.abs(new.linear[:, -1]).min() > 0
