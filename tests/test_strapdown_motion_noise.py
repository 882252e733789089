"""A strapdown INS flying a noisy motion file is told what the noise does.

The attitude of a file's flight follows its velocity (heading = course, pitch =
flight-path angle, roll = coordinated bank atan(V r / g₀)), so the body rate is made of the
velocity splines' second derivatives: logged velocity noise is differentiated twice.
The references here are independent of the flight generator: SciPy cubic splines of the
file built here, the attitude of their derivatives, and the body rate as the finite
difference of that attitude's direction-cosine matrix.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

import ins_errors
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric.motion_spec import read_motion_file

G0 = 9.80665
LAT, LON = np.radians(50.0), np.radians(30.0)
EARTH_RATE = 7.292115e-5
RUN = 300.0


def log(path: Path, noise: float, seed: int = 1) -> Path:
    """A 10-Hz log of a flight at 50 m/s that turns at 30° bank from 100 s to 160 s
    (5-s smooth roll-in and roll-out) and climbs at 2 m/s, with ``noise`` (m/s, 1σ) on
    the velocities and ten times that (m) on the height."""
    t = np.arange(0.0, 400.0 + 0.05, 0.1)
    ramp = np.clip(np.minimum(t - 100.0, 160.0 - t) / 5.0, 0.0, 1.0)
    ramp = ramp**2 * (3 - 2 * ramp)  # C¹ roll-in
    rate = G0 * np.tan(np.radians(30.0)) / 50.0 * ramp
    course = np.radians(20.0) + np.concatenate([[0.0], np.cumsum(0.05 * (rate[1:] + rate[:-1]))])
    rng = np.random.default_rng(seed)
    vN = 50.0 * np.cos(course) + noise * rng.standard_normal(t.size)
    vE = 50.0 * np.sin(course) + noise * rng.standard_normal(t.size)
    h = 1000.0 + 2.0 * t + 10 * noise * rng.standard_normal(t.size)
    np.savetxt(path, np.column_stack([t, vN, vE, h]), delimiter=",", header="t,v_N,v_E,h",
               comments="", fmt="%.6f")
    return path


@pytest.fixture(scope="module")
def model():
    return ins_errors.load_model("strapdown_ned")


@pytest.fixture(scope="module")
def twins(tmp_path_factory):
    folder = tmp_path_factory.mktemp("twins")
    return log(folder / "clean.csv", 0.0), log(folder / "noisy.csv", 0.05)


def flight(path: Path) -> st.Flight:
    return st.flight_from_profile(read_motion_file(path, LAT, LON, 0.0, 0.0))


def reference_rates(path: Path, t_end: float):
    """|ω_nb^b| (rad/s) and |f^b| without Earth rate and transport rate (m/s²) at the
    samples and the quarters between them up to ``t_end``, from SciPy splines of the
    file: the attitude's direction cosines differenced over ±0.1 µs."""
    t, vN, vE, h = np.loadtxt(path, delimiter=",", skiprows=1).T
    sN, sE, sh = CubicSpline(t, vN), CubicSpline(t, vE), CubicSpline(t, h)
    a, e2 = 6378137.0, 6.69437999014e-3
    knots = np.append(t[t < t_end], t_end)
    at = np.append((knots[:-1, None] + np.diff(knots)[:, None] * np.arange(4) / 4).ravel(),
                   t_end)

    def dcm(s):  # C_b^n of the flight-path attitude at times s
        n, e, d = sN(s), sE(s), -sh(s, 1)
        V = np.hypot(n, e)
        course_rate = (n * sE(s, 1) - e * sN(s, 1)) / V**2
        R_E = a / np.sqrt(1 - e2 * np.sin(LAT) ** 2)
        r = course_rate - e * np.tan(LAT) / (R_E + sh(s))  # on top of the geodesic
        roll, pitch, psi = np.arctan(V * r / G0), np.arctan2(-d, V), np.arctan2(e, n)
        cr, sr, cp, sp, cy, sy = (np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch),
                                  np.cos(psi), np.sin(psi))
        return np.array([[cp * cy, sr * sp * cy - cr * sy, cr * sp * cy + sr * sy],
                         [cp * sy, sr * sp * sy + cr * cy, cr * sp * sy - sr * cy],
                         [-sp, sr * cp, cr * cp]])

    delta = 1e-7  # (the rate has kinks at the samples: an error of δ × its rate jump)
    C = dcm(at)
    rate = np.einsum("jia,jka->ika", C, (dcm(at + delta) - dcm(at - delta)) / (2 * delta))
    omega = np.array([rate[2, 1], rate[0, 2], rate[1, 0]])
    gravity = 9.81  # |f| only to compare peaks of hundreds of m/s²
    f_n = np.array([sN(at, 1), sE(at, 1), -sh(at, 2) - gravity])
    return at, np.linalg.norm(omega, axis=0), np.linalg.norm(f_n, axis=0)


