"""Speed of the static-base analysis (issue 5): symbolic derivation and closed forms.

Prints wall and CPU seconds of

* each model's static-base analysis (resolvent, modes, closed forms of every source),
  the document and the numpy module (what ``make derive``'s transfer-function step does);
* evaluating the generated closed forms of every source on 24 h at 1 s, against
  integrating the linear error equations (scipy DOP853) to the same times.
"""

from __future__ import annotations

import time

import numpy as np


def _timed(label: str, function):
    wall, cpu = time.perf_counter(), time.process_time()
    result = function()
    print(f"{label:<58}{time.perf_counter() - wall:8.2f} s wall"
          f"{time.process_time() - cpu:8.2f} s CPU")
    return result


def main(quick: bool = False) -> None:
    from derive.transfer_functions import closed_form_module, markdown
    from ins_errors.numeric.closed_forms import closed_forms
    from ins_errors.numeric.model import load_model
    from ins_errors.symbolic.static_base import SETUPS, static_analyses

    for model in SETUPS:
        results = _timed(f"{model}: static analysis (all variants, all sources)",
                         lambda model=model: static_analyses(model))
        _timed(f"{model}: transfer_functions.md",
               lambda model=model, results=results: markdown(model, results))
        _timed(f"{model}: closed_forms.py",
               lambda model=model, results=results: closed_form_module(model, results))

    from scipy.integrate import solve_ivp

    model = load_model("north_pointing")
    latitude = np.radians(39.0)
    cf = closed_forms(model, latitude)
    times = np.arange(0.0, 3600.0 * (2 if quick else 24) + 1, 1.0)
    _timed(f"north_pointing: closed forms, 12 sources x {times.size} times",
           lambda: cf.responses(times))
    F = model.state_matrix(cf.x, cf.u, cf.p)
    G = model.source_matrix(cf.x, cf.u, cf.p)
    E = model.initial_error_matrix(model.initial_condition_vector(latitude=latitude), cf.u,
                                   cf.p)
    n, m = G.shape
    _timed(f"north_pointing: DOP853 (rtol 1e-12), 12 sources x {times.size} times",
           lambda: solve_ivp(lambda _t, z: (F @ z.reshape(n, m) + G).ravel(),
                             (0.0, times[-1]), E.ravel(), method="DOP853", t_eval=times,
                             rtol=1e-12, atol=1e-16))


if __name__ == "__main__":
    main()
