"""Each source's contribution to every navigation error at chosen times (``--at``).

The allocated (or fixed) magnitudes are propagated once more with every error state and
output as a readout: each source's 1σ share of every navigation error (each platform
angle and each output's error) at the times asked for, latitude and longitude errors as
metres north and east.
"""

from __future__ import annotations

import numpy as np

from ins_errors.analysis.budget import (
    Allocation,
    BudgetError,
    _radii,
    format_time,
    rounding_floors,
    typical_state_sizes,
)
from ins_errors.analysis.covariance import SourceStatistics, propagate
from ins_errors.specs import HOUR, Spec, SpecError
from ins_errors.units import parse_quantity

OUTPUT_DISPLAY = {"rad": "arcmin", "m/s": "m/s", "rad/s": "deg/h", "m": "m", "1": "ppm"}
"""Units the output table quotes SI quantities in."""

POSITION_METRES = {"delta_latitude": ("delta_r_N", 1), "delta_longitude": ("delta_r_E", 2)}
"""Latitude and longitude errors shown as north and east position errors, m: the name of
the distance and the index of its radius among the results of
:func:`~ins_errors.analysis.budget._radii` (R_N, R_E cos φ)."""


PERTURBATION_MARGIN = 1000.0
"""A contribution is round-off when it is at most this many times what it changes by
when the error equations are perturbed in their last bit (:func:`perturbed_spread`).
Round-off measured this way changes by its own size (0.05 to 11 times the spread,
orthodromic over 48 h at rest); a real contribution by 1e-6 of it or less."""

PERTURBATIONS = 2
"""Perturbed propagations :func:`perturbed_spread` makes (fixed seeds: the same table
every time)."""


