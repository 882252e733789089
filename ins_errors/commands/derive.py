"""``ins-errors derive MODEL_FILE [--out DIR]``: write a model's generated package."""

from __future__ import annotations

import argparse
import time
from dataclasses import asdict

from ins_errors.json_output import emit
from ins_errors.user_paths import user_path


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "derive", help="derive a model file and write its generated package",
        description="Vary the model defined in MODEL (a Python file written with "
                    "ins_errors.modeling, or an installed model) and write the same "
                    "generated package `make derive` writes for a built-in model: metadata "
                    "(__init__.py, with the hash of the model file and a fingerprint of "
                    "the code that derives it), numpy_model.py, "
                    "casadi_model.py (first- and second-order error equations) and "
                    "error_equations.md (the equations as Markdown/LaTeX). All or nothing: "
                    "on any error DIR is left as it was.")
    parser.add_argument("model", help="model file, e.g. examples/own_model/schuler_loop.py")
    parser.add_argument("--out", "-o", type=user_path, metavar="DIR",
                        help="package folder to write (default for a model file: "
                             "<file stem>_generated/ next to it, where the other commands "
                             "look first)")
    parser.add_argument("--json", action="store_true", help="machine-readable summary")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_lookup import (
        definition_of,
        next_to,
        package_record,
        resolve,
        write_derived,
    )

    start = time.perf_counter()
    ref = resolve(args.model)
    if args.out is None and ref.kind != "file":
        raise InsErrorsError(f"{ref.label}: give --out DIR (only a model file has a default "
                             "folder next to it)")
    out = args.out if args.out is not None else next_to(ref.path)
    d = definition_of(ref)
    if ref.kind == "builtin":  # the package `make derive` writes, its sources' hashes too
        from ins_errors.model_identity import builtin_record

        origin, record = None, builtin_record(ref.spec)
    else:
        origin, record = package_record(ref)
    summary = write_derived(ref, d, out, origin, record)
    files = sorted(p.name for p in out.iterdir())
    if args.json:
        fields = asdict(summary)
        # wall time of this derivation (short where the cache holds the model's
        # variation): named by its unit as every JSON time is
        fields["wall_time_s"] = fields.pop("seconds")
        emit({**fields, "out": str(out), "files": files,
              "model_file_sha256": ref.sha256,
              "derivation_code_sha256": record.get("DERIVATION_CODE_SHA256")})
        return 0
    from ins_errors.derive.model_files import summary_table

    print("\n".join(summary_table([summary])))
    print(f"derive: wrote {out} ({', '.join(files)}) in {time.perf_counter() - start:.1f} s")
    return 0
