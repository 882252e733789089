"""``ins-errors matrices MODEL --convention NAME --out FILE``: the model's linear error
model F(t), G(t) in a convention along the matrix check's motions, written for a filter
designer (:func:`ins_errors.conventions.error_matrices`).

Examples::

    ins-errors matrices strapdown_ned --convention phi --out fg.npz
    ins-errors matrices my_ins.py --convention psi --motion cruise --hours 1 --step 1s \\
        --bias-states gyro_bias_x,gyro_bias_y,gyro_bias_z --out fg.mat

The file holds what ``check --write-samples`` writes (``t_<motion>`` and the navigation
description per motion) and ``F_<motion>`` (K, n, n), ``G_<motion>`` (K, n, m),
``x_<motion>`` (K, n_x) and ``u_<motion>`` (K, n_u) (the model's true states and inputs),
``states`` (F's rows and columns), ``sources`` (G's columns; G and ``sources`` are left
out when every source is a bias state), ``model_states``,
``model_inputs``, ``parameters`` (n_p,) with ``parameter_names``, and with ``--markov``
``markov_states`` with their correlation times ``markov_tau`` (s): the layout
``ins-errors check MODEL --matrix FILE --convention NAME`` reads, so the file checks the
derived model against itself.

Without ``--convention`` the convention is ``phi``, or ``model`` for a model whose only
convention is its own error states (a model without a navigation description:
``orthodromic``, a platform model file), said on stderr. Such a model flies the same
motions and its file holds no navigation description (``t_<motion>``, F, G, x, u); a
moving motion its flight refuses is listed as not flown (a static base it cannot fly
stops the command)::

    ins-errors matrices orthodromic --motion static --hours 1 --out out/fg_own.npz

``--discrete`` adds the discrete-time model a Kalman filter runs over each sample step
(:func:`ins_errors.analysis.discrete_model.discrete_matrices`): ``Phi_<motion>`` and
``Qd_<motion>`` (K − 1, n, n), Q from the white-noise densities ``--noise NAME=DENSITY``
(1σ, with units: ``gyro_bias_x=0.003deg/rt-hr,accel_bias_y=50ug/rtHz``; for a
``--markov`` bias state a value in the source's own unit is its steady-state 1σ, whose
driving noise enters Q), listed in ``noise_sources`` and ``noise_densities`` (SI)::

    ins-errors matrices strapdown_ned --motion static --hours 1 --step 1s --discrete \
        --noise gyro_bias_x=0.003deg/rt-hr --out fg.npz
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from ins_errors.commands import hours, motion_kinds
from ins_errors.json_output import emit
from ins_errors.machine_memory import available_memory, size_text
from ins_errors.units import percent_text
from ins_errors.user_paths import user_path

MOTIONS = ("static", "cruise", "manoeuvre")
"""The matrix check's motions (:mod:`ins_errors.checker.check_motions`)."""

MAX_BYTES = 10 * 10**9
"""Largest arrays (bytes, the file's size) written without ``--allow-large``."""

