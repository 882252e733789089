"""Closed-form static-base error responses, evaluated from the generated numpy code.

``generated/<model>/closed_forms.py`` holds, for each analysed variant (``"full"``, and
named simplifications such as ``"report_reduced"``), the response of every error state
to a unit error source and the mode frequencies. This module checks the arguments
(latitude away from the poles, R > 0, g > 0, finite times) and evaluates them.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from types import ModuleType

import numpy as np

from ins_errors.errors import DomainError, ShapeError, UnknownNameError, unknown_name
from ins_errors.numeric.model import Model, load_model


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
        Static-base state (zero velocity; only the position matters).
    p : numpy.ndarray, shape (np,)
        Parameters.
    """

    model: Model
    x: np.ndarray
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
        """
        variant = self._variant(variant)
        t = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(t)):
            raise DomainError("times contain NaN or infinite values")
        if np.any(t < 0):
            raise DomainError("closed-form responses hold for t >= 0 only")
        function = getattr(self.module, f"responses_{variant}")
        return function(t[None, ...], self.x, self.p)

    def response(self, t, sources: dict[str, float], variant: str = "full") -> np.ndarray:
        """Error states for the given sources (SI) acting together, shape (ne,) + t.shape."""
        w = self.model.source_vector(**sources)
        return np.einsum("ij...,j->i...", self.responses(t, variant), w)

    def frequencies(self, variant: str = "full") -> dict[str, float]:
        """Mode name -> angular frequency, rad/s."""
        variant = self._variant(variant)
        values = getattr(self.module, f"frequencies_{variant}")(self.x, self.p)
        return dict(zip(self.module.MODES[variant], np.asarray(values, dtype=float),
                        strict=True))

    def periods(self, variant: str = "full") -> dict[str, float]:
        """Mode name -> period 2π/ω, s."""
        return {k: 2 * np.pi / w for k, w in self.frequencies(variant).items()}


def closed_forms(model: Model | str, latitude: float, p: np.ndarray | None = None,
                 **parameters: float) -> ClosedForms:
    """Closed forms of ``model`` on a static base at ``latitude`` (rad).

    Parameters
    ----------
    model : Model or str
    latitude : float
        rad; must be strictly between −π/2 and π/2.
    p : numpy.ndarray, optional
        Parameter vector (default: the model's defaults with ``parameters`` applied).
    **parameters : float
        Parameter overrides by name (``R=...``, ``g=...``), SI.

    Raises
    ------
    DomainError
        Latitude at a pole, R <= 0, g <= 0, non-finite values, or an ellipsoid (the
        closed forms are derived for the sphere).
    """
    model = load_model(model) if isinstance(model, str) else model
    closed_form_module(model)
    if p is None:
        p = _default_parameters(model, parameters)
    elif parameters:
        raise ShapeError("give either a parameter vector p or parameter overrides, not both")
    latitude = float(latitude)
    if not np.isfinite(latitude):
        raise DomainError(f"latitude must be finite, got {latitude}")
    names = [s.name for s in model.states]
    x = np.zeros(len(names))
    x[_latitude_index(model)] = latitude
    x, _u, p = model._check_state(x, np.zeros(len(model.inputs)), p, "closed forms")
    names = [q.name for q in model.parameters]
    if "ecc2" in names and p[names.index("ecc2")] != 0:
        raise DomainError("closed forms are derived for a spherical Earth: ecc2 must be 0")
    return ClosedForms(model, x, p)


def _default_parameters(model: Model, overrides: dict[str, float]) -> np.ndarray:
    values = {q.name: float(q.default) for q in model.parameters}
    for key, value in overrides.items():
        model.index("parameters", key)
        values[key] = float(value)
    p = np.array([values[q.name] for q in model.parameters])
    if not np.all(np.isfinite(p)):
        raise DomainError("parameters contain NaN or infinite values")
    return p


def _latitude_index(model: Model) -> int:
    for k, state in enumerate(model.states):
        if state.name in ("phi", "latitude"):
            return k
    raise UnknownNameError(f"model {model.name!r} has no latitude state")
