"""Compiled loops that read their numbers at run time (``runtime_constants``).

A baked loop writes the numbers CasADi folded from the model parameters ``p`` and a
time-invariant motion's inputs ``u`` into its C code, so each latitude, heading or
parameter value of a sweep compiled loops of its own (seconds each). A loop with
``runtime_constants`` is the same graph, copied operation for operation with those numbers
read from an array (:func:`ins_errors.numeric.integrators.lift_constants`): one library
per structure. Its numbers must be the baked loop's to the last bit, checked here for
every generated model at rest and moving, RK4 and Euler, with the direct, linear and
refined runs; the virtual machine is unaffected; and a sweep's store must not change.

(Writing ``p`` and ``u`` as symbols instead would not do: CasADi folds a baked graph
with rewrites that are not exact, ``a*(b*x) -> (a*b)*x`` for numbers ``a``, ``b``, and
with its zeros, ``x + 0 -> x``: such loops differed in the last bits, e.g. the orthodromic
model's V_xi by 1.4e-14 m/s within 300 Euler steps.)
"""

from __future__ import annotations

import numpy as np
import pytest

import ins_errors
from ins_errors.numeric import integrators as integ
from ins_errors.numeric import simulate as sim_module
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.motion_spec import motion_profile
from ins_errors.numeric.simulate import runtime_constant_loops, simulate

DEG = np.pi / 180.0
MODELS = ("orthodromic", "north_pointing", "free_azimuth", "geodetic_vertical",
          "strapdown_ned")
def _scenario(folder, text: str):
    from ins_errors.scenario import load_scenario

    path = folder / "sweep.toml"
    path.write_text(text)
    return load_scenario(path)


def test_the_generated_models_are_all_checked():
    assert set(MODELS) == set(ins_errors.available_models())


def _bits(values: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=float).view(np.int64)


def _turn_file(folder) -> str:
    """A motion file of a 300-s turn at 100 m/s (north and east velocities), for the
    models that cannot fly a great circle."""
    t = np.arange(0.0, 401.0, 10.0)
    rows = "".join(f"{s:g},{100 * np.cos(s / 200):.17g},{100 * np.sin(s / 200):.17g}\n"
                   for s in t)
    (folder / "turn.csv").write_text("t,v_N,v_E\n" + rows)
    return "turn.csv"


def _trajectory(model, motion: str, folder) -> tr.Trajectory:
    if motion == "static":
        profile = tr.static_profile(50 * DEG, 30 * DEG, 20 * DEG)
    elif any(o.name == "heading" for o in model.outputs):
        profile = tr.great_circle_profile(50 * DEG, 30 * DEG, 40 * DEG, 250.0)
    else:
        profile = motion_profile({"kind": "file", "file": _turn_file(folder),
                                  "latitude": "50 deg"}, base=folder)
    return tr.trajectory(model, profile, 300.0, 1.0)


