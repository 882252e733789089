"""docs/generated.md stays true for everyone who calls generated/<model>/ directly.

* Its Python blocks run as docs/api.md's do (tests/page_blocks.py: one namespace, shape
  and print comments checked), in a scratch folder where the page's ``ins-errors``
  command has written the file they read.
* Its table of functions is every built-in model's ``FUNCTIONS``: each function's
  arguments in that order (the numpy signature and the CasADi input names), the numpy
  result's shape in the page's lengths, and the CasADi output ``out``.
* The generated folder imports with numpy and casadi alone (a copy, ins-errors, SymPy
  and SciPy made unimportable), and the ``Model``'s methods take the generated order
  except ``second_order``, as the page's warning says.
"""

from __future__ import annotations

import inspect
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ins_errors import available_models, load_model
from ins_errors.cli import main
from tests.page_blocks import printed_claims, python_blocks, run_blocks, shape_claims
from tests.test_docs_commands import BLOCK, _lines

ROOT = Path(__file__).resolve().parent.parent
PAGE_PATH = ROOT / "docs" / "generated.md"
PAGE = PAGE_PATH.read_text(encoding="utf-8")
BUILT_IN = ("orthodromic", "north_pointing", "free_azimuth", "geodetic_vertical",
            "strapdown_ned")


def test_the_blocks_run_and_state_true_shapes(monkeypatch, tmp_path):
    blocks = python_blocks(PAGE)
    assert len(blocks) >= 5
    assert sum(len(shape_claims(b)) for b in blocks) >= 20
    assert sum(len(printed_claims(b)) for b in blocks) >= 8
    monkeypatch.chdir(tmp_path)
    commands = [command for block in BLOCK.findall(PAGE) for command, _ in _lines(block)]
    assert commands and all(c.startswith("ins-errors ") for c in commands), commands
    for command in commands:  # (tests/test_docs_commands.py runs them on their own too)
        assert main(shlex.split(command)[1:]) == 0, command
    run_blocks(blocks, "docs/generated.md")


def _function_table() -> dict[str, tuple[list[str], str]]:
    """function -> (arguments in order, numpy result shape text) from the page's table."""
    section = PAGE.split("\n## The functions", 1)[1].split("\n## ", 1)[0]
    rows = re.findall(r"^\| `(\w+)` \| `([^`]*)` \| (\([^|]*\)) \|", section, re.M)
    return {name: ([a.strip() for a in args.split(",")], shape) for name, args, shape in rows}


def _lengths(model) -> dict[str, int]:
    meta = model.meta
    return {"n_x": len(meta.STATES), "n_e": len(meta.ERROR_STATES), "n_u": len(meta.INPUTS),
            "n_p": len(meta.PARAMETERS), "n_w": len(meta.SOURCES), "n_y": len(meta.OUTPUTS),
            "n_c": len(meta.INITIAL_CONDITIONS), "len(DOMAIN)": len(meta.DOMAIN),
            "len(INITIAL_DOMAIN)": len(meta.INITIAL_DOMAIN)}


def _shape(text: str, lengths: dict[str, int]) -> tuple[int, ...]:
    """The page's ``(n_e, n_w)`` or ``(max(1, len(DOMAIN)),)`` in a model's lengths."""
    for name, value in sorted(lengths.items(), key=lambda item: -len(item[0])):
        text = text.replace(name, str(value))
    return tuple(eval(text, {"max": max}))


def test_the_built_in_models_are_the_ones_the_page_knows():
    assert set(BUILT_IN) <= set(available_models())


