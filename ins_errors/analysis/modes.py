"""Static-base modes of any model's error equations: the eigenvalues of F, named.

At rest the linear error equations ``ẋe = F xe + G w`` have constant coefficients, and
their free motions are the modes of F: each eigenvalue λ (a conjugate pair counted once)
is an integrator (λ = 0), a damped or growing exponential (real λ), an undamped
oscillation (λ = ±iω) or a damped or growing one. :func:`static_modes` builds the static
base exactly as ``ins-errors compare MODEL --motion static`` does
(:func:`ins_errors.numeric.trajectories.trajectory`, which hands ``strapdown_ned`` to
:mod:`ins_errors.numeric.strapdown_truth`), evaluates F from the generated numpy
functions at t = 0 and names its modes in the field's terms against the textbook values
of the model's own g, R and Ω (:mod:`ins_errors.analysis.mode_references`):

* oscillations whose natural frequency |λ| lies near ω_s = √(g/R), damped or not (|ζ|
  below :data:`NAMED_DAMPING`): "Schuler"; two of them whose imaginary parts are split by
  Ω|sin φ| (within 10 %) are the Foucault pair, named by size as
  :data:`~ins_errors.numeric.closed_forms.SPLIT_MODES` names them ("Schuler − Foucault"
  the lower frequency, the longer period);
* oscillations with |λ| near Ω: "Earth";
* a named oscillation damped by |ζ| >= :data:`LIGHT_DAMPING` says so: "Schuler
  (damped)", "Schuler − Foucault (growing)";
* real λ near ±√(2g/R): "vertical channel (growing)" / "(decaying)";
* the rest by kind: "integrator", "damped", "growing", "oscillation", "damped
  oscillation", "growing oscillation".

A named oscillation is compared with its textbook value by its natural period 2π/|λ|
where it is damped or growing (the damped Foucault pair against
:meth:`~ins_errors.analysis.mode_references.References.split` at its ζ), by its period
2π/Im λ where it is not.

"Near" is within a factor :data:`BAND`. Each mode lists the error states that take part:
the row norms of an orthonormal basis of its invariant subspace (ordered real Schur
form), relative to the largest, with the states measured as equivalent angles in the
units of the Schuler loop (lengths over R, velocities over √(gR); see
:func:`schuler_loop_scales`),
or in their display units when the model lacks g or R.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from ins_errors.analysis.mode_references import References, references
from ins_errors.errors import DomainError, unknown_name
from ins_errors.numeric.closed_forms import SPLIT_MODES
from ins_errors.numeric.model import Model, as_model
from ins_errors.numeric.nonfinite import WHY, nonfinite_entries

ZERO = 1e-6
"""Eigenvalues (and real or imaginary parts) below this share of the largest |λ| are
zero: rounding splits a repeated zero eigenvalue of a Jordan chain into ±1e-12 1/s."""

BAND = 1.25
"""A mode is named after a reference rate when it lies within this factor of it."""

FOUCAULT_MATCH = 0.1
"""Two Schuler pairs are the Foucault split when half their difference is Ω|sin φ|
within this share."""

LIGHT_DAMPING = 0.05
"""A named oscillation damped (or growing) by a damping ratio at least this in size says
so in its name ("Schuler (damped)"); below it the name is plain: coupling to a damped
vertical loop leaves the Schuler and Earth pairs damped by ζ ~ 1e-4."""

NAMED_DAMPING = 0.9
"""An oscillation is named after a reference frequency only while its damping ratio is
below this in size. Beyond it the pair hardly oscillates (its first overshoot,
e^(−πζ/√(1 − ζ²)), is below 0.2 %; its damped period more than 2.29 times its
natural one), and near critical damping what is left of Im λ is set by the Earth's turning
Ω sin φ more than by the loop: with Ω the Schuler pair never becomes real (ζ → 1 only as
the gain grows without bound), so ζ = 1 cannot mark the end of the name. Without Ω an
overdamped loop (ζ >= 1) has two real modes, listed by kind ("damped")."""

DAMPING_WORDS = (" (damped)", " (growing)")
"""What a named oscillation's name ends with where |ζ| >= :data:`LIGHT_DAMPING`."""

SHOWN_SHARE = 0.1
"""Error states below this share of the largest are left out of the short listing."""

UNSEEN = 1e-7
"""Tolerance of the split of a mode into the part the model's errors reach and its
outputs see and the rest (:func:`_split`), on the states of the Schuler loop's units:
a direction is not reached when the sources' and initial errors' columns of [G E]
(each of unit length), projected on the mode and carried by F (T/|λ|, T = Vᵀ F V on its
invariant subspace V), span it only with singular values at or below it; not seen when
every output's row of H (unit length) reads it, and F's action on it, below it.
Rounding leaves ~1e-15; an INS mode is reached and read at 1e-4 and more."""

UNSEEN_WORDS = ("not reached by any error source or initial error: directions of the "
                "state its constraints hold fixed (e.g. a rotation matrix stored as 9 "
                "entries, or a quaternion, leaving the rotations), not modes of the INS")
"""What the text says of the modes no error reaches."""

UNREAD_WORDS = ("reached by the errors but not seen by any output: the INS's own, in "
                "error states no output reads, directly or through F (e.g. the azimuth "
                "where the Earth does not turn)")
