"""``ins-errors check MODEL FILE``: audit hand-written error equations term by term;
``ins-errors check MODEL --matrix FILE.py:FUNCTION --convention NAME``: audit a hand-coded
F and G entry by entry (:mod:`ins_errors.checker.matrix`)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

from ins_errors.json_output import emit
from ins_errors.user_paths import expand_user, user_path


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "check", help="compare hand-written error equations with the model's variation",
        description="Compare a researcher's error equations (SymPy text or LaTeX, one per "
                    "line) with the mechanical variation of MODEL, term by term. Each "
                    "discrepancy says what it is (omitted term, wrong coefficient, wrong "
                    "symbol or index, wrong sign, wrong function, wrong exponent) and how "
                    "much it matters (sized along reference motions relative to the largest "
                    "term of its equation): a wrong term is a mistake whatever its size, an "
                    "omitted small term a 'dropped small term', an omission the file declares "
                    "a 'declared drop'; knock-on findings are listed under their root. Exit "
                    "status: 0 no mistake, 1 mistakes found, 2 input problems. Notation: "
                    "docs/hand_check.md. "
                    "With --matrix, a hand-coded F (and G) is checked instead: "
                    "FILE.py:FUNCTION defines FUNCTION(nav, imu) returning F or (F, G) and "
                    "lists STATES (names from the convention's vocabulary, F's order) and "
                    "SOURCES (model error sources, G's columns); nav has t, motion, "
                    "latitude, longitude, height, v_ned, C_bn, omega_ie_n, omega_en_n, "
                    "omega_in_n, gravity, R_N, R_E, a, e2, earth_rate, parameters (the "
                    "model's, by name); imu has f_b, omega_ib_b, f_n (SI, NED). "
                    "FILE.npz / FILE.mat hold 'states', optional 'sources', F_<motion> "
                    "(K, n, n) and G_<motion> at the samples written by --write-samples. "
                    "Every entry is classed agrees / dropped small term / mistake, and both "
                    "models are propagated for 1 h and 24 h. Details: docs/matrix_check.md.")
    parser.add_argument("model", help="model name (e.g. orthodromic) or model file (my_ins.py)")
    parser.add_argument("file", type=user_path, nargs="*",
                        help="hand file (.txt SymPy syntax, .tex LaTeX); several are "
                             "checked one after the other, each report under a header "
                             "naming its file (--json: one JSON array), the exit status "
                             "the worst; not with --matrix")
    parser.add_argument("--matrix", type=expand_user, metavar="FILE.py:FUNCTION|FILE.npz|FILE.mat",
                        help="check a hand-coded F (and G) instead of equations")
    parser.add_argument("--convention", default=None,
                        help="state convention of the hand-coded matrices (default: the "
                             "one a file written by 'ins-errors matrices' names, else "
                             "'model': the model's own error states; see --list-conventions)")
    parser.add_argument("--list-conventions", action="store_true",
                        help="print the model's conventions and their state vocabulary")
    parser.add_argument("--write-samples", type=user_path, metavar="FILE.npz|FILE.mat",
                        help="write the navigation state and IMU outputs at every sample "
                             "time of the matrix check's motions, for computing F elsewhere")
    parser.add_argument("--latex", action="store_true",
                        help="read FILE as LaTeX whatever its suffix")
    parser.add_argument("--threshold", type=float, default=1e-3,
                        help="relative size separating dropped small terms from mistakes "
                             "(default 1e-3)")
    parser.add_argument("--magnitude", action="append", default=[], metavar="UNIT=QUANTITY",
                        help="typical error size for one SI unit, e.g. 'm/s=0.1 m/s', or "
                             "'attitude=20 arcsec' for the declared attitude error the "
                             "Schuler-consistent sizes follow from (repeatable)")
    parser.add_argument("--parameter", "-p", action="append", default=[], metavar="NAME=VALUE",
                        help="model parameter with unit, as for 'ins-errors compare', e.g. "
                             "strapdown_ned's vertical damping gains k_h1=0.0293/s and "
                             "k_h2=4.42e-4/s^2 (repeatable): the reference motions, term "
                             "sizes and effects use it; a term multiplied by a damping gain "
                             "left at 0 is not checked (a warning says so)")
    parser.add_argument("--mapping", type=user_path,
                        help="mapping file (@alias / @source lines) added to the default "
                             "notation")
    parser.add_argument("--report", type=user_path,
                        help="also write the report here: LaTeX (a fragment to \\input into a "
                             "referee report, coefficients typeset in the model's notation) "
                             "when the name ends in .tex, Markdown otherwise")
    parser.add_argument("--no-progress", action="store_true",
                        help="never show progress (the status lines of a long check)")
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument("--latex-parser", choices=("lalr", "sympy"), default="lalr",
                        help="parser of LaTeX arithmetic: fast LALR grammar (default) or "
                             "SymPy's parse_latex with lark (slow, for cross-checks)")
    parser.set_defaults(func=run)


def parse_magnitudes(entries: list[str]) -> dict[str, str]:
    """``--magnitude UNIT=QUANTITY`` entries -> {unit: quantity text}."""
    from ins_errors.errors import InsErrorsError

    magnitudes = {}
    for entry in entries:
        unit, sep, quantity = entry.partition("=")
        if not sep or not unit.strip() or not quantity.strip():
            raise InsErrorsError(f"--magnitude {entry!r}: expected UNIT=QUANTITY, e.g. "
                                 "'m/s=0.1 m/s' or 'attitude=20 arcsec'")
        magnitudes[unit.strip()] = quantity.strip()
    return magnitudes


def latex_report(args: argparse.Namespace) -> bool:
    """Whether ``--report`` asks for LaTeX (its name ends in ``.tex``)."""
    return args.report is not None and args.report.suffix.lower() == ".tex"


def run(args: argparse.Namespace) -> int:
    files = args.file if isinstance(args.file, list) else [args.file]
    files = [path for path in files if path is not None]
    args.file = files[0] if files else None
    if len(files) > 1:
        return _run_files(args, files)
    if latex_report(args) and (args.matrix or args.list_conventions or args.write_samples
                               or (args.file is not None and _declares_convention(args.file))):
        from ins_errors.errors import InsErrorsError

        raise InsErrorsError(f"--report {args.report}: a LaTeX report is written for "
                             "equation files only; write the report of --matrix or of an "
                             "@convention file as Markdown (e.g. --report report.md)")
    if args.matrix or args.list_conventions or args.write_samples:
        from ins_errors.commands.check_matrix import run_matrix

        args.convention = _matrix_convention(args.matrix, args.convention)
        return run_matrix(args)
    args.convention = args.convention or "model"
    from ins_errors.checker.compare import check_hand_file
    from ins_errors.checker.report import to_json, to_markdown, to_terminal
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_lookup import definition_of, resolve
    from ins_errors.output import check_file
    from ins_errors.progress import stage

    # the model first: a misspelt model name is said (with the close ones) before anything
    definition = definition_of(resolve(args.model))  # a name, a file or an entry point
    if args.file is None:
        raise InsErrorsError("check needs a hand FILE of equations or --matrix "
                             "FILE.py:FUNCTION")
    magnitudes = parse_magnitudes(args.magnitude)
    if args.report is not None:
        check_file(args.report)
    try:
        if _declares_convention(args.file):
            return _run_convention(args, magnitudes)
        from ins_errors.model_parameters import parse_parameter_options

        parameters = parse_parameter_options(definition, args.parameter)
        with stage(f"checking {args.file.name} against {definition.name}"):
            report = check_hand_file(args.file, model=definition, threshold=args.threshold,
                                     latex=True if args.latex else None,
                                     mapping_path=args.mapping,
                                     latex_backend=args.latex_parser,
                                     magnitudes=magnitudes, parameters=parameters)
    except InsErrorsError as error:
        error = named_as_given(error, args.file, args.mapping)
        if args.json:  # a grading script gets JSON whatever the file holds
            convention = _declared_convention(args.file)
            emit_json(args, _input_problem_json(args, definition, error)
                      if convention is None else
                      _refused_convention_json(args, definition, convention, error))
        raise error from None
    if report.problems and not any(_compared(result) for result in report.results):
        # nothing could be checked: no report that reads "(no discrepancies)", as for a
        # file without equations; the problems on stderr (and in the JSON, if asked)
        if args.json:
            emit_json(args, with_parameters(to_json(report), definition, parameters))
        say_problems(args.file, report.problems)
        return 2
    if report.unchecked_gains:
        warn_unchecked_gains(definition, parameters, report.unchecked_gains)

    def written() -> str:
        if latex_report(args):
            from ins_errors.checker.report_latex import to_latex

            return to_latex(report, definition, f"ins-errors check from {args.file.name}")
        return to_markdown(report, f"`ins-errors check` from `{args.file.name}`")

    emit_report(args, written, lambda: with_parameters(to_json(report), definition, parameters),
                lambda: to_terminal(report))
    say_problems(args.file, report.problems)  # the report lists them too
    return report.exit_status


def _compared(result) -> bool:
    """Whether an equation form was compared with the model (it agrees or has a mistake),
    not left unchecked (an input error, a tautology, a definition of the hand's own)."""
    return result.status.startswith("agrees") or result.status == "mistake"


def say_problems(path: Path, problems: list) -> None:
    """Print every input problem of the hand file ``path`` on stderr, one line each,
    naming the file as given and the place: ``eq.txt: line 3, column 14: cannot parse
    ...``, so a script's log shows why the exit status is 2 whatever went to stdout.

    Parameters
    ----------
    path : Path
        The hand file as the user gave it.
    problems : list of ins_errors.checker.parse.Problem
        In file order; nothing is printed for none.
    """
    for problem in problems:
        print(f"ins-errors: error: {path}: {problem}", file=sys.stderr, flush=True)


def unchecked_gains_warning(model, parameters: dict[str, float],
                            names: list[str] | None = None) -> str | None:
    """The warning that terms multiplied by a damping gain at 0 are not checked, with how
    to set the gains (their own examples), or None when no gain (of ``names``, if given)
    is 0.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model or ins_errors.modeling.ModelDefinition
        Its ``parameters`` say which are damping gains (``damping_gain=True``).
    parameters : dict of str to float
        The values set (SI); the others keep their defaults.
    names : list of str, optional
        Only these gains (e.g. those a compared line holds).
    """
    from ins_errors.numeric.linear_system import undamped_remedy

    p = [float(parameters.get(info.name, info.default)) for info in model.parameters]
    remedy = undamped_remedy(model, p, names)
    return f"terms multiplied by a damping gain at 0 are not checked{remedy}" if remedy else None


def warn_unchecked_gains(model, parameters: dict[str, float],
                         names: list[str] | None = None) -> None:
    """Print :func:`unchecked_gains_warning` on stderr, one line, if there is one."""
    import sys

    text = unchecked_gains_warning(model, parameters, names)
    if text is not None:
        print(f"ins-errors: warning: {text}", file=sys.stderr)


def with_parameters(data: dict, model, parameters: dict[str, float]) -> dict:
    """A check's JSON, with the parameters set under ``"parameters"`` when any was
    (:func:`ins_errors.model_parameters.parameters_record`); unchanged otherwise."""
    if not parameters:
        return data
    from ins_errors.model_parameters import parameters_record

    return {**data, "parameters": parameters_record(model, parameters)}


def emit_report(args: argparse.Namespace, markdown: Callable[[], str],
                as_json: Callable[[], dict], terminal: Callable[[], str]) -> None:
    """Write ``--report`` (``markdown()``'s text) if asked, then print the JSON or the
    terminal form.

    Each form is built only when it is shown.
    """
    from ins_errors.output import write_text

    if args.report is not None:
        write_text(args.report, markdown())
    if args.json:
        emit_json(args, as_json())
    else:
        print(terminal())


def emit_json(args: argparse.Namespace, data: dict) -> None:
    """Print one file's JSON, or keep it for the array of several files
    (:func:`_run_files` gives ``args.json_files``)."""
    kept = getattr(args, "json_files", None)
    if kept is None:
        emit(data)
    else:
        kept.append({"path": str(args.file), **data})


def _input_problem_json(args: argparse.Namespace, model, error: Exception) -> dict:
    """The JSON of a hand file that could not be checked at all (not found, empty, only
    comments): a report with no equation and the one input problem, exit status 2."""
    from ins_errors.checker.compare import CheckReport
    from ins_errors.checker.parse import Problem
    from ins_errors.checker.report import to_json

    message = str(error)
    for shown in (str(args.file), args.file.name):
        if message.startswith(f"{shown}: "):
            message = message[len(shown) + 2:]
            break
    latex = args.latex or args.file.suffix.lower() in (".tex", ".latex")
    report = CheckReport(model=model.name, hand_name=args.file.name,
                         hand_format="latex" if latex else "text", threshold=args.threshold,
                         points=[], basis=[], sections=[], results=[],
                         problems=[Problem(None, None, message)], out_of_scope=[],
                         from_model={}, unused=[])
    return to_json(report)


def _run_files(args: argparse.Namespace, files: list[Path]) -> int:
    """Check several hand files against one model, in one process: each file's report
    under a header naming it (``==> FILE <==``), or with ``--json`` one JSON array of
    the files' objects (each with its ``path`` as given). A file that cannot be checked
    prints its error line and the others go on. Returns the worst exit status (2 > 1 >
    0)."""
    from ins_errors.errors import InsErrorsError

    if args.matrix or args.list_conventions or args.write_samples:
        raise InsErrorsError("check takes one FILE with --matrix, --list-conventions or "
                             "--write-samples; several hand files only without them")
    if args.report is not None:
        raise InsErrorsError(f"--report {args.report}: one report file holds one hand "
                             "file's report: give one FILE, or leave out --report for "
                             "several")
    if not 0 < args.threshold < 1:
        raise InsErrorsError(f"threshold must be between 0 and 1, got {args.threshold}")
    from ins_errors.model_lookup import definition_of, resolve
    from ins_errors.model_parameters import parse_parameter_options

    parse_parameter_options(definition_of(resolve(args.model)), args.parameter)  # fail once
    parse_magnitudes(args.magnitude)
    kept: list[dict] = []
    worst = 0
    for path in files:
        one = argparse.Namespace(**vars(args))
        one.file = path
        if args.json:
            one.json_files = kept
        else:
            print(f"==> {path} <==", flush=True)
        try:
            status = run(one)
        except InsErrorsError as error:
            print(f"ins-errors: error: {error}", file=sys.stderr, flush=True)
            status = 2
        if not args.json:
            print(flush=True)
        worst = max(worst, status)
    if args.json:
        emit(kept)
    return worst


def named_as_given(error: Exception, *paths: Path | None) -> Exception:
    """``error``, its message naming a file as the user gave it (``/dev/null``,
    ``sub/eq.txt``) where it begins with the file's bare name, as the checker's messages
    name a hand or mapping file (``null: ...``, ``eq.txt, line 3: ...``)."""
    text = str(error)
    for path in paths:
        if path is None or str(path) == path.name:
            continue
        if text.startswith((f"{path.name}:", f"{path.name},")):
            error.args = (str(path) + text[len(path.name):],)
            break
    return error


def _matrix_convention(matrix: str | None, given: str | None) -> str:
    """The convention of ``--matrix``: the one a matrix file (``.npz``/``.mat``) written by
    ``ins-errors matrices`` names (its ``convention`` entry) where ``--convention`` is not
    given; ``given`` otherwise, or ``model``. One line where both are given and differ."""
    from ins_errors.checker.matrix_input import stored_convention
    from ins_errors.errors import InsErrorsError

    stored = None
    if matrix is not None and Path(matrix).suffix.lower() in (".npz", ".mat"):
        stored = stored_convention(Path(matrix))
    if given is not None and stored is not None and given != stored:
        raise InsErrorsError(f"--convention {given} but {matrix} holds matrices in "
                             f"{stored} (its 'convention' entry): drop --convention or give "
                             f"--convention {stored}")
    return given or stored or "model"


def _declares_convention(path: Path) -> bool:
    """Whether the hand file has an ``@convention NAME`` line (read errors: no)."""
    return _declared_convention(path) is not None


def _declared_convention(path: Path) -> str | None:
    """The NAME of the hand file's first ``@convention NAME`` line (``""`` without a
    name), None when it has none or cannot be read."""
    try:
        text = path.read_text(encoding="utf-8-sig")  # a BOM before @convention
    except (OSError, UnicodeDecodeError):
        return None
    for line in text.splitlines():
        words = line.split("%", 1)[0].split("#", 1)[0].split()
        if words[:1] == ["@convention"]:
            return words[1] if len(words) > 1 else ""
    return None


def _refused_convention_json(args: argparse.Namespace, model, convention_name: str,
                             error: Exception) -> dict:
    """The JSON of a ``@convention`` file that could not be checked: the keys of a
    checked one, nothing compared, the problem with its line and column
    (:func:`~ins_errors.checker.convention_equations.refused_json`)."""
    from ins_errors.checker.convention_equations import problem_place, refused_json

    states: list[str] = []
    try:
        from ins_errors.checker.conventions import convention
        from ins_errors.numeric.model import load_model

        states = list(convention(load_model(args.model), convention_name).names)
    except Exception:  # an unknown convention or a model without: the problem says so
        states = []
    place = problem_place(str(error), (str(args.file), args.file.name))
    return refused_json(model.name, convention_name or None, args.file.name,
                        args.threshold, states, place)


def _run_convention(args: argparse.Namespace, magnitudes: dict[str, str]) -> int:
    """Check a hand file written in a convention's states (``@convention NAME``) against
    the model as given (a name, a model file or an entry point)."""
    from ins_errors.checker.check_motions import motions
    from ins_errors.checker.convention_equations import (
        check_convention_file,
        to_json,
        to_terminal,
    )
    from ins_errors.checker.derived_convention import unchecked_gains
    from ins_errors.checker.matrix_report import to_markdown
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import parse_parameter_options
    from ins_errors.numeric.model import load_model
    from ins_errors.progress import stage

    if args.mapping is not None:
        raise InsErrorsError("--mapping does not apply to a file with @convention")
    model = load_model(args.model)
    parameters = parse_parameter_options(model, args.parameter)
    # the derived model is evaluated along the matrix checker's motions, flown with them
    with stage(f"checking {args.file.name} against {args.model} in its convention"):
        check = check_convention_file(args.file, args.model, threshold=args.threshold,
                                      magnitudes=magnitudes,
                                      latex=True if args.latex else None,
                                      parameters=parameters)
    for note in check.notes:
        print(f"ins-errors: note: {note}", file=sys.stderr)
    warn_unchecked_gains(model, parameters, unchecked_gains(
        model, check.report.convention, check.lines, motions(model, parameters=parameters)[0]))
    emit_report(args,
                lambda: to_markdown(check.report, f"`ins-errors check` from `{args.file.name}`"),
                lambda: with_parameters(to_json(check), model, parameters),
                lambda: to_terminal(check))
    return check.exit_status
