"""``ins-errors modes`` on a Schuler loop damped by an external velocity reference.

The model is tests/models/damped_ins.py (a damped-INS probe's file): a north-pointing
platform on a sphere whose computed velocity is pulled towards a reference velocity with
the gain k_v (and the platform command with k_p). Before, its damped Schuler pair was two
"damped oscillation" rows with no textbook value, its lightly damped pair was compared by
its damped period (+0.085 % "off" at k_v = 1e-4/s, though its natural period is the
textbook one), and the Foucault footer said no pair was split, giving causes that were
not there.

References (independent of the code under test):

* the characteristic polynomial of the two horizontal channels at rest, written as one
  complex error z = e_E + i e_N: s² + (k_v + 2iΩ sin φ) s + g/R = 0 (velocity damping
  and the Coriolis turning act on the same velocity error), its roots by numpy; without
  Earth rate a single channel s² + k_v s + (1 + k_p) g/R;
* for a growing pair (a gain the model file refuses), F written here from that equation
  (4 real states).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from ins_errors.analysis.modes import static_modes
from ins_errors.cli import main
from tests.test_cli_json import strict_json

ROOT = Path(__file__).resolve().parent.parent
MODEL = str(ROOT / "tests/models/damped_ins.py")
G, R, U = 9.80665, 6_371_000.0, 7.292115e-5  # the model file's defaults
OMEGA_S = np.sqrt(G / R)
ZETA_HALF = 1.24e-3  # k_v of ζ ≈ 0.5 (the model's example)


@pytest.fixture(scope="module", autouse=True)
def model():
    """The model, derived (first use: one line on stderr) before any output is read."""
    from ins_errors.numeric.model import load_model

    return load_model(MODEL)


def _roots(k_v: float, latitude: float, k_p: float = 0.0, rate: float = U) -> list[complex]:
    """The textbook pair, each root with Im > 0 (a conjugate pair counted once), by
    increasing Im: the roots of s² + (k_v + 2iΩ sin φ) s + (1 + k_p) g/R and their
    conjugates."""
    roots = np.roots([1.0, k_v + 2j * rate * np.sin(latitude), (1 + k_p) * G / R])
    return sorted((r if r.imag > 0 else r.conjugate() for r in roots), key=lambda r: r.imag)


def _schuler(result) -> list:
    return sorted((m for m in result.modes if m.name.startswith("Schuler")),
                  key=lambda m: m.eigenvalue.imag)


@pytest.mark.parametrize("latitude_deg", [50.0, -30.0, 75.0])
@pytest.mark.parametrize("k_v", [1e-4, ZETA_HALF, 1.75e-3, 2.2e-3])  # ζ 0.04 ... 0.89
def test_a_damped_pair_is_the_foucault_split_schuler_pair_at_its_natural_period(
        latitude_deg, k_v):
    latitude = np.radians(latitude_deg)
    result = static_modes(MODEL, latitude, parameters={"k_v": k_v})
    roots = _roots(k_v, latitude)
    lower, upper = _schuler(result)
    word = "" if k_v < 1e-3 else " (damped)"
    assert (lower.name, upper.name) == (f"Schuler − Foucault{word}",
                                        f"Schuler + Foucault{word}")
    for mode, root in zip((lower, upper), roots, strict=True):
        assert mode.eigenvalue == pytest.approx(root, rel=1e-9)
        assert mode.damping_ratio == pytest.approx(-root.real / abs(root), rel=1e-8)
        # compared by its natural period with the textbook pair's natural period: the
        # same for a model that is the textbook loop
        assert mode.natural_period_s == pytest.approx(2 * np.pi / abs(root), rel=1e-9)
        assert mode.reference.quantity == "natural_period"
        assert mode.reference.seconds == pytest.approx(2 * np.pi / abs(root), rel=1e-9)
        assert abs(mode.reference.relative_difference) < 1e-9
    # the damped period is still shown, and longer
    assert lower.period_s == pytest.approx(2 * np.pi / roots[0].imag, rel=1e-9)
    # the Foucault period from the pair is 2π/(Ω|sin φ|) whatever the damping
    assert result.foucault_period_from_modes_s == pytest.approx(
        2 * np.pi / (U * abs(np.sin(latitude))), rel=1e-9)


def test_the_probes_pair_at_zeta_half_and_its_table(capsys):
    """The probe's run: ζ ≈ 0.5, rows named, 0.000 % off, the Foucault footer from the
    pair (it said no two Schuler rows differed by Ω|sin φ|, and --json had null)."""
    assert main(["modes", MODEL, "-p", f"k_v={ZETA_HALF}/s"]) == 0
    out = capsys.readouterr().out
    rows = {line.split(" | ")[0].lstrip("| "): line for line in out.splitlines()
            if line.startswith("| Schuler")}
    assert set(rows) == {"Schuler − Foucault (damped)", "Schuler + Foucault (damped)"}
    for line in rows.values():
        assert "| 0.000 % |" in line and "ζ = 0.499" in line
    footer = next(line for line in out.splitlines() if line.startswith("Foucault period"))
    assert "turns once in it; from the split pair, 2π/((ω₊ − ω₋)/2) = 31.24 h" in footer
    assert "no two Schuler rows" not in footer
    assert "natural period 2π/(ω̄_ζ − Ω_ζ), Ω_ζ = Ω|sin φ|/√(1 − ζ²)" in out
    assert main(["modes", MODEL, "-p", f"k_v={ZETA_HALF}/s", "--json"]) == 0
    data = strict_json(capsys.readouterr().out)
    assert data["foucault"]["from_modes_s"] == pytest.approx(
        2 * np.pi / (U * np.sin(np.radians(50.0))), rel=1e-9)
    [minus] = [m for m in data["modes"] if m["name"] == "Schuler − Foucault (damped)"]
    assert minus["reference"]["quantity"] == "natural_period"


def test_without_earth_rate_the_damped_loop_is_schuler_at_its_natural_frequency():
    """Ω = 0: each channel is s² + k_v s + (1 + k_p) g/R; k_p stiffens the loop, and the
    row says by how much its natural period is off 2π√(R/g): 1/√(1 + k_p) − 1 (it was a
    "damped oscillation" with no textbook value)."""
    k_v, k_p = ZETA_HALF, 0.2
    result = static_modes(MODEL, np.radians(50.0), parameters={"k_v": k_v, "k_p": k_p,
                                                               "U": 0.0})
    [root, _] = _roots(k_v, 0.0, k_p, rate=0.0)
    [row] = _schuler(result)
    assert row.name == "Schuler (damped)" and row.multiplicity == 2
    assert row.eigenvalue == pytest.approx(root, rel=1e-9)
    assert row.reference.seconds == pytest.approx(2 * np.pi / OMEGA_S, rel=1e-12)
    assert row.reference.relative_difference == pytest.approx(1 / np.sqrt(1 + k_p) - 1,
                                                              rel=1e-9)
    assert result.foucault_period_s is None
    # overdamped (ζ = 1.5): no oscillation is left, two real modes per channel, named by
    # kind, not Schuler; the product of their rates is still g/R
    k_v = 3 * OMEGA_S
    result = static_modes(MODEL, np.radians(50.0), parameters={"k_v": k_v, "U": 0.0})
    assert not _schuler(result)
    damped = sorted(-m.eigenvalue.real for m in result.modes if m.kind == "damped")
    assert damped == pytest.approx(sorted(-np.roots([1.0, k_v, G / R]).real), rel=1e-9)
    assert damped[0] * damped[1] == pytest.approx(G / R, rel=1e-9)


def test_at_the_equator_the_damped_pair_is_one_schuler_row_at_2_pi_sqrt_r_over_g():
    result = static_modes(MODEL, 0.0, parameters={"k_v": ZETA_HALF})
    [row] = _schuler(result)
    assert row.name == "Schuler (damped)" and row.multiplicity == 2
    assert row.natural_period_s == pytest.approx(2 * np.pi / OMEGA_S, rel=1e-9)
    assert abs(row.reference.relative_difference) < 1e-9
    assert row.period_s == pytest.approx(2 * np.pi / _roots(ZETA_HALF, 0.0)[0].imag, rel=1e-9)


@pytest.mark.parametrize("k_v", [2.4e-3, 3 * OMEGA_S])  # ζ ≈ 0.96, ≈ 0.9996 with Ω
def test_a_heavily_damped_pair_is_not_schuler_and_the_footer_says_only_what_is_there(
        k_v, capsys):
    """With Ω the pair never becomes real; beyond |ζ| = 0.9 it is named by kind. The
    Foucault footer said "(a frame that does not follow the meridian, or a larger split
    of another cause, as near the equator)": neither is so here."""
    latitude = np.radians(50.0)
    result = static_modes(MODEL, latitude, parameters={"k_v": k_v})
    assert not _schuler(result)
    rows = [m for m in result.modes if m.kind == "damped oscillation"]
    roots = _roots(k_v, latitude)
    assert sorted(m.eigenvalue.imag for m in rows) == pytest.approx(
        [r.imag for r in roots], rel=1e-9)
    assert all(m.damping_ratio > 0.9 for m in rows)
    assert main(["modes", MODEL, "-p", f"k_v={k_v}/s"]) == 0
    footer = next(line for line in capsys.readouterr().out.splitlines()
                  if line.startswith("Foucault period"))
    assert "no row here is named Schuler: no oscillation has |λ| within a factor 1.25 of " \
           "√(g/R) = 1.2407e-03 rad/s with |ζ| < 0.9" in footer
    assert "meridian, or" not in footer and "equator" not in footer


