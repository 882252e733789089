"""Zero-copy compiled calls and batches split over threads give the same bits as before.

The previous code path called the compiled library through ``casadi.external`` with
CasADi matrices; the new one calls the same C entry point through ctypes on numpy
buffers. Both must return identical numbers, and a batch split into thread groups must
give every case exactly what the case gives when run alone.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from ins_errors.errors import ShapeError
from ins_errors.numeric import integrators as integ
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate

DEG = np.pi / 180.0


def _function() -> ca.Function:
    x, y = ca.SX.sym("x", 3), ca.SX.sym("y", 2, 4)
    out = ca.vertcat(ca.sin(x[0]) * y[0, :] + x[1] ** 2, ca.exp(-x[2]) * y[1, :] / 3.0)
    return ca.Function("native_probe", [x, y], [out, ca.sumsqr(y) * x])


def test_native_call_returns_the_bits_of_casadi_external(tmp_path, monkeypatch):
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    function = _function()
    library = integ.compile_library([function])
    if library is None:
        pytest.skip("no C compiler")
    native = integ.NativeFunction(library, function)
    external = ca.external("native_probe", str(library))
    rng = np.random.default_rng(3)
    x, y = rng.normal(size=3), rng.normal(size=(2, 4))
    # column-major matrices live in C-ordered arrays of the transposed shape
    out0, out1 = np.empty((4, 2)), np.empty((1, 3))
    native([x.copy(), np.ascontiguousarray(y.T)], [out0, out1])
    ref0, ref1 = (np.asarray(v) for v in external(x, y))
    assert np.array_equal(out0.T, ref0) and np.array_equal(out1.ravel(), ref1.ravel())
    virtual = integ.VirtualFunction(function)
    vm0, vm1 = np.empty((4, 2)), np.empty((1, 3))
    virtual([x.copy(), np.ascontiguousarray(y.T)], [vm0, vm1])
    np.testing.assert_allclose(vm0, out0, rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(vm1, out1, rtol=1e-15, atol=1e-15)


def test_native_call_refuses_a_buffer_of_the_wrong_shape():
    virtual = integ.VirtualFunction(_function())
    with pytest.raises(ShapeError, match="input 1 must be a contiguous float64 array of 2x4"):
        virtual([np.zeros(3), np.zeros((2, 4))[:, ::2]], [np.empty((4, 2)), np.empty(3)])


def _group_spy(monkeypatch) -> set[int]:
    """The groups of cases a loop runs (filled as simulations run): two groups mean the
    batch was split over two threads."""
    seen: set[int] = set()
    original = integ.CompiledLoop._advance_group

    def spy(self, *args):
        seen.add(args[-1])
        return original(self, *args)

    monkeypatch.setattr(integ.CompiledLoop, "_advance_group", spy)
    return seen


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_batch_split_over_threads_equals_one_serial_batch(orthodromic, method, monkeypatch):
    legs = [tr.Leg(60.0, 260.0, 45 * DEG, 1500.0)]
    traj = tr.trajectory(orthodromic, tr.manoeuvre_profile(30 * DEG, 0.0, 0.0, 200.0, legs),
                         120.0, 0.5)
    cases = [{"gyro_drift_x": 1e-6}, {"accel_bias_y": 1e-4}, {"initial_tilt_x": 1e-4},
             {"gyro_drift_z": -2e-6, "accel_bias_x": 3e-5}, {"initial_azimuth_error": 1e-3}]
    groups = _group_spy(monkeypatch)
    monkeypatch.setenv("INS_ERRORS_THREADS", "2")  # groups of 3 and 2 (padded to 3)
    threaded = simulate(orthodromic, traj, cases, method=method, record_interval=5.0)
    assert groups == {0, 1}
    groups.clear()
    monkeypatch.setenv("INS_ERRORS_THREADS", "1")
    serial = simulate(orthodromic, traj, cases, method=method, record_interval=5.0)
    assert groups == {0}
    for part in ("ideal", "real", "linear", "refined"):
        assert np.array_equal(getattr(threaded, part), getattr(serial, part)), part
    assert np.abs(serial.real[8:]).max() > 0  # the cases really differ from zero


def test_static_batch_threads_run_their_groups_through_the_whole_run(orthodromic,
                                                                    monkeypatch):
    """Constant inputs: each thread runs its group start to end without waiting for the
    other (several progress pieces, a tail shorter than a chunk); same bits as serial."""
    traj = tr.trajectory(orthodromic, tr.static_profile(50 * DEG, 30 * DEG, 20 * DEG),
                         3 * 3600.0, 1.0)
    cases = [{"gyro_drift_x": 1e-6}, {"accel_bias_y": 1e-4}, {"initial_tilt_x": 1e-4}]
    groups = _group_spy(monkeypatch)
    monkeypatch.setenv("INS_ERRORS_THREADS", "2")  # groups of 2 and 1 (padded to 2)
    threaded = simulate(orthodromic, traj, cases, record_interval=2.0, progress=True,
                        method="euler")
    assert groups == {0, 1}
    groups.clear()
    monkeypatch.setenv("INS_ERRORS_THREADS", "1")
    serial = simulate(orthodromic, traj, cases, record_interval=2.0, method="euler")
    assert groups == {0}
    for part in ("ideal", "real", "linear", "refined"):
        assert np.array_equal(getattr(threaded, part), getattr(serial, part)), part
    assert np.abs(serial.real[8:, -1]).min() > 0  # every case tilts the platform


@pytest.mark.parametrize("method", ["euler", "rk4"])
@pytest.mark.parametrize("moving", [False, True])
def test_compiled_loop_gives_the_bits_of_the_virtual_machine(orthodromic, method, moving,
                                                             monkeypatch):
    """The compiled loop (its own C driver around the CasADi step, no fused multiply-add)
    and CasADi's virtual machine (fold/mapaccum/map graphs) give the same bits: every
    part, batched cases, static (inputs baked in) and moving (streamed inputs)."""
    if moving:
        legs = [tr.Leg(30.0, 260.0, 45 * DEG, 1500.0)]
        profile = tr.manoeuvre_profile(30 * DEG, 0.0, 0.0, 200.0, legs)
        traj = tr.trajectory(orthodromic, profile, 60.0, 0.5)
    else:
        traj = tr.trajectory(orthodromic, tr.static_profile(50 * DEG, 30 * DEG, 20 * DEG),
                             20.0, 0.01)
    cases = [{"gyro_drift_x": 1e-6, "correction_gain_error_z": 1e-4},
             {"accel_bias_y": 1e-4, "accel_scale_error_x": 1e-3}, {"initial_tilt_x": 1e-3}]
    monkeypatch.setenv("INS_ERRORS_THREADS", "1")  # one group of three
    runs = [simulate(orthodromic, traj, cases, method=method, record_interval=1.0, jit=jit)
            for jit in (True, False)]
    for part in ("ideal", "real", "linear", "refined"):
        assert np.array_equal(getattr(runs[0], part), getattr(runs[1], part)), part
    assert np.abs(runs[0].real[8:, -1]).min() > 0


@pytest.mark.parametrize("method", ["euler", "rk4"])
@pytest.mark.parametrize("streamed", [False, True])
def test_compiled_margins_are_the_running_minimum_of_the_virtual_machine(method, streamed):
    """Margins (running minimum within a chunk) and states of a toy loop ż = −z + u w,
    margin 1 − z₀² − u₀/10, compiled and in the virtual machine, with a tail of single
    records after the chunks."""
    z, u, w, p = ca.SX.sym("z", 2), ca.SX.sym("u", 2), ca.SX.sym("w", 1), ca.SX.sym("p", 1)
    rhs = ca.Function("toy", [z, u, w, p], [ca.vertcat(-z[0] + u[0] * w[0], p[0] * z[0])])
    margin = ca.Function("toy_margin", [z, u, w, p], [1 - z[0] ** 2 - u[0] / 10])
    steps, every, tau = 70, 5, 0.05
    t = np.arange(steps + 1) * tau
    inputs = np.vstack([np.sin(3 * t), np.cos(t)])
    mid = np.vstack([np.sin(3 * (t[:-1] + tau / 2)), np.cos(t[:-1] + tau / 2)])
    z0, wv = np.array([[0.2, -0.5], [0.0, 1.0]]), np.array([[1.5, -2.0]])
    results = []
    for jit in (True, False):
        loop = integ.CompiledLoop(rhs, margin, method, every, tau, np.array([0.3]),
                                  None if streamed else np.array([0.4, 1.0]), chunk=4,
                                  batch=2, jit=jit, workers=1)
        stream = integ.input_stream(inputs, mid, method) if streamed else None
        results.append(loop.run(z0, wv, steps, stream))
    assert np.array_equal(results[0].states, results[1].states)
    assert np.array_equal(results[0].margins, results[1].margins)
    assert np.ptp(results[0].margins) > 0.1


def test_an_interrupted_threaded_batch_stops_every_group(monkeypatch):
    """Ctrl-C (or an error) in one group's thread ends the other threads at their next
    piece, instead of letting them run to the end of the run."""
    import time

    z, u, w, p = ca.SX.sym("z", 1), ca.SX.sym("u", 1), ca.SX.sym("w", 1), ca.SX.sym("p", 0)
    rhs = ca.Function("toy", [z, u, w, p], [-z + w])
    loop = integ.CompiledLoop(rhs, None, "euler", 1, 0.1, np.zeros(0), np.zeros(1),
                              chunk=4, batch=2, workers=2)
    calls = {0: 0, 1: 0}
    original = integ.CompiledLoop._advance_group

    def flaky(self, *args):
        g = args[-1]
        calls[g] += 1
        if g == 1:
            raise KeyboardInterrupt
        time.sleep(0.005)
        return original(self, *args)

    monkeypatch.setattr(integ.CompiledLoop, "_advance_group", flaky)
    with pytest.raises(KeyboardInterrupt):
        loop.run(np.zeros(1), np.array([[1.0, 2.0]]), 400 * 4)   # 100 pieces a group
    assert calls[1] == 1 and calls[0] < 20


def test_loop_source_reads_its_arguments_without_pointer_tests():
    """The driver passes every pointer, so the generated step loses CasADi's tests of
    them (one basic block: sin and cos of one angle become one sincos call); a CasADi
    whose code no longer matches the patterns would silently lose that."""
    x, u = ca.SX.sym("x", 3), ca.SX.sym("u", 2)
    step = ca.Function("probe_step", [x, u], [ca.vertcat(ca.sin(x[0]) * u[0],
                                                         ca.cos(x[0]) + x[1] * u[1])])
    source = integ.generated_source([step])
    assert "arg[0]? arg[0][" in source and "if (res[0]!=0) res[0][" in source
    stripped = integ._assume_arguments(source)
    assert "?" not in stripped.split("probe_step:")[1].split("}")[0]
    assert "!=0" not in stripped.split("probe_step:")[1].split("}")[0]


def test_thread_count_from_the_environment_is_checked(monkeypatch):
    monkeypatch.setenv("INS_ERRORS_THREADS", "two")
    with pytest.raises(integ.InsErrorsError, match="INS_ERRORS_THREADS must be a whole"):
        integ.worker_count()


def test_a_pool_worker_runs_its_batches_on_one_thread(monkeypatch):
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    monkeypatch.delenv("INS_ERRORS_THREADS", raising=False)
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("fork")) as pool:
        assert pool.submit(integ.worker_count).result() == 1


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_stream_rows_are_the_transposed_input_stream_to_the_bit(method):
    """The rows a compiled loop reads, built with one copy, hold exactly the numbers of
    the stacked stream transposed (and are C-contiguous, as ``advance`` requires)."""
    rng = np.random.default_rng(3)
    inputs, mid = rng.standard_normal((7, 41)), rng.standard_normal((7, 40))
    rows = integ.stream_rows(inputs, mid, method)
    assert rows.flags.c_contiguous and rows.dtype == np.float64
    assert np.array_equal(rows, integ.input_stream(inputs, mid, method).T)
    if method == "rk4":
        with pytest.raises(integ.StepError, match="midpoints"):
            integ.stream_rows(inputs, None, method)



def test_stream_rows_fill_a_given_buffer_and_refuse_a_wrong_one():
    inputs, mid = np.ones((2, 6)), np.zeros((2, 5))
    out = np.full((5, 6), np.nan)
    assert integ.stream_rows(inputs, mid, "rk4", out) is out
    assert np.array_equal(out, integ.input_stream(inputs, mid, "rk4").T)
    with pytest.raises(integ.StepError, match=r"shape \(5, 6\)"):
        integ.stream_rows(inputs, mid, "rk4", np.empty((5, 2)))


def test_a_cached_loop_is_found_by_its_description_and_only_by_it(tmp_path, monkeypatch):
    """A loop whose library is in the cache is not written again (its description, not
    its C source, names the library); any change to what the C is written from (the
    function, a baked-in constant or input, the step, the scheme, the
    writing code) names another library, whose results are the virtual machine's bits."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    if integ._compiler() is None:
        pytest.skip("no C compiler")
    z, u, w, p = ca.SX.sym("z", 2), ca.SX.sym("u", 2), ca.SX.sym("w", 1), ca.SX.sym("p", 1)

    def toy(c: float) -> ca.Function:
        return ca.Function("toy", [z, u, w, p], [ca.vertcat(-z[0] + u[0] * w[0],
                                                            p[0] * z[0] + c * z[1])])

    def run(jit=True, c=0.5, method="rk4", tau=0.05, p0=0.3, u0=0.4):
        loop = integ.CompiledLoop(toy(c), None, method, 5, tau, np.array([p0]),
                                  np.array([u0, 1.0]), chunk=4, batch=1, jit=jit)
        return loop.run(np.array([0.2, -0.5]), np.array([1.5]), 40).states

    first = run()
    assert len(list(tmp_path.glob("loop_*.so"))) == 1

    def no_writing(functions):
        raise AssertionError("the C source was written again")

    with monkeypatch.context() as patched:
        patched.setattr(integ, "generated_source", no_writing)
        assert np.array_equal(run(), first)
    changes = [{"c": 0.5 + 1e-12}, {"p0": 0.3 + 1e-12}, {"u0": 0.4 + 1e-12},
               {"tau": 0.04}, {"method": "euler"}]
    for k, change in enumerate(changes, start=2):
        states = run(**change)
        assert len(list(tmp_path.glob("loop_*.so"))) == k, change
        assert np.array_equal(states, run(jit=False, **change)), change
        assert not np.array_equal(states, first), change
    monkeypatch.setattr(integ, "_writer_version", lambda: "another version of the writer")
    assert np.array_equal(run(), first)
    assert len(list(tmp_path.glob("loop_*.so"))) == len(changes) + 2


