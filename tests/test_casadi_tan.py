"""The generated CasADi functions write tan x as sin x / cos x (a compiled loop then
computes a latitude's sine and cosine in one call and its tangent in a division, about
a sixth of a strapdown INS's RK4 step); the numpy functions keep numpy's tan. Both are
the same functions to rounding, for every model, at every latitude short of the pole."""

from __future__ import annotations

import inspect

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.models import model_names


@pytest.mark.parametrize("name", model_names())
def test_casadi_and_numpy_functions_agree_to_rounding(name):
    model = load_model(name)
    rng = np.random.default_rng(7)
    checked = 0
    for function_name in model.casadi.FUNCTIONS:
        numpy_function = getattr(model.numpy, function_name)
        casadi_function = model.casadi.function(function_name)
        sizes = [casadi_function.size1_in(k) for k in range(casadi_function.n_in())]
        assert len(inspect.signature(numpy_function).parameters) == len(sizes)
        for _ in range(3):
            # latitudes up to 1.4 rad (80°, tan 5.8); a value outside a function's domain
            # (a square root of a negative) is NaN in both
            args = [rng.uniform(-1.4, 1.4, size) for size in sizes]
            with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
                expected = np.asarray(numpy_function(*args), dtype=float)
            got = np.asarray(casadi_function(*args), dtype=float)
            got = got.reshape(expected.shape, order="F") if got.size == expected.size else got
            finite = np.isfinite(expected)
            assert np.array_equal(finite, np.isfinite(got)), function_name
            scale = np.abs(expected[finite]).max(initial=1.0)
            np.testing.assert_allclose(got[finite], expected[finite], rtol=1e-12,
                                       atol=1e-13 * scale, err_msg=function_name)
            checked += 1
    assert checked


def test_casadi_modules_call_tan_as_sine_over_cosine():
    """The generated text: no CasADi tan is called, the module's _tan is, and it is
    sin/cos (numpy's tan stays where numpy evaluates)."""
    import casadi as ca

    model = load_model("strapdown_ned")
    source = inspect.getsource(model.casadi)
    assert "_m.tan(" not in source and "_tan(" in source
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [model.casadi._tan(x)])
    for value in (0.3, 1.2, -1.5):
        assert float(f(value)) == pytest.approx(np.tan(value), rel=4e-16)
    assert "_m.tan(" in inspect.getsource(model.numpy)
