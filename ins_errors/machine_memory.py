"""How much memory the machine has, and byte counts as people read them.

Runs and stores that could outgrow the machine are sized before they start; these are
the figures they are weighed against and the words their refusals use.
"""

from __future__ import annotations

import os


def physical_memory() -> int | None:
    """The machine's physical memory, bytes, or None where the system does not say."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return None


def available_memory() -> int | None:
    """Memory this machine has available now, bytes (psutil where installed, else the
    free pages the system reports), or None where it does not say."""
    try:
        import psutil
        return int(psutil.virtual_memory().available)
    except ImportError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return None


def size_text(size: float) -> str:
    """Bytes as ``"45 MB"`` or ``"5.1 GB"`` (decimal units, two significant digits below
    ten of a unit, whole units from ten)."""
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if size >= 0.9995 * scale:  # what rounds to 1000 of the next unit down is 1 of it
            value = size / scale
            return f"{value:.2g} {unit}" if value < 9.95 else f"{value:.0f} {unit}"
    return f"{size:.0f} bytes"