"""What the text says of the modes the errors reach and no output sees."""


@dataclass(frozen=True)
class Reference:
    """A mode's textbook value and how far the mode is from it.

    Attributes
    ----------
    formula : str
        E.g. ``"2π√(R/g)"``.
    seconds : float
        The textbook period (oscillations) or time constant (real modes), s.
    relative_difference : float
        (mode's value − textbook value) / textbook value.
    quantity : str
        The mode's value compared: ``"period"`` (2π/Im λ, an undamped oscillation),
        ``"natural_period"`` (2π/|λ|, a damped or growing one) or ``"time_constant"``
        (1/|λ|, a real mode).
    """

    formula: str
    seconds: float
    relative_difference: float
    quantity: str = "period"

    def to_dict(self) -> dict:
        return {"formula": self.formula, "value_s": self.seconds,
                "relative_difference": self.relative_difference, "quantity": self.quantity}


@dataclass(frozen=True)
class Mode:
    """One mode of F at the static base.

    Attributes
    ----------
    name : str
        Field name ("Schuler − Foucault", "Earth", "vertical channel (growing)"; a named
        oscillation with |ζ| >= :data:`LIGHT_DAMPING` ends in " (damped)" or
        " (growing)": "Schuler − Foucault (damped)") or kind.
    kind : str
        "integrator", "damped", "growing", "oscillation", "damped oscillation" or
        "growing oscillation".
    eigenvalue : complex
        λ, 1/s (of a pair, the one with positive imaginary part).
    multiplicity : int
        How many times λ (a pair: the pair) is an eigenvalue.
    period_s : float or None
        2π/Im λ, s (oscillations).
    time_constant_s : float or None
        1/|Re λ|, s: decay time of a damped mode, e-folding time of a growing one.
    damping_ratio : float or None
        −Re λ / |λ| (oscillations; negative when growing).
    reference : Reference or None
        The textbook value of a named mode.
    participation : dict of str to float
        Error state -> its size in the mode relative to the largest (1), every state.
    independent_directions : int or None
        For the integrators: the number of independent zero-eigenvalue directions
        (fewer than ``multiplicity`` when F has a Jordan chain, an error growing as t^k).
    note : str or None
        Why the mode is off its textbook value, where the model says so (its
        :attr:`~ins_errors.numeric.model.Model.mode_notes`: a property of the
        mechanisation, e.g. ``geodetic_vertical``'s Earth mode on the ellipsoid).
    seen : bool
        False for a mode no error source or initial error reaches or no output sees
        (:data:`UNSEEN`), named by kind only, listed in :attr:`StaticModes.unseen_modes`
        (JSON ``reached_and_seen``).
    reached : bool
        False for a mode no error source or initial error reaches: a direction the
        state's constraints hold fixed (a rotation matrix's orthonormality, a
        quaternion's norm). A mode the errors reach and no output sees (``seen`` False,
        ``reached`` True) is the INS's own, in error states no output reads, directly
        or through F: north_pointing's azimuth integrator where the Earth does not turn
        (``-p U=0rad/s``).
    """

    name: str
    kind: str
    eigenvalue: complex
    multiplicity: int
    period_s: float | None
    time_constant_s: float | None
    damping_ratio: float | None
    reference: Reference | None
    participation: dict[str, float]
    independent_directions: int | None = None
    note: str | None = None
    seen: bool = True
    reached: bool = True

    @property
    def base_name(self) -> str:
        """The name of an oscillation without the word on its damping:
        ``"Schuler − Foucault"`` for ``"Schuler − Foucault (damped)"`` (the name itself
        otherwise: "vertical channel (growing)" is a real mode's whole name)."""
        for word in DAMPING_WORDS:
            if self.period_s is not None and self.name.endswith(word):
                return self.name.removesuffix(word)
        return self.name

    @property
    def doubling_time_s(self) -> float | None:
        """ln 2 · e-folding time of a growing mode, s (None otherwise)."""
        if self.eigenvalue.real > 0 and self.time_constant_s is not None:
            return float(np.log(2.0) * self.time_constant_s)
        return None

    @property
    def natural_period_s(self) -> float | None:
        """2π/|λ|, s: the period the oscillation would have without its damping (or
        growth), the loop's natural frequency ω_n = |λ| (a damped Schuler loop
        s² + k s + ω_s² has ω_n = ω_s: its 84.4 min); None for a mode that does not
        oscillate or is neither damped nor growing."""
        if self.period_s is None or self.time_constant_s is None:
            return None
        return float(2 * np.pi / abs(self.eigenvalue))

    def states(self, share: float = SHOWN_SHARE) -> list[tuple[str, float]]:
        """(error state, share) of the states at or above ``share``, largest first."""
        return sorted(((k, v) for k, v in self.participation.items() if v >= share),
                      key=lambda item: -item[1])

    def to_dict(self) -> dict:
        return {"name": self.name, "kind": self.kind,
                "eigenvalue": {"real": self.eigenvalue.real, "imag": self.eigenvalue.imag},
                "multiplicity": self.multiplicity, "period_s": self.period_s,
                "time_constant_s": self.time_constant_s,
                "doubling_time_s": self.doubling_time_s,
                "natural_period_s": self.natural_period_s,
                "damping_ratio": self.damping_ratio,
                "independent_directions": self.independent_directions,
                "reference": None if self.reference is None else self.reference.to_dict(),
                "note": self.note, "reached_and_seen": self.seen,
                "participation": self.participation}


