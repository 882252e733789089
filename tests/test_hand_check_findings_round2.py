"""Findings named as what they are (a researcher checking their own derivation).

One slip that changes two entries is one finding with the effect of both changes: the
Coriolis pair between the horizontal and the vertical velocity (matrix check), the
Coriolis pair of a plain file, a term written in the wrong row (both paths). A ratio
that is a unit slip (1/R, 2) or, at one latitude, a sin/cos swap (cot φ) is named; a
definition several mistakes come through leads them; a file labelled with the wrong
convention is told the one it agrees with; a height effect comes with the derived
model's own height error; a derived entry that is rounding is printed as 0.

Every effect figure is checked against an own propagation: the linear model built here
(from the textbook equations, or the derived F and G of
:func:`ins_errors.conventions.error_matrices`, with the hand's change put in by hand),
propagated with SciPy's ``expm`` from each initial error and source at its typical size.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from ins_errors.checker.compare import check_hand_file
from ins_errors.checker.convention_equations import check_convention_file, to_terminal
from ins_errors.checker.kinds import FUNCTION, SYMBOL
from ins_errors.checker.report import summary_counts, to_json

ROOT = Path(__file__).resolve().parent.parent
SPHERE = str(ROOT / "examples" / "strapdown" / "strapdown_sphere.py")
SCHULER = str(ROOT / "examples" / "own_model" / "schuler_loop.py")

# φ-angle equations of the sphere model, as a researcher writes them (geodetic states)
PHI_GEODETIC = """@convention phi_geodetic
{scope}
r = R + h
W_N = U*cos(lat) + v_E/r
W_E = -v_N/r
W_D = -U*sin(lat) - v_E*tan(lat)/r
dOm_N = {dOm_N}
dOm_D = -U*cos(lat)*dlat
drho_N = dv_E/r - v_E*dh/r**2
drho_E = -dv_N/r + v_N*dh/r**2
drho_D = -tan(lat)*dv_E/r - v_E*dlat/(r*cos(lat)**2) + v_E*tan(lat)*dh/r**2
K_N = {K_N}
K_E = -v_N/r
K_D = {K_D}
dK_N = 2*dOm_N + drho_N
dK_E = drho_E
dK_D = 2*dOm_D + drho_D
bg_N = C11*gyro_bias_x + C12*gyro_bias_y + C13*gyro_bias_z
bg_E = C21*gyro_bias_x + C22*gyro_bias_y + C23*gyro_bias_z
bg_D = C31*gyro_bias_x + C32*gyro_bias_y + C33*gyro_bias_z
ba_N = C11*accel_bias_x + C12*accel_bias_y + C13*accel_bias_z
ba_E = C21*accel_bias_x + C22*accel_bias_y + C23*accel_bias_z
ba_D = C31*accel_bias_x + C32*accel_bias_y + C33*accel_bias_z

dot(phi_N) = W_D*phi_E - W_E*phi_D {phi_N_extra}+ drho_N - bg_N
dot(phi_E) = W_N*phi_D - W_D*phi_N {phi_E_extra}+ drho_E - bg_E
dot(phi_D) = W_E*phi_N - W_N*phi_E + dOm_D + drho_D - bg_D

dot(dv_N) = f_E*phi_D - f_D*phi_E - (dK_E*v_D - dK_D*v_E) - (K_E*dv_D - K_D*dv_E) + ba_N
dot(dv_E) = f_D*phi_N - f_N*phi_D - (dK_D*v_N - dK_N*v_D) - (K_D*dv_N - K_N*dv_D) + ba_E
dot(dv_D) = f_N*phi_E - f_E*phi_N - (dK_N*v_E - dK_E*v_N) - (K_N*dv_E - K_E*dv_N) + ba_D

