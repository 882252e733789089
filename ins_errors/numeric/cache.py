"""The on-disk cache of compiled loops: where it is, its size limit, who uses what.

Compiled libraries (``loop_<hash>.so``, see
:func:`ins_errors.numeric.integrators.compile_library`) are kept in one folder per user:
``$INS_ERRORS_CACHE`` (its ``casadi/`` subfolder where it has one, the user cache
folder's layout) or ``$XDG_CACHE_HOME/ins-errors/casadi`` (``~/.cache/...``). A
library's modification time is its last use (refreshed whenever it is loaded); when the
folder grows beyond its size limit (``$INS_ERRORS_CACHE_LIMIT`` in MB, default
:data:`DEFAULT_LIMIT_MB`) the least recently used libraries are deleted until it fits.

Several checkouts of the project may share the folder. Each records which libraries it
used as empty marker files under ``owners/<checkout id>/`` (the id is a hash of the
checkout's folder, so no path is written), which lets ``ins-errors cache clear
--checkout`` (``make clean``) remove one checkout's libraries and leave those another
checkout also uses.

A cache folder this process cannot write (a shared cache mounted read-only on a cluster)
is still read: its loops and model packages are used, and what is missing is made in a
private folder of this user in the temporary folder (:func:`private_directory`), said
once in one line (:func:`loops_directory`, :func:`writable_store`).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import stat
import tempfile
import time
import warnings
from collections.abc import Iterable, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path

from ins_errors.errors import InsErrorsError, InsErrorsNotice

DEFAULT_LIMIT_MB = 200.0
"""Default size limit of the cache folder, MB (10⁶ bytes)."""

PATTERN = "loop_*.so"
"""File names of compiled libraries in the cache."""

NOTES = "notes"
"""Subfolder of small notes that spare work on a cache hit (what a loop freezes, the
fingerprint of the code that writes loops): each named by a hash of what it answers."""

NOTE_LIMIT = 4096
"""Most notes kept; writing one beyond it deletes the older half."""


def root() -> Path | None:
    """The folder ``$INS_ERRORS_CACHE`` names, absolute; None when it is unset or empty.

    ``~`` and ``$VARIABLES`` in the value are expanded (a value quoted in a shell or set
    in a CI file arrives unexpanded), and a relative value is taken against the working
    folder of its first use. The absolute folder is written back to the variable, so the
    process keeps that folder if it changes its working folder, and the processes it
    starts (pool and Dask workers) use the same one.
    """
    text = os.environ.get("INS_ERRORS_CACHE")
    if not text:
        return None
    folder = os.path.abspath(os.path.expanduser(os.path.expandvars(text)))
    if folder != text:
        os.environ["INS_ERRORS_CACHE"] = folder
    return Path(folder)


LOOPS = "casadi"
"""Subfolder of the compiled loops in the user cache folder (``~/.cache/ins-errors/casadi``)."""


def directory() -> Path:
    """The folder of the compiled loops; may not exist.

    ``$INS_ERRORS_CACHE`` itself, or its :data:`LOOPS` subfolder when it has one: a
    variable pointed at a folder laid out as the user cache folder (``~/.cache/
    ins-errors``, loops in ``casadi/``) uses, shows, bounds and clears the loops it
    holds. Without the variable, ``$XDG_CACHE_HOME/ins-errors/casadi`` (``~/.cache/...``).
    """
    chosen = root()
    if chosen is not None:
        nested = chosen / LOOPS
        return nested if nested.is_dir() else chosen
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "ins-errors" / LOOPS


SCRATCH_PREFIX = "tmp"
"""Names of the compiles' scratch folders in the cache folder (``tmp`` + random)."""

SCRATCH_LOCK = ".compiling"
"""File in a scratch folder that the compiling process holds locked while it works."""

SCRATCH_GRACE = 60.0
"""Seconds after its creation during which a scratch folder without a held lock is
still taken as in use (the compile may not have locked it yet); where the system has no
file locks, a compile's whole time limit plus this."""

COMPILE_TIMEOUT = 600.0
"""Longest a compile may take, s."""


