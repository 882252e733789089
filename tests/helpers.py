"""Random admissible points and consistent inputs for the physics tests."""

from __future__ import annotations

import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

import ins_errors

QUIET_DASK = {"DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED": "False",
              "DASK_DISTRIBUTED__ADMIN__TICK__INTERVAL": "1s",
              "DASK_DISTRIBUTED__ADMIN__SYSTEM_MONITOR__INTERVAL": "5s",
              "DASK_DISTRIBUTED__WORKER__MEMORY__MONITOR_INTERVAL": "2s",
              "DASK_DISTRIBUTED__WORKER__MULTIPROCESSING_METHOD": "forkserver"}
"""Dask settings of every cluster the suite starts (environment variables, read when Dask
is imported: tests/conftest.py sets them for this process and the processes it starts).
Dask's statistical profiler (every 10 ms in each worker and nanny) and its 20-ms /
500-ms / 100-ms health, system and memory monitors cost about 0.1 s CPU per second of an
idle cluster; none is what the tests look at (dashboards and diagnostics), and none
changes a result. Worker processes are forked from one fork server that imported Dask
once (Dask's own test suite does the same) instead of each starting a fresh interpreter
and importing Dask (~0.7 s CPU per worker; the cluster tests start three)."""


def static_inputs(model: ins_errors.Model, x: np.ndarray, p: np.ndarray, h: float = 0.0,
                  g: float = 9.81) -> np.ndarray:
    """Inputs that keep the ideal velocities constant at state x (V̇ = 0)."""
    u = model.input_vector(a_zeta=g, h=h)
    rates = model.numpy.ideal_rhs(x, u, p)
    u[0], u[1] = -rates[6], -rates[7]
    return u


def random_points(model: ins_errors.Model, count: int, seed: int, moving: bool):
    """Random admissible (x, u, p) triples, static base or moving."""
    rng = np.random.default_rng(seed)
    p = model.parameter_vector()
    points = []
    for _ in range(count):
        c = model.initial_condition_vector(
            latitude=np.radians(rng.uniform(-80, 80)),
            longitude=np.radians(rng.uniform(-180, 180)),
            heading=np.radians(rng.uniform(-180, 180)),
            v_N=rng.uniform(-300, 300) if moving else 0.0,
            v_E=rng.uniform(-300, 300) if moving else 0.0,
        )
        h = rng.uniform(0, 12000) if moving else rng.uniform(0, 500)
        u = model.input_vector(h=h)
        x = model.initial_state(c, u, p)
        if moving:
            u = model.input_vector(a_xi=rng.uniform(-5, 5), a_eta=rng.uniform(-5, 5),
                                   a_zeta=rng.uniform(7, 13), V_zeta=rng.uniform(-20, 20), h=h)
        else:
            u = static_inputs(model, x, p, h=h)
        points.append((x, u, p))
    return points


