"""Methods of library classes replaced by wrappers while at least one caller needs them.

:mod:`ins_errors.text_layouts` and :mod:`ins_errors.tick_updates` wrap a few of
matplotlib's methods, but only while ``save_figure`` draws: the first caller in installs
the wrappers, the last one out puts the originals back, and callers may nest and come
from several threads. This module holds that bookkeeping once.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager

Patch = tuple[object, str, Callable[[Callable], Callable]]
"""(class, method name, function making the wrapper from the original method)."""


class MethodPatches:
    """Wrappers installed while any caller is inside :meth:`applied`.

    Parameters
    ----------
    patches : callable
        Returns the patches to install, as ``(class, name, wrap)`` triples; called at each
        installation (so it may import lazily and leave out methods a library lacks).
    reset : callable, optional
        Called before installing and after removing the wrappers (e.g. to forget what
        the wrappers saw).
    """

    def __init__(self, patches: Callable[[], list[Patch]],
                 reset: Callable[[], None] = lambda: None) -> None:
        self._patches = patches
        self._reset = reset
        self._lock = threading.Lock()
        self._users = 0
        self._originals: list[tuple[object, str, Callable]] = []

    @contextmanager
    def applied(self) -> Iterator[None]:
        """The wrappers are in place inside the context (nestable, thread-safe)."""
        with self._lock:
            if self._users == 0:
                self._reset()
                for owner, name, wrap in self._patches():
                    original = getattr(owner, name)
                    self._originals.append((owner, name, original))
                    setattr(owner, name, wrap(original))
            self._users += 1
        try:
            yield
        finally:
            with self._lock:
                self._users -= 1
                if self._users == 0:
                    while self._originals:
                        owner, name, original = self._originals.pop()
                        setattr(owner, name, original)
                    self._reset()