WORKING_COPIES = 3
"""One motion's arrays held again while they are made (F and G over every source, the
noise columns, the averaged step's Φ and Q of the hold's estimate), for the memory
estimate."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "matrices", help="write the linear error model F(t), G(t) in a convention along "
                         "the check's motions (for a filter designer)",
        description="Write MODEL's linear error model in a convention (phi, psi, ...: "
                    "'ins-errors check MODEL --list-conventions') at every sample of the "
                    "matrix check's motions (static base, great-circle cruise, manoeuvre): "
                    "t_<motion>, the navigation description, F_<motion> (K, n, n), "
                    "G_<motion> (K, n, m), the model's states x_<motion> and inputs "
                    "u_<motion>, and the names of F's states and G's sources, as .npz or "
                    "MATLAB .mat; with --discrete also the filter's discrete model over "
                    "each sample step, Phi_<motion> and Qd_<motion> (K-1, n, n), Q from "
                    "the --noise densities. A model without a navigation description "
                    "(no convention but its own error states) is written in those, "
                    "without the navigation description. Details: docs/matrix_check.md.")
    parser.add_argument("model", help="model name (e.g. strapdown_ned) or model file "
                                      "(my_ins.py)")
    parser.add_argument("--convention", default=None,
                        help="state convention of F and G ('ins-errors check MODEL "
                             "--list-conventions'; 'model': the model's own error states); "
                             "default phi, or model for a model that has no other (one "
                             "without a navigation description, e.g. orthodromic or a "
                             "platform model file: said on stderr)")
    parser.add_argument("--motion", action="append", type=motion_kinds(MOTIONS),
                        choices=MOTIONS, default=None,
                        help="motion to write (repeatable; default every motion the model "
                             "can fly)")
    parser.add_argument("--hours", type=hours, default=24.0,
                        help="length of each motion, h (default 24, as check)")
    parser.add_argument("--step", default="60 s",
                        help="sample step (default 60 s, as check, whose --matrix then "
                             "reads the file)")
    parser.add_argument("--bias-states", default="", metavar="NAME,...",
                        help="constant error sources carried as states after the "
                             "convention's (a 15-state filter: gyro_bias_x,...,"
                             "accel_bias_z); their columns of G move into F")
    parser.add_argument("--markov", action="append", default=[], metavar="NAME=TIME",
                        help="a bias state that is a first-order Gauss-Markov process of "
                             "this correlation time (its row of F is -1/tau), e.g. "
                             "gyro_bias_x=300s (repeatable; the name must be in "
                             "--bias-states)")
    parser.add_argument("--discrete", action="store_true",
                        help="also write the discrete-time model over each sample step: "
                             "Phi_<motion> = e^(F dt) and Qd_<motion> (Van Loan, F and G "
                             "held at the step's start: exact on a static base, for a "
                             "moving one keep --step short against the motion)")
    parser.add_argument("--noise", action="append", default=[], metavar="NAME=DENSITY",
                        help="white-noise density (1σ) of an error source for Qd, with "
                             "its unit, e.g. gyro_bias_x=0.003deg/rt-hr or "
                             "accel_bias_y=50ug/rtHz (repeatable or a comma list; needs "
                             "--discrete). A bias state's noise enters through the column "
                             "of its bias; for a --markov bias state a value in the "
                             "source's own unit (gyro_bias_x=0.01deg/h) is its "
                             "steady-state 1σ, driving it with density σ·sqrt(2/tau)")
    parser.add_argument("--allow-large", action="store_true",
                        help="write the file even when its arrays are beyond "
                             f"{MAX_BYTES / 1e9:g} GB or the memory this machine has "
                             "available (estimated before anything is flown)")
    parser.add_argument("--parameter", "-p", action="append", default=[],
                        metavar="NAME=VALUE",
                        help="model parameter with unit, e.g. k_h1=0.0293/s (repeatable)")
    parser.add_argument("--out", "-o", type=user_path, default=None, metavar="FILE.npz|FILE.mat",
                        help="file to write (.npz, or MATLAB .mat; required)")
    parser.add_argument("--json", action="store_true",
                        help="print what was written as JSON")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ins_errors.analysis.discrete_model import (
        HOLD_TOLERANCE,
        discrete_matrices,
        hold_error,
        process_noise,
    )
    from ins_errors.checker.check_motions import flown_motions
    from ins_errors.checker.matrix_input import sample_arrays, save_arrays
    from ins_errors.conventions import error_matrices, model_convention
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import parameters_record, parse_parameter_options
    from ins_errors.numeric.model import load_model
    from ins_errors.units import parse_quantity

    model = load_model(args.model)  # a misspelt model is said first (with close names)
    if args.out is None:
        raise InsErrorsError("matrices needs --out FILE.npz or FILE.mat (the file to write)")
    if args.out.suffix.lower() not in (".npz", ".mat"):
        raise InsErrorsError(f"--out {str(args.out)!r} must end in .npz or .mat")
    step = parse_quantity(args.step, "s", "--step")
    if not (math.isfinite(step) and 0 < step <= args.hours * 3600.0):
        raise InsErrorsError(f"--step {args.step!r} must be positive and at most the motion's "
                             f"length ({args.hours:g} h)")
    parameters = parse_parameter_options(model, args.parameter)
    biases = [b.strip() for b in args.bias_states.split(",") if b.strip()]
    markov = _markov_times(args.markov, biases)
    if args.noise and not args.discrete:
        raise InsErrorsError("--noise gives the process noise of the discrete model: add "
                             "--discrete (Phi and Qd over each sample step)")
    args.convention = _default_convention(model, args.convention)
    # the convention (and the bias states) before the flights: a wrong name costs nothing
    conv = model_convention(model, args.convention, biases, markov)
    white, sigma = _noise_values(model, args.noise, biases, markov)
    warnings = _undriven(model, markov, sigma) if args.discrete else []
    for text in warnings:
        print(f"ins-errors: warning: {text}", file=sys.stderr)
    size = _size(model, args, step, len(conv.names), len(biases), len(white) + len(sigma))
    # a model without a navigation description flies them too, in its own error states
    # (no navigation arrays in the file: t_<motion>, F, G, x, u)
    flown, skipped = flown_motions(model, args.hours, step, parameters=parameters,
                                   require_navigation=False)
    wanted = args.motion or [m.label for m in flown]
    missing = [label for label in wanted if label not in {m.label for m in flown}]
    if missing:
        why = next(text.split(": ", 1)[1] for text in skipped
                   if text.split(": ", 1)[0] == missing[0])
        raise InsErrorsError(f"model {model.name!r} cannot fly the {missing[0]} motion: "
                             f"{why}")
    chosen = [m for m in flown if m.label in wanted]
    kinds = {src.name: src.kind for src in model.sources}
    arrays = sample_arrays(chosen)
    mat = args.out.suffix.lower() == ".mat"

    def names(values) -> np.ndarray:  # a cell array in .mat, strings in .npz
        return np.array(list(values), dtype=object if mat else str)

    states: tuple[str, ...] = ()
    sources: list[str] = []
    noises: tuple[str, ...] = ()
    holds: list[dict] = []
    units = [state.unit for state in conv.states]
    for motion in chosen:
        p = np.asarray(motion.p, dtype=float)
        p = p if p.ndim == 1 else p[:, 0]  # (constant along the samples)
        em = error_matrices(model, args.convention, motion.x, motion.u, p,
                            bias_states=biases, markov=markov or None)
        states = em.states
        # a bias state's source is a state, not a column of G (as check --matrix reads);
        # an initial error (kind initial) is no input at all: it only sets the start
        keep = [j for j, s in enumerate(em.sources)
                if s not in biases and kinds[s] != "initial"]
        sources = [em.sources[j] for j in keep]
        arrays[f"F_{motion.label}"] = em.F
        if keep:  # (no G when every source is a state: check --matrix reads F alone)
            arrays[f"G_{motion.label}"] = em.G[:, :, keep]
        arrays[f"x_{motion.label}"] = motion.x.T
        arrays[f"u_{motion.label}"] = motion.u.T
        if args.discrete:
            Gw, densities, noises = process_noise(em.F, em.G, em.states, em.sources,
                                                  white, sigma, markov)
            dm = discrete_matrices(em.F, Gw, motion.times, densities)
            arrays[f"Phi_{motion.label}"] = dm.Phi
            arrays[f"Qd_{motion.label}"] = dm.Qd
            if noises:
                arrays[f"L_{motion.label}"] = Gw
            hold = hold_error(em.F, Gw, motion.times, densities, dm, units,
                              _state_sizes(model, conv, motion, units, parameters),
                              twice_above=HOLD_TOLERANCE)
            holds.append(_hold_record(motion.label, hold, motion.times, step, states))
            if hold.size > HOLD_TOLERANCE:
                text = _hold_warning(holds[-1], args.step, step)
                warnings.append(text)
                print(f"ins-errors: warning: {text}", file=sys.stderr)
    arrays["states"] = names(states)
    # one string (a char array in .mat): check --matrix takes it as its default convention
    arrays["convention"] = np.array(args.convention)
    if markov:  # what check --matrix reads to know the Gauss-Markov bias states
        arrays["markov_states"] = names(markov)
        arrays["markov_tau"] = np.array(list(markov.values()), dtype=float)
    if sources:
        arrays["sources"] = names(sources)
    if args.discrete and noises:
        arrays["noise_sources"] = names(noises)
        arrays["noise_densities"] = densities
    arrays["model_states"] = names(s.name for s in model.states)
    arrays["model_inputs"] = names(s.name for s in model.inputs)
    arrays["parameter_names"] = names(q.name for q in model.parameters)
    arrays["parameters"] = p
    save_arrays(args.out, arrays, "--out")
    k = chosen[0].times.size
    if args.json:
        emit({"model": model.name, "convention": args.convention, "out": str(args.out),
              "states": list(states), "sources": sources,
              "bias_states": [{"name": b.name, "statistics": "markov" if b.tau else
                               "constant", "tau_s": b.tau} for b in conv.biases],
              "size_bytes": size,
              "motions": [{"label": m.label, "samples": int(m.times.size),
                           "start_s": float(m.times[0]), "stop_s": float(m.times[-1])}
                          for m in chosen],
              "skipped_motions": skipped,
              "parameters": parameters_record(model, parameters),
              **({"discrete": {"step_s": step, "noise_sources": list(noises),
                               "noise_densities_si": densities.tolist(),
                               "hold_error": holds}}
                 if args.discrete else {}),
              "warnings": warnings})
        return 0
    g = (f" and G ({k}, {len(states)}, {len(sources)})" if sources
         else " (no G: every source is a state)")
    order = (f"\nstates: {', '.join(states)}" if biases else "")
    print(f"wrote {args.out}: F ({k}, {len(states)}, {len(states)}){g} in "
          f"{args.convention} at {_samples_text(k, [m.label for m in chosen])}" + order
          + (_discrete_line(k, len(states), args.step, noises) if args.discrete else "")
          + "".join(f"\nnot flown: {text}" for text in skipped))
    return 0


def _samples_text(k: int, labels: list[str]) -> str:
    """``37 samples of static``, or ``37 samples each of static, cruise and manoeuvre``:
    every motion has K samples (the same step over the same hours), not K in all."""
    if len(labels) == 1:
        return f"{k} samples of {labels[0]}"
    return f"{k} samples each of {', '.join(labels[:-1])} and {labels[-1]}"


def _default_convention(model, given: str | None) -> str:
    """``given``, or without ``--convention`` the default: ``phi``, or ``model`` for a
    model whose only convention is its own error states (said on stderr). One line for a
    model with conventions but no ``phi`` (``north_pointing``: ``psi`` and ``model``)."""
    from ins_errors.checker.conventions import conventions
    from ins_errors.errors import InsErrorsError

    if given is not None:
        return given
    known = list(conventions(model))
    if "phi" in known:
        return "phi"
    if known == ["model"]:
        print(f"ins-errors: note: {model.name} has no φ/ψ convention (no navigation "
              "description): F and G are in its own error states, --convention model",
              file=sys.stderr)
        return "model"
    raise InsErrorsError(f"model {model.name!r} has no phi convention: give --convention "
                         f"{' or '.join(known)} ('ins-errors check {model.name} "
                         "--list-conventions' lists their states)")


def _markov_times(items: list[str], biases: list[str]) -> dict[str, float]:
    """``--markov NAME=TIME`` options as name -> correlation time (s); each name a bias
    state, each time positive (one line naming the option otherwise: the API's check,
    :func:`ins_errors.conventions.correlation_time`)."""
    from ins_errors.conventions import correlation_time
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import name_value_pairs
    from ins_errors.units import parse_quantity

    times: dict[str, float] = {}
    for name, text in name_value_pairs(items, "--markov", "gyro_bias_x=300s").items():
        if name not in biases:
            raise InsErrorsError(f"--markov {name}={text}: {name!r} is not a bias state "
                                 f"(--bias-states {','.join(biases) or '...'})")
        tau = parse_quantity(text, "s", f"--markov {name}")
        times[name] = correlation_time(name, tau, f"--markov {name}={text}")
    return times


def _discrete_line(k: int, n: int, step: str, noises: tuple[str, ...]) -> str:
    """The printed line of ``--discrete``: what Phi and Qd are and which noises made Q."""
    made = (f"from the noise of {', '.join(noises)}" if noises
            else "zero: no --noise given")
    return (f"\ndiscrete model over each {step.strip()} step: Phi and Qd ({k - 1}, {n}, {n}); "
            f"Qd {made}")


def _noise_values(model, items: list[str], biases: list[str], markov: dict[str, float]
                  ) -> tuple[dict[str, float], dict[str, float]]:
    """``--noise NAME=VALUE`` options (repeated or comma lists) as the white-noise
    densities (name -> SI unit of the source times √s) and the steady-state 1σ of
    Gauss–Markov bias states (name -> SI unit of the source).

    A value is a density (``0.003deg/rt-hr``, ``50ug/rtHz``), except for a ``--markov``
    bias state, where a value in the source's own unit (``0.01deg/h``) is its
    steady-state 1σ (such a state may take both, its name given twice). One line naming
    the option for an unknown source, a name given twice as the same kind, an initial
    error,
    a value without a unit or in another unit, a 1σ value for a source that is no
    Gauss–Markov state (a random constant has no driving noise), a negative or NaN value.
    """
    import contextlib

    from ins_errors.analysis.budget import density_display
    from ins_errors.errors import InsErrorsError, unknown_name
    from ins_errors.model_parameters import name_value_pairs
    from ins_errors.units import UnitError, parse_quantity

    split = [part for item in items for part in item.split(",") if part.strip()]
    infos = {s.name: s for s in model.sources}
    white: dict[str, float] = {}
    sigma: dict[str, float] = {}
    # one item at a time: a Gauss–Markov bias state may take a name twice, its
    # instrument's white noise (a density) and its own steady-state σ
    pairs = [pair for part in split for pair in
             name_value_pairs([part], "--noise", "gyro_bias_x=0.003deg/rt-hr").items()]
    for name, text in pairs:
        where = f"--noise {name}={text.strip()}"
        if name not in infos:
            error = unknown_name(f"error source of {model.name}", name, infos)
            raise InsErrorsError(f"{where}: {error}")
        info = infos[name]
        if info.kind == "initial":
            raise InsErrorsError(f"{where}: {name!r} is an initial error (it sets the error "
                                 "at the start), which no noise drives")
        unit = f"({info.unit})*s**0.5"
        display = info.display_unit or info.unit
        density_unit = density_display(display, unit)
        value, is_sigma = None, False
        if name in markov:  # a value in the source's unit: the steady-state 1σ
            with contextlib.suppress(UnitError):
                value, is_sigma = parse_quantity(text, info.unit, where), True
        if value is None:
            try:
                value = parse_quantity(text, unit, where, numbers_are_si=False)
            except UnitError as error:
                raise InsErrorsError(_noise_unit_problem(
                    where, name, text, info.unit, display, density_unit, biases, markov,
                    str(error))) from None
        if not value >= 0:
            raise InsErrorsError(f"{where}: a noise density or σ must be >= 0")
        values = sigma if is_sigma else white
        if name in values:
            kind = " as a steady-state σ" if is_sigma else " as a density"
            raise InsErrorsError(f"--noise {name} given twice"
                                 + (kind if name in markov else ""))
        values[name] = value
    return white, sigma


def _noise_unit_problem(where: str, name: str, text: str, unit: str, display: str,
                        density_unit: str, biases: list[str], markov: dict[str, float],
                        problem: str) -> str:
    """The one line for a ``--noise`` value that is no density of the source: a 1σ
    value where no Gauss–Markov state takes one said as such, any other unit problem
    with the density's unit as the example."""
    from ins_errors.units import UnitError, parse_quantity

    try:
        parse_quantity(text, unit, where)
        is_sigma = True
    except UnitError:
        is_sigma = False
    if is_sigma and name in biases:
        return (f"{where}: {name!r} is a random-constant bias state, which no noise drives, "
                f"so a 1σ in {display} has no place in Q: give --markov {name}=TAU to make "
                f"it a Gauss–Markov process of that steady-state σ, or the instrument's "
                f"white noise as a density in {density_unit}")
    if is_sigma:
        return (f"{where}: a white-noise density has units of {density_unit}, not "
                f"{display} (a 1σ constant, which adds no noise)")
    reason = problem.split(": ", 1)[-1].split("; give ")[0]
    sigma = (f" or, for the Gauss–Markov bias state, its steady-state 1σ in {display}"
             if name in markov else "")
    return f"{where}: {reason}; give a density in {density_unit}{sigma}"


