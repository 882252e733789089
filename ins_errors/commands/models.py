"""``ins-errors models [NAME]``: list the models, or one model's names and units."""

from __future__ import annotations

import argparse

from ins_errors.json_output import emit


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "models", help="list the models, or show one model's states, sources and outputs",
        description="Without NAME, list the models. With NAME, list its error states, "
                    "error sources (with units and the lab manual's factor numbers), "
                    "outputs, inputs, parameters (with their default values) and initial "
                    "conditions, and whether it is a strapdown INS that flies the strapdown "
                    "motions and has the φ/ψ conventions (for a model file that is "
                    "not: what it lacks).")
    parser.add_argument("name", nargs="?",
                        help="model name (e.g. orthodromic) or model file (my_ins.py)")
    parser.add_argument("--json", action="store_true", help="machine-readable output")
    parser.set_defaults(func=run)


def default_text(value: float, unit: str) -> str:
    """A parameter's default as the listing shows it and -p takes it: ``6378137 m``,
    ``9.81 m/s^2``, ``0/s``, ``0.00335281`` (every digit a float needs to come back
    unchanged; no unit for ``"1"``); an angle
    (SI unit ``rad``) in degrees, as people set it: ``50 deg``
    (:func:`parameter_text`)."""
    if unit == "rad":
        return parameter_text(value, unit)
    from ins_errors.units import typed_value

    number = repr(float(value))
    if number.endswith(".0"):
        number = number[:-2]
    return typed_value(number, unit)


def parameter_text(value: float, unit: str, digits: int = 10) -> str:
    """A parameter's value (SI) for people: ``digits`` significant digits and its unit
    (none for ``"1"``) as typed after ``-p`` (``1/s^2``, not SymPy's ``1/s**2``), an angle
    (``rad``) in degrees: ``0.8726646259971648 rad`` reads ``50 deg``, as
    ``-p phi0=50deg`` sets it (JSON keeps SI)."""
    import math

    if unit == "rad":
        return f"{math.degrees(float(value)):.{digits}g} deg"
    number = f"{float(value):.{digits}g}"
    return number if unit == "1" else f"{number} {unit.replace('**', '^')}"


def strapdown_status(model) -> dict:
    """Whether ``model`` is a strapdown INS the strapdown motions and the φ/ψ conventions
    carry (:func:`~ins_errors.checker.strapdown_description.is_strapdown`).

    Returns
    -------
    dict
        ``recognised`` (bool), ``lacks`` (list of str: what it lacks to describe itself,
        :func:`~ins_errors.checker.strapdown_description.missing`; empty when
        recognised) and ``conventions`` (list of str: its conventions besides its own
        error states, ``model``).
    """
    from ins_errors.checker import strapdown_description
    from ins_errors.checker.conventions import conventions

    recognised = strapdown_description.is_strapdown(model)
    return {"recognised": recognised,
            "lacks": [] if recognised else strapdown_description.missing(model),
            "conventions": [name for name in conventions(model) if name != "model"]}


def strapdown_line(model, status: dict) -> str | None:
    """The listing's one line on ``status`` (:func:`strapdown_status`): for a strapdown
    INS what it flies and its conventions; for a model file that is not one, what it
    lacks; None for a built-in model that is not one (a platform model: the strapdown
    requirements are beside the point)."""
    if status["recognised"]:
        return ("strapdown INS: yes, it flies the strapdown motions (static base, great "
                "circle, manoeuvre, motion file) and has the conventions "
                f"{', '.join(status['conventions'])} (ins-errors check MODEL "
                "--list-conventions)")
    if model.folder is None:
        return None
    return ("strapdown INS: no, so no strapdown motions and no φ/ψ conventions; it lacks "
            f"{'; '.join(status['lacks'])} (docs/matrix_check.md, 'Which models')")


def run(args: argparse.Namespace) -> int:
    from ins_errors.numeric.model import available_models, load_model

    if args.name is None:
        from ins_errors.errors import InsErrorsError

        rows = []
        for name in available_models():
            try:  # a broken installed model must not hide the others
                m = load_model(name)
                rows.append({"name": m.name, "title": m.title, "source": m.source_document})
            except InsErrorsError as error:
                rows.append({"name": name, "error": str(error)})
        if args.json:
            emit(rows)
        else:
            for row in rows:
                print(f"{row['name']:<20} " + (f"{row['title']}  [{row['source']}]"
                                               if "error" not in row else
                                               f"(cannot be loaded: {row['error']})"))
        return 0
    model = load_model(args.name)
    groups = {"error_states": model.error_states, "sources": model.sources,
              "outputs": model.outputs, "inputs": model.inputs,
              "parameters": model.parameters, "initial_conditions": model.initial_conditions}
    status = strapdown_status(model)
    if args.json:
        emit({**{k: [vars(i) for i in v] for k, v in groups.items()}, "strapdown": status})
        return 0
    print(f"{model.name}: {model.title}\nsource: {model.source_document}")
    line = strapdown_line(model, status)
    if line is not None:
        print(line)
    for title, infos in groups.items():
        print(f"\n{title.replace('_', ' ')}:")
        if not infos:
            print("  (none)")
        for i in infos:
            extra = f" (quoted in {i.display_unit}, {i.kind}" + (
                f", manual factor {i.factor})" if i.factor else ")") if i.kind else ""
            if title == "parameters":
                extra = f" (default {default_text(i.default, i.unit)}"
                if getattr(i, "damping_gain", False):  # the growth warning's remedy names it
                    extra += "; a damping gain" + (
                        f", e.g. -p {i.name}={i.example}" if i.example else "") + (
                        f" ({i.example_gives})" if i.example_gives else "")
                extra += ")"
            unit = i.unit.replace("**", "^")  # as -p and the files take it (JSON: SI)
            print(f"  {i.name:<36} [{unit}] {i.description}{extra}")
    return 0
