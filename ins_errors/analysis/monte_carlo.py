"""Monte Carlo checks of the covariance: sampled sources through linear or direct runs.

* :func:`linear_monte_carlo` integrates the linear error equations ``ẋ = F x + G b`` with
  classical RK4 (no matrix exponential, so it checks the Van Loan discretisation
  independently), for random constants, white noise (additive increments of variance
  q·h per substep) and Gauss-Markov noise (exact AR(1) update per substep, held over
  the substep), batched over runs;
* :func:`direct_monte_carlo` samples the random constants and runs the model's
  real-work and ideal-work equations side by side (direct modelling, compiled CasADi
  loops from :mod:`ins_errors.numeric.simulate`), in tasks of a few draws each, run on
  Dask, a local process pool or this process (:mod:`ins_errors.analysis.engine`), every
  draw seeded on its own (:func:`draw_generator`).

With N runs of a zero-mean Gaussian quantity of standard deviation σ, the sample RMS has
relative standard error ≈ 1/sqrt(2N) (e.g. 2.2 % for N = 1000); :func:`sampling_error`
returns it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ins_errors.analysis.covariance import Functionals, LinearSystem, SourceStatistics
from ins_errors.errors import InsErrorsError
from ins_errors.numeric.blas_threads import one_blas_thread


class MonteCarloError(InsErrorsError):
    """A Monte Carlo request that cannot be run."""


def sampling_error(runs: int) -> float:
    """Relative standard error of a sample RMS of N zero-mean Gaussian values, 1/sqrt(2N)."""
    return 1.0 / np.sqrt(2.0 * runs)


@dataclass(frozen=True)
class MonteCarloResult:
    """Sample statistics of a batch of runs.

    Attributes
    ----------
    times : numpy.ndarray, shape (nt,)
        s.
    names : tuple of str
        Quantities.
    samples : numpy.ndarray, shape (nt, q, N)
        Every run's value of every quantity, SI.
    kind : str
        ``"linear"`` or ``"direct"``.
    """

    times: np.ndarray
    names: tuple[str, ...]
    samples: np.ndarray
    kind: str

    @property
    def runs(self) -> int:
        return self.samples.shape[-1]

    @property
    def rms(self) -> np.ndarray:
        """Sample RMS about zero, shape (nt, q) (the quantities have zero mean)."""
        return np.sqrt(np.mean(self.samples**2, axis=-1))

    @property
    def relative_sampling_error(self) -> float:
        return sampling_error(self.runs)


def sample_constants(sources: Sequence[SourceStatistics], source_names: Sequence[str],
                     runs: int, rng: np.random.Generator) -> np.ndarray:
    """Gaussian draws of the random constants, zero elsewhere, shape (nw, runs), SI."""
    w = np.zeros((len(source_names), runs))
    for s in sources:
        if s.kind == "constant":
            w[list(source_names).index(s.name)] = rng.normal(0.0, s.sigma, runs)
    return w


def refuse_noise_sources(kinds: Sequence[tuple[str, str]], option: str | None = None) -> None:
    """Refuse noise sources for direct runs, whose real-work equations take constants.

    Parameters
    ----------
    kinds : sequence of (str, str)
        Each source's name and kind (``"constant"``, ``"white"`` or ``"markov"``).
    option : str, optional
        The option that asked for the runs, put in front of the message.

    Raises
    ------
    MonteCarloError
        One line naming every noise source.
    """
    noisy = [name for name, kind in kinds if kind != "constant"]
    if noisy:
        lead = f"{option}: " if option else ""
        raise MonteCarloError(f"{lead}direct runs take random constants only; noise "
                              f"sources: {', '.join(noisy)} (kind 'white' or 'markov')")


def _check_runs(runs: int) -> None:
    if isinstance(runs, bool) or not isinstance(runs, (int, np.integer)) or runs < 2:
        raise MonteCarloError(f"runs must be an integer >= 2, got {runs!r}")


@one_blas_thread
def linear_monte_carlo(system: LinearSystem, sources: Sequence[SourceStatistics],
                       functionals: Functionals, runs: int, seed: int = 0,
                       substeps: int = 1) -> MonteCarloResult:
    """Sampled runs of the linear error equations (RK4), quantities at every grid time.

    Parameters
    ----------
    system : LinearSystem
        Error equations; F and G are interpolated linearly inside a step.
    sources : sequence of SourceStatistics
        Statistics with their actual magnitudes. A source may be listed once per kind
        (a constant plus a white or Markov part): the parts are drawn independently and
        add on the source's column.
    functionals : Functionals
        Quantities to record, ``y = C_x x + C_b b``.
    runs : int
        Number of runs N.
    seed : int
        Random seed.
    substeps : int
        RK4 substeps per grid step.

    Notes
    -----
    White noise is a Gaussian value held over each substep with variance σ²/h (h the
    substep), passed through the RK4 stages with the other sources; the variance's
    error falls as (h/t)² (a doubly integrated noise after one substep: 3/4 of the exact
    variance; after six, 99 %).

    BLAS runs single-threaded here, as in :func:`~ins_errors.analysis.covariance.propagate`:
    the products are of an n × n matrix (tens of rows) with the n × N states, where BLAS
    threads cost more CPU than they save (3000 runs of the static 11-state model: about
    0.6 s CPU with one thread, 1.6 s with two, same numbers).
    """
    return _linear_monte_carlo(system, sources, functionals, runs, seed, substeps)


def _linear_monte_carlo(system: LinearSystem, sources: Sequence[SourceStatistics],
                        functionals: Functionals, runs: int, seed: int,
                        substeps: int) -> MonteCarloResult:
    _check_runs(runs)
    rng = np.random.default_rng(seed)
    names = system.source_names
    _n, _nw = system.E.shape
    K = len(system.times) - 1
    h = system.step / substeps
    w = sample_constants(sources, names, runs, rng)
    x = system.E @ w
    # A source may have several parts (a constant, a Markov process, white noise): each
    # part is its own draw on the source's column, so none overwrites another.
    markov = [(names.index(s.name), s, rng.normal(0.0, s.sigma, runs))  # stationary start
              for s in sources if s.kind == "markov"]
    white = [(names.index(s.name), s) for s in sources if s.kind == "white"]

    def source_values() -> np.ndarray:
        """The constant and Markov parts of every source now, (nw, runs)."""
        b = w.copy()
        for j, _s, value in markov:
            b[j] = b[j] + value
        return b

    def matrices(k: float) -> tuple[np.ndarray, np.ndarray]:
        if system.time_invariant:
            return system.F, system.G
        lo = min(int(np.floor(k)), K - 1)
        f = k - lo
        return ((1 - f) * system.F[lo] + f * system.F[lo + 1],
                (1 - f) * system.G[lo] + f * system.G[lo + 1])

    def record(k: int) -> np.ndarray:
        C_x = functionals.C_x if functionals.C_x.ndim == 2 else functionals.C_x[k]
        return C_x @ x + functionals.C_b @ source_values()

    out = np.empty((K + 1, len(functionals.names), runs))
    out[0] = record(0)
    for k in range(K):
        for sub in range(substeps):
            t0 = k + sub / substeps
            F0, G0 = matrices(t0)
            Fm, Gm = matrices(t0 + 0.5 / substeps)
            F1, G1 = matrices(t0 + 1.0 / substeps)
            drive = source_values()
            # white noise as a value held over the substep (variance σ²/h, so its integral
            # over the substep has σ² h): through the RK4 stages it integrates as the
            # midpoint rule does, where a kick at the substep's end would lose a quarter
            # of the variance of a doubly integrated noise over the first substeps
            for j, s in white:
                drive[j] = drive[j] + rng.normal(0.0, s.sigma / np.sqrt(h), runs)
            # each distinct G times the sources once (one G for a time-invariant system)
            forcing0 = G0 @ drive
            forcing_m = forcing0 if Gm is G0 else Gm @ drive
            forcing1 = forcing0 if G1 is G0 else G1 @ drive
            k1 = F0 @ x + forcing0
            k2 = Fm @ (x + 0.5 * h * k1) + forcing_m
            k3 = Fm @ (x + 0.5 * h * k2) + forcing_m
            k4 = F1 @ (x + h * k3) + forcing1
            x = x + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
            for index, (j, s, value) in enumerate(markov):
                decay = np.exp(-h / s.tau)
                markov[index] = (j, s, decay * value
                                 + rng.normal(0.0, s.sigma * np.sqrt(1 - decay**2), runs))
        out[k + 1] = record(k + 1)
    return MonteCarloResult(system.times, functionals.names, out, "linear")


# --------------------------------------------------------------------------------------
# Direct runs
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class DirectErrors:
    """Error quantities of direct runs (real − ideal), as ``simulate`` reports them.

    Attributes
    ----------
    times : numpy.ndarray, shape (nt,)
    names : tuple of str
        ``alpha_x, ...`` then ``delta_<output>``; for a strapdown INS then its φ-angle
        ``phi_N, phi_E, phi_D`` (:data:`ins_errors.analysis.budget_attitude.PHI_QUANTITIES`).
    values : numpy.ndarray, shape (nq, nt, N)
    sources : numpy.ndarray, shape (nw, N)
        The sampled source vectors.
    """

    times: np.ndarray
    names: tuple[str, ...]
    values: np.ndarray
    sources: np.ndarray

    def __getitem__(self, name: str) -> np.ndarray:
        from ins_errors.errors import unknown_name

        if name not in self.names:
            raise unknown_name("error quantity", name, self.names)
        return self.values[self.names.index(name)]


def _direct_batch(model_name: str, trajectory, w: np.ndarray, method: str,
                  record_interval: float) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """Direct runs of the draws ``w`` (nw, B): times, values (nq, R + 1, B) and names of
    the error quantities; for a strapdown INS its φ-angle besides
    (:func:`ins_errors.analysis.budget_attitude.direct_attitude`, the covariance's rows along the
    runs' own ideal states)."""
    from ins_errors.analysis.budget_attitude import direct_attitude
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.simulate import simulate

    model = load_model(model_name)
    run = simulate(model, trajectory, w, method=method, record_interval=record_interval,
                   parts=("real",))
    errors = run.direct_errors()
    names, values = direct_attitude(model, run.ideal, run.real, trajectory.parameters)
    if not names:
        return errors.times, errors.values, tuple(errors.names)
    return (errors.times, np.concatenate([errors.values, values]),
            (*errors.names, *names))


def draw_generator(seed: int, draw: int) -> np.random.Generator:
    """The random generator of draw number ``draw`` of a run seeded with ``seed``.

    Every draw has its own stream (``SeedSequence(seed, spawn_key=(draw,))``), so a draw's
    values do not depend on how draws are grouped into tasks or on which worker runs them.
    """
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(draw,)))


