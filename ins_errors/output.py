"""Every file ins-errors writes goes through here: atomically, and never over a stranger's.

Three rules, one place:

* **Atomic.** A file is written to a temporary file beside it and renamed over the
  target (:func:`os.replace`), so an interrupted run leaves either the old file or the
  new one, never half of one.
* **Folders.** A report folder that ins-errors writes holds a small manifest
  (:data:`MANIFEST`) listing the files it wrote. Writing into that folder again replaces
  those files and removes the ones the new run does not write (no stale ``case_3.png``
  beside a two-case report); files that someone else put there are left alone. A folder
  that is not empty and has no manifest is refused, pointing to ``--force``. The
  manifest never lags behind the folder: a file's name is recorded in it before the
  file is written, so a run interrupted between two files (Ctrl-C while ``curves.mat``
  is written) leaves a folder the next run writes into again without ``--force``.
* **All or nothing.** A folder holds one run's files, never a mix of two: until
  :meth:`OutputFolder.finish`, each file it replaces (and each it removes) is kept, as a
  hard link, in a hidden undo folder inside it. A command stopped before ``finish``
  (Ctrl-C, SIGTERM, an error raised through :func:`ins_errors.cli.main`) takes its own
  run back (:func:`take_back_unfinished`): the earlier files are put back, the new ones
  removed, and one line on stderr names the folder. Only the process that made an undo
  folder takes it back, and only on such a failure; at a normal exit an unfinished run
  keeps its files (its undo folder is discarded). An undo folder of another process (a
  run going on now, or one killed outright) is never taken back: the folder is refused
  until that run ends, or ``--force`` discards the undo folder.
* **One-line errors.** A missing or read-only folder, a target that is a directory, a
  full disk: an :class:`~ins_errors.errors.InsErrorsError` naming the path.

Single files named on the command line (``--plot out/drift.png``, ``--markdown``,
``--report``) are replaced; ins-errors says so on stderr when one already existed.
"""

from __future__ import annotations

import atexit
import errno
import json
import os
import shutil
import signal
import socket
import sys
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from datetime import datetime
from pathlib import Path

from ins_errors.errors import InsErrorsError

MANIFEST = ".ins-errors-files.json"
"""Name of the file, inside an output folder, that lists what ins-errors wrote there."""

UNDO_PREFIX = ".ins-errors-undo-"
"""Names of the hidden folders, inside an output folder, that keep what a run still
writing has replaced or removed (:class:`OutputFolder`)."""

DONE_PREFIX = ".ins-errors-done-"
"""An undo folder renamed so once its run has finished (removed right after)."""

JOURNAL = "journal.json"
"""The file of an undo folder naming its process and the files the run made new."""

KEPT = "files"
"""The subfolder of an undo folder holding the files the run replaced or removed."""


PNG_ZLIB_RLE = 3
"""zlib's ``Z_RLE`` strategy, Pillow's ``compress_type`` for PNG files."""

DRAWING_RC = {"text.hinting": "no_hinting"}
"""matplotlib settings while :func:`save_figure` draws.

Unhinted glyphs: FreeType's hinting (``text.hinting: default``, matplotlib 3.11's
default) runs the font's hinting program for every glyph drawn, about half the cost of
the many tick labels of a report's figures; unhinted text at these sizes reads the
same (glyph outlines are not snapped to the pixel grid; positions are unchanged).
"""


class OutputError(InsErrorsError):
    """An output file or folder that cannot be written (or must not be overwritten)."""