def _undriven(model, markov: dict[str, float], sigma: dict[str, float]) -> list[str]:
    """The warnings for Gauss–Markov bias states without a steady-state σ: no noise
    drives them in Q, so a filter lets them decay to 0 and grows overconfident."""
    units = {s.name: s.display_unit or s.unit for s in model.sources}
    return [f"the Gauss-Markov bias state {name} has no steady-state 1σ, so nothing drives "
            f"it: its row of Qd is zero and a filter would let it decay to 0 and grow "
            f"overconfident; give its σ in {units[name]} as --noise {name}=SIGMA (e.g. "
            f"{name}=0.01{units[name].replace(' ', '')}, beside any density)"
            for name in markov if name not in sigma]


def _size(model, args: argparse.Namespace, step: float, n: int, biases: int,
          noises: int) -> int:
    """The bytes of the arrays the file will hold (estimated before anything is flown),
    said on stderr when large; refused in one line beyond :data:`MAX_BYTES` or the
    memory available, unless ``--allow-large``."""
    from ins_errors.errors import InsErrorsError

    samples = math.floor(args.hours * 3600.0 / step + 1e-9) + 1
    motions = len(set(args.motion or MOTIONS))
    inputs = sum(s.kind != "initial" for s in model.sources) - biases
    per_sample = (n * n + n * inputs + len(model.states) + len(model.inputs) + 20
                  + (2 * n * n + n * noises if args.discrete else 0))
    size = 8 * samples * motions * per_sample
    working = 8 * samples * WORKING_COPIES * (
        n * n + n * len(model.sources) + (2 * n * n + n * noises if args.discrete else 0))
    what = (f"{motions} motion{'s' if motions > 1 else ''} × {samples:,} samples × "
            f"{n} states")
    anyway = (f"; give a longer --step, fewer --hours{' or one --motion' * (motions > 1)}"
              ", or --allow-large to write it anyway")
    if not args.allow_large:
        if size > MAX_BYTES:
            raise InsErrorsError(f"the arrays would take about {size_text(size)} ({what}), "
                                 f"beyond the limit of {size_text(MAX_BYTES)}{anyway}")
        free = available_memory()
        if free is not None and size + working > free:
            raise InsErrorsError(f"the arrays would need about {size_text(size + working)} "
                                 f"of memory ({what}), and this machine has "
                                 f"{size_text(free)} available{anyway}")
    if size > 10**9:
        print(f"ins-errors: the arrays will take about {size_text(size)} ({what})",
              file=sys.stderr)
    return size