def test_a_compile_stopped_by_ctrl_c_is_an_interrupt_not_a_missing_compiler(tmp_path,
                                                                          monkeypatch):
    """Ctrl-C reaches the compiler too: its death by SIGINT must stop the run, not switch
    to the virtual machine with a warning that the compiler does not work."""
    import signal
    import subprocess
    import warnings

    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    monkeypatch.setattr(integ, "_NOTICE_GIVEN", False)

    def interrupted(argv, **kwargs):
        raise subprocess.CalledProcessError(-signal.SIGINT, argv)

    monkeypatch.setattr(integ.subprocess, "run", interrupted)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning (the compiler notice) fails
        with pytest.raises(KeyboardInterrupt):
            integ.compile_library([_function()])
    assert not integ._NOTICE_GIVEN


def test_local_cluster_processes_start_deaf_to_ctrl_c():
    """Processes started inside the block never get SIGINT (it stays blocked in them:
    Ctrl-C then stops the sweep's own process only, which closes the cluster); a process
    started after it does; the handler is restored."""
    import signal
    import subprocess
    import sys

    from ins_errors.analysis import engine

    # the suite itself may run with SIGINT ignored (started in the background by a
    # script): take Python's own handler first, as an interactive command has it
    started_with = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        before = signal.getsignal(signal.SIGINT)
        probe = [sys.executable, "-c",
                 "import os, signal, time\n"
                 "try:\n"
                 "    os.kill(os.getpid(), signal.SIGINT)\n"
                 "    time.sleep(0.2)\n"
                 "    print('on')\n"
                 "except KeyboardInterrupt:\n"
                 "    print('stopped')\n"]
        with engine._workers_ignore_ctrl_c():
            inside = subprocess.run(probe, capture_output=True, text=True, check=True).stdout
        outside = subprocess.run(probe, capture_output=True, text=True, check=True).stdout
        assert (inside.strip(), outside.strip()) == ("on", "stopped")
        assert signal.getsignal(signal.SIGINT) is before
    finally:
        signal.signal(signal.SIGINT, started_with)
