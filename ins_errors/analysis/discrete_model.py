r"""The discrete-time error model a Kalman filter runs: Φ_k and Q_k over each sample step.

A filter carries its error state from one sample to the next,
``x_{k+1} = Φ_k x_k + w_k`` with ``E[w_k w_kᵀ] = Q_k``. From the continuous model
``ẋ = F(t) x + G(t) w`` (:func:`ins_errors.conventions.error_matrices`), with ``w`` white
noise, ``E[w(t) w(s)ᵀ] = diag(q²) δ(t − s)`` (``q`` the 1σ noise densities a datasheet
quotes: an angle random walk in deg/√h, an accelerometer's noise in µg/√Hz, both the
source's unit times √s in SI), :func:`discrete_matrices` gives

    Φ_k = e^{F_k Δt_k},   Q_k = ∫₀^{Δt_k} e^{F_k s} G_k diag(q²) G_kᵀ e^{F_kᵀ s} ds,

by Van Loan's method (:func:`ins_errors.analysis.covariance.van_loan`) with F and G held
at the step's start. That is exact for a system constant over the step (a static base);
along a moving base the step must be short against the motion's time scales (the turns
and accelerations of a manoeuvre).

:func:`process_noise` builds the noise columns of a model written with bias states: the
white noise of an instrument whose bias is a state enters through the column its bias
has (the measured rate or force carries both additively), and a first-order Gauss–Markov
bias state ``ḃ = −b/τ + n`` of steady-state 1σ ``σ`` is driven by ``n`` of density
``σ √(2/τ)`` (PSD ``2σ²/τ``, as :mod:`ins_errors.analysis.covariance` models a Markov
source).

Example
-------
>>> import numpy as np
>>> from ins_errors.analysis.discrete_model import discrete_matrices
>>> F = np.zeros((2, 2, 2)); F[:, 0, 1] = 1.0           # a double integrator
>>> G = np.zeros((2, 2, 1)); G[:, 1, 0] = 1.0           # white acceleration noise
>>> dm = discrete_matrices(F, G, np.array([0.0, 2.0]), np.array([0.5]))
>>> dm.Phi[0].tolist(), dm.Qd[0].round(12).tolist()      # q² [[Δt³/3, Δt²/2], [Δt²/2, Δt]]
([[1.0, 2.0], [0.0, 1.0]], [[0.666666666667, 0.5], [0.5, 0.5]])
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from ins_errors.errors import InsErrorsError, ShapeError, name_mapping, unknown_name
from ins_errors.numeric.blas_threads import one_blas_thread

_CHUNK = 2048
"""Steps whose Van Loan exponentials are formed together (a few MB of arrays)."""


class DiscreteMatrices(NamedTuple):
    """The discrete-time error model over K − 1 sample steps.

    Attributes
    ----------
    Phi : numpy.ndarray, shape (K - 1, n, n)
        Transition from sample k to sample k + 1 (entry [k, i, j]: unit of state i per
        unit of state j).
    Qd : numpy.ndarray, shape (K - 1, n, n)
        Covariance of the noise added over step k (symmetric, positive semi-definite;
        entry [k, i, j] in the units of state i times those of state j).
    """

    Phi: np.ndarray
    Qd: np.ndarray


@one_blas_thread
def discrete_matrices(F, G, times, densities) -> DiscreteMatrices:
    r"""Transition Φ_k and process-noise covariance Q_k over each step between samples.

    The continuous model ``ẋ = F(t) x + G(t) w``, with ``w`` white noise of 1σ densities
    ``densities`` (two-sided power spectral density ``diag(densities²)``, independent
    columns), is discretised by Van Loan's method with F and G held at their values at
    the step's *start* (sample k for the step k → k + 1):

    .. math::

        Φ_k = e^{F_k Δt_k}, \qquad
        Q_k = \int_0^{Δt_k} e^{F_k s} G_k \,\mathrm{diag}(q^2)\, G_k^T e^{F_k^T s}\, ds.

    That is exact for a system constant over the step (a static base); for a moving
    base the step must be short against the motion's time scales (turns, accelerations,
    the change of the transport rate), which F follows only sample by sample. Each step
    is scaled down by a power of two until ``‖F Δt‖₁ ≤ 1`` and the result doubled back
    (``Q ← Φ Q Φᵀ + Q``, ``Φ ← Φ²``), so a fast state (a Gauss–Markov bias state with τ
    much shorter than the step) loses no accuracy to the ``e^{‖F‖Δt}`` growth of the
    Van Loan block.

    Parameters
    ----------
    F : array_like, shape (K, n, n)
        State matrix at the samples, 1/s (entry [k, i, j]: unit of state i per unit of
        state j per s).
    G : array_like, shape (K, n, m)
        Noise matrix at the samples: unit of state i per s per unit of noise j.
    times : array_like, shape (K,)
        Sample times, s, strictly increasing (any spacing); K ≥ 2.
    densities : array_like, shape (m,)
        1σ white-noise density of each column of ``G``, SI unit of that noise times √s
        (rad/s·√s = rad/√s for a gyro's angle random walk, m/s²·√s = m/s/√s for an
        accelerometer's velocity random walk); 0 for a column without white noise (a
        random-constant bias, or a bias carried as a state, whose column of G is zero).

    Returns
    -------
    DiscreteMatrices
        ``(Phi, Qd)``, each of shape (K − 1, n, n).

    Raises
    ------
    ShapeError
        For arrays of inconsistent shapes.
    InsErrorsError
        For NaN or infinite entries, times that do not increase, or a negative density.
    """
    F, G, t, q = _checked(F, G, times, densities)
    steps, n = t.size - 1, F.shape[-1]
    Phi = np.empty((steps, n, n))
    Qd = np.empty((steps, n, n))
    for k0 in range(0, steps, _CHUNK):
        k1 = min(steps, k0 + _CHUNK)
        Phi[k0:k1], Qd[k0:k1] = _steps(F[k0:k1], G[k0:k1] * q, np.diff(t[k0:k1 + 1]))
    return DiscreteMatrices(Phi, Qd)


def _steps(F: np.ndarray, Gq: np.ndarray, dt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Φ and Q of steps ``dt`` (s,) for F (s, n, n) and the noise columns scaled by their
    densities, Gq (s, n, m): Van Loan on ``dt / 2^d`` then ``d`` doublings."""
    from ins_errors.analysis.covariance import van_loan

    norm = float(np.max(np.abs(F).sum(axis=-2).max(axis=-1) * dt))
    doublings = max(0, math.ceil(math.log2(norm))) if norm > 1.0 else 0
    h = (dt / 2.0**doublings)[:, None, None]
    rate = Gq @ np.swapaxes(Gq, -1, -2)                    # G diag(q²) Gᵀ
    # van_loan of (F h, rate h) over a unit step: ∫₀^h e^{Fs} rate e^{Fᵀs} ds
    Phi, Qd = van_loan(F * h, rate * h, 1.0)
    for _ in range(doublings):
        Qd = Phi @ Qd @ np.swapaxes(Phi, -1, -2) + Qd
        Phi = Phi @ Phi
    return Phi, 0.5 * (Qd + np.swapaxes(Qd, -1, -2))