def test_the_measured_peak_body_rate_is_the_files(model, twins):
    earth = st._earth(model, model.parameter_vector())
    for path in twins:
        rates = st.file_rates(flight(path), earth, RUN)
        at, omega, force = reference_rates(path, RUN)
        # |ω_ib| and |ω_nb| differ by at most the Earth rate plus the transport rate
        assert abs(rates.peak_rate - omega.max()) < EARTH_RATE + 1e-5
        assert rates.peak_rate_time == pytest.approx(at[np.argmax(omega)], abs=1e-9)
        assert rates.peak_force == pytest.approx(force.max(), rel=2e-3)  # γ(φ, h) vs 9.81
    clean, noisy = (st.file_rates(flight(path), earth, RUN) for path in twins)
    # the clean log banks at 30° in 5 s: a few degrees per second at most; the noise
    # twin's double derivative makes it hundreds
    assert np.degrees(clean.peak_rate) < 10.0 < 30 * np.degrees(clean.peak_rate) \
        < np.degrees(noisy.peak_rate)
    assert noisy.noisy and not clean.noisy
    assert noisy.noise > 10 * np.radians(1.0) and clean.noise < 1e-6


def test_the_noisy_twin_gets_the_note_and_the_clean_one_does_not(model, twins):
    clean, noisy = twins
    with pytest.warns(RuntimeWarning, match="ins-errors: note:") as caught:
        traj = st.trajectory(model, flight(noisy), RUN, 0.1)
    (note,) = [str(w.message) for w in caught if "note:" in str(w.message)]
    assert str(noisy) in note and "smooth or decimate" in note
    assert traj.notes == [note.removeprefix("ins-errors: note: ")]
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        traj = st.trajectory(model, flight(clean), RUN, 0.1)  # no warning at all
    assert traj.notes == []


def _cli(capsys, *argv):
    from ins_errors.cli import main

    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_compare_and_run_say_it_in_one_line(twins, capsys, tmp_path):
    clean, noisy = twins
    argv = ["--duration", "60s", "--step", "0.1s", "-s", "gyro_scale_error_x=300ppm",
            "--no-refined"]
    status, out, err = _cli(capsys, "compare", "strapdown_ned", "--motion-file", str(noisy),
                            *argv)
    assert status == 0
    notes = [line for line in err.splitlines() if line.startswith("ins-errors: note:")]
    assert len(notes) == 1 and str(noisy) in notes[0]
    model = ins_errors.load_model("strapdown_ned")
    rates = st.file_rates(flight(noisy), st._earth(model, model.parameter_vector()), 60.0)
    assert f"{np.degrees(rates.peak_rate):.4g}°/s (t = {rates.peak_rate_time:.6g} s)" \
        in notes[0]
    status, out, err = _cli(capsys, "compare", "strapdown_ned", "--motion-file", str(noisy),
                            *argv, "--json")
    assert status == 0 and any("smooth or decimate" in w for case in json.loads(out)["cases"]
                               for w in case["warnings"])
    status, out, err = _cli(capsys, "compare", "strapdown_ned", "--motion-file", str(clean),
                            *argv)
    assert status == 0 and "note:" not in err
    for path, noted in ((noisy, True), (clean, False)):
        scenario = tmp_path / f"{path.stem}.toml"
        scenario.write_text(f'model = "strapdown_ned"\n[motion]\nkind = "file"\nfile = '
                            f'"{path.as_posix()}"\nlatitude = "50 deg"\n[run]\nduration = '
                            f'"60 s"\nstep = "0.1 s"\nrecord = "10 s"\nrefined = false\n'
                            f'[[case]]\ngyro_scale_error_x = "300 ppm"\n')
        status, out, err = _cli(capsys, "run", str(scenario), "--out",
                                str(tmp_path / path.stem), "--json")
        assert status == 0, err
        warned = [w for case in json.loads(out)["cases"] for w in case["warnings"]]
        assert any(str(path) in w and "smooth or decimate" in w for w in warned) is noted
