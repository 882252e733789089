"""Lay out each text once per save; shape and measure each string once per font and size.

Three of matplotlib's text costs are repeated work, and the pictures are the same without
the repetition:

* **A text's box.** While matplotlib draws an axis it lays out every tick label three
  times: to measure the labels (for the offset text), to measure them again (to place
  the axis label beside them) and to draw them. Each layout looks the font up, reads its
  size tables and measures every line, and none of it is kept. Inside
  :func:`remembered_layouts` a text's layout is kept (beside the text, which it does not
  keep alive) and given back while everything it depends on is unchanged: the renderer,
  string, font, size, angle, alignment, line spacing, resolution and text settings.
  Texts whose layout depends on more (wrapped texts, TeX, mathtext) are laid out
  afresh.
* **A string's glyphs.** matplotlib 3.11 places the glyphs of every string it draws
  with its text-shaping library (``FT2Font._layout``: about 0.4 ms for "0.0025", more
  than drawing the glyphs), even when the same string was shaped in the same font and
  size a moment before: the time axis labels of every panel, the titles, the legends
  of each figure of a report. Inside :func:`remembered_layouts` the glyph placements
  are kept per font, size, string, load flags, features and language.
* **A string's size.** matplotlib keeps a string's measured size per renderer, and a
  new figure (or a figure saved at another resolution) has a new renderer, so every
  label of every new figure is shaped again to be measured (``FT2Font.set_text``, the
  same 0.4 ms). Inside :func:`remembered_layouts` the sizes measured by the Agg
  renderer are kept per resolution, string, font and text settings across renderers.

All three are pure functions of what they are kept under, so the drawing is the same,
bit for bit (the tests compare whole files with matplotlib's own drawing). Outside the
context matplotlib works as usual.
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Iterator
from contextlib import contextmanager

from ins_errors.figure_layout import FONT_FAMILY_SETTINGS
from ins_errors.method_patches import MethodPatches

_RC_KEYS = ("text.hinting", "text.hinting_factor", "text.kerning_factor",
            *FONT_FAMILY_SETTINGS)
"""Settings that change how a text measures (hinting, kerning, the font families a
generic family name resolves to)."""

_GLYPH_LAYOUTS_KEPT = 20_000
"""Most glyph layouts kept (a report keeps a few hundred)."""

_boxes: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
"""Per text: (what its layout depends on, the renderer, the layout)."""
_glyphs: dict = {}
"""Per (font, size, string, flags, features, language): the glyph layout."""
_sizes: dict = {}
"""Per font: the size last set (only while the context is in use)."""
_measures: dict = {}
"""Per (renderer class, dpi, string, font, text settings): width, height, descent."""
_local = threading.local()
"""Per thread: the text settings of each :func:`remembered_layouts` it is inside."""


def _patches() -> list:
    from matplotlib import ft2font
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.text import Text

    patches = [(Text, "_get_layout", _kept_box),
               (RendererAgg, "get_text_width_height_descent", _kept_measure)]
    if hasattr(ft2font.FT2Font, "_layout"):  # (matplotlib >= 3.11 shapes every string)
        patches += [(ft2font.FT2Font, "_layout", _kept_glyphs),
                    (ft2font.FT2Font, "set_size", _seen_size),
                    (ft2font.FT2Font, "clear", _cleared)]
    return patches


_installed = MethodPatches(_patches, reset=_sizes.clear)
"""The wrappers; the sizes seen are forgotten whenever they are not installed (sizes set
meanwhile were not seen)."""


@contextmanager
def remembered_layouts() -> Iterator[None]:
    """Keep text layouts while drawing (see the module notes).

    Nestable and safe with several threads: a text's box is kept only for threads
    inside the context; glyph layouts, a pure function of their key, for every thread
    while any is inside.
    """
    import matplotlib

    rc = matplotlib.rcParams
    settings = repr([rc[k] for k in _RC_KEYS if k in rc])  # (fixed while drawing)
    with _installed.applied():
        stack = _local.__dict__.setdefault("settings", [])
        stack.append(settings)
        try:
            yield
        finally:
            stack.pop()


def _kept_box(layout):
    def _get_layout(text, renderer):
        settings = _local.__dict__.get("settings")
        raw = text.get_text()
        if not settings or text.get_wrap() or text.get_usetex() or "$" in raw:
            return layout(text, renderer)
        key = (raw, hash(text.get_fontproperties()), text.get_rotation(),
               text.get_horizontalalignment(), text.get_verticalalignment(),
               getattr(text, "_multialignment", None), getattr(text, "_linespacing", None),
               text.get_rotation_mode(), text.figure.dpi, settings[-1])
        kept = _boxes.get(text)
        if kept is not None and kept[0] == key and kept[1]() is renderer:
            return kept[2]
        result = layout(text, renderer)
        _boxes[text] = (key, weakref.ref(renderer), result)
        return result

    _get_layout.__doc__ = layout.__doc__
    return _get_layout


def _kept_measure(measure):
    def get_text_width_height_descent(renderer, s, prop, ismath):
        settings = _local.__dict__.get("settings")
        if not settings or ismath is not False:
            return measure(renderer, s, prop, ismath)
        key = (type(renderer), renderer.dpi, s, hash(prop), settings[-1])
        kept = _measures.get(key)
        if kept is None:
            kept = measure(renderer, s, prop, ismath)
            if len(_measures) >= _GLYPH_LAYOUTS_KEPT:
                _measures.clear()
            _measures[key] = kept
        return kept

    get_text_width_height_descent.__doc__ = measure.__doc__
    return get_text_width_height_descent


def _seen_size(set_size):
    def seen(font, ptsize, dpi):
        _sizes[font] = None  # (unknown if the call fails)
        set_size(font, ptsize, dpi)
        _sizes[font] = (float(ptsize), float(dpi))

    seen.__doc__ = set_size.__doc__
    return seen


def _cleared(clear):
    def cleared(font):
        _sizes.pop(font, None)  # (a cleared font's size is not relied on)
        clear(font)

    cleared.__doc__ = clear.__doc__
    return cleared


def _kept_glyphs(layout):
    def _layout(font, string, flags, *, features=None, language=None):
        size = _sizes.get(font)
        if size is None:
            return layout(font, string, flags, features=features, language=language)
        key = (font, size, string, flags,
               None if features is None else tuple(features),
               language if language is None or isinstance(language, str)
               else tuple(tuple(part) for part in language))
        kept = _glyphs.get(key)
        if kept is None:
            kept = layout(font, string, flags, features=features, language=language)
            if len(_glyphs) >= _GLYPH_LAYOUTS_KEPT:
                _glyphs.clear()
            _glyphs[key] = kept
        return list(kept)

    _layout.__doc__ = layout.__doc__
    return _layout