dot(dlat) = {dlat}
dot(dlon) = dv_E/(r*cos(lat)) + v_E*tan(lat)*dlat/(r*cos(lat)) - v_E*dh/(r**2*cos(lat))
dot(dh) = -dv_D
"""
RIGHT = {"scope": "", "dOm_N": "-U*sin(lat)*dlat", "K_N": "2*U*cos(lat) + v_E/r",
         "K_D": "-2*U*sin(lat) - v_E*tan(lat)/r", "phi_N_extra": "+ dOm_N ",
         "phi_E_extra": "", "dlat": "dv_N/r - v_N*dh/r**2"}
STATIC = "@scope static base"


def phi_file(tmp_path: Path, name: str = "eq.txt", **changes: str) -> Path:
    """The φ-angle equations with ``changes`` (the keys of :data:`RIGHT`)."""
    path = tmp_path / name
    path.write_text(PHI_GEODETIC.format(**{**RIGHT, **changes}), encoding="utf-8")
    return path


def static_derived(convention: str = "phi_geodetic"):
    """The derived F (9, 9) and G (9, 6) of the sphere model on the static base, the
    latitude and the Earth rate, from the model's own linearisation."""
    from ins_errors import load_model
    from ins_errors.checker.check_motions import flown_motions
    from ins_errors.conventions import error_matrices

    model = load_model(SPHERE)
    motions, _ = flown_motions(model, 1.0, 60.0)
    (static,) = [m for m in motions if m.label == "static"]
    em = error_matrices(model, convention, static.x[:, :1], static.u[:, :1], static.p)
    latitude = float(np.ravel(static.navigation["latitude"])[0])
    values = {p.name: p.default for p in model.parameters}
    return em.F[0], em.G[0], list(em.states), list(em.sources), latitude, values


def propagate(F: np.ndarray, G: np.ndarray, x0: np.ndarray, w: np.ndarray,
              seconds: float) -> np.ndarray:
    """States after ``seconds`` of x' = F x + G w (w constant) from x0, by expm."""
    n, m = G.shape
    A = np.zeros((n + m, n + m))
    A[:n, :n], A[:n, n:] = F, G
    return (expm(A * seconds) @ np.concatenate([x0, w]))[:n]


def cases(n: int, sizes_x: np.ndarray, sizes_w: np.ndarray):
    """Each initial error alone, then each source alone, at its typical size."""
    for j in range(n):
        yield np.eye(n)[j] * sizes_x[j], np.zeros(sizes_w.size)
    for b in range(sizes_w.size):
        yield np.zeros(n), np.eye(sizes_w.size)[b] * sizes_w[b]


# --------------------------------------------------------------------------------------
# 1. the Coriolis pair between the horizontal and the vertical velocity
# --------------------------------------------------------------------------------------
def test_vertical_coriolis_pair_is_one_finding_with_the_pairs_height_effect(tmp_path):
    """2Ω left out of the turn rate: the vertical pair F[dv_E, dv_D] / F[dv_D, dv_E]
    (±2Ω_N, exactly antisymmetric) is one finding, as the horizontal one is, and its
    height effect (vertical channel free) is both entries' together, beside the derived
    model's own height error: both checked against expm of the derived static F with
    ∓2U cos φ put into the two entries."""
    path = phi_file(tmp_path, scope=STATIC, K_N="v_E/r", K_D="-v_E*tan(lat)/r")
    report = check_convention_file(path, SPHERE).report
    assert len(report.mistakes) == 2
    pairs = {frozenset({f.entry, f"F[{f.pair[0]}, {f.pair[1]}]"}) for f in report.mistakes}
    assert pairs == {frozenset({"F[dv_N, dv_E]", "F[dv_E, dv_N]"}),
                     frozenset({"F[dv_E, dv_D]", "F[dv_D, dv_E]"})}
    (f,) = [f for f in report.mistakes if "dv_D" in (f.row, f.column)]
    F, G, states, sources, lat, p = static_derived()
    two_omega_n = 2 * p["U"] * math.cos(lat)
    e_, d_ = states.index("dv_E"), states.index("dv_D")
    hand = F.copy()
    hand[e_, d_] -= two_omega_n
    hand[d_, e_] += two_omega_n
    # the hand entries the check read are those built here
    i, j = states.index(f.row), states.index(f.column)
    assert f.hand == pytest.approx(hand[i, j], rel=1e-9)
    assert f.model == pytest.approx(F[i, j], rel=1e-9)
    size_x = np.array([report.magnitudes[s][0] for s in states])
    size_w = np.array([report.magnitudes[s][0] for s in sources])
    assert sources == report.sources
    e = report.vertical_effects[f.entry]
    h = states.index("dh")
    for n, hours in enumerate(e.hours):
        rows = [(abs(propagate(hand, G, x0, w, hours * 3600.0)[h]
                     - propagate(F, G, x0, w, hours * 3600.0)[h]),
                 abs(propagate(F, G, x0, w, hours * 3600.0)[h]))
                for x0, w in cases(len(states), size_x, size_w)]
        change, own = max(rows)
        assert e.motion[n] == "static" and not e.exponential[n]
        assert e.height[n] == pytest.approx(change, rel=1e-6)
        assert e.derived[n] == pytest.approx(own, rel=1e-6)
    assert "the pair together: height error, vertical channel not held" in to_terminal(
        check_convention_file(path, SPHERE))


