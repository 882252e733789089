"""Update an axis' ticks once per drawing of the axis, not twice.

matplotlib's ``Axis.draw`` computes the tick locations, formats their labels and moves
every tick (``Axis._update_ticks``), draws them, and then, to place the axis label beside
the tick labels, computes, formats and moves them all again, with nothing changed in
between. Inside :func:`ticks_updated_once` the second update of an axis within its own
drawing gives back the first one's ticks (other axes' updates, e.g. of axes sharing
it, and updates outside a drawing run as usual). The ticks are the same objects in the
same places, so the drawing is the same, bit for bit.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Iterator
from contextlib import contextmanager

from ins_errors.method_patches import MethodPatches

_local = threading.local()
"""Per thread: how many contexts it is inside, and per axis being drawn its ticks."""


def _patches() -> list:
    from matplotlib.axis import Axis

    return [(Axis, "draw", _drawing), (Axis, "_update_ticks", _updating)]


_installed = MethodPatches(_patches)


@contextmanager
def ticks_updated_once() -> Iterator[None]:
    """Update each axis' ticks once per drawing of it (see the module notes); nestable,
    and safe with several threads (only threads inside the context are affected)."""
    with _installed.applied():
        _local.depth = getattr(_local, "depth", 0) + 1
        try:
            yield
        finally:
            _local.depth -= 1


def _drawing(draw):
    @functools.wraps(draw)  # (keeps matplotlib's marks on it, e.g. rasterization)
    def drawing(axis, *args, **kwargs):
        if not getattr(_local, "depth", 0):
            return draw(axis, *args, **kwargs)
        drawn = _local.__dict__.setdefault("drawn", {})
        drawn[id(axis)] = None  # (no ticks yet in this drawing)
        try:
            return draw(axis, *args, **kwargs)
        finally:
            del drawn[id(axis)]

    return drawing


def _updating(update):
    @functools.wraps(update)
    def updating(axis):
        drawn = _local.__dict__.get("drawn")
        if not drawn or id(axis) not in drawn:
            return update(axis)
        ticks = drawn[id(axis)]
        if ticks is None:
            ticks = drawn[id(axis)] = update(axis)
        return list(ticks)

    return updating