def umask() -> int:
    """This process's file-creation mask: from ``/proc/self/status`` where there is one
    (Linux), else by setting it and setting it back (a thread creating a file in that
    instant would get the mask set meanwhile)."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def open_modes() -> tuple[int, int]:
    """The permissions ``open()`` and ``mkdir()`` give a new file and folder here
    (``0o644`` and ``0o755`` under the usual umask): for files and folders made by
    ``mkstemp``/``mkdtemp``, which make them private, before they are renamed into place
    where others (a shared cache, a shared checkout) read them."""
    mask = umask()
    return 0o666 & ~mask, 0o777 & ~mask


def _reason(error: OSError) -> str:
    return error.strerror or str(error)


SHOWN_LENGTH = 80
"""Longest path quoted whole in a message; a longer one is shortened in the middle."""


def shown(path: str | Path) -> str:
    """``path`` quoted for a one-line message, shortened in the middle when huge.

    Parameters
    ----------
    path : str or Path
        Any path (possibly thousands of characters, e.g. a name the system refused).

    Returns
    -------
    str
        ``'out/report.md'``, or ``'aaaa…aaaa.md' (304 characters)`` for a long one.
    """
    text = str(path)
    if len(text) <= SHOWN_LENGTH:
        return repr(text)
    head, tail = text[:SHOWN_LENGTH // 2], text[-SHOWN_LENGTH // 4:]
    return f"{head + '…' + tail!r} ({len(text)} characters)"


def os_error_line(error: OSError, doing: str = "cannot use") -> str:
    """One line for an :class:`OSError`: what was done, the path(s) and the system's reason.

    Parameters
    ----------
    error : OSError
        The error (``filename`` and ``strerror`` are used when set).
    doing : str
        What failed, e.g. ``"cannot write"``.
    """
    where = " ".join(shown(name) for name in (error.filename, error.filename2)
                     if name is not None)
    return f"{doing} {where}: {_reason(error)}" if where else f"{doing}: {_reason(error)}"


def check_file(path: str | Path) -> Path:
    """Check, before any computing, that ``path`` can be written; leave nothing behind.

    Writability is tried, not read from permission bits (which root, a read-only mount or
    a virtual file system such as ``/proc`` make meaningless): the folder takes a
    temporary file named as :func:`write_with` names its own, removed again (of a folder
    still to be made, its nearest existing parent takes a temporary folder), and an
    existing ``path`` is opened for appending, without writing (its contents and
    modification time are unchanged).

    Raises
    ------
    OutputError
        When ``path`` is a folder, one of its parents is a file, or the file or its
        folder cannot be written (one line with the system's reason).
    """
    path = Path(path)
    try:
        if path.is_dir():
            raise OutputError(f"cannot write {shown(path)}: it is a folder; give a file name")
        parent = path.parent
        while not parent.exists() and parent != parent.parent:
            parent = parent.parent
        if not parent.is_dir():
            raise OutputError(f"cannot write {shown(path)}: {shown(parent)} is a file, "
                              "not a folder")
    except OSError as error:  # e.g. a name longer than the file system allows
        raise OutputError(f"cannot write {shown(path)}: {_reason(error)}") from None
    if parent != path.parent:  # missing folders, to be made in parent
        try:
            os.rmdir(tempfile.mkdtemp(prefix=".ins-errors-", dir=parent))
        except OSError as error:
            raise OutputError(f"cannot write {shown(path)}: no folder can be made in "
                              f"{shown(parent)} ({_reason(error)})") from None
        return path
    try:
        handle, probe = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix,
                                         dir=parent)
    except OSError as error:
        if error.errno == errno.ENAMETOOLONG:  # the writer's scratch name is longer still
            raise OutputError(f"cannot write {shown(path)}: its name is too long to be "
                              "written through a scratch file beside it (the file system's "
                              "limit); give a shorter name") from None
        raise OutputError(f"cannot write {shown(path)}: folder {shown(parent)} takes no "
                          f"new files ({_reason(error)})") from None
    os.close(handle)
    os.unlink(probe)
    if path.exists():
        try:
            with open(path, "ab"):
                pass
        except OSError as error:
            raise OutputError(f"cannot write {shown(path)}: it cannot be opened for "
                              f"writing ({_reason(error)})") from None
    return path


def figure_format(path: str | Path) -> str:
    """The image format a plot file's suffix names (``png`` for ``out/drift.png``).

    Raises
    ------
    OutputError
        When the name has no suffix, or one matplotlib cannot write (the message lists
        the usual ones).
    """
    from matplotlib.backend_bases import FigureCanvasBase

    suffix = Path(path).suffix.lstrip(".").lower()
    known = FigureCanvasBase.get_supported_filetypes()
    if suffix in known:
        return suffix
    what = f"its suffix .{suffix} is not an image format" if suffix else "it has no suffix"
    raise OutputError(f"cannot write the plot {shown(path)}: {what}; end the name with the "
                      "format, such as .png, .pdf or .svg")


def check_figure(path: str | Path) -> Path:
    """:func:`check_file` for a plot: also refuses a name without a known image suffix.

    Raises
    ------
    OutputError
        See :func:`check_file` and :func:`figure_format`.
    """
    figure_format(path)
    return check_file(path)


def _prepare_parent(path: Path) -> None:
    check_file(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputError(f"cannot create folder {shown(path.parent)}: "
                          f"{_reason(error)}") from None
    if not path.parent.is_dir():
        raise OutputError(f"cannot write {shown(path)}: {shown(path.parent)} is not a folder")


def write_with(path: str | Path, writer: Callable[[Path], object]) -> Path:
    """Write ``path`` atomically: ``writer(temporary_path)`` fills a temporary file beside
    it, which is then renamed over ``path``.

    Parameters
    ----------
    path : str or Path
        Target file; missing parent folders are created.
    writer : callable
        Called with the temporary path (same folder and suffix as ``path``, so tools
        that choose a format by suffix, such as matplotlib, pick the right one).

    Returns
    -------
    Path
        The written file.

    Notes
    -----
    Replacing an existing file is said on stderr, unless the file belongs to a folder
    that ins-errors manages (:class:`OutputFolder`), where replacing is the point.

    Raises
    ------
    OutputError
        One line naming the path and the reason.
    """
    path = Path(path)
    _prepare_parent(path)
    try:
        existed = path.exists()
        handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix,
                                             dir=path.parent)
    except OSError as error:
        raise OutputError(f"cannot write {shown(path)}: {_reason(error)}") from None
    os.close(handle)
    temporary = Path(temporary)
    try:
        writer(temporary)
        os.chmod(temporary, open_modes()[0])  # mkstemp makes it private: as open() would
        os.replace(temporary, path)
    except OSError as error:
        raise OutputError(f"cannot write {shown(path)}: {_reason(error)}") from None
    except ValueError as error:  # e.g. matplotlib: unknown image format
        raise OutputError(f"cannot write {shown(path)}: {error}") from None
    finally:
        temporary.unlink(missing_ok=True)
    if existed and not (path.parent / MANIFEST).exists():
        print(f"ins-errors: replaced {path}", file=sys.stderr)
    return path


def write_text(path: str | Path, text: str) -> Path:
    """Write UTF-8 text atomically (see :func:`write_with`)."""
    return write_with(path, lambda p: p.write_text(text, encoding="utf-8"))


def save_figure(figure, path: str | Path, close: bool = True, **options) -> Path:
    """Save a matplotlib figure atomically and close it (drawn with :data:`DRAWING_RC`).

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure.
    path : str or Path
        Target; its suffix (png, pdf, svg, ...) chooses the format.
    close : bool
        Close the figure afterwards (``False``: the caller draws it again).
    **options
        Passed to ``Figure.savefig`` (e.g. ``dpi``).
    """
    import matplotlib.pyplot as plt

    path = Path(path)
    try:
        fmt = figure_format(path)
    except OutputError:
        if close:
            plt.close(figure)
        raise
    if fmt == "png":
        # zlib's run-length strategy: the same pixels in about half the encoding time of
        # the default, for a file about 10 % larger (plots are mostly flat runs of colour)
        options.setdefault("pil_kwargs", {"compress_type": PNG_ZLIB_RLE})
    import matplotlib

    from ins_errors.text_layouts import remembered_layouts
    from ins_errors.tick_updates import ticks_updated_once

    try:
        with (_without_layout_placeholder(figure), matplotlib.rc_context(DRAWING_RC),
              remembered_layouts(), ticks_updated_once()):
            return write_with(path, lambda p: figure.savefig(p, format=fmt, **options))
    finally:
        if close:
            plt.close(figure)


@contextmanager
def _without_layout_placeholder(figure):
    """Save without the extra layout pass ``Figure.tight_layout`` leaves behind.

    ``tight_layout()`` lays the figure out once and leaves a placeholder layout engine
    that does nothing; ``savefig`` sees an engine and draws the whole figure once more
    (every tick and label) before drawing it for the file. The placeholder is taken away
    while saving and put back afterwards: the file is the same, one draw cheaper.
    """
    import matplotlib
    from matplotlib.layout_engine import PlaceHolderLayoutEngine

    engine = figure.get_layout_engine()
    automatic = (matplotlib.rcParams["figure.autolayout"]
                 or matplotlib.rcParams["figure.constrained_layout.use"])
    if automatic or not isinstance(engine, PlaceHolderLayoutEngine):
        yield  # (with an automatic layout, None would choose that one: leave it)
        return
    figure.set_layout_engine(None)
    try:
        yield
    finally:
        figure.set_layout_engine(engine)


class OutputFolder:
    """A folder of files written by one command (a report folder).

    Parameters
    ----------
    folder : str or Path
        The folder; created if missing.
    force : bool
        Write into a non-empty folder that ins-errors did not write (its other files
        are left alone), or into one holding another run's undo folder (discarded: the
        folder may hold a mix of runs until this run finishes).
    option : str
        The option that named the folder, for messages (``"--out"``).
    create : bool
        Create the folder now (``False``: only check, e.g. before a long computation).

    Raises
    ------
    OutputError
        When the folder is a file, cannot be created, or holds files of someone else
        or another run's undo folder (named with its process, host and start time), and
        ``force`` is false.

    Notes
    -----
    Use :meth:`write_text`, :meth:`save_figure` or :meth:`write_with` for every file,
    then :meth:`finish`, which removes the files of an earlier run that this run did not
    write and records the new list. Until then the manifest lists the earlier run's
    files and this run's so far (each recorded before it is written), so an interrupted
    run leaves a folder that is still ins-errors' own.

    The files are written in place (a caller may read one back, e.g. a plot embedded in
    a page), and whatever a file replaces is first kept in a hidden undo folder inside
    the folder (:data:`UNDO_PREFIX`; a hard link, or the file moved there where the file
    system has no links), as is each file :meth:`finish` removes. :meth:`finish` ends
    by renaming the undo folder (the moment the new set becomes the folder's) and
    deleting it. A run that does not reach it is taken back by :meth:`take_back`: the
    folder holds the earlier run's files again, or, made by this run, is removed. The
    command line does so on its failure path (Ctrl-C, SIGTERM, an error:
    :func:`take_back_unfinished`), and so does ``with OutputFolder(...) as out:`` when
    an exception leaves the block (a block left normally finishes the run). A run never
    finished nor taken back keeps its files: at a normal exit of the process, or when
    this process opens the folder again, its undo folder is discarded.

    Only the process that made an undo folder takes it back. Another process's (a run
    writing there now, or one killed outright) makes the folder refused, naming that
    process, until it is gone or ``force`` discards it.
    """

    def __init__(self, folder: str | Path, force: bool = False, option: str = "--out",
                 create: bool = True):
        self.path = Path(folder)
        self.option = option
        self.written: list[str] = []
        self._undo: Path | None = None
        self._created: list[str] = []
        self._made = False
        self._force = force
        self._finished = False
        try:
            self._open(force, option, create)
        except OSError as error:  # e.g. a name longer than the file system allows
            raise OutputError(f"cannot write folder {shown(self.path)}: "
                              f"{_reason(error)}") from None

    def _open(self, force: bool, option: str, create: bool) -> None:
        if self.path.exists() and not self.path.is_dir():
            raise OutputError(f"{option} {shown(self.path)} is a file, not a folder")
        if self.path.is_dir():
            self._leftovers(force, discard=create)
        manifest = self.path / MANIFEST
        self.previous = self._read_manifest(manifest)
        self._listed = list(self.previous or ())  # what the manifest on disk lists
        foreign = self.path.is_dir() and self.previous is None and any(
            not _bookkeeping(p.name) for p in self.path.iterdir())
        if foreign and not force:
            raise OutputError(f"{option} {shown(self.path)} is not empty and was not "
                              "written by ins-errors: choose another folder or add "
                              "--force (replaces only the files ins-errors writes)")
        if not create:
            return
        self._made = not self.path.exists()
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise OutputError(f"cannot create folder {shown(self.path)}: "
                              f"{_reason(error)}") from None

    @staticmethod
    def _read_manifest(manifest: Path) -> list[str] | None:
        if not manifest.is_file():
            return None
        try:
            names = json.loads(manifest.read_text(encoding="utf-8"))["files"]
        except (OSError, ValueError, KeyError, TypeError):
            return []
        return [n for n in names if isinstance(n, str) and "/" not in n and "\\" not in n]

    def _leftovers(self, force: bool, discard: bool) -> None:
        """Deal with the undo folders in the folder before this run: another process's
        are refused (``force``: discarded), this process's unfinished ones (a run never
        finished) and finished ones' remains are discarded; ``discard`` false only
        checks."""
        for path in _bookkeeping_entries(self.path):
            owner = _UNFINISHED.get(path)
            if path.name.startswith(DONE_PREFIX):
                if discard:
                    shutil.rmtree(path, ignore_errors=True)
            elif owner is not None:  # this process's: the run keeps its files as they are
                if discard:
                    owner._abandon()
            elif not force:
                raise OutputError(_refusal(self.option, self.path, path))
            elif discard:
                _discard(path)

    def __enter__(self) -> OutputFolder:
        return self

    def __exit__(self, kind, error, trace) -> bool:
        """Finish the run when the block ends normally, take it back when an exception
        (Ctrl-C included) leaves it; inside a command of the command line
        (:func:`command_takes_back`) the command takes it back after its line saying
        why it stopped."""
        if kind is None:
            if not self._finished:
                self.finish()
        elif self._undo is not None and not _COMMAND_TAKES_BACK[0]:
            with _signals_held():
                self.take_back()
        return False

    def take_back(self) -> bool:
        """Take this unfinished run back (:func:`take_back`); nothing when it has not
        replaced anything yet or has finished.

        Returns
        -------
        bool
            True when the folder still exists.
        """
        if self._undo is None:
            return self.path.exists()
        return take_back(self._undo, self.option)

    def _abandon(self) -> None:
        """Leave this unfinished run's files as they are and discard its undo folder."""
        undo, self._undo = self._undo, None
        self._created = []
        if undo is not None:
            _UNFINISHED.pop(undo, None)
            _discard(undo)

    def file(self, name: str) -> Path:
        """The path of ``name`` inside the folder, recorded as written by this run.

        A name new to the manifest is added to it (on disk) before the file is written:
        an interruption before :meth:`finish` leaves a manifest that lists every file
        ins-errors put in the folder (the earlier run's and this run's so far). What the
        file will replace is kept first in the undo folder (see the class's notes).
        """
        if name not in self.written:
            try:
                self._keep(name)
            except OSError as error:
                raise OutputError(f"cannot write {shown(self.path / name)}: "
                                  f"{_reason(error)}") from None
            self.written.append(name)
            if name not in self._listed:
                self._listed.append(name)
                self._write_manifest(self._listed)
        return self.path / name

    def write_text(self, name: str, text: str) -> Path:
        """Write a text file of the folder atomically."""
        return write_text(self.file(name), text)

    def write_with(self, name: str, writer: Callable[[Path], object]) -> Path:
        """Write a file of the folder atomically with ``writer(temporary_path)``."""
        return write_with(self.file(name), writer)

    def save_figure(self, figure, name: str, **options) -> Path:
        """Save a matplotlib figure as a file of the folder, atomically."""
        return save_figure(figure, self.file(name), **options)

    def finish(self) -> list[Path]:
        """Remove the earlier run's files that this run did not write; record this run's.

        Returns
        -------
        list of Path
            The files written by this run.
        """
        try:
            self._keep(MANIFEST)
        except OSError as error:
            raise OutputError(f"cannot write {shown(self.path / MANIFEST)}: "
                              f"{_reason(error)}") from None
        for name in self.previous or ():
            if name not in self.written:
                try:
                    self._keep(name, move=True)
                except OSError as error:
                    raise OutputError(f"cannot remove {shown(self.path / name)} (written "
                                      f"by an earlier run): {_reason(error)}") from None
        self._write_manifest(self.written)
        self._listed = list(self.written)
        undo, self._undo = self._undo, None
        if undo is not None:  # the new set is complete: the rename makes it the folder's
            done = undo.with_name(DONE_PREFIX + undo.name[len(UNDO_PREFIX):])
            try:
                os.rename(undo, done)
            except OSError as error:
                self._undo = undo
                raise OutputError(f"cannot finish {shown(self.path)}: "
                                  f"{_reason(error)}") from None
            _UNFINISHED.pop(undo, None)
            shutil.rmtree(done, ignore_errors=True)
        self._created = []
        self._finished = True
        return [self.path / n for n in self.written]

    def _keep(self, name: str, move: bool = False) -> None:
        """Keep what ``name`` holds now in the undo folder (made on first use), or note
        it as new to the folder; ``move`` moves it there (a file :meth:`finish` removes).
        Each name once per run.

        Raises
        ------
        OSError
            When the file cannot be kept (the caller's message names it).
        OutputError
            When another run discarded this run's undo folder (``--force``).
        """
        undo = self._undo or self._start()
        if not undo.is_dir():
            raise OutputError(f"cannot write in {shown(self.path)}: another run into the "
                              "folder with --force discarded this run's undo folder; the "
                              "folder is that run's to finish")
        target, kept = self.path / name, undo / KEPT / name
        if os.path.lexists(kept) or name in self._created:
            return
        if not os.path.lexists(target):
            self._created.append(name)
            _write_journal(undo, self._made, self._created, self._started)
        elif target.is_dir() and not target.is_symlink():
            if move:  # never moved away (and deleted with the undo folder)
                raise IsADirectoryError(errno.EISDIR, "Is a directory")
            return  # not a file of ins-errors': writing it fails with its own line
        elif move:
            os.replace(target, kept)
        else:
            try:
                os.link(target, kept, follow_symlinks=False)
            except OSError:  # a file system without hard links
                os.replace(target, kept)

    def _start(self) -> Path:
        """Make this run's undo folder, then refuse (``force``: discard) another
        process's that came meanwhile: of two runs starting together at least one
        sees the other's and backs off, never both go on."""
        self._started = datetime.now().astimezone().isoformat(sep=" ", timespec="seconds")
        try:
            self.path.mkdir(parents=True, exist_ok=True)
            undo = Path(tempfile.mkdtemp(prefix=UNDO_PREFIX, dir=self.path))
            (undo / KEPT).mkdir()
            _write_journal(undo, self._made, [], self._started)
        except OSError as error:
            raise OutputError(f"cannot write in {shown(self.path)}: "
                              f"{_reason(error)}") from None
        for other in _bookkeeping_entries(self.path):
            if (other == undo or other in _UNFINISHED
                    or not other.name.startswith(UNDO_PREFIX)):
                continue
            if not self._force:
                shutil.rmtree(undo, ignore_errors=True)
                raise OutputError(_refusal(self.option, self.path, other))
            _discard(other)
        self._undo = undo
        _UNFINISHED[undo] = self
        _register_exit()
        if os.path.lexists(self.path / MANIFEST):
            self._keep(MANIFEST)
        else:
            self._created.append(MANIFEST)
            _write_journal(undo, self._made, self._created, self._started)
        return undo

    def _write_manifest(self, names: list[str]) -> None:
        write_text(self.path / MANIFEST, json.dumps({"written_by": "ins-errors",
                                                    "files": names}, indent=1) + "\n")


