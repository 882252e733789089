"""The ``--matrix`` / ``--list-conventions`` / ``--write-samples`` part of ``ins-errors check``."""

from __future__ import annotations

import argparse
import sys

from ins_errors.json_output import emit

BIAS_HEADER = "bias states"
"""Heading of the error sources a hand model may carry as states (``--list-conventions``)."""


def run_matrix(args: argparse.Namespace) -> int:
    """Run the matrix check (or list conventions, or write the samples); exit status."""
    from ins_errors.checker.check_motions import flown_motions
    from ins_errors.checker.conventions import conventions
    from ins_errors.checker.derived_convention import unchecked_gains
    from ins_errors.checker.matrix import check_matrices
    from ins_errors.checker.matrix_input import write_samples
    from ins_errors.checker.matrix_report import to_json, to_markdown, to_terminal
    from ins_errors.commands.check import (
        emit_report,
        parse_magnitudes,
        warn_unchecked_gains,
        with_parameters,
    )
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import parse_parameter_options
    from ins_errors.numeric.model import load_model
    from ins_errors.output import check_file

    if args.file is not None:
        raise InsErrorsError("give either a hand FILE of equations or --matrix, not both")
    for flag, given in (("--latex", args.latex), ("--mapping", args.mapping),
                        ("--latex-parser", args.latex_parser != "lalr")):
        if given:
            raise InsErrorsError(f"{flag} applies to equation files, not to --matrix")
    model = load_model(args.model)
    parameters = parse_parameter_options(model, args.parameter)
    if args.list_conventions:
        from ins_errors.checker.navigation import adapter_name

        if adapter_name(model) is None:
            return _list_equation_states(model, args.json)
        found = list(conventions(model).values())
        # error sources that enter the equations may be bias states in any convention
        biases = [s for s in model.sources if s.kind == "constant"]
        if args.json:
            emit({"model": model.name, "conventions": [
                {"name": conv.name, "description": conv.description,
                 "states": [{"name": s.name, "unit": s.unit, "description": s.description}
                            for s in conv.states]} for conv in found],
                "bias_states": [{"name": s.name, "unit": s.unit,
                                 "description": s.description} for s in biases]})
            return 0
        for conv in found:
            print(f"{conv.name}: {conv.description}")
            for s in conv.states:
                print(f"  {s.name} ({s.unit}): {s.description}")
        if biases:
            print(f"{BIAS_HEADER}: error sources a hand model may carry as states, in any "
                  "convention")
            for s in biases:
                print(f"  {s.name} ({s.unit}): {s.description}")
        return 0
    # the derived model's values along the motions the model can fly (and why not the others)
    motion_list, skipped = flown_motions(model, parameters=parameters)
    if args.write_samples is not None:
        write_samples(args.write_samples, motion_list)
        written = {"model": model.name, "samples": str(args.write_samples),
                   "motions": [{"label": m.label, "samples": int(m.times.size),
                                "start_s": float(m.times[0]), "stop_s": float(m.times[-1])}
                               for m in motion_list],
                   "skipped_motions": skipped}
        said = (f"wrote {args.write_samples}: {', '.join(m.label for m in motion_list)}, "
                f"{motion_list[0].times.size} samples each"
                + "".join(f"\nnot flown: {text}" for text in skipped))
        if not args.matrix:  # with --matrix the check's report is the output
            if args.json:
                emit(written)
            else:
                print(said)
            return 0
        print(said, file=sys.stderr if args.json else sys.stdout)
    if args.report is not None:
        check_file(args.report)
    report = check_matrices(args.model, args.matrix, args.convention,
                            threshold=args.threshold, motion_list=motion_list,
                            magnitudes=parse_magnitudes(args.magnitude),
                            parameters=parameters, skipped_motions=skipped)
    warn_unchecked_gains(model, parameters, unchecked_gains(model, args.convention,
                                                            report.states, motion_list[0]))
    emit_report(args,
                lambda: to_markdown(report, f"`ins-errors check --matrix` of `{report.hand_name}`"),
                lambda: with_parameters(to_json(report), model, parameters),
                lambda: to_terminal(report))
    return report.exit_status


NO_CONVENTION = ("no convention: --matrix, --write-samples and files with @convention need a "
                 "navigation description this model lacks (docs/matrix_check.md, 'Which "
                 "models'); an equation file (ins-errors check MODEL FILE.txt) is written "
                 "in its own error states")
"""What ``--list-conventions`` says of a model without a navigation description."""


def _list_equation_states(model, as_json: bool) -> int:
    """``--list-conventions`` of a model no convention works for: say so, and list the
    error states an equation file of it is written in (no bias states: they belong to a
    convention)."""
    states = [{"name": s.name, "unit": s.unit, "description": s.description}
              for s in model.error_states]
    if as_json:
        emit({"model": model.name, "conventions": [], "bias_states": [],
              "note": NO_CONVENTION, "equation_file_states": states})
        return 0
    print(f"{model.name}: {NO_CONVENTION}:")
    for s in states:
        print(f"  {s['name']} ({s['unit']}): {s['description']}")
    return 0
