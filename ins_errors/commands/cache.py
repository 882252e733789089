"""``ins-errors cache info|clear``: the on-disk cache of compiled loops."""

from __future__ import annotations

import argparse
import json


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "cache", help="show or clear the cache of compiled loops",
        description="Compiled simulation loops are kept in a cache folder "
                    "($INS_ERRORS_CACHE, default ~/.cache/ins-errors/casadi) limited to "
                    "$INS_ERRORS_CACHE_LIMIT MB (default 200); the least recently used "
                    "are deleted first when it is full. Both actions take --json for "
                    "machine-readable output.")
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    info = actions.add_parser("info", help="folder, number of libraries, size and limit")
    clear = actions.add_parser("clear", help="delete compiled libraries")
    clear.add_argument("--checkout", action="store_true",
                       help="only the libraries this checkout used and no other checkout "
                            "uses (what `make clean` runs)")
    for action in (info, clear):
        action.add_argument("--json", action="store_true", help="machine-readable output")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ins_errors.numeric import cache

    folder = cache.directory()
    if args.action == "clear":
        count, freed = cache.clear(folder, checkout_only=args.checkout)
        if args.json:
            print(json.dumps({"folder": str(folder), "removed": count, "bytes_freed": freed,
                              "checkout_only": args.checkout}))
            return 0
        which = "of this checkout " if args.checkout else ""
        print(f"removed {count} compiled libraries {which}({freed / 1e6:.1f} MB) from {folder}")
        return 0
    entries = cache.entries(folder) if folder.is_dir() else []
    total = sum(e.size for e in entries)
    mine = [e for e in entries if e.mine]
    if args.json:
        print(json.dumps({"folder": str(folder), "libraries": len(entries), "bytes": total,
                          "limit_bytes": cache.limit_bytes(), "checkout_libraries": len(mine),
                          "checkout_bytes": sum(e.size for e in mine)}))
        return 0
    print(f"folder: {folder}")
    print(f"libraries: {len(entries)}, {total / 1e6:.1f} MB "
          f"(limit {cache.limit_bytes() / 1e6:g} MB, least recently used deleted first)")
    print(f"used by this checkout: {len(mine)}, {sum(e.size for e in mine) / 1e6:.1f} MB")
    return 0