@contextmanager
def scratch_folder(folder: Path) -> Iterator[Path]:
    """A scratch folder inside ``folder`` for one compile, locked while in use.

    The folder holds :data:`SCRATCH_LOCK`, locked (``flock``) by this process until the
    block ends, so that ``ins-errors cache clear`` run meanwhile by another process
    leaves it alone (:func:`scratch_in_use`); it is deleted afterwards. A process that
    dies releases its lock: its folder is then a leftover that ``clear`` removes.

    Raises
    ------
    OSError
        When the folder cannot be made.
    """
    path = Path(tempfile.mkdtemp(prefix=SCRATCH_PREFIX, dir=folder))
    handle = None
    try:
        handle = open(path / SCRATCH_LOCK, "w")  # noqa: SIM115 (held until the end)
        try:
            import fcntl

            fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except (ImportError, OSError):
            pass  # no file locks here: scratch_in_use goes by age
        yield path
    finally:
        if handle is not None:
            handle.close()
        shutil.rmtree(path, ignore_errors=True)


def scratch_in_use(path: Path, now: float | None = None) -> bool:
    """Whether a compile is working in the scratch folder ``path`` now.

    In use: its :data:`SCRATCH_LOCK` is locked by a live process, or it is younger than
    :data:`SCRATCH_GRACE` seconds (just made, maybe not locked yet). Where the system has
    no file locks, any folder younger than a compile may take.

    Parameters
    ----------
    path : Path
        A folder of the cache named ``tmp*``.
    now : float, optional
        The current time (``time.time()``), s.
    """
    now = time.time() if now is None else now
    try:
        age = now - path.stat().st_mtime
    except OSError:
        return False  # gone
    try:
        import fcntl
    except ImportError:
        return age < COMPILE_TIMEOUT + SCRATCH_GRACE
    if age < SCRATCH_GRACE:
        return True
    try:
        with open(path / SCRATCH_LOCK) as handle:
            try:
                fcntl.flock(handle.fileno(), fcntl.LOCK_SH | fcntl.LOCK_NB)
            except BlockingIOError:
                return True  # held by the compiling process
            except OSError:
                return False  # a file system without locks: an old folder is a leftover
            fcntl.flock(handle.fileno(), fcntl.LOCK_UN)
    except OSError:
        return False  # no lock file: an older version's or an interrupted compile's
    return False


def limit_bytes() -> int:
    """The size limit in bytes (``$INS_ERRORS_CACHE_LIMIT`` MB, default 200 MB).

    Raises
    ------
    InsErrorsError
        If the variable is not a non-negative number.
    """
    text = os.environ.get("INS_ERRORS_CACHE_LIMIT")
    if not text:
        return int(DEFAULT_LIMIT_MB * 1e6)
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value >= 0 or value == float("inf"):
        raise InsErrorsError(f"INS_ERRORS_CACHE_LIMIT must be a size in MB (a non-negative "
                             f"number), got {text!r}")
    return int(value * 1e6)


def check_settings() -> None:
    """Check the cache's environment variables, as a command starts, before any work:
    ``$INS_ERRORS_CACHE_LIMIT`` is a size (:func:`limit_bytes`) and ``$INS_ERRORS_CACHE``,
    when set, names a folder or a path one can be made at (it is made absolute,
    :func:`root`; a missing folder is made when first written).

    Raises
    ------
    InsErrorsError
        One line naming the variable and what is wrong with it.
    """
    limit_bytes()
    chosen = root()
    if chosen is not None and (chosen.exists() or chosen.is_symlink()) \
            and not chosen.is_dir():
        raise unusable_cache(chosen, "it is not a folder")


def unusable_cache(folder: Path, why: str) -> InsErrorsError:
    """The one-line error of a ``$INS_ERRORS_CACHE`` that cannot be the cache folder."""
    return InsErrorsError(f"INS_ERRORS_CACHE={str(folder)!r} cannot be the cache folder "
                          f"({why}): point it at a folder, or unset it")


