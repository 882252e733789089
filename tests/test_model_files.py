"""Model files from outside the package: derive, lookup, staleness, mistakes.

The model under test is the tutorial's single-axis Schuler loop
(``examples/own_model/schuler_loop.py``). Its physics is checked against textbook
relations that do not come from the code: the loop oscillates at ω_s = √(g/R)
(period 84.4 min for R = 6371 km); a constant accelerometer bias b gives the tilt
ψ = (b/g)(1 − cos ω_s t) (mean b/g) and the latitude error (b/g)(1 − cos ω_s t); a
constant gyro drift ε gives the latitude error ε (sin ω_s t / ω_s − t).
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.cli import main
from tests.helpers import fresh_model_cache

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
R, G = 6_371_000.0, 9.80665
OMEGA = math.sqrt(G / R)


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """Generated code of model files goes to a fresh cache per test."""
    return fresh_model_cache(tmp_path, monkeypatch)


def copy_model(tmp_path: Path, *replacements: tuple[str, str],
               name: str = "my_ins.py") -> Path:
    """A copy of the Schuler loop file with text replacements (a deliberate mistake)."""
    text = SCHULER.read_text(encoding="utf-8")
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new)
    target = tmp_path / name
    target.write_text(text, encoding="utf-8")
    return target


# --------------------------------------------------------------------------------------
# derive and lookup
# --------------------------------------------------------------------------------------
def test_derive_writes_the_generated_package(tmp_path, capsys):
    out = tmp_path / "out" / "own"
    assert main(["derive", str(SCHULER), "--out", str(out)]) == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == ["__init__.py", "casadi_model.py", "error_equations.md", "numpy_model.py"]
    init = (out / "__init__.py").read_text(encoding="utf-8")
    assert init.startswith("# GENERATED FILE")
    assert "MODEL_FILE = 'schuler_loop.py'" in init
    assert hashlib.sha256(SCHULER.read_bytes()).hexdigest() in init
    numpy_src = (out / "numpy_model.py").read_text(encoding="utf-8")
    assert "def second_order(" in numpy_src and "def state_matrix(" in numpy_src
    listing = (out / "error_equations.md").read_text(encoding="utf-8")
    assert r"\psi" in listing
    assert not list(out.parent.glob(".own.*")), "scratch folder left behind"
    # deriving again replaces the package byte for byte
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert main(["derive", str(SCHULER), "--out", str(out)]) == 0
    assert before == {p.name: p.read_bytes() for p in out.iterdir()}


def test_state_matrix_oscillates_at_the_schuler_frequency():
    model = load_model(str(SCHULER))
    F = model.state_matrix(np.zeros(2), np.zeros(1))
    eigenvalues = np.linalg.eigvals(F)
    oscillating = sorted(eigenvalues, key=lambda z: z.imag)
    assert abs(oscillating[0] + 1j * OMEGA) < 1e-12 and abs(oscillating[-1] - 1j * OMEGA) < 1e-12
    period_min = 2 * math.pi / oscillating[-1].imag / 60
    assert abs(period_min - 84.4) < 0.05  # textbook Schuler period


def _direct(model, sources: dict[str, float], seconds: float):
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.simulate import simulate

    trajectory = tr.trajectory(model, tr.static_profile(math.radians(50)), seconds, 10.0)
    return simulate(model, trajectory, sources, method="rk4", record_interval=60.0)


def test_accelerometer_bias_gives_tilt_b_over_g():
    model = load_model(str(SCHULER))
    b = 1e-3  # m/s², about 100 µg
    run = _direct(model, {"accel_bias": b}, 10_140.0)  # two Schuler periods, 10 130 s
    errors = run.direct_errors()
    t = errors.times
    psi = errors["psi"][:, 0]
    assert np.allclose(psi, b / G * (1 - np.cos(OMEGA * t)), rtol=0, atol=1e-6 * b / G)
    assert abs(psi.mean() - b / G) < 0.02 * b / G  # two whole periods: mean tilt b/g
    latitude = errors["delta_latitude"][:, 0]
    assert np.allclose(latitude, b / G * (1 - np.cos(OMEGA * t)), rtol=0, atol=1e-6 * b / G)


def test_gyro_drift_gives_growing_latitude_error():
    model = load_model(str(SCHULER))
    eps = math.radians(0.01) / 3600  # 0.01 deg/h
    errors = _direct(model, {"gyro_drift": eps}, 3 * 3600.0).direct_errors()
    t = errors.times
    expected = eps * (np.sin(OMEGA * t) / OMEGA - t)
    assert np.allclose(errors["delta_latitude"][:, 0], expected, rtol=0,
                       atol=1e-5 * np.abs(expected).max())


def test_compare_linear_agrees_with_direct(capsys):
    assert main(["compare", str(SCHULER), "--source", "accel_bias=100ug", "--source",
                 "gyro_drift=0.01deg/h", "--hours", "3", "--step", "10s", "--method", "rk4",
                 "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["model"] == "schuler_loop"
    for row in result["cases"][0]["metrics"]:
        assert row["excited"] and row["max_direct"] > 0
        # the direct run keeps sin ψ: it differs from the linear one, by O(ψ²) relative
        assert 0 < row["linear_ratio"] < 1e-6, row


def test_models_lists_the_file_and_names_derivation_once(capsys):
    assert main(["models", str(SCHULER)]) == 0
    captured = capsys.readouterr()
    assert "gyro_drift" in captured.out and "deg/h" in captured.out
    assert "deriving model file schuler_loop.py" in captured.err
    assert len(captured.err.strip().splitlines()) == 1


def test_scenario_model_file_is_relative_to_the_scenario(tmp_path, capsys, monkeypatch):
    folder = tmp_path / "study"
    folder.mkdir()
    copy_model(folder, name="loop.py")
    scenario = folder / "bias.toml"
    scenario.write_text('title = "bias"\nmodel = "loop.py"\n'
                        '[motion]\nkind = "static"\nlatitude = "50 deg"\n'
                        '[run]\nduration = "1 h"\nstep = "10 s"\nmethod = "rk4"\n'
                        '[[case]]\naccel_bias = "100 ug"\n', encoding="utf-8")
    monkeypatch.chdir(tmp_path)  # not the scenario's folder
    assert main(["run", str(scenario), "--out", str(tmp_path / "report"), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["model"] == "schuler_loop"
    report = (tmp_path / "report" / "report.md").read_text(encoding="utf-8")
    assert "| model | `schuler_loop` |" in report and r"\psi" in report


# --------------------------------------------------------------------------------------
# staleness
# --------------------------------------------------------------------------------------
def _gravity(model) -> float:
    F = model.state_matrix(np.zeros(2), np.zeros(1))
    return float(np.max(np.linalg.eigvals(F).imag)) ** 2 * R


def test_edited_model_file_never_uses_stale_generated_code(tmp_path, capsys, monkeypatch):
    path = copy_model(tmp_path)
    assert main(["derive", str(path)]) == 0  # default: my_ins_generated/ next to the file
    beside = tmp_path / "my_ins_generated"
    assert (beside / "numpy_model.py").is_file()
    capsys.readouterr()
    model = load_model(str(path))
    assert model.folder == beside and abs(_gravity(model) - G) < 1e-9
    assert capsys.readouterr().err == ""  # up to date: used silently

    path.write_text(path.read_text(encoding="utf-8").replace("9.80665", "9.5"),
                    encoding="utf-8")
    with pytest.warns(RuntimeWarning) as caught:   # the API's notice: a warning
        model = load_model(str(path))
    said = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(said) == 1 and "my_ins_generated/ is stale" in said[0], said
    assert capsys.readouterr().err == ""
    assert model.folder != beside and abs(_gravity(model) - 9.5) < 1e-9
    assert "9.80665" in (beside / "__init__.py").read_text(encoding="utf-8")  # untouched

    # through the command line too (a new process: nothing loaded yet); the new default
    # gravity is what `models` reports, and the stale folder is named again
    from ins_errors import model_lookup
    from ins_errors.numeric.model import _file_model

    _file_model.cache_clear()
    monkeypatch.setattr(model_lookup, "_NOTICES_GIVEN", set())
    assert main(["models", str(path), "--json"]) == 0
    captured = capsys.readouterr()
    parameters = {p["name"]: p["default"] for p in json.loads(captured.out)["parameters"]}
    assert parameters["g"] == 9.5 and "stale" in captured.err

    assert main(["derive", str(path)]) == 0  # refresh: silent again
    capsys.readouterr()
    _file_model.cache_clear()
    assert load_model(str(path)).folder == beside
    assert capsys.readouterr().err == ""


def test_a_derived_model_file_is_loaded_without_importing_it(tmp_path, monkeypatch):
    """Once derived, a model file is named and loaded (as by a command or a worker
    process) by its hash alone: neither the file nor the modelling API (SymPy) is
    imported, and its build() does not run."""
    from ins_errors import model_lookup
    from ins_errors.numeric.model import _file_model

    path = copy_model(tmp_path)
    first = load_model(str(path))  # derived into the (private) cache
    _file_model.cache_clear()
    model_lookup._definition.cache_clear()
    monkeypatch.setitem(sys.modules, "ins_errors.model_files", None)  # importing it fails
    model = load_model(str(path))
    assert model.folder == first.folder and abs(_gravity(model) - G) < 1e-9


def test_a_key_refuses_a_model_file_edited_during_a_run(tmp_path):
    from ins_errors.errors import ModelDefinitionError

    path = copy_model(tmp_path)
    key = load_model(str(path)).key
    assert load_model(key).key == key
    path.write_text(path.read_text(encoding="utf-8") + "\n# edited\n", encoding="utf-8")
    with pytest.raises(ModelDefinitionError, match="changed while in use"):
        load_model(key)


# --------------------------------------------------------------------------------------
# mistakes in a model file: one line, exit status 2, nothing half-written
# --------------------------------------------------------------------------------------
MISTAKES = {
    "undefined symbol": (
        ("real_rhs = sp.Matrix([f, omega_c, omega_c - omega + drift])",
         "real_rhs = sp.Matrix([f, omega_c, omega_c - omega + sp.Symbol('eps', real=True)])"),
        ["schuler_loop", "real-work equation", "'psi'", "undefined symbol(s) eps",
         "checking the definition"]),
    "wrong shape": (
        ("ideal_rhs = sp.Matrix([a_N, omega])", "ideal_rhs = sp.Matrix([[a_N, omega]])"),
        ["schuler_loop", "ideal_rhs", "must be a column", "checking the definition"]),
    "state without equation": (
        ("real_rhs = sp.Matrix([f, omega_c, omega_c - omega + drift])",
         "real_rhs = sp.Matrix([f, omega_c])"),
        ["schuler_loop", "real_rhs", "no equation for 'psi'", "checking the definition"]),
    "error not switched off": (
        ("real_rhs = sp.Matrix([f, omega_c, omega_c - omega + drift])",
         "real_rhs = sp.Matrix([f + 1e-3, omega_c, omega_c - omega + drift])"),
        ["schuler_loop", "'delta_V'", "does not reduce to the ideal work"]),
    "SymPy failure in the variation": (
        # a function SymPy cannot differentiate (say, a table the author wraps)
        ("def outputs(", "from sympy.core.function import ArgumentIndexError\n\n\n"
                        "class table(sp.Function):\n"
                        "    @classmethod\n"
                        "    def eval(cls, x):\n"
                        "        return sp.S.One if x == 0 else None\n\n"
                        "    def fdiff(self, argindex=1):\n"
                        "        raise ArgumentIndexError(self, argindex)\n\n\n"
                        "def outputs("),
        ('f = real.let("f", a_N * sp.cos(psi)', 'f = real.let("f", a_N * table(psi)'),
        ["schuler_loop", "state matrix F", "derivative", "step: variation"]),
    "display unit of another dimension": (
        ('"m/s**2", "ug"', '"m/s**2", "deg/h"'),
        ["my_ins.py", "error source 'accel_bias'", "display unit 'deg/h' does not convert",
         "'m/s**2'", "checking the definition"]),
    "unit the units library cannot read": (
        ('Variable("V", "m/s",', 'Variable("V", "m/sec2",'),
        ["state 'V'", "unit 'm/sec2'", "checking the definition"]),
    # the suggestion was '0.03/s' whatever the unit: it now has the parameter's unit
    "parameter example without its unit": (
        ('"g", 9.80665)', '"g", 9.80665, example="9.8")'),
        ["parameter 'g'", "example '9.8' is not a value in 'm/s**2' with its unit",
         "(e.g. '9.8 m/s^2')", "checking the definition"]),
    "parameter example of another dimension": (
        ('"g", 9.80665)', '"g", 9.80665, example="9.8 m/s")'),
        ["parameter 'g'", "example '9.8 m/s' is not a value in 'm/s**2'",
         "(e.g. '9.8 m/s^2')", "checking the definition"]),
    "plain-number parameter example with a unit": (
        ('"g", 9.80665)', '"g", 9.80665),\n    Parameter("k_p", "1", "a gain", "k_p", 0.0, '
                          'example="0.5/s")'),
        ("R, g = (v.symbol for v in PARAMETERS)", "R, g = (v.symbol for v in PARAMETERS[:2])"),
        ["parameter 'k_p'", "example '0.5/s' is not a plain number (unit '1')",
         "(e.g. '0.5')", "checking the definition"]),
    "rate parameter example in another unit": (
        ('"g", 9.80665)', '"g", 9.80665),\n    Parameter("k_v", "1/s", "a gain", "k_v", 0.0, '
                          'example="1.24e-3 deg/h")'),
        ("R, g = (v.symbol for v in PARAMETERS)", "R, g = (v.symbol for v in PARAMETERS[:2])"),
        ["parameter 'k_v'", "example '1.24e-3 deg/h' is not a value in '1/s'",
         "(e.g. '1.24e-3/s')", "checking the definition"]),
    "what a missing example gives": (
        ('"g", 9.80665)', '"g", 9.80665, example_gives="standard gravity")'),
        ["parameter 'g'", "example_gives 'standard gravity' without an example value",
         "checking the definition"]),
    "non-finite parameter default": (
        ('"g", 9.80665)', '"g", float("nan"))'),
        ["parameter 'g'", "default nan is not a finite number", "checking the definition"]),
    "undefined function in an intermediate": (
        ('omega_c = real.let("omega", V_c / R,',
         'omega_c = real.let("omega", V_c / R * sp.Function("k")(psi),'),
        ["my_ins.py", "intermediate omega_c of the real mechanisation",
         "undefined function(s) k:", "checking the definition"]),
    "unknown kind of error source": (
        ('"constant", None, r"\\nabla"', '"const", None, r"\\nabla"'),
        ["error source 'accel_bias'", "kind 'const' is not one of 'constant', 'initial'",
         "did you mean 'constant'?", "checking the definition"]),
    "equation of the wrong unit": (  # dφ/dt = V: m/s for a latitude in rad
        ("ideal_rhs = sp.Matrix([a_N, omega])", "ideal_rhs = sp.Matrix([a_N, V])"),
        ("real_rhs = sp.Matrix([f, omega_c,", "real_rhs = sp.Matrix([f, V_c,"),
        ["ideal-work equation for 'phi'", "is in m/s but must be in 1/s",
         "the unit of phi, rad, per second", "checking the definition"]),
    "equation of the wrong unit in the real work alone": (  # told as the unit slip it is,
        # not as a residual of the reduction to the ideal work (a marine probe's dλ/dt)
        ("real_rhs = sp.Matrix([f, omega_c,", "real_rhs = sp.Matrix([f, V_c,"),
        ["real-work equation for 'delta_phi'", "is in m/s but must be in 1/s",
         "the unit of delta_phi, rad, per second", "checking the definition"]),
    "cosine of a length": (
        ('omega = ideal.let("omega", V / R,', 'omega = ideal.let("omega", V / R * sp.cos(R),'),
        ('omega_c = real.let("omega", V_c / R,',
         'omega_c = real.let("omega", V_c / R * sp.cos(R),'),
        ["intermediate omega of the ideal mechanisation", "cos of R, a quantity in m",
         "checking the definition"]),
    "exception while importing": (
        ("V, phi = (v.symbol for v in STATES)", "V, phi = (v.symbol for v in STATES[:1])"),
        ["my_ins.py", "line", "ValueError", "importing the file"]),
    "exception in build()": (
        ("    lat0, v0 = (v.symbol", "    lat0, v0 = 1 / 0, (v.symbol"),
        ["my_ins.py", "ZeroDivisionError", "building the definition"]),
    # sys.exit() in the file ended ins-errors with the file's status (0: a silent success)
    "sys.exit() in build()": (
        ("    lat0, v0 = (v.symbol", "    import sys\n    sys.exit(0)\n    lat0, v0 = (v.symbol"),
        ["my_ins.py", "line", "called sys.exit(0)", "building the definition"]),
    "sys.exit() while importing": (
        ("V, phi = (v.symbol for v in STATES)",
         "V, phi = (v.symbol for v in STATES)\nimport sys\nsys.exit(3)"),
        ["my_ins.py", "line", "called sys.exit(3)", "importing the file"]),
    # non-finite numbers were derived into generated code that read math.nan without
    # importing math (a NameError in every run), with a wrong second-order warning
    "complex infinity in an intermediate": (
        ('omega = ideal.let("omega", V / R,', 'omega = ideal.let("omega", V / R + sp.zoo,'),
        ["intermediate omega of the ideal mechanisation", "is not finite", "zoo",
         "checking the definition"]),
    "log(0) in an intermediate": (
        ('omega = ideal.let("omega", V / R,', 'omega = ideal.let("omega", V / R + sp.log(V - V),'),
        ["intermediate omega of the ideal mechanisation", "is not finite", "zoo",
         "checking the definition"]),
    "not a number in an equation": (
        ("real_rhs = sp.Matrix([f, omega_c, omega_c - omega + drift])",
         "real_rhs = sp.Matrix([f, omega_c, omega_c - omega + drift + 0 * sp.oo])"),
        ["real-work equation (real_rhs) for 'psi'", "is not finite", "nan",
         "checking the definition"]),
    "infinite derivative at zero error": (  # finite itself, its slope at ψ = 0 is not
        ('- g * sp.sin(psi) + bias', '- g * sp.sin(psi) + 1e-3 * g * sp.cbrt(psi) + bias'),
        ["state matrix F", "real-work equation for 'delta_V' by psi", "not finite",
         "zoo", "step: variation"]),
    # a wrong type of an argument of the authoring API was a TypeError traceback
    "a number for the list of states": (
        ("        states=STATES,", "        states=5,"),
        ["states: must be a list or tuple of Variable, got int 5", "checking the definition"]),
    "a string for the list of inputs": (
        ("        inputs=INPUTS,", '        inputs="a_N",'),
        ["inputs: must be a list or tuple of Variable, got str 'a_N'"]),
    "a symbol among the error sources": (
        ("        sources=SOURCES,", "        sources=(*SOURCES[:2], bias),"),
        ["sources[2]: must be an ErrorSource", "got Symbol accel_bias"]),
    "a number for the model's name": (
        ('name="schuler_loop",', "name=7,"),
        ["my_ins.py", "the model's name must be a str, got int 7"]),
}


@pytest.mark.parametrize("mistake", sorted(MISTAKES))
def test_model_file_mistake_is_one_line(mistake, tmp_path, capsys, private_cache):
    *replacements, words = MISTAKES[mistake]
    path = copy_model(tmp_path, *replacements)
    out = tmp_path / "out"
    assert main(["derive", str(path), "--out", str(out)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ins-errors: error: "), captured.err
    for word in words:
        assert word in lines[0], (word, lines[0])
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["my_ins.py"]
    # every other command says the same, and writes nothing into the cache
    assert main(["models", str(path)]) == 2
    assert capsys.readouterr().err.strip().splitlines()[-1] == lines[0]
    assert not private_cache.exists() or not any(private_cache.iterdir())


def test_literal_constants_are_not_refused_by_the_dimension_check(tmp_path, capsys,
                                                                   private_cache):
    """A file may write a constant as a number (g as 9.80665, R as 6371000.0): its unit
    is not written, so the dimension check gives no verdict on those terms instead of
    refusing a right model ("a sum of m/s**2 and 1"), while the wrong-unit equation
    stays refused (MISTAKES)."""
    path = copy_model(
        tmp_path,
        ('f = real.let("f", a_N * sp.cos(psi) - g * sp.sin(psi)',
         'f = real.let("f", a_N * sp.cos(psi) - 9.80665 * sp.sin(psi)'),
        ('omega = ideal.let("omega", V / R,', 'omega = ideal.let("omega", V / 6371000.0,'),
        ('omega_c = real.let("omega", V_c / R,', 'omega_c = real.let("omega", V_c / 6371000,'))
    assert main(["models", str(path)]) == 0, capsys.readouterr().err
    assert "accel_bias" in capsys.readouterr().out


def test_failed_derive_keeps_the_previous_package(tmp_path, capsys):
    path = copy_model(tmp_path)
    out = tmp_path / "pkg"
    assert main(["derive", str(path), "--out", str(out)]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    path.write_text(path.read_text(encoding="utf-8").replace(
        "ideal_rhs = sp.Matrix([a_N, omega])", "ideal_rhs = sp.Matrix([a_N])"), encoding="utf-8")
    assert main(["derive", str(path), "--out", str(out)]) == 2
    assert "no equation for 'phi'" in capsys.readouterr().err
    assert before == {p.name: p.read_bytes() for p in out.iterdir()}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["my_ins.py", "pkg"]


def test_derive_refuses_to_overwrite_a_foreign_folder(tmp_path, capsys):
    out = tmp_path / "notes"
    out.mkdir()
    (out / "mine.txt").write_text("keep", encoding="utf-8")
    assert main(["derive", str(SCHULER), "--out", str(out)]) == 2
    assert "not empty" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == ["mine.txt"]


def test_unknown_model_and_missing_file(capsys):
    assert main(["models", "schuler"]) == 2
    assert "(or a model file" in capsys.readouterr().err
    assert main(["models", "no_such_dir/my_ins.py"]) == 2
    assert "model file 'no_such_dir/my_ins.py' not found" in capsys.readouterr().err


def test_a_folder_is_named_a_folder_not_missing(tmp_path, capsys, monkeypatch):
    """A folder given as the model file was "not found"; it is there, and a folder."""
    (tmp_path / "my_ins").mkdir()
    monkeypatch.chdir(tmp_path)
    for spec in ("my_ins/", str(tmp_path / "my_ins")):
        assert main(["models", spec]) == 2
        err = capsys.readouterr().err.strip()
        assert f"model file {spec!r} is a folder, not a Python file" in err
        assert "not found" not in err and "\n" not in err
    assert main(["models", "my_ins"]) == 2  # a bare name: still no built-in model
    err = capsys.readouterr().err
    assert "unknown model 'my_ins'" in err and "'my_ins' is a folder" in err


def test_a_model_file_may_not_take_a_built_in_name(tmp_path, capsys):
    path = copy_model(tmp_path, ('name="schuler_loop"', 'name="orthodromic"'))
    assert main(["models", str(path)]) == 2
    assert "taken by a built-in model" in capsys.readouterr().err


# --------------------------------------------------------------------------------------
# entry points
# --------------------------------------------------------------------------------------
def test_installed_package_registers_a_model_by_entry_point(tmp_path, monkeypatch, capsys):
    site = tmp_path / "site"
    package = site / "loops_pkg"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("", encoding="utf-8")
    shutil.copy(SCHULER, package / "schuler.py")
    dist = site / "loops_pkg-1.0.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: loops-pkg\nVersion: 1.0\n",
                                   encoding="utf-8")
    (dist / "entry_points.txt").write_text(
        "[ins_errors.models]\nschuler_loop = loops_pkg.schuler\nloop = loops_pkg.schuler\n",
        encoding="utf-8")
    monkeypatch.syspath_prepend(str(site))
    model = load_model("schuler_loop")
    assert model.name == "schuler_loop" and abs(_gravity(model) - G) < 1e-9
    assert load_model(model.key).key == model.key  # what worker processes are handed
    # a registration under another name than the model's own is refused
    assert main(["models", "loop"]) == 2
    assert "under the model's own name" in capsys.readouterr().err
    assert main(["models"]) == 0  # the listing shows both, the bad one with its problem
    listing = capsys.readouterr().out
    assert re.search(r"^schuler_loop\s+Single-axis Schuler loop", listing, re.M)
    assert re.search(r"^loop\s+\(cannot be loaded: .*own name\)", listing, re.M)


def test_validity_of_a_model_file_shows_the_sine_residual(capsys):
    # direct keeps sin ψ, linear has ψ: the relative residual is ψ²/6-like, slope 2
    assert main(["validity", str(SCHULER), "--motion", "static", "--source", "accel_bias",
                 "--hours", "1", "--step", "30s", "--json", "--no-progress"]) == 0
    [row] = json.loads(capsys.readouterr().out)["sources"]
    assert row["source"] == "accel_bias" and abs(row["linear_slope"] - 2.0) < 0.01


def test_a_module_next_to_the_model_file_is_part_of_its_identity(tmp_path, capsys):
    (tmp_path / "loop_constants.py").write_text("GRAVITY = 9.80665\n", encoding="utf-8")
    path = copy_model(tmp_path, ('Parameter("g", "m/s**2", "gravity", "g", 9.80665)',
                                 'Parameter("g", "m/s**2", "gravity", "g", GRAVITY)'),
                      ("import sympy as sp\n",
                       "import sympy as sp\nfrom loop_constants import GRAVITY\n"))
    assert main(["derive", str(path)]) == 0
    capsys.readouterr()
    assert abs(_gravity(load_model(str(path))) - G) < 1e-9
    (tmp_path / "loop_constants.py").write_text("GRAVITY = 9.5\n", encoding="utf-8")
    with pytest.warns(RuntimeWarning, match="my_ins_generated/ is stale"):
        model = load_model(str(path))  # same process, model file itself unchanged
    assert abs(_gravity(model) - 9.5) < 1e-9


def test_the_cache_keeps_a_few_versions_of_an_edited_model(tmp_path, private_cache):
    from ins_errors.model_lookup import KEEP_VERSIONS

    path = copy_model(tmp_path)
    for k in range(KEEP_VERSIONS + 2):
        path.write_text(path.read_text(encoding="utf-8") + f"\n# edit {k}\n", encoding="utf-8")
        assert load_model(str(path)).name == "schuler_loop"
    versions = sorted(private_cache.glob("schuler_loop-*"))
    assert len(versions) == KEEP_VERSIONS
    assert load_model(str(path)).folder in versions  # the newest is among them


# --------------------------------------------------------------------------------------
# the matrix check: a model file is taken like a name, and says what it lacks
# --------------------------------------------------------------------------------------
def test_matrix_check_of_a_model_file_names_what_it_lacks(tmp_path, capsys, monkeypatch):
    from ins_errors.checker.matrix import check_matrices
    from ins_errors.errors import InsErrorsError, UnknownNameError

    monkeypatch.chdir(tmp_path)
    hand = tmp_path / "hand.py"
    hand.write_text("import numpy as np\nSTATES = ['delta_V', 'delta_phi', 'psi']\n"
                    "def f(nav, imu):\n    return np.zeros((3, 3))\n", encoding="utf-8")
    lines = []
    for flags in (["--matrix", f"{hand}:f"], ["--write-samples", "s.npz"]):
        assert main(["check", str(SCHULER), *flags]) == 2
        err = [line for line in capsys.readouterr().err.splitlines()
               if line.startswith("ins-errors: error:")]
        assert len(err) == 1, err
        lines.append(err[0])
    assert lines[0] == lines[1]
    for word in ("'schuler_loop'", "cannot be checked with --matrix", "navigation description",
                 "platform model", "north_pointing", "as an equation file",
                 "docs/matrix_check.md"):
        assert word in lines[0], (word, lines[0])
    # a platform model is not told the strapdown requirements (outputs roll, pitch, ...,
    # inputs omega_x, f_x, ...): they are beside the point for it
    for word in ("strapdown", "roll", "omega_x", "f_x"):
        assert word not in lines[0], (word, lines[0])
    assert not (tmp_path / "s.npz").exists()
    # the docs the message points at say so
    assert "## Which models" in (ROOT / "docs" / "matrix_check.md").read_text(encoding="utf-8")
    # from Python: the same line, not a failed lookup of the model's name
    with pytest.raises(InsErrorsError) as raised:
        check_matrices(str(SCHULER), f"{hand}:f", "model")
    assert not isinstance(raised.value, UnknownNameError)
    assert f"ins-errors: error: {raised.value}" == lines[0]
    # the conventions of a model file are listed like those of a built-in model
    assert main(["check", str(SCHULER), "--list-conventions"]) == 0
    assert "psi (rad): platform tilt about the west axis" in capsys.readouterr().out


def test_derive_warns_of_a_source_the_linear_model_does_not_see(tmp_path, capsys):
    # a bias squared (b²/g, a slip) has a zero column in G: d(b²)/db = 0 at b = 0
    path = copy_model(tmp_path, ("g * sp.sin(psi) + bias,", "g * sp.sin(psi) + bias**2 / g,"))
    assert main(["derive", str(path), "--out", str(tmp_path / "out")]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warnings) == 1, warnings
    for word in ("error source 'accel_bias'", "second order or higher", "does not see it"):
        assert word in warnings[0], (word, warnings[0])
    # a declared source that no equation uses
    path = copy_model(tmp_path, ("omega_c - omega + drift]", "omega_c - omega]"),
                      name="unused.py")
    assert main(["derive", str(path), "--out", str(tmp_path / "out2")]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warnings) == 1 and "'gyro_drift' is used in no equation" in warnings[0]
    # the tutorial model sees all its sources
    assert main(["derive", str(SCHULER), "--out", str(tmp_path / "out3")]) == 0
    assert "warning" not in capsys.readouterr().err


def test_built_in_models_pass_the_unit_and_dimension_checks():
    from ins_errors.model_lookup import builtin_names
    from ins_errors.models import definition
    from ins_errors.symbolic.consistency import check_dimensions, check_units

    for name in builtin_names():
        check_units(definition(name))
        check_dimensions(definition(name))


def test_validity_advice_when_the_linear_model_does_not_see_a_source(tmp_path, capsys):
    # with b²/g in the equation the linear error is exactly zero at any b: the ratio is 1
    # at every magnitude, and no scale of the magnitudes makes the linear model valid
    path = copy_model(tmp_path, ("g * sp.sin(psi) + bias,", "g * sp.sin(psi) + bias**2 / g,"))
    assert main(["compare", str(path), "--source", "accel_bias=100ug", "--hours", "1",
                 "--step", "60s", "--json"]) == 0
    [case] = json.loads(capsys.readouterr().out)["cases"]
    assert case["one_percent_scale"] is None
    assert len(case["warnings"]) == 1, case["warnings"]
    assert "does not see accel_bias" in case["warnings"][0]
    assert "× the magnitudes" not in case["warnings"][0]
    assert main(["validity", str(path), "--motion", "static", "--source", "accel_bias",
                 "--hours", "1", "--step", "60s", "--json", "--no-progress"]) == 0
    [row] = json.loads(capsys.readouterr().out)["sources"]
    assert row["status"] == "not seen by the linear model"
    assert row["magnitude_1pct"] is None and "zero columns in G" in row["note"]


def test_validity_of_a_static_only_model_maps_the_static_base(capsys):
    # no east velocity: the default motions drop the great circle, in one line
    assert main(["validity", str(SCHULER), "--source", "accel_bias", "--hours", "1",
                 "--step", "60s", "--json", "--no-progress"]) == 0
    captured = capsys.readouterr()
    assert [r["motion"] for r in json.loads(captured.out)["sources"]] == ["static"]
    [line] = [x for x in captured.err.splitlines() if "validity" in x]
    assert "mapping static only" in line and "great-circle" in line and "v_E" in line
    # asked for explicitly, the great circle is refused with the way out
    assert main(["validity", str(SCHULER), "--motion", "great-circle", "--hours", "1",
                 "--step", "60s", "--no-progress"]) == 2
    [line] = capsys.readouterr().err.strip().splitlines()
    assert "no east velocity" in line and line.endswith("--motion static")


POSITION_SPEC = """title = "position only"
sigma_level = 2
operating_time = "2 h"
step = "60 s"
[motion]
kind = "static"
latitude = "50 deg"
[items.position_error]
value = "3.7 km/h"
times = ["1 h", "2 h"]
"""
# (no longitude or height: the Schuler loop has neither, and a value given for one is
# refused as one it would ignore)


def test_budget_names_everything_a_model_file_lacks_in_one_line(tmp_path, capsys):
    spec = tmp_path / "position.toml"
    spec.write_text(POSITION_SPEC, encoding="utf-8")
    # no longitude output and no Earth radius: both named in the one line
    path = copy_model(tmp_path, ('Parameter("R", "m",', 'Parameter("R_s", "m",'))
    assert main(["budget", str(path), "--spec", str(spec)]) == 2
    [line] = [x for x in capsys.readouterr().err.splitlines() if "error:" in x]
    assert "position_error (it has no output longitude and no Earth radius parameter" in line
    # with a longitude output the position item runs: the Earth rate U is not needed
    path = copy_model(tmp_path, ('    Variable("v_N", "m/s", "north velocity", "v_N"),\n)',
                                 '    Variable("v_N", "m/s", "north velocity", "v_N"),\n'
                                 '    Variable("longitude", "rad", "longitude", "L"),\n)'),
                      ("sp.Matrix([latitude, velocity])", "sp.Matrix([latitude, velocity, 0])"),
                      name="with_longitude.py")
    assert main(["budget", str(path), "--spec", str(spec), "--json"]) == 0
    capsys.readouterr()
    assert "U" not in {p.name for p in load_model(str(path)).parameters}
    # the default spec: every item listed with what is missing, in one line
    assert main(["budget", str(SCHULER)]) == 2
    [line] = [x for x in capsys.readouterr().err.splitlines() if "error:" in x]
    for word in ("position_error", "ground_speed_error", "vertical_error", "heading_drift",
                 "no output longitude", "no output v_E", "no platform error angles"):
        assert word in line, (word, line)


def test_compare_without_a_source_names_one_of_the_models_own(capsys):
    assert main(["compare", str(SCHULER), "--hours", "1", "--step", "60s"]) == 2
    [line] = [x for x in capsys.readouterr().err.splitlines() if "error:" in x]
    assert line.endswith("e.g. --source gyro_drift=0.01deg/h"), line


def test_a_pole_is_refused_for_what_is_undefined_there(capsys):
    # the Schuler loop divides by nothing, but north and longitude are undefined at a pole
    assert main(["compare", str(SCHULER), "--source", "accel_bias=100ug", "--latitude",
                 "90deg", "--hours", "1", "--step", "60s"]) == 2
    [line] = [x for x in capsys.readouterr().err.splitlines() if "error:" in x]
    assert "pole, where north, east and longitude are undefined" in line


def test_a_heading_is_refused_where_it_changes_nothing(capsys):
    # no heading output: at rest the model runs in the geographic frame, heading unused
    assert main(["compare", str(SCHULER), "--source", "accel_bias=100ug", "--heading",
                 "45deg", "--hours", "1", "--step", "60s"]) == 2
    [line] = [x for x in capsys.readouterr().err.splitlines() if "error:" in x]
    assert "--heading: model 'schuler_loop' has no heading output" in line


# --------------------------------------------------------------------------------------
# damping gains flagged in the modelling API
# --------------------------------------------------------------------------------------
VERTICAL = '''"""A barometer-aided vertical channel: the height loop of an INS, alone."""

import sympy as sp

from ins_errors.modeling import (Mechanisation, ModelDefinition, Parameter, Variable,
                                 computed_symbols, error_source, error_states_of)

STATES = (Variable("h", "m", "height", "h"), Variable("v", "m/s", "up velocity", "v"))
INPUTS = (Variable("a_zeta", "m/s**2", "true up specific force", "f"),)
{parameters}
SOURCES = (
    error_source("accel_bias", "m/s**2", "ug", "constant", None, "b", "up accelerometer bias"),
    error_source("initial_height_error", "m", "m", "initial", None, "e", "height error at 0"))
OUTPUTS = (Variable("height", "m", "height", "h"), Variable("v_U", "m/s", "up velocity", "v"))
INITIAL_CONDITIONS = (Variable("height", "m", "initial height", "h_0"),
                      Variable("v_U", "m/s", "initial up velocity", "v_0"))
h, v = (s.symbol for s in STATES)
h_c, v_c = computed_symbols(STATES)
f, (R, g, c_1, c_2), (b, e) = INPUTS[0].symbol, (s.symbol for s in PARAMETERS), (
    s.symbol for s in SOURCES)


def build():
    h0, v0 = (s.symbol for s in INITIAL_CONDITIONS)
    return ModelDefinition(
        name="baro_vertical", title="Baro-aided vertical channel", source="tests",
        states=STATES, error_states=error_states_of(STATES, ()), real_states=[h_c, v_c],
        inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES, outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS, ideal=Mechanisation(),
        real=Mechanisation(computed=True),
        ideal_rhs=sp.Matrix([v, f - g * (1 - 2 * h / R)]),
        # the barometer reads the true height h
        real_rhs=sp.Matrix([v_c - c_1 * (h_c - h),
                            f + b - g * (1 - 2 * h_c / R) - c_2 * (h_c - h)]),
        output_map=lambda eq, state, inputs: sp.Matrix(list(state)),
        initial_state=sp.Matrix([h0, v0]), initial_real_state=sp.Matrix([h0 + e, v0]))
'''


def _docs_damping_snippet() -> str:
    """The model-file snippet of docs/models.md's section on damping gains."""
    page = (ROOT / "docs" / "models.md").read_text(encoding="utf-8")
    section = page.split("\n## Damping gains of any model", 1)[1].split("\n## ", 1)[0]
    return section.split("```python\n", 1)[1].split("```", 1)[0]


