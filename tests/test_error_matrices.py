"""The linear error model of any model in a convention, at the caller's samples
(ins_errors.conventions.error_matrices).

References, independent of the function:

* for ``strapdown_ned``, the maps of ins_errors.models.strapdown_conventions
  (``convention_matrices``), to the last bit;
* for a strapdown model file (examples/strapdown/strapdown_sphere.py: its attitude is the
  direction-cosine matrix, read here straight from its states) and a copy of it with its
  parameters in another order: the textbook φ-angle model's blocks, F[δv, φ] = [f^n×],
  G = [−C_b^n, 0; 0, C_b^n] (Titterton & Weston, C̃ = (I − [φ×]) C), and central
  differences of the model's ideal work from nonlinearly perturbed states, read back
  through the φ-angle, the velocity difference and the NED position difference in metres.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from ins_errors import InsErrorsError, load_model
from ins_errors.checker.check_motions import Motion
from ins_errors.checker.conventions import convention
from ins_errors.checker.derived_convention import derived_in_convention
from ins_errors.checker.navigation import navigation_arrays
from ins_errors.conventions import error_matrices
from ins_errors.models import strapdown_conventions as sc
from ins_errors.numeric import trajectories as tr

ROOT = Path(__file__).resolve().parents[1]
SPHERE_FILE = ROOT / "examples" / "strapdown" / "strapdown_sphere.py"


def _manoeuvre(model, p, seconds: float = 1800.0, step: float = 60.0) -> tr.Trajectory:
    legs = [tr.Leg(600.0, 250.0, np.radians(90.0), 0.0), tr.Leg(600.0, 300.0, 0.0, 0.0)]
    profile = tr.manoeuvre_profile(np.radians(50), np.radians(30), np.radians(60), 250.0,
                                   legs)
    return tr.trajectory(model, profile, seconds, step, p=p, stream=False)


@pytest.fixture(scope="module")
def sphere():
    return load_model(str(SPHERE_FILE))


@pytest.fixture(scope="module")
def reordered(tmp_path_factory):
    folder = tmp_path_factory.mktemp("reordered")
    text = SPHERE_FILE.read_text(encoding="utf-8")
    # the parameters (R, g, U) as (U, g, R), under another name
    lines = text.split("PARAMETERS = (\n", 1)
    head, rest = lines[0], lines[1]
    block, tail = rest.split("\n)\n", 1)
    order = {line.split('"')[1]: line for line in block.splitlines()}
    block = "\n".join(order[name] for name in ("U", "g", "R"))
    text = head + "PARAMETERS = (\n" + block + "\n)\n" + tail
    text = text.replace('name="strapdown_sphere"', 'name="sphere_reordered"')
    path = folder / "sphere_reordered.py"
    path.write_text(text, encoding="utf-8")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("INS_ERRORS_CACHE", str(folder / "cache"))  # a throw-away model
        model = load_model(str(path))
    assert [q.name for q in model.parameters] == ["U", "g", "R"]
    return model


@pytest.mark.parametrize("name, position", [("phi", "ned"), ("psi", "ned"),
                                            ("psi_modified", "ned"), ("psi", "geodetic"),
                                            ("psi_ecef", "ned")])
def test_strapdown_ned_is_convention_matrices_to_the_last_bit(name, position):
    model = load_model("strapdown_ned")
    p = model.parameter_vector()
    run = _manoeuvre(model, p)
    x, u = run.truth, run.inputs
    label = name + ("_geodetic" if position == "geodetic" else "")
    em = error_matrices(model, label, x, u, p)
    F0, G0 = sc.convention_matrices(model, name, x, u, p, position=position)
    assert em.F.shape == (x.shape[1], 9, 9) and em.G.shape == (x.shape[1], 9, 33)
    assert np.array_equal(em.F, np.moveaxis(F0, -1, 0))
    assert np.array_equal(em.G, np.moveaxis(G0, -1, 0))
    assert em.states == sc.state_names(name, position)
    assert em.sources == tuple(s.name for s in model.sources)
    one = error_matrices(model, label, x[:, 7], u[:, 7], p)  # one sample, (n_x,)
    F1, G1 = sc.convention_matrices(model, name, x[:, 7], u[:, 7], p, position=position)
    assert np.array_equal(one.F[0], F1) and np.array_equal(one.G[0], G1)


def _skew(w: np.ndarray) -> np.ndarray:
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def _fd_phi_model(model, x: np.ndarray, u: np.ndarray, p: np.ndarray, radius: float
                  ) -> np.ndarray:
    """F in (φ, δv, δr NED m) of the sphere's ideal work by central differences: a state
    perturbed by z (C̃ = exp(−[φ×]) C, ṽ = v + δv, position moved by δr metres) and the
    true state flown ±τ, z read back nonlinearly, then differenced in z."""
    def rhs(state):
        return np.asarray(model.numpy.ideal_rhs(state[:, None], u[:, None], p))[:, 0]

    def perturbed(z):
        out = x.copy()
        out[:9] = (expm(-_skew(z[:3])) @ x[:9].reshape(3, 3)).ravel()
        out[9:12] += z[3:6]
        r = radius + x[14]
        out[12] += z[6] / r
        out[13] += z[7] / (r * np.cos(x[12]))
        out[14] -= z[8]
        return out

    def error(computed, true):
        A = np.eye(3) - computed[:9].reshape(3, 3) @ true[:9].reshape(3, 3).T
        r = radius + true[14]
        return np.r_[(A[2, 1] - A[1, 2]) / 2, (A[0, 2] - A[2, 0]) / 2, (A[1, 0] - A[0, 1]) / 2,
                     computed[9:12] - true[9:12], r * (computed[12] - true[12]),
                     r * np.cos(true[12]) * (computed[13] - true[13]),
                     true[14] - computed[14]]

    def rate(computed, tau=0.5):
        f, fc = rhs(x), rhs(computed)
        return (error(computed + tau * fc, x + tau * f)
                - error(computed - tau * fc, x - tau * f)) / (2 * tau)

    scale = np.r_[[1e-5] * 3, [1e-2] * 3, [10.0] * 3]
    F = np.zeros((9, 9))
    for j in range(9):
        z = np.zeros(9)
        z[j] = scale[j]
        F[:, j] = (rate(perturbed(z)) - rate(perturbed(-z))) / (2 * scale[j])
    return F, scale


@pytest.mark.parametrize("which", ["sphere", "reordered"])
def test_a_model_file_in_phi_is_the_textbook_phi_model(which, sphere, reordered):
    model = {"sphere": sphere, "reordered": reordered}[which]
    p = model.parameter_vector()
    radius = p[[q.name for q in model.parameters].index("R")]
    run = _manoeuvre(model, p)
    x, u = run.truth, run.inputs
    em = error_matrices(model, "phi", x, u, p)
    assert em.states == ("phi_N", "phi_E", "phi_D", "dv_N", "dv_E", "dv_D",
                         "dr_N", "dr_E", "dr_D")
    assert em.sources == ("gyro_bias_x", "gyro_bias_y", "gyro_bias_z",
                          "accel_bias_x", "accel_bias_y", "accel_bias_z")
    # the checker's own route, along a motion with its navigation description
    motion = Motion("m", "m", run.times, x, u, p, navigation_arrays(model, x, u, p))
    F_route, G_route = derived_in_convention(model, convention(model, "phi"), motion)
    assert np.array_equal(em.F, F_route) and np.array_equal(em.G, G_route)
    # the textbook blocks, C_b^n straight from the states (the body → NED matrix)
    C = np.moveaxis(x[:9].reshape(3, 3, -1), -1, 0)
    f_n = np.einsum("kij,jk->ki", C, u[3:6])
    Z = np.zeros_like(C)
    G_book = np.concatenate([np.concatenate([-C, Z], axis=2), np.concatenate([Z, C], axis=2),
                             np.zeros((C.shape[0], 3, 6))], axis=1)
    assert np.abs(em.G - G_book).max() < 1e-14
    F_vphi = np.array([_skew(f) for f in f_n])
    assert np.abs(em.F[:, 3:6, 0:3] - F_vphi).max() < 1e-12 * np.abs(F_vphi).max()
    # finite differences of the ideal work, row-relative in scaled states
    for k in (0, 12, 25):
        F_fd, s = _fd_phi_model(model, x[:, k], u[:, k], p, radius)
        scaled = em.F[k] * s[None, :] / s[:, None]
        d = np.abs(F_fd - em.F[k]) * s[None, :] / s[:, None]
        assert (d / np.abs(scaled).max(axis=1, keepdims=True)).max() < 1e-6, k


def test_the_reordered_copy_gives_the_original_matrices(sphere, reordered):
    p = sphere.parameter_vector()
    run = _manoeuvre(sphere, p, 600.0)
    p_other = np.array([p[2], p[1], p[0]])  # (U, g, R)
    for name in ("phi", "psi_geodetic", "psi_ecef"):
        mine = error_matrices(sphere, name, run.truth, run.inputs, p)
        other = error_matrices(reordered, name, run.truth, run.inputs, p_other)
        assert np.allclose(other.F, mine.F, rtol=1e-12, atol=1e-12 * np.abs(mine.F).max())
        assert np.allclose(other.G, mine.G, rtol=1e-12, atol=1e-15)


def test_the_documented_convention_matrices_takes_a_model_file(sphere, reordered):
    # it mapped every model as strapdown_ned's layout: a CasADi shape error on the sphere
    # (15 states), a LinAlgError on a reordered file
    p = sphere.parameter_vector()
    run = _manoeuvre(sphere, p, 600.0)
    x, u = run.truth, run.inputs
    em = error_matrices(sphere, "psi", x, u, p)
    F, G = sc.convention_matrices(sphere, "psi", x, u, p)
    assert np.array_equal(np.moveaxis(F, -1, 0), em.F)
    assert np.array_equal(np.moveaxis(G, -1, 0), em.G)
    F1, G1 = sc.convention_matrices(reordered, "phi", x[:, 3], u[:, 3], p[::-1],
                                    position="geodetic")
    ref = error_matrices(sphere, "phi_geodetic", x[:, 3:4], u[:, 3:4], p)
    assert F1.shape == (9, 9) and np.allclose(F1, ref.F[0], rtol=1e-12, atol=1e-20)
    assert np.allclose(G1, ref.G[0], rtol=1e-12, atol=1e-20)


def test_bias_states_make_the_15_state_model(sphere):
    p = sphere.parameter_vector()
    run = _manoeuvre(sphere, p, 600.0)
    biases = ["gyro_bias_x", "gyro_bias_y", "gyro_bias_z",
              "accel_bias_x", "accel_bias_y", "accel_bias_z"]
    nine = error_matrices(sphere, "phi", run.truth, run.inputs, p)
    em = error_matrices(sphere, "phi", run.truth, run.inputs, p, bias_states=biases,
                        markov={"accel_bias_z": 3600.0})
    assert em.states == (*nine.states, *biases) and em.F.shape[1:] == (15, 15)
    assert np.array_equal(em.F[:, :9, :9], nine.F)
    assert np.array_equal(em.F[:, :9, 9:], nine.G)  # each bias's column is its source's
    assert np.array_equal(em.F[:, 9:, :9], np.zeros_like(em.F[:, 9:, :9]))
    assert np.array_equal(em.F[0, 9:, 9:], np.diag([0.0] * 5 + [-1 / 3600.0]))
    assert not em.G.any()  # every source is a state


@pytest.mark.parametrize("model, args, said", [
    ("strapdown_sphere", dict(x=np.zeros((10, 3))), "x must have shape (n_x, K) = (15, K)"),
    ("strapdown_sphere", dict(u=np.zeros((6, 2))), "u must have shape (n_u, K) = (6, 3)"),
    ("strapdown_sphere", dict(p=np.zeros(8)), "p must have shape (3,)"),
    ("strapdown_sphere", dict(x="north"), "x must be an array of numbers"),
    ("strapdown_sphere", dict(nan=True), "x contains NaN or infinite values"),
    ("strapdown_sphere", dict(convention="phy"), "did you mean 'phi'"),
    ("strapdown_sphere", dict(bias_states=["gyro_bias_q"]), "gyro_bias_q"),
    ("orthodromic", {}, "has no convention but its own error states ('model')"),
])
def test_bad_input_is_one_line(sphere, model, args, said):
    m = sphere if model == "strapdown_sphere" else load_model(model)
    p = m.parameter_vector()
    x = np.repeat(np.asarray(m.initial_state(m.initial_condition_vector(), m.input_vector(),
                                             p))[:, None], 3, axis=1)
    u = np.zeros((len(m.inputs), 3))
    if args.pop("nan", False):
        x = x.copy()
        x[0, 1] = np.nan
    kw = {"x": x, "u": u, "p": p, "convention": "phi", **args}
    with pytest.raises(InsErrorsError) as raised:
        error_matrices(m, kw.pop("convention"), kw.pop("x"), kw.pop("u"), kw.pop("p"), **kw)
    text = str(raised.value)
    assert said in text and "\n" not in text, text
    if model == "strapdown_sphere" and "x" in args and not isinstance(args["x"], str):
        with pytest.raises(InsErrorsError):  # the documented function says the same
            sc.convention_matrices(m, "phi", args["x"], u, p)