def can_write(folder: Path) -> bool:
    """Whether ``folder`` is (made if missing) a folder this process can write in."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return False
    return folder.is_dir() and os.access(folder, os.W_OK | os.X_OK)


def _why_not_a_folder(folder: Path) -> str:
    """Why ``folder`` cannot be made (for a path :func:`can_write` refused, not a folder)."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        return "it is a file" if folder.is_file() else (error.strerror
                                                         or type(error).__name__)
    return "not writable"


PRIVATE_NOTICE_VARIABLE = "INS_ERRORS_PRIVATE_CACHE_NOTICE_GIVEN"
"""Set (to ``1``) once a process has said that new work goes to the private folder; its
worker processes do not say it again."""

_PRIVATE: Path | None = None
_LINKED: set[tuple[Path, Path]] = set()
_PRIVATE_NOTICE_GIVEN = False
_PRIVATE_FOR: dict[Path, Path] = {}


def _shared_private() -> Path:
    """``ins-errors-<uid>`` in the temporary folder: the private folder kept between runs."""
    user = os.getuid() if hasattr(os, "getuid") else None
    return Path(tempfile.gettempdir()) / f"ins-errors-{'user' if user is None else user}"


def private_directory() -> Path:
    """This user's own folder for what the cache folder cannot take (made if missing).

    ``ins-errors-<uid>`` in the temporary folder, laid out as a ``$INS_ERRORS_CACHE``
    folder (loops in it, the other stores in subfolders) and kept between runs; when
    that path is not a folder of this user that others cannot write (another user may
    have made it), a new temporary folder for this process instead, removed when the
    process ends (it would otherwise be left behind by every run).
    """
    global _PRIVATE
    if _PRIVATE is not None and _PRIVATE.is_dir():
        return _PRIVATE
    user = os.getuid() if hasattr(os, "getuid") else None
    shared = _shared_private()
    try:
        shared.mkdir(mode=0o700, exist_ok=True)
        info = shared.lstat()
        if (stat.S_ISDIR(info.st_mode) and (user is None or info.st_uid == user)
                and not info.st_mode & 0o022 and os.access(shared, os.W_OK | os.X_OK)):
            _PRIVATE = shared
            return shared
    except OSError:
        pass
    _PRIVATE = Path(tempfile.mkdtemp(prefix="ins-errors-"))
    import atexit
    import shutil

    atexit.register(shutil.rmtree, _PRIVATE, ignore_errors=True)
    return _PRIVATE


def _private_notice(folder: Path, private: Path) -> None:
    """Say once per process (and not again in its workers) where new work goes."""
    global _PRIVATE_NOTICE_GIVEN
    if _PRIVATE_NOTICE_GIVEN:
        return
    _PRIVATE_NOTICE_GIVEN = True
    import multiprocessing

    if (os.environ.get(PRIVATE_NOTICE_VARIABLE)
            and multiprocessing.parent_process() is not None):
        return  # a worker: the process that started it has said so
    os.environ[PRIVATE_NOTICE_VARIABLE] = "1"
    kept = "kept in" if private == _shared_private() else "made (for this run only) in"
    if folder.is_dir():
        text = (f"ins-errors: the cache folder {str(folder)!r} is read-only: what it holds "
                f"is used, what it lacks is {kept} {str(private)!r}")
    else:
        text = (f"ins-errors: the cache folder {str(folder)!r} cannot be written; compiled "
                f"loops and other new work are {kept} {str(private)!r} instead")
    warnings.warn(text, InsErrorsNotice, stacklevel=3)


def _link_loops(source: Path, target: Path) -> None:
    """Link ``target/loop_*.so`` to each library of the read-only folder ``source``
    (once per process), so that a loop found there is not compiled again; links whose
    library has gone are removed."""
    if (source, target) in _LINKED:
        return
    _LINKED.add((source, target))
    try:
        for link in target.glob(PATTERN):
            if link.is_symlink() and not link.exists():
                link.unlink(missing_ok=True)
        names = [path.name for path in source.glob(PATTERN)]
    except OSError:
        return
    for name in names:
        link = target / name
        try:
            if not link.exists() and not link.is_symlink():
                link.symlink_to(source / name)
        except OSError:
            continue  # made meanwhile by another process, or no links here


