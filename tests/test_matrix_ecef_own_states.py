"""A hand F in the own states of an ECEF strapdown INS (tests/models/ecef_ins.py): no state
is a north or east position, and none is the vertical channel; and ``nav.gravity`` of a
model file without a parameter g.

References, independent of the checker:

* the static base propagated with SciPy's matrix exponential: Groves' ECEF error model
  (tests/data/ecef_vr.py) turned into NED by C_e^n, its down velocity and position held
  (rows and columns zeroed, as the checker holds dv_D, dr_D), read as north and east
  metres; the attitude error of the computed frame, δθ = (δλ cos φ, −δφ, −δλ sin φ);
* the gravity of the model's equations written out: |−μ r/|r|³ − Ω × (Ω × r)|, and the
  fixture tests/models/enu_strapdown.py's γ(φ) (a/(a + h))².
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.checker.check_motions import motions

HERE = Path(__file__).resolve().parent
MODEL = str(HERE / "models" / "ecef_ins.py")
HAND = HERE / "data" / "ecef_vr.py"
G0 = 9.80665
MU, R, U = 3.986004418e14, 6_371_000.0, 7.292115e-5
LAT, LON, HEADING = np.radians(50.0), np.radians(30.0), np.radians(30.0)


def test_nav_gravity_is_the_gravity_of_the_models_own_equations():
    from ins_errors.checker.navigation import navigation_arrays

    model = load_model(MODEL)
    earth = np.array([0.0, 0.0, U])
    for motion in motions(model)[:2]:  # at rest at h = 0, and the cruise at 10 km
        nav = motion.navigation
        lat, lon, h = nav["latitude"], nav["longitude"], nav["height"]
        r = (R + h) * np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon),
                                np.sin(lat)])
        g = -MU * r / np.linalg.norm(r, axis=0)**3 - np.cross(earth, np.cross(earth, r.T)).T
        np.testing.assert_allclose(nav["gravity"], np.linalg.norm(g, axis=0), rtol=1e-12)
    # at rest the accelerometers read it (what `ins-errors modes` takes as g): 9.806267,
    # not the WGS-84 normal-gravity formula with e² = 0 (9.791413)
    static = motions(model)[0].navigation
    np.testing.assert_allclose(static["gravity"], np.linalg.norm(static["f_b"], axis=0),
                               rtol=1e-12)
    assert static["gravity"][0] == pytest.approx(9.806267, abs=1e-6)
    # a model file with normal gravity falling off as (a/(a + h))²
    enu = load_model(str(HERE / "models" / "enu_strapdown.py"))
    cruise = motions(enu)[1]
    p = dict(zip((q.name for q in enu.parameters), cruise.p, strict=True))
    nav = navigation_arrays(enu, cruise.x, cruise.u, cruise.p)
    s2 = np.sin(nav["latitude"])**2
    a, e2 = p["a"], p["e2"]
    gamma = p["gamma_e"] * (1 + p["gk"] * s2) / np.sqrt(1 - e2 * s2)
    np.testing.assert_allclose(nav["gravity"], gamma * (a / (a + nav["height"]))**2,
                               rtol=1e-12)