def sample_draws(sources: Sequence[SourceStatistics], source_names: Sequence[str],
                 seed: int, draws: range | Sequence[int]) -> np.ndarray:
    """Gaussian random constants of the given draws, zero elsewhere, shape (nw, len(draws)).

    Draw ``k`` takes one normal value per random constant, in the order of ``sources``,
    from :func:`draw_generator` ``(seed, k)``.
    """
    draws = list(draws)
    w = np.zeros((len(source_names), len(draws)))
    rows = [(list(source_names).index(s.name), s.sigma) for s in sources
            if s.kind == "constant"]
    for column, draw in enumerate(draws):
        rng = draw_generator(seed, draw)
        for row, sigma in rows:
            w[row, column] = rng.normal(0.0, sigma)
    return w


def _direct_block(model_name: str, trajectory, sources: tuple, seed: int, start: int,
                  stop: int, method: str, record_interval: float
                  ) -> tuple[np.ndarray, np.ndarray, tuple[str, ...], np.ndarray]:
    """One task: draws ``start..stop-1`` sampled and run directly.

    Raises
    ------
    MonteCarloError
        A draw whose run fails (e.g. leaves the model's domain): its number, seed and
        reason, found by running the block's draws one by one once the block failed.
        The statistics are never computed without it.
    """
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric.model import load_model

    names = [i.name for i in load_model(model_name).sources]
    w = sample_draws(sources, names, seed, range(start, stop))
    try:
        times, values, quantities = _direct_batch(model_name, trajectory, w, method,
                                                  record_interval)
    except InsErrorsError as error:
        reason, which = error, f"one of the draws {start}..{stop - 1}"
        for j in range(stop - start) if stop - start > 1 else ():
            try:
                _direct_batch(model_name, trajectory, w[:, j:j + 1], method,
                              record_interval)
            except InsErrorsError as alone:
                reason, which = alone, f"draw {start + j}"
                break
        if stop - start == 1:
            which = f"draw {start}"
        raise MonteCarloError(f"Monte Carlo {which} (seed {seed}) failed: {reason}"
                              ) from None
    return times, values, quantities, w