def _state_sizes(model, conv, motion, units: list[str], parameters) -> np.ndarray:
    """Typical size of each state (SI) for the hold's estimate: by its unit, and a
    latitude or longitude error (rad) as the typical position error over the Earth's
    radius, as the matrix check weighs it (an angle's 1e-4 rad would be 640 m)."""
    from ins_errors.analysis.discrete_model import typical_sizes
    from ins_errors.checker.matrix import position_angle_magnitude, position_angles
    from ins_errors.checker.typical import typical_magnitude

    sizes = typical_sizes(units)
    if motion.navigation:  # (a model's own error states have no position readout)
        angles = position_angles(conv, motion)
        size = position_angle_magnitude(model, typical_magnitude("m"), parameters)[0]
        for i, state in enumerate(conv.states):
            if state.name in angles:
                sizes[i] = size
    return sizes


def _hold_record(label: str, hold, times: np.ndarray, step: float,
                 states: tuple[str, ...]) -> dict:
    """A motion's hold-error estimate as the JSON's record (docs/json.md); a step is
    suggested where the estimate at twice the step shows the error falling with the
    step and the step is short against the motion's fastest change (:data:`FASTEST_CHANGE`,
    :func:`~ins_errors.analysis.discrete_model.suggested_step`); a step suggested divides
    the run."""
    from ins_errors.analysis.discrete_model import suggested_step

    def block(first_stop: tuple[int, int]) -> str:
        first, stop = first_stop
        return states[first] if stop - first == 1 else f"{states[first]}…{states[stop - 1]}"

    suggested = suggested_step(step, hold.size, hold.twice, run=float(times[-1] - times[0]),
                               fastest=FASTEST_CHANGE.get(label))
    return {"label": label, "size": hold.size, "matrix": hold.matrix,
            "block": f"{hold.matrix}[{block(hold.rows)}, {block(hold.columns)}]",
            "time_s": float(times[hold.step]), "size_twice_step": hold.twice,
            "suggested_step_s": suggested}