_UNFINISHED: dict[Path, OutputFolder] = {}
"""Undo folders of this process's unfinished :class:`OutputFolder` runs, and each run."""

_EXIT_REGISTERED: list[int] = []
"""The process id that registered :func:`_discard_at_exit` (a forked child leaves its
parent's runs alone)."""


def _bookkeeping(name: str) -> bool:
    """Whether ``name`` is an undo folder, live or finished, rather than a file of the
    folder's own."""
    return name.startswith((UNDO_PREFIX, DONE_PREFIX))


def _bookkeeping_entries(folder: Path) -> list[Path]:
    """The undo folders, live or finished, inside ``folder`` (none when unreadable)."""
    try:
        return sorted(p for p in folder.iterdir() if _bookkeeping(p.name))
    except OSError:
        return []


def _write_journal(undo: Path, made: bool, created: list[str], started: str) -> None:
    """Record in ``undo`` this process (id, host, start time), whether it made the
    folder, and the names it made new (removed when the run is taken back)."""
    journal = undo / JOURNAL
    scratch = undo / (JOURNAL + ".new")
    scratch.write_text(json.dumps({"pid": os.getpid(), "host": socket.gethostname(),
                                   "started": started, "made_folder": made,
                                   "created": created}), encoding="utf-8")
    os.replace(scratch, journal)