TURNING_RATE = 1e-12
"""Least rate, rad/s, at which an angle of the ideal state that F depends on counts as
turning at rest (a turn in 200 000 years; rounding of an Earth-rate term is 1e-20)."""


@dataclass(frozen=True)
class TurningAtRest:
    """An angle of the ideal state that turns at rest, with F depending on it: F at the
    base's start is then one instant of a matrix that changes (free_azimuth's wander angle
    A takes up the Earth's vertical rate, Ȧ = −U sin φ).

    Attributes
    ----------
    state : str
        The ideal state (an angle, rad).
    rate : float
        Its rate at rest, rad/s.
    """

    state: str
    rate: float

    @property
    def period_s(self) -> float:
        """The time of one turn, 2π/|rate|, s."""
        return float(2 * np.pi / abs(self.rate))

    def words(self) -> str:
        """``"its state's angle A turns at rest (-5.586e-05 rad/s: once every 31.24 h)"``."""
        from ins_errors.time_text import duration_text

        return (f"its state's angle {self.state} turns at rest ({self.rate:.4g} rad/s: once "
                f"every {duration_text(self.period_s)}), and F with it")

    def to_dict(self) -> dict:
        return {"state": self.state, "rate_rad_per_s": self.rate,
                "period_s": self.period_s}


def turning_at_rest(model: Model, x: np.ndarray, u: np.ndarray, p: np.ndarray
                    ) -> TurningAtRest | None:
    """The fastest angle of the ideal state (unit rad) that turns at rest faster than
    :data:`TURNING_RATE` while F depends on it (a change of 1e-3 rad in it changes F), or
    None: F at rest is then the same at every time."""
    x = np.asarray(x, dtype=float).reshape(-1)
    with np.errstate(all="ignore"):
        rates = np.asarray(model.numpy.ideal_rhs(x, u, p), dtype=float).reshape(-1)
        F = np.asarray(model.state_matrix(x, u, p), dtype=float)
    found = None
    for k, state in enumerate(model.states):
        if state.unit != "rad" or not abs(rates[k]) > TURNING_RATE:
            continue
        moved = x.copy()
        moved[k] += 1e-3
        with np.errstate(all="ignore"):
            changed = np.asarray(model.state_matrix(moved, u, p), dtype=float)
        if not np.any(changed != F):
            continue
        if found is None or abs(rates[k]) > abs(found.rate):
            found = TurningAtRest(state.name, float(rates[k]))
    return found


@dataclass(frozen=True, eq=False)
class RestPoint:
    """The point of the static base F was evaluated at (what other analyses of the same
    base, e.g. :mod:`ins_errors.analysis.transfer`, evaluate G, H and E at).

    Compared by identity (``==`` is ``is``; hashable): it holds arrays, whose ``==``
    has no single truth value.

    Attributes
    ----------
    x : numpy.ndarray, shape (n,)
        True state at rest, SI.
    u : numpy.ndarray, shape (nu,)
        Inputs at rest, SI.
    p : numpy.ndarray, shape (np,)
        Parameters, SI.
    c : numpy.ndarray, shape (nc,)
        Initial conditions of the base, SI.
    factors : numpy.ndarray, shape (ne,)
        Per error state, the factor that measures it in the units of the Schuler loop
        (:func:`schuler_loop_scales`; its display unit without g or R).
    """

    x: np.ndarray
    u: np.ndarray
    p: np.ndarray
    c: np.ndarray
    factors: np.ndarray