def _sources(model) -> list[dict[str, float]]:
    """Three cases (a batch split over threads), each with a drift-like and a
    bias-like source."""
    names = [s.name for s in model.sources]
    return [{names[-1]: 1e-6, names[len(names) // 2]: 1e-4}, {names[0]: 2e-4},
            {names[-2]: -3e-6}]


@pytest.mark.parametrize("motion", ["static", "moving"])
@pytest.mark.parametrize("name", MODELS)
def test_run_time_constants_give_the_baked_loops_bits(name, motion, tmp_path):
    model = ins_errors.load_model(name)
    traj = _trajectory(model, motion, tmp_path)
    assert traj.constant == (motion == "static" and name != "free_azimuth")
    cases = _sources(model)
    for method in ("rk4", "euler"):
        baked = simulate(model, traj, cases, method=method)
        with runtime_constant_loops():
            carried = simulate(model, traj, cases, method=method)
        for part in ("ideal", "real", "linear", "refined"):
            a, b = getattr(baked, part), getattr(carried, part)
            assert a.shape == b.shape == (a.shape[0], 301, 3)
            assert np.array_equal(_bits(a), _bits(b)), (method, part)
        assert np.abs(baked.direct_errors().values[:, -1]).max() > 0   # the errors moved
        for curves in ("direct_errors", "linear_errors", "refined_errors"):
            a, b = getattr(baked, curves)(), getattr(carried, curves)()
            assert np.array_equal(_bits(a.values), _bits(b.values)), (method, curves)


def test_one_compiled_loop_serves_every_latitude_and_parameter(orthodromic, monkeypatch):
    """Three static latitudes and two Earth radii: the baked loops compile one library
    per combination, the run-time loops one per structure, which these share, and per
    set of states held at rest (:meth:`CompiledLoop._frozen`: the ideal work, when one
    step returns it to the last bit, which some of these starts do and some do not)."""
    keys: list[str | None] = []
    held: list[tuple[int, ...]] = []
    compile_source, frozen = integ.compile_source, integ.CompiledLoop._frozen

    def spy(source, flags=integ.DEFAULT_FLAGS, key=None):
        keys.append(key)
        return compile_source(source, flags, key)

    def at_rest(self, carry):
        found = frozen(self, carry)
        held.append(tuple(i for i, _ in found))
        return found

    monkeypatch.setattr(integ, "compile_source", spy)
    monkeypatch.setattr(integ.CompiledLoop, "_frozen", at_rest)
    runs = [(latitude, radius) for latitude in (20, 45, 70) for radius in (6378245.0, 6.4e6)]
    found = {}
    for runtime in (False, True):
        keys.clear()
        held.clear()
        sim_module._loop.cache_clear()
        results = []
        for latitude, radius in runs:
            traj = tr.trajectory(orthodromic, tr.static_profile(latitude * DEG, 0.0, 0.0),
                                 60.0, 1.0, p=orthodromic.parameter_vector(a=radius))
            with runtime_constant_loops(runtime):
                results.append(simulate(orthodromic, traj, {"gyro_drift_x": 1e-6},
                                        parts=("real",)).real)
        found[runtime] = set(keys), results, set(held)
    assert len(found[False][0]) == len(runs)
    assert len(found[True][0]) == len(found[True][2]) < len(runs)
    assert any(found[True][2])   # a start held at rest: its work done once per call
    for a, b in zip(found[False][1], found[True][1], strict=True):
        assert np.array_equal(_bits(a), _bits(b))
    # the runs differ: the shared libraries computed six different runs
    assert len({r[:, -1, 0].tobytes() for r in found[True][1]}) == len(runs)


@pytest.mark.parametrize("how", ["jit=False", "INS_ERRORS_NO_JIT"])
def test_the_virtual_machine_takes_run_time_constants_too(orthodromic, how, monkeypatch):
    traj = tr.trajectory(orthodromic, tr.static_profile(35 * DEG, 0.0, 10 * DEG), 60.0, 1.0)
    cases = [{"gyro_drift_x": 1e-6}, {"accel_bias_y": 1e-4}]
    with runtime_constant_loops():
        compiled = simulate(orthodromic, traj, cases, method="rk4")
    jit = True
    if how == "jit=False":
        jit = False
    else:
        monkeypatch.setenv("INS_ERRORS_NO_JIT", "1")
    sim_module._loop.cache_clear()
    with runtime_constant_loops():
        virtual = simulate(orthodromic, traj, cases, method="rk4", jit=jit)
    sim_module._loop.cache_clear()
    for part in ("ideal", "real", "linear", "refined"):
        assert np.array_equal(_bits(getattr(compiled, part)), _bits(getattr(virtual, part)))


def test_lifting_keeps_every_operation_and_refuses_what_it_cannot_copy():
    """CasADi rewrites ``3.5*(2*x)`` as ``7*x`` and drops ``+ 0``: the lifted graph keeps
    the folded graph's operations (here its one number 7), not the expression as typed."""
    import casadi as ca

    x = ca.SX.sym("x", 2)
    folded = ca.Function("f", [x], [ca.vertcat(3.5 * (2.0 * x[0]) + 0.0 * x[1], x[1] / 3.0)])
    with integ._no_simplification():
        outs, numbers, values = integ.lift_constants(folded, [x])
    assert sorted(values) == [3.0, 7.0]
    lifted = ca.Function("g", [x, numbers], outs)
    at = np.array([0.1, -0.3])
    assert np.array_equal(_bits(np.asarray(lifted(at, values))),
                          _bits(np.asarray(folded(at))))
    # a call of another function (never inlined) is not copied: refused in one line
    inner = ca.Function("inner", [x], [ca.sin(x)], {"never_inline": True})
    called = ca.Function("h", [x], [inner(x) * 2.0])
    with pytest.raises(integ.LiftError, match="is not an operation of one or two"):
        integ.lift_constants(called, [x])


def test_a_toy_loop_held_at_rest_gives_the_baked_bits_in_pieces_and_groups():
    """b' = u (b - 1) rests at b = 1 and e' = (b - 1) e + (b - 1)/3 while it does (held:
    computed once per call), a' = w and c' = a move; four cases in two groups of two,
    runs in pieces (one call per piece): baked, run-time and virtual-machine bits alike."""
    import casadi as ca

    z, u, w, p = ca.SX.sym("z", 4), ca.SX.sym("u", 1), ca.SX.sym("w", 1), ca.SX.sym("p", 1)
    a, b, e = z[0], z[1], z[3]
    rhs = ca.Function("toy", [z, u, w, p], [ca.vertcat(
        p[0] * w[0], u[0] * (b - 1), ca.sin(a) * p[0], (b - 1) * e + (b - 1) / 3)])
    z0 = np.array([[0.0] * 4, [1.0] * 4, [0.25] * 4, [0.7] * 4])
    w = np.array([[0.5, -1.5, 2.0, 0.1]])

    def run(**how):
        loop = integ.CompiledLoop(rhs, None, "rk4", 3, 0.1, np.array([1.3]), np.array([0.3]),
                                  chunk=4, batch=4, workers=2, **how)
        return loop, loop.run(z0, w, 600).states

    baked = run()[1]
    loop, carried = run(runtime_constants=True)
    assert [i for i, _ in loop._frozen(loop.start(z0, w))] == [1, 3]
    assert [calls[0] for calls in loop._built.values()] == [None]   # the lifted library
    assert np.array_equal(_bits(baked), _bits(carried))
    assert np.array_equal(_bits(baked), _bits(run(jit=False)[1]))
    assert np.all(carried[1] == 1.0) and np.abs(carried[2, -1] - 0.25).min() > 0.01


SWEEP = """
title = "latitudes"
model = "orthodromic"
[motion]
kind = "static"
heading = "20 deg"
[run]
duration = "10 min"
step = "1 s"
record = "60 s"
[[case]]
accel_bias_x = "100 ug"
gyro_drift_y = "0.01 deg/h"
[sweep]
latitude = ["10 deg", "45 deg", "75 deg"]
"""


def test_a_sweeps_store_is_the_same_with_run_time_constants(tmp_path, monkeypatch):
    """Three static latitudes run with one run-time-constant loop; forced to the baked
    loops (one per latitude), the store is bit for bit the same."""
    import xarray as xr

    from ins_errors.analysis import sweep as sw

    scenario = _scenario(tmp_path, SWEEP)
    assert sw.loop_combinations(sw.grid(scenario).jobs) == 3
    used = []
    original = sim_module._loop

    def spy(*args):
        used.append(args[-1])   # runtime_constants
        return original(*args)

    monkeypatch.setattr(sim_module, "_loop", spy)
    sw.run_sweep(scenario, tmp_path / "carried.zarr", engine="serial")
    assert used and all(used)
    used.clear()
    monkeypatch.setattr(sw, "loop_combinations", lambda jobs: 1)
    sw.run_sweep(scenario, tmp_path / "baked.zarr", engine="serial")
    assert used and not any(used)
    a = xr.open_zarr(tmp_path / "carried.zarr").load()
    b = xr.open_zarr(tmp_path / "baked.zarr").load()
    assert sorted(a.variables) == sorted(b.variables) and a.attrs == b.attrs
    for name in a.variables:
        x, y = a[name].values, b[name].values
        if x.dtype.kind == "f":
            assert np.array_equal(_bits(x), _bits(y)), name
        else:
            assert np.array_equal(x, y), name
    assert np.all(a["failure"].values == "")


@pytest.mark.parametrize(("grid", "motion", "combinations"), [
    ('latitude = ["10 deg", "45 deg"]\nheading = ["0 deg", "30 deg"]', "static", 4),
    ('latitude = ["10 deg", "45 deg"]', "great-circle", 1),      # inputs read as it goes
    ('accel_bias_x = ["50 ug", "100 ug", "200 ug"]', "static", 1),
    ('U = ["7.2e-5 rad/s", "7.3e-5 rad/s"]', "great-circle", 2),   # parameters baked
])
def test_loops_are_shared_only_where_baked_ones_would_differ(tmp_path, grid, motion,
                                                            combinations):
    from ins_errors.analysis import sweep as sw

    text = SWEEP.replace('"static"', f'"{motion}"').split("[sweep]")[0] + "[sweep]\n" + grid
    jobs = sw.grid(_scenario(tmp_path, text)).jobs
    assert sw.loop_combinations(jobs) == combinations
