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
``model_inputs``, ``parameters`` (n_p,) with ``parameter_names``: the layout
``ins-errors check MODEL --matrix FILE --convention NAME`` reads, so the file checks the
derived model against itself.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from ins_errors.commands import hours
from ins_errors.json_output import emit

MOTIONS = ("static", "cruise", "manoeuvre")
"""The matrix check's motions (:mod:`ins_errors.checker.check_motions`)."""


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
                    "MATLAB .mat. Details: docs/matrix_check.md.")
    parser.add_argument("model", help="model name (e.g. strapdown_ned) or model file "
                                      "(my_ins.py)")
    parser.add_argument("--convention", default="phi",
                        help="state convention of F and G (default phi; 'model': the "
                             "model's own error states)")
    parser.add_argument("--motion", action="append", choices=MOTIONS, default=None,
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
    parser.add_argument("--parameter", "-p", action="append", default=[],
                        metavar="NAME=VALUE",
                        help="model parameter with unit, e.g. k_h1=0.0293/s (repeatable)")
    parser.add_argument("--out", "-o", type=Path, default=None, metavar="FILE.npz|FILE.mat",
                        help="file to write (.npz, or MATLAB .mat; required)")
    parser.add_argument("--json", action="store_true",
                        help="print what was written as JSON")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ins_errors.checker.check_motions import flown_motions
    from ins_errors.checker.matrix_input import sample_arrays, save_arrays
    from ins_errors.conventions import error_matrices, model_convention
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import parse_parameter_options
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
    # the convention (and the bias states) before the flights: a wrong name costs nothing
    model_convention(model, args.convention, biases)
    flown, skipped = flown_motions(model, args.hours, step, parameters=parameters)
    wanted = args.motion or [m.label for m in flown]
    missing = [label for label in wanted if label not in {m.label for m in flown}]
    if missing:
        raise InsErrorsError(f"model {model.name!r} cannot fly the {missing[0]} motion: "
                             + "; ".join(skipped))
    chosen = [m for m in flown if m.label in wanted]
    arrays = sample_arrays(chosen)
    mat = args.out.suffix.lower() == ".mat"

    def names(values) -> np.ndarray:  # a cell array in .mat, strings in .npz
        return np.array(list(values), dtype=object if mat else str)

    states: tuple[str, ...] = ()
    sources: list[str] = []
    for motion in chosen:
        p = np.asarray(motion.p, dtype=float)
        p = p if p.ndim == 1 else p[:, 0]  # (constant along the samples)
        em = error_matrices(model, args.convention, motion.x, motion.u, p,
                            bias_states=biases, markov=markov or None)
        states = em.states
        # a bias state's source is a state, not a column of G (as check --matrix reads)
        keep = [j for j, s in enumerate(em.sources) if s not in biases]
        sources = [em.sources[j] for j in keep]
        arrays[f"F_{motion.label}"] = em.F
        if keep:  # (no G when every source is a state: check --matrix reads F alone)
            arrays[f"G_{motion.label}"] = em.G[:, :, keep]
        arrays[f"x_{motion.label}"] = motion.x.T
        arrays[f"u_{motion.label}"] = motion.u.T
    arrays["states"] = names(states)
    if sources:
        arrays["sources"] = names(sources)
    arrays["model_states"] = names(s.name for s in model.states)
    arrays["model_inputs"] = names(s.name for s in model.inputs)
    arrays["parameter_names"] = names(q.name for q in model.parameters)
    arrays["parameters"] = p
    save_arrays(args.out, arrays, "--out")
    k = chosen[0].times.size
    if args.json:
        emit({"model": model.name, "convention": args.convention, "out": str(args.out),
              "states": list(states), "sources": sources,
              "motions": [{"label": m.label, "samples": int(m.times.size),
                           "start_s": float(m.times[0]), "stop_s": float(m.times[-1])}
                          for m in chosen],
              "skipped_motions": skipped, "parameters": parameters})
        return 0
    g = (f" and G ({k}, {len(states)}, {len(sources)})" if sources
         else " (no G: every source is a state)")
    print(f"wrote {args.out}: F ({k}, {len(states)}, {len(states)}){g} in "
          f"{args.convention} at {k} samples of "
          f"{', '.join(m.label for m in chosen)}"
          + "".join(f"\nnot flown: {text}" for text in skipped))
    return 0


def _markov_times(items: list[str], biases: list[str]) -> dict[str, float]:
    """``--markov NAME=TIME`` options as name -> correlation time (s); each name a bias
    state, each time positive (one line naming the option otherwise)."""
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import name_value_pairs
    from ins_errors.units import parse_quantity

    times: dict[str, float] = {}
    for name, text in name_value_pairs(items, "--markov", "gyro_bias_x=300s").items():
        if name not in biases:
            raise InsErrorsError(f"--markov {name}={text}: {name!r} is not a bias state "
                                 f"(--bias-states {','.join(biases) or '...'})")
        tau = parse_quantity(text, "s", f"--markov {name}")
        if not (math.isfinite(tau) and tau > 0):
            raise InsErrorsError(f"--markov {name}={text}: the correlation time must be "
                                 "positive")
        times[name] = tau
    return times