@dataclass(frozen=True, eq=False)
class StaticModes:
    """The modes of one model's F at one static base.

    Compared by identity (``==`` is ``is``; hashable): it holds arrays, whose ``==``
    has no single truth value.

    Attributes
    ----------
    model : str
        Model name.
    base : str
        The base as the other commands describe it (values the model does not use
        left out).
    latitude, height : float or None
        Of the base, rad and m; None for a model without one (its runs do not depend on
        it: a tangent-plane INS whose origin latitude is a parameter).
    state_matrix : numpy.ndarray, shape (ne, ne)
        F at the base, SI.
    eigenvalues : numpy.ndarray, shape (ne,)
        Every eigenvalue of F, 1/s.
    references : References
        g, R, Ω read from the model (None where it lacks one).
    scales : dict of str to str
        Error state -> the unit its participation is measured in.
    modes : tuple of Mode
        The modes the model's errors reach and some output sees (the INS's own), by
        increasing |λ|.
    latitude_source : str or None
        Where the latitude of the Foucault split Ω|sin φ| came from: ``"base"``, a
        parameter (``"parameter phi0"``) for a model without a latitude, or None (no
        latitude: no Foucault split is named).
    point : RestPoint or None
        The state, inputs, parameters and initial conditions of the base, and the
        states' scale factors (None when built from F alone).
    unseen_modes : tuple of Mode
        The modes no error reaches or no output sees (``seen`` False; :data:`UNSEEN`),
        by increasing |λ|: directions the state's constraints hold fixed, e.g. a
        rotation matrix stored as 9 entries leaving the orthonormal ones. Empty where
        every mode is reached and seen.
    """

    model: str
    base: str
    latitude: float | None
    height: float | None
    state_matrix: np.ndarray
    eigenvalues: np.ndarray
    references: References
    scales: dict[str, str]
    modes: tuple[Mode, ...] = field(default_factory=tuple)
    latitude_source: str | None = "base"
    point: RestPoint | None = field(default=None, repr=False, compare=False)
    unseen_modes: tuple[Mode, ...] = field(default_factory=tuple)
    turning: TurningAtRest | None = None

    def mode(self, name: str) -> Mode:
        """The first mode called ``name``.

        Raises
        ------
        UnknownNameError
            If no mode has that name (the names are listed).
        """
        for mode in self.modes:
            if mode.name == name:
                return mode
        raise unknown_name(f"mode of {self.model}", name,
                           list(dict.fromkeys(m.name for m in self.modes)))

    @property
    def foucault_period_s(self) -> float | None:
        """The Foucault period 2π/(Ω|sin φ|), s, of the model's Ω at the latitude: the
        time in which the plane of the Schuler oscillation turns once (None without Ω
        or a latitude, and at the equator)."""
        rate = self.references.foucault
        return 2 * np.pi / rate if rate else None

    @property
    def foucault_period_from_modes_s(self) -> float | None:
        """The Foucault period from the eigenvalues, 2π/((ω₊ − ω₋)/2), s, ω± the
        imaginary parts of the split Schuler pair: their half difference is the rate the
        oscillation's plane turns at, damped or not (None without the named split pair)."""
        rates = [m.eigenvalue.imag for m in self.modes if m.base_name in SPLIT_MODES]
        if len(rates) != 2 or rates[0] == rates[1]:
            return None
        return float(2 * np.pi / (abs(rates[1] - rates[0]) / 2))

    def to_dict(self) -> dict:
        refs = self.references
        latitude = None if refs.latitude is None else {
            "value": refs.latitude, "unit": "rad", "source": self.latitude_source}
        foucault = None if self.foucault_period_s is None else {
            "formula": "2π/(Ω|sin φ|)", "period_s": self.foucault_period_s,
            "from_modes_s": self.foucault_period_from_modes_s}
        return {"model": self.model, "base": self.base, "latitude_rad": self.latitude,
                "height_m": self.height,
                "references": {**refs.to_dict(), "latitude": latitude},
                "foucault": foucault,
                "participation_units": self.scales,
                "eigenvalues": [{"real": v.real, "imag": v.imag} for v in self.eigenvalues],
                "modes": [m.to_dict() for m in self.modes],
                "unseen_modes": [m.to_dict() for m in self.unseen_modes],
                "turning_at_rest": None if self.turning is None else self.turning.to_dict()}


def static_modes(model: Model | str, latitude: float = np.radians(50.0),
                 longitude: float = np.radians(30.0), heading: float = 0.0,
                 height: float = 0.0, parameters: Mapping[str, float] | None = None,
                 ) -> StaticModes:
    """The modes of ``model``'s error equations on a static base.

    Parameters
    ----------
    model : Model or str
        A loaded model, a model name or a model file.
    latitude, longitude : float
        Position of the base, rad (defaults: 50°, 30°, as ``--motion static``).
    heading : float
        Track angle of the model's trihedron (a strapdown body's heading), rad.
    height : float
        Height of the base, m.
    parameters : mapping of str to float, optional
        Model parameters to set, SI (e.g. ``{"k_h1": 0.0293, "k_h2": 4.42e-4}``); the
        others keep the model's defaults.

    Returns
    -------
    StaticModes
        F, its eigenvalues and the named modes.

    Raises
    ------
    InsErrorsError
        An unknown model or parameter, a latitude at a pole or not finite, F not finite.

    Examples
    --------
    >>> from ins_errors.analysis.modes import static_modes
    >>> modes = static_modes("north_pointing")
    >>> round(modes.mode("Earth").period_s / 3600, 2)
    23.93
    """
    from ins_errors.numeric import trajectories as tr

    return modes_at_rest(model, tr.static_profile(latitude, longitude, heading, height),
                         parameters)


