"""The advice after a refused pair moves what the latitude actually comes from.

tests/models/tangent_plane_ins.py has no latitude on its base: its origin latitude is
the parameter phi0 (``-p phi0=...``). With its velocity loop damped (c_v, c_i) and phi0
1e-7° from the equator, gyro_drift_U → x_E reaches the east position through couplings
going with sin phi0, below what rounding resolves, and the pair is refused. The refusal
must say so (the cause the parameter's latitude supports, not "roots too close") and
point to the nearest phi0 at which the pair resolves, as the user sets it: before, it
said "the base has no latitude to move".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
TANGENT = str(ROOT / "tests" / "models" / "tangent_plane_ins.py")
DAMPING = ["-p", "c_v=2e-3/s", "-p", "c_i=1e-6/s^2"]
PAIR = ["--source", "gyro_drift_U", "--output", "x_E"]


def test_refusal_moves_the_latitude_parameter(capsys):
    from ins_errors.numeric.model import load_model

    load_model(TANGENT)     # a first use in a cache says "deriving model file ..." first
    capsys.readouterr()
    assert main(["transfer", TANGENT, *PAIR, "-p", "phi0=1e-7deg", *DAMPING]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "gyro_drift_U → x_E of tangent_plane_ins cannot be resolved" in err
    assert "near the equator its couplings go with sin φ" in err
    assert "no latitude to move" not in err
    advice = err.split("the same pair is resolved at ")[1].strip()
    assert advice == "-p phi0=0.0100001deg"  # 1e-7° + 0.01°, the nearest step tried
    # the setting as advised, the other parameters kept: the pair resolves, and its W
    # agrees with h (iωI − F)⁻¹ g of the model's F at that phi0 (a solve of our own)
    assert main(["transfer", TANGENT, *PAIR, *advice.split(), *DAMPING, "--json"]) == 0
    import json

    from ins_errors.analysis.modes import static_modes
    from ins_errors.analysis.transfer import transfer_at_base
    from ins_errors.numeric.model import load_model

    data = json.loads(capsys.readouterr().out)
    assert data["pairs"][0]["check_error"] < 1e-6
    model = load_model(TANGENT)
    modes = static_modes(model, parameters={"phi0": np.radians(0.0100001), "c_v": 2e-3,
                                            "c_i": 1e-6})
    pair = transfer_at_base(model, modes, ["gyro_drift_U"], ["x_E"]).pairs[0]
    point = modes.point
    g = np.asarray(model.source_matrix(point.x, point.u, point.p), float)[
        :, model.index("sources", "gyro_drift_U")]
    h = np.asarray(model.output_matrix(point.x, point.u, point.p), float)[
        model.index("outputs", "x_E")]
    omegas = np.geomspace(1e-6, 1e-1, 15)
    direct = np.array([h @ np.linalg.solve(1j * w * np.eye(len(g)) - modes.state_matrix, g)
                       for w in omegas])
    assert np.abs(pair(1j * omegas) - direct).max() < 1e-6 * np.abs(direct).max()
    assert data["pairs"][0]["gain"] == pair.gain