def _growth_warning(capsys, path: Path, *options: str, hours: str = "2") -> str | None:
    """The growth warning of a compare at rest (2 h, 10-s steps), or None."""
    assert main(["compare", str(path), "--source", "accel_bias=10ug", "--hours", hours,
                 "--step", "10s", "--no-refined", "--no-progress", *options]) == 0
    found = [x for x in capsys.readouterr().out.splitlines() if "grow exponentially" in x]
    return found[0] if found else None


def test_a_flagged_damping_gain_of_a_model_file_is_named_with_its_own_example(
        tmp_path, capsys):
    """The warning's remedy came from the word "damping" in a description and gave
    values only for strapdown_ned's k_h1, k_h2. The docs' gains c_1, c_2 (no "damping" in
    their descriptions) are flagged: the warning names them with their own examples, and
    those examples damp the channel. Reference: the undamped channel δh'' = (2g/R) δh
    grows ×e every √(R/2g); with c_1, c_2 its modes are s² + c_1 s + c_2 − 2g/R = 0."""
    snippet = _docs_damping_snippet()
    assert "damping" not in re.sub(r"damping_gain=True", "", snippet)
    path = tmp_path / "baro_vertical.py"
    path.write_text(VERTICAL.format(parameters=snippet), encoding="utf-8")
    warning = _growth_warning(capsys, path)
    minutes = float(re.search(r"×e every ([\d.]+) min", warning).group(1))
    assert minutes == pytest.approx(math.sqrt(R / (2 * G)) / 60.0, rel=1e-3)
    assert warning.endswith("; the damping gains c_1, c_2 are 0 (undamped): set them, e.g. "
                            "`-p c_1=0.03/s -p c_2=4.4e-4/s^2` (a 300-s loop)"), warning
    gains = re.search(r"`(-p c_1=\S+ -p c_2=\S+)`", warning).group(1).split()
    c_1, c_2 = 0.03, 4.4e-4  # the example's loop: period 2π/√(c_2 − 2g/R) ≈ 300 s
    assert 2 * math.pi / math.sqrt(c_2 - 2 * G / R) == pytest.approx(300.0, abs=1.0)
    assert c_1 / (2 * math.sqrt(c_2 - 2 * G / R)) == pytest.approx(0.7, abs=0.03)
    assert _growth_warning(capsys, path, *gains) is None
    # c_1 alone leaves a slow growing root s = (−c_1 + √(c_1² + 8g/R))/2 (×e every
    # 2.7 h): over 12 h the warning names only the gain still at 0
    warning = _growth_warning(capsys, path, "-p", "c_1=0.03/s", hours="12")
    rate = (-c_1 + math.sqrt(c_1**2 + 8 * G / R)) / 2
    assert float(re.search(r"×e every ([\d.]+) h", warning).group(1)) == pytest.approx(
        1 / rate / 3600, rel=1e-3)
    assert warning.endswith("; the damping gain c_2 is 0 (undamped): set it, e.g. "
                            "`-p c_2=4.4e-4/s^2` (a 300-s loop)"), warning
    # flagged without an example: named, no value made up
    bare = tmp_path / "bare" / "baro_vertical.py"
    bare.parent.mkdir()
    bare.write_text(VERTICAL.format(parameters=snippet.replace(
        ', example="4.4e-4/s^2", example_gives="a 300-s loop"', "")), encoding="utf-8")
    assert _growth_warning(capsys, bare).endswith(
        "; the damping gains c_1, c_2 are 0 (undamped): set them (`-p c_1=… -p c_2=…`)")


def test_a_gain_without_the_flag_is_never_named_whatever_its_description(tmp_path, capsys):
    """Unflagged, even a description that says "damping" (the old criterion) and the
    strapdown_ned name k_h1 get no remedy: only the flag marks a damping gain."""
    snippet = (_docs_damping_snippet().replace("damping_gain=True, ", "")
               .replace("baro loop:", "damping loop:").replace('"c_1", "1/s"', '"k_h1", "1/s"'))
    path = tmp_path / "baro_vertical.py"
    path.write_text(VERTICAL.format(parameters=snippet), encoding="utf-8")
    warning = _growth_warning(capsys, path)
    # no remedy; the command names the file as a command takes it (not 'baro_vertical')
    named = re.search(r"`ins-errors modes ([^`]+)` names the mode$", warning)
    assert named and Path(named[1]).resolve() == path.resolve(), warning
