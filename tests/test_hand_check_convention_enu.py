r"""``@convention`` files written in east-north-up names (the PhD probe's thesis).

An ENU thesis writes φ_U, δv_U, f_U, v_U, R_M (meridian) beside R_N (prime vertical), e²,
δL for the latitude error and its damping gains by their printed names. Each is read
mechanically and exactly into the convention's north-east-down names, so a file written
in ENU gets the findings of the same equations converted by hand (the reference: the
twin file ``enu_thesis_phi_ned.txt``, converted line by line, see its header).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from ins_errors.checker.convention_equations import check_convention_file
from ins_errors.errors import InsErrorsError

FAST = {"hours": 2.0, "step": 600.0, "effects": False}
DATA = Path(__file__).parent / "data" / "convention"
GAIN = {"k_h1": 0.0293}


def _findings(check) -> list[tuple]:
    return sorted((f.row, f.column, f.kind, f.severity, f.size)
                  for f in check.report.findings)


def _write(tmp_path, text: str, name: str = "f.txt") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_an_enu_file_gets_the_findings_of_its_ned_twin():
    enu = check_convention_file(DATA / "enu_thesis_phi.tex", parameters=GAIN, **FAST)
    ned = check_convention_file(DATA / "enu_thesis_phi_ned.txt", parameters=GAIN, **FAST)
    assert set(enu.lines) == set(ned.lines) == {"phi_E", "phi_N", "phi_D", "dv_E", "dv_D",
                                                "dlat", "dh"}
    a, b = _findings(enu), _findings(ned)
    assert [f[:4] for f in a] == [f[:4] for f in b]
    assert all(math.isclose(x[4], y[4], rel_tol=1e-9) for x, y in zip(a, b, strict=True))
    # the two planted slips are found, each as a mistake
    mistakes = {(f.row, f.column): f for f in enu.report.mistakes}
    assert ("dv_E", "dv_N") in mistakes
    slip = mistakes[("dlat", "dv_N")]
    assert slip.kind == "wrong symbol or index"
    assert slip.detail.startswith("R_N written where R_M belongs")
    # the damping gain row agrees with the model's value of k_h1 (k_1 in the thesis)
    assert not [f for f in enu.report.findings if f.row == "dh" and f.column == "dh"]
    assert enu.notes and "R_N is read as the prime-vertical radius" in enu.notes[0]


def test_up_components_in_text_and_in_a_vector_line(tmp_path):
    """``dot(dv_U)``, ``v_U``, ``f_U``, ``omega_ie_U`` are -dv_D, -v_D, ...: rows and a
    vector line written with them get the findings of their NED forms."""
    ned = ("@convention phi\n"
           "dot(dv_N) = f_D*phi_E - f_E*phi_D + v_D*dv_N/(R_N + h) + 2*omega_ie_D*dv_E\n"
           "dot(dv_D) = -f_N*phi_E + 2*omega_ie_D*dv_E + C33*accel_bias_z\n"
           "dot(phi) = -cross(omega_in, phi) - C_bn*gyro_bias\n")
    enu = ("@convention phi\n"
           "dot(dv_N) = -f_U*phi_E + f_E*phi_U - v_U*dv_N/(R_N + h) - 2*omega_ie_U*dv_E\n"
           "dot(dv_U) = f_N*phi_E + 2*omega_ie_U*dv_E - C33*accel_bias_z\n"
           "dot(phi) = -cross(vec(omega_in_N, omega_in_E, -omega_in_U), phi) "
           "- C_bn*gyro_bias\n")
    a = check_convention_file(_write(tmp_path, ned), **FAST)
    b = check_convention_file(_write(tmp_path, enu, "u.txt"), **FAST)
    assert a.report.mistakes
    assert set(a.lines) == set(b.lines)
    assert [f[:4] for f in _findings(a)] == [f[:4] for f in _findings(b)]
    assert all(math.isclose(x[4], y[4], rel_tol=1e-9)
               for x, y in zip(_findings(a), _findings(b), strict=True))


def test_r_n_beside_r_m_is_the_prime_vertical_radius(tmp_path):
    """A file with R_M (meridian) and R_N: R_N is the prime-vertical radius, with a
    note; before, R_M was unknown and R_N silently the meridian radius."""
    right = _write(tmp_path, "@convention phi_geodetic\n"
                   "dot(dlat) = dv_N/(R_M + h) - v_N*dh/(R_M + h)**2\n"
                   "dot(dlon) = dv_E/((R_N + h)*cos(lat)) + v_E*tan(lat)*dlat/((R_N + h)"
                   "*cos(lat)) - v_E*dh/((R_N + h)**2*cos(lat))\n")
    check = check_convention_file(right, **FAST)
    assert check.report.mistakes == []
    assert len(check.notes) == 1 and "R_M for the meridian" in check.notes[0]
    swapped = _write(tmp_path, "@convention phi_geodetic\ndot(dlat) = dv_N/(R_N + h)\n"
                     "dot(dlon) = dv_E/((R_M + h)*cos(lat))\n", "s.txt")
    kinds = {(f.row, f.column): (f.kind, f.detail) for f in
             check_convention_file(swapped, **FAST).report.mistakes}
    assert kinds[("dlat", "dv_N")][0] == "wrong symbol or index"
    assert kinds[("dlat", "dv_N")][1].startswith("R_N written where R_M belongs")
    assert kinds[("dlon", "dv_E")][1].startswith("R_M written where R_N belongs")


def test_r_n_is_named_or_defined_or_refused(tmp_path):
    head = "@convention phi_geodetic\n"
    rows = "dot(dlat) = dv_N/(R_M + h)\ndot(dlon) = dv_E/((R_N + h)*cos(lat))\n"
    named = check_convention_file(_write(tmp_path, head + "@name R_N = R_E\n" + rows),
                                  **FAST)
    assert named.notes == []
    assert not [f for f in named.report.mistakes if f.row in ("dlat", "dlon")
                and f.column in ("dv_N", "dv_E")]
    # a definition says which radius it is: no note, and it is the file's R_N
    defined = _write(tmp_path, head + "R_N = a/sqrt(1 - e2*sin(lat)**2)\n" + rows, "d.txt")
    check = check_convention_file(defined, **FAST)
    assert check.notes == [] and "R_N" in check.definitions
    assert not [f for f in check.report.mistakes if f.column in ("dv_N", "dv_E")]
    # R_N declared the meridian: the longitude rate is then a radius slip
    meridian = check_convention_file(_write(tmp_path, head + "@name R_N = R_M\n" + rows,
                                            "m.txt"), **FAST)
    assert ("dlon", "dv_E") in {(f.row, f.column) for f in meridian.report.mistakes}
    three = _write(tmp_path, head + "r_E = R_E + h\n" + rows, "t.txt")
    with pytest.raises(InsErrorsError, match=r"R_M, R_N and R_E are all used, so R_N could "
                                             r"be either radius"):
        check_convention_file(three, **FAST)
    alone = check_convention_file(_write(tmp_path, head + "dot(dlat) = dv_N/(R_N + h) "
                                         "- v_N*dh/(R_N + h)**2\n", "a.txt"), **FAST)
    assert alone.report.mistakes == []
    assert len(alone.notes) == 1 and "R_N is read as the meridian radius" in alone.notes[0]


def test_e_squared_is_the_model_eccentricity(tmp_path):
    """``e^2`` (LaTeX) and ``e**2`` (text) are the model's e2: the meridian radius
    written with it agrees; for a model with a spherical Earth it is 0, with a note."""
    tex = _write(tmp_path, "@convention phi_geodetic\n"
                 r"R_m = \frac{a(1-e^2)}{(1-e^2\sin^2 L)^{3/2}}" "\n"
                 r"\dot{\delta\varphi} = \frac{\delta v_N}{R_m + h}" "\n", "e.tex")
    check = check_convention_file(tex, **FAST)
    assert not [f for f in check.report.findings if f.column == "dv_N"]
    text = _write(tmp_path, "@convention phi_geodetic\n"
                  "dot(dlat) = dv_N/(a*(1 - e**2)/(1 - e**2*sin(lat)**2)**1.5 + h)\n")
    assert not [f for f in check_convention_file(text, **FAST).report.findings
                if f.column == "dv_N"]
    # a spherical Earth has no eccentricity: e^2 is 0 there (an ellipsoid's equations
    # hold on a sphere), said in a note naming the line
    sphere = Path(__file__).parents[1] / "examples" / "strapdown" / "strapdown_sphere.py"
    notes = check_convention_file(text, str(sphere), **FAST).notes
    assert notes == [f"{text.name}, line 2: e^2 (eccentricity squared) is read as 0: model "
                     "'strapdown_sphere' has no eccentricity, its Earth is a sphere "
                     "(parameters R, g, U)"]


def test_delta_l_is_the_latitude_error_where_l_is_the_latitude(tmp_path):
    r"""``\delta L`` (L the latitude, as T&W and Chinese texts print it) is dlat in a
    ``_geodetic`` convention: the same findings as ``\delta\varphi``."""
    row = (r"\dot{\delta\lambda} = \frac{\delta v_E}{(R_E + h)\cos L} + \frac{v_E\tan L}"
           r"{(R_E + h)\cos L}\,{LAT}")
    a = check_convention_file(_write(tmp_path, "@convention phi_geodetic\n" + row.replace(
        "{LAT}", r"\delta L") + "\n", "l.tex"), **FAST)
    b = check_convention_file(_write(tmp_path, "@convention phi_geodetic\n" + row.replace(
        "{LAT}", r"\delta\varphi") + "\n", "p.tex"), **FAST)
    assert _findings(a) == _findings(b)
    assert "dlat" not in {f.column for f in a.report.mistakes}
    # a file that defines \delta L itself keeps its definition
    own = _write(tmp_path, "@convention phi_geodetic\n" r"\delta L = \delta\varphi" "\n"
                 + row.replace("{LAT}", r"\delta L") + "\n", "o.tex")
    assert "Delta_lat" in check_convention_file(own, **FAST).definitions


def test_model_parameters_are_named_quantities(tmp_path):
    """A damping gain of the model (k_h1, printed k_1) is read with the model's value
    (set with -p) in a row and in a definition."""
    right = _write(tmp_path, "@convention phi_geodetic\nk = k_h1\ndot(dh) = -dv_D - k*dh\n")
    check = check_convention_file(right, parameters=GAIN, **FAST)
    assert not [f for f in check.report.findings if f.column == "dh"]
    wrong = _write(tmp_path, "@convention phi_geodetic\n"
                   r"\dot{\delta h} = -\delta v_D - 2 k_1 \delta h" "\n", "w.tex")
    found = [f for f in check_convention_file(wrong, parameters=GAIN, **FAST).report.mistakes
             if (f.row, f.column) == ("dh", "dh")]
    assert len(found) == 1


def test_a_hand_function_sees_the_model_parameters():
    """``nav.parameters`` of a hand-coded F and G: the values the motions are flown with."""
    from ins_errors.checker.check_motions import motions
    from ins_errors.checker.matrix_input import _kept_samples
    from ins_errors.numeric.model import load_model

    model = load_model("strapdown_ned")
    motion = motions(model, 2.0, 600.0, parameters=GAIN)[0]
    nav, _ = _kept_samples(motion)[0]
    assert nav.parameters["k_h1"] == GAIN["k_h1"]
    names = [p.name for p in model.parameters]
    assert np.isclose(nav.parameters["e2"], motion.p[names.index("e2")])
    with pytest.raises(TypeError):
        nav.parameters["k_h1"] = 1.0


def test_the_radius_note_is_one_line_on_stderr_and_in_json(tmp_path, capsys):
    import json

    from ins_errors.cli import main

    path = _write(tmp_path, "@convention phi_geodetic\n"
                  "dot(dlat) = dv_N/(R_M + h) - v_N*dh/(R_M + h)**2\n"
                  "dot(dlon) = dv_E/((R_N + h)*cos(lat))\n")
    status = main(["check", "strapdown_ned", str(path), "--json"])
    captured = capsys.readouterr()
    notes = [line for line in captured.err.splitlines() if line.startswith("ins-errors: note")]
    assert len(notes) == 1 and "R_N is read as the prime-vertical radius" in notes[0]
    assert json.loads(captured.out)["notes"] == [notes[0].removeprefix("ins-errors: note: ")]
    assert status in (0, 1)
