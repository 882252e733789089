"""The labelled result store of a sweep: an xarray dataset in Zarr, filled as tasks finish.

Layout (dimensions ``point``, ``time``, ``quantity``, ``source``; SI values)::

    direct, linear[, refined]   (point, time, quantity)  error curves
    max_direct                  (point, quantity)        max |direct error|
    linear_ratio[, refined_ratio] (point, quantity)      max |linear − direct| / max |direct|
    excited                     (point, quantity)        1 where the ratio is meaningful
    integration_error           (point, quantity)        estimated integration error
                                                         (step doubling, as compare)
    source_value                (point, source)          error sources the point ran with
    done                        (point)                  1 once the point is written
    failure                     (point)                  why the point failed (text;
                                                         empty: it did not; UTF-8 bytes
                                                         xarray reads as text,
                                                         :data:`FAILURE_ENCODING`)
    coordinates                 time (s), quantity and its unit, source and its unit,
                                every swept parameter per point (with its unit), case, draw
    attributes                  title, model, settings, the swept names, and
                                ``parameters``: the model parameters the scenario set
                                (JSON text, name -> SI value and unit; ``{}``: none);
                                ``judged_quantities``: the ``[outputs] quantities``
                                the worst ratios judge (JSON list, ``null``: all);
                                ``settings`` (JSON, readable name -> text); of a
                                shard store ``shard`` (``"I/N"``)

Units are CF ``units`` attributes (UDUNITS text that xarray shows and pint reads) on
every variable that has one unit: ``time`` (``s``), each swept parameter (its SI unit:
``rad``, ``m/s``, ``rad/s``, ...), the ratios and flags (``1``). A variable over
quantities or sources has the unit of each (SI), given by the coordinate
``quantity_unit`` (``source_unit``), which its ``comment`` attribute names; it has no
``units`` attribute, as no one unit is right. Text (``failure``, ``point_key``, labels)
has none.

Each point is its own chunk, written by the calling process only (one writer), data
first and ``done`` last: a point whose write was interrupted is not marked done and runs
again. A point that failed on its own bad input (a motion that reaches a pole) is
written as its one-line reason in ``failure`` and then ``done``; its data stay NaN (0 in
``excited``). A store written before ``failure`` existed gains the variable when it is
reopened (its points read as not failed).

Opening an existing store checks that it was made by the same sweep (a fingerprint of
everything that determines the numbers) and returns which points are done, so a
restarted sweep computes only the rest. A store named ``*.nc`` is filled as
``*.nc.partial.zarr`` and converted to NetCDF (xarray's default writer; scipy's when no
netCDF library is installed) once every point is done: NetCDF suits sweeps whose curves
fit in memory, Zarr any size. When points failed, the partial Zarr folder is kept beside
the NetCDF file, so that they can be run again (``--retry-failed``) and the file
rewritten.

One process writes a store at a time: :func:`store_lock` holds an exclusive lock on a
file beside it (``<store>.lock``, removed at the end) while a sweep fills it, so that a
second process started on the same store stops with a one-line error instead of
writing into it too. A store is created under that lock in a scratch folder
(``<store>.creating``) renamed into place once whole, so that a process that dies while
creating it leaves no half-made store.

Every point carries ``point_key``, a hash of its full definition (model, motion, run,
sources, scheme, judging: everything its numbers depend on). A sweep of other grid values
over a store of the same settings otherwise *extends* it (:func:`grow`): the store is
rewritten (in a scratch folder renamed into place) with the points it held and the new
ones, which are then computed; a sweep's points are found in it by their keys, and a
store may so hold points of several grids.

Before a sweep writes into a store (new, resumed, extended or merged), its size once
done is estimated (:func:`store_size`: bytes on disk and files, an upper bound) and said,
and a store beyond :data:`MAX_STORE_BYTES` or :data:`MAX_STORE_FILES`, or beyond the
room left on its file system, is refused (:func:`check_room`) unless allowed
(``--allow-large-store``).

A *shard* store (``ins-errors sweep --shard I/N``) has the layout of the whole sweep
but fills only the points of its share; its attribute ``shard`` says which
(``"I/N"``). The attribute ``settings`` records the sweep's settings as text, so that
a store of another sweep is refused with the settings that differ.
"""

from __future__ import annotations

import asyncio
import errno
import json
import os
import shutil
import socket
import stat
import warnings
from collections.abc import Callable, Coroutine, Iterator, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ins_errors.errors import InsErrorsError, InsErrorsNotice
from ins_errors.machine_memory import size_text

STORE_HINT = "pip install 'ins-errors[distributed]'"
"""How to install the store's libraries (xarray, zarr)."""


class StoreError(InsErrorsError):
    """A store that cannot be used for this sweep."""


FULL_DISK = (errno.ENOSPC, errno.EDQUOT)
"""Errors of a file system with no room left: no space, or the user's quota (of bytes
or of files, as cluster file systems count them) used up."""


def disk_full(error: BaseException) -> bool:
    """Whether ``error`` says the file system has no room left (:data:`FULL_DISK`)."""
    return isinstance(error, OSError) and error.errno in FULL_DISK


def full_disk_error(store: str | Path, kept: int, points: int,
                    error: OSError) -> StoreError:
    """The one line of a store whose disk filled while a sweep wrote it: the store, the
    points it keeps (each point is written whole or not at all, so the store resumes)
    and that the same command goes on once there is room."""
    why = error.strerror or os.strerror(error.errno or 0)
    return StoreError(f"the disk of the sweep store {str(store)!r} is full ({why}): it "
                      f"keeps {kept} of the {points} points; the same command resumes "
                      "the sweep once there is space (or a quota allows more)")


STORE_KINDS = {".zarr": "a Zarr folder, filled as points finish",
               ".nc": "a NetCDF file, written once every point is done"}
"""The store's format by the suffix of its name."""


def store_path(path: str | Path) -> Path:
    """The store's path, refused unless its suffix names a format (:data:`STORE_KINDS`).

    Raises
    ------
    StoreError
        Another suffix or none (``x.txt`` would otherwise become a Zarr folder).
    """
    path = Path(path)
    if path.suffix not in STORE_KINDS:
        kinds = " or ".join(f"*{suffix} ({kind})" for suffix, kind in STORE_KINDS.items())
        found = f"suffix {path.suffix!r}" if path.suffix else "no suffix"
        raise StoreError(f"sweep store {str(path)!r} has {found}: name it {kinds}")
    return path


def _libraries():
    try:
        import xarray
        import zarr
    except ImportError as error:
        raise StoreError(f"sweep stores need xarray and zarr ({error.name} is missing): "
                         f"{STORE_HINT}") from None
    return xarray, zarr


