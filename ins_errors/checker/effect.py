"""Does it matter? The effect of each finding on the 1 h and 24 h error.

The model's linear error equations ``x' = F x + G w`` are frozen at each reference point
(their coefficients evaluated there) and propagated from each error state alone at its
typical magnitude and from each of the file's error sources alone at its typical
magnitude (the cases), once with the model's coefficients and once with the mistake put
in:

* a finding in an error-state line changes that row of F (and G) by the hand's minus the
  model's coefficient of its quantity (its own part: with the definitions it uses
  corrected; for a declared drop, the term the declaration removes);
* a mistake in a definition changes every error-state line it reaches by what it carries
  there (hand minus isolated hand of those lines);
* a mistake in a latitude/longitude line changes the position read out, not the states;
* one finding of two lines (a mirror pair, a term in the wrong row:
  :mod:`~ins_errors.checker.line_pairs`) changes both lines' entries together.

The effect is the largest change over the cases (the worst single error, as the matrix
check reports) of the horizontal position error (latitude and longitude errors, m, on a
sphere of the model's radius; for a model without them, its north and east position
outputs in metres where its equations identify them, :func:`metre_position`; neither:
no position figure, None) and of the attitude error (the platform angles,
:attr:`~ins_errors.modeling.ModelDefinition.platform_angles`, rad; for a model without
them, a strapdown INS, the changes of its roll, pitch and heading outputs; neither: no
attitude figure, None) after 1 h and 24 h, at the reference point where the finding is
largest (for a finding without one, the largest over the points; by the attitude for a
model without a position figure). The 24 h state is the
1 h transition matrix to the 24th power (exact for frozen coefficients).

A change too large for floating point (a coefficient of 1e300: the propagation
overflows to inf or NaN) is an infinite figure marked ``overflow_1h``/``overflow_24h``,
never one below the floor.

Each change is compared with the rounding floor of the two propagations
(:func:`ins_errors.checker.matrix_effects.rounding_floor`, the matrix check's): at or below it the
change is rounding, not an effect. When the mistake gives the frozen equations a growing
mode the model lacks (an eigenvalue with a larger positive real part), the effect is
said to grow exponentially, with the e-folding time of that mode, once the growth over
the time compared exceeds :data:`GROWTH_SHOWN` e-foldings; likewise for a growing mode
of the model itself (an undamped vertical channel) where the difference did grow that
much since 1 h (:func:`~ins_errors.checker.growth.mark_growth`).
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ins_errors.checker import classify as cl
from ins_errors.checker.growth import GROWTH_SHOWN, growth_rate, hours_tag, mark_growth
from ins_errors.checker.matrix_effects import rounding_floor
from ins_errors.checker.reference import _earth
from ins_errors.checker.sides import identified
from ins_errors.numeric.blas_threads import import_limited, one_blas_thread

HOURS = (1.0, 24.0)
"""Propagation times, h."""

ATTITUDE_OUTPUTS = ("roll", "pitch", "heading")
"""Outputs whose changes make the attitude effect of a model without platform angles."""

ELSEWHERE_SHOWN = 1.5
"""A finding's 24-h effect at another reference point is named beside the one at its own
point when it is more than this many times larger."""

STEP = 60.0
"""Sample step (s) the rounding floor counts steps in (the matrix check's, whose static
base is one exponential as well)."""


@one_blas_thread
def _propagate(f: np.ndarray, drive: np.ndarray, x0: np.ndarray) -> list[np.ndarray]:
    """Response of ``x' = F x + D w`` (w constant) to each case alone at each of
    :data:`HOURS`, by the exponential of the augmented matrix over the first time and
    its integer powers for the others.

    Parameters
    ----------
    f : ndarray, shape (n, n)
        Frozen F, 1/s (SI units of the error states).
    drive : ndarray, shape (n, m)
        Drive of each source at its typical magnitude (G column times magnitude), SI/s.
    x0 : ndarray, shape (n,)
        Typical magnitude of each error state, SI.

    Returns
    -------
    list of ndarray, shape (n, n + m)
        At each time: column j < n the states after error state j started at ``x0[j]``
        alone; column n + b after source b alone (from zero states).
    """
    expm = import_limited("scipy.linalg").expm  # (SciPy's BLAS limited as well)

    drive = np.asarray(drive, dtype=float).reshape(f.shape[0], -1)
    n, m = drive.shape
    a = np.zeros((n + m, n + m))
    a[:n, :n] = f
    a[:n, n:] = drive
    step = expm(a * HOURS[0] * 3600.0)
    start = np.diag(np.append(x0, np.ones(m)))
    return [(np.linalg.matrix_power(step, round(h / HOURS[0])) @ start)[:n] for h in HOURS]


def _worst(diffs: np.ndarray) -> tuple[float, int]:
    """Largest of per-case differences and its case (first of equal ones)."""
    j = int(np.argmax(diffs))
    return float(diffs[j]), j


def add_effects(report, d, side, comparison, identify, prepared, resolver,
                parameters=None) -> None:
    """Attach ``effect`` dicts to the report's root mistakes (see module docstring);
    ``parameters`` (name -> SI value, optional) are the model parameters the check set,
    the Earth radius among them."""
    from ins_errors.checker.sides import UnresolvedError as _UnresolvedError

    states = [v.name for v in d.error_states]
    symbols = [side.error_states[s] for s in states]
    basis_symbols = comparison.symbols
    sources = [b for b in basis_symbols if b not in symbols]
    magnitude = comparison.magnitude
    n, k = len(states), len(comparison.points)
    radius, _ = _earth(d, parameters)
    platform = [states.index(v.name) for v in d.platform_angles]
    geographic = [name for name in ("latitude", "longitude") if name in side.outputs]
    metres = {} if geographic else metre_position(d, _moving_points(d, comparison.points,
                                                                   parameters))
    has_position = bool(geographic or metres)
    read = (*geographic, *metres) + (() if platform else ATTITUDE_OUTPUTS)
    try:
        rows = [identified(side.state_rhs[s], identify) for s in states]
        outputs = {name: identified(side.delta(name), identify)
                   for name in read if name in side.outputs}
        entries = []  # (kind, row, quantity, coefficient): evaluated in one call
        for i, row in enumerate(rows):
            for b, c in comparison.linear_parts(row)[0].items():
                entries.append(("f", i, b, c))
        for name, expr in outputs.items():
            for b, c in comparison.linear_parts(expr)[0].items():
                entries.append((name, 0, b, c))
        values = comparison.evaluate([c for *_, c in entries]) if entries else []
        f = np.zeros((k, n, n))
        drive = np.zeros((k, n, len(sources)))
        readout = {name: np.zeros((k, n)) for name in outputs}
        for (kind, i, b, _), value in zip(entries, values, strict=True):
            if kind == "f" and b in symbols:
                f[:, i, symbols.index(b)] = value
            elif kind == "f" and b in sources:
                drive[:, i, sources.index(b)] += value * magnitude[b]
            elif kind != "f" and b in symbols:
                readout[kind][:, symbols.index(b)] = value
        cos_lat = (np.cos(comparison.evaluate([side.outputs["latitude"]])[0])
                   if "latitude" in side.outputs else np.ones(k))
    except (_UnresolvedError, KeyError):
        return
    angles = [name for name in ATTITUDE_OUTPUTS if name in readout]

    def attitude(point: int, x: np.ndarray) -> np.ndarray:
        """Attitude error (rad) of the states x (n, m): the platform angles, or the
        changes of the roll, pitch and heading outputs."""
        if platform:
            return x[platform]
        return np.array([readout[name][point] @ x for name in angles])
    x0 = np.array([magnitude[s] for s in symbols])
    items = {}
    for eq, its in zip(resolver.hand.equations, prepared, strict=True):
        for it in its:
            items[(id(eq), it.form)] = it

    cases = [f"initial {s}" for s in states] + [f"source {b}" for b in sources]
    scale = np.where(x0 > 0, x0, 1.0)[:, None]  # scaled responses for the floor

    def position_rows(point: int, extra: dict | None = None) -> np.ndarray:
        """Readout (2, n): north and east position error, m per SI unit of each state
        (latitude and longitude errors on the sphere of the model's radius, or the
        model's own outputs in metres, :func:`metre_position`)."""
        rows = np.zeros((2, n))
        if metres:
            for name, (axis, sign) in metres.items():
                rows[axis] += sign * readout[name][point]
                if extra and name in extra:
                    rows[axis] += sign * extra[name][point]
            return rows
        for i, name in enumerate(("latitude", "longitude")):
            if name in readout:
                rows[i] += readout[name][point]
            if extra and name in extra:
                rows[i] += extra[name][point]
        rows[1] *= cos_lat[point]
        return radius * rows

    # the figure the largest effect over the points and a model's own growth are read in
    shown = "position" if has_position else "attitude"
    baseline: dict[int, tuple[list[np.ndarray], float]] = {}
    labels = [point.label for point in comparison.points]

    def run(delta_f: np.ndarray, delta_drive: np.ndarray, out_delta: dict,
            where: str = "") -> dict | None:
        """Effect at the finding's point (every point if it has none; the largest kept).

        A finding with a point is also propagated at the other points: the largest
        24-h figure among them that is more than :data:`ELSEWHERE_SHOWN` times the one at
        the finding's point (and above its floor) is added with its point
        (``largest_point``, ``largest_what``, ``largest_24h``), since the point where a
        coefficient differs most in relative terms need not be where the error grows
        most; where the effect grows exponentially at another point (and not at the
        finding's), that point and the e-folding time are added instead
        (``largest_24h`` None, ``largest_e_folding_s``)."""
        at = labels.index(where) if where in labels else None
        best = None
        for p in ([at] if at is not None else range(k)):
            effect = effect_at(p, delta_f, delta_drive, out_delta)
            if best is None or (effect[f"{shown}_24h"] or 0.0) > (best[f"{shown}_24h"] or 0.0):
                best = {"point": comparison.points[p].label, **effect}
        if at is None or best is None or best.get("exponential_24h"):
            return best
        here = best[f"{shown}_24h"] or 0.0
        larger = None   # (growing?, size: 1/e-folding or the figure, point, effect)
        for p in range(k):
            if p == at:
                continue
            other = effect_at(p, delta_f, delta_drive, out_delta)
            if other.get("exponential_24h"):
                candidate = (True, 1.0 / other["e_folding_s"], p, other)
            else:
                value = other[f"{shown}_24h"] or 0.0
                if (value <= ELSEWHERE_SHOWN * here
                        or value <= (other[f"{shown}_floor_24h"] or 0.0)):
                    continue
                candidate = (False, value, p, other)
            if larger is None or candidate[:2] > larger[:2]:
                larger = candidate
        if larger is not None:
            growing, size, p, other = larger
            best.update(largest_point=comparison.points[p].label, largest_what=shown,
                        largest_24h=None if growing else size)
            if growing:
                best.update(largest_e_folding_s=other["e_folding_s"],
                            largest_growing_mode=other.get("growing_mode"))
        return best

    def effect_at(p: int, delta_f: np.ndarray, delta_drive: np.ndarray,
                  out_delta: dict) -> dict:
        """The effect (figures after 1 h and 24 h, their floors and cases, growth) with
        the equations frozen at point ``p``."""
        if p not in baseline:
            baseline[p] = (_propagate(f[p], drive[p], x0), growth_rate(f[p]))
        base_x, base_growth = baseline[p]
        changed_f = f[p] + delta_f[p]
        changed = _propagate(changed_f, drive[p] + delta_drive[p], x0)
        rows_base, rows_changed = position_rows(p), position_rows(p, out_delta)
        units = (max(float(np.linalg.norm(np.abs(r) @ x0))
                     for r in (rows_base, rows_changed)) if has_position else 0.0,
                 float(np.linalg.norm(np.abs(attitude(p, np.eye(n))) @ x0))
                 if platform or angles else 0.0)
        effect: dict = {}
        for hours, base, x in zip(HOURS, base_x, changed, strict=True):
            tag = hours_tag(hours)
            dpos = (np.linalg.norm(rows_changed @ x - rows_base @ base, axis=0)
                    if has_position else None)
            datt = (np.linalg.norm(attitude(p, x - base), axis=0) if platform or angles
                    else None)
            # a coefficient of 1e300 overflows the propagation: its NaN and inf are no
            # figure below the rounding floor but an effect beyond any
            overflow = not np.all(np.isfinite(x))
            largest = max(float(np.abs(r / scale).max(initial=0.0))
                          for r in ((base,) if overflow else (base, x)))
            steps = round(hours * 3600.0 / STEP)
            for what, diffs, unit in (("position", dpos, units[0]),
                                      ("attitude", datt, units[1])):
                if diffs is None:  # no position or attitude to read: no figure, not 0
                    effect.update({f"{what}_{tag}": None, f"{what}_floor_{tag}": None,
                                   f"{what}_case_{tag}": None})
                    continue
                value, j = _worst(diffs)
                floor = rounding_floor(largest, n + len(sources), steps, unit)
                if overflow or not np.all(np.isfinite(diffs)):
                    # (every case is NaN once the exponential overflows: no case named)
                    effect.update({f"overflow_{tag}": True, f"{what}_{tag}": math.inf,
                                   f"{what}_floor_{tag}": floor, f"{what}_case_{tag}": None})
                    continue
                effect[f"{what}_{tag}"] = value
                effect[f"{what}_floor_{tag}"] = floor
                effect[f"{what}_case_{tag}"] = cases[j] if value > floor else None
        mark_growth(effect, growth_rate(changed_f), base_growth, HOURS, shown)
        return effect

    state_of = {f"error state {s}": i for i, s in enumerate(states)}
    by_line = {f"line {r.equation.line} {r.label}": r for r in report.results}
    for result in report.results:
        item = items.get((id(result.equation), result.form))
        if item is None or item.hand is None:
            continue
        # an error-state line: one effect per finding, only its own columns
        if result.target in state_of and item.model_full is not None:
            effects = {}
            for g in result.findings:
                # the line's own findings, also those one slip of the line explains
                # (knock-ons of the line itself, under its root cl.LINE: all its columns)
                inline = g.role == cl.KNOCK_ON and g.roots == (result.reference,)
                if ((g.role != cl.ROOT and not inline) or not np.isfinite(g.size)
                        or g.merged):  # (the other half of a pair: its effect is there)
                    continue
                delta_f, delta_drive = np.zeros((k, n, n)), np.zeros((k, n, len(sources)))
                # the line's own part (definitions it uses corrected); a declared drop
                # is measured against the full model, whose term it leaves out
                hand, model = ((item.hand_isolated, item.model_full)
                               if g.severity == cl.DECLARED
                               else (item.hand_isolated, item.model_declared))
                try:
                    _add_row(delta_f, delta_drive, state_of[result.target], hand, model,
                             comparison, symbols, sources, magnitude,
                             only=None if g.quantity == cl.LINE
                             else set(g.quantity.split(" -> ")))
                    other = by_line.get(g.pair[0]) if g.pair else None
                    it = (items.get((id(other.equation), other.form))
                          if other is not None else None)
                    if it is not None and other.target in state_of:  # a pair: both lines
                        _add_row(delta_f, delta_drive, state_of[other.target],
                                 it.hand_isolated, it.model_declared, comparison, symbols,
                                 sources, magnitude, only={g.pair[1]})
                except _UnresolvedError:
                    continue
                effects[id(g)] = run(delta_f, delta_drive, {}, g.point)
            result.findings = [_with(g, effects[id(g)]) if id(g) in effects else g
                               for g in result.findings]
            continue
        roots = [g for g in result.findings if g.role == cl.ROOT and g.is_mistake
                 and np.isfinite(g.size)]
        if not roots:
            continue
        delta_f, delta_drive = np.zeros((k, n, n)), np.zeros((k, n, len(sources)))
        out_delta: dict[str, np.ndarray] = {}
        try:
            output = result.target.removeprefix("output ")
            if result.target.startswith("output latitude") or result.target in (
                    "intermediate phi",) or result.target.startswith("output longitude") \
                    or result.target == "intermediate lam" or output in metres:
                name = (output if output in metres
                        else "latitude" if ("latitude" in result.target
                                            or result.target.endswith("phi"))
                        else "longitude")
                diff = comparison.linear_parts(item.hand_isolated)[0]
                model = comparison.linear_parts(item.model_declared)[0]
                row = np.zeros((k, n))
                wanted = [b for b in set(diff) | set(model) if b in symbols]
                if wanted:
                    values = comparison.evaluate([diff.get(b, sp.S.Zero)
                                                  - model.get(b, sp.S.Zero) for b in wanted])
                    for b, value in zip(wanted, values, strict=True):
                        row[:, symbols.index(b)] = value
                out_delta[name] = row
            else:
                for other in report.results:
                    if other.target not in state_of:
                        continue
                    if not any(g.role == cl.KNOCK_ON and result.reference in g.roots
                               for g in other.findings):
                        continue
                    it = items.get((id(other.equation), other.form))
                    if it is None or it.hand is None:
                        continue
                    _add_row(delta_f, delta_drive, state_of[other.target], it.hand,
                             it.hand_isolated, comparison, symbols, sources, magnitude)
        except _UnresolvedError:
            continue
        if not delta_f.any() and not delta_drive.any() and not out_delta:
            effect = {"point": "—", "position_1h": 0.0, "position_24h": 0.0,
                      "attitude_1h": 0.0, "attitude_24h": 0.0,
                      "note": "reaches no error-state or position line"}
        else:
            effect = run(delta_f, delta_drive, out_delta, roots[0].point)
        result.findings = [g if g not in roots else _with(g, effect) for g in result.findings]


def _moving_points(d, points, parameters=None) -> list:
    """The points flown, or when none of them moves (``@scope static base``) every
    reference point of the model: what its outputs are does not depend on the scope."""
    if any(np.hypot(*p.ground_velocity) > 0 for p in points):
        return list(points)
    from ins_errors.checker.reference import reference_points

    return reference_points(d, None, parameters).points


def metre_position(d, points) -> dict[str, tuple[int, float]]:
    """The model's horizontal position outputs in metres, where its equations identify them.

    An output in m is the north (east) position when its ideal rate,
    ``∂y/∂x · ẋ`` of the model's ``ideal_rhs``, equals plus or minus the motion's north
    (east) ground velocity at every moving reference point (to 1e-6 of the speed): the
    cruises fly several tracks, so only a horizontal position in metres along those axes
    does (a height, an along-track distance or a rotated axis does not). Names play no
    part.

    Parameters
    ----------
    d : ModelDefinition
    points : sequence of ReferencePoint
        Their ``values`` (ideal states, inputs, parameters) and ``ground_velocity``.

    Returns
    -------
    dict of str to (int, float)
        Output name -> (axis: 0 north, 1 east; sign ±1), both axes or nothing (empty also
        when no point moves).
    """
    moving = [p for p in points if np.hypot(*p.ground_velocity) > 0]
    candidates = [k for k, v in enumerate(d.outputs) if v.unit == "m"]
    if not moving or not candidates:
        return {}
    outputs = d.outputs_expanded()
    rhs = d.ideal_rhs_expanded()
    rates = [sum((outputs[k].diff(x) * f for x, f in zip(d.x, rhs, strict=True)),
                 sp.S.Zero) for k in candidates]
    evaluate = sp.lambdify([d.x, d.u, d.p], rates, "numpy", docstring_limit=0)
    found: dict[int, list[tuple[str, float]]] = {0: [], 1: []}
    with np.errstate(all="ignore"):
        values = np.array([np.broadcast_to(np.asarray(
            evaluate([p.values[s] for s in d.x], [p.values[s] for s in d.u],
                     [p.values[s] for s in d.p]), dtype=float), (len(candidates),))
            for p in moving])  # (points, candidates)
    velocity = np.array([p.ground_velocity for p in moving])  # (points, 2)
    tolerance = 1e-6 * np.hypot(velocity[:, 0], velocity[:, 1])
    for j, k in enumerate(candidates):
        for axis in (0, 1):
            for sign in (1.0, -1.0):
                if np.all(np.abs(values[:, j] - sign * velocity[:, axis]) <= tolerance):
                    found[axis].append((d.outputs[k].name, sign))
    if len(found[0]) != 1 or len(found[1]) != 1 or found[0][0][0] == found[1][0][0]:
        return {}
    return {name: (axis, sign) for axis in (0, 1) for name, sign in found[axis]}


def _with(finding, effect):
    from dataclasses import replace

    return replace(finding, effect=dict(effect))


def _add_row(delta_f, delta_drive, row, hand, model, comparison, symbols, sources, magnitude,
             only: set[str] | None = None):
    """Add (hand − model) coefficients of one error-state line to row ``row`` (only the
    quantities named in ``only``, if given)."""
    h = comparison.linear_parts(hand)[0]
    m = comparison.linear_parts(model)[0]
    wanted = sorted((b for b in set(h) | set(m) if only is None or str(b) in only),
                    key=sp.default_sort_key)
    if not wanted:
        return
    values = comparison.evaluate([h.get(b, sp.S.Zero) - m.get(b, sp.S.Zero) for b in wanted])
    for b, value in zip(wanted, values, strict=True):
        if b in symbols:
            delta_f[:, row, symbols.index(b)] += value
        elif b in sources:
            delta_drive[:, row, sources.index(b)] += value * magnitude[b]


__all__ = ["GROWTH_SHOWN", "HOURS", "add_effects", "metre_position"]