# --------------------------------------------------------------------------------------
# 2. the Coriolis pair of a plain file
# --------------------------------------------------------------------------------------
NORTH_POINTING_F = """@scope static base
dot(delta_v_E) = -g*alpha_N + accel_bias_east
dot(delta_v_N) = g*alpha_E + accel_bias_north
dot(delta_latitude) = delta_v_N/R
dot(alpha_E) = -delta_v_N/R + U*sin(phi)*alpha_N - U*cos(phi)*alpha_U + gyro_drift_east
dot(alpha_N) = delta_v_E/R - U*sin(phi)*delta_latitude - U*sin(phi)*alpha_E + gyro_drift_north
dot(alpha_U) = tan(phi)*delta_v_E/R + U*cos(phi)*delta_latitude + U*cos(phi)*alpha_E + gyro_drift_up
"""


def north_pointing_static(p: dict[str, float], lat: float, coriolis: bool) -> tuple:
    """The textbook static F and G of a north-pointing platform INS (states δv_E, δv_N,
    δφ, δλ, α_E, α_N, α_U; sources ∇_E, ∇_N, ε_E, ε_N, ε_U), with or without the
    Coriolis terms ±2U sin φ of the velocity rows."""
    g, R, U = p["g"], p["R"], p["U"]
    s, c = math.sin(lat), math.cos(lat)
    F = np.zeros((7, 7))
    F[0, 5], F[1, 4] = -g, g
    if coriolis:
        F[0, 1], F[1, 0] = 2 * U * s, -2 * U * s
    F[2, 1] = 1 / R
    F[3, 0] = 1 / (R * c)
    F[4, 1], F[4, 5], F[4, 6] = -1 / R, U * s, -U * c
    F[5, 0], F[5, 2], F[5, 4] = 1 / R, -U * s, -U * s
    F[6, 0], F[6, 2], F[6, 4] = math.tan(lat) / R, U * c, U * c
    G = np.zeros((7, 5))
    G[0, 0] = G[1, 1] = G[4, 2] = G[5, 3] = G[6, 4] = 1.0
    return F, G