def test_an_unsplit_footer_gives_the_measured_half_difference(capsys):
    """k_p = 0.3 (torquing fed by the velocity disagreement) stiffens the loop and turns it
    with the Earth otherwise than the velocity equation does: its two damped Schuler rows
    are split by more than Ω|sin φ| (+10 % and beyond). The footer gives the two numbers,
    not a cause (it said "(a frame that does not follow the meridian, or ...)")."""
    assert main(["modes", MODEL, "-p", f"k_v={ZETA_HALF}/s", "-p", "k_p=0.3"]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.startswith("| Schuler")]
    assert [row.split(" | ")[0] for row in rows] == ["| Schuler (damped)"] * 2
    rates = sorted(float(re.search(r"±([\d.e+-]+)i", row).group(1)) for row in rows)
    footer = next(line for line in out.splitlines() if line.startswith("Foucault period"))
    half = re.search(r"half the difference of their Im λ is ([\d.e+-]+) rad/s, "
                     r"Ω\|sin φ\| = ([\d.e+-]+) rad/s", footer)
    assert half is not None, footer
    assert float(half.group(1)) == pytest.approx((rates[1] - rates[0]) / 2, rel=1e-3)
    assert float(half.group(2)) == pytest.approx(U * np.sin(np.radians(50.0)), rel=1e-3)
    assert float(half.group(1)) > 1.1 * float(half.group(2))
    assert "meridian, or" not in footer and "equator" not in footer