def _refusal(option: str, folder: Path, undo: Path) -> str:
    """The one line refusing ``folder``, which holds ``undo``, another process's."""
    try:
        journal = json.loads((undo / JOURNAL).read_text(encoding="utf-8"))
        who = (f"process {int(journal['pid'])} on host {journal.get('host', '?')}, "
               f"started {journal.get('started', '?')}")
    except (OSError, ValueError, KeyError, TypeError):
        who = "its journal cannot be read"
    return (f"{option} {shown(folder)} holds the undo folder {undo.name} of another "
            f"ins-errors run ({who}), which is writing there now or was stopped "
            "before it finished (killed); that folder keeps the files the run "
            "replaced. Wait for that run to end, or add --force (discards the undo "
            "folder: the folder may hold a mix of runs until this run finishes)")


def _discard(undo: Path) -> None:
    """Drop an undo folder without taking it back (renamed first: at once no longer
    one, also for a run still writing, whose own take back then finds it gone)."""
    done = undo.with_name(DONE_PREFIX + undo.name[len(UNDO_PREFIX):])
    try:
        os.rename(undo, done)
    except OSError:
        return
    shutil.rmtree(done, ignore_errors=True)


def take_back(undo: Path, option: str = "--out") -> bool:
    """Take back the unfinished run that ``undo`` (an undo folder) belongs to, saying so
    in one line on stderr.

    The files it kept are put back, the names its run made new are removed, and the
    undo folder is deleted; a folder the run made is removed when nothing else is left
    in it (silently). When an entry cannot be put back or removed, the undo folder is
    kept, with every earlier file not put back, and the line says where.

    Parameters
    ----------
    undo : Path
        The undo folder (:data:`UNDO_PREFIX`) inside an output folder; only the process
        that made it may take it back.
    option : str
        The option that named the folder, for the line (``"--out"``).

    Returns
    -------
    bool
        True when the folder still exists (it held files before the run), False when
        it was made by the run and is removed again.
    """
    owner = _UNFINISHED.pop(undo, None)
    if owner is not None:  # no longer its run's: neither finished nor discarded at exit
        owner._undo, owner._created = None, []
    folder = undo.parent
    stopped = f"ins-errors: {option} {folder}: this run stopped before its files were all written"
    if not undo.is_dir():
        print(f"{stopped}; its undo folder is gone (another run into the folder with "
              "--force discards it), so nothing is taken back: the folder may hold a mix "
              "of runs until that run finishes", file=sys.stderr)
        return folder.exists()
    try:
        journal = json.loads((undo / JOURNAL).read_text(encoding="utf-8"))
        created, made = list(journal["created"]), bool(journal["made_folder"])
    except (OSError, ValueError, KeyError, TypeError):
        created, made = [], False
    kept = undo / KEPT
    failed: list[str] = []
    for path in sorted(kept.iterdir()) if kept.is_dir() else ():
        try:
            os.replace(path, folder / path.name)
        except OSError as error:  # (a folder in its place): the rest is still put back
            failed.append(f"{path.name}: {_reason(error)}")
    for name in created:
        if "/" in name or "\\" in name:
            continue
        try:
            (folder / name).unlink(missing_ok=True)
        except OSError as error:
            failed.append(f"{name} (new): {_reason(error)}")
    if failed:  # the undo folder stays: it holds what is not put back
        more = f" and {len(failed) - 1} more" if len(failed) > 1 else ""
        print(f"{stopped}; taking it back failed ({failed[0]}{more}): the earlier files "
              f"not put back are kept in {kept}", file=sys.stderr)
        return True
    shutil.rmtree(undo, ignore_errors=True)
    if made:  # (kept when something else came into it meanwhile)
        with suppress(OSError):
            folder.rmdir()
        return folder.exists()
    print(f"{stopped}; the folder holds the earlier files again", file=sys.stderr)
    return True


