"""``ins-errors cache info|clear``: the on-disk cache of compiled loops."""

from __future__ import annotations

import argparse


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "cache", help="show or clear the cache of compiled loops",
        description="Compiled simulation loops are kept in a cache folder "
                    "($INS_ERRORS_CACHE, default ~/.cache/ins-errors/casadi) limited to "
                    "$INS_ERRORS_CACHE_LIMIT MB (default 200); the least recently used "
                    "are deleted first when it is full.")
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    actions.add_parser("info", help="folder, number of libraries, size and limit")
    clear = actions.add_parser("clear", help="delete compiled libraries")
    clear.add_argument("--checkout", action="store_true",
                       help="only the libraries this checkout used and no other checkout "
                            "uses (what `make clean` runs)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ins_errors.numeric import cache

    folder = cache.directory()
    if args.action == "clear":
        count, freed = cache.clear(folder, checkout_only=args.checkout)
        which = "of this checkout " if args.checkout else ""
        print(f"removed {count} compiled libraries {which}({freed / 1e6:.1f} MB) from {folder}")
        return 0
    entries = cache.entries(folder) if folder.is_dir() else []
    total = sum(e.size for e in entries)
    mine = [e for e in entries if e.mine]
    print(f"folder: {folder}")
    print(f"libraries: {len(entries)}, {total / 1e6:.1f} MB "
          f"(limit {cache.limit_bytes() / 1e6:g} MB, least recently used deleted first)")
    print(f"used by this checkout: {len(mine)}, {sum(e.size for e in mine) / 1e6:.1f} MB")
    return 0