FASTEST_CHANGE = {"manoeuvre": 600.0}
"""Duration (s) of the fastest change of each of the checker's motions that has one
(:mod:`~ins_errors.checker.check_motions`): the platform manoeuvre's shortest legs and half
of a strapdown manoeuvre's 20-min S-turn are 10 min (the weave of a model without a
heading is slower). The static base and the cruise change only with the Earth's rotation
and the transport rate."""


def _hold_warning(record: dict, step_text: str, step: float) -> str:
    """The one line of a motion whose step is too long for the hold of F (stderr and
    JSON ``warnings``): the step suggested only where the error was seen to fall with
    the step."""
    from ins_errors.analysis.discrete_model import (
        FALLING,
        HOLD_TOLERANCE,
        SAMPLES_PER_CHANGE,
    )

    against = ("against what a step does to those states" if record["matrix"] == "Phi"
               else "against their variances")
    head = (f"{record['label']}: F held at each step's start puts Phi and Qd off by up to "
            f"{percent_text(record['size'])} ({record['block']} at t = "
            f"{record['time_s'] / 3600:.2f} h, {against}; estimated from F at the step's "
            f"end)")
    twice = record["size_twice_step"]
    if record["suggested_step_s"] is not None:
        return (f"{head}, {percent_text(twice)} at twice the step: it falls with the step, "
                f"and --step {record['suggested_step_s']:g}s (not {step_text.strip()}) "
                f"brings it under about {HOLD_TOLERANCE:.0%}")
    fastest = FASTEST_CHANGE.get(record["label"])
    if twice is not None and FALLING[0] * record["size"] <= twice <= FALLING[1] * record["size"] \
            and fastest is not None and step > fastest / SAMPLES_PER_CHANGE:
        # it seems to fall with the step, but at steps too long to show the motion's changes
        return (f"{head}, {percent_text(twice)} at twice the step; the step is longer than "
                f"half of the {record['label']}'s fastest change ({fastest:g} s), so the "
                "estimate misses changes between its samples and no step follows from it; "
                f"shorten --step to {fastest / SAMPLES_PER_CHANGE:g} s or less and run again "
                "to see what it comes to")
    seen = ("" if twice is None else
            f", {percent_text(twice)} at twice the step: not the steady fall of an error in "
            f"proportion to the step (a step too long for the estimate), so no step "
            f"follows from it")
    return f"{head}{seen}; shorten --step and run again to see what it comes to"
