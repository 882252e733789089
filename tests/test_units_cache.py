"""pint's parsed unit definitions are cached on disk; the cached registry converts every
unit the product accepts to the same SI numbers as a registry parsed afresh."""

from __future__ import annotations

import math
from pathlib import Path

from ins_errors import units

QUANTITIES = [("0.01 deg/h", "rad/s"), ("10 ug", "m/s**2"), ("1e-4 g", "m/s**2"),
              ("3 mg", "m/s**2"), ("20 arcsec", "rad"), ("5 arcmin", "rad"),
              ("39 deg", "rad"), ("100 ppm", "1"), ("0.1 m/s", "m/s"), ("900 km/h", "m/s"),
              ("5 km", "m"), ("10 min", "s"), ("24 h", "s"), ("1 rad/s", "rad/s")]


def _converted() -> list[float]:
    """The quantities in SI through a registry made for this call."""
    units.registry.cache_clear()
    try:
        return [units.parse_quantity(text, unit) for text, unit in QUANTITIES]
    finally:
        units.registry.cache_clear()


def test_cached_definitions_convert_to_the_same_numbers(tmp_path, monkeypatch):
    (tmp_path / "a file").write_text("not a folder", encoding="utf-8")
    monkeypatch.setattr(units, "units_cache_directory", lambda: tmp_path / "a file" / "units")
    fresh = _converted()            # no usable cache folder: the definitions parsed afresh
    folder = tmp_path / "units"
    monkeypatch.setattr(units, "units_cache_directory", lambda: folder)
    written = _converted()          # parsed and written to the cache
    assert folder.is_dir() and any(folder.rglob("*"))
    read = _converted()             # read back from it
    assert written == read == fresh
    assert math.isclose(fresh[0], 0.01 * math.pi / 180 / 3600, rel_tol=1e-15)
    assert math.isclose(fresh[1], 10e-6 * 9.80665, rel_tol=1e-15)


def test_kept_conversions_equal_pints_and_do_not_mix():
    """parse_quantity keeps each text's conversion per process: the kept value is pint's
    own to the last bit, a text asked in another unit is converted (or refused) afresh,
    and a refusal is worded with the name of each call."""
    import pytest

    ureg = units.registry()
    for text, unit in [*QUANTITIES, ("-45deg", "rad"), ("1 g", "m/s**2"), ("2 nmi", "m")]:
        first = units.parse_quantity(text, unit)
        kept = units.parse_quantity(text, unit)
        direct = float(ureg.parse_expression(units._normalise(text))
                       .to(ureg.parse_units(units._normalise(unit) if unit != "1"
                                            else "dimensionless")).magnitude)
        assert first == kept == direct, text
    assert units.parse_quantity("1 deg", "rad") == math.pi / 180
    assert units.parse_quantity("1 deg/h", "rad/s") == math.pi / 180 / 3600
    with pytest.raises(units.UnitError, match="drift: '1 deg' has units of deg"):
        units.parse_quantity("1 deg", "rad/s", "drift")
    for what in ("first", "second"):
        with pytest.raises(units.UnitError, match=f"^{what}: '3' has no unit"):
            units.parse_quantity("3", "rad", what)
        with pytest.raises(units.UnitError, match=f"^{what}: cannot read '3 florps'"):
            units.parse_quantity("3 florps", "rad", what)


def _stale_sets(folders, tmp_path) -> None:
    """Parse pint's definitions from a copy of its files into each of ``folders``, then
    delete the copy: what a deleted checkout's virtual environment leaves in the shared
    cache. (Parsed once, into the first folder; the others get copies of its files,
    which a parse from the same copy would write again.)"""
    import shutil

    import pint

    other = tmp_path / "deleted environment"
    other.mkdir(exist_ok=True)
    for name in ("default_en.txt", "constants_en.txt"):
        shutil.copy(Path(pint.__file__).parent / name, other / name)
    first, *more = folders
    pint.UnitRegistry(str(other / "default_en.txt"), cache_folder=first)
    for folder in more:
        shutil.copytree(first, folder, dirs_exist_ok=True)
    shutil.rmtree(other)


def test_sets_of_deleted_installations_are_not_read_and_are_removed(tmp_path, monkeypatch):
    """pint finds a cached set by the files' contents but reads the files it includes
    from the folder the set was parsed from: a set left by a deleted virtual environment
    made every registry fail and be parsed afresh. Each installation now has its own set;
    the deleted one's is removed, a living one's kept, and so is one made on another
    machine sharing the folder (its installation need not exist here)."""
    import platform

    import pint

    host = platform.node()
    store = tmp_path / "units"
    notes = {"0123456789abcdef": f"{tmp_path / 'deleted environment'}\n{host}\n",
             "fedcba9876543210": f"{tmp_path}\n{host}\n",
             "00000000ffffffff": f"{tmp_path / 'deleted environment'}\n{host}-other\n"}
    # the earlier one-set layout (in the store itself), and one set per installation
    _stale_sets([store / name for name in notes] + [store], tmp_path)
    for name, note in notes.items():
        (store / name / units.INSTALLATION_FILE).write_text(note, encoding="utf-8")
    kept = ["fedcba9876543210", "00000000ffffffff"]
    fresh = _converted()
    made, original = [], pint.UnitRegistry

    def recorded(*args, **kwargs):
        registry = original(*args, **kwargs)
        made.append(kwargs.get("cache_folder"))       # only registries that loaded
        return registry

    monkeypatch.setattr(pint, "UnitRegistry", recorded)
    monkeypatch.setattr(units, "units_cache_directory", lambda: store)
    assert _converted() == fresh
    own = units.installation_folder(store)
    scratch, = made               # parsed once, in a scratch folder renamed to its set
    assert scratch.parent == store and not scratch.exists() and own.is_dir()
    assert sorted(p.name for p in store.iterdir()) == sorted([own.name, *kept])
    assert (own / units.INSTALLATION_FILE).read_text("utf-8") == (
        f"{Path(pint.__file__).resolve().parent}\n{host}\n")
    assert _converted() == fresh and made == [scratch, own]   # read from its set