@contextmanager
def _signals_held() -> Iterator[None]:
    """Ignore Ctrl-C and SIGTERM meanwhile (a second Ctrl-C: not half taken back)."""
    handlers = {}
    for number in (signal.SIGINT, signal.SIGTERM):
        with suppress(ValueError, OSError):  # (not the main thread)
            handlers[number] = signal.signal(number, signal.SIG_IGN)
    try:
        yield
    finally:
        for number, handler in handlers.items():
            signal.signal(number, handler)


_COMMAND_TAKES_BACK = [False]
"""True while a command of the command line runs (:func:`command_takes_back`)."""


@contextmanager
def command_takes_back() -> Iterator[None]:
    """Inside, a ``with OutputFolder(...)`` block left by an exception leaves its run to
    the command, which takes it back after the line that says why it stopped
    (:func:`take_back_unfinished`), so that the line about the folder follows it."""
    before = _COMMAND_TAKES_BACK[0]
    _COMMAND_TAKES_BACK[0] = True
    try:
        yield
    finally:
        _COMMAND_TAKES_BACK[0] = before


def unfinished() -> frozenset[Path]:
    """The undo folders of this process's runs not finished yet."""
    return frozenset(_UNFINISHED)


def take_back_unfinished(besides: frozenset[Path] = frozenset()) -> None:
    """Take back the runs of this process that have not finished: the command line's
    failure path (Ctrl-C, SIGTERM, an error raised through it). One line per folder
    that held files before (:func:`take_back`).

    Parameters
    ----------
    besides : frozenset of Path
        Undo folders left alone (:func:`unfinished` before the command: runs of the
        Python API in the same process).
    """
    if [os.getpid()] != _EXIT_REGISTERED or not _UNFINISHED:
        return
    with _signals_held():
        for undo, owner in list(_UNFINISHED.items()):
            if undo not in besides:
                owner.take_back()