def loops_directory(folder: Path | None = None) -> Path:
    """Where compiled loops are looked up and written: the loops' folder ``folder``
    (default :func:`directory`, made if missing) when it can be written.

    Otherwise this user's :func:`private_directory`: when ``folder`` is a folder (a
    read-only cache), the private folder links to every library it holds, which are used
    as they are; only missing loops are compiled, into the private folder, and the first
    one compiled there is said in one line (:func:`register`). The size limit is checked
    first, whether or not a loop is compiled.

    Raises
    ------
    InsErrorsError
        If ``$INS_ERRORS_CACHE_LIMIT`` is not a size, or ``$INS_ERRORS_CACHE`` names
        something that is not a folder and cannot be made one (a folder the user chose
        is not silently replaced).
    """
    folder = directory() if folder is None else folder
    limit_bytes()
    if can_write(folder):
        return folder
    if not folder.is_dir() and os.environ.get("INS_ERRORS_CACHE"):
        raise unusable_cache(folder, _why_not_a_folder(folder))
    private = private_directory()
    if folder.is_dir():
        _link_loops(folder, private)
    _PRIVATE_FOR[private] = folder
    return private


def store_folders(folder: Path) -> list[Path]:
    """Where entries of the store kept in ``folder`` (:func:`store_directory`) are looked
    up: ``folder``, then the same store in this user's :func:`private_directory` when
    ``folder`` cannot be written (a read-only cache)."""
    if can_write(folder):
        return [folder]
    return [folder, private_directory() / folder.name]


def writable_store(folder: Path) -> Path:
    """Where new entries of the store kept in ``folder`` (:func:`store_directory`) are
    written: ``folder`` when it can be written (made if missing), else the same store in
    this user's :func:`private_directory`, said in one line (once). Call it before the
    costly work whose result it keeps.

    Raises
    ------
    InsErrorsError
        If ``$INS_ERRORS_CACHE`` names something that is not a folder and cannot be made
        one.
    """
    if can_write(folder):
        return folder
    chosen = root()
    if chosen is not None and not chosen.is_dir():
        raise unusable_cache(chosen, _why_not_a_folder(chosen))
    private = private_directory() / folder.name
    private.mkdir(exist_ok=True)
    _private_notice(chosen if chosen is not None else folder.parent, private.parent)
    return private


def checkout_id() -> str:
    """A short id of the installed project folder (the checkout this code runs from)."""
    root = Path(__file__).resolve().parents[2]
    return hashlib.sha256(str(root).encode()).hexdigest()[:16]


def _owners(folder: Path) -> Path:
    return folder / "owners"


def touch(library: Path) -> None:
    """Mark ``library`` as used now (LRU order) by this checkout.

    A library of a read-only cache, found through its link in the private folder
    (:func:`loops_directory`), is left as it is: the owner of a file may set its times
    even in a folder that cannot be written, and the read-only cache's order was
    updated through the link."""
    if library.is_symlink() or not os.access(library.parent, os.W_OK | os.X_OK):
        return
    try:
        os.utime(library)
        _mark(library)
    except OSError:
        pass  # a read-only cache still works; only its order is not kept


def store_directory(name: str) -> Path:
    """The folder of the on-disk store ``name`` beside the compiled loops:
    ``$INS_ERRORS_CACHE/<name>``, else ``<name>`` next to the loops' folder in the user
    cache (e.g. ``~/.cache/ins-errors/motions``); may not exist."""
    chosen = root()
    return (chosen if chosen is not None else directory().parent) / name


def code_digest(files: Iterable[tuple[str, Path]], versions: Iterable[str]) -> str:
    """SHA-256 (hex) of the code a stored result follows from: each file's label and
    bytes, then the version strings and the entries' layout (:data:`ENTRY_FORMAT`)
    joined by ``|`` (the part of a store's key that makes a change of code, library or
    layout a new key).

    Parameters
    ----------
    files : iterable of (str, Path)
        A label (the file's name or package-relative path) and the file, in a fixed order.
    versions : iterable of str
        Python's and the libraries' versions, e.g. ``"sympy 1.13.3"``.
    """
    digest = hashlib.sha256()
    for label, path in files:
        digest.update(label.encode() + b"\0" + path.read_bytes() + b"\0")
    digest.update("|".join([*versions, ENTRY_FORMAT]).encode())
    return digest.hexdigest()


