"""A motion description written in exact SI text (what sweep and validity tasks carry to
their workers) gives the profile of the description as written, bit for bit, and is read
without pint."""

from __future__ import annotations

import numpy as np
import pytest

from ins_errors import units
from ins_errors.errors import InsErrorsError
from ins_errors.numeric.motion_spec import in_si, motion_profile

DESCRIPTIONS = [
    {},
    {"kind": "static", "latitude": "47.5 deg", "heading": "20 arcmin", "height": "300 ft"},
    {"kind": "great-circle"},  # moving: heading due east by default
    {"kind": "great_circle", "latitude": "-33 deg", "heading": "215 deg",
     "speed": "480 knot", "height": "10 km"},
    {"kind": "manoeuvre", "latitude": "0.9 rad", "speed": "200 m/s"},
    {"kind": "manoeuvre", "speed": "900 km/h",
     "legs": [{"duration": "5 min", "turn": "45 deg"},
              {"duration": "300 s", "speed": "250 m/s", "height": "1 mi", "turn": "-0.5 rad"},
              {"duration": "0.1 h"}]},
]


def refuse_pint():
    raise AssertionError("pint was asked for a unit")


def same_profile(a, b) -> None:
    for name in ("frame", "latitude", "longitude", "heading", "description", "static"):
        assert getattr(a, name) == getattr(b, name), name
    assert np.array_equal(np.asarray(a.breaks, dtype=float), np.asarray(b.breaks, dtype=float))
    t = np.linspace(0.0, 4000.0, 801)
    for got, expected in zip(a.commands(t), b.commands(t), strict=True):
        assert np.array_equal(got, expected)


@pytest.mark.parametrize("description", DESCRIPTIONS)
def test_si_text_gives_the_same_profile_without_pint(description, monkeypatch):
    written = motion_profile(description)
    si = in_si(description)
    assert all(isinstance(v, str) for k, v in si.items() if k != "legs")
    monkeypatch.setattr(units, "registry", refuse_pint)
    same_profile(motion_profile(si), written)


def test_a_motion_file_keeps_its_path(tmp_path, monkeypatch):
    (tmp_path / "m.csv").write_text(
        "t,v_N,v_E\n0,0,0\n1000,120,-40\n2000,150,10\n3000,150,30\n4000,90,30\n")
    description = {"kind": "file", "file": "m.csv", "latitude": "45 deg"}
    written = motion_profile(description, base=tmp_path)
    si = in_si(description)
    assert si["file"] == "m.csv"
    monkeypatch.setattr(units, "registry", refuse_pint)
    same_profile(motion_profile(si, base=tmp_path), written)


@pytest.mark.parametrize("description, message", [
    ({"kind": "orbit"}, "motion kind"),
    ({"latitud": "50 deg"}, "did you mean 'latitude'"),
    ({"latitude": "50"}, "needs a unit"),
    ({"kind": "manoeuvre", "legs": [{"turns": "3 deg"}]}, "key of a motion leg"),
])
def test_bad_descriptions_are_refused_as_by_motion_profile(description, message):
    with pytest.raises(InsErrorsError, match=message):
        in_si(description)
    with pytest.raises(InsErrorsError, match=message):
        motion_profile(description)
