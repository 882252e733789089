r"""The linear error model of any model written in a convention, at given samples.

A filter designer needs the continuous error model ``ż = F(t) z + G(t) w`` in the states
of their filter (φ-angle, velocity error, position error, perhaps IMU biases) along a
motion of their own. :func:`error_matrices` gives it for a built-in model or a model
file, at the true states, inputs and parameters the model's generated functions take:

    F_c = (Ṫ + T F) T⁻¹,   G_c = T G,

with ``T(x)`` the change of error states from the model's own to the convention's
(``T⁻¹`` a lift onto the model's own state manifold, or the pseudo-inverse where the
model's error state has a direction the convention does not see), exactly as
``ins-errors check --matrix`` carries the derived model (docs/matrix_check.md,
'Conventions'). The conventions a model has: ``model`` (its own error states) for every
model; ``phi``, ``psi``, ``phi_modified``, ``psi_modified`` (position in NED metres or,
with the suffix ``_geodetic``, as latitude, longitude, height) and ``psi_ecef`` for
``strapdown_ned`` and every strapdown model file that describes itself; ``psi`` for
``north_pointing`` (``ins-errors check MODEL --list-conventions`` lists them with their
states). The discrete model a filter runs over each sample step, Φ_k and Q_k from the
sources' white-noise densities, is
:func:`ins_errors.analysis.discrete_model.discrete_matrices` of these F and G.

Example
-------
>>> import numpy as np
>>> from ins_errors import load_model
>>> from ins_errors.conventions import error_matrices
>>> model = load_model("strapdown_ned")
>>> p = model.parameter_vector()
>>> c = model.initial_condition_vector(latitude=np.radians(45))
>>> x = model.initial_state(c, model.input_vector(), p)
>>> u = model.input_vector(omega_x=7.292115e-5 * np.cos(np.radians(45)),
...                        omega_z=-7.292115e-5 * np.sin(np.radians(45)), f_z=-9.806)
>>> em = error_matrices(model, "phi", x[:, None], u[:, None], p)
>>> em.F.shape, em.G.shape, em.states[:3]
((1, 9, 9), (1, 9, 33), ('phi_N', 'phi_E', 'phi_D'))
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np

from ins_errors.errors import InsErrorsError, ShapeError, name_list, name_mapping
from ins_errors.numeric.nonfinite import WHY, nonfinite_entries


class SourceNames(tuple):
    """The names of a model's error sources, a tuple of str, that also holds which of
    them are initial errors (``initial``): those only set the error at the start, so no
    noise drives them (:func:`~ins_errors.analysis.discrete_model.process_noise` refuses
    one, as ``ins-errors matrices --noise`` does)."""

    initial: frozenset[str]

    def __new__(cls, names, initial=()) -> SourceNames:
        self = super().__new__(cls, names)
        self.initial = frozenset(initial)
        return self


class ErrorMatrices(NamedTuple):
    """The linear error model in a convention at K samples.

    Attributes
    ----------
    F : numpy.ndarray, shape (K, n, n)
        State matrix, 1/s (entry [k, i, j]: unit of state i per unit of state j per s).
    G : numpy.ndarray, shape (K, n, m)
        Source matrix: unit of state i per s per unit of source j.
    states : tuple of str
        The n states (rows and columns of F), in order.
    sources : tuple of str
        The m error sources (columns of G): every source of the model, in its order
        (a :class:`SourceNames`, which also says which are initial errors).
    """

    F: np.ndarray
    G: np.ndarray
    states: tuple[str, ...]
    sources: tuple[str, ...]


def error_matrices(model, convention: str, x, u, p, *, bias_states: Sequence[str] = (),
                   markov: Mapping[str, float] | None = None) -> ErrorMatrices:
    """F and G of ``model``'s linear error model in ``convention`` at the samples ``x``.

    Parameters
    ----------
    model : Model or str
        A loaded model, or a name or model file as :func:`ins_errors.load_model` takes.
    convention : str
        A convention of the model (``phi``, ``psi_geodetic``, ``model``, …;
        ``ins-errors check MODEL --list-conventions``).
    x : array_like, shape (n_x, K)
        True states of the model, one column per sample (its generated functions'
        layout; ``(n_x,)`` is one sample).
    u : array_like, shape (n_u, K) or (n_u,)
        Inputs at the samples (one column is used at every sample).
    p : array_like, shape (n_p,)
        Model parameters (``model.parameter_vector()``).
    bias_states : sequence of str, optional
        Error sources of kind ``constant`` carried as states after the convention's own
        (a 15-state filter's gyro and accelerometer biases), in the order given: a bias
        state's column of F is its source's column of G, its row is 0 (or −1/τ,
        ``markov``); its column of G is 0.
    markov : mapping of str to float, optional
        Correlation time τ (s, a positive number) of bias states that are first-order
        Gauss–Markov processes.

    Returns
    -------
    ErrorMatrices
        ``(F, G, states, sources)``; F (K, n, n), G (K, n, m).

    Raises
    ------
    InsErrorsError
        One line for an array of the wrong shape or with NaN, an unknown convention
        (a model with no navigation description has only ``model``), bias states that
        are no constant error sources, a correlation time that is no positive number of
        seconds (0, negative, NaN, infinite, text: :func:`correlation_times`), or samples
        the convention cannot carry.
    """
    from ins_errors.checker.check_motions import Motion
    from ins_errors.checker.derived_convention import derived_in_convention
    from ins_errors.numeric.model import load_model

    model = load_model(model)
    x, u, p = _samples(model, x, u, p)
    conv = model_convention(model, convention, bias_states, markov)
    k = x.shape[1]
    motion = Motion("samples", "given samples", np.arange(k, dtype=float), x, u, p, {})
    try:
        with np.errstate(all="ignore"):  # what is not finite is said below, by entry
            F, G = derived_in_convention(model, conv, motion)
    except np.linalg.LinAlgError as error:
        raise InsErrorsError(
            f"model {model.name!r}: the map to convention {convention!r} cannot be inverted "
            f"at these samples ({error}): are they true states of the model (a unit "
            "attitude, a latitude off the poles)?") from None
    bad = ~np.isfinite(F).all(axis=(1, 2)) | ~np.isfinite(G).all(axis=(1, 2))
    if bad.any():
        first = int(np.argmax(bad))
        sources = [s.name for s in model.sources]
        listed = " and ".join(text for text in (
            nonfinite_entries("F", F[first], conv.names, conv.names),
            nonfinite_entries("G", G[first], conv.names, sources)) if text)
        raise InsErrorsError(
            f"model {model.name!r}: F or G in convention {convention!r} is NaN or infinite "
            f"at sample {first} (of {k}) in {listed}: {WHY}, or the samples are no true "
            "states of the model")
    return ErrorMatrices(np.array(F), np.array(G), tuple(conv.names),
                         SourceNames((s.name for s in model.sources),
                                     (s.name for s in model.sources if s.kind == "initial")))


def model_convention(model, convention: str, bias_states: Sequence[str] = (),
                     markov: Mapping[str, float] | None = None):
    """The :class:`~ins_errors.checker.conventions.Convention` ``convention`` of
    ``model`` with ``bias_states`` (see :func:`error_matrices`).

    Raises
    ------
    InsErrorsError
        One line for a convention the model does not have (saying when it has only its
        own error states), a bias state that is no constant error source (a state of the
        convention, an initial error, an unknown name), one given twice, a correlation
        time of something that is no bias state, or one that is no positive number of
        seconds (:func:`correlation_times`). The bias states follow the convention's
        states in the order given.
    """
    from ins_errors.checker.conventions import conventions
    from ins_errors.checker.matrix import bias_states as make_bias_states
    from ins_errors.errors import unknown_name

    known = conventions(model)
    if convention not in known:
        if list(known) == ["model"]:
            raise InsErrorsError(
                f"model {model.name!r} has no convention but its own error states "
                f"('model'), so not {convention!r}: the φ/ψ conventions need a navigation "
                "description (docs/matrix_check.md, 'Which models')")
        raise unknown_name(f"convention of {model.name}", str(convention), known)
    conv = known[convention]
    bias_states = name_list(bias_states, "bias_states")  # one string: one bias state
    seen: set[str] = set()
    for name in bias_states:
        if name in seen:
            raise InsErrorsError(f"bias state {name!r} is given twice (--bias-states)")
        seen.add(name)
        if name in conv.names:
            sources = [s.name for s in model.sources if s.kind == "constant"]
            raise InsErrorsError(
                f"bias state {name!r} is a state of convention {convention!r} already: "
                "bias states are constant error sources of the model carried as further "
                f"states ({', '.join(sources[:3])}, …; 'ins-errors models {model.name}')")
    markov = correlation_times(markov)
    for name in markov:
        if name not in bias_states:
            raise InsErrorsError(
                f"a correlation time (--markov {name}=TAU) is given for {name!r}, which is "
                "not a bias state: name it in --bias-states too")
    if bias_states or markov:
        states = [*conv.names, *bias_states]
        made = make_bias_states(states, [], markov, conv, model,
                                "bias_states", "markov")
        # in the order given (a filter's layout), not the model's order of its sources
        conv = conv.with_biases(tuple(sorted(made, key=lambda b: bias_states.index(b.name))))
    return conv


def correlation_times(markov: Mapping[str, float] | None,
                      what: str = "markov") -> dict[str, float]:
    """``markov`` (bias state -> correlation time τ, s) as a dict, each τ checked by
    :func:`correlation_time`.

    Raises
    ------
    InsErrorsError
        One line for anything but a mapping of names to positive numbers of seconds.
    """
    markov = name_mapping(markov, what, "bias state -> correlation time (s)",
                          "{'gyro_bias_x': 300.0}")
    return {name: correlation_time(name, tau, f"{what}[{name!r}]")
            for name, tau in markov.items()}


def correlation_time(name: str, tau, where: str) -> float:
    """The correlation time τ (s) of the Gauss–Markov bias state ``name``, checked: the
    one check of the Python API (``markov=``) and of ``ins-errors matrices --markov``.

    Parameters
    ----------
    name : str
        The bias state.
    tau : float
        Its correlation time, s (a number: text with units is refused, naming
        :func:`ins_errors.units.parse_quantity`).
    where : str
        How the caller gave it (``markov['gyro_bias_z']``, ``--markov gyro_bias_z=0s``),
        the start of the message.

    Returns
    -------
    float
        τ, s: positive and finite, and so is 1/τ (the bias row's −1/τ of F).

    Raises
    ------
    InsErrorsError
        One line naming ``where``, the bias state and the value: 0 (white noise, which
        is no state), negative (a growing bias), NaN, infinite or too small for 1/τ.
    """
    from ins_errors.numeric.model import si_number

    if isinstance(tau, bool):
        raise InsErrorsError(f"{where}: the correlation time of bias state {name!r} must be "
                             f"a number of seconds, got {tau!r}")
    value = si_number(tau, where, "s")
    if value == 0:
        raise InsErrorsError(f"{where}: a correlation time of 0 s makes bias state {name!r} "
                             "white noise, which no state carries: leave it out of the bias "
                             "states and give its white noise as a density")
    if not (value > 0 and math.isfinite(value)):
        raise InsErrorsError(f"{where}: the correlation time of bias state {name!r} must be "
                             f"positive and finite, got {value:g} s"
                             + (": its row of F, -1/tau, would make the bias grow"
                                if value < 0 else ""))
    if not math.isfinite(1.0 / value):
        raise InsErrorsError(f"{where}: a correlation time of {value:g} s of bias state "
                             f"{name!r} is too short: -1/tau overflows")
    return value


def _samples(model, x, u, p) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``x`` (n_x, K), ``u`` (n_u, K) and ``p`` (n_p,) as float arrays, checked.

    Raises
    ------
    ShapeError
        Naming the array, the shape it has and the one it needs.
    InsErrorsError
        For NaN or infinite values, or an array that is no array of numbers.
    """
    nx, nu, npar = len(model.states), len(model.inputs), len(model.parameters)
    arrays = []
    for name, value in (("x", x), ("u", u), ("p", p)):
        try:
            arrays.append(np.asarray(value, dtype=float))
        except (TypeError, ValueError):
            raise InsErrorsError(f"{name} must be an array of numbers, got "
                                 f"{type(value).__name__}") from None
    x, u, p = arrays
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2 or x.shape[0] != nx or x.shape[1] == 0:
        raise ShapeError(f"x must have shape (n_x, K) = ({nx}, K), one column per sample of "
                         f"the {nx} states of {model.name}, got {x.shape}")
    k = x.shape[1]
    if u.ndim == 1 and u.shape[0] == nu:
        u = np.repeat(u[:, None], k, axis=1)
    if u.shape != (nu, k):
        raise ShapeError(f"u must have shape (n_u, K) = ({nu}, {k}) or ({nu},) for the {nu} "
                         f"inputs of {model.name}, got {u.shape}")
    if p.shape != (npar,):
        raise ShapeError(f"p must have shape ({npar},) for the {npar} parameters of "
                         f"{model.name} (model.parameter_vector()), got {p.shape}")
    for name, a in (("x", x), ("u", u), ("p", p)):
        if not np.isfinite(a).all():
            raise InsErrorsError(f"{name} contains NaN or infinite values")
    return np.ascontiguousarray(x), np.ascontiguousarray(u), p
