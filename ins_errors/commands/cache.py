"""``ins-errors cache info|clear``: every on-disk store of the user cache folder."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

from ins_errors.errors import InsErrorsError
from ins_errors.json_output import emit


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "cache", help="show or clear the on-disk caches (compiled loops and the rest)",
        description="Work that is costly to redo is kept on disk, in folders under "
                    "$INS_ERRORS_CACHE (compiled loops in the folder itself, the others "
                    "in subfolders; a folder with a casadi/ subfolder, such as "
                    "~/.cache/ins-errors, keeps them there; without the variable, "
                    "~/.cache/ins-errors/casadi for "
                    "the loops and ~/.cache/ins-errors/<store> for the others, "
                    "$XDG_CACHE_HOME in place of ~/.cache where it is set). Compiled "
                    "loops are bounded by size, $INS_ERRORS_CACHE_LIMIT MB (default 200, "
                    "least recently used deleted first); notes of frozen states, "
                    "generated model code, CasADi functions of the studies, flown motions, "
                    "propagations and structured variations by a number of files or "
                    "versions each; pint's parsed unit definitions by one set per pint "
                    "installation; leftovers of "
                    "interrupted or older runs beside the loops are shown and cleared "
                    "too. Everything is rebuilt when needed. Both actions take --json.")
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    info = actions.add_parser("info", help="each store's folder, files, size and bound")
    clear = actions.add_parser("clear", help="empty every store (loops and the rest)")
    clear.add_argument("--checkout", action="store_true",
                       help="only the compiled loops this checkout used and no other "
                            "checkout uses (what `make clean` runs); the other stores "
                            "do not record who used an entry and are kept")
    for action in (info, clear):
        action.add_argument("--json", action="store_true", help="machine-readable output")
    parser.set_defaults(func=run)


FLAT_LOOPS = ("loop_*.so", "notes", "owners")
"""Names, in a ``$INS_ERRORS_CACHE`` folder whose loops are in its ``casadi/`` subfolder,
of the loops, notes and owner marks kept in the folder itself (before it had that
subfolder, e.g. by a version that did not look for it): no longer used."""

LEFTOVERS = ("tmp*", "writer_*.key", "verified-generated.json")
"""Names of entries of the compiled loops' folder that no current store keeps: scratch
folders of compiles that were interrupted (``tempfile``'s ``tmp`` prefix), fingerprint
files an older version wrote beside the loops, the test suite's record of verified
generated code (tests/test_generated_fresh.py)."""


@dataclass(frozen=True)
class Store:
    """One on-disk store besides the compiled loops.

    Attributes
    ----------
    name : str
        Short name (the folder's own name).
    folder : pathlib.Path
        Where it is kept.
    holds : str
        What it keeps.
    bound : str
        How it is kept from growing.
    limit : dict
        The bound as numbers (``{"files": n}`` or ``{"versions_per_name": n}``), empty
        where there is none.
    patterns : tuple of str
        Only the entries of ``folder`` whose names match these (glob patterns) belong to
        the store; empty: all of the folder.
    """

    name: str
    folder: Path
    holds: str
    bound: str
    limit: dict
    patterns: tuple[str, ...] = ()

    def _parts(self, removing: bool = False) -> list[Path]:
        """The store's entries; when ``removing``, without the scratch folders of
        compiles running now (another process would find its files gone)."""
        from ins_errors.numeric import cache

        if not self.folder.is_dir():
            return []
        parts = sorted({p for pattern in self.patterns for p in self.folder.glob(pattern)})
        if removing:
            parts = [p for p in parts if not (p.name.startswith(cache.SCRATCH_PREFIX)
                                              and p.is_dir() and cache.scratch_in_use(p))]
        return parts

    def usage(self) -> tuple[int, int]:
        """Number of files and bytes in the store (0, 0 if its folder is missing)."""
        from ins_errors.numeric import cache

        return self._tally(cache.usage, remove=False)

    def empty(self) -> tuple[int, int]:
        """Delete the store's contents; returns the files and bytes deleted."""
        from ins_errors.numeric import cache

        return self._tally(cache.empty, remove=True)

    def _tally(self, folder_tally, remove: bool) -> tuple[int, int]:
        """Files and bytes of the store's parts, each folder counted by ``folder_tally``
        (``cache.usage`` or ``cache.empty``); with ``remove`` the parts are deleted."""
        if not self.patterns:
            return folder_tally(self.folder)
        files = size = 0
        for path in self._parts(removing=remove):
            if path.is_dir() and not path.is_symlink():
                more, extra = folder_tally(path)
                if remove:
                    path.rmdir()
            else:
                try:
                    more, extra = 1, path.lstat().st_size
                except FileNotFoundError:
                    continue  # removed meanwhile
                if remove:
                    path.unlink(missing_ok=True)
            files, size = files + more, size + extra
        return files, size


def stores() -> list[Store]:
    """The stores besides the compiled loops, each at the folder its own module uses."""
    from ins_errors import model_lookup, units
    from ins_errors.checker import motion_store, propagation_store
    from ins_errors.numeric import cache
    from ins_errors.studies import function_cache
    from ins_errors.symbolic import variation_store

    chosen = cache.root()
    flat = []
    if chosen is not None and cache.directory() != chosen:  # the user cache's layout
        unused = Store("unused", chosen,
                       "compiled loops and notes kept in the folder itself, not in its "
                       f"{cache.LOOPS}/ (no longer used)",
                       "none: not used; cache clear removes them", {}, patterns=FLAT_LOOPS)
        flat = [unused] if unused._parts() else []
    return [
        Store("notes", cache.directory() / cache.NOTES,
              "notes of compiled loops (frozen states, code fingerprint)",
              f"at most {cache.NOTE_LIMIT} notes, the older half dropped beyond",
              {"files": cache.NOTE_LIMIT}),
        Store("models", model_lookup.models_cache_directory(),
              "generated code of model files",
              f"the {model_lookup.KEEP_VERSIONS} newest versions of each model file",
              {"versions_per_name": model_lookup.KEEP_VERSIONS}),
        Store("units", units.units_cache_directory(), "pint's parsed unit definitions",
              "one set per pint installation; those of deleted installations and "
              "earlier versions removed",
              {}),
        Store("functions", function_cache.cache_directory(),
              "CasADi functions of the methodological studies",
              f"the {function_cache.KEEP_VERSIONS} most recently used versions of each",
              {"versions_per_name": function_cache.KEEP_VERSIONS}),
        Store("motions", motion_store.folder(), "flown motions of the matrix checks",
              f"the {motion_store.KEEP} most recently used",
              {"files": motion_store.KEEP}),
        Store("transitions", propagation_store.folder(),
              "propagations of the matrix checks",
              f"at most {propagation_store.KEEP}; beyond, the least recently used "
              f"dropped down to {propagation_store.kept_after_prune()}",
              {"files": propagation_store.KEEP}),
        Store("variations", variation_store.folder(),
              "structured variations of models (the hand-derivation checker's and the "
              "documents' error lines)",
              f"the {variation_store.KEEP} most recently used",
              {"files": variation_store.KEEP}),
        Store("leftovers", cache.directory(),
              "scratch folders of interrupted compiles, files of older versions, the "
              "test suite's note of verified generated code",
              "none (small; only what an interrupted or older run left)", {},
              patterns=LEFTOVERS),
        *flat,
    ]


def _check_folder(folder: Path) -> None:
    if folder.exists() and not folder.is_dir():
        raise InsErrorsError(f"the cache folder {str(folder)!r} is not a folder "
                             "(see $INS_ERRORS_CACHE)")


def _refuse_unmakeable() -> None:
    """Refuse a ``$INS_ERRORS_CACHE`` folder that is missing and cannot be made, with the
    line every other command gives when it would write there (``/proc/nonexist``); the
    folder is made to find out and removed again (``info`` and ``clear`` leave no new
    folder behind). A missing folder that can be made is shown as empty."""
    from ins_errors.numeric import cache

    chosen = cache.root()
    if chosen is None or chosen.is_dir():
        return
    missing = [chosen, *(p for p in chosen.parents if not p.exists())]
    try:
        chosen.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        why = error.strerror or type(error).__name__
        raise cache.unusable_cache(chosen, why) from None
    for made in missing:  # the deepest first; a folder filled meanwhile is kept
        try:
            made.rmdir()
        except OSError:
            break


def _failed(action: str, folder: Path, error: OSError) -> InsErrorsError:
    where = error.filename or folder
    return InsErrorsError(f"cannot {action} the cache folder {str(folder)!r}: "
                          f"{error.strerror or error} ({where})")


def _count(count: int, one: str, many: str) -> str:
    """``count`` and the noun: ``1 file``, ``0 files``, ``2 files``."""
    return f"{count} {one if count == 1 else many}"


def _size(count: int) -> str:
    return f"{count / 1e6:.1f} MB" if count >= 1e5 else f"{count / 1e3:.1f} kB"


def run(args: argparse.Namespace) -> int:
    from ins_errors.numeric import cache

    folder = cache.directory()
    _check_folder(folder)
    _refuse_unmakeable()
    others = stores()
    if args.action == "clear":
        return _clear(args, folder, others)
    limit = cache.limit_bytes()
    try:
        entries = cache.entries(folder) if folder.is_dir() else []
        used = {store.name: store.usage() for store in others}
    except OSError as error:
        raise _failed("read", folder, error) from None
    total = sum(e.size for e in entries)
    mine = [e for e in entries if e.mine]
    rows = [{"name": "loops", "folder": str(folder), "files": len(entries), "bytes": total,
             "holds": "compiled simulation loops",
             "bound": f"{limit / 1e6:g} MB, least recently used deleted first",
             "limit": {"bytes": limit}}]
    rows += [{"name": s.name, "folder": str(s.folder), "files": used[s.name][0],
              "bytes": used[s.name][1], "holds": s.holds, "bound": s.bound,
              "limit": s.limit} for s in others]
    if args.json:
        emit({"folder": str(folder), "libraries": len(entries), "bytes": total,
              "limit_bytes": limit, "checkout_libraries": len(mine),
              "checkout_bytes": sum(e.size for e in mine), "stores": rows,
              "total_files": sum(r["files"] for r in rows),
              "total_bytes": sum(r["bytes"] for r in rows)})
        return 0
    print(f"folder: {folder}")
    print(f"libraries: {len(entries)}, {total / 1e6:.1f} MB "
          f"(limit {limit / 1e6:g} MB, least recently used deleted first)")
    print(f"used by this checkout: {len(mine)}, {sum(e.size for e in mine) / 1e6:.1f} MB")
    print("stores:")
    width = max(len(r["folder"]) for r in rows)
    for r in rows:
        print(f"  {r['name']:<12} {r['folder']:<{width}} {r['files']:>6} files "
              f"{_size(r['bytes']):>9}  bound: {r['bound']}")
    print(f"total: {sum(r['files'] for r in rows)} files, "
          f"{sum(r['bytes'] for r in rows) / 1e6:.1f} MB")
    return 0


def _clear(args: argparse.Namespace, folder: Path, others: list[Store]) -> int:
    from ins_errors.numeric import cache

    rows = []
    try:
        if not args.checkout:
            for store in others:
                files, freed = store.empty()
                rows.append({"name": store.name, "folder": str(store.folder),
                             "removed": files, "bytes_freed": freed})
        count, freed = cache.clear(folder, checkout_only=args.checkout)
    except OSError as error:
        raise _failed("clear", folder, error) from None
    rows.insert(0, {"name": "loops", "folder": str(folder), "removed": count,
                    "bytes_freed": freed})
    if args.json:
        emit({"folder": str(folder), "removed": count, "bytes_freed": freed,
              "checkout_only": args.checkout, "stores": rows})
        return 0
    which = "of this checkout " if args.checkout else ""
    print(f"removed {_count(count, 'compiled library', 'compiled libraries')} {which}"
          f"({freed / 1e6:.1f} MB) from {folder}")
    if args.checkout:
        print("kept the other stores (" + ", ".join(s.name for s in others)
              + "): they do not record which checkout used an entry")
        return 0
    for row in rows[1:]:
        print(f"removed {_count(row['removed'], 'file', 'files')} ({_size(row['bytes_freed'])}) "
              f"of {row['name']} from {row['folder']}")
    return 0