@pytest.mark.parametrize("name", BUILT_IN)
def test_the_function_table_is_each_models_functions(name):
    model = load_model(name)
    table = _function_table()
    lengths = _lengths(model)
    assert set(model.numpy.FUNCTIONS) <= set(table)
    small = {"real_rhs_small_angle", "second_order_small_angle"}
    assert (small <= set(model.numpy.FUNCTIONS)) == (name != "strapdown_ned")
    assert not small & set(model.numpy.FUNCTIONS) or name != "strapdown_ned"
    assert model.casadi.FUNCTIONS == model.numpy.FUNCTIONS
    sizes = {"x": "n_x", "xr": "n_e", "xe": "n_e", "u": "n_u", "p": "n_p", "w": "n_w",
             "c": "n_c"}
    for function in model.numpy.FUNCTIONS:
        arguments, shape = table[function]
        numpy_function = getattr(model.numpy, function)
        assert list(inspect.signature(numpy_function).parameters) == arguments, function
        f = model.casadi.function(function)
        assert f.name_in() == arguments and f.name_out() == ["out"], function
        values = [np.full(lengths[sizes[a]], 0.1) for a in arguments]
        # a physical point where the formulas hold: the model's own start at 45°
        point = _point(model)
        values = [point.get(a, v) for a, v in zip(arguments, values, strict=True)]
        result = numpy_function(*values)
        assert result.shape == _shape(shape, lengths), function
        casadi_result = np.array(f(*values))
        expected = result.shape if result.ndim == 2 else (result.shape[0], 1)
        assert casadi_result.shape == expected, function
        assert np.allclose(casadi_result.reshape(result.shape), result, rtol=1e-9,
                           atol=1e-12), function
        with pytest.raises(ValueError, match=rf"{function}: argument {arguments[0]} must "
                                             r"have shape"):
            numpy_function(values[0][:-1], *values[1:])


def _point(model) -> dict[str, np.ndarray]:
    """x, xr, c, u, p, w at the model's start at 45° N, at rest (SI)."""
    p = model.parameter_vector()
    c = model.initial_condition_vector(latitude=np.radians(45.0))
    u = model.input_vector()
    x = model.initial_state(c, u, p)
    w = np.full(len(model.sources), 1e-6)
    return {"x": x, "xr": model.initial_real_state(c, u, w, p), "c": c, "u": u, "p": p,
            "w": w, "xe": np.full(len(model.error_states), 1e-4)}


@pytest.mark.parametrize("name", BUILT_IN)
def test_xr_is_the_computed_states_in_the_order_of_x_then_the_extra_error_states(name):
    """Without error sources the real work starts where the ideal work does: xr(0) is
    x(0), then zeros for the extra error states (the platform angles alpha_*; none for
    strapdown_ned), as the page's table of the vectors says."""
    model = load_model(name)
    point = _point(model)
    xr = model.numpy.initial_real_state(point["c"], point["u"], np.zeros(len(model.sources)),
                                        point["p"])
    n_x = len(model.states)
    assert np.array_equal(xr[:n_x], point["x"])
    assert xr.shape == (len(model.error_states),) and not xr[n_x:].any()
    extra = [s.name for s in model.error_states[n_x:]]
    assert (name == "strapdown_ned") == (not extra)
    assert all(e.startswith("alpha_") for e in extra), extra


@pytest.mark.parametrize("name", BUILT_IN)
def test_the_model_methods_take_the_generated_order_except_second_order(name):
    model = load_model(name)
    wrapped = {"ideal_rhs": "ideal_rhs", "real_rhs": "real_rhs", "outputs_of": "outputs",
               "state_matrix": "state_matrix", "source_matrix": "source_matrix",
               "output_matrix": "output_matrix", "initial_state": "initial_state",
               "initial_real_state": "initial_real_state",
               "initial_error_matrix": "initial_error_matrix"}
    for method, function in wrapped.items():
        ours = list(inspect.signature(getattr(model, method)).parameters)
        theirs = list(inspect.signature(getattr(model.numpy, function)).parameters)
        assert ours == theirs and theirs[-1] == "p", method
        assert inspect.signature(getattr(model, method)).parameters["p"].default is None
    for function in model.numpy.FUNCTIONS:  # p last, but in the second-order terms
        arguments = list(inspect.signature(getattr(model.numpy, function)).parameters)
        if function.startswith("second_order"):
            assert arguments == ["x", "u", "p", "xe", "w"], function
        else:
            assert arguments[-1] == "p", function
    assert list(inspect.signature(model.second_order).parameters) == ["x", "u", "xe", "w", "p"]
    assert list(inspect.signature(model.numpy.second_order).parameters) == [
        "x", "u", "p", "xe", "w"]


