"""The hand checker on every built-in model: a correct hand derivation agrees in full,
copies with injected mistakes are reported in the right line with the right kind, the
001 report's printed F is checked on a static base with its declared Foucault drop.

The correct files in tests/data were derived by hand from each model's mechanisation as
its source describes it (see their headers), not printed from the model code.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from ins_errors.checker.compare import check_hand, check_hand_file
from ins_errors.checker.notation import default_notation, names_table
from ins_errors.checker.parse import parse_hand_text
from ins_errors.cli import main
from tests.helpers import one_blas_thread_for_references

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data"
F_001 = ROOT / "examples" / "report_001" / "F.txt"

# (line starts with, old, new, quantity, kind): sign, index, missing term, wrong factor
INJECTED = {
    "north_pointing": [
        ("dot(delta_v_E)", "-alpha_N*f_U", "+alpha_N*f_U", "alpha_N", "wrong sign"),
        ("dot(alpha_N)", "alpha_U*omega_E", "alpha_U*omega_N", "alpha_U",
         "wrong symbol or index"),
        ("dot(alpha_U)", " + Delta_omega_U", "", "delta_latitude", "omitted term"),
        ("dot(delta_latitude)", "Delta_v_N/r_N", "2*Delta_v_N/r_N", "delta_v_N",
         "wrong coefficient"),
    ],
    "free_azimuth": [
        ("dot(Delta_V_y)", "+ a_zeta*alpha_x", "- a_zeta*alpha_x", "alpha_x", "wrong sign"),
        ("dot(alpha_x)", "- alpha_z*omega_y", "- alpha_z*omega_x", "alpha_z",
         "wrong symbol or index"),
        ("dot(alpha_z)", "alpha_x*omega_y - ", "-", "alpha_x", "omitted term"),
        ("dot(Delta_V_x)", "a_y*alpha_z", "2*a_y*alpha_z", "alpha_z", "wrong coefficient"),
    ],
    "geodetic_vertical": [
        ("dot(Delta_W_eta)", "+ a_zeta*alpha_x", "- a_zeta*alpha_x", "alpha_x", "wrong sign"),
        ("dot(alpha_y)", "Omega_xi*alpha_z", "Omega_eta*alpha_z", "alpha_z",
         "wrong symbol or index"),
        ("dot(alpha_x)", " + Omega_zeta*alpha_y", "", "alpha_y", "omitted term"),
        ("dot(Delta_Phi)", "-Delta_W_eta/R", "-2*Delta_W_eta/R", "delta_W_eta",
         "wrong coefficient"),
    ],
}


def _check(model: str, text: str):
    hand = parse_hand_text(text, default_notation(model))
    return check_hand(hand, model=model, effects=False)


@pytest.mark.parametrize("model", sorted(INJECTED))
def test_correct_hand_file_agrees_and_injected_mistakes_are_found(model):
    text = (DATA / f"hand_correct_{model}.txt").read_text(encoding="utf-8")
    report = _check(model, text)
    assert not report.problems
    assert {r.status for r in report.results} == {"agrees"}, [
        (r.equation.line, r.findings) for r in report.results if r.status != "agrees"]
    assert report.exit_status == 0
    lines = text.splitlines()
    where = {}
    for start, old, new, quantity, kind in INJECTED[model]:
        number = next(i for i, s in enumerate(lines) if s.startswith(start))
        assert old in lines[number], (model, start, old)
        lines[number] = lines[number].replace(old, new, 1)
        where[number + 1] = (quantity, kind)
    report = _check(model, "\n".join(lines))
    assert report.exit_status == 1
    for line, (quantity, kind) in where.items():
        found = {(f.quantity, f.kind, f.severity) for r in report.results
                 if r.equation.line == line for f in r.findings}
        assert (quantity, kind, "mistake") in found, (model, line, found)
    # nothing is reported on the lines left alone
    assert {r.equation.line for r, _ in report.findings} == set(where)


def _foucault_drop_effect(east: bool) -> dict[int, float]:
    """Largest position change (m) after 1 h and 24 h when the Foucault term of the east
    (or north) velocity equation is dropped from the report's static-base F, over the
    checker's cases (each state alone at its typical size: velocities √(gR)θ, angles θ;
    each of the file's sources: accelerations gθ, rates ω_s θ), θ = 1e-4, φ = 50°."""
    import math

    import numpy as np
    from scipy.linalg import expm

    g, R, w, theta = 9.80665, 6_371_000.0, 7.292115e-5, 1e-4
    L = math.radians(50.0)
    s, c = math.sin(L), math.cos(L)
    # states dVx (east), dVy (north), dL, dlam, Qx, Qy, Qz; sources Dx, Dy, Ex, Ey, Ez
    F = np.zeros((7, 7))
    F[0, 5], F[0, 1] = -g, 2 * w * s
    F[1, 4], F[1, 0] = g, -2 * w * s
    F[2, 1] = 1 / R
    F[3, 0] = 1 / (R * c)
    F[4, 1], F[4, 5], F[4, 6] = -1 / R, w * s, -w * c
    F[5, 0], F[5, 2], F[5, 4] = 1 / R, -w * s, -w * s
    F[6, 0], F[6, 2], F[6, 4] = math.tan(L) / R, w * c, w * c
    G = np.zeros((7, 5))
    G[0, 0] = G[1, 1] = G[4, 2] = G[5, 3] = G[6, 4] = 1.0
    dropped = F.copy()
    dropped[(0, 1) if east else (1, 0)] = 0.0
    omega_s = math.sqrt(g / R)
    sizes = [math.sqrt(g * R) * theta] * 2 + [theta] * 5
    cases = [np.eye(7)[k] * sizes[k] for k in range(7)]
    forcing = [G[:, k] * (g * theta if k < 2 else omega_s * theta) for k in range(5)]
    effect = {}
    for hours in (1, 24):
        t = hours * 3600.0

        def response(A, x0=None, b=None, t=t):
            # augmented exponential: the state and a constant source together
            M = np.zeros((8, 8))
            M[:7, :7] = A
            if b is not None:
                M[:7, 7] = b
            z = expm(M * t) @ np.r_[x0 if x0 is not None else np.zeros(7), 1.0]
            return z[:7]

        worst = 0.0
        runs = [(x0, None) for x0 in cases] + [(None, b) for b in forcing]
        with one_blas_thread_for_references():
            for x0, b in runs:
                d = response(F, x0, b) - response(dropped, x0, b)
                worst = max(worst, math.hypot(R * d[2], R * c * d[3]))
        effect[hours] = worst
    return effect