def test_plain_coriolis_pair_is_one_root_with_the_pairs_effect(tmp_path):
    """north_pointing's static F without ±2U sin φ: one root mistake (the other half
    listed under it, counted once) whose effect is both lines' together: 779 m after a
    day, not the 3.46 km of each alone; checked against expm of the textbook F."""
    from ins_errors.checker.compare import resolve_model

    path = tmp_path / "F.txt"
    path.write_text(NORTH_POINTING_F, encoding="utf-8")
    report = check_hand_file(path, model="north_pointing")
    roots = report.root_mistakes
    assert len(roots) == 1
    result, f = roots[0]
    assert f.pair and not f.merged and "one finding with its mirror" in f.detail
    (other,) = [g for r, g in report.findings if g.merged]
    assert other.pair == (f"line {result.equation.line} {result.label}", f.quantity)
    counts = summary_counts(report)["findings"]
    assert (counts["mistakes"], counts["root_mistakes"], counts["knock_on_mistakes"]) == (
        1, 1, 0)
    assert report.exit_status == 1
    halves = [x["pair"] for e in to_json(report)["equations"] for x in e["findings"]]
    assert sorted(h["merged"] for h in halves) == [False, True]
    d = resolve_model("north_pointing")
    p = {q.name: float(q.default) for q in d.parameters}
    assert p.get("ecc2", 0.0) == 0.0  # a sphere at the defaults: R is both radii
    lat = math.radians(50.0)
    F, G = north_pointing_static(p, lat, True)
    hand, _ = north_pointing_static(p, lat, False)
    size = {b.name: b.magnitude for b in report.basis}
    states = ["delta_v_E", "delta_v_N", "delta_latitude", "delta_longitude", "alpha_E",
              "alpha_N", "alpha_U"]
    sources = ["accel_bias_east", "accel_bias_north", "gyro_drift_east", "gyro_drift_north",
               "gyro_drift_up"]
    size_x = np.array([size[s] for s in states])
    size_w = np.array([size[s] for s in sources])
    for hours in (1, 24):
        worst = 0.0
        for x0, w in cases(7, size_x, size_w):
            dx = (propagate(hand, G, x0, w, hours * 3600.0)
                  - propagate(F, G, x0, w, hours * 3600.0))
            worst = max(worst, p["R"] * math.hypot(dx[2], math.cos(lat) * dx[3]))
        assert f.effect[f"position_{hours}h"] == pytest.approx(worst, rel=1e-6)
    assert f.effect["position_24h"] == pytest.approx(779, rel=2e-3)


# --------------------------------------------------------------------------------------
# 3. a term written in the wrong row
# --------------------------------------------------------------------------------------
def test_plain_term_in_the_wrong_row_is_one_finding_with_the_moves_effect(tmp_path):
    """The Schuler loop's gyro drift written in the latitude line instead of the tilt
    line: one root finding (not an extra and an omitted term, 2.85 km and 3.46 km after
    1 h), `belongs in row dot(psi)`, with the move's effect: 6.31 km after 1 h and
    136 km after 24 h, as expm of the loop with the drift moved gives."""
    path = tmp_path / "s3.txt"
    path.write_text("dot(delta_V) = -g*psi + accel_bias\n"
                    "dot(delta_phi) = delta_V/R + gyro_drift\n"
                    "dot(psi) = delta_V/R\n", encoding="utf-8")
    report = check_hand_file(path, model=SCHULER)
    (root,) = report.root_mistakes
    result, f = root
    assert result.label == "dot(delta_phi)" and f.kind == SYMBOL
    assert "belongs in row dot(psi)" in f.detail and "not row dot(delta_phi)" in f.detail
    assert summary_counts(report)["findings"]["mistakes"] == 1
    R, g = 6_371_000.0, 9.80665
    F = np.array([[0, 0, -g], [1 / R, 0, 0], [1 / R, 0, 0]])
    G = np.array([[0.0, 1.0], [0.0, 0.0], [1.0, 0.0]])   # drift -> ψ, bias -> δV
    moved = np.array([[0.0, 1.0], [1.0, 0.0], [0.0, 0.0]])  # drift -> δφ
    size = {b.name: b.magnitude for b in report.basis}
    size_x = np.array([size[s] for s in ("delta_V", "delta_phi", "psi")])
    size_w = np.array([size[s] for s in ("gyro_drift", "accel_bias")])
    for hours, expected in ((1, 6.31e3), (24, 136e3)):
        worst = max(abs(R * (propagate(F, moved, x0, w, hours * 3600.0)[1]
                             - propagate(F, G, x0, w, hours * 3600.0)[1]))
                    for x0, w in cases(3, size_x, size_w))
        assert f.effect[f"position_{hours}h"] == pytest.approx(worst, rel=1e-6)
        assert worst == pytest.approx(expected, rel=5e-3)