def modes_at_rest(model: Model | str, profile, parameters: Mapping[str, float] | None = None,
                  given: Mapping[str, tuple[str, str]] | None = None) -> StaticModes:
    """The modes of ``model``'s error equations on the static base ``profile``.

    Parameters
    ----------
    model : Model or str
        A loaded model, a model name or a model file.
    profile : ins_errors.numeric.trajectories.Profile
        A static profile (:func:`~ins_errors.numeric.trajectories.static_profile`, or
        :func:`~ins_errors.numeric.motion_spec.motion_profile` of kind ``"static"``).
    parameters : mapping of str to float, optional
        Model parameters to set, SI.
    given : mapping of str to (str, str), optional
        The base's reference values given explicitly (reference name -> (option, text),
        e.g. ``{"latitude": ("--latitude", "10deg")}``): those the model has none of are
        refused (:func:`~ins_errors.numeric.trajectories.refuse_unused_references`).

    Returns
    -------
    StaticModes
        For a model without a latitude (or height) :attr:`StaticModes.latitude`
        (``height``) is None; the Foucault split then uses the model's latitude
        parameter if it has one (:func:`~ins_errors.numeric.trajectories.reference_parameter`).

    Raises
    ------
    InsErrorsError
        A moving profile, an unknown model or parameter, a latitude at a pole, F not
        finite, a reference value given for a model without it.
    """
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric import trajectories as tr

    model = as_model(model, "static_modes")
    if not getattr(profile, "static", False):
        raise InsErrorsError("static_modes: the profile must be a static base "
                             "(trajectories.static_profile)")
    p = model.parameter_vector(**dict(parameters or {}))
    motion = tr.trajectory(model, profile, 1.0, 1.0, p=p, stream=True)
    tr.refuse_unused_references(model, motion, given or {})
    x, u = motion.start_state, motion.start_inputs
    with np.errstate(all="ignore"):  # said below, by entry, in the model's names
        F = np.asarray(model.state_matrix(x, u, p), dtype=float)
    states = [e.name for e in model.error_states]
    listed = nonfinite_entries("F", F, states, states)
    if listed is not None:
        raise DomainError(f"F of {model.name} is not finite at the {motion.description} "
                          f"in {listed}; {WHY}")
    used = tr.REFERENCES if motion.references is None else motion.references
    height = float(profile.commands(np.zeros(1))[0][2, 0]) if "height" in used else None
    latitude, source = _latitude(model, p, profile.latitude, "latitude" in used)
    refs = references(model, u, p, latitude, height or 0.0)
    factors, units = schuler_loop_scales(model, refs,
                                         np.asarray(x, dtype=float).reshape(-1))
    names = [s.name for s in model.error_states]
    point = RestPoint(np.asarray(x, dtype=float), np.asarray(u, dtype=float), p,
                      np.asarray(motion.initial_conditions, dtype=float), factors)
    H = np.asarray(model.output_matrix(x, u, p), dtype=float).reshape(-1, len(names))
    B = np.hstack([np.asarray(model.source_matrix(x, u, p), dtype=float).reshape(len(names), -1),
                   np.asarray(model.initial_error_matrix(point.c, u, p), dtype=float
                              ).reshape(len(names), -1)])
    seen, unseen = _modes(F, factors, names, refs, model.mode_notes, H, B)
    return StaticModes(model.name, motion.description,
                       profile.latitude if "latitude" in used else None, height, F,
                       np.linalg.eigvals(F), refs, dict(zip(names, units, strict=True)),
                       seen, source, point, unseen, turning_at_rest(model, x, u, p))


def _latitude(model: Model, p: np.ndarray, base: float, used: bool
              ) -> tuple[float | None, str | None]:
    """The latitude of the Foucault split and where it came from: the base's, or, for a
    model without a latitude, its latitude parameter's (None, None without one)."""
    from ins_errors.numeric import trajectories as tr

    if used:
        return float(base), "base"
    parameter = tr.reference_parameter(model, "latitude")
    if parameter is None:
        return None, None
    value = p[[q.name for q in model.parameters].index(parameter.name)]
    return float(value), f"parameter {parameter.name}"


def _longitude_scales(model: Model, x: np.ndarray, latitude: float | None
                      ) -> dict[int, tuple[float, str]]:
    """Error state index -> (cos of its latitude, that latitude's name) for the errors of
    the model's longitude states.

    A longitude error δλ is a distance R cos φ δλ on the ground: measured as the latitude
    error is (an angle of the great circle), it is cos φ δλ, not δλ. A longitude state is
    a state in rad whose description says "longitude"; its latitude is the model's one
    state in rad whose description says "latitude", at the base (the orthodromic Φ of an
    orthodromic Λ), else the base's latitude; without either, none is scaled.
    """
    def says(state, word: str) -> bool:
        return state.unit == "rad" and word in state.description.lower()

    longitudes = [k for k, s in enumerate(model.states) if says(s, "longitude")]
    latitudes = [k for k, s in enumerate(model.states)
                 if says(s, "latitude") and not says(s, "longitude")]
    if len(latitudes) == 1:
        value, name = float(x[latitudes[0]]), model.states[latitudes[0]].name
    elif latitude is not None:
        value, name = float(latitude), "φ"
    else:
        return {}
    return {k: (float(np.cos(value)), name) for k in longitudes}


