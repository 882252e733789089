"""``modes`` keeps an oscillation's real part wherever F has one beyond rounding, however
small beside F's largest |λ|, and zeroes it where F has none.

A part of λ below 1e-6 of F's largest |λ| used to be zero, to hide rounding. That also
hid real damping and growth: strapdown_ned's Schuler pairs beside its damped vertical
loop near the pole (Re λ ≈ −1.1e-8 1/s at 80°, 5e-7 of the loop's |λ|;
tests/test_transfer_damped_pole.py), and geodetic_vertical's with its orthodrome's start
point off the equator (orth_latitude = 10°: Schuler + Foucault growing by 1.1e-9 1/s,
9e-7 of |λ|, listed as undamped beside Schuler − Foucault growing by 2.5e-9 1/s).
The reference is the eigenvalues of the model's own F at 50 digits (mpmath): every
mode's real part agrees with theirs where they have one (beyond 1e-25 1/s, the rounding
of F's entries), and is exactly 0 where they do not (north_pointing, strapdown_ned
undamped apart from its vertical channel).
"""

from __future__ import annotations

import numpy as np
import pytest

mp = pytest.importorskip("mpmath")

from ins_errors.analysis.modes import static_modes  # noqa: E402

CASES = [
    ("geodetic_vertical", 10.0, {"orth_latitude": np.radians(10.0)}),
    ("strapdown_ned", 85.0, {"k_h1": 0.0293, "k_h2": 4.42e-4}),
    ("north_pointing", 45.0, {}),
    ("strapdown_ned", 45.0, {}),
]


def test_real_parts_are_kept_where_f_has_them_and_zero_where_it_has_none():
    kept = 0
    for model, degrees, parameters in CASES:
        modes = static_modes(model, np.radians(degrees), parameters=parameters)
        with mp.workdps(50):
            values = mp.eig(mp.matrix(modes.state_matrix.tolist()), left=False,
                            right=False)
            values = [complex(v) for v in values]
        tol = 1e-6 * max(abs(v) for v in values)
        for mode in (*modes.modes, *modes.unseen_modes):
            if not mode.eigenvalue.imag:
                continue
            exact = min(values, key=lambda v: abs(v - mode.eigenvalue))
            where = (model, degrees, mode.name)
            if abs(exact.real) > 1e-25:
                assert mode.eigenvalue.real == pytest.approx(exact.real, rel=1e-6), where
                assert mode.time_constant_s == pytest.approx(1 / abs(exact.real),
                                                             rel=1e-6), where
                kept += abs(exact.real) < tol  # the ones the old rule zeroed
            else:
                assert mode.eigenvalue.real == 0.0 and mode.time_constant_s is None, where
    assert kept == 3  # geodetic_vertical's Schuler + Foucault, strapdown_ned's two
