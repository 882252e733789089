"""Entry point of `make derive`: ``python -m derive [--out DIR] [--model NAME ...]``."""

from __future__ import annotations

import argparse
import gc
import os
import sys
import time
from pathlib import Path

# SymPy's caches keep 1,000 results per function by default, far fewer than one model's
# derivation revisits (sums, products, assumptions), so most of them are computed again:
# a larger cache saves about a tenth of the CPU of a run. Read when SymPy is first
# imported (the next lines), so it has no effect where SymPy already is (tests); no
# result depends on it.
os.environ.setdefault("SYMPY_CACHE_SIZE", "20000")

from ins_errors.errors import InsErrorsError
from ins_errors.symbolic.quick_sympy import quick_sympy

from .model_files import summary_table
from .pipeline import derive_all

ROOT = Path(__file__).resolve().parent.parent


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m derive",
                                     description="Regenerate generated/ from the models.")
    parser.add_argument("--out", type=Path, default=ROOT / "generated",
                        help="output folder (default: generated/ of this checkout)")
    parser.add_argument("--model", action="append", help="only this model (repeatable)")
    args = parser.parse_args(argv)
    # SymPy allocates millions of short-lived objects and almost no reference cycles:
    # the cyclic GC only walks them (0.6-0.8 s CPU of a full run even with a 50,000
    # first generation) and frees next to nothing (peak memory +10 %). Off for the run,
    # in the forked workers too; no result depends on it (restored afterwards: tests
    # call main in their own process)
    enabled = gc.isenabled()
    gc.disable()
    start = time.perf_counter()
    try:
        with quick_sympy():  # the same answers, in the forked workers too
            summaries = derive_all(args.out, args.model)
    except InsErrorsError as error:
        print(f"derive: error: {error}", file=sys.stderr)
        return 2
    finally:
        if enabled:
            gc.enable()
    print("\n".join(summary_table(summaries)))
    if args.model:
        print("derive: --model given, so the documents built across models (transfer "
              "functions, hand-check reports) were not rewritten")
    print(f"derive: wrote {args.out} in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