ENTRY_FORMAT = "sealed-1"
"""The layout of the cache's entries (part of every store's keys and of the loops' and
notes' names, so an entry of another layout is never read): each file ends with a seal
line (:func:`sealed`) that records the hash and length of what precedes it."""

_SEAL_START = b"\n# ins-errors cache entry: sha256 "
_SEAL_SIZE = len(_SEAL_START) + 64 + len(b", ") + 16 + len(b" bytes\n")


def sealed(data: bytes) -> bytes:
    """``data`` followed by its seal line: ``# ins-errors cache entry: sha256 <64 hex>,
    <16 digits> bytes`` on a line of its own (a comment in Python, ignored after the
    end of a shared library's contents), which :func:`unsealed` checks.

    Parameters
    ----------
    data : bytes
        The entry's contents.
    """
    digest = hashlib.sha256(data).hexdigest().encode()
    return data + _SEAL_START + digest + b", %016d bytes\n" % len(data)


def unsealed(raw: bytes) -> bytes | None:
    """The contents of a file written by :func:`sealed`, or None when it is not complete
    and unchanged: cut short (truncated, emptied), grown, altered, or never sealed."""
    if len(raw) < _SEAL_SIZE:
        return None
    body, seal = raw[:-_SEAL_SIZE], raw[-_SEAL_SIZE:]
    start = len(_SEAL_START)
    if not seal.startswith(_SEAL_START) or seal[start + 64:start + 66] != b", " \
            or not seal.endswith(b" bytes\n"):
        return None
    try:
        size = int(seal[start + 66:start + 82])
    except ValueError:
        return None
    if size != len(body) or hashlib.sha256(body).hexdigest().encode() != seal[start:start + 64]:
        return None
    return body


_DAMAGE_SAID: set[str] = set()


def report_damaged(path: Path, redo: str) -> None:
    """Say in one line that the cache entry ``path`` is damaged and is not used; ``redo``
    says what is done instead ("compiling it again"). Said for the first damaged entry
    of each folder in a process only (a store found damaged often holds many: one line,
    not one per entry). A :class:`RuntimeWarning` starting with ``ins-errors:``, which
    the command line prints as its one line on stderr."""
    folder = str(Path(path).parent)
    if folder in _DAMAGE_SAID:
        return
    _DAMAGE_SAID.add(folder)
    warnings.warn(f"ins-errors: the cache entry {str(path)!r} is damaged (incomplete or "
                  f"altered) and is not used; {redo}", InsErrorsNotice, stacklevel=3)


def read_entry(path: Path, redo: str) -> bytes | None:
    """The contents of the cache entry ``path`` (written by :func:`write_entry`), or None
    when there is none or it cannot be read; a damaged one (:func:`unsealed`) is said in
    one line (:func:`report_damaged`, with ``redo``) and never used: the caller computes
    the entry again and writes it over the damaged one.

    The file is read once, through one open file: an entry that another process replaces
    meanwhile (atomically, :func:`write_entry`) is read whole, the old one or the new.
    """
    try:
        raw = path.read_bytes()
    except OSError:
        return None
    body = unsealed(raw)
    if body is None:
        report_damaged(path, redo)
    return body


def write_entry(path: Path, data: bytes) -> None:
    """Keep ``data`` as the cache entry ``path``: sealed (:func:`sealed`) and written
    atomically (:func:`replace_file`), so a reader finds the whole entry or none.

    Raises
    ------
    OSError
        If the folder or the file cannot be written (``path`` is then unchanged).
    """
    replace_file(path, sealed(data))


def seal_file(path: Path) -> None:
    """Append its seal line (:func:`sealed`) to the file ``path`` (a compiled library in
    its scratch folder, before it is renamed into the cache: the bytes after the end of
    a shared library's contents are not read by the loader).

    Raises
    ------
    OSError
        If the file cannot be read or written.
    """
    data = path.read_bytes()
    with open(path, "ab") as out:
        out.write(sealed(data)[len(data):])


