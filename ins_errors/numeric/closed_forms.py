"""Closed-form static-base error responses, evaluated from the generated numpy code.

``generated/<model>/closed_forms.py`` holds, for each analysed variant (``"full"``, and
named simplifications such as ``"report_reduced"``), the response of every error state
to a unit error source and the mode frequencies. This module builds the static-base
state, inputs and parameters from a latitude, checks the arguments (latitude away from
the poles, R > 0, g > 0, finite times >= 0, the parameters the closed forms were derived
for) with :class:`~ins_errors.errors.DomainError`, and evaluates them. The generated
functions refuse the same with a one-line ``ValueError`` when called directly.

Where a denominator of a variant's forms vanishes inside the domain, the generated
function takes forms derived at that point (its ``LIMITS``: the orthodromic equator,
where the general forms divide by Ω sin φ); where one vanishes with no such forms, or
the forms overflow, it refuses in one line, and :meth:`ClosedForms.responses` says so
with :class:`~ins_errors.errors.DomainError` (never NaN).

The generated modules name the Foucault-split Schuler pair after ω± = ω̄ ± Ω sin φ with
the *signed* Ω sin φ, so south of the equator their "Schuler + Foucault" is the slower
mode. :meth:`ClosedForms.frequencies` and :meth:`ClosedForms.periods` name the pair by
size in either hemisphere (:data:`SPLIT_MODES`): "Schuler − Foucault" is always the
lower frequency ω̄ − Ω|sin φ| (the longer period), "Schuler + Foucault" the higher.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from types import ModuleType

import numpy as np

from ins_errors.errors import DomainError, ShapeError, UnknownNameError, unknown_name
from ins_errors.numeric.model import Model, load_model
from ins_errors.units import STANDARD_GRAVITY

SPLIT_MODES = ("Schuler − Foucault", "Schuler + Foucault")
"""Names of the Foucault-split Schuler modes: the lower frequency ω̄ − Ω|sin φ| (the
longer period), then the higher ω̄ + Ω|sin φ|, ω̄ = √(g/R + Ω² sin² φ)."""


def _split_pair_by_size(frequencies: dict[str, float]) -> dict[str, float]:
    """``frequencies`` (mode name -> rad/s) with the :data:`SPLIT_MODES` pair named by
    size, same keys in the same order (other modes unchanged)."""
    if not all(name in frequencies for name in SPLIT_MODES):
        return frequencies
    by_size = dict(zip(SPLIT_MODES, sorted(frequencies[name] for name in SPLIT_MODES),
                       strict=True))
    return {name: by_size.get(name, value) for name, value in frequencies.items()}


def closed_form_module(model: Model | str) -> ModuleType:
    """The generated closed-form module of ``model``.

    Raises
    ------
    UnknownNameError
        If the model has no static-base closed forms.
    """
    model = load_model(model) if isinstance(model, str) else model
    try:
        return importlib.import_module(f"ins_errors.generated.{model.name}.closed_forms")
    except ModuleNotFoundError:
        raise UnknownNameError(f"model {model.name!r} has no closed-form static-base "
                               "responses (see ins_errors/symbolic/static_base.py)") from None


@dataclass
class ClosedForms:
    """Validated access to one model's closed forms at one static base.

    Attributes
    ----------
    model : Model
    x : numpy.ndarray, shape (n,)
        Static-base state (zero ground velocity at the chosen latitude).
    u : numpy.ndarray, shape (nu,)
        Static-base inputs (only the vertical specific force is used, where it is one).
    p : numpy.ndarray, shape (np,)
        Parameters (the model's BAKED values where the closed forms fix them).
    """

    model: Model
    x: np.ndarray
    u: np.ndarray
    p: np.ndarray

    @property
    def module(self) -> ModuleType:
        """The generated module."""
        return closed_form_module(self.model)

    @property
    def variants(self) -> tuple[str, ...]:
        """Analysed variants (``"full"``, simplification names)."""
        return tuple(self.module.VARIANTS)

    def _variant(self, variant: str) -> str:
        if variant not in self.variants:
            raise unknown_name(f"closed-form variant of {self.model.name}", variant,
                               self.variants)
        return variant

    def responses(self, t, variant: str = "full") -> np.ndarray:
        """Error states for unit sources, shape (ne, nw) + t.shape.

        Parameters
        ----------
        t : array_like
            Times since the start, s (finite, >= 0).
        variant : str
            ``"full"`` or a simplification name.

        Raises
        ------
        DomainError
            Times not finite or negative; a point where a denominator of the forms
            vanishes and no limiting form is derived for it (the generated module's
            ``DENOMINATORS``; its ``LIMITS`` are taken instead of the general forms,
            e.g. the orthodromic equator).
        """
        variant = self._variant(variant)
        t = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(t)):
            raise DomainError("times contain NaN or infinite values")
        if np.any(t < 0):
            raise DomainError("closed-form responses hold for t >= 0 only")
        function = getattr(self.module, f"responses_{variant}")
        try:
            return function(t[None, ...], self.x, self.u, self.p)
        except ValueError as error:  # a denominator of the forms vanishes here
            raise DomainError(str(error)) from None

    def response(self, t, sources: dict[str, float], variant: str = "full") -> np.ndarray:
        """Error states for the given sources (SI) acting together, shape (ne,) + t.shape."""
        w = self.model.source_vector(**sources)
        return np.einsum("ij...,j->i...", self.responses(t, variant), w)

    def frequencies(self, variant: str = "full") -> dict[str, float]:
        """Mode name -> angular frequency, rad/s; the Foucault-split pair named by size
        (:data:`SPLIT_MODES`: "Schuler − Foucault" the lower) in either hemisphere."""
        variant = self._variant(variant)
        values = getattr(self.module, f"frequencies_{variant}")(self.x, self.u, self.p)
        return _split_pair_by_size(dict(zip(
            self.module.MODES[variant], np.asarray(values, dtype=float).tolist(),
            strict=True)))

    def periods(self, variant: str = "full") -> dict[str, float]:
        """Mode name -> period 2π/ω, s ("Schuler − Foucault" the longer of the pair)."""
        return {k: 2 * np.pi / w for k, w in self.frequencies(variant).items()}


def closed_forms(model: Model | str, latitude: float, p: np.ndarray | None = None,
                 gravity: float | None = None, **parameters: float) -> ClosedForms:
    """Closed forms of ``model`` on a static base at ``latitude`` (rad).

    Parameters
    ----------
    model : Model or str
    latitude : float
        rad; must be strictly between −π/2 and π/2.
    p : numpy.ndarray, optional
        Parameter vector (default: the model's defaults, then the values the closed
        forms were derived for (``BAKED``), then ``parameters``).
    gravity : float, optional
        Vertical specific force at rest, m/s², for models where it is an input
        (``a_zeta`` of ``orthodromic``); ``north_pointing`` has ``g`` as a parameter.
        Default: the static base's of the motion generators with these parameters (the
        normal gravity of the model's Earth at the latitude,
        :func:`~ins_errors.numeric.linear_system.static_base_gravity`), as
        ``ins-errors modes`` and ``propagation --orthodromic`` take it: 9.78781 m/s² for
        ``orthodromic`` at 39°.
    **parameters : float
        Parameter overrides by name (``R=...``, ``g=...``), SI.

    Raises
    ------
    DomainError
        Latitude at a pole, R <= 0, g <= 0, non-finite values, or parameters other than
        those the closed forms were derived for (e.g. an ellipsoid).
    """
    model = load_model(model) if isinstance(model, str) else model
    baked = getattr(closed_form_module(model), "BAKED", {})
    names = [q.name for q in model.parameters]
    if p is None:
        values = {q.name: float(q.default) for q in model.parameters}
        values.update(baked)
        for key, value in parameters.items():
            model.index("parameters", key)
            values[key] = float(value)
        p = np.array([values[n] for n in names])
    elif parameters:
        raise ShapeError("give either a parameter vector p or parameter overrides, not both")
    p = model._vector(p, model.parameters, "parameters p", "closed forms")
    latitude = float(latitude)
    if not np.isfinite(latitude):
        raise DomainError(f"latitude must be finite, got {latitude}")
    inputs = [i.name for i in model.inputs]
    u = np.zeros(len(inputs))
    if "a_zeta" in inputs:
        if gravity is not None and not gravity > 0:
            raise DomainError(f"gravity (vertical specific force a_zeta) must be positive, "
                              f"got {gravity}")
        u[inputs.index("a_zeta")] = STANDARD_GRAVITY if gravity is None else gravity
    c = model.initial_condition_vector(latitude=latitude)
    model._initial_domain(c, u, p, "closed forms")
    if "a_zeta" in inputs and gravity is None:  # the site is valid: the generators' own
        from ins_errors.numeric.linear_system import static_base_gravity

        u[inputs.index("a_zeta")] = static_base_gravity(model, latitude, p=p)
    x = model.initial_state(c, u, p)
    x, u, p = model._check_state(x, u, p, "closed forms")
    for name, value in baked.items():
        if not np.isclose(p[names.index(name)], value, rtol=1e-12, atol=0):
            what = "a spherical Earth" if name in ("e2", "ecc2") else f"{name} = {value:g}"
            raise DomainError(f"the closed forms of {model.name} are derived for {what}; "
                              f"got {name} = {p[names.index(name)]:g}")
    return ClosedForms(model, x, u, p)