def central_difference(f, at: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """Jacobian of ``f`` at ``at`` by central differences, one step per component."""
    columns = []
    for j, step in enumerate(steps):
        delta = np.zeros_like(at)
        delta[j] = step
        columns.append((f(at + delta) - f(at - delta)) / (2 * step))
    return np.stack(columns, axis=1)


def complex_step_matrices(model: ins_errors.Model):
    """F and G of ``model`` by complex-step differentiation of its in-memory SymPy
    real-work equations (printed by ``sympy.lambdify``, intermediates substituted).

    ``Im f(v + i h e_j) / h`` is the derivative by ``v_j`` to rounding (no difference
    of nearby values is taken, unlike finite differences) when ``f`` is analytic in
    ``v`` near the point: true of the built-in models' equations (rational functions,
    sin, cos, tan, powers of positive quantities). Independent of the variation
    machinery and of the generated code.

    Returns
    -------
    callable
        ``(x, u, p) -> (F, G)``, shapes (ne, ne) and (ne, nw).
    """
    import sympy as sp

    d = model.symbolic
    real = sp.lambdify([d.real_states, d.x, d.u, d.w, d.p], list(d.real_rhs_expanded()),
                       "numpy")
    ne, nw, step = len(d.real_states), len(d.w), 1e-100

    def matrices(x, u, p):
        xr, w = np.r_[x, np.zeros(ne - len(x))], np.zeros(nw)

        def columns(values, count):  # row i: d f_i / d v_j for each column j
            return np.array([np.broadcast_to(v, (count,)) for v in values]).imag / step

        F = columns(real(xr[:, None] + 1j * step * np.eye(ne), x, u, w, p), ne)
        G = columns(real(xr, x, u, w[:, None] + 1j * step * np.eye(nw), p), nw)
        return F, G

    return matrices


def row_relative_error(approx: np.ndarray, exact: np.ndarray) -> float:
    """Largest row-wise error relative to the row's largest entry (zero rows must match)."""
    worst = 0.0
    for a_row, e_row in zip(approx, exact, strict=True):
        scale = np.abs(e_row).max()
        if scale == 0:
            assert np.abs(a_row).max() < 1e-12
            continue
        worst = max(worst, np.abs(a_row - e_row).max() / scale)
    return worst


def source_steps(model: ins_errors.Model) -> np.ndarray:
    """Finite-difference step per error source, by its SI unit."""
    scale = {"rad": 1e-6, "rad/s": 1e-9, "m/s**2": 1e-6, "m/s": 1e-3, "1": 1e-6}
    return np.array([scale[s.unit] for s in model.sources])


def joined_chunks(trajectory, size: int = 20_000):
    """A streamed trajectory's chunks of ``size`` steps joined: states, inputs, midpoints."""
    return _joined(list(trajectory.chunks(size)))


def _joined(chunks):
    """Consecutive chunks joined: states, inputs, midpoints."""
    truth = np.hstack([chunks[0].truth[:, :1]] + [c.truth[:, 1:] for c in chunks])
    inputs = np.hstack([chunks[0].inputs[:, :1]] + [c.inputs[:, 1:] for c in chunks])
    midpoints = np.hstack([c.midpoints for c in chunks])
    return truth, inputs, midpoints


def assert_chunks_join_into(streamed, stored, sizes) -> None:
    """A streamed trajectory's chunks, for every chunk size in ``sizes``, join into the
    stored trajectory of the same motion bit for bit: start, states, inputs, midpoints."""
    assert np.array_equal(streamed.start_state, stored.truth[:, 0])
    assert np.array_equal(streamed.start_inputs, stored.inputs[:, 0])
    for size in sizes:
        chunks = list(streamed.chunks(size))  # generated once, checked and joined
        assert chunks[0].start == 0 and sum(c.size for c in chunks) == stored.n_steps
        truth, inputs, midpoints = _joined(chunks)
        assert np.array_equal(truth, stored.truth)
        assert np.array_equal(inputs, stored.inputs)
        assert np.array_equal(midpoints, stored.midpoints)


def assert_pictures_alike(reduced, full, most: int = 20) -> None:
    """Two PNG files of the same figure differ in at most ``most`` pixels by more than 64
    grey levels (a quarter of the range), and are not the same file.

    Used to compare a figure drawn through the column envelope (``reduced``) with the
    same figure drawn from every sample (``full``): antialiased edges may differ by a
    few levels, a missing or moved stroke shows as dark pixels.
    """
    from PIL import Image

    with Image.open(reduced) as a, Image.open(full) as b:
        ours, every = (np.asarray(i.convert("L"), dtype=int) for i in (a, b))
    assert ours.shape == every.shape
    strokes = int((np.abs(ours - every) > 64).sum())
    assert strokes <= most, strokes
    assert reduced.read_bytes() != full.read_bytes()  # (the envelope is in use)


@contextmanager
def one_blas_thread_for_references() -> Iterator[None]:
    """A test's own reference computations (SciPy's expm of matrices of tens of rows) with
    BLAS on one thread, SciPy's bundled OpenBLAS included (imported first, so that the
    limit reaches it). On matrices this small BLAS threads only burn CPU waiting for
    each other: about 7 ms of CPU per 12 × 12 exponential on a loaded 2-core machine
    instead of about 0.1 ms. The product's own calls limit themselves
    (:mod:`ins_errors.numeric.blas_threads`); this is for the tests' references."""
    import scipy.linalg  # noqa: F401  (loads SciPy's OpenBLAS before the limit is set)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


def fresh_model_cache(tmp_path, monkeypatch):
    """Point the model files' code cache at a fresh folder below ``tmp_path`` and forget
    the models loaded so far (they remember their folder); returns the folder."""
    from ins_errors.numeric.model import _file_model

    cache = tmp_path / "cache"
    monkeypatch.setattr("ins_errors.model_lookup.models_cache_directory", lambda: cache)
    _file_model.cache_clear()
    return cache


SLOW_SWEEP = """model = "orthodromic"
[motion]
kind = "great-circle"
latitude = "50 deg"
longitude = "30 deg"
heading = "0 deg"
speed = "250 m/s"
[run]
duration = "4 h"
step = "2 s"
record = "60 s"
[[case]]
accel_bias_x = "100 ug"
[outputs]
quantities = ["delta_latitude"]
[sweep]
latitude = ["10 deg", "20 deg", "30 deg", "40 deg", "50 deg"]
heading = { start = "0 deg", stop = "90 deg", count = 4 }
"""
"""A sweep of 20 four-hour flights at a 2-s step: long enough to stop, signal or crash
while it runs (tests/test_engine.py, tests/test_ci_robustness.py)."""

FLIGHT_10_MIN = """
title = "flight"
model = "orthodromic"
[motion]
kind = "great-circle"
latitude = "50 deg"
longitude = "30 deg"
heading = "0 deg"
speed = "250 m/s"
[run]
duration = "10 min"
step = "5 s"
record = "60 s"
[[case]]
accel_bias_x = "100 ug"
"""
"""A 10-min great-circle flight at 250 m/s from 50° N, heading north, with one case: the
head of the sweep-store and failed-point scenarios, which add their outputs or sweep."""


def edited_model_file(source: Path, folder: Path, old: str, new: str, name: str) -> Path:
    """A copy of the model file ``source`` in ``folder`` with the text ``old`` (which must
    be there) replaced by ``new`` and the model renamed ``name`` (its file ``name.py``):
    a model with one slip, built at test time."""
    text = source.read_text(encoding="utf-8")
    assert old in text, old
    base = re.search(r'name="([^"]+)"', text).group(1)
    path = folder / f"{name}.py"
    path.write_text(text.replace(old, new).replace(f'name="{base}"', f'name="{name}"'),
                    encoding="utf-8")
    return path


COARSE_RECTANGLE = """title = "Coarse rectangle steps"
model = "north_pointing"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "2 h"
step = "60 s"
method = "euler"
[[case]]
accel_bias_east = "100 ug"
"""
"""The rectangle method at 60 s over 2 h: its integration error is a quarter of the
error, and the rectangle step that would do is below a millisecond (9 million steps): a
scenario whose run warns (tests/test_fail_on_warning.py,
tests/test_compare_brief_warnings.py)."""

