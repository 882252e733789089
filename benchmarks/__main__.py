"""``python -m benchmarks [--quick] [NAME ...]``: run every ``bench_*`` module and print.

Each module exposes ``main(quick: bool = False)`` and prints its own figures (wall and
CPU seconds, ratios to the goals of its issue). Nothing is asserted: speed is reported,
never tested. ``NAME`` restricts the run to modules whose name contains it.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
import time
from pathlib import Path


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    quick = "--quick" in args
    wanted = [a for a in args if not a.startswith("--")]
    folder = Path(__file__).parent
    names = sorted(m.name for m in pkgutil.iter_modules([str(folder)])
                   if m.name.startswith("bench_"))
    if wanted:
        names = [n for n in names if any(w in n for w in wanted)]
    for name in names:
        print(f"== {name} {'(quick)' if quick else ''}")
        start = time.perf_counter()
        importlib.import_module(f"benchmarks.{name}").main(quick=quick)
        print(f"== {name}: {time.perf_counter() - start:.1f} s in all\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