def test_report_001_printed_f_on_a_static_base(capsys):
    report = check_hand_file(F_001, model="north_pointing")
    assert report.scope == "static base" and [p.label for p in report.points] == [
        "static base"]
    assert not report.problems and not report.mistakes and report.exit_status == 0
    drops = {(r.label, f.quantity): f for r, f in report.findings}
    # the Foucault terms 2 U sin(phi) dV, each about 9 % of its line, declared dropped
    assert set(drops) == {("dot(delta_v_E)", "delta_v_N"), ("dot(delta_v_N)", "delta_v_E")}
    assert {f.severity for f in drops.values()} == {"declared drop"}
    # independently: 2 U sin 50° * sqrt(g R) θ  against  g θ (the largest term, g·Q)
    import math

    u, g, radius = 7.292115e-5, 9.80665, 6_371_000.0
    expected = 2 * u * math.sin(math.radians(50)) * math.sqrt(g * radius) / g
    for f in drops.values():
        assert f.size == pytest.approx(expected, rel=1e-6)
    # their effect, against the report's own F (the equations of F.txt, with the δλ row
    # and the Foucault terms added) propagated by SciPy's matrix exponential, with and
    # without the dropped term, each case alone at its typical size
    for (label, _), f in drops.items():
        want = _foucault_drop_effect(label == "dot(delta_v_E)")
        for hours in (1, 24):
            assert f.effect[f"position_{hours}h"] == pytest.approx(want[hours], rel=1e-3)
    # without the declaration and the scope the same rows are mistakes
    bare = "\n".join(s for s in F_001.read_text().splitlines()
                     if not s.startswith(("@neglect", "@scope")))
    loose = _check("north_pointing", bare)
    assert loose.exit_status == 1
    assert {(r.label, f.kind) for r, f in loose.root_mistakes} >= {
        ("dot(delta_v_E)", "omitted term"), ("dot(delta_v_N)", "omitted term")}
    assert main(["check", "north_pointing", str(F_001), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["scope"] == "static base" and data["summary"]["findings"]["declared_drops"] == 2


@pytest.mark.parametrize("model", ["north_pointing", "free_azimuth", "geodetic_vertical",
                                   "orthodromic"])
def test_docs_list_the_names_a_hand_file_may_use(model):
    docs = (ROOT / "docs" / "hand_check.md").read_text(encoding="utf-8")
    section = docs.split(f"### Names for `{model}`", 1)[1].split("### ", 1)[0]
    for kind, name, _ in names_table(model):
        assert f"`{name}`" in section, (model, kind, name)


def test_a_model_that_cannot_fly_a_motion_says_which():
    report = _check("north_pointing", "dot(alpha_U) = alpha_E*omega_N - alpha_N*omega_E "
                                      "+ Delta_omega_U + gyro_drift_up\n")
    assert report.skipped_motions == ["climb: the model has no vertical-velocity input V_zeta"]
    assert "climb" not in {p.motion for p in report.points}


def test_model_file_from_outside_the_package(tmp_path, capsys):
    """The tutorial's Schuler loop (a model file): δV' = −g ψ + ∇, δφ' = ψ' − ε = δV/R."""
    model = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
    hand = tmp_path / "loop.txt"
    hand.write_text("dot(delta_V) = -g*psi + accel_bias\ndot(delta_phi) = delta_V/R\n"
                    "dot(psi) = delta_V/R + gyro_drift\n")
    assert main(["check", model, str(hand)]) == 0
    assert "3 agree" in capsys.readouterr().out
    hand.write_text("dot(delta_V) = g*psi + accel_bias\n")
    assert main(["check", model, str(hand), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    ((finding,),) = [e["findings"] for e in data["equations"]]
    assert (finding["quantity"], finding["kind"]) == ("psi", "wrong sign")


def test_strapdown_position_lines():
    """strapdown_ned: height and latitude rates, with R_N's variation from the model."""
    text = ("dot(Delta_h) = -Delta_v_D\n"
            "dot(Delta_phi) = Delta_v_N/(R_N + h) - v_N/(R_N + h)**2*(Delta_R_N + Delta_h)\n"
            "dot(Delta_lambda) = Delta_v_E/((R_E + h)*cos(lat)) - v_E/((R_E + h)**2*cos(lat))"
            "*(Delta_R_E + Delta_h) + v_E*sin(lat)/((R_E + h)*cos(lat)**2)*Delta_phi\n")
    report = _check("strapdown_ned", text)
    assert report.exit_status == 0 and len(report.results) == 3
    assert "climb" in {p.motion for p in report.points}  # v_D0 sets the climb
    wrong = _check("strapdown_ned", text.replace("= -Delta_v_D", "= Delta_v_D"))
    ((result, finding),) = wrong.mistakes
    assert (result.equation.line, finding.kind) == (1, "wrong sign")


@pytest.mark.parametrize(("directive", "message"), [
    ("@scope moving", "@scope: unknown motion class 'moving'"),
    ("@magnitude m/s = abc", "cannot read 'abc' as a quantity"),
    ("@magnitude furlong = 3 m", "magnitude for unknown unit 'furlong'"),
    ("@neglect Delta_Rq_xi", "Rq_xi has no variation in the model"),
])
def test_bad_directives_are_one_line_input_errors(tmp_path, capsys, directive, message):
    path = tmp_path / "bad.txt"
    path.write_text(f"{directive}\ndot(alpha_x) = -omega_eta*alpha_z + omega_zeta*alpha_y "
                    "+ Delta_omega_xi + omega_dp\n")
    assert main(["check", "orthodromic", str(path)]) == 2
    captured = capsys.readouterr()
    assert message in captured.out + captured.err
    assert "Traceback" not in captured.out + captured.err


def test_a_wrong_term_in_an_input_that_is_zero_at_every_point_is_a_mistake(tmp_path, capsys):
    """The Schuler loop flies only level, unaccelerated points (a_N = 0 at each), so a
    wrong term 5 a_N ψ agrees there. Physics: f~ = a_N cos ψ − g sin ψ + ∇ has
    ∂/∂ψ = −a_N sin ψ − g cos ψ = −g at ψ = 0, with no a_N: the term is extra."""
    model = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
    hand = tmp_path / "aN.txt"
    correct = ("dot(delta_V) = -g*psi + accel_bias\ndot(delta_phi) = delta_V/R\n"
               "dot(psi) = delta_V/R + gyro_drift\n")
    hand.write_text(correct.replace("+ accel_bias", "+ accel_bias + 5*a_N*psi"))
    assert main(["check", model, str(hand), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    (finding,) = [f for e in data["equations"] for f in e["findings"]]
    assert (finding["quantity"], finding["kind"], finding["class"]) == (
        "psi", "extra term", "mistake")
    assert "a_N is 0 at every reference point" in finding["detail"]
    assert data["equations"][0]["line"] == 1 and finding["size"] is None
    hand.write_text(correct.replace("= delta_V/R + gyro_drift",
                                    "= delta_V/R + gyro_drift + 0*a_N*psi"))
    assert main(["check", model, str(hand)]) == 0  # a zero coefficient is no term


def test_sources_the_file_leaves_out_are_named_on_the_terminal(tmp_path, capsys):
    """δV' = −g ψ + ∇ and ψ' = δV/R + ε written without ∇ and ε agree (both sides take
    the sources as zero) but the terminal says so; the initial tilt, which only sets
    the initial state, and sources of lines the file does not write are not named."""
    model = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
    hand = tmp_path / "nosrc.txt"
    hand.write_text("dot(delta_V) = -g*psi\ndot(delta_phi) = delta_V/R\n"
                    "dot(psi) = delta_V/R\n")
    assert main(["check", model, str(hand)]) == 0
    out = capsys.readouterr().out
    (line,) = [s for s in out.splitlines() if "never mentions" in s]
    assert line.endswith("not checked): gyro_drift, accel_bias")
    hand.write_text("dot(delta_V) = -g*psi\ndot(delta_phi) = delta_V/R\n")
    assert main(["check", model, str(hand), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["unchecked_sources"] == ["accel_bias"]
    assert data["out_of_scope"] == ["gyro_drift", "accel_bias", "initial_tilt"]


@pytest.mark.parametrize(("line", "kind", "detail"), [
    ("dot(delta_phi) = delta_V/R**2", "wrong exponent", "exponent -2 of R where -1 belongs"),
    ("dot(delta_phi) = delta_V/sqrt(R)", "wrong exponent",
     "exponent -1/2 of R where -1 belongs"),
    ("dot(delta_V) = -g**2*psi + accel_bias", "wrong exponent",
     "exponent 2 of g where 1 belongs"),
    # a plain factor stays a coefficient (2 is no power of R or g), named as a factor
    ("dot(delta_phi) = 2*delta_V/R", "wrong coefficient",
     "hand/model = 2 at every point: a factor 2 too many?"),
])
def test_exponent_slips_on_model_parameters(tmp_path, capsys, line, kind, detail):
    """δφ' = δV/R and δV' = −g ψ + ∇ (the tutorial's loop) with one exponent changed: the
    constant ratio (1/R, R^-1/2, g) is an exponent slip, not an opaque factor."""
    model = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
    hand = tmp_path / "exp.txt"
    hand.write_text(line + "\n")
    assert main(["check", model, str(hand), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    (finding,) = [f for e in data["equations"] for f in e["findings"]]
    assert (finding["kind"], finding["detail"]) == (kind, detail)


@pytest.mark.parametrize(("name", "text"), [
    ("fd.txt", "Delta_f = accel_bias + g*psi\ndot(delta_V) = Delta_f\n"
               "dot(delta_phi) = delta_V/R\ndot(psi) = delta_V/R + gyro_drift\n"),
    # as the generated equations print the real-work specific force: \Delta \tilde{f}
    ("ft.tex", "\\Delta \\tilde{f} = \\nabla + g \\psi\n\\Delta\\dot{V} = \\Delta\\tilde{f}\n"
               "\\Delta\\dot{\\varphi} = \\frac{\\Delta V}{R}\n"
               "\\dot{\\psi} = \\frac{\\Delta V}{R} + \\varepsilon\n"),
])
def test_a_real_work_intermediate_is_checked_and_blamed(tmp_path, capsys, name, text):
    """f~ = a_N cos ψ − g sin ψ + ∇ exists only in the real work; to first order
    Δf = ∇ − g ψ. A file that writes +g ψ has its mistake in that line (the root), and
    δV' = Δf carries it as a knock-on; written with −g ψ everything agrees."""
    model = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
    hand = tmp_path / name
    hand.write_text(text)
    assert main(["check", model, str(hand), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert not data["problems"]
    found = {(e["line"], f["quantity"], f["kind"], f["role"])
             for e in data["equations"] for f in e["findings"]}
    assert found == {(1, "psi", "wrong sign", "root"), (2, "psi", "wrong sign", "knock-on")}
    assert data["equations"][0]["compared_with"] == "intermediate f"
    hand.write_text(text.replace("+ g*psi", "- g*psi").replace("+ g \\psi", "- g \\psi"))
    assert main(["check", model, str(hand)]) == 0
    assert "4 agree" in capsys.readouterr().out


def test_cruise_points_are_labelled_on_the_models_sphere():
    """The cruise points sit at fixed arcs of the great circle (2000 km and 4000 km on a
    6371 km sphere); on a Mars-sized loop (R = 3389.5 km) the label gives that arc on the
    model's sphere, and the latitude there follows the spherical-triangle formula
    sin φ = sin φ0 cos s + cos φ0 sin s cos χ0 (φ0 50°, track χ0 60°)."""
    import dataclasses
    import importlib.util
    import math

    from ins_errors.checker.reference import reference_points
    from ins_errors.modeling import Parameter

    spec = importlib.util.spec_from_file_location(
        "schuler_loop_mars", ROOT / "examples" / "own_model" / "schuler_loop.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    earth = module.build()
    mars = dataclasses.replace(earth, name="schuler_mars", parameters=(
        Parameter("R", "m", "Mars radius", "R", 3_389_500.0),
        Parameter("g", "m/s**2", "gravity", "g", 3.721)))
    assert [p.label for p in reference_points(earth).points] == [
        "static base", "cruise 0 km", "cruise 2000 km", "cruise 4000 km"]
    points = reference_points(mars).points
    labels = [p.label for p in points]
    arcs = [2000 / 6371, 4000 / 6371]
    assert labels == ["static base", "cruise 0 km"] + [
        f"cruise {round(s * 3389.5 / 10) * 10} km" for s in arcs]
    assert labels[2:] == ["cruise 1060 km", "cruise 2130 km"]
    phi = next(v for v in mars.states if v.name == "phi").symbol
    lat0, track0 = math.radians(50.0), math.radians(60.0)
    for point, s in zip(points[2:], arcs, strict=True):
        expected = math.asin(math.sin(lat0) * math.cos(s)
                             + math.cos(lat0) * math.sin(s) * math.cos(track0))
        assert point.values[phi] == pytest.approx(expected, abs=1e-12)
        assert "radius 3390 km" in point.description


def test_an_indexed_latex_letter_the_model_has_without_index_is_named(tmp_path, capsys):
    """\\nabla is the loop's one accelerometer bias: \\nabla_N is no model name, and the
    message points at \\nabla, not at the similar-looking a_N."""
    model = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
    hand = tmp_path / "nabla.tex"
    hand.write_text("\\Delta\\dot{V} = -g \\psi + \\nabla_N\n")
    assert main(["check", model, str(hand)]) == 2
    out = capsys.readouterr().err  # nothing of the file was checked: its problem, on stderr
    assert "unknown symbol 'nabla_N'; did you mean 'nabla' (accel_bias" in out
    assert "'a_N'" not in out


def _ground_velocity_after(d, values, seconds):
    """(v_N, v_E) of the model's outputs after an ideal run of ``seconds`` (RK4, 0.5 s
    steps; negative: backwards) from the point ``values``, its inputs held but the
    height following the vertical velocity."""
    import numpy as np
    import sympy as sp

    names = [o.name for o in d.outputs]
    rhs = sp.lambdify([d.x, d.u, d.p], list(d.ideal_rhs_expanded()), "numpy")
    out = sp.lambdify([d.x, d.u, d.p], list(d.outputs_expanded()), "numpy")
    inputs = {v.name: k for k, v in enumerate(d.inputs)}
    x = np.array([values[s] for s in d.x])
    u0 = np.array([values[s] for s in d.u])
    p = [values[s] for s in d.p]

    def inputs_at(t):
        u = u0.copy()
        if "h" in inputs:
            u[inputs["h"]] += u0[inputs["V_zeta"]] * t
        return u

    def f(t, x):
        return np.asarray(rhs(x, inputs_at(t), p), dtype=float)

    n = 4
    dt = seconds / n
    t = 0.0
    for _ in range(n):
        k1 = f(t, x)
        k2 = f(t + dt / 2, x + dt / 2 * k1)
        k3 = f(t + dt / 2, x + dt / 2 * k2)
        k4 = f(t + dt, x + dt * k3)
        x, t = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4), t + dt
    y = out(x, inputs_at(t), p)
    return np.array([float(y[names.index("v_N")]), float(y[names.index("v_E")])])


@pytest.mark.parametrize("model", ["orthodromic", "free_azimuth"])
def test_the_climb_point_accelerates_along_the_ground_track(model):
    """At the climb point the ground velocity (the model's own v_N, v_E outputs) grows by
    1 m/s² along the track and does not turn off it: the rate is measured by a central
    difference of two 2 s ideal runs from the point with its solved inputs, not from how
    the point was built. The old point accelerated the absolute velocity states (they
    carry the Earth's rotation, ~20° off the track at 150 m/s): 0.94 m/s² along and
    0.36 m/s² across. A great circle turns in azimuth at v_E tan φ / R, so its ground
    velocity has an across-track rate V v_E tan φ / R ≈ 0.004 m/s² here; the orthodromic
    climb follows its orthodrome and shows that, the free-azimuth climb (whose velocity
    axes keep a fixed absolute azimuth) turns by the Earth rate's vertical part besides."""
    import numpy as np

    from ins_errors.checker.reference import reference_points
    from ins_errors.model_lookup import definition_of, resolve

    d = definition_of(resolve(model))
    point = next(p for p in reference_points(d).points if p.motion == "climb")
    v = _ground_velocity_after(d, point.values, 0.0)
    rate = (_ground_velocity_after(d, point.values, 2.0)
            - _ground_velocity_after(d, point.values, -2.0)) / 4.0
    speed = np.hypot(*v)
    along, across = (v @ rate) / speed, (v[0] * rate[1] - v[1] * rate[0]) / speed
    assert speed == pytest.approx(150.0, rel=1e-9)
    assert along == pytest.approx(1.0, abs=1e-4)
    assert abs(across) < 0.015
    if model == "orthodromic":
        latitude, radius = np.radians(50.0), 6_378_137.0 + 3_000.0
        great_circle = speed * v[1] * np.tan(latitude) / radius
        assert across == pytest.approx(great_circle, rel=0.01)


def test_the_earth_part_is_zero_exactly_when_sympy_simplifies_it_to_zero():
    """The reference points decide whether a model's velocity states carry the Earth's
    rotation by a numeric look at one point before SymPy's simplify (which took seconds
    on free_azimuth's parts): the verdict is simplify's for zeros in disguise (tiny at the
    point), for expressions that are zero or not a finite number at the point without
    being zero (simplify decides) and for nonzero ones; and the models whose velocity
    states are absolute (orthodromic's V_ξ, V_η, free_azimuth's V_x, V_y) are the ones
    with an Earth part (the climb test above measures what it does to the point)."""
    import sympy as sp

    from ins_errors.checker import reference
    from ins_errors.models import definition, model_names

    x, y = sp.symbols("x y", positive=True)
    cases = [sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1, y * (sp.cosh(x) ** 2 - sp.sinh(x) ** 2 - 1),
             (x + 1) ** 2 - x ** 2 - 2 * x - 1, 1 / (x - x), 1e-30 * y,
             sp.sqrt(y - 2) - sp.I * sp.sqrt(2 - y), sp.Float(1e-25), x * y - 1, sp.sin(x)]
    verdicts = [reference._identically_zero(e) for e in cases]
    assert verdicts == [sp.simplify(e) == 0 for e in cases]
    assert verdicts[:3] == [True] * 3 and verdicts[-2:] == [False] * 2
    with_earth = set()
    for name in model_names():
        d = definition(name)
        outputs = dict(zip((v.name for v in d.outputs), d.outputs_expanded(), strict=True))
        at_rest = {v.symbol: sp.S.Zero if v.name in reference._GROUND_VELOCITY
                   else outputs[v.name] for v in d.initial_conditions
                   if v.name in reference._GROUND_VELOCITY or v.name in outputs}
        parts = [d.initial_state[k].xreplace(at_rest)
                 for k, v in enumerate(d.states) if v.unit == "m/s"]
        if not all(reference._identically_zero(e) for e in parts):
            with_earth.add(name)
    assert with_earth == {"orthodromic", "free_azimuth"}
