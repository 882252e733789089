"""Quantities a source moves only at second order on a motion.

On a static base at the equator the Earth rate lies along north, and a level gyro bias
about east (``gyro_bias_y`` of strapdown_ned at heading 0) drives the north channel
only: the Coriolis term (2Ω × δv)_D = 2U·δv_E there, so the east and vertical channels
get nothing at first order and the linear model gives them exactly 0. The direct run
moves them at second order (their peaks scale with the square of the magnitude).
Their linear/direct ratio is then 100 % at any magnitude: it was judged as the case's
worst ratio and a validity warning named a magnitude "at which it would be 1 %" (a
marine INS at the equator got "1 % at 23.4× the magnitudes ... 100.00 % at 136×").
"""

from __future__ import annotations

import math

import pytest

from ins_errors import load_model
from ins_errors.numeric import compare as cmp
from ins_errors.numeric import trajectories as tr

BIAS = 1.0 * math.pi / 180 / 3600   # 1 deg/h


@pytest.fixture(scope="module")
def equator():
    model = load_model("strapdown_ned")
    trajectory = tr.trajectory(model, tr.static_profile(0.0, 0.5), 3600.0, 10.0)
    return model, trajectory


def _case(equator, size: float):
    model, trajectory = equator
    return cmp.compare(model, trajectory, [{"gyro_bias_y": size}], record_interval=300.0,
                       integration_error=False, refined=False)[0]


def test_a_quantity_moved_only_at_second_order_is_named_and_not_judged(equator):
    case = _case(equator, BIAS)
    v_E, v_N = case.metric("delta_v_E"), case.metric("delta_v_N")
    assert not case.linear["delta_v_E"].any() and v_E.max_direct > 0
    assert v_E.second_order_only and not v_E.excited and v_E.linear_ratio == 1.0
    assert v_N.excited and not v_N.second_order_only
    # the worst ratio is a first-order quantity's, and no validity warning is given
    assert case.worst_linear.quantity != "delta_v_E" and case.worst_linear.linear_ratio < 0.05
    assert not any("validity" in w for w in case.warnings), case.warnings
    (note,) = [w for w in case.warnings if "second order" in w]
    assert "delta_v_E" in note and "delta_v_N" not in note
    assert "| `delta_v_E` |" in cmp.markdown_table(case)
    assert "2nd order |" in cmp.markdown_table(case)


def test_the_direct_error_of_such_a_quantity_is_quadratic_in_the_magnitude(equator):
    """The independent evidence that it is a second-order effect: halving the bias
    quarters the east velocity error and halves the north one."""
    full, half = _case(equator, BIAS), _case(equator, BIAS / 2)
    assert half.metric("delta_v_E").max_direct / full.metric("delta_v_E").max_direct == (
        pytest.approx(0.25, rel=0.02))
    assert half.metric("delta_v_N").max_direct / full.metric("delta_v_N").max_direct == (
        pytest.approx(0.5, rel=0.02))


def test_a_source_the_linear_model_does_not_see_at_all_is_still_said_so(equator):
    """Where nothing moves linearly the quantities are not marked second order: that
    case has its own warning (no equation uses the source)."""
    model, trajectory = equator
    direct = cmp.compare(model, trajectory, [{"gyro_bias_y": BIAS}], record_interval=300.0,
                         integration_error=False, refined=False, validity_threshold=None)[0]
    assert any(m.second_order_only for m in direct.metrics)
    nothing = cmp.metrics_of(*_curves(direct))
    assert not any(m.second_order_only for m in nothing)


def _curves(case):
    """Error curves of a case with its linear curves all zero."""
    import numpy as np

    from ins_errors.numeric.simulate import ErrorCurves

    names = [m.quantity for m in case.metrics]
    units = [m.unit for m in case.metrics]
    direct = np.stack([case.direct[n] for n in names])[:, :, None]
    return (ErrorCurves(names, units, case.times, direct),
            ErrorCurves(names, units, case.times, np.zeros_like(direct)), None)


def test_the_python_api_issues_the_notes_as_warnings(equator):
    """A notebook user never saw a case's notes unless they printed ``.warnings``: they
    are now also Python warnings (InsErrorsWarning, the case's label first); warn=False,
    as the command line passes, keeps them in ``.warnings`` alone."""
    import warnings

    from ins_errors.errors import InsErrorsWarning

    model, trajectory = equator
    with pytest.warns(InsErrorsWarning, match=r"gyro_bias_y = .*: .*second order") as seen:
        (case,) = cmp.compare(model, trajectory, [{"gyro_bias_y": BIAS}],
                              record_interval=300.0, integration_error=False, refined=False)
    assert [str(w.message) for w in seen if w.category is InsErrorsWarning] == [
        f"{case.label}: {text}" for text in case.warnings]
    assert seen[0].filename == __file__   # pointed at the caller's line
    with warnings.catch_warnings():
        warnings.simplefilter("error", InsErrorsWarning)
        (quiet,) = cmp.compare(model, trajectory, [{"gyro_bias_y": BIAS}], record_interval=300.0,
                               integration_error=False, refined=False, warn=False)
    assert quiet.warnings == case.warnings