def intact(path: Path) -> bool:
    """Whether the file ``path`` (followed if a link) is complete and unchanged since it
    was sealed (:func:`unsealed`); False when it cannot be read. Checked before a
    compiled library is loaded: loading one cut short may kill the process (SIGBUS)."""
    try:
        return unsealed(path.read_bytes()) is not None
    except OSError:
        return False


def replace_file(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically: into a scratch file of the same folder
    (created if missing), renamed over ``path``; the scratch file never stays behind.
    The file gets the permissions ``open()`` would give it (not ``mkstemp``'s private
    ones: other users of a shared cache read it).

    Raises
    ------
    OSError
        If the folder or the file cannot be written (``path`` is then unchanged).
    """
    from ins_errors.output import open_modes

    path.parent.mkdir(parents=True, exist_ok=True)
    handle, scratch = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.",
                                       suffix=".tmp")
    try:
        with os.fdopen(handle, "wb") as out:
            out.write(data)
        os.chmod(scratch, open_modes()[0])  # readable by the users of a shared cache
        os.replace(scratch, path)
    except BaseException:
        Path(scratch).unlink(missing_ok=True)
        raise


def drop_least_recent(paths: Iterable[Path], keep: int) -> None:
    """Delete all but the ``keep`` most recently modified of ``paths`` (files; a path
    that has gone meanwhile is skipped)."""
    dated = []
    for path in paths:
        try:
            dated.append((path.stat().st_mtime, path))
        except OSError:
            continue
    dated.sort(reverse=True)
    for _, path in dated[max(keep, 0):]:
        path.unlink(missing_ok=True)


def _note_path(name: str) -> Path:
    return directory() / NOTES / f"{name}.{ENTRY_FORMAT}"


def read_note(name: str) -> str | None:
    """The note ``name`` (:data:`NOTES`), or None when there is none or it cannot be read.
    A damaged note (cut short, altered: :func:`read_entry`) is said in one line and
    taken as none, so the caller works the answer out again and writes it over."""
    data = read_entry(_note_path(name), "working its answer out again")
    try:
        return None if data is None else data.decode("utf-8")
    except UnicodeDecodeError:
        return None


def write_note(name: str, text: str) -> None:
    """Keep ``text`` as the note ``name`` (sealed and atomic, :func:`write_entry`;
    nothing happens where the folder cannot be written). Beyond :data:`NOTE_LIMIT` notes
    the older half is deleted."""
    path = _note_path(name)
    folder = path.parent
    try:
        write_entry(path, text.encode("utf-8"))
        notes = [path for path in folder.iterdir() if not path.name.startswith(".")]
        if len(notes) > NOTE_LIMIT:
            drop_least_recent(notes, len(notes) - len(notes) // 2)
    except OSError:
        pass


def register(library: Path) -> None:
    """Record a newly compiled ``library`` and evict the least recently used beyond the
    limit (never ``library`` itself); a library compiled into the private folder
    (:func:`loops_directory`) is said, once."""
    refused = _PRIVATE_FOR.get(library.parent)
    if refused is not None:  # the loops' folder cannot be written: say where it went
        _private_notice(refused, library.parent)
    try:
        _mark(library)
        evict(library.parent, limit_bytes(), keep=library)
    except OSError:
        pass


def _mark(library: Path) -> None:
    marker = _owners(library.parent) / checkout_id() / library.name
    if not marker.exists():
        marker.parent.mkdir(parents=True, exist_ok=True)
        marker.touch()


@dataclass
class Entry:
    """One compiled library in the cache."""

    path: Path
    size: int
    last_used: float
    mine: bool


def entries(folder: Path | None = None) -> list[Entry]:
    """The libraries in the cache, least recently used first."""
    folder = directory() if folder is None else folder
    mine_dir = _owners(folder) / checkout_id()
    found = []
    for path in folder.glob(PATTERN):
        if path.is_symlink():
            continue  # a link to a read-only cache's library (loops_directory)
        try:
            info = path.stat()
        except OSError:
            continue  # removed meanwhile
        found.append(Entry(path, info.st_size, info.st_mtime, (mine_dir / path.name).exists()))
    return sorted(found, key=lambda e: (e.last_used, e.path.name))


def evict(folder: Path, limit: int, keep: Path | None = None) -> list[Path]:
    """Delete least recently used libraries until the folder holds at most ``limit`` bytes.

    Returns
    -------
    list of pathlib.Path
        The deleted libraries.
    """
    current = entries(folder)
    total = sum(e.size for e in current)
    removed = []
    for entry in current:
        if total <= limit:
            break
        if keep is not None and entry.path.name == keep.name:
            continue
        if _remove(folder, entry.path):
            total -= entry.size
            removed.append(entry.path)
    return removed


def _remove(folder: Path, library: Path) -> bool:
    try:
        library.unlink()
    except FileNotFoundError:
        return False
    for marker in _owners(folder).glob(f"*/{library.name}"):
        marker.unlink(missing_ok=True)
    return True


def clear(folder: Path | None = None, checkout_only: bool = False) -> tuple[int, int]:
    """Delete compiled libraries: all of them (and the notes), or those this checkout used
    and no other.

    Returns
    -------
    (int, int)
        Number of libraries deleted and bytes freed.
    """
    folder = directory() if folder is None else folder
    count = freed = 0
    if not folder.is_dir():
        return 0, 0
    if not checkout_only:
        targets = [e for e in entries(folder)]
        shutil.rmtree(folder / NOTES, ignore_errors=True)
    else:
        mine = _owners(folder) / checkout_id()
        others = {m.name for d in _owners(folder).glob("*") if d != mine and d.is_dir()
                  for m in d.iterdir()}
        targets = [e for e in entries(folder) if e.mine and e.path.name not in others]
        for marker in mine.glob("*") if mine.is_dir() else []:
            marker.unlink(missing_ok=True)
        if mine.is_dir():
            mine.rmdir()
    for entry in targets:
        if _remove(folder, entry.path):
            count += 1
            freed += entry.size
    _prune_owners(folder)
    return count, freed


def _prune_owners(folder: Path) -> None:
    """Delete the marks of libraries no longer in ``folder`` and the folders of
    :func:`_owners` left empty (``cache clear`` left ``owners/<checkout>/`` behind)."""
    owners = _owners(folder)
    for checkout in owners.glob("*") if owners.is_dir() else ():
        if not checkout.is_dir() or checkout.is_symlink():
            continue
        for marker in checkout.iterdir():
            if not (folder / marker.name).exists():
                marker.unlink(missing_ok=True)
        with suppress(OSError):  # marks of libraries still there, or one made meanwhile
            checkout.rmdir()
    with suppress(OSError):
        owners.rmdir()


def usage(folder: Path) -> tuple[int, int]:
    """Number of files and their bytes under ``folder`` (recursively; 0, 0 if missing).

    Raises
    ------
    OSError
        If ``folder`` exists but cannot be read.
    """
    files = size = 0
    if not folder.is_dir():
        return 0, 0
    for root, _, names in os.walk(folder, onerror=_raise):
        for name in names:
            try:
                size += os.lstat(os.path.join(root, name)).st_size
            except FileNotFoundError:
                continue  # removed meanwhile
            files += 1
    return files, size


def empty(folder: Path) -> tuple[int, int]:
    """Delete everything inside ``folder`` (the folder itself is kept; nothing happens if
    it is missing).

    Returns
    -------
    (int, int)
        Number of files deleted and their bytes.

    Raises
    ------
    OSError
        If something in ``folder`` cannot be deleted.
    """
    files, size = usage(folder)
    if not folder.is_dir():
        return 0, 0
    for root, folders, names in os.walk(folder, topdown=False, onerror=_raise):
        for name in names:
            Path(root, name).unlink(missing_ok=True)
        for name in folders:
            path = Path(root, name)
            try:
                path.unlink() if path.is_symlink() else path.rmdir()
            except FileNotFoundError:
                continue  # removed meanwhile
    return files, size


def _raise(error: OSError) -> None:
    raise error