def _checked(F, G, times, densities
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The inputs of :func:`discrete_matrices` as float arrays, shapes and values checked."""
    arrays = []
    for name, value in (("F", F), ("G", G), ("times", times), ("densities", densities)):
        try:
            arrays.append(np.asarray(value, dtype=float))
        except (TypeError, ValueError):
            text = next((v for v in np.ravel(np.asarray(value, dtype=object))
                         if isinstance(v, str)), None)
            if text is not None:  # a density as on a datasheet: the API takes SI numbers
                unit = {"times": "'s'", "densities": "UNIT), UNIT the source's SI unit "
                        "times s**0.5 ('(rad/s)*s**0.5' for a gyro's angle random walk"
                        }.get(name, "UNIT")
                raise InsErrorsError(
                    f"{name} takes numbers in SI units, got {text!r:.40}; convert text with "
                    f"ins_errors.units.parse_quantity({text!r:.40}, {unit})") from None
            raise InsErrorsError(f"{name} must be an array of numbers, got "
                                 f"{type(value).__name__}") from None
    F, G, t, q = arrays
    if F.ndim != 3 or F.shape[1] != F.shape[2]:
        raise ShapeError(f"F must have shape (K, n, n), got {F.shape}")
    k, n = F.shape[0], F.shape[1]
    if G.ndim != 3 or G.shape[:2] != (k, n):
        raise ShapeError(f"G must have shape (K, n, m) = ({k}, {n}, m) like F, got {G.shape}")
    if t.shape != (k,):
        raise ShapeError(f"times must have shape (K,) = ({k},), one per sample, got {t.shape}")
    if k < 2:
        raise ShapeError(f"at least 2 samples are needed for a step, got {k}")
    if q.shape != (G.shape[2],):
        raise ShapeError(f"densities must have shape (m,) = ({G.shape[2]},), one per column "
                         f"of G, got {q.shape}")
    for name, a in (("F", F), ("G", G), ("times", t), ("densities", q)):
        if not np.isfinite(a).all():
            raise InsErrorsError(f"{name} contains NaN or infinite values")
    if not (np.diff(t) > 0).all():
        k_bad = int(np.argmax(~(np.diff(t) > 0)))
        raise InsErrorsError(f"times must increase strictly: sample {k_bad + 1} "
                             f"({t[k_bad + 1]:g} s) is not after sample {k_bad} "
                             f"({t[k_bad]:g} s)")
    if (q < 0).any():
        raise InsErrorsError(f"densities must be >= 0 (1σ densities), got "
                             f"{q[int(np.argmax(q < 0))]:g} in column {int(np.argmax(q < 0))}")
    return F, G, t, q


def process_noise(F, G, states, sources, white: Mapping[str, float] | None = None,
                  markov_sigma: Mapping[str, float] | None = None,
                  markov: Mapping[str, float] | None = None
                  ) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """Noise columns and densities of a model in a convention, bias states included.

    Parameters
    ----------
    F : array_like, shape (K, n, n)
        :attr:`ErrorMatrices.F <ins_errors.conventions.ErrorMatrices>`; a bias state's
        column holds its source's column of G above the bias rows.
    G : array_like, shape (K, n, m)
        :attr:`ErrorMatrices.G <ins_errors.conventions.ErrorMatrices>` over every source.
    states, sources : sequence of str
        The n states (bias states by their source's name) and the m sources
        (:attr:`ErrorMatrices.sources <ins_errors.conventions.ErrorMatrices>` also says
        which are initial errors, which no noise drives: those are refused).
    white : mapping of str to float, optional
        Source name -> 1σ white-noise density, SI unit of the source times √s. A source
        that is a bias state takes it too: that instrument's white noise enters through
        the column its bias has (its column of F above the bias rows).
    markov_sigma : mapping of str to float, optional
        Gauss–Markov bias state -> steady-state 1σ of the bias, SI unit of the source;
        its driving noise of density ``σ √(2/τ)`` enters the bias state's own row.
    markov : mapping of str to float, optional
        Correlation time τ (s) of each Gauss–Markov bias state (as
        :func:`~ins_errors.conventions.error_matrices` takes it).

    Returns
    -------
    Gw : numpy.ndarray, shape (K, n, r)
        One column per given noise (``white`` first, in its order, then
        ``markov_sigma``), state units per s per unit of noise.
    densities : numpy.ndarray, shape (r,)
        Their 1σ densities: unit of the noise times √s.
    names : tuple of str
        The noises: the source's name, or ``<name>:markov`` for a bias state's driving
        noise.

    Raises
    ------
    InsErrorsError
        One line for an unknown source, an initial error given a noise, a steady-state
        σ of a source that is no Gauss–Markov bias state, a negative or non-finite
        value, text where a number is expected (naming
        :func:`ins_errors.units.parse_quantity`), or a correlation time that is no
        positive number of seconds (:func:`ins_errors.conventions.correlation_time`).
    """
    from ins_errors.conventions import correlation_times

    F, G = np.asarray(F, dtype=float), np.asarray(G, dtype=float)
    initial = getattr(sources, "initial", frozenset())   # ErrorMatrices.sources says
    states, sources = list(states), list(sources)
    white = _named_values(white, "white", "a 1σ white-noise density",
                          "{'gyro_bias_x': 8.7e-07}")
    markov_sigma = _named_values(markov_sigma, "markov_sigma", "a steady-state 1σ",
                                 "{'gyro_bias_x': 4.8e-08}")
    markov = correlation_times(markov, "process_noise: markov")
    bias_rows = [i for i, s in enumerate(states) if s in sources]
    columns, densities, names = [], [], []
    for name, density in white.items():
        if name not in sources:
            raise unknown_name("error source", name, sources)
        if name in initial:
            raise InsErrorsError(f"process_noise: white[{name!r}]: {name!r} is an initial "
                                 "error (it sets the error at the start), which no noise "
                                 "drives")
        density = _non_negative(density, f"process_noise: white[{name!r}]",
                                "white-noise density",
                                f'f"({{model.source({name!r}).unit}})*s**0.5"')
        if name in states:           # a bias state: the column its bias has in F
            column = F[:, :, states.index(name)].copy()
            column[:, bias_rows] = 0.0
        else:
            column = G[:, :, sources.index(name)]
        columns.append(column)
        densities.append(float(density))
        names.append(name)
    for name, sigma in markov_sigma.items():
        if name not in markov or name not in states:
            raise InsErrorsError(f"{name!r} is no Gauss–Markov bias state (bias states with "
                                 f"a correlation time: {', '.join(markov) or 'none'}), so "
                                 "it has no steady-state σ driving a noise")
        sigma = _non_negative(sigma, f"process_noise: markov_sigma[{name!r}]",
                              "steady-state σ", f"model.source({name!r}).unit")
        column = np.zeros(F.shape[:2])
        column[:, states.index(name)] = 1.0
        columns.append(column)
        densities.append(float(sigma) * math.sqrt(2.0 / markov[name]))
        names.append(f"{name}:markov")
    Gw = np.stack(columns, axis=-1) if columns else np.zeros((*F.shape[:2], 0))
    return Gw, np.array(densities, dtype=float), tuple(names)


def _named_values(values: Mapping[str, float] | None, what: str, value: str,
                  example: str) -> dict[str, float]:
    """``values`` (source name -> ``value``) as a dict; one line for anything but a
    mapping (a name alone, a list)."""
    return name_mapping(values, f"process_noise: {what}", f"source name -> {value} (SI)",
                        example)


def _non_negative(value, where: str, what: str, unit: str) -> float:
    """``value`` as a float, a finite number >= 0: one line naming ``where`` otherwise,
    text with units refused naming ``parse_quantity`` (with ``unit``, the Python
    expression of its SI unit, as its second argument)."""
    if isinstance(value, str):
        raise InsErrorsError(f"{where} takes a number in SI units, got {value!r:.40}; convert "
                             f"text with ins_errors.units.parse_quantity({value!r:.40}, "
                             f"{unit})")
    if isinstance(value, bool) or np.ndim(value) != 0 or np.iscomplexobj(value):
        raise InsErrorsError(f"{where} must be one real number (a {what}, SI), got "
                             f"{value!r:.60}")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InsErrorsError(f"{where} must be a number (a {what}, SI), got "
                             f"{value!r:.60}") from None
    if not (math.isfinite(number) and number >= 0):
        raise InsErrorsError(f"{where}: a {what} must be a finite number >= 0, got "
                             f"{number!r}")
    return number


HOLD_TOLERANCE = 0.01
"""Relative hold error (:func:`hold_error`) above which ``ins-errors matrices --discrete``
warns that its step is too long for the motion."""

_ROUNDING = 1e-12
"""Least change of its states (in typical sizes, next to Φ's identity) that a step's
Φ error is measured against (:func:`hold_error`): a row of Φ that is the identity's
(a random-constant bias state) differs by rounding (1e-16 of an entry near 1) at most,
which is no error of the hold."""


class HoldError(NamedTuple):
    """How much holding F and G at a step's start changes Φ and Q (:func:`hold_error`).

    Attributes
    ----------
    sizes : numpy.ndarray, shape (K - 1,)
        Each step's largest relative difference (0: F constant over the step).
    size : float
        The largest of ``sizes``.
    step : int
        The step it is at (from sample ``step`` to ``step + 1``).
    matrix : str
        ``"Phi"`` or ``"Qd"``: where it is.
    rows, columns : tuple of int
        The states of its block (first, stop), indices into the states.
    twice : float or None
        The same estimate with every other sample (steps twice as long): how the error
        changes with the step, measured; None for fewer than 3 samples.
    """

    sizes: np.ndarray
    size: float
    step: int
    matrix: str
    rows: tuple[int, int]
    columns: tuple[int, int]
    twice: float | None = None


def state_blocks(units: list) -> list[tuple[int, int]]:
    """Runs of consecutive equal entries of ``units`` (the states' units, or their
    (unit, typical size) pairs: attitude, velocity, position, gyro biases, …) as
    (first, stop) index pairs."""
    blocks: list[tuple[int, int]] = []
    for i, unit in enumerate(units):
        if blocks and units[blocks[-1][0]] == unit:
            blocks[-1] = (blocks[-1][0], i + 1)
        else:
            blocks.append((i, i + 1))
    return blocks


def typical_sizes(units: list[str]) -> np.ndarray:
    """The fixed typical size (SI) of each state by its unit
    (:func:`~ins_errors.checker.typical.typical_magnitude`: 1e-4 rad, 0.1 m/s, 10 m, …;
    1 for a unit without one)."""
    from ins_errors.checker.typical import typical_magnitude

    scale = []
    for unit in units:
        try:
            scale.append(typical_magnitude(unit)[0])
        except InsErrorsError:
            scale.append(1.0)
    return np.array(scale)


@one_blas_thread
def hold_error(F, G, times, densities, held: DiscreteMatrices, units: list[str],
               sizes=None, twice_above: float | None = None) -> HoldError:
    r"""A first-order estimate of what holding F and G at the step's start costs.

    :func:`discrete_matrices` holds F and G at their values at each step's start. Over the
    same step, F and G averaged over its two ends, ``(F_k + F_{k+1})/2``, give the
    discrete model to one order of Δt more (the trapezoid: exact for F varying linearly
    within the step, to O(Δt³)); the difference of the two is the hold's error to first
    order. Each block of states of one unit and typical size (:func:`state_blocks`) is
    weighed by what it does:

    * Φ: in the states' typical sizes (``Φ_ij s_j / s_i``), the block's largest
      difference relative to the largest entry of its rows of ``Φ − I`` (over every
      column), what the step does to those states: a block of no consequence to them
      (the attitude's drift from a position error, a height's from a tilt) does not
      count, however large its own relative change, and a block whose entries pass
      through zero (a coupling whose sign changes in a turn) is not measured against
      itself;
    * Q: the block's largest difference relative to √(Q_ii Q_jj) of the largest
      variances of its rows' and columns' states (a correlation's scale: a cross term of
      no consequence does not count).

    The same estimate is also made with every other sample (steps twice as long,
    :attr:`HoldError.twice`), which shows how the error changes with the step; with
    ``twice_above``, only where the estimate at the step is above it (the twice-the-step
    estimate costs about a third of the whole, and only a step to suggest needs it).

    Parameters
    ----------
    F, G, times, densities
        As :func:`discrete_matrices` takes them.
    held : DiscreteMatrices
        :func:`discrete_matrices` of these.
    units : list of str
        SI unit of each state (for the blocks and, without ``sizes``, the typical sizes).
    sizes : array_like, shape (n,), optional
        Typical size of each state, its SI unit (default :func:`typical_sizes` of
        ``units``; a latitude or longitude error is better weighed as the position
        error it is, 10 m over the Earth's radius, than as an angle).
    twice_above : float, optional
        Make the estimate at twice the step only when the estimate at the step exceeds
        this relative size (e.g. :data:`HOLD_TOLERANCE`); default: always.

    Returns
    -------
    HoldError
    """
    F, G, t, q = _checked(F, G, times, densities)
    s = typical_sizes(units) if sizes is None else np.asarray(sizes, dtype=float)
    if s.shape != (F.shape[-1],) or not (np.isfinite(s).all() and (s > 0).all()):
        raise ShapeError(f"sizes must be {F.shape[-1]} positive numbers, one per state")
    blocks = state_blocks(list(zip(units, s.tolist(), strict=True)))
    found = _hold_sizes(F, G, t, q, held, s, blocks)
    sizes_k = np.max(np.stack([f[0] for f in found]), axis=0)
    worst = max(found, key=lambda f: float(f[0].max()))
    k = int(np.argmax(worst[0]))
    twice = None
    if t.size >= 3 and (twice_above is None or float(worst[0][k]) > twice_above):
        F2, G2, t2 = F[::2], G[::2], t[::2]
        coarse = _hold_sizes(F2, G2, t2, q, discrete_matrices(F2, G2, t2, q), s, blocks)
        twice = float(max(f[0].max() for f in coarse))
    return HoldError(sizes_k, float(worst[0][k]), k, worst[1], worst[2], worst[3], twice)


def _hold_sizes(F: np.ndarray, G: np.ndarray, t: np.ndarray, q: np.ndarray,
                held: DiscreteMatrices, s: np.ndarray, blocks: list[tuple[int, int]]
                ) -> list[tuple[np.ndarray, str, tuple[int, int], tuple[int, int]]]:
    """Per block of Φ and of Q, each step's relative difference between ``held`` and
    the trapezoid's discretisation (:func:`hold_error`), with where it is."""
    F_mid, G_mid = 0.5 * (F[:-1] + F[1:]), 0.5 * (G[:-1] + G[1:])
    # (the last sample's F and G are not used by a step: pad to K)
    mid = discrete_matrices(np.concatenate([F_mid, F_mid[-1:]]),
                            np.concatenate([G_mid, G_mid[-1:]]), t, q)
    found = [(np.zeros(t.size - 1), "Phi", blocks[0], blocks[0])]
    ratio = s[None, None, :] / s[None, :, None]
    A, B = held.Phi * ratio, mid.Phi * ratio
    eye = np.eye(F.shape[-1])
    for r in blocks:
        # what the step does to the block's states: their rows of Φ − I, typical sizes
        does = np.maximum(np.abs(A[:, r[0]:r[1]] - eye[r[0]:r[1]]).max(axis=(1, 2)),
                          np.abs(B[:, r[0]:r[1]] - eye[r[0]:r[1]]).max(axis=(1, 2)))
        for c in blocks:
            d = np.abs(A[:, r[0]:r[1], c[0]:c[1]] - B[:, r[0]:r[1], c[0]:c[1]]
                       ).max(axis=(1, 2))
            found.append((d / np.maximum(does, _ROUNDING), "Phi", r, c))
    variances = np.maximum(np.einsum("kii->ki", held.Qd), np.einsum("kii->ki", mid.Qd))
    dQ = np.abs(held.Qd - mid.Qd)
    for r in blocks:
        for c in blocks:
            scale_rc = np.sqrt(variances[:, r[0]:r[1]].max(axis=1)
                               * variances[:, c[0]:c[1]].max(axis=1))
            d = dQ[:, r[0]:r[1], c[0]:c[1]].max(axis=(1, 2))
            rel = np.where(scale_rc > 0, d / np.where(scale_rc > 0, scale_rc, 1.0), 0.0)
            found.append((rel, "Qd", r, c))
    return found


FALLING = (1.4, 3.0)
"""Range of the ratio of the hold error with steps twice as long to that at the step
(:func:`hold_error`, ``twice / size``) in which it is taken to fall steadily with the
step (an order between about 0.5 and 1.6), so that a shorter step is suggested from the
two (:func:`suggested_step`). Outside it the step is too long for the estimate to say
how the error falls: it barely changes (the error near its ceiling), or changes
erratically (steps as long as the motion's turns)."""


def suggested_step(step: float, size: float, twice: float | None,
                   tolerance: float = HOLD_TOLERANCE, *, run: float | None = None,
                   fastest: float | None = None) -> float | None:
    r"""A step (s) at which the hold error would be about ``tolerance`` or less, from its
    estimate at the step and at twice the step; None where none is needed or none follows.

    The hold's relative error grows in proportion to the step while it is small and
    more slowly as it approaches its ceiling, ``e(h) = a h / (1 + b h)``. Its two
    measured values, ``e(Δt) = size`` and ``e(2Δt) = twice``, fix ``a`` and ``b``
    (``b Δt = (2 − ρ) / (2(ρ − 1))`` for ``ρ = twice / size`` between 1 and 2; for ρ ≥ 2,
    an error falling at least in proportion, ``b = 0``); ``h = tolerance / a`` is then
    under the tolerance, rounded down to 1, 2 or 5 times a power of ten (or, where that
    does not divide ``run``, to the largest step of three significant digits that does).
    An error that does not fall steadily with the step (``ρ`` outside :data:`FALLING`)
    gives None: no step follows from it. So does a step longer than
    :data:`SAMPLES_PER_CHANGE` steps fit into the motion's ``fastest`` change: F is seen
    only at the steps' ends, so changes shorter than that fall between its samples (a
    manoeuvre's turns every 4 h are the same turn, and the estimate sees a steady F).

    Parameters
    ----------
    step : float
        The step, s.
    size, twice : float
        :attr:`HoldError.size` and :attr:`HoldError.twice` (None: not measured).
    tolerance : float
        The relative error wanted.
    run : float, optional
        The run's length, s: the step suggested divides it (one the command line takes).
    fastest : float, optional
        Duration of the motion's fastest change, s (its shortest leg or half-turn; None:
        a motion without such changes).

    Returns
    -------
    float or None
    """
    from ins_errors.numeric.accuracy import typable_step
    from ins_errors.numeric.integrators import whole_steps
    from ins_errors.units import nice_below

    if not size > tolerance or twice is None \
            or not FALLING[0] * size <= twice <= FALLING[1] * size \
            or (fastest is not None and step > fastest / SAMPLES_PER_CHANGE):
        return None
    rho = twice / size
    b_step = 0.0 if rho >= 2.0 else (2.0 - rho) / (2.0 * (rho - 1.0))
    slope = size * (1.0 + b_step) / step          # a: the error per second of step
    found = nice_below(tolerance / slope)
    if run is None or whole_steps(run, found) is not None:
        return found
    return typable_step(found, run)[0]


SAMPLES_PER_CHANGE = 2
"""Steps that must fit into a motion's fastest change (its shortest leg or half-turn)
for :func:`suggested_step` to trust the hold estimate's fall with the step: F is seen at
each step's two ends only, and as with any sampling a change needs two samples to be seen
(the strapdown manoeuvre's S-turns, half a turn 10 min, at a 4-h step put every sample
at the same point of a turn)."""