def direct_monte_carlo(model, trajectory, sources: Sequence[SourceStatistics], runs: int,
                       seed: int = 0, method: str = "euler",
                       record_interval: float | None = None, batch: int = 50,
                       workers: int | None = None, progress: bool = True,
                       engine: str = "auto", scheduler: str | None = None) -> DirectErrors:
    """Direct runs (real − ideal work) with sampled random constants.

    The runs are split into tasks of ``batch`` draws, run by
    :func:`ins_errors.analysis.engine.run_tasks` (a Dask cluster, a local process pool or
    this process). Draw ``k`` is sampled from its own generator
    (:func:`draw_generator`), so the samples depend on ``seed`` only; with the same
    ``batch`` the results are bit-identical on every engine.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    trajectory : Trajectory
        True motion and step (e.g. 0.01 s for 100 Hz).
    sources : sequence of SourceStatistics
        Random constants with their 1σ (noise sources cannot be run directly: the
        real-work equations take constant sources).
    runs : int
        Number of runs.
    seed : int
        Random seed.
    method : {"euler", "rk4"}
        Scheme (``"euler"``: the manual's rectangle method).
    record_interval : float, optional
        s between recorded samples (default: 60 s or the run length if shorter).
    batch : int
        Runs per task (one compiled batch).
    workers : int, optional
        Workers of a local cluster or pool (default: the number of CPUs); 1 runs in this
        process.
    progress : bool
        Show a progress bar over tasks.
    engine : {"auto", "dask", "pool", "serial"}
        Where the tasks run (see :mod:`ins_errors.analysis.engine`).
    scheduler : str, optional
        Address of a running Dask scheduler (default: a local cluster).
    """
    from ins_errors.analysis.engine import run_tasks

    _check_runs(runs)
    refuse_noise_sources([(s.name, s.kind) for s in sources])
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise MonteCarloError(f"seed must be a whole number >= 0, got {seed!r}")
    if isinstance(batch, bool) or not isinstance(batch, (int, np.integer)) or batch < 1:
        raise MonteCarloError(f"batch must be a positive integer, got {batch!r}")
    if record_interval is None:
        record_interval = min(60.0, trajectory.duration)
    statistics = tuple(sources)
    blocks = [(k, min(k + batch, runs)) for k in range(0, runs, batch)]
    # the first block here: compiles (or loads) the loop once and checks the request
    results: list = [None] * len(blocks)
    results[0] = _direct_block(model.key, trajectory, statistics, seed, *blocks[0], method,
                               record_interval)
    rest = [(*block, method, record_interval) for block in blocks[1:]]
    if workers == 1 and scheduler is None and engine == "auto":
        engine = "serial"

    def keep(k: int, result) -> None:
        results[k + 1] = result

    if rest:
        run_tasks(_direct_block, rest, engine=engine, scheduler=scheduler, workers=workers,
                  shared=(model.key, trajectory, statistics, seed), on_result=keep,
                  progress=progress, label="direct Monte Carlo")
    times, _, quantity_names, _ = results[0]
    values = np.concatenate([r[1] for r in results], axis=-1)
    w = np.concatenate([r[3] for r in results], axis=-1)
    return DirectErrors(times, quantity_names, values, w)