def perturbed_spread(system, stats, functionals, covariance, index) -> np.ndarray:
    """How much each 1σ contribution changes when F, G, E and the readouts are
    perturbed in their last bit, the largest over :data:`PERTURBATIONS` propagations.

    A functional that does not depend on a source at all may still get a value from
    entries of F that hold an identity (cos² + sin² = 1, a cancelling pair of Earth-rate
    terms) only to the last bit: the system the propagation solves is then a neighbour
    of the true one, and that neighbour's dependence grows with time as the dynamics
    integrate it (an accelerometer bias's azimuth at rest: 6e-19 rad after 1 h,
    1.6e-15 rad after 8 h, 1.8e-13 rad after 48 h, about t³), past a bound on the
    rounding of the propagation itself. Another neighbour (each entry times
    1 ± ε, signs drawn) gives another such value: the change measures it, whatever the
    mechanism, while a real contribution changes by ~1e-15 of itself.

    Parameters
    ----------
    system : LinearSystem
    stats : list of SourceStatistics
        The sources propagated (allocated magnitudes).
    functionals : Functionals
    covariance : Covariance
        The propagation of ``stats`` on ``system``.
    index : list of int
        Grid steps of the times asked for.

    Returns
    -------
    numpy.ndarray, shape (len(index), functionals, sources)
        Largest change of each 1σ contribution, in the functionals' SI units.
    """
    from dataclasses import replace

    from ins_errors.analysis.budget import EPS

    std = np.sqrt(covariance.contributions[index])
    spread = np.zeros_like(std)
    def nudge(a: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        return a * (1.0 + EPS * rng.choice([-1.0, 1.0], size=a.shape))

    for seed in range(PERTURBATIONS):
        rng = np.random.default_rng(seed)
        neighbour = replace(system, F=nudge(system.F, rng), G=nudge(system.G, rng),
                            E=nudge(system.E, rng))
        readouts = replace(functionals, C_x=nudge(functionals.C_x, rng))
        other = np.sqrt(propagate(neighbour, stats, readouts, warn=False).contributions[index])
        spread = np.maximum(spread, np.abs(other - std))
    return spread


def check_times(spec: Spec, times, what: str = "--at") -> None:
    """Refuse, before any work, times outside the spec's operating time or off its
    analysis grid (one line naming the operating time and the step).

    Parameters
    ----------
    spec : Spec
    times : iterable of float
        s.
    what : str
        Where the times were given, for the message.

    Raises
    ------
    SpecError
    """
    from ins_errors.numeric.integrators import whole_steps

    end = spec.step * max(1, round(spec.operating_time / spec.step))
    for t in times:
        if not np.isfinite(t) or t < 0 or t > end * (1 + 1e-12):
            raise SpecError(f"{what}: time {format_time(t)} is outside the spec's operating "
                            f"time, 0 to {format_time(end)}")
        if whole_steps(t, spec.step) is None:
            raise SpecError(f"{what}: time {format_time(t)} is not on the spec's "
                            f"{spec.step:g} s analysis grid (its operating time: 0 to "
                            f"{format_time(end)} in steps of {spec.step:g} s)")


def navigation_errors(model, names: tuple[str, ...]) -> list[int]:
    """Indices, among the functionals of
    :func:`~ins_errors.analysis.covariance.state_and_output_functionals` (``names``), of
    every navigation error: the platform angles, then every output's error in the
    model's order of outputs (position, height, velocity, attitude, as the model has
    them).

    The platform angles are the error states beyond the errors of the computed states
    (a platform model's α; a strapdown model has none, its attitude is its roll, pitch
    and heading outputs). An output's error is the functional named for it: the output
    row ``delta_<output>`` (``delta_<output>_output`` where an error state has that
    name but H reads the output otherwise), or the error state itself where H reads
    that state alone (north_pointing's latitude, longitude and velocities, a strapdown
    model's velocities), which the functionals list once, among the states.
    """
    chosen = list(range(len(model.states), len(model.error_states)))
    for output in model.outputs:
        name = f"delta_{output.name}"
        for candidate in (f"{name}_output", name):
            if candidate in names:
                chosen.append(names.index(candidate))
                break
        else:
            raise BudgetError(f"the error of output {output.name!r} is none of the "
                              f"propagated functionals")
    return chosen


def output_contributions(model, allocation: Allocation, times: list[float]) -> dict:
    """Each source's 1σ contribution to every navigation error
    (:func:`navigation_errors`: platform angles and every output's error).

    A latitude and a longitude error are given as the north and east position errors
    ``delta_r_N`` = R_N Δφ and ``delta_r_E`` = R_E cos φ Δλ, m (the radii of the
    position item, :func:`~ins_errors.analysis.budget._radii`, along the motion at each
    time) when the model has an Earth radius; in arcmin otherwise.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    allocation : Allocation
        Magnitudes to use (unconstrained sources are left out).
    times : list of float
        s, on the spec's analysis grid and within its operating time.

    Returns
    -------
    dict
        ``{"times_h", "quantities", "units", "sources", "std", "total"}``: ``std`` of
        shape (len(times), quantities, sources), each source's 1σ contribution, and
        ``total`` of shape (len(times), quantities), their root sum of squares, in the
        display units ``units`` (one per quantity).
    """
    from ins_errors.analysis.covariance import state_and_output_functionals

    budget = allocation.budget
    system = budget.system
    keep = [j for j in range(len(budget.sources)) if np.isfinite(allocation.sigma[j])]
    stats = [SourceStatistics(budget.sources[j].name, budget.sources[j].statistics,
                              float(allocation.sigma[j]), budget.sources[j].tau) for j in keep]
    functionals = state_and_output_functionals(model, system)
    chosen = navigation_errors(model, functionals.names)
    check_times(budget.spec, times)
    index = [round(t / system.step) for t in times]
    covariance = propagate(system, stats, functionals, warn=False)
    contributions = covariance.contributions[np.ix_(index, chosen)]      # (t, q, s)
    # a contribution at or below the rounding floor of the propagation is round-off
    # (e.g. 7e-35 arcmin): shown as 0
    readout = functionals.C_x if functionals.C_x.ndim == 2 else functionals.C_x[index]
    ne = len(model.error_states)
    floors = rounding_floors(covariance.contributions[index][:, :ne], readout,
                             typical_state_sizes(model), ne + len(keep),
                             np.array(index))[:, chosen]
    spread = perturbed_spread(system, stats, functionals, covariance, index)[:, chosen]
    floors = np.maximum(floors, (PERTURBATION_MARGIN * spread) ** 2)
    contributions = np.where(contributions > floors, contributions, 0.0)
    std = np.sqrt(contributions)
    total = np.sqrt(contributions.sum(-1))
    names = [functionals.names[i] for i in chosen]
    units = [functionals.units[i] for i in chosen]
    radii = None
    if any(name in POSITION_METRES for name in names):
        try:
            radii = _radii(model, system)
        except BudgetError:   # no Earth radius: the angles stay
            radii = None
    shown = []
    for q, unit in enumerate(units):
        if radii is not None and names[q] in POSITION_METRES and unit == "rad":
            names[q], which = POSITION_METRES[names[q]]
            factor = radii[which][index]                     # m per rad at each time
            std[:, q] *= factor[:, None]
            total[:, q] *= factor
            shown.append("m")
            continue
        target = OUTPUT_DISPLAY.get(unit, unit)
        factor = parse_quantity(f"1 {unit}", target, "unit") if unit != "1" else 1e6
        std[:, q] *= factor
        total[:, q] *= factor
        shown.append(target)
    return {"times_h": [t / HOUR for t in times], "quantities": names, "units": shown,
            "sources": [budget.sources[j].label for j in keep], "std": std, "total": total}