def schuler_loop_scales(model: Model, refs: References,
                        x: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """Per error state: the factor that makes it an equivalent angle, and how it reads.

    With g and R known, every state is measured in the units of the Schuler loop, in
    which a tilt ε comes with a velocity error ε √(gR) and a position error ε R: angles
    and dimensionless states (direction cosines, quaternion components) as they are,
    lengths over R, velocities over √(gR), accelerations over g, rates over ω_s, and a
    longitude error times the cosine of its latitude (a distance over R, as the latitude
    error is; :func:`_longitude_scales`). Without g or R, each state in its display unit
    (angles in arcmin, m/s, m; a longitude error again times the cosine).
    """
    from ins_errors.units import display_scale

    natural: dict[str, tuple[float, str]] = {}
    if refs.g is not None and refs.R is not None:
        g, R = refs.g.value, refs.R.value
        natural = {"rad": (1.0, "rad"), "1": (1.0, "1 (as an angle)"),
                   "m": (1.0 / R, "m / R"), "m/s": (1.0 / np.sqrt(g * R), "(m/s) / √(gR)"),
                   "m/s**2": (1.0 / g, "(m/s²) / g"), "rad/s": (np.sqrt(R / g), "(rad/s) / ω_s")}
    longitudes = _longitude_scales(model, x, refs.latitude)
    factors, units = [], []
    for k, state in enumerate(model.error_states):
        factor, unit = natural.get(state.unit) or display_scale(
            "rad" if state.unit == "1" else state.unit)
        if k in longitudes:
            cosine, name = longitudes[k]
            factor, unit = factor * cosine, f"{unit} × cos {name} (a distance over R)"
        factors.append(factor)
        units.append(unit)
    return np.array(factors), units


# --------------------------------------------------------------------------------------
# Eigenvalues grouped into modes, their subspaces, their names
# --------------------------------------------------------------------------------------
def _accuracies(A: np.ndarray, eigenvalues: np.ndarray) -> np.ndarray:
    """Per eigenvalue of ``A``, the size below which its computed value is rounding, 1/s:
    :data:`~ins_errors.analysis.transfer_reduction.GROUP_SAFETY` times its first-order
    accuracy κ n ε ‖A‖ (or a Jordan block's split;
    :func:`~ins_errors.analysis.transfer_reduction.roots_and_accuracies`, on A over its
    norm)."""
    from ins_errors.analysis.transfer_reduction import GROUP_SAFETY, roots_and_accuracies

    size = float(np.linalg.norm(A, 2))
    if not size or not len(A):
        return np.zeros(len(eigenvalues))
    values, errors = roots_and_accuracies(A / size, 0.0)
    nearest = np.argmin(np.abs(eigenvalues[:, None] - size * values[None, :]), axis=1)
    return GROUP_SAFETY * size * errors[nearest]


def _groups(eigenvalues: np.ndarray, tol: float, accuracies: np.ndarray | None = None
            ) -> list[tuple[complex, int]]:
    """(λ with Im λ >= 0, multiplicity) of each distinct eigenvalue, by increasing |λ|;
    parts below ``tol`` set to zero, except the real part of an oscillation above its
    accuracy (``accuracies``, 1/s, per eigenvalue): its damping (a Schuler pair damped
    by a damped vertical channel near a pole, Re λ ~ 1e-8 1/s, is 1e-6 of |λ| there)."""
    groups: list[list] = []
    if accuracies is None:
        accuracies = np.full(len(eigenvalues), np.inf)
    for value, accuracy in sorted(zip(eigenvalues, accuracies, strict=True),
                                  key=lambda v: (abs(v[0]), v[0].imag)):
        if value.imag < -tol:
            continue  # counted with its conjugate
        imag = 0.0 if abs(value.imag) <= tol else value.imag
        cut = min(tol, accuracy) if imag else tol
        value = complex(0.0 if abs(value.real) <= cut else value.real, imag)
        for group in groups:
            if abs(group[0] - value) <= tol:
                group[1] += 1
                break
        else:
            groups.append([value, 1])
    return [(complex(v), int(k)) for v, k in groups]


def _subspace(A: np.ndarray, value: complex, count: int, tol: float
              ) -> tuple[np.ndarray, np.ndarray]:
    """Orthonormal basis (n, k) of the invariant subspace of the eigenvalues near
    ``value`` (and its conjugate), and the k × k block of the real Schur form on it."""
    from scipy.linalg import schur

    def near(re, im):
        return abs(complex(re, abs(im)) - value) <= tol

    T, Q, k = schur(A, output="real", sort=near)
    expected = count * (2 if value.imag else 1)
    if k != expected:  # reordering failed to separate them: the eigenvectors instead
        w, V = np.linalg.eig(A)
        chosen = V[:, [j for j, v in enumerate(w) if near(v.real, v.imag)]]
        basis = np.linalg.svd(np.hstack([chosen.real, chosen.imag]))[0][:, :expected]
        return basis, basis.T @ A @ basis
    return Q[:, :k], T[:k, :k]


def _participation(basis: np.ndarray, names: list[str]) -> dict[str, float]:
    size = np.linalg.norm(basis, axis=1)
    size = size / size.max()
    return {name: float(s) for name, s in zip(names, size, strict=True)}


def _note(name: str, notes: Mapping[str, str]) -> str | None:
    """The model's note on the mode called ``name`` (:data:`~ins_errors.modeling.
    MODE_NOTE_KEYS`: "Schuler" for the Foucault-split pair too), or None."""
    for key, text in notes.items():
        if name == key or name.startswith(f"{key} "):
            return text
    return None


def _outputs(H: np.ndarray | None, factors: np.ndarray) -> np.ndarray | None:
    """H on the states of the Schuler loop's units, each output's row of unit length (rows
    reading nothing dropped); None without outputs (every mode then counts as seen)."""
    if H is None or not H.size or not np.all(np.isfinite(H)):
        return None
    rows = H / factors[None, :]
    size = np.linalg.norm(rows, axis=1)
    rows = rows[size > 0] / size[size > 0, None]
    return rows if len(rows) else None


def _projected(A: np.ndarray, basis: np.ndarray, value: complex, count: int, tol: float,
               factors: np.ndarray, B: np.ndarray | None) -> np.ndarray | None:
    """The columns of B (on the states of the Schuler loop's units) in a mode's invariant
    subspace ``basis``, by the spectral projection along the other modes: W'ᵀ B, W' the
    left invariant subspace made dual to ``basis``; each column scaled to the unit
    length of its projection's largest. None without B or where it fails."""
    if B is None or not B.size or not np.all(np.isfinite(B)):
        return None
    left, _ = _subspace(A.T, value, count, tol)
    try:
        projected = np.linalg.solve(left.T @ basis, left.T @ (factors[:, None] * B))
    except np.linalg.LinAlgError:
        return None
    size = np.linalg.norm(factors[:, None] * B, axis=0)
    return projected[:, size > 0] / size[size > 0]


def _krylov(start: np.ndarray, step: np.ndarray) -> np.ndarray:
    """Orthonormal basis of the span of ``start``'s columns and their images under
    ``step`` (k × k, its eigenvalues of size 1): singular values above :data:`UNSEEN`."""
    k = len(step)
    blocks, block = [], start
    for _ in range(k):
        blocks.append(block)
        block = step @ block
    u, singular, _ = np.linalg.svd(np.hstack(blocks), full_matrices=False)
    return u[:, :int(np.sum(singular > UNSEEN))]


def _split(block: np.ndarray, read: np.ndarray | None, reached: np.ndarray | None,
           rate: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Orthonormal bases (k, ·) of the part of a mode's invariant subspace the model's
    errors reach and its outputs see, of the part they reach and no output sees, and of
    the part they do not reach, in the subspace's coordinates.

    ``block`` is F on the subspace (k × k), ``read`` the outputs' reading of it (H V),
    ``reached`` the sources' and initial errors' share in it (the spectral projection
    of [G E]), ``rate`` |λ| (1 for λ = 0). The part reached is the Krylov space of
    ``reached`` under T; of it, the part seen is the orthogonal complement of the null
    space of [H V; H V T/rate; ...] there (the unseen part: F keeps it, no output reads
    it)."""
    k = len(block)
    step = block / rate
    reach = np.eye(k) if reached is None else _krylov(reached, step)
    kept, unseen = reach, reach[:, :0]
    if read is not None and reach.shape[1]:
        seen = _krylov((read @ reach).T, (reach.T @ step @ reach).T)
        kept = reach @ seen
        unseen = reach @ np.linalg.svd(seen, full_matrices=True)[0][:, seen.shape[1]:]
    u = np.linalg.svd(reach, full_matrices=True)[0]
    return kept, unseen, u[:, reach.shape[1]:]


def _modes(F: np.ndarray, factors: np.ndarray, names: list[str], refs: References,
           notes: Mapping[str, str] | None = None, H: np.ndarray | None = None,
           B: np.ndarray | None = None) -> tuple[tuple[Mode, ...], tuple[Mode, ...]]:
    """The modes the errors of B (sources and initial errors, columns) reach and some
    output of H sees (named), and the rest (by kind); without H or B, all are kept."""
    A = factors[:, None] * F / factors[None, :]  # F in display units: same eigenvalues
    outputs = _outputs(H, factors)
    eigenvalues = np.linalg.eigvals(A)
    radius = float(np.abs(eigenvalues).max())
    tol = ZERO * radius if radius > 0 else np.finfo(float).tiny
    raw, unseen = [], []
    for value, count in _groups(eigenvalues, tol, _accuracies(A, eigenvalues)):
        basis, block = _subspace(A, value, count, tol)
        shown, unread, unreached = _split(
            block, None if outputs is None else outputs @ basis,
            _projected(A, basis, value, count, tol, factors, B), abs(value) or 1.0)
        per = 2 if value.imag else 1
        for part, into, reached in ((shown, raw, True), (unread, unseen, True),
                                    (unreached, unseen, False)):
            if not part.shape[1]:
                continue
            if part.shape[1] < len(block):
                block_part = part.T @ block @ part  # F on the part (on the quotient: shown)
                basis_part = basis @ part
            else:
                block_part, basis_part = block, basis
            directions = None
            if value == 0:
                singular = np.linalg.svd(block_part, compute_uv=False)
                directions = int(part.shape[1] - np.sum(
                    singular > 1e-8 * np.linalg.norm(A)))
            into.append((value, part.shape[1] // per, _participation(basis_part, names),
                         directions, reached))
    named = _names([(v, k) for v, k, _, _, _ in raw], refs)
    seen = tuple(_mode(value, count, name, reference, participation, directions,
                       _note(name, notes or {}) if _explained(reference) else None)
                 for (value, count, participation, directions, _), (name, reference)
                 in zip(raw, named, strict=True))
    return seen, tuple(
        replace(_mode(value, count, kind_of_eigenvalue(value), None, participation,
                      directions),
                seen=False, reached=reached)
        for value, count, participation, directions, reached in unseen)


def kind_of_eigenvalue(value: complex) -> str:
    """What an eigenvalue of F does, in words: "integrator", "damped", "growing",
    "oscillation", "damped oscillation" or "growing oscillation" (a pole no textbook
    mode names is called by its kind)."""
    if value == 0:
        return "integrator"
    if not value.imag:
        return "damped" if value.real < 0 else "growing"
    if not value.real:
        return "oscillation"
    return "damped oscillation" if value.real < 0 else "growing oscillation"


NOTED_DIFFERENCE = 1e-4
"""A model's note on a mode is shown where the mode is off its textbook value by more
than this (0.01 %): a row at its textbook value needs no explanation (strapdown_ned's
Schuler note, on the undamped vertical channel's coupling, has nothing to say once the
damping loop is set)."""


def _explained(reference: Reference | None) -> bool:
    return reference is not None and abs(reference.relative_difference) > NOTED_DIFFERENCE


def _mode(value: complex, count: int, name: str, reference: Reference | None,
          participation: dict[str, float], directions: int | None,
          note: str | None = None) -> Mode:
    period = 2 * np.pi / value.imag if value.imag else None
    time_constant = 1.0 / abs(value.real) if value.real else None
    # + 0.0: an undamped oscillation's −0/|λ| is −0.0, shown as "-0.0" in JSON
    damping = -value.real / abs(value) + 0.0 if value.imag else None
    return Mode(name, kind_of_eigenvalue(value), value, count, period, time_constant, damping,
                reference, participation, directions, note)


def _near(rate: float, reference: float | None) -> bool:
    return reference is not None and reference / BAND <= rate <= reference * BAND


def _reference(formula: str, seconds: float, reference_seconds: float,
               quantity: str = "period") -> Reference:
    return Reference(formula, reference_seconds, seconds / reference_seconds - 1.0, quantity)


def _damping_word(zeta: float) -> str:
    """What a named oscillation's name says of its damping ratio ζ."""
    if abs(zeta) < LIGHT_DAMPING:
        return ""
    return DAMPING_WORDS[0] if zeta > 0 else DAMPING_WORDS[1]


def _oscillation_reference(formula: str, value: complex, frequency: float) -> Reference:
    """An oscillation λ against the textbook frequency (rad/s): its period 2π/Im λ when
    undamped, its natural period 2π/|λ| when damped or growing (the textbook values are
    those of undamped loops, whose natural frequency a damping gain leaves alone)."""
    if value.real:
        return _reference(formula, 2 * np.pi / abs(value), 2 * np.pi / frequency,
                          "natural_period")
    return _reference(formula, 2 * np.pi / value.imag, 2 * np.pi / frequency)


def _foucault_split(groups: list[tuple[complex, int]], schuler: list[int],
                    refs: References) -> bool:
    """Whether the Schuler rows ``schuler`` are one Foucault-split pair: two pairs (with
    their multiplicities), damped alike, whose imaginary parts differ by 2 Ω|sin φ|
    (within :data:`FOUCAULT_MATCH`). Damped or not, that half difference is the turning
    rate: the pair is the roots of s² + (k + 2iΩ sin φ) s + ω_s² = 0, whose sum has the
    imaginary part −2Ω sin φ whatever the gain k (:meth:`References.split`)."""
    if refs.split() is None or not refs.foucault:
        return False
    pairs = [groups[j][0] for j in schuler for _ in range(groups[j][1])]
    if len(pairs) != 2 or len({_damping_word(-v.real / abs(v)) for v in pairs}) != 1:
        return False
    half = abs(pairs[1].imag - pairs[0].imag) / 2
    return abs(half - refs.foucault) <= FOUCAULT_MATCH * refs.foucault


def _names(groups: list[tuple[complex, int]], refs: References
           ) -> list[tuple[str, Reference | None]]:
    """(name, reference) of each group."""
    out: list[tuple[str, Reference | None]] = [(kind_of_eigenvalue(v), None) for v, _ in groups]
    zeta = [-v.real / abs(v) if v.imag else None for v, _ in groups]
    named = [z is not None and abs(z) < NAMED_DAMPING for z in zeta]
    schuler = [j for j, (v, _) in enumerate(groups) if named[j] and _near(abs(v), refs.schuler)]
    foucault = _foucault_split(groups, schuler, refs)
    rates = sorted(groups[j][0].imag for j in schuler)
    for j in schuler:
        value, word = groups[j][0], _damping_word(zeta[j])
        if foucault:
            lower = value.imag == rates[0]
            frequency = refs.split(zeta[j])[0 if lower else 1]
            sign = "−" if lower else "+"
            formula = (f"2π/(ω̄_ζ {sign} Ω_ζ)" if value.real else f"2π/(ω̄ {sign} Ω|sin φ|)")
            name = SPLIT_MODES[0 if lower else 1]
        else:
            name, frequency, formula = "Schuler", refs.schuler, "2π√(R/g)"
        out[j] = (name + word, _oscillation_reference(formula, value, frequency))
    for j, (value, _) in enumerate(groups):
        if named[j] and refs.Omega is not None and _near(
                abs(value), refs.Omega.value) and j not in schuler:
            out[j] = ("Earth" + _damping_word(zeta[j]),
                      _oscillation_reference("2π/Ω", value, refs.Omega.value))
        elif not value.imag and value.real and _near(abs(value.real), refs.vertical):
            which = "growing" if value.real > 0 else "decaying"
            out[j] = (f"vertical channel ({which})",
                      _reference("√(R/2g)", 1 / abs(value.real), 1 / refs.vertical,
                                 "time_constant"))
    return out