def test_a_call_in_the_models_order_is_refused_when_the_lengths_differ():
    model = load_model("strapdown_ned")
    point = _point(model)
    assert (len(model.parameters), len(model.error_states)) == (8, 10)
    with pytest.raises(ValueError, match="second_order: argument p must have shape"):
        model.numpy.second_order(point["x"], point["u"], point["xe"], point["w"],
                                 point["p"])


@pytest.mark.parametrize("name", ["strapdown_ned", "orthodromic"])
def test_the_generated_folder_imports_with_numpy_and_casadi_alone(name, tmp_path):
    """A copy of generated/<model>/ beside a script that makes ins_errors, SymPy and
    SciPy unimportable: both modules import and evaluate F, and nothing outside the
    standard library but numpy and casadi was imported."""
    shutil.copytree(ROOT / "generated" / name, tmp_path / name,
                    ignore=shutil.ignore_patterns("__pycache__"))
    model = load_model(name)
    point = _point(model)
    np.savez(tmp_path / "point.npz", x=point["x"], u=point["u"], p=point["p"])
    F = model.numpy.state_matrix(point["x"], point["u"], point["p"])
    np.save(tmp_path / "F.npy", F)
    script = f"""
import sys
sys.path.insert(0, ".")  # beside the copy (-I leaves the folder out)
class Refuse:
    def find_spec(self, fullname, path=None, target=None):
        if fullname.split(".")[0] in ("ins_errors", "sympy", "scipy"):
            raise ImportError("not available: " + fullname)
sys.meta_path.insert(0, Refuse())
import numpy as np
import {name} as meta
from {name} import casadi_model, numpy_model
d = np.load("point.npz")
F = numpy_model.state_matrix(d["x"], d["u"], d["p"])
Fc = np.array(casadi_model.function("state_matrix")(d["x"], d["u"], d["p"]))
assert np.array_equal(F, np.load("F.npy")), "numpy"
assert np.allclose(Fc, F, rtol=1e-9, atol=1e-15), "casadi"
assert meta.NAME == {name!r}
third = sorted({{m.split(".")[0] for m in sys.modules}} - set(sys.stdlib_module_names)
               - {{"{name}"}})
# (swig_runtime_data*: the table SWIG's runtime keeps in sys.modules for casadi)
print(" ".join(m for m in third if not m.startswith(("_", "swig_runtime_data"))))
"""
    run = subprocess.run([sys.executable, "-I", "-c", script], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert set(run.stdout.split()) == {"numpy", "casadi"}, run.stdout


def test_a_built_in_models_modules_are_those_of_ins_errors_generated():
    import importlib

    model = load_model("strapdown_ned")
    assert model.numpy is importlib.import_module("ins_errors.generated.strapdown_ned."
                                                  "numpy_model")
    assert model.casadi is importlib.import_module("ins_errors.generated.strapdown_ned."
                                                   "casadi_model")


def test_a_model_files_package_is_in_its_folder():
    model = load_model(str(ROOT / "examples" / "own_model" / "schuler_loop.py"))
    assert model.folder is not None
    assert Path(model.numpy.__file__).parent == model.folder
    assert model.numpy.FUNCTIONS == model.casadi.FUNCTIONS


def test_the_files_g_drops_only_zero_columns_of_initial_errors(monkeypatch, tmp_path):
    """The page: the file's G has the sources that drive the errors (24 for
    strapdown_ned), error_matrices every source (33), the initial errors' columns 0."""
    from ins_errors.conventions import error_matrices

    monkeypatch.chdir(tmp_path)
    assert main(["matrices", "strapdown_ned", "--motion", "static", "--hours", "1",
                 "--step", "600s", "--out", "fg.npz"]) == 0
    data = np.load("fg.npz")
    model = load_model("strapdown_ned")
    em = error_matrices(model, "phi", data["x_static"].T, data["u_static"].T,
                        data["parameters"])
    kept = [str(s) for s in data["sources"]]
    assert (len(kept), len(em.sources)) == (24, 33)
    initial = [j for j, s in enumerate(em.sources) if model.source(s).kind == "initial"]
    assert len(initial) == 33 - 24 and not em.G[:, :, initial].any()
    assert np.array_equal(data["G_static"], em.G[:, :, [em.sources.index(s) for s in kept]])