@dataclass(frozen=True)
class Layout:
    """Shape and labels of a store.

    Attributes
    ----------
    points : int
        Number of grid points.
    times : numpy.ndarray, shape (nt,)
        Recorded times, s (the longest run; shorter runs are NaN after their end).
    quantities, quantity_units : tuple of str
        Error quantities and their SI units.
    sources, source_units : tuple of str
        Error sources and their SI units.
    coordinates : dict of str to (numpy.ndarray, dict)
        Per-point coordinates (shape (points,)) and their attributes.
    curves : tuple of str
        ``("direct", "linear")`` or with ``"refined"``.
    attributes : dict
        Dataset attributes (title, model, ``settings``: the sweep's settings as a dict
        of readable name to text, compared to say which differs...).
    fingerprint : str
        Identity of the sweep; a store with another fingerprint is refused.
    shard : tuple of (int, int) or None
        ``(I, N)``: the store holds shard I of N (the points ``I - 1, I - 1 + N, ...``);
        None: every point.
    """

    points: int
    times: np.ndarray
    quantities: tuple[str, ...]
    quantity_units: tuple[str, ...]
    sources: tuple[str, ...]
    source_units: tuple[str, ...]
    coordinates: Mapping[str, tuple[np.ndarray, dict]]
    curves: tuple[str, ...]
    attributes: Mapping[str, object]
    fingerprint: str
    shard: tuple[int, int] | None = None

    @property
    def share(self) -> np.ndarray:
        """Indices of the points this store fills, in order, shape (n,)."""
        if self.shard is None:
            return np.arange(self.points)
        index, count = self.shard
        return np.arange(index - 1, self.points, count)

    @property
    def shard_text(self) -> str:
        """``"I/N"``, or empty text for a store of every point."""
        return "" if self.shard is None else f"{self.shard[0]}/{self.shard[1]}"

    @property
    def point_variables(self) -> list[str]:
        """The data variables a point writes (:meth:`SweepStore.write`), as
        :func:`_create` lays them out: the curves, ``max_direct``, each model curve's
        ``*_ratio``, ``excited``, ``integration_error`` and ``source_value``."""
        return [*self.curves, "max_direct", *(f"{curve}_ratio" for curve in self.curves[1:]),
                "excited", "integration_error", "source_value"]


MAX_STORE_BYTES = 20 * 10**9
"""Largest store (disk space, bytes) a sweep writes without ``--allow-large-store``: of
the order of a user's quota on a cluster's file systems (tens of GB)."""

MAX_STORE_FILES = 500_000
"""Most files (and folders) a store may have without ``--allow-large-store``: a file
system's quota of files (inodes) per user is commonly 10^5 to 10^6, and a Zarr store has
about ten files per point."""

BLOCK = 4096
"""Disk space a file takes at least (bytes; the usual block of a file system), where the
file system does not say."""

BLOSC_HEADER = 16
"""Bytes Blosc adds to each compressed chunk."""


@dataclass(frozen=True)
class StoreSize:
    """How large a store is (an estimate: :func:`store_size`).

    Attributes
    ----------
    points : int
        Points it holds.
    bytes : int
        Disk space it takes (whole blocks per file), bytes.
    files : int
        Files and folders (inodes, as quotas of files count them).
    netcdf : int
        Of a ``*.nc`` store: the bytes of its NetCDF file (also in ``bytes``; while it is
        filled the store is a Zarr folder, then both are on disk while the file is
        written); 0 for a Zarr store.
    """

    points: int
    bytes: int
    files: int
    netcdf: int = 0

    def __sub__(self, other: StoreSize) -> StoreSize:
        return StoreSize(self.points - other.points, self.bytes - other.bytes,
                         self.files - other.files, self.netcdf)

    @property
    def text(self) -> str:
        """``"1,200 points, about 45 MB in 3,700 files"`` (of a ``*.nc`` store also the
        NetCDF file it is written as at the end)."""
        folder = (self.bytes - self.netcdf, self.files - 1) if self.netcdf else (
            self.bytes, self.files)
        text = (f"{self.points:,} point{'s' if self.points != 1 else ''}, about "
                f"{size_text(folder[0])} in {folder[1]:,} files")
        if self.netcdf:
            text += f" while filled, then a NetCDF file of {size_text(self.netcdf)}"
        return text


def block_size(path: str | Path) -> int:
    """The disk space unit of the file system ``path`` is (or would be) on, bytes
    (:data:`BLOCK` where it cannot be told)."""
    try:
        size = os.statvfs(_existing_folder(Path(path))).f_frsize
    except (OSError, AttributeError):
        return BLOCK
    return size if 512 <= size <= 1 << 20 else BLOCK


def _existing_folder(path: Path) -> Path:
    """The nearest folder that exists at or above ``path`` (where the store would be)."""
    path = Path(os.path.abspath(path))
    while not path.is_dir() and path != path.parent:
        path = path.parent
    return path


