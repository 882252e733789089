"""The docstrings of the generated real-work functions say what the model has.

``real_rhs``'s ``xr`` was "computed state, then platform angles" for every model, the
strapdown INS (which has none) included, and its summary said it "needs the true state
for the platform". Now ``xr`` names the model's extra error states (or says there are
none), and the summary says whether ``x`` is used: checked here against the committed
generated/ (its files read as they are, not through the installed package) and by
evaluating the function with and without a meaningful ``x``.
"""

from __future__ import annotations

import ast
import importlib.util
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from ins_errors import load_model

ROOT = Path(__file__).resolve().parent.parent
BUILT_IN = ("orthodromic", "north_pointing", "free_azimuth", "geodetic_vertical",
            "strapdown_ned")


def _docstrings(name: str) -> dict[str, str]:
    """Function name -> docstring of generated/<name>/numpy_model.py in this tree."""
    tree = ast.parse((ROOT / "generated" / name / "numpy_model.py").read_text("utf-8"))
    return {node.name: ast.get_docstring(node) for node in tree.body
            if isinstance(node, ast.FunctionDef)}


def _module(name: str):
    """generated/<name>/numpy_model.py of this tree, loaded from its file."""
    path = ROOT / "generated" / name / "numpy_model.py"
    spec = importlib.util.spec_from_file_location(f"_docstring_check_{name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _xr_line(docstring: str) -> str:
    lines = docstring.splitlines()
    return lines[lines.index(next(line for line in lines if line.startswith("xr :"))) + 1]


@pytest.mark.parametrize("name", BUILT_IN)
def test_xr_names_the_extra_error_states_the_model_has(name):
    model = load_model(name)
    n_x = len(model.states)
    extra = [s.name for s in model.error_states[n_x:]]
    docs = _docstrings(name)
    for function in ("real_rhs", "real_rhs_small_angle"):
        if function not in docs:
            continue
        line = _xr_line(docs[function])
        assert f"the {n_x} computed states in the order of x" in line, line
        if extra:
            assert f"then the platform angles {', '.join(extra)} (rad)" in line, line
        else:
            assert "platform" not in line and line.endswith("no further state"), line


@pytest.mark.parametrize("name", BUILT_IN)
def test_the_summary_says_whether_x_is_used_and_it_is_so(name):
    """A strapdown INS's real work does not read the true state: real_rhs is the same
    with x all NaN. A platform's real work does: another x changes the rate."""
    model = load_model(name)
    summary = _docstrings(name)["real_rhs"].splitlines()[0]
    module = _module(name)
    p = model.parameter_vector()
    c = model.initial_condition_vector(latitude=np.radians(45.0))
    u = model.input_vector()
    x = model.initial_state(c, u, p)
    w = np.full(len(model.sources), 1e-5)
    xr = model.initial_real_state(c, u, w, p)
    rate = module.real_rhs(xr, x, u, w, p)
    other = module.real_rhs(xr, np.full_like(x, np.nan), u, w, p)
    if name == "strapdown_ned":
        assert summary.endswith("(x is not used: the signature all models share)."), summary
        assert np.array_equal(other, rate)
    else:
        assert summary.endswith("(needs the true state x for the platform)."), summary
        assert np.isnan(other).any()


def test_extra_states_that_are_no_platform_angles_are_named_with_their_units():
    """A damping loop's integrator (m/s²) beside a platform angle: the states by name and
    unit (a description of any model definition, no derivation needed)."""
    from derive.model_files import real_state_description

    alpha = SimpleNamespace(name="alpha_z", unit="rad")
    integrator = SimpleNamespace(name="int_v", unit="m/s**2")
    mixed = SimpleNamespace(states=[1, 2, 3], extra_error_states=(alpha, integrator),
                            platform_angles=(alpha,))
    assert real_state_description(mixed) == (
        "real-work state: the 3 computed states in the order of x, then the states zero "
        "in ideal work: alpha_z (rad), int_v (m/s**2)")
    none = SimpleNamespace(states=[1, 2], extra_error_states=(), platform_angles=())
    assert real_state_description(none) == ("real-work state: the 2 computed states in "
                                            "the order of x, no further state")
