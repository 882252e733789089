"""Monte Carlo checks of the covariance: sampled sources through linear or direct runs.

* :func:`linear_monte_carlo` integrates the linear error equations ``ẋ = F x + G b`` with
  classical RK4 (no matrix exponential, so it checks the Van Loan discretisation
  independently), for random constants, white noise (additive increments of variance
  q·h per substep) and Gauss-Markov noise (exact AR(1) update per substep, held over
  the substep), batched over runs;
* :func:`direct_monte_carlo` samples the random constants and runs the model's
  real-work and ideal-work equations side by side (direct modelling, compiled CasADi
  loops from :mod:`ins_errors.numeric.simulate`), in batches spread over worker
  processes, with a progress bar.

With N runs of a zero-mean Gaussian quantity of standard deviation σ, the sample RMS has
relative standard error ≈ 1/sqrt(2N) (e.g. 2.2 % for N = 1000); :func:`sampling_error`
returns it.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass

import numpy as np

from ins_errors.analysis.covariance import Functionals, LinearSystem, SourceStatistics
from ins_errors.errors import InsErrorsError


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


def _check_runs(runs: int) -> None:
    if isinstance(runs, bool) or not isinstance(runs, (int, np.integer)) or runs < 2:
        raise MonteCarloError(f"runs must be an integer >= 2, got {runs!r}")


def linear_monte_carlo(system: LinearSystem, sources: Sequence[SourceStatistics],
                       functionals: Functionals, runs: int, seed: int = 0,
                       substeps: int = 1) -> MonteCarloResult:
    """Sampled runs of the linear error equations (RK4), quantities at every grid time.

    Parameters
    ----------
    system : LinearSystem
        Error equations; F and G are interpolated linearly inside a step.
    sources : sequence of SourceStatistics
        Statistics with their actual magnitudes.
    functionals : Functionals
        Quantities to record, ``y = C_x x + C_b b``.
    runs : int
        Number of runs N.
    seed : int
        Random seed.
    substeps : int
        RK4 substeps per grid step.
    """
    _check_runs(runs)
    rng = np.random.default_rng(seed)
    names = system.source_names
    _n, _nw = system.E.shape
    K = len(system.times) - 1
    h = system.step / substeps
    w = sample_constants(sources, names, runs, rng)
    x = system.E @ w
    b = w.copy()                                   # current source values
    markov = [(names.index(s.name), s) for s in sources if s.kind == "markov"]
    white = [(names.index(s.name), s) for s in sources if s.kind == "white"]
    for j, s in markov:
        b[j] = rng.normal(0.0, s.sigma, runs)      # stationary start

    def matrices(k: float) -> tuple[np.ndarray, np.ndarray]:
        if system.time_invariant:
            return system.F, system.G
        lo = min(int(np.floor(k)), K - 1)
        f = k - lo
        return ((1 - f) * system.F[lo] + f * system.F[lo + 1],
                (1 - f) * system.G[lo] + f * system.G[lo + 1])

    def record(k: int) -> np.ndarray:
        C_x = functionals.C_x if functionals.C_x.ndim == 2 else functionals.C_x[k]
        C_b = functionals.C_b.copy()
        for j, _s in white:
            C_b[:, j] = 0.0
        return C_x @ x + C_b @ b

    out = np.empty((K + 1, len(functionals.names), runs))
    out[0] = record(0)
    for k in range(K):
        for sub in range(substeps):
            t0 = k + sub / substeps
            F0, G0 = matrices(t0)
            Fm, Gm = matrices(t0 + 0.5 / substeps)
            F1, G1 = matrices(t0 + 1.0 / substeps)
            drive = b.copy()
            for j, _ in white:
                drive[j] = 0.0
            k1 = F0 @ x + G0 @ drive
            k2 = Fm @ (x + 0.5 * h * k1) + Gm @ drive
            k3 = Fm @ (x + 0.5 * h * k2) + Gm @ drive
            k4 = F1 @ (x + h * k3) + G1 @ drive
            x = x + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
            for j, s in white:
                x = x + np.outer(Gm[:, j], rng.normal(0.0, s.sigma * np.sqrt(h), runs))
            for j, s in markov:
                decay = np.exp(-h / s.tau)
                b[j] = decay * b[j] + rng.normal(0.0, s.sigma * np.sqrt(1 - decay**2), runs)
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
        ``alpha_x, ...`` then ``delta_<output>``.
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
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.simulate import simulate

    model = load_model(model_name)
    run = simulate(model, trajectory, w, method=method, record_interval=record_interval,
                   parts=("real",))
    errors = run.direct_errors()
    return errors.times, errors.values, tuple(errors.names)


def direct_monte_carlo(model, trajectory, sources: Sequence[SourceStatistics], runs: int,
                       seed: int = 0, method: str = "euler",
                       record_interval: float | None = None, batch: int = 50,
                       workers: int | None = None, progress: bool = True) -> DirectErrors:
    """Direct runs (real − ideal work) with sampled random constants.

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
        Random seed (the samples do not depend on ``batch`` or ``workers``).
    method : {"euler", "rk4"}
        Scheme (``"euler"``: the manual's rectangle method).
    record_interval : float, optional
        s between recorded samples (default: 60 s or the run length if shorter).
    batch : int
        Runs per compiled batch.
    workers : int, optional
        Worker processes (default: the number of CPUs);
        1 runs in this process.
    progress : bool
        Show a progress bar over runs.
    """
    _check_runs(runs)
    noisy = [s.name for s in sources if s.kind != "constant"]
    if noisy:
        raise MonteCarloError(f"direct runs take random constants only; noise sources: "
                              f"{', '.join(noisy)}")
    if record_interval is None:
        record_interval = min(60.0, trajectory.duration)
    names = [i.name for i in model.sources]
    w = sample_constants(sources, names, runs, np.random.default_rng(seed))
    batches = [w[:, i:i + batch] for i in range(0, runs, batch)]
    workers = max(1, min(workers or os.cpu_count() or 1, len(batches)))
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=runs, unit="run", desc="direct Monte Carlo", leave=False)
    results: list = [None] * len(batches)
    try:
        # compile (or load from the cache) once here, then run
        first = _direct_batch(model.name, trajectory, batches[0], method, record_interval)
        results[0] = first
        if bar is not None:
            bar.update(batches[0].shape[1])
        if workers == 1 or len(batches) == 1:
            for i, wb in enumerate(batches[1:], start=1):
                results[i] = _direct_batch(model.name, trajectory, wb, method,
                                           record_interval)
                if bar is not None:
                    bar.update(wb.shape[1])
        else:
            import multiprocessing

            # fork: no re-import of the caller's __main__, compiled code shared
            methods = multiprocessing.get_all_start_methods()
            context = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
            with ProcessPoolExecutor(workers, mp_context=context) as pool:
                futures = {pool.submit(_direct_batch, model.name, trajectory, wb, method,
                                       record_interval): i
                           for i, wb in enumerate(batches[1:], start=1)}
                for future in as_completed(futures):
                    results[futures[future]] = future.result()
                    if bar is not None:
                        bar.update(batches[futures[future]].shape[1])
    finally:
        if bar is not None:
            bar.close()
    times, _, quantity_names = results[0]
    values = np.concatenate([r[1] for r in results], axis=-1)
    return DirectErrors(times, quantity_names, values, w)