def store_size(layout: Layout, filled: int, *, netcdf: bool = False,
               block: int = BLOCK) -> StoreSize:
    """Estimate the size of a store of ``layout`` holding ``filled`` points.

    The files are those :func:`_create` and :meth:`SweepStore.write` make: the folder,
    its metadata (``.zgroup``, ``.zattrs``, ``.zmetadata``), per array a folder with
    ``.zarray`` and ``.zattrs``, each coordinate's one chunk, and per point one chunk of
    each data variable and of ``done``. Each chunk is counted at its size before
    compression plus Blosc's header, each file rounded up to whole blocks: the estimate
    is an upper bound, reached where the data do not compress and no chunk is left out
    (Zarr writes no chunk that holds only the fill value, such as a point's ``excited``
    when no quantity is, or the ``failure`` of a point that did not fail).

    Parameters
    ----------
    layout : Layout
        The store's layout.
    filled : int
        Points written (done).
    netcdf : bool
        A ``*.nc`` store: its NetCDF file (every variable uncompressed) is counted too.
    block : int
        The file system's disk space unit, bytes (:func:`block_size`).
    """
    def disk(size: int) -> int:
        return -(-max(size, 1) // block) * block

    P, T = layout.points, len(layout.times)
    Q, W = len(layout.quantities), len(layout.sources)
    attrs = len(json.dumps(stored_attributes(layout)))
    coordinates = [P * 8, T * 8, *(4 * Q * max(map(len, layout.quantities), default=1),
                                  4 * Q * max(map(len, layout.quantity_units), default=1),
                                  4 * W * max(map(len, layout.sources), default=1),
                                  4 * W * max(map(len, layout.source_units), default=1))]
    coordinates += [np.asarray(values).nbytes for values, _ in layout.coordinates.values()]
    chunks = [T * Q * 8] * len(layout.curves) + [Q * 8] * len(layout.curves)  # max_direct,
    chunks += [Q, Q * 8, W * 8, 1]  # the ratios; excited, integration_error, source_value,
    arrays = len(coordinates) + len(chunks) + 1  # done; and failure
    metadata = 700  # bytes of one array's .zarray and .zattrs (about 500 and 200)
    size = disk(20) + disk(attrs) + disk(attrs + arrays * metadata) + block  # root, folder
    size += arrays * (2 * disk(metadata // 2) + block)  # each array's metadata and folder
    size += sum(disk(c + BLOSC_HEADER) for c in coordinates)
    size += filled * sum(disk(c + BLOSC_HEADER) for c in chunks)
    files = 4 + 3 * arrays + len(coordinates) + filled * len(chunks)
    nc = 0
    if netcdf:  # every variable as it is, and its header
        nc = (P * (sum(chunks) + 1) + sum(coordinates) + attrs + arrays * metadata)
        nc = disk(nc)
        size += nc
        files += 1
    return StoreSize(filled, size, files, nc)


def check_room(path: str | Path, final: StoreSize, needed: StoreSize,
               allow: bool = False) -> None:
    """Refuse a store too large for its limits or for the room left where it goes.

    Parameters
    ----------
    path : str or Path
        The store.
    final : StoreSize
        The store once the sweep is done (:func:`store_size`).
    needed : StoreSize
        What the sweep still writes into it (bytes and files; for a store rewritten
        whole, as an extended one is, all of it).
    allow : bool
        ``--allow-large-store``: write it anyway.

    Raises
    ------
    StoreError
        One line: the store is beyond :data:`MAX_STORE_BYTES` or :data:`MAX_STORE_FILES`,
        or needs more bytes or files than its file system has free (``shutil.disk_usage``,
        ``os.statvfs``), naming the figures and the option that writes it anyway.
    """
    if allow:
        return
    shown = f"the sweep store {str(path)!r}"
    anyway = ("; give fewer points or a coarser [run] record, or --allow-large-store to "
              "write it anyway")
    if final.bytes > MAX_STORE_BYTES or final.files > MAX_STORE_FILES:
        raise StoreError(f"{shown} would take about {size_text(final.bytes)} in "
                         f"{final.files:,} files, beyond the limit of "
                         f"{size_text(MAX_STORE_BYTES)} or {MAX_STORE_FILES:,} files (a "
                         f"common quota on a cluster){anyway}")
    folder = _existing_folder(Path(path).parent)
    try:
        free = shutil.disk_usage(folder).free
        system = os.statvfs(folder)
    except (OSError, AttributeError):
        return
    if needed.bytes > free:
        raise StoreError(f"{shown} needs about {size_text(needed.bytes)} more, and its "
                         f"file system has {size_text(free)} free{anyway}")
    if system.f_files and needed.files > system.f_favail:
        raise StoreError(f"{shown} needs about {needed.files:,} more files, and its file "
                         f"system has room for {system.f_favail:,}{anyway}")


POINT_KEY = "point_key"
"""The per-point coordinate that identifies a point by its full definition."""


def stored_layout(dataset) -> Layout:
    """The layout of a store as read back (:func:`read_store`): its points, times,
    labels, per-point coordinates, curves, attributes and fingerprint."""
    def plain(values) -> np.ndarray:
        values = np.asarray(values)
        return values.astype(str) if values.dtype.kind in "OSU" else values

    def python(attrs: Mapping) -> dict:  # (NetCDF gives numpy numbers and arrays)
        return {str(k): v.tolist() if isinstance(v, (np.generic, np.ndarray)) else v
                for k, v in attrs.items()}

    coordinates = {str(name): (plain(dataset[name].values), python(dataset[name].attrs))
                   for name in dataset.coords
                   if name != "point" and dataset[name].dims == ("point",)}
    attributes = {k: v for k, v in python(dataset.attrs).items()
                  if k not in ("fingerprint", "shard")}
    return Layout(dataset.sizes["point"], np.asarray(dataset["time"].values, dtype=float),
                  tuple(plain(dataset["quantity"].values).tolist()),
                  tuple(plain(dataset["quantity_unit"].values).tolist()),
                  tuple(plain(dataset["source"].values).tolist()),
                  tuple(plain(dataset["source_unit"].values).tolist()),
                  coordinates, tuple(c for c in ("direct", "linear", "refined")
                                     if c in dataset.data_vars),
                  attributes, str(dataset.attrs.get("fingerprint", "")))


def stored_attributes(layout: Layout) -> dict:
    """The dataset attributes a store of ``layout`` has (as read back): its attributes,
    those that are not text or numbers as JSON text, its fingerprint and shard."""
    attrs = {k: (v if isinstance(v, (str, int, float)) else json.dumps(v))
             for k, v in layout.attributes.items()}
    attrs["fingerprint"] = layout.fingerprint
    if layout.shard is not None:
        attrs["shard"] = layout.shard_text
    return attrs


class SweepStore:
    """A Zarr store of one sweep, opened for filling.

    Use :meth:`open` (creates or resumes), :meth:`write` per finished point,
    :meth:`dataset` to read everything back and :meth:`finish` when all points are done.
    """

    def __init__(self, path: Path, work: Path, layout: Layout, done: np.ndarray,
                 failure: Sequence[str] | None = None):
        self.path = path
        self.work = work
        self.layout = layout
        self.done = done
        self.failure: list[str] = (list(failure) if failure is not None
                                   else [""] * layout.points)
        self._written = False
        _, zarr = _libraries()
        complete = bool(done[layout.share].all())
        group = None if complete and not work.exists() else zarr.open_group(
            str(work), mode="r+", zarr_format=2)
        # opened once (the consolidated metadata lists them): a point's write then only
        # stores chunks instead of reading each array's metadata again
        self._arrays = {} if group is None else dict(group.arrays())
        if group is not None and "failure" not in self._arrays:  # a store made before it
            _add_failure(work)
            self._arrays = dict(zarr.open_group(str(work), mode="r+",
                                                zarr_format=2).arrays())

    # ----------------------------------------------------------------------------------
    @classmethod
    def open(cls, path: str | Path, layout: Layout) -> SweepStore:
        """Create the store, or reopen it and find the points already done.

        The caller holds :func:`store_lock` of ``path`` (one writer at a time).

        Raises
        ------
        StoreError
            If the path holds a store of another sweep (naming the settings that differ)
            or of another share of it, or something that is not a store, or its name
            ends in neither ``.zarr`` nor ``.nc``.
        """
        path = store_path(path)
        netcdf = path.suffix == ".nc"
        work = path.with_name(path.name + ".partial.zarr") if netcdf else path
        if netcdf and path.exists():
            existing = read_store(path)
            with existing:
                _check_fingerprint(existing.attrs, layout, path)
                done = np.asarray(existing["done"].values, dtype=bool)
                failure = failure_reasons(existing)
            if not work.exists():  # kept only when points failed (to run them again)
                return cls(path, work, layout, done, failure)
        if work.exists():
            existing = read_store(work)
            _check_fingerprint(existing.attrs, layout, work)
            done = np.asarray(existing["done"].values, dtype=bool)
            failure = failure_reasons(existing)
            existing.close()
            return cls(path, work, layout, done, failure)
        try:
            _create(work, layout)
        except OSError as error:  # a parent that is a file, a read-only or missing place
            raise StoreError(f"cannot write the sweep store {str(path)!r}: "
                             f"{error.strerror or type(error).__name__}") from None
        return cls(path, work, layout, np.zeros(layout.points, dtype=bool))

    # ----------------------------------------------------------------------------------
    def write(self, index: int, values: Mapping[str, np.ndarray]) -> None:
        """Write one finished point (data first, then its ``done`` flag).

        The point's chunks are stored concurrently (one round trip to Zarr's I/O thread
        instead of one per array); ``done`` is stored after all of them.
        """
        arrays = self._arrays
        nt = len(self.layout.times)
        chunks = []
        for name, value in values.items():
            value = np.asarray(value)
            if name in self.layout.curves:
                padded = np.full((nt, value.shape[1]), np.nan)
                padded[:value.shape[0]] = value
                value = padded
            chunks.append(arrays[name].async_array.setitem(index, value))

        async def data() -> None:
            await asyncio.gather(*chunks)

        _run_together(data())
        if self.failure[index]:  # a failed point run again: no longer failed
            self._set_reason(index, "")
        arrays["done"][index] = 1
        self.done[index] = True
        self._written = True

    def fail(self, index: int, reason: str) -> None:
        """Record that a point failed (its one-line ``reason``, then its ``done`` flag);
        its data stay empty (NaN)."""
        reason = " ".join(str(reason).split()) or "failed"
        self._set_reason(index, reason)
        self._arrays["done"][index] = 1
        self.done[index] = True
        self._written = True

    def _set_reason(self, index: int, reason: str) -> None:
        """Store one point's failure reason (empty text: none) in the form its store
        holds them: a row of bytes (:func:`stored_reason`; the variable widened first
        when the reason is longer than the width its consolidated metadata gives), or
        variable-length text in a store made before (kept so)."""
        array = self._arrays["failure"]
        if array.ndim == 1:  # variable-length text (a store made before)
            array[index] = reason
            self.failure[index] = reason
            return
        data = stored_reason(reason)
        if len(data) > array.shape[1]:  # (this array has the consolidated shape)
            import zarr

            array.resize((array.shape[0], len(data)))
            zarr.consolidate_metadata(str(self.work), zarr_format=2)
        row = np.zeros(array.shape[1], dtype="S1")
        row[:len(data)] = np.frombuffer(data, dtype="S1")
        array[index] = row
        self.failure[index] = data.decode(FAILURE_ENCODING)

    def record_attributes(self, attributes: Mapping[str, str]) -> None:
        """Write dataset attributes whose stored text differs from ``attributes`` (the
        ``judged_quantities`` of the sweep that uses the store now, when every point is
        reused too): into the Zarr folder (and its consolidated metadata) and into a
        finished ``*.nc`` store's file (rewritten whole, as :meth:`finish` writes it),
        so that the store read later says what the command reported."""
        if self.work.exists():
            import zarr

            group = zarr.open_group(str(self.work), mode="r+", zarr_format=2)
            changed = {k: v for k, v in attributes.items() if group.attrs.get(k) != v}
            if changed:
                group.attrs.update(changed)
                zarr.consolidate_metadata(str(self.work), zarr_format=2)
        if self.path.suffix != ".nc" or not self.path.exists():
            return
        xr, _ = _libraries()
        with xr.open_dataset(self.path, mask_and_scale=False) as data:
            if all(data.attrs.get(k) == v for k, v in attributes.items()):
                return
            data = data.load()
        data.attrs.update(attributes)
        _write_netcdf(data, self.path)

    @property
    def failed(self) -> list[int]:
        """Indices of the points that failed, in order."""
        return [k for k, reason in enumerate(self.failure) if reason]

    @property
    def complete(self) -> bool:
        """Whether every point of the store's share is done."""
        return bool(self.done[self.layout.share].all())

    def dataset(self):
        """The store as an :class:`xarray.Dataset`.

        A Zarr store is opened lazily (a variable is read when its values are used, so
        summaries of a large sweep do not load its curves); a NetCDF file is loaded.
        """
        written = self.path.suffix == ".nc" and self.path.exists()
        return read_store(self.path if written else self.work)

    def finish(self) -> None:
        """Once every point is done: write the NetCDF file of a ``*.nc`` store (again
        when points were written since it was). Its partial Zarr folder is removed unless
        points failed."""
        if not self.complete or self.path.suffix != ".nc":
            return
        if self.path.exists() and not self._written:
            return
        xr, _ = _libraries()
        data = xr.open_zarr(str(self.work), chunks=None, consolidated=False,
                            mask_and_scale=False).load()  # sweeps that fit in memory
        _write_netcdf(data, self.path)
        if not self.failed:
            shutil.rmtree(self.work, ignore_errors=True)


def _write_netcdf(data, path: Path) -> None:
    """Write ``data`` as the NetCDF file ``path``, through ``<path>.tmp`` renamed into
    place: half a file (a full disk, Ctrl-C) is removed, never left as the store (the
    Zarr folder keeps every point, and a rerun writes it)."""
    scratch = path.with_name(path.name + ".tmp")
    try:
        data.to_netcdf(scratch)
        scratch.replace(path)
    except BaseException:
        scratch.unlink(missing_ok=True)
        raise


def _run_together(work: Coroutine) -> None:
    """Run ``work``, a coroutine of Zarr's asynchronous API, to its end from plain code.

    Zarr's own ``zarr.core.sync.sync`` runs it on the event-loop thread that Zarr's
    synchronous calls use (one round trip for many arrays). That function is not public
    API; if a Zarr release moves it, a private event loop on a helper thread does the
    same job (a fresh thread, so it also works where the caller's thread already runs a
    loop, as in a notebook).
    """
    try:
        from zarr.core.sync import sync
    except ImportError:
        with ThreadPoolExecutor(max_workers=1) as thread:
            thread.submit(asyncio.run, work).result()
        return
    sync(work)


def failure_reasons(dataset) -> list[str]:
    """Each point's failure reason as stored ("" where the point did not fail, and for
    every point of a store written before failures were recorded), shape (P,).

    The reasons read as text whatever form the store holds them in: UTF-8 bytes decoded
    by xarray (:data:`FAILURE_ENCODING`), the variable-length text of stores written
    before, or bytes read without decoding."""
    if "failure" not in dataset:
        return [""] * dataset.sizes["point"]
    return [v.decode(FAILURE_ENCODING) if isinstance(v, bytes) else v if isinstance(v, str)
            else "" for v in dataset["failure"].values.tolist()]


FAILURE_ENCODING = "utf-8"
"""How the ``failure`` variable's text is stored: as the bytes of this encoding, one row of
single bytes (``S1``) per point along the dimension :data:`FAILURE_BYTES` (NetCDF's
character-array form), the encoding named in the variable's ``_Encoding`` attribute.
xarray joins a row into one text and decodes it (CF convention), so a store opened with
``xr.open_zarr`` has ``failure`` as ordinary Python text (``object`` dtype).

Variable-length text (Zarr's ``vlen-utf8``, which stores up to now used) reads back with
Zarr 3.1 and NumPy 2 as NumPy's ``StringDType``, which xarray cannot combine with the NaN
of a missing value: ``ds.where(...)``, ``ds.reindex(...)`` and ``ds.fillna(...)`` of a
store raised ``DTypePromotionError``. Variable-length bytes read back as a nested array
when one point is selected (``ds.sel(point=k)`` then failed). Fixed-width text needs its
width when the store is made, before any reason is known."""

FAILURE_BYTES = "failure_bytes"
"""The dimension along which a point's failure reason is stored byte by byte; xarray
joins it away (the dataset has no such dimension)."""

FAILURE_CHUNK = 4096
"""Bytes of a point's chunk of the ``failure`` variable: the longest reason stored whole.
The variable is as wide as the longest reason written (at least 1 byte; widened in place
as longer ones come, never beyond a chunk: xarray joins a row only within one chunk). A
longer reason (a one-line reason never is) keeps its first part and says it was cut and
how long it was (:func:`stored_reason`)."""

FAILURE_ATTRIBUTES = {"long_name": "why the point failed (empty: it did not); its data "
                                   "are NaN"}
"""Attributes of the ``failure`` variable (text: no ``units``)."""


def _failure_array(points: int) -> dict:
    """Keyword arguments of the ``failure`` array: one row of single bytes per point
    (:data:`FAILURE_ENCODING`), one chunk per point (:data:`FAILURE_CHUNK` wide), 1 byte
    wide until a reason is written, fill 0 (unwritten points read as empty text)."""
    return {"name": "failure", "shape": (points, 1), "chunks": (1, FAILURE_CHUNK),
            "dtype": "S1", "fill_value": None,
            "attributes": {"_ARRAY_DIMENSIONS": ["point", FAILURE_BYTES],
                           **FAILURE_ATTRIBUTES, "_Encoding": FAILURE_ENCODING}}


def stored_reason(reason: str) -> bytes:
    """A failure reason as the store keeps it: its bytes (:data:`FAILURE_ENCODING`), or,
    beyond :data:`FAILURE_CHUNK` bytes, its first part followed by a note saying that it
    was cut and how many bytes it had (never cut silently)."""
    data = reason.encode(FAILURE_ENCODING)
    if len(data) <= FAILURE_CHUNK:
        return data
    note = f" … [cut: the reason has {len(data):,} bytes]".encode(FAILURE_ENCODING)
    kept = data[:FAILURE_CHUNK - len(note)].decode(FAILURE_ENCODING, errors="ignore")
    return kept.encode(FAILURE_ENCODING) + note


def _add_failure(work: Path) -> None:
    """Give a store made before the ``failure`` variable existed an empty one (and its
    consolidated metadata the new array)."""
    import zarr

    group = zarr.open_group(str(work), mode="r+", zarr_format=2)
    points = group["done"].shape[0]
    group.create_array(**_failure_array(points))
    zarr.consolidate_metadata(str(work), zarr_format=2)


def read_store(path: Path):
    """Open a store (a Zarr folder lazily, a NetCDF file loaded) for reading.

    Raises
    ------
    StoreError
        ``path`` is not a readable store (one line naming it).
    """
    xr, _ = _libraries()
    netcdf = path.suffix == ".nc" and not path.is_dir()
    try:
        with warnings.catch_warnings():  # a folder that is no store: said below, once
            warnings.simplefilter("ignore")
            if netcdf:
                with xr.open_dataset(path, mask_and_scale=False) as data:
                    return data.load()
            return xr.open_zarr(str(path), chunks=None, consolidated=False,
                                mask_and_scale=False)
    except Exception as error:  # any unreadable file (xarray raises several types)
        kind = "NetCDF sweep store" if netcdf else "sweep store"
        raise StoreError(f"{str(path)!r} exists and is not a readable {kind} "
                         f"({type(error).__name__}); remove it or choose another "
                         "store") from None


SHOWN_DIFFERENCES = 3
"""Settings a refusal names at most (then how many more differ)."""


def _brief(text: object, width: int = 60) -> str:
    text = "absent" if text is None else str(text)
    return text if len(text) <= width else text[:width - 1] + "…"


def setting_differences(found: Mapping, wanted: Mapping) -> list[str]:
    """The settings two sweeps differ in, one phrase each (``"[sweep] seed is 5 there,
    6 here"``), in the order of ``wanted``.

    Parameters
    ----------
    found : dict of str to str
        A store's ``settings`` attribute (readable name -> value as text).
    wanted : dict of str to str
        The sweep's.
    """
    names = [*wanted, *(n for n in found if n not in wanted)]
    return [f"{name} is {_brief(found.get(name))} there, {_brief(wanted.get(name))} here"
            for name in names if found.get(name) != wanted.get(name)]


def _recorded_settings(attributes: Mapping) -> dict | None:
    """A store's ``settings`` attribute as a dict (None: a store made before it)."""
    text = attributes.get("settings")
    if not isinstance(text, str):
        return None
    try:
        settings = json.loads(text)
    except ValueError:
        return None
    return settings if isinstance(settings, dict) else None


def mismatch(attributes: Mapping, layout: Layout) -> str:
    """Why a store (its attributes) is not one of ``layout``'s sweep and share: empty
    text when it is; else the settings that differ (or the shard), as a phrase."""
    found = attributes.get("fingerprint")
    if not found:
        return "no sweep"
    if found != layout.fingerprint:
        wanted = layout.attributes.get("settings")
        recorded = _recorded_settings(attributes)
        differences = (setting_differences(*_unreplaced(recorded, wanted, attributes,
                                                        layout))
                       if recorded is not None and isinstance(wanted, Mapping) else [])
        if not differences:  # a store made before settings were recorded, or a change
            return "another sweep (other settings, grid or seed)"  # they do not show
        more = len(differences) - SHOWN_DIFFERENCES
        return ("another sweep: " + ", ".join(differences[:SHOWN_DIFFERENCES])
                + (f" and {more} more setting{'s' if more > 1 else ''} differ"
                   if more > 0 else ""))
    shard = str(attributes.get("shard", ""))
    if shard != layout.shard_text:
        have = f"shard {shard} of this sweep" if shard else "the whole sweep"
        want = (f"shard {layout.shard_text} (--shard {layout.shard_text} needs a store of "
                "its own)" if layout.shard_text else "the whole sweep (run without --shard)")
        return f"{have}, not {want}"
    return ""


def _unreplaced(recorded: Mapping, wanted: Mapping, attributes: Mapping,
                layout: Layout) -> tuple[dict, dict]:
    """Two sweeps' settings without the ``[parameters]`` values a grid of both replaces
    (a store written before such values were left out of its settings still records
    them: not a difference)."""
    try:
        before = {str(n) for n in json.loads(str(attributes.get("swept", "[]")))}
    except (ValueError, TypeError):
        before = set()
    both = before & {str(n) for n in layout.attributes.get("swept", [])}
    replaced = {f"[parameters] {name}" for name in both}
    return ({k: v for k, v in recorded.items() if k not in replaced},
            {k: v for k, v in wanted.items() if k not in replaced})


def _check_fingerprint(attributes: Mapping, layout: Layout, where: Path) -> None:
    why = mismatch(attributes, layout)
    if why:
        raise StoreError(f"{str(where)!r} holds {why}; remove it or choose another store")


def _overridden(name: str, swept: set[str]) -> bool:
    """Whether a setting (its readable name) is a grid of a sweep sweeping ``swept``, or
    a value such a grid replaces (``[motion] latitude`` beside a latitude grid,
    ``[parameters] k_v`` beside a grid of the model parameter ``k_v``)."""
    for grid in swept:
        if name in (f"[sweep] {grid}", f"[motion] {grid}", f"[run] {grid}",
                    f"[parameters] {grid}"):
            return True
        if name.startswith("[[case]] ") and name.endswith(f" {grid}") and \
                name[len("[[case]] "):-len(grid) - 1].isdigit():
            return True
    return False


def extension_differences(attributes: Mapping, layout: Layout) -> list[str] | None:
    """The settings other than the grids in which a store (its attributes) and the sweep
    of ``layout`` differ (empty: the sweep may extend the store), or None when that
    cannot be told (a store made before settings were recorded).

    A grid's values, and the value a grid replaces in the other sweep (the ``[motion]``
    latitude of a sweep that did not sweep it), are left out; every other setting must be
    the same, so points of incompatible sweeps never share a store.
    """
    recorded = _recorded_settings(attributes)
    wanted = layout.attributes.get("settings")
    if recorded is None or not isinstance(wanted, Mapping):
        return None
    try:
        before = json.loads(str(attributes.get("swept", "[]")))
    except ValueError:
        before = []
    now = layout.attributes.get("swept", [])
    swept = {str(n) for n in [*before, *now]}
    found, meant = effective_settings(recorded), effective_settings(wanted)
    differ = {name for name in [*found, *meant] if found.get(name) != meant.get(name)}
    # the settings that differ in effect, said as written (or in effect, where absent)
    there = {k: recorded.get(k, found.get(k)) for k in differ if not _overridden(k, swept)}
    here = {k: wanted.get(k, meant.get(k)) for k in differ if not _overridden(k, swept)}
    order = {k: n for n, k in enumerate([*wanted, *meant, *recorded, *found])}
    return [text for _, text in sorted(
        (order[k], f"{k} is {_brief(there.get(k))} there, {_brief(here.get(k))} here")
        for k in set(there) | set(here))]


def effective_settings(settings: Mapping[str, str]) -> dict[str, str]:
    """A sweep's ``settings`` with the values that take effect: the ``[motion]`` with its
    defaults filled in, as exact SI text, and every model parameter (its default, or its
    ellipsoid's, where ``[parameters]`` sets none) as ``repr`` of its SI value. A
    setting written out at its default (``heading = "0 deg"``, ``a = "6378245 m"``) is
    then the same as one left out; values that cannot be read are kept as written."""
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import in_si

    out = dict(settings)
    motion: dict = {}
    for key, text in settings.items():
        if key.startswith("[motion] "):
            try:
                motion[key[len("[motion] "):]] = json.loads(text)
            except ValueError:
                motion[key[len("[motion] "):]] = text
    with suppress(InsErrorsError, ValueError, TypeError):
        for name, value in in_si(motion).items():
            out[f"[motion] {name}"] = (value if isinstance(value, str)
                                       else json.dumps(value, sort_keys=True))
    given = {key[len("[parameters] "):]: text for key, text in settings.items()
             if key.startswith("[parameters] ")}
    ellipsoid = settings.get("[run] ellipsoid")
    with suppress(InsErrorsError, ValueError, TypeError, KeyError):
        model = load_model(str(settings["model"]))
        vector = model.parameter_vector(
            ellipsoid=None if ellipsoid in (None, "the model's own", "None") else ellipsoid,
            **{name: float(text) for name, text in given.items()})
        for info, value in zip(model.parameters, vector, strict=True):
            out[f"[parameters] {info.name}"] = repr(float(value))
    return out


def points_done(path: Path) -> int | None:
    """How many points a store being filled (or its ``*.nc.partial.zarr``) holds, read
    from its ``done`` flags; None when it cannot be read (no store yet, or being moved)."""
    import zarr

    work = _work_of(Path(path))
    try:
        group = zarr.open_group(str(work), mode="r", zarr_format=2)
        return int(np.count_nonzero(np.asarray(group["done"][:])))
    except Exception:  # any reason it cannot be read: the caller keeps its own count
        return None


def _work_of(path: Path) -> Path:
    """The Zarr folder a store is filled in (of ``x.nc``: ``x.nc.partial.zarr``)."""
    return path.with_name(path.name + ".partial.zarr") if path.suffix == ".nc" else path


def _aside(work: Path, what: str) -> Path:
    return work.with_name(f"{work.name}.{what}")


def _fingerprint_of(path: Path) -> str | None:
    """A store's fingerprint, read without loading its data (None: unreadable)."""
    xr, _ = _libraries()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if path.is_dir():
                data = xr.open_zarr(str(path), chunks=None, consolidated=False)
            else:
                data = xr.open_dataset(path, mask_and_scale=False)
            with data:
                return str(data.attrs.get("fingerprint", ""))
    except Exception:  # not a store: said by whoever opens it
        return None


def stored_source(path: str | Path) -> Path | None:
    """What a store is read from: its Zarr folder (also the partial folder of an
    unfinished ``*.nc`` store, or one kept for its failed points), else its NetCDF file;
    None when there is no store yet.

    An extension interrupted while its rewritten store was being put in place is
    finished or undone first (the caller holds :func:`store_lock`).
    """
    path = store_path(path)
    work = _work_of(path)
    previous = _aside(work, "previous")
    if previous.exists():
        if work.exists():  # the rewritten store is in place: the old one goes
            shutil.rmtree(previous, ignore_errors=True)
        else:  # stopped between the two renames: the store as it was
            previous.rename(work)
    shutil.rmtree(_aside(work, "extending"), ignore_errors=True)
    if work != path and work.exists() and path.exists() and \
            _fingerprint_of(path) != _fingerprint_of(work):
        path.unlink()  # the NetCDF file of an extended store's points, all in work now
    if work.exists():
        return work
    return path if path.exists() else None


def grow(path: str | Path, layout: Layout,
         points: Sequence[tuple[int, str, Callable[[], Mapping[str, np.ndarray]]]]
         ) -> SweepStore:
    """Rewrite a store with the layout of an extended sweep, copying points into it.

    The new store is made in a scratch folder (``<work>.extending``) and renamed into
    place once every point is copied (the old one is moved to ``<work>.previous`` and
    removed after; :func:`stored_source` finishes or undoes a rename that was
    interrupted), so the store is never half-made. Of a ``*.nc`` store the NetCDF file
    goes too: its points are in the Zarr folder, which is written as NetCDF once
    complete. The caller holds :func:`store_lock`.

    Parameters
    ----------
    path : str or Path
        The store.
    layout : Layout
        Of the extended store (every point it keeps and every new one).
    points : sequence of (int, str, callable)
        The points to copy: their index in ``layout``, their failure reason (empty: it
        did not fail) and a function returning their data variables as stored.

    Returns
    -------
    SweepStore
        The extended store, opened for filling (the copied points done).
    """
    path = store_path(path)
    work = _work_of(path)
    scratch, previous = _aside(work, "extending"), _aside(work, "previous")
    shutil.rmtree(scratch, ignore_errors=True)
    try:
        _create(scratch, layout)
    except OSError as error:
        raise StoreError(f"cannot write the sweep store {str(path)!r}: "
                         f"{error.strerror or type(error).__name__}") from None
    try:
        filling = SweepStore(path, scratch, layout, np.zeros(layout.points, dtype=bool))
        for index, reason, values in points:
            if reason:
                filling.fail(index, reason)
            else:
                filling.write(index, values())
    except BaseException as error:
        shutil.rmtree(scratch, ignore_errors=True)
        if disk_full(error):  # the store is as it was
            raise StoreError(f"the disk of the sweep store {str(path)!r} is full "
                             f"({error.strerror}) while it was being extended: it is as "
                             f"it was, with its {len(points)} finished points; the same "
                             "command extends it once there is space") from None
        raise
    if work.exists():
        work.rename(previous)
    scratch.rename(work)
    if work != path and path.exists():
        path.unlink()
    shutil.rmtree(previous, ignore_errors=True)
    return SweepStore(path, work, layout, filling.done.copy(), filling.failure)


def reopen(path: str | Path, dataset) -> SweepStore:
    """A store of points of several grids (or of another grid) opened as it is, for
    filling, from ``dataset`` (:func:`read_store` of :func:`stored_source`)."""
    path = store_path(path)
    return SweepStore(path, _work_of(path), stored_layout(dataset),
                      np.asarray(dataset["done"].values, dtype=bool),
                      failure_reasons(dataset))


LOCK_SUFFIX = ".lock"
"""Suffix of the lock file beside a store (``all.zarr.lock``)."""


class StoreBusyError(StoreError):
    """Another process is writing the store."""


@contextmanager
def store_lock(path: str | Path, reading: bool = False) -> Iterator[None]:
    """Hold the store's lock (``<store>.lock`` beside it) while the block runs.

    The lock is an exclusive ``flock`` on that file, released by the system when the
    process ends in any way; the file is removed at the end of the block. Where the
    file system has no locks (or, when ``reading``, the folder cannot be written), the
    block runs unlocked.

    Parameters
    ----------
    path : str or Path
        The store.
    reading : bool
        Only read the store (a shard store being merged).

    Raises
    ------
    StoreBusyError
        Another process holds the lock (one line naming it, with its host and process
        id).
    StoreError
        The folder of the store cannot be made or written.
    """
    path = Path(path)
    # beside the store itself: a link to a store and the store lock the same file (a
    # link in a folder above leads to the same file anyway)
    real = path.resolve() if path.is_symlink() else path
    lock = real.with_name(real.name + LOCK_SUFFIX)
    try:
        import fcntl
    except ImportError:  # no POSIX file locks on this system
        yield
        return
    while True:
        try:
            if not reading:
                lock.parent.mkdir(parents=True, exist_ok=True)
            # never through a link planted in its place (it would write the holder's
            # name into the link's target), and only a regular file
            handle = os.open(lock, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0),
                             0o644)
            if not stat.S_ISREG(os.fstat(handle).st_mode):
                os.close(handle)
                raise OSError(0, f"{lock.name} is not a regular file")
        except OSError as error:
            if reading:
                yield
                return
            from ins_errors.output import shown

            why = (f"{lock.name} is a symbolic link (remove it)" if lock.is_symlink()
                   else error.strerror or str(error) or type(error).__name__)
            raise StoreError(f"cannot write the sweep store {shown(path)}: {why}") from None
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = _lock_holder(handle)
            os.close(handle)
            advice = ("wait for its sweep to finish" if reading else
                      "wait for it to finish, or give each job its own store (--shard "
                      "I/N splits a sweep between jobs)")
            raise StoreBusyError(f"sweep store {str(path)!r} is being written by another "
                                 f"process ({holder}holding {lock.name}); {advice}"
                                 ) from None
        except OSError:  # a file system without locks (Lustre without -o flock, ...)
            os.close(handle)
            if not reading:
                warnings.warn(f"ins-errors: the file system of {str(path)!r} has no file "
                              "locks: this store is written unlocked (give each job its own "
                              "store: --shard I/N)", InsErrorsNotice, stacklevel=3)
            yield
            return
        # the lock file may have been removed by a holder that finished meanwhile: a
        # lock on the removed file would not exclude a process that makes a new one
        try:
            current = os.stat(lock).st_ino == os.fstat(handle).st_ino
        except OSError:
            current = False
        if current:
            break
        os.close(handle)
    try:
        with suppress(OSError):
            os.ftruncate(handle, 0)
            os.write(handle, f"{socket.gethostname()} {os.getpid()}\n".encode())
        yield
    finally:
        with suppress(OSError):
            lock.unlink()
        os.close(handle)


def _lock_holder(handle: int) -> str:
    """``process N on host H, `` from a lock file's text, or empty text."""
    try:
        text = os.pread(handle, 200, 0).decode(errors="replace").split()
    except OSError:
        return ""
    if len(text) == 2 and text[1].isdigit():
        return f"process {text[1]} on host {text[0]}, "
    return ""


def _create(work: Path, layout: Layout) -> None:
    """Write coordinates, attributes and empty arrays to ``work`` (atomically by rename).

    The layout is the one :meth:`xarray.Dataset.to_zarr` gives the coordinates (Zarr
    format 2, one chunk each, NaN fill for floats, none for integers and text, the
    ``coordinates`` attribute naming the non-dimension coordinates) plus the empty data
    arrays, one chunk per point. Every array is made, and every coordinate written,
    concurrently in one round trip to Zarr's I/O thread (xarray and one call per array
    took about as many round trips as there are files).
    """
    _libraries()  # the clear error when xarray or zarr is missing
    from zarr.api import asynchronous as zarr_async

    if work.parent != Path("") and not work.parent.exists():
        work.parent.mkdir(parents=True, exist_ok=True)
    scratch = work.with_name(work.name + ".creating")
    shutil.rmtree(scratch, ignore_errors=True)
    coords = {
        "point": (("point",), np.arange(layout.points), {}),
        "time": (("time",), np.asarray(layout.times, dtype=float), {"units": "s"}),
        "quantity": (("quantity",), np.asarray(layout.quantities, dtype=str), {}),
        "quantity_unit": (("quantity",), np.asarray(layout.quantity_units, dtype=str), {}),
        "source": (("source",), np.asarray(layout.sources, dtype=str), {}),
        "source_unit": (("source",), np.asarray(layout.source_units, dtype=str), {}),
    }
    for name, (values, attrs) in layout.coordinates.items():
        coords[name] = (("point",), np.asarray(values), dict(attrs))
    for name, (_, values, _) in coords.items():
        if values.dtype.kind not in "iufU":
            raise StoreError(f"sweep coordinate {name!r} has values of type {values.dtype} "
                             "(numbers or text expected)")
    attrs = stored_attributes(layout)
    attrs["coordinates"] = " ".join(sorted(name for name, (dims, _, _) in coords.items()
                                           if dims != (name,)))
    P, T, Q, W = layout.points, len(layout.times), len(layout.quantities), len(layout.sources)
    # a variable over quantities (or sources) has the unit of each, in coordinate
    # quantity_unit (source_unit): no one unit for a CF ``units`` attribute
    per_quantity = {"comment": "SI: each quantity in its unit, coordinate quantity_unit"}
    # integer flags get no fill value: unwritten chunks read as 0, and xarray keeps
    # them integers instead of masking 0 as missing
    empty = []  # name, dims, shape, dtype, fill value, attributes

    def array(name: str, dims: Sequence[str], shape: tuple, dtype: str, fill, attrs: dict):
        empty.append((name, dims, shape, dtype, fill, attrs))

    for curve in layout.curves:
        array(curve, ("point", "time", "quantity"), (P, T, Q), "f8", np.nan,
              {"long_name": f"{curve} error", **per_quantity})
    array("max_direct", ("point", "quantity"), (P, Q), "f8", np.nan,
          {"long_name": "max |direct error| over the run", **per_quantity})
    for curve in layout.curves[1:]:
        array(f"{curve}_ratio", ("point", "quantity"), (P, Q), "f8", np.nan,
              {"long_name": f"max |{curve} - direct| / max |direct|", "units": "1"})
    array("excited", ("point", "quantity"), (P, Q), "i1", None,
          {"long_name": "1 where the quantity is excited (its ratios are meaningful)",
           "units": "1"})
    array("integration_error", ("point", "quantity"), (P, Q), "f8", np.nan,
          {"long_name": "estimated integration error (step doubling; larger of direct "
                        "and linear)", **per_quantity})
    array("source_value", ("point", "source"), (P, W), "f8", np.nan,
          {"long_name": "error sources of the point",
           "comment": "SI: each source in its unit, coordinate source_unit"})
    array("done", ("point",), (P,), "i1", None,
          {"long_name": "1 once the point's results (or its failure) are written",
           "units": "1"})
    failure = _failure_array(P)

    async def build() -> None:
        group = await zarr_async.open_group(str(scratch), mode="w", zarr_format=2,
                                            attributes=attrs)

        async def coordinate(name: str, dims: tuple, values: np.ndarray, extra: dict):
            made = await group.create_array(
                name, shape=values.shape, chunks=values.shape, dtype=values.dtype,
                fill_value=np.nan if values.dtype.kind == "f" else None,
                attributes={**extra, "_ARRAY_DIMENSIONS": list(dims)})
            await made.setitem(Ellipsis, values)

        async def data(name: str, dims: Sequence[str], shape: tuple, dtype: str, fill,
                       extra: dict):
            await group.create_array(name, shape=shape, chunks=(1, *shape[1:]),
                                     dtype=dtype, fill_value=fill,
                                     attributes={"_ARRAY_DIMENSIONS": list(dims), **extra})

        await asyncio.gather(*(coordinate(name, *spec) for name, spec in coords.items()),
                             *(data(*spec) for spec in empty),
                             group.create_array(**failure))
        # the metadata never changes after this (points only fill chunks), so a
        # consolidated copy stays valid: plain xr.open_zarr(path) reads the store
        # without a warning
        await zarr_async.consolidate_metadata(str(scratch), zarr_format=2)

    try:
        _run_together(build())
        scratch.rename(work)
    except BaseException:  # nothing half-made is left (Ctrl-C included)
        shutil.rmtree(scratch, ignore_errors=True)
        raise