def test_matrix_term_in_the_wrong_row_is_one_finding_and_rounding_prints_as_zero(tmp_path):
    """−U sin φ δφ (dOm_N) written in the φ_E row instead of the φ_N row of a
    @convention file: one `wrong symbol or index` on F[phi_E, dlat] naming F[phi_N,
    dlat], whose effect alone is both entries moved (expm of the derived static F, the
    vertical channel held), and the derived entry F[phi_E, dlat], 0 but for rounding,
    is printed as 0."""
    path = phi_file(tmp_path, scope=STATIC, phi_N_extra="", phi_E_extra="+ dOm_N ")
    check = check_convention_file(path, SPHERE)
    report = check.report
    (f,) = report.mistakes
    assert (f.entry, f.kind, f.pair) == ("F[phi_E, dlat]", SYMBOL, ("phi_N", "dlat"))
    assert "it belongs in row phi_N, not phi_E" in f.detail
    F, G, states, sources, lat, p = static_derived()
    i_n, i_e, j = states.index("phi_N"), states.index("phi_E"), states.index("dlat")
    assert F[i_n, j] == pytest.approx(-p["U"] * math.sin(lat), rel=1e-12)
    assert abs(F[i_e, j]) <= 1e-12 * abs(F[i_n, j])  # 0 but for rounding
    assert "model 0 (rounding)" in to_terminal(check)
    hand = F.copy()
    hand[i_e, j], hand[i_n, j] = F[i_n, j], 0.0
    held = [states.index("dv_D"), states.index("dh")]
    size_x = np.array([report.magnitudes[s][0] for s in states])
    size_w = np.array([report.magnitudes[s][0] for s in sources])

    def hold(A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        A, B = A.copy(), B.copy()
        A[held, :] = 0.0
        A[:, held] = 0.0
        B[held, :] = 0.0
        return A, B

    radius = p["R"]
    worst = 0.0
    for x0, w in cases(len(states), size_x, size_w):
        dx = (propagate(*hold(hand, G), x0, w, 86400.0)
              - propagate(*hold(F, G), x0, w, 86400.0))
        worst = max(worst, radius * math.hypot(dx[j], math.cos(lat) * dx[j + 1]))
    alone = report.finding_effects[f.entry]
    assert alone.position == pytest.approx(worst, rel=1e-6)


# --------------------------------------------------------------------------------------
# 4. ratios named: sin/cos at one latitude, unit slips
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize(("written", "quantity", "ratio", "slip"), [
    ("U*cos(phi)*alpha_N - U*cos(phi)*alpha_U", "alpha_N", "cot(phi)",
     "cos(phi) written where sin(phi) belongs?"),
    ("U*sin(phi)*alpha_N - U*sin(phi)*alpha_U", "alpha_U", "tan(phi)",
     "sin(phi) written where cos(phi) belongs?"),
])
def test_sin_cos_swap_at_one_reference_point_is_named(tmp_path, written, quantity, ratio,
                                                      slip):
    """With `@scope static base` the only point is at φ = 50°, where cos φ/sin φ =
    0.8391 is also a constant: the swap is named (wrong function, the ratio as cot φ),
    not `hand/model = 0.8391`."""
    path = tmp_path / "one.txt"
    path.write_text("@scope static base\n"
                    f"dot(alpha_E) = -delta_v_N/R + {written} + gyro_drift_east\n",
                    encoding="utf-8")
    (result,) = [r for r in check_hand_file(path, model="north_pointing",
                                            effects=False).results]
    (f,) = result.findings
    assert f.quantity == quantity and f.kind == FUNCTION
    assert f.detail == f"hand/model = {ratio} at the one reference point: {slip}"


def test_sin_cos_swap_in_a_definition_leads_its_findings(tmp_path):
    """dOm_N with cos for sin reaches F[phi_N, dlat] and F[dv_D, dlat]: the findings by
    line begin with the definition; at rest, where the term is the whole entry,
    hand/model is cot φ (cos 50°/sin 50° = 0.8391); with `@scope static base` the entry
    says so at every sample."""
    wrong = "-U*cos(lat)*dlat"
    check = check_convention_file(phi_file(tmp_path, dOm_N=wrong), SPHERE, effects=False)
    text = to_terminal(check)
    lead = ("  the definition of dOm_N (line 7) has cos where sin belongs; it reaches "
            "F[phi_N, dlat] and F[dv_D, dlat] (2 of the 3 entries it reaches differ)")
    assert text.split("Findings by line of the hand file:\n")[1].startswith(lead)
    (f,) = [f for f in check.report.findings if f.entry == "F[phi_N, dlat]"]
    assert "on motion 'static' (φ = 50° throughout) hand/model = cot φ" in f.detail
    static = check_convention_file(phi_file(tmp_path, "static.txt", scope=STATIC,
                                            dOm_N=wrong), SPHERE, effects=False)
    (f,) = [f for f in static.report.findings if f.entry == "F[phi_N, dlat]"]
    cot = 1 / math.tan(math.radians(50.0))
    assert f.detail.startswith(f"hand/model = {cot:.6g} = cot φ at every sample")


def test_unit_slip_ratios_are_named(tmp_path):
    """−g/R ψ for −g ψ (hand/model = 1/R = 1.56961e-07) and 2δV/R for δV/R in a plain
    file; δv_N/r² for δv_N/r in a @convention file at rest (1/R again): each ratio
    named as the factor it is."""
    path = tmp_path / "gR.txt"
    path.write_text("dot(delta_V) = -g/R*psi + accel_bias\n"
                    "dot(delta_phi) = 2*delta_V/R\n", encoding="utf-8")
    found = {r.label: f for r in check_hand_file(path, model=SCHULER,
                                                 effects=False).results
             for f in r.findings}
    inverse = f"{1 / 6_371_000.0:.6g}"
    assert inverse == "1.56961e-07"
    assert found["dot(delta_V)"].detail == (
        f"hand/model = {inverse} = 1/R (R = 6.371e+06 m) at every point: a factor 1/R too "
        "many?")
    assert found["dot(delta_phi)"].detail == (
        "hand/model = 2 at every point: a factor 2 too many?")
    check = check_convention_file(phi_file(tmp_path, "m.txt", scope=STATIC,
                                           dlat="dv_N/r**2 - v_N*dh/r**2"), SPHERE,
                                  effects=False)
    (f,) = check.report.findings
    assert f.entry == "F[dlat, dv_N]"
    assert f.detail == (f"hand/model = {inverse} = 1/R (R = 6.371e+06 m) at every sample: "
                        "a factor 1/R too many?")


# --------------------------------------------------------------------------------------
# 5. the wrong convention named
# --------------------------------------------------------------------------------------
def test_phi_equations_labelled_psi_name_the_convention_they_agree_with(tmp_path):
    """φ-angle equations with the states renamed as psi_geodetic's (psi_N, dvc_N)
    under `@convention psi_geodetic` give 24 mistakes; the hint names phi_geodetic,
    and the same equations under `@convention phi_geodetic` indeed agree entirely."""
    right = PHI_GEODETIC.format(**RIGHT)
    psi = right.replace("@convention phi_geodetic", "@convention psi_geodetic")
    for a in ("N", "E", "D"):
        psi = psi.replace(f"phi_{a}", f"psi_{a}").replace(f"dv_{a}", f"dvc_{a}")
    labelled = tmp_path / "psi.txt"
    labelled.write_text(psi, encoding="utf-8")
    report = check_convention_file(labelled, SPHERE, effects=False).report
    assert len(report.mistakes) >= 5
    assert report.convention_hint.startswith(
        f"these entries agree with convention phi_geodetic (0 mistakes, against "
        f"{len(report.mistakes)} in psi_geodetic)")
    same = tmp_path / "phi.txt"
    same.write_text(right, encoding="utf-8")
    assert check_convention_file(same, SPHERE, effects=False).report.mistakes == []