def _register_exit() -> None:
    if [os.getpid()] != _EXIT_REGISTERED:
        _EXIT_REGISTERED[:] = [os.getpid()]
        atexit.register(_discard_at_exit)


def _discard_at_exit() -> None:
    """At a normal exit, the runs of this process that never finished (the Python API
    without :meth:`OutputFolder.finish`) keep their files; their undo folders go."""
    if [os.getpid()] != _EXIT_REGISTERED:
        return
    for owner in list(_UNFINISHED.values()):
        owner._abandon()


def require_matplotlib(what: str = "plots") -> None:
    """Fail early, in one line, when matplotlib (the ``plots`` extra) is missing.

    Call it before any computing in a command that will draw.

    Raises
    ------
    InsErrorsError
        ``"<what> need matplotlib: install ins-errors[plots]"``.
    """
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise InsErrorsError(f"{what} need matplotlib, which is not installed: "
                             "install ins-errors[plots] (pip install 'ins-errors[plots]')"
                             ) from None




def failure_list(header: str, lines: list[str], limit: int = 10) -> str:
    """``header`` and the first ``limit`` of ``lines`` (indented), then how many more:
    the failed points or sweeps a command lists on stderr before exiting 2."""
    shown_lines = [header, *(f"  {line}" for line in lines[:limit])]
    if len(lines) > limit:
        shown_lines.append(f"  ... and {len(lines) - limit} more (--json lists them all)")
    return "\n".join(shown_lines)