def test_a_growing_pair_is_named_growing_and_compared_by_its_natural_period():
    """F written here from the complex equation with a negative gain (the model file
    refuses one): z'' + (k + 2iW) z' + ω² z = 0 as (e_E, e_N, v_E, v_N)."""
    from ins_errors.analysis.mode_references import Constant, References
    from ins_errors.analysis.modes import _modes

    latitude, k = np.radians(40.0), -0.6e-3
    w = U * np.sin(latitude)
    F = np.array([[0.0, 0.0, 1.0, 0.0],
                  [0.0, 0.0, 0.0, 1.0],
                  [-G / R, 0.0, -k, 2 * w],
                  [0.0, -G / R, -2 * w, -k]])
    refs = References(Constant(G, "m/s**2", "typed"), Constant(R, "m", "typed"),
                      Constant(U, "rad/s", "typed"), latitude)
    modes, _ = _modes(F, np.ones(4), ["e_E", "e_N", "v_E", "v_N"], refs)
    roots = _roots(k, latitude)
    assert [m.name for m in modes] == ["Schuler − Foucault (growing)",
                                       "Schuler + Foucault (growing)"]
    for mode, root in zip(modes, roots, strict=True):
        assert mode.eigenvalue == pytest.approx(root, rel=1e-9)
        assert mode.damping_ratio < -0.2
        assert mode.reference.seconds == pytest.approx(2 * np.pi / abs(root), rel=1e-9)


def test_the_damped_table_of_docs_modes_is_the_commands_output(capsys):
    """docs/modes.md's damped_ins rows (its "Damped modes" section) are what the command
    it names prints today, run from the repository's root as the page says."""
    text = (ROOT / "docs/modes.md").read_text(encoding="utf-8")
    section = text[text.index("## Damped modes"):]
    command = re.search(r"`(ins-errors modes tests/models/damped_ins\.py -p\s+k_v=[^`]+)`",
                        section).group(1).split()
    shown = re.search(r"^```text\n(.*?)^```", section, re.M | re.S).group(1)
    assert main([command[1], str(ROOT / command[2]), *command[3:]]) == 0
    printed = capsys.readouterr().out.splitlines()
    rows = [line for line in shown.splitlines() if line.startswith("|")]
    assert len(rows) == 3
    for row in rows:
        assert row in printed, row
