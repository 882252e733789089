"""pint's parsed unit definitions are cached on disk; the cached registry converts every
unit the product accepts to the same SI numbers as a registry parsed afresh."""

from __future__ import annotations

import math

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
